"""Shorten: the iso-line of surface distance from an opening becomes the new edge."""

from __future__ import annotations

import numpy as np
import pytest

from ptailor.errors import PtailorError
from ptailor.formats.garment import load_garment
from ptailor.geometry.segments import nearest_segment_distance as point_segment_distance
from ptailor.model.frame import Frame
from ptailor.pipeline import adjustment
from ptailor.recipe import parse_recipe
from ptailor.run import RunOptions, run_garment
from ptailor.samples import cone_skirt, cylinder, lantern_sleeve
from tests.conftest import REAL, real_path
from tests.garment_checks import adjust_sample_cli, assert_seams_equal, assert_valid


def ring(V: np.ndarray, used: np.ndarray, which) -> np.ndarray:
    y = V[used, 1]
    return used[np.isclose(y, which(y))]


def test_cone_skirt_hem_moves_exactly_inward_waist_untouched():
    g = cone_skirt()
    adj = adjustment(g, parse_recipe("steps: [{op: shorten, opening: hem, by: 5}]"))
    b = adj.state.base
    assert_valid(b, V2=adj.result.V2)
    assert_seams_equal(b, adj.result.V2)
    rec = adj.state.log[0]
    for side in ("front", "back"):
        assert rec["achieved"]["pattern"][side]["mean"] == pytest.approx(5.0, rel=1e-2)
        assert rec["achieved"]["pattern"][side]["min"] == pytest.approx(5.0, rel=1e-2)
        assert rec["achieved"]["pattern"][side]["max"] == pytest.approx(5.0, rel=1e-2)
    # in the pattern: the new hem is 5 from the old hem arc, the waist vertices did not move
    used0 = np.unique(g.F3)
    old_hem3 = ring(g.V3, used0, np.min)
    new_used = np.unique(b.F3)
    new_hem3 = ring(adj.state.V3, new_used, np.min)
    P = adj.result.V2[np.unique(b.F2[np.isin(b.F3, new_hem3)])]
    # distance of the new hem's pattern vertices from the old hem polyline of each panel
    h_old = g.V2[np.unique(g.F2[np.isin(g.F3, old_hem3)])]
    d = point_segment_distance(P, h_old, h_old)  # to the old hem's vertices (a fine ring)
    assert np.median(d) == pytest.approx(5.0, rel=2e-2)
    waist3 = ring(g.V3, used0, np.max)
    waist_new = ring(adj.state.V3, new_used, np.max)
    assert len(waist_new) == len(waist3)
    np.testing.assert_allclose(np.sort(adj.state.V3[waist_new, 0]), np.sort(g.V3[waist3, 0]))


def test_shorten_then_extend_bookkeeping_on_the_elastic_cuff():
    g = lantern_sleeve()
    adj = adjustment(g, parse_recipe("steps: [{op: shorten, opening: cuff, by: 3}]"))
    b = adj.state.base
    assert_valid(b, V2=adj.result.V2)
    # the cuff (8 high) lost 3 in 3D and 3 in the pattern (height is isometric there)
    cuff = next(p for p in adj.state.panels if p.name == "cuff")
    h = np.ptp(adj.result.V2[cuff.vertices], axis=0)
    assert h[1] == pytest.approx(5.0, rel=1e-6)
    assert h[0] == pytest.approx(40.0, rel=1e-6)


@pytest.mark.slow
@pytest.mark.parametrize("key", ["tee6", "dress"])
def test_shorten_hem_on_real_garments(key, tmp_path):
    path = real_path(key)
    g = load_garment(path, pattern_units=REAL[key][1]).garment
    by = 5.0 if key == "tee6" else 0.05 * np.ptp(g.V3[:, 1])
    adj = adjustment(
        g, parse_recipe(f"steps: [{{op: shorten, opening: hem, by: {by}}}]"), baseline=False
    )
    b = adj.state.base
    assert_valid(b, V2=adj.result.V2)
    from tests.garment_checks import seam_sides

    if all(abs(x - y) <= 1e-6 * max(x, y) for x, y in seam_sides(g, g.V2)):
        assert_seams_equal(b, adj.result.V2)
    ach = adj.state.log[0]["achieved"]["3d"]
    assert ach["mean"] == pytest.approx(by, rel=0.05)
    # the output is a garment ptailor can adjust again
    rep = run_garment(
        str(path),
        parse_recipe(f"steps: [{{op: shorten, opening: hem, by: {by}}}]"),
        tmp_path / "o",
        options=RunOptions(pattern_units=REAL[key][1], drape_units="cm"),
    )
    again = run_garment(
        str(tmp_path / "o" / "garment.obj"),
        parse_recipe("steps: []"),
        tmp_path / "o2",
        options=RunOptions(pattern_units=REAL[key][1], drape_units="cm"),
    )
    assert len(again["panels"]) == len(rep["panels"])


