"""Shorten: the iso-line of surface distance from an opening becomes the new edge."""

from __future__ import annotations

import numpy as np
import pytest

from ptailor.adjust import adjust
from ptailor.formats.garment import load_garment
from ptailor.job import run_adjust
from ptailor.recipe import parse_recipe
from ptailor.report.outline import point_segment_distance
from ptailor.samples import cone_skirt, lantern_sleeve
from tests.conftest import REAL, real_path
from tests.garment_checks import adjust_sample_cli, assert_seams_equal, assert_valid


def ring(V: np.ndarray, used: np.ndarray, which) -> np.ndarray:
    y = V[used, 1]
    return used[np.isclose(y, which(y))]


def test_cone_skirt_hem_moves_exactly_inward_waist_untouched():
    g = cone_skirt()
    adj = adjust(g, parse_recipe("steps: [{op: shorten, opening: hem, by: 5}]"))
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
    adj = adjust(g, parse_recipe("steps: [{op: shorten, opening: hem, by: 3}]"))
    b = adj.state.base
    assert_valid(b, V2=adj.result.V2)
    # the cuff (8 high) lost 3 in 3D and 3 in the pattern (height is isometric there)
    cuff = next(p for p in adj.state.panels if p.name == "cuff")
    h = np.ptp(adj.result.V2[cuff.vertices], axis=0)
    assert h[1] == pytest.approx(5.0, rel=1e-6)
    assert h[0] == pytest.approx(40.0, rel=1e-6)


@pytest.mark.parametrize("key", ["tee6", "dress"])
def test_shorten_hem_on_real_garments(key, tmp_path):
    path = real_path(key)
    g = load_garment(path, pattern_units=REAL[key][1]).garment
    by = 5.0 if key == "tee6" else 0.05 * np.ptp(g.V3[:, 1])
    adj = adjust(
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
    rep = run_adjust(
        str(path),
        parse_recipe(f"steps: [{{op: shorten, opening: hem, by: {by}}}]"),
        tmp_path / "o",
        pattern_units=REAL[key][1],
    )
    again = run_adjust(
        str(tmp_path / "o" / "garment.obj"),
        parse_recipe("steps: []"),
        tmp_path / "o2",
        pattern_units=REAL[key][1],
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


@pytest.mark.parametrize("op", ["extend", "shorten"])
def test_dress_hem_edits_are_valid_and_readjustable(op, tmp_path):
    import ptailor.edits.extend  # noqa: F401  (registers the op)

    path = real_path("dress")
    rec = parse_recipe(f"steps: [{{op: {op}, opening: hem, by: 5}}]")
    rep = run_adjust(str(path), rec, tmp_path / "o", pattern_units="auto", baseline=False)
    out = load_garment(tmp_path / "o" / "garment.obj", pattern_units="auto").garment
    assert_valid(out)
    assert rep["steps"][0]["achieved"]["3d"]["mean"] == pytest.approx(5.0, rel=0.05)
    assert all(p["flipped_triangles"] == 0 for p in rep["panels"])
    again = run_adjust(
        str(tmp_path / "o" / "garment.obj"),
        parse_recipe("steps: []"),
        tmp_path / "o2",
        pattern_units="auto",
    )
    assert len(again["panels"]) == len(rep["panels"])
