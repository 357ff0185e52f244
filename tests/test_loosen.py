"""Loosen / tighten: offset a region along its normals, or over-sketch a silhouette."""

from __future__ import annotations

import json
import re
from functools import cache

import numpy as np
import pytest
import yaml

import ptailor.edits.loosen  # noqa: F401  (registers the ops)
from ptailor.edits import EditOptions
from ptailor.edits.loosen import (
    falloff_weights,
    normal_smoother,
    outward_normals,
    row_crossings,
    turned_faces,
)
from ptailor.edits.region import region_faces
from ptailor.errors import LimitError, PtailorError, RecipeError
from ptailor.formats.garment import load_garment
from ptailor.geometry.triangles import signed_areas_2d
from ptailor.model.garment import Garment, panels
from ptailor.pipeline import adjustment, apply_steps
from ptailor.recipe import parse_recipe
from ptailor.samples import cone_skirt, cylinder, lantern_sleeve
from tests.conftest import real_path
from tests.garment_checks import assert_valid, seam_sides


def recipe(step: dict, **top) -> object:
    return parse_recipe(yaml.safe_dump({"steps": [step], **top}))


def radii(V: np.ndarray) -> np.ndarray:
    """Distance of each vertex from the y axis."""
    return np.hypot(V[:, 0], V[:, 2])


def width(V2: np.ndarray) -> float:
    return float(np.ptp(V2[:, 0]))


# ---------------------------------------------------------------------------------------
# offset form
# ---------------------------------------------------------------------------------------


@pytest.mark.slow
@pytest.mark.parametrize("s", [1.0, 1.25])
@pytest.mark.parametrize("op, sign", [("loosen", 1.0), ("tighten", -1.0)])
def test_cylinder_pattern_width_grows_by_2_pi_d_over_s(s, op, sign):
    d = 2.0
    g = cylinder(stretch=s)
    W = width(g.V2)
    adj = adjustment(g, recipe({"op": op, "region": "all", "by": d}))
    # every vertex moved radially by d (the normals of the tube are radial)
    np.testing.assert_allclose(radii(adj.state.V3) - radii(g.V3), sign * d, atol=1e-9)
    np.testing.assert_allclose(adj.state.V3[:, 1], g.V3[:, 1], atol=1e-9)
    # the scale-preserving method keeps the intrinsic scale s: 2 pi d extra in 3D is
    # 2 pi d / s in the pattern
    expected = W + sign * 2.0 * np.pi * d / s
    assert width(adj.result.V2) == pytest.approx(expected, rel=0.01)
    # uniform flattening makes the pattern as wide as the drape: s W + 2 pi d
    assert width(adj.baseline.V2) == pytest.approx(s * W + sign * 2.0 * np.pi * d, rel=0.01)
    if s != 1.0:
        assert abs(width(adj.baseline.V2) - expected) > 0.1 * W
    # normals smoothed over |by| (a length of the edit, not of the mesh: the mean edge
    # length here is 1.05, and no longer widens it)
    rec = {"op": op, "by": d, "triangles": g.n_faces, "smoothing": pytest.approx(d)}
    assert adj.state.log == (rec,)
    assert not adj.state.even.any()  # the panel's outline changed


def flip_panel(g: Garment, name: str) -> Garment:
    """The same garment with one panel's triangles wound the other way (drape and pattern)."""
    p = next(p for p in panels(g) if p.name == name)
    F3, F2 = g.F3.copy(), g.F2.copy()
    F3[p.faces] = F3[p.faces][:, ::-1]
    F2[p.faces] = F2[p.faces][:, ::-1]
    return Garment(g.V3, F3, g.V2, F2, g.face_group, g.group_names, g.units)


@pytest.mark.parametrize(
    "g",
    [cone_skirt(), flip_panel(cone_skirt(), "back"), flip_panel(cone_skirt(), "front")],
    ids=["skirt", "back-flipped", "front-flipped"],
)
def test_normals_point_away_from_the_axis_whatever_the_winding(g):
    N = outward_normals(g.V3, g.F3, g.F2, panels(g))
    r = g.V3 * np.array([1.0, 0.0, 1.0])
    assert np.all(np.einsum("ij,ij->i", N, r) > 0.5 * radii(g.V3))
    s = apply_steps(g, recipe({"op": "loosen", "by": 1.0}), options=EditOptions())
    assert np.all(radii(s.V3) > radii(g.V3) + 0.9)


