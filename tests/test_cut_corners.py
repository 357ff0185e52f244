"""Cuts pass through their sketch's corners, say how deep they reach, leave no crumbs.

A V-neck 10 cm deep on a tee of 4 cm cells used to reach 8.8 cm (its tip fell inside a
triangle and the split ran straight across it); a narrow V could leave cloth inside its tip;
a cut could leave a piece of one triangle, silently.
"""

from __future__ import annotations

import numpy as np
import pytest

from ptailor.edits import tolerances as edit_tol
from ptailor.edits.corners import mean_edge
from ptailor.edits.cut import sketch_field, view_frame
from ptailor.edits.state import EditOptions
from ptailor.formats.garment import load_garment
from ptailor.pipeline import adjustment, apply_steps
from ptailor.recipe import parse_recipe
from ptailor.samples import flat_tee
from tests.conftest import real_path


def vneck(half: float, depth: float, *, origin: str = "neckline", extra: str = "") -> str:
    """A V-neck cut from the front layer, ``depth`` below the front neck point."""
    return (
        f"units: cm\nsteps: [{{op: cut, view: front, origin: {origin}, "
        f"sketch: [[-{half}, 1], [0, -{depth}], [{half}, 1]], remove: above, layers: near"
        f"{extra}}}]"
    )


def boundary_edges(F: np.ndarray) -> np.ndarray:
    """Edges used by one triangle, ``(e, 2)`` sorted."""
    E = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    keys, count = np.unique(E, axis=0, return_counts=True)
    return keys[count == 1]


def tip_vertex(V3: np.ndarray, frame, origin, tip) -> tuple[int, float]:
    """The near-layer drape vertex nearest the sketch's tip in the front view, and how far."""
    X = V3 @ view_frame("front", frame=frame).T
    far = X[:, 2] > np.median(X[:, 2])
    d = np.linalg.norm(X[:, :2] - (np.asarray(origin) + tip), axis=1) + 1e6 * far
    i = int(np.argmin(d))
    return i, float(d[i])


def off_the_arms(st, step, origin) -> float:
    """How far the new neckline's drape vertices inside the V's span (front layer, from 0.5
    cm below the origin to the tip) lie from the sketch in the front view, at most."""
    import dataclasses

    X = st.V3 @ view_frame("front", frame=st.frame).T - np.r_[origin, 0.0]
    edge = np.unique(boundary_edges(st.base.F3))
    inside = (X[edge, 2] < np.median(X[:, 2])) & (X[edge, 1] < -0.5) & (X[edge, 1] > -11)
    sel = edge[inside & (np.abs(X[edge, 0]) < 7.5)]
    both = dataclasses.replace(step, layers="both")
    return float(np.abs(sketch_field(st.V3[sel], both, frame=st.frame, origin=origin)).max())


def test_a_v_neck_reaches_its_depth_on_a_coarse_tee_and_says_so():
    """The tip is a vertex of the new outline in the drape and in the adjusted pattern (the
    pattern's outline turns there by the V's angle), the record gives the depth asked and
    achieved and the neck drop before and after."""
    g = flat_tee(cell=4)
    adj = adjustment(g, parse_recipe(vneck(8, 10)), baseline=False)
    rec = adj.state.log[-1]
    assert rec["depth"] == {"along": "down", "asked": 10.0, "achieved": pytest.approx(10.0)}
    assert rec["corner_vertices"] == 1
    nd = rec["neck_drop"]
    assert nd["after"] - nd["before"] == pytest.approx(10.0, abs=1e-6)
    G = adj.garment
    tip, off = tip_vertex(G.V3, G.frame, rec["origin"], [0.0, -10.0])
    assert off < 1e-9
    assert tip in boundary_edges(G.F3)
    faces, corners = G.F3, G.F2
    r, c = np.nonzero(faces == tip)
    t2 = np.unique(corners[r, c])
    assert len(t2) == 1  # inside the front panel: one pattern vertex
    ends = boundary_edges(G.F2)
    ends = ends[(ends == t2[0]).any(axis=1)]
    assert len(ends) == 2  # on the pattern's outline
    u, w = (G.V2[e[e != t2[0]][0]] - G.V2[t2[0]] for e in ends)
    angle = np.degrees(np.arccos(u @ w / np.linalg.norm(u) / np.linalg.norm(w)))
    assert angle == pytest.approx(np.degrees(2 * np.arctan(8 / 11)), abs=0.5)
    # the arms are straight: every vertex of the new edge on them (0.31 cm off before)
    assert off_the_arms(adj.state, parse_recipe(vneck(8, 10)).steps[0], rec["origin"]) < 1e-9