@pytest.mark.parametrize(
    ("step", "message"),
    [
        ("{op: shorten, opening: hem, by: 500}", "nowhere farther"),
        ("{op: shorten, opening: collar, by: 5}", "no opening named 'collar'"),
        ("{op: shorten, opening: {loop: 9}, by: 5}", "no opening {loop: 9}"),
    ],
)
def test_shorten_errors(tmp_path, step, message):
    r = adjust_sample_cli(tmp_path, step)
    assert r.exit_code == 2 and message in r.output, r.output
    assert not (tmp_path / "o").exists()
    if "collar" in step:
        assert "hem" in r.output and "waist" in r.output  # lists what the garment has


@pytest.mark.slow
@pytest.mark.parametrize("op", ["extend", "shorten"])
def test_dress_hem_edits_are_valid_and_readjustable(op, tmp_path):
    import ptailor.edits.extend  # noqa: F401  (registers the op)

    path = real_path("dress")
    rec = parse_recipe(f"steps: [{{op: {op}, opening: hem, by: 5}}]")
    rep = run_garment(
        str(path), rec, tmp_path / "o", options=RunOptions(pattern_units="auto", baseline=False)
    )
    out = load_garment(tmp_path / "o" / "garment.obj", pattern_units="auto").garment
    assert_valid(out)
    assert rep["steps"][0]["achieved"]["3d"]["mean"] == pytest.approx(5.0, rel=0.05)
    assert all(p["flipped_triangles"] == 0 for p in rep["panels"])
    again = run_garment(
        str(tmp_path / "o" / "garment.obj"),
        parse_recipe("steps: []"),
        tmp_path / "o2",
        options=RunOptions(pattern_units="auto"),
    )
    assert len(again["panels"]) == len(rep["panels"])


# ---------------------------------------------------------------------------------------
# measure: pattern
# ---------------------------------------------------------------------------------------


def stretched_tube(amplitude: float = 0.3):
    """A tube whose drape is stretched along by ``1 + amplitude cos(phi)`` around it.

    The pattern is :func:`ptailor.samples.cylinder`'s rectangle (hem on ``y = 0``); each
    drape column is taller than its pattern column by its own factor, so surface distance
    from the hem and pattern distance from it differ column by column.
    """
    from dataclasses import replace

    g = cylinder(circumference=30.0, height=20.0, n_around=40, n_along=16)
    phi = np.arctan2(g.V3[:, 2], g.V3[:, 0])
    V3 = g.V3.copy()
    V3[:, 1] *= 1.0 + amplitude * np.cos(phi)
    return replace(g, V3=V3)


def new_edge_vertices(adj, name: str = "hem") -> np.ndarray:
    """Pattern vertices of the adjusted garment's opening ``name``."""
    from ptailor.edits.extend import opening_edges
    from ptailor.model.openings import openings

    b = adj.state.base
    loop = next(o.loop for o in openings(adj.state.V3, b.F3, frame=Frame()) if o.name == name)
    oe = opening_edges(b.F3, b.F2, loop)
    return np.unique(np.r_[oe.a2, oe.b2])