def test_mirrored_cylinder_loosens_outward():
    g = cylinder(mirrored=True)
    s = apply_steps(g, recipe({"op": "loosen", "by": 1.5}), options=EditOptions())
    np.testing.assert_allclose(radii(s.V3) - radii(g.V3), 1.5, atol=1e-9)


LANTERN_BOX = {"box": {"min": [-50, 18, -50], "max": [50, 38, 50]}}


def test_loosen_takes_the_seam_pairs_the_flatten_uses(monkeypatch):
    """The offset's orientation takes the seam half-edges of the garment's structure (which
    the flatten after it uses too): computed once per adjustment, and the same normals."""
    import ptailor.model.structure as structure_mod
    from ptailor.edits.loosen import panel_orientation
    from ptailor.model.seams import seam_halfedges

    g = lantern_sleeve()
    pl = panels(g)
    pairs = seam_halfedges(g.F3, g.F2)
    for a, b in zip(
        panel_orientation(g.F3, g.F2, pl),
        panel_orientation(g.F3, g.F2, pl, pairs=pairs),
        strict=True,
    ):
        np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(
        outward_normals(g.V3, g.F3, g.F2, pl), outward_normals(g.V3, g.F3, g.F2, pl, pairs=pairs)
    )
    calls = []

    def counted(F3, F2):
        calls.append(len(F3))
        return seam_halfedges(F3, F2)

    monkeypatch.setattr(structure_mod, "seam_halfedges", counted)
    monkeypatch.setattr("ptailor.edits.loosen.normals.seam_halfedges", counted)
    adjustment(g, recipe({"op": "loosen", "region": LANTERN_BOX, "by": 1.0}), baseline=False)
    assert calls == [len(g.F3)]


@pytest.mark.slow
def test_lantern_middle_ring_grows_by_by_and_the_ends_stay():
    by = 2.0
    g = lantern_sleeve()  # sleeve y 8..48, cuff y 0..8, rows 1 cm apart
    adj = adjustment(g, recipe({"op": "loosen", "region": LANTERN_BOX, "by": by}))
    V0, V1, y = g.V3, adj.state.V3, g.V3[:, 1]
    dr = radii(V1) - radii(V0)
    middle = np.abs(y - 28.0) < 1e-9
    assert dr[middle] == pytest.approx(by, rel=0.01)
    move = np.linalg.norm(V1 - V0, axis=1)
    for end in (0.0, 48.0):  # the cuff's hem and the armhole
        assert move[np.abs(y - end) < 1e-9].max() < 0.1 * by
    # outside the box (and on its border) nothing moves at all
    outside = (y < 18.0 + 1e-9) | (y > 38.0 - 1e-9)
    assert np.array_equal(V1[outside], V0[outside])
    # the region's border rings do not move; the offset rises smoothly inside it
    for border in (18.0, 38.0):
        assert np.abs(dr[np.abs(y - border) < 1e-9]).max() < 1e-6
    ring_dr = [dr[np.abs(y - k) < 1e-9].mean() for k in range(18, 29)]
    assert np.all(np.diff(ring_dr)[:4] > 0) and np.all(np.diff(ring_dr) >= -1e-12)
    assert np.all(np.diff(ring_dr) < 0.8 * by)  # no step: at most ~0.75 by per cm here
    assert_valid(adj.state.base, V2=adj.result.V2)
    # seams: the sleeve's and cuff's own back seams stay equal, the eased sleeve-to-cuff
    # seam (28 against 40) keeps its ease exactly (flatten.seams: ease) and about its size
    sides = sorted(seam_sides(adj.state.base, adj.result.V2), key=lambda ab: -max(ab))
    (la, lb), (ma, mb), (ka, kb) = sides
    assert abs(la - lb) <= 1e-6 * la and abs(ka - kb) <= 1e-6 * ka
    assert max(ma, mb) / min(ma, mb) == pytest.approx(40.0 / 28.0, rel=1e-6)
    assert max(ma, mb) == pytest.approx(40.0, rel=0.02)
    assert min(ma, mb) == pytest.approx(28.0, rel=0.03)
    # the sleeve panel's middle row widens, towards 28 + 2 pi by (the bulge is doubly
    # curved, so flattening spreads part of it to the rows around); its ends stay about 28
    sleeve = next(p for p in adj.state.panels if p.name == "sleeve")
    Y0 = g.V2[sleeve.vertices, 1]  # pattern y = drape y - 8

    def row_width(y2: float) -> float:
        return width(adj.result.V2[sleeve.vertices[np.abs(Y0 - y2) < 1e-9]])

    assert 28.0 + np.pi * by < row_width(20.0) < 28.0 + 2.0 * np.pi * by
    assert row_width(0.0) == pytest.approx(28.0, rel=0.03)
    assert row_width(40.0) == pytest.approx(28.0, rel=0.03)
    assert adj.state.log[-1]["triangles"] == 2 * 48 * 20