@pytest.mark.parametrize(
    ("half", "extra"),
    [(2, ""), (8, ""), (3, ", symmetric: true")],
    ids=["narrow", "wide", "symmetric"],
)
def test_no_cloth_is_left_inside_a_sharp_v(half, extra):
    """A V narrower than the triangles crosses edges twice near its tip (both ends on the
    kept side): those edges are split too, so nothing of the near layer inside the V (or
    its mirror image) is kept and the cut reaches its depth."""
    g = flat_tee(cell=4)
    text = vneck(half, 10, extra=extra).replace("[0, -10]", "[-1, -10]")
    rec = parse_recipe(text)
    st = apply_steps(g, rec, options=EditOptions())
    log = st.log[-1]
    assert log["depth"]["achieved"] == pytest.approx(10.0, abs=1e-9)
    F = st.base.F3
    mid = st.V3[F].mean(axis=1)
    o = np.asarray(log["origin"])
    phi = sketch_field(mid, rec.steps[0], frame=st.frame, origin=o, mid=float("inf"))
    d = view_frame("front", frame=st.frame)[2]
    near = mid @ d < np.median(g.V3 @ d)
    if "symmetric" in extra:  # the mirror image (the tee is symmetric about x = 0)
        m = mid * np.array([-1.0, 1.0, 1.0])
        phi = np.minimum(phi, sketch_field(m, rec.steps[0], frame=st.frame, origin=o, mid=np.inf))
    assert np.all(phi[near] > -1e-9)


def test_a_cut_drops_the_crumbs_it_leaves_and_names_them():
    """A plane 0.2 cm beyond the left underarm seams leaves a strip of each left sleeve
    piece of 18 x 0.2 cm: under four of its triangles, dropped, each named in a warning
    and the record."""
    g = flat_tee()
    text = "units: cm\nsteps: [{op: cut, plane: {point: [24.2, 0, 0], normal: [1, 0, 0]}}]"
    adj = adjustment(g, parse_recipe(text), baseline=False)
    rec = adj.state.log[-1]
    dropped = {p["piece"] for p in rec["dropped"]}
    assert dropped == {"sleeve_left_front", "sleeve_left_back"}
    assert all(p["area"] < 4 * 2.0 for p in rec["dropped"])  # cells of 2 x 2 cm: 2 cm2 each
    assert sum("drops piece sleeve_left" in w for w in rec["warnings"]) == 2
    names = {p.name for p in adj.state.panels}
    assert not names & dropped
    assert adj.garment.V3[np.unique(adj.garment.F3), 0].max() <= 24.0 + 1e-9


@pytest.mark.slow
def test_a_v_neck_on_the_shared_tshirt_reaches_its_depth():
    g = load_garment(real_path("tshirt"), pattern_units="auto").garment
    st = apply_steps(g, parse_recipe(vneck(8, 10)), options=EditOptions())
    rec = st.log[-1]
    assert rec["depth"]["achieved"] == pytest.approx(10.0, abs=1e-6)  # 9.76 before
    assert rec["neck_drop"]["after"] - rec["neck_drop"]["before"] == pytest.approx(10.0, abs=1e-6)
    tip, off = tip_vertex(st.V3, st.frame, rec["origin"], [0.0, -10.0])
    h = mean_edge(st.V3, st.base.F3)
    assert off <= edit_tol.CUT_CORNER_SNAP_REL * h  # on an edge within the corner's snap
    assert tip in boundary_edges(st.base.F3)
    step = parse_recipe(vneck(8, 10)).steps[0]
    assert off_the_arms(st, step, rec["origin"]) < 1e-5  # 0.47 cm before, next to the tip


@pytest.mark.slow
def test_a_v_neck_through_the_dress_leaves_no_crumb_of_a_strap():
    """A wide, deep V takes most of the right strap and left a triangle of it (0.03 cm2),
    ``strap_right_1``, unsaid: now dropped and named."""
    g = load_garment(real_path("dress"), pattern_units="auto").garment
    st = apply_steps(g, parse_recipe(vneck(10, 15)), options=EditOptions())
    rec = st.log[-1]
    assert rec["depth"]["achieved"] == pytest.approx(15.0, abs=1e-6)  # 14.83 before
    assert [p["piece"] for p in rec["dropped"]] == ["strap_right_1"]
    assert rec["dropped"][0]["triangles"] == 1
    assert any("strap_right_1" in w for w in rec["warnings"])