def output_edge_distances(g0, adj, name: str = "hem") -> dict:
    """Per input panel: the new edge's distances from the old one in ``adj.result.V2``.

    The old edge's pattern segments are carried into the output's frame by each panel's
    rigid fit from the adjusted garment's own original pattern to the output.
    """
    from ptailor.edits.extend import opening_edges
    from ptailor.model.garment import panels
    from ptailor.model.openings import openings

    def by_panel(g, V3):
        loop = next(o.loop for o in openings(V3, g.F3, frame=Frame()) if o.name == name)
        oe = opening_edges(g.F3, g.F2, loop)
        plist = panels(g)
        flab = np.empty(g.n_faces, dtype=np.int64)
        for p in plist:
            flab[p.faces] = p.index
        return {
            p.name: (oe.a2[flab[oe.face] == p.index], oe.b2[flab[oe.face] == p.index])
            for p in plist
            if np.any(flab[oe.face] == p.index)
        }, {p.name: p for p in plist}

    old, _ = by_panel(g0, g0.V3)
    b, X = adj.state.base, adj.result.V2
    new, plist = by_panel(b, adj.state.V3)
    out = {}
    for pname, (a0, b0) in old.items():
        q = plist[pname]
        Y, Z = b.V2[q.vertices], X[q.vertices]
        cy, cz = Y.mean(0), Z.mean(0)
        U, _, Vt = np.linalg.svd((Y - cy).T @ (Z - cz))
        R = (U @ np.diag([1.0, np.sign(np.linalg.det(U @ Vt))]) @ Vt).T
        assert np.abs((Y - cy) @ R.T + cz - Z).max() < 1e-6 * np.ptp(Y, axis=0).max()
        A, B = (g0.V2[a0] - cy) @ R.T + cz, (g0.V2[b0] - cy) @ R.T + cz
        pts = np.unique(np.r_[new[pname]])
        out[pname] = point_segment_distance(X[pts], A, B)
    return out


def test_pattern_measure_cuts_a_straight_hem_exactly_by_up_on_a_stretched_tube():
    g = stretched_tube()
    rec = parse_recipe("steps: [{op: shorten, opening: hem, by: 3, measure: pattern}]")
    adj = adjustment(g, rec)
    b, X = adj.state.base, adj.result.V2
    assert_valid(b, V2=X)
    assert_seams_equal(b, X)
    # hand-computed: the new hem is the pattern line y = 3, across the whole width
    hem = new_edge_vertices(adj)
    np.testing.assert_allclose(X[hem, 1], 3.0, atol=1e-9)
    np.testing.assert_allclose([X[hem, 0].min(), X[hem, 0].max()], [0.0, 30.0], atol=1e-9)
    np.testing.assert_allclose(np.ptp(X[:, 1]), 17.0, atol=1e-9)  # 20 - 3, nothing else cut
    step = adj.state.log[-1]
    assert step["measure"] == "pattern"
    assert step["amount"]["pattern"]["tube"] == {"min": 3.0, "median": 3.0, "max": 3.0}
    # on the drape the strip is 3 (1 + 0.3 cos phi) wide: 2.1 to 3.9 (at the columns)
    drape = step["amount"]["drape"]
    assert drape["min"] == pytest.approx(2.1, abs=0.05) and drape["max"] > 3.8
    assert drape["median"] == pytest.approx(3.0, abs=0.2)


def test_drape_measure_is_the_default_and_leaves_that_hem_uneven():
    g = stretched_tube()
    adj = adjustment(g, parse_recipe("steps: [{op: shorten, opening: hem, by: 3}]"))
    step = adj.state.log[-1]
    assert step["measure"] == "drape"
    y = adj.result.V2[new_edge_vertices(adj), 1]
    assert np.ptp(y) > 1.5  # 3 / 1.3 to 3 / 0.7 in the pattern
    assert step["amount"]["pattern"]["tube"]["min"] == pytest.approx(3 / 1.3, abs=0.05)
    assert step["amount"]["drape"] == {"min": 3.0, "median": 3.0, "max": 3.0}


def test_pattern_measure_on_the_cone_skirt_keeps_the_side_seams_one():
    g = cone_skirt(n_around=32, n_along=12)
    adj = adjustment(
        g, parse_recipe("steps: [{op: shorten, opening: hem, by: 4.3, measure: pattern}]")
    )
    b, X = adj.state.base, adj.result.V2
    assert_valid(b, V2=X)
    assert_seams_equal(b, X)
    for side in ("front", "back"):
        d = output_edge_distances(g, adj)[side]
        np.testing.assert_allclose(d, 4.3, atol=1e-9)


def test_pattern_distance_is_carried_over_seams_into_the_next_panel():
    """Shorten the lantern cuff (8 high) by 10.5: the cuff goes, the sleeve loses 2.5."""
    g = lantern_sleeve()
    rec = parse_recipe("steps: [{op: shorten, opening: cuff, by: 10.5, measure: pattern}]")
    adj = adjustment(g, rec)
    b, X = adj.state.base, adj.result.V2
    assert_valid(b, V2=X)
    assert [p.name for p in adj.state.panels] == ["sleeve"]
    step = adj.state.log[-1]
    assert step["amount"]["removed_panels"] == ["cuff"]
    assert step["amount"]["pattern"] == {}  # no cuff edge is left to measure
    hem = new_edge_vertices(adj, "cuff")  # the sleeve alone is still a lone sleeve
    np.testing.assert_allclose(X[hem, 1] - g.V2[:, 1].min(), 2.5, atol=1e-9)
    np.testing.assert_allclose(np.ptp(X[:, 1]), 37.5, atol=1e-9)