def test_falloff_weights_are_zero_on_the_border_and_one_inside():
    g = lantern_sleeve()
    faces = region_faces(LANTERN_BOX, g, g.V3, panels(g))
    w = falloff_weights(g.V3, g.F3, faces, band=4.0)
    y = g.V3[:, 1]
    assert np.all(w[(y < 18.0 - 1e-9) | (y > 38.0 + 1e-9)] == 0.0)
    assert np.all(w[np.abs(y - 18.0) < 1e-9] == 0.0)
    assert np.all(w[(y > 22.0 - 1e-9) & (y < 34.0 + 1e-9)] == 1.0)
    assert w[np.abs(y - 20.0) < 1e-9] == pytest.approx(0.5, abs=0.01)  # smoothstep(1/2)
    # the whole garment has no border: weight 1 everywhere
    assert np.all(falloff_weights(g.V3, g.F3, np.arange(g.n_faces), band=4.0) == 1.0)


def test_tightening_past_the_axis_is_an_error_naming_panel_and_height():
    g = cylinder()  # radius about 4.8, y from 0 to 20; every triangle turns over
    with pytest.raises(PtailorError, match="inside out") as err:
        apply_steps(g, recipe({"op": "tighten", "by": 10.0}), options=EditOptions())
    # the triangles' centroids span heights 1/3 to 20 - 1/3 (rows 1.25 apart)
    assert "(panel 'tube', height 0.4 to 19.6)" in str(err.value)
    # the refusal names the largest of its probes that passes: 7.5 and 5 turn it too
    assert str(err.value).endswith("(by: 2.5 passes)"), str(err.value)
    assert isinstance(err.value, LimitError)
    # tightening by less than the radius is fine, and exact
    s = apply_steps(g, recipe({"op": "tighten", "by": 4.0}), options=EditOptions())
    np.testing.assert_allclose(radii(s.V3), radii(g.V3) - 4.0, atol=1e-9)


def test_smoothed_normals_of_a_tube_stay_radial():
    g = cylinder()
    N0 = outward_normals(g.V3, g.F3, g.F2, panels(g))
    step = normal_smoother(g.V3, g.F3, tau=4.0)
    N = N0
    for _ in range(16):
        N = step(N)
    length = np.linalg.norm(N, axis=1)
    assert length.max() < 0.9  # the field did diffuse (the radial mode decays) ...
    np.testing.assert_allclose(N / length[:, None], N0, atol=1e-12)  # ... but not turn
    np.testing.assert_allclose(N0[:, [0, 2]], g.V3[:, [0, 2]] / radii(g.V3)[:, None], atol=1e-12)


# ---------------------------------------------------------------------------------------
# wrinkles: a tube with radial folds far tighter than the offset
# ---------------------------------------------------------------------------------------

#: radius, wrinkles around, wrinkle amplitude, vertices around (8 per wrinkle)
WR, WM, WA, WN = 10.0, 20, 0.3, 160


def wrinkly_cylinder() -> tuple[Garment, np.ndarray]:
    """A cylinder whose rings are ``r = WR + WA sin(WM phi)``; also returns ``r``."""
    g = cylinder(circumference=2.0 * np.pi * WR, height=20.0, n_around=WN, n_along=20)
    V = g.V3.copy()
    phi = np.arctan2(V[:, 0], V[:, 2])
    r = WR + WA * np.sin(WM * phi)
    V[:, 0], V[:, 2] = r * np.sin(phi), r * np.cos(phi)
    return Garment(V, g.F3, g.V2, g.F2, g.face_group, g.group_names, g.units), r


def ring_perimeter(V: np.ndarray) -> float:
    """Perimeter of the bottom ring (the first ``WN`` vertices, in order around)."""
    P = V[:WN]
    return float(np.linalg.norm(np.roll(P, -1, axis=0) - P, axis=1).sum())


def test_wrinkly_cylinder_premise():
    # polar curvature at a trough (r = WR - WA, r' = 0, r'' = WA WM^2): concave, radius
    # below 1 cm, far below the offsets tested, so offsetting along the raw normals folds
    rt = WR - WA
    kappa = (rt**2 - rt * WA * WM**2) / rt**3
    assert kappa < 0.0 and 1.0 / abs(kappa) < 1.0
    g, _ = wrinkly_cylinder()
    N = outward_normals(g.V3, g.F3, g.F2, panels(g))
    assert turned_faces(g.V3, g.V3 + 2.0 * N, g.F3).sum() > 0.2 * g.n_faces


@pytest.mark.slow
@pytest.mark.parametrize("op, d", [("loosen", 2.0), ("loosen", 5.0), ("tighten", 2.0)])
def test_wrinkles_ride_along_and_the_girth_grows_by_2_pi_d(op, d):
    g, r = wrinkly_cylinder()
    sign = 1.0 if op == "loosen" else -1.0
    adj = adjustment(g, recipe({"op": op, "region": "all", "by": d}))
    V0, V1 = g.V3, adj.state.V3
    assert not turned_faces(V0, V1, g.F3).any()
    assert_valid(adj.state.base, V2=adj.result.V2)
    # every vertex moves radially by d (the smoothed normals are radial): the wrinkles keep
    # their amplitude and the mean girth 2 pi mean(r) gains exactly 2 pi d
    np.testing.assert_allclose(radii(V1), r + sign * d, atol=1e-3 * d)
    np.testing.assert_allclose(V1[:, 1], V0[:, 1], atol=1e-12)
    gain = 2.0 * np.pi * (radii(V1).mean() - radii(V0).mean())
    assert gain == pytest.approx(sign * 2.0 * np.pi * d, rel=1e-3)
    # the wrinkled ring's own length is the polygon's with radii r + d, computed here
    phi = np.arctan2(V0[:WN, 0], V0[:WN, 2])
    ring = (r[:WN] + sign * d)[:, None] * np.stack([np.sin(phi), 0.0 * phi, np.cos(phi)], 1)
    assert ring_perimeter(V1) == pytest.approx(ring_perimeter(ring), rel=1e-3)
    # the pattern (a plain rectangle: intrinsic scale s around) gains that length over s
    s = ring_perimeter(V0) / width(g.V2)
    expected = (ring_perimeter(ring) - ring_perimeter(V0)) / s
    assert width(adj.result.V2) - width(g.V2) == pytest.approx(expected, rel=0.02)


# ---------------------------------------------------------------------------------------
# silhouette form
# ---------------------------------------------------------------------------------------


def skirt_rings(V3: np.ndarray, n_around: int = 64) -> np.ndarray:
    """A cone skirt's drape as ``(rings, n_around, 3)``, ring 0 the hem."""
    return V3.reshape(-1, n_around, 3)