@pytest.mark.slow
@pytest.mark.parametrize("key", sorted(REAL))
def test_real_hem_shortened_by_5_in_the_output_pattern(key):
    """Acceptance: with ``measure: pattern`` every panel's new hem is 5 +- 0.05 away."""
    g = load_garment(real_path(key), pattern_units=REAL[key][1]).garment
    rec = parse_recipe("steps: [{op: shorten, opening: hem, by: 5, measure: pattern}]")
    adj = adjustment(g, rec, baseline=False)
    assert_valid(adj.state.base, V2=adj.result.V2)
    dist = output_edge_distances(g, adj)
    assert len(dist) >= 2
    for d in dist.values():
        assert np.all(np.abs(d - 5.0) <= 0.05), (d.min(), d.max())
    amount = adj.state.log[-1]["amount"]
    assert sorted(amount["pattern"]) == sorted(dist)
    assert all(abs(v[s] - 5.0) <= 0.05 for v in amount["pattern"].values() for s in v)


@pytest.mark.slow
def test_tee6_hem_shortened_by_5_on_the_drape_is_uneven_in_the_pattern():
    """The paper's measure: 5 on the drape, 5.4 to 7.7 in the pattern (an S-shaped hem)."""
    g = load_garment(real_path("tee6"), pattern_units=REAL["tee6"][1]).garment
    for measure, drape_max in (("drape", 5.01), ("pattern", 4.8)):
        rec = parse_recipe(f"steps: [{{op: shorten, opening: hem, by: 5, measure: {measure}}}]")
        adj = adjustment(g, rec, baseline=False)
        dist = output_edge_distances(g, adj)
        amount = adj.state.log[-1]["amount"]
        assert amount["drape"]["max"] < drape_max
        if measure == "drape":
            assert max(d.max() for d in dist.values()) > 6.5
            assert amount["drape"]["min"] == pytest.approx(5.0, abs=0.01)


def test_pattern_measure_refuses_a_strip_wider_than_the_garment():
    rec = parse_recipe("steps: [{op: shorten, opening: hem, by: 500, measure: pattern}]")
    with pytest.raises(PtailorError, match=r"nowhere farther than that from its hem \(in the"):
        adjustment(cone_skirt(), rec)


def test_measure_is_a_checked_recipe_key():
    with pytest.raises(PtailorError, match="measure"):
        parse_recipe("steps: [{op: shorten, opening: hem, by: 5, measure: ruler}]")


@pytest.mark.slow
@pytest.mark.parametrize("op", ["shorten", "extend"])
@pytest.mark.parametrize("sample", ["cone_skirt", "bodice", "cylinder", "lantern_sleeve"])
def test_generated_hems_move_exactly_5_in_the_output_pattern(sample, op):
    from ptailor.samples import SAMPLES

    g = SAMPLES[sample]()
    end = "cuff" if sample == "lantern_sleeve" else "hem"  # a lone sleeve's lower end
    rec = parse_recipe(f"steps: [{{op: {op}, opening: {end}, by: 5, measure: pattern}}]")
    adj = adjustment(g, rec, baseline=False)
    assert_valid(adj.state.base, V2=adj.result.V2)
    for d in output_edge_distances(g, adj, end).values():
        np.testing.assert_allclose(d, 5.0, atol=1e-6)


def test_a_cut_through_existing_vertices_reports_what_it_achieved():
    """The bodice's rows lie 40/24 apart: 5 from the hem in the pattern hits no row, but
    the record must measure the new edge whether the split made its vertices or found
    them on the level."""
    from ptailor.samples import bodice

    for by in (5.0, 40.0 / 24 * 3):  # between rows, and exactly on a row
        adj = adjustment(
            bodice(), parse_recipe(f"steps: [{{op: shorten, opening: hem, by: {by}}}]")
        )
        rec = adj.state.log[0]
        assert rec["achieved"]["3d"]["mean"] == pytest.approx(by, rel=1e-3)
        for side in ("front", "back"):
            assert rec["achieved"]["pattern"][side]["min"] == pytest.approx(by, rel=1e-3)