@pytest.mark.slow
def test_silhouette_tightens_the_skirt_onto_the_sketch():
    g = cone_skirt()  # y up, hem at y = 0, waist at the top; front view: u = x, v = y
    R = skirt_rings(g.V3)
    right, left = np.argmax(R[0, :, 0]), np.argmin(R[0, :, 0])
    top = R[:, 0, 1].max()
    upper = R[:, 0, 1] >= 0.5 * top - 1e-9
    change = 3.0
    outline = R[upper, right, :2]
    sketch = (outline - [change, 0.0])[::-1].tolist()  # the right outline, 3 cm in
    adj = adjustment(g, recipe({"op": "tighten", "view": "front", "silhouette": sketch}))
    R1 = skirt_rings(adj.state.V3)
    # every ring's outline in the sketch's rows lies on the sketch, within 2 % of the change
    got = R1[upper, :, 0].max(axis=1)
    np.testing.assert_allclose(got, outline[:, 0] - change, atol=0.02 * change)
    np.testing.assert_allclose(R1[upper, right, 1], outline[:, 1], atol=1e-9)
    # the far side follows (rings stay round); the hem keeps its size (as-rigid-as-possible
    # keeps the lengths below the sketch, so it may rise a little)
    np.testing.assert_allclose(R1[upper, left, 0] - R[upper, left, 0], change, atol=0.02 * change)
    r1 = radii(R1[upper].reshape(-1, 3)).reshape(-1, 64)
    assert np.ptp(r1, axis=1).max() < 0.01 * change
    assert np.abs(radii(R1[0]) - radii(R[0])).max() < 0.1 * change
    assert_valid(adj.state.base, V2=adj.result.V2)
    for p in adj.state.panels:
        a0 = signed_areas_2d(g.V2, g.F2[p.faces]).sum()
        a1 = signed_areas_2d(adj.result.V2, g.F2[p.faces]).sum()
        assert a1 < 0.95 * a0
        # the waist edge of the pattern is shorter
        waist = p.vertices[np.abs(g.V2[p.vertices, 1] - g.V2[p.vertices, 1].max()) < 1.0]
        assert np.ptp(adj.result.V2[waist, 0]) < np.ptp(g.V2[waist, 0])
    rec = adj.state.log[-1]
    assert rec["op"] == "tighten" and rec["view"] == "front"
    assert rec["change_mean"] == pytest.approx(-change) and rec["outline_points"] > 4
    assert not adj.state.even.any()


def test_silhouette_loosen_of_a_tube_equals_the_offset():
    g = cylinder()
    r = float(radii(g.V3).max())
    sketch = [[r + 2.0, -1.0], [r + 2.0, 21.0]]  # the whole right outline, 2 cm out
    a = apply_steps(
        g, recipe({"op": "loosen", "view": "front", "silhouette": sketch}), options=EditOptions()
    )
    b = apply_steps(g, recipe({"op": "loosen", "by": 2.0}), options=EditOptions())
    np.testing.assert_allclose(a.V3, b.V3, atol=1e-9)
    assert a.log[-1]["change_mean"] == pytest.approx(2.0)


@pytest.mark.parametrize(
    "sketch",
    [
        [[200.0, 20.0], [205.0, 50.0]],  # far to the right
        [[10.0, 300.0], [12.0, 350.0]],  # above the garment
        [[0.5, 30.0], [0.5, 50.0]],  # on the centre line, far from both outlines
    ],
)
def test_a_sketch_matching_no_outline_is_an_error(sketch):
    g = cone_skirt()
    with pytest.raises(PtailorError, match="matches no outline of the garment in the front view"):
        apply_steps(
            g,
            recipe({"op": "tighten", "view": "front", "silhouette": sketch}),
            options=EditOptions(),
        )


def test_row_crossings():
    Q = np.array([[0.0, 0.0], [2.0, 2.0], [2.0, 4.0], [6.0, 4.0]])
    P = np.array([[5.0, 1.0], [0.0, 3.0], [5.0, 4.0], [1.0, -1.0], [9.0, 4.0]])
    u, found = row_crossings(P, Q)
    assert found.tolist() == [True, True, True, False, True]
    np.testing.assert_allclose(u[found], [1.0, 2.0, 5.0, 6.0])


# ---------------------------------------------------------------------------------------
# recipe validation
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "step, message",
    [
        ("{op: loosen}", "exactly one of 'by'"),
        ("{op: tighten, by: 1, silhouette: [[0, 0], [1, 1]]}", "exactly one of 'by'"),
        ("{op: loosen, by: 2, view: front}", "'view' goes with 'silhouette'"),
        ("{op: tighten, region: all, silhouette: [[0, 0], [1, 1]]}", "'region' goes with 'by'"),
        ("{op: loosen, by: 0}", "must be > 0"),
        ("{op: tighten, silhouette: [[0, 0]]}", "at least 2 points"),
        ("{op: tighten, view: sideways, silhouette: [[0, 0], [1, 1]]}", "expected one of front"),
    ],
)
def test_recipe_checks(step, message):
    with pytest.raises(RecipeError, match=message):
        parse_recipe(f"steps: [{step}]")


# ---------------------------------------------------------------------------------------
# real garments
# ---------------------------------------------------------------------------------------


@pytest.mark.slow
def test_tee6_loosen_all_is_valid():
    g = load_garment(real_path("tee6")).garment
    adj = adjustment(
        g, recipe({"op": "loosen", "region": "all", "by": 1.0}, flatten={"seams": "keep"})
    )
    assert_valid(adj.state.base, V2=adj.result.V2)
    for la, lb in seam_sides(adj.state.base, adj.result.V2):
        assert abs(la - lb) <= 1e-3 * max(la, lb)
    # every panel gets wider: a tube of a half-sleeve gains about pi per half
    for p in adj.state.panels:
        assert width(adj.result.V2[p.vertices]) > width(g.V2[p.vertices]) + 1.0


#: real drapes in true units: path key, pattern units, drape units, torso panels, heights
#: where a torso offset is at full strength (for d up to 5), a box band (y min, y max)
TORSO = {
    "tee6": ("0.3333cm", "0.3333cm", ["back", "front"], [-20.0, -12.0], (-23.0, 9.0)),
    "tshirt": ("auto", "cm", ["front", "back"], [108.0, 116.0], (105.0, 131.0)),
    "longsleeve": ("auto", "cm", ["front", "back"], [80.0, 88.0], (77.0, 102.0)),
    "dress": (  # bodice and skirt, not the straps
        "auto",
        "cm",
        [
            *(f"bodice_back_{s}" for s in ("left", "left_side", "right", "right_side")),
            *(f"bodice_front{s}" for s in ("", "_left", "_right", "_upper")),
            *(f"skirt_{s}" for s in ("front", "back_left", "back_right")),
        ],
        [100.0, 106.0],
        (82.0, 108.0),
    ),
}


@cache
def torso_garment(key: str) -> Garment:
    pu, du = TORSO[key][:2]
    return load_garment(real_path(key), pattern_units=pu, drape_units=du).garment


def torso_region(key: str, kind: str) -> tuple[dict, list[float]]:
    """The recipe region and the heights to measure the girth at."""
    _, _, names, heights, (y0, y1) = TORSO[key]
    if kind == "panels":
        return {"panels": names}, heights
    return {"box": {"min": [-1e3, y0, -1e3], "max": [1e3, y1, 1e3]}}, [0.5 * (y0 + y1)]


def cross_section(V: np.ndarray, F: np.ndarray, faces: np.ndarray, y: float):
    """The material curve at height ``y`` through some triangles: its segments' triangles
    ``(s,)`` and their ends' barycentric coordinates ``(s, 2, 3)``."""
    T = F[faces]
    hgt = V[T][:, :, 1] - y
    neg = hgt < 0.0
    cut = neg.any(axis=1) & ~neg.all(axis=1)
    tri, hgt, neg = faces[cut], hgt[cut], neg[cut]
    a, b = np.array([0, 1, 2]), np.array([1, 2, 0])
    k = np.argsort(neg[:, a] == neg[:, b], axis=1, kind="stable")[:, :2]  # the crossed edges
    ea, eb = a[k], b[k]
    rows = np.arange(len(tri))[:, None]
    t = hgt[rows, ea] / (hgt[rows, ea] - hgt[rows, eb])
    bary = np.zeros((len(tri), 2, 3))
    bary[rows, [0, 1], ea] = 1.0 - t
    bary[rows, [0, 1], eb] = t
    return tri, bary


def curve_length(X: np.ndarray, F: np.ndarray, tri: np.ndarray, bary: np.ndarray) -> float:
    P = np.einsum("skc,scd->skd", bary, X[F[tri]])
    return float(np.linalg.norm(P[:, 0] - P[:, 1], axis=1).sum())


def girth_gains(g: Garment, faces: np.ndarray, y: float, V3: np.ndarray, V2=None):
    """Length gains of the material curve at height ``y``: ``(3D, pattern, s)``, with ``s``
    the curve's intrinsic scale (3D over pattern length) before."""
    tri, bary = cross_section(g.V3, g.F3, faces, y)
    l3 = curve_length(g.V3, g.F3, tri, bary)
    l2 = curve_length(g.V2, g.F2, tri, bary)
    g3 = curve_length(V3, g.F3, tri, bary) - l3
    g2 = None if V2 is None else curve_length(V2, g.F2, tri, bary) - l2
    return g3, g2, l3 / l2


def test_cross_section_of_a_cylinder_is_its_circumference():
    g = cylinder()  # a 40-gon of perimeter 30
    tri, bary = cross_section(g.V3, g.F3, np.arange(g.n_faces), 7.3)
    assert curve_length(g.V3, g.F3, tri, bary) == pytest.approx(30.0, rel=1e-12)
    assert curve_length(g.V2, g.F2, tri, bary) == pytest.approx(30.0, rel=1e-12)


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["panels", "box"])
@pytest.mark.parametrize("d", [1.0, 5.0])
@pytest.mark.parametrize("key", sorted(TORSO))
def test_real_torso_offset_adds_2_pi_d_of_girth(key, d, kind):
    """Simulated drapes (wrinkles of radius well below 1 cm): loosening the torso by d
    turns nothing over and adds 2 pi d of girth around it, within 15 % (the wrinkles ride
    along, so the wrinkled curve gains a little less: 0.92 to 1.0 measured)."""
    g = torso_garment(key)
    region, heights = torso_region(key, kind)
    s = apply_steps(g, recipe({"op": "loosen", "region": region, "by": d}), options=EditOptions())
    assert not turned_faces(g.V3, s.V3, g.F3).any()
    faces = region_faces(region, g, g.V3, panels(g))
    for y in heights:
        gain3, _, _ = girth_gains(g, faces, y, s.V3)
        assert gain3 == pytest.approx(2.0 * np.pi * d, rel=0.15), y


@pytest.mark.slow
@pytest.mark.parametrize("key", ["tee6", "tshirt"])
def test_real_torso_loosen_2cm_widens_the_pattern_by_2_pi_d_over_s(key):
    g = torso_garment(key)
    d = 2.0
    region, heights = torso_region(key, "panels")
    adj = adjustment(g, recipe({"op": "loosen", "region": region, "by": d}))
    assert not turned_faces(g.V3, adj.state.V3, g.F3).any()
    assert_valid(adj.state.base, V2=adj.result.V2)  # no flipped pattern triangle
    faces = region_faces(region, g, g.V3, panels(g))
    for y in heights:
        _, gain2, s = girth_gains(g, faces, y, adj.state.V3, adj.result.V2)
        assert gain2 == pytest.approx(2.0 * np.pi * d / s, rel=0.15), y


@pytest.mark.slow
@pytest.mark.parametrize("key, kind", [("tee6", "box"), ("tshirt", "panels")])
def test_real_torso_loosen_cli_exits_0_without_flips(tmp_path, key, kind):
    from click.testing import CliRunner

    from ptailor.cli.main import cli

    pu, du = TORSO[key][:2]
    region, _ = torso_region(key, kind)
    rec = tmp_path / "r.yaml"
    rec.write_text(
        yaml.safe_dump({"units": "cm", "steps": [{"op": "loosen", "region": region, "by": 2}]})
    )
    out = tmp_path / "o"
    args = ["adjust", str(real_path(key)), str(rec), "-o", str(out)]
    args += ["--pattern-units", pu, "--drape-units", du, "--formats", "obj", "--no-baseline"]
    res = CliRunner().invoke(cli, args)
    assert res.exit_code == 0, res.output
    report = json.loads((out / "report.json").read_text())
    assert sum(p["flipped_triangles"] for p in report["panels"]) == 0


@pytest.mark.slow
def test_real_tightening_sleeves_past_their_radius_names_them():
    g = torso_garment("tee6")  # half-sleeves 16.7 cm wide: a tube of radius about 5.3
    with pytest.raises(PtailorError, match="inside out") as err:
        apply_steps(g, recipe({"op": "tighten", "region": "all", "by": 8.0}), options=EditOptions())
    # most turned triangles are on the sleeves (four halves), between y 12.8 and 26.9
    assert re.search(r"\(panel 'sleeve_\w+', 'sleeve_\w+'", str(err.value)), str(err.value)
    # the torso alone tightens by that much
    faces = region_faces({"panels": ["back", "front"]}, g, g.V3, panels(g))
    s = apply_steps(
        g,
        recipe({"op": "tighten", "region": {"panels": ["back", "front"]}, "by": 5.0}),
        options=EditOptions(),
    )
    assert not turned_faces(g.V3, s.V3, g.F3[faces]).any()
