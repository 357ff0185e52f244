"""Cut: exact splits, barycentric pattern transfer, valid output, clear errors."""

from __future__ import annotations

import numpy as np
import pytest

from ptailor.errors import PtailorError
from ptailor.formats.garment import load_garment
from ptailor.geometry.topology import half_edges
from ptailor.model.garment import panels
from ptailor.pipeline import adjustment
from ptailor.recipe import parse_recipe
from ptailor.run import RunOptions, run_garment
from ptailor.samples import cone_skirt, lantern_sleeve
from tests.conftest import real_path
from tests.garment_checks import adjust_sample_cli, assert_seams_equal, assert_valid

PLANE = "steps: [{op: cut, plane: {point: [0, 20, 0], normal: [0, -1, 0]}}]"


def test_plane_cut_splits_exactly_and_transfers_the_pattern():
    g = cone_skirt()
    adj = adjustment(g, parse_recipe(PLANE))
    b = adj.state.base
    assert_valid(b, V2=adj.result.V2)
    # everything below y = 20 is gone, the new edge lies on the plane
    used = np.unique(b.F3)
    assert adj.state.V3[used, 1].min() == pytest.approx(20.0, abs=1e-9)
    # no deformation: the final pattern is the transferred one, kept triangles unchanged
    np.testing.assert_allclose(adj.result.V2, b.V2, atol=1e-9)
    # developable and isometric: every pattern edge has its drape length, new ones included
    h3, h2 = half_edges(b.F3), half_edges(b.F2)
    l3 = np.linalg.norm(b.V3[h3[:, 1]] - b.V3[h3[:, 0]], axis=1)
    l2 = np.linalg.norm(b.V2[h2[:, 1]] - b.V2[h2[:, 0]], axis=1)
    np.testing.assert_allclose(l2, l3, rtol=1e-9)
    assert_seams_equal(b, adj.result.V2)
    assert [p.name for p in adj.state.panels] == ["front", "back"]
    rec = adj.state.log[0]
    assert rec["split_triangles"] == 128 and rec["new_edge_vertices"] == 128


def test_cut_through_a_seam_gives_one_drape_vertex_and_two_pattern_vertices():
    g = lantern_sleeve()  # the sleeve's closing seam runs along y
    adj = adjustment(
        g, parse_recipe("steps: [{op: cut, plane: {point: [0, 30.3, 0], normal: [0, 1, 0]}}]")
    )
    b = adj.state.base
    ring = np.flatnonzero(np.isclose(adj.state.V3[:, 1], 30.3))
    assert len(ring) == 96  # per column: the vertical edge and the quad's diagonal
    on_cut2 = np.unique(b.F2[np.isin(b.F3, ring)])
    assert len(on_cut2) == 97  # the seam's crossing appears once per side in the pattern
    assert_valid(b, V2=adj.result.V2)


def test_sketch_cut_both_layers_and_near_layer():
    g = cone_skirt()
    both = adjustment(
        g,
        parse_recipe(
            "steps: [{op: cut, view: front, sketch: [[-50, 15], [0, 25], [50, 15]], remove: below}]"
        ),
    )
    near = adjustment(
        g,
        parse_recipe(
            "steps: [{op: cut, view: front, sketch: [[-50, 15], [0, 25], [50, 15]], remove: below,"
            " layers: near}]"
        ),
    )
    zf = both.state.V3[np.unique(both.state.base.F3)]
    # both layers: nothing below the sketch is left, front or back
    assert zf[:, 1].min() >= 15 - 1e-9
    zn = near.state.V3[np.unique(near.state.base.F3)]
    back_low = (zn[:, 2] < -5) & (zn[:, 1] < 10)
    front_low = (zn[:, 2] > 5) & (zn[:, 1] < 10)
    assert back_low.any() and not front_low.any()
    for a in (both, near):
        assert_valid(a.state.base, V2=a.result.V2)


def test_symmetric_cut_mirrors_the_sketch():
    g = cone_skirt()
    adj = adjustment(
        g,
        parse_recipe(
            "steps: [{op: cut, view: front, sketch: [[10, 0], [10, 60]], remove: right,"
            " symmetric: true}]"
        ),
    )
    X = adj.state.V3[np.unique(adj.state.base.F3), 0]
    # the mirror plane passes through the area centroid (x = 0 up to triangulation)
    assert X.min() == pytest.approx(-10, abs=1e-3) and X.max() == pytest.approx(10, abs=1e-3)


@pytest.mark.slow
def test_cut_output_can_be_adjusted_again(tmp_path):
    from ptailor.samples.obj_text import sample_obj_text

    src = tmp_path / "skirt.obj"
    src.write_text(sample_obj_text("cone_skirt"))
    run_garment(str(src), parse_recipe(PLANE), tmp_path / "o")
    again = load_garment(tmp_path / "o" / "garment.obj")
    rep = run_garment(
        str(tmp_path / "o" / "garment.obj"), parse_recipe("steps: []"), tmp_path / "o2"
    )
    assert [p["name"] for p in rep["panels"]] == ["front", "back"]
    assert again.garment.n_faces == rep["panels"][0]["triangles"] + rep["panels"][1]["triangles"]


@pytest.mark.slow
@pytest.mark.parametrize(
    ("step", "message"),
    [
        ("{op: cut, plane: {point: [0, 500, 0], normal: [0, 1, 0]}}", "misses the garment"),
        ("{op: cut, plane: {point: [0, 500, 0], normal: [0, -1, 0]}}", "whole garment"),
        ("{op: cut, view: front, sketch: [[-50, 500], [50, 500]], remove: above}", "misses"),
    ],
)
def test_cut_errors(tmp_path, step, message):
    r = adjust_sample_cli(tmp_path, step)
    assert r.exit_code == 2 and message in r.output
    assert not (tmp_path / "o").exists()
    with pytest.raises(PtailorError):
        adjustment(
            load_garment(tmp_path / "cone_skirt.obj").garment, parse_recipe(f"steps: [{step}]")
        )


@pytest.mark.slow
@pytest.mark.parametrize("key", ["tee6", "dress"])
def test_plane_cut_on_real_garments(key, tmp_path):
    from tests.conftest import REAL
    from tests.garment_checks import seam_sides

    path = real_path(key)
    g = load_garment(path, pattern_units=REAL[key][1]).garment
    used = np.unique(g.F3)
    y0, y1 = g.V3[used, 1].min(), g.V3[used, 1].max()
    y = y0 + 0.3 * (y1 - y0)
    rec = parse_recipe(f"steps: [{{op: cut, plane: {{point: [0, {y}, 0], normal: [0, -1, 0]}}}}]")
    adj = adjustment(g, rec, baseline=False)
    b = adj.state.base
    assert_valid(b, V2=adj.result.V2)
    assert adj.state.V3[np.unique(b.F3), 1].min() >= y - 1e-6
    # seams equal before stay equal (barycentric transfer on both sides)
    if all(abs(a - c) <= 1e-6 * max(a, c) for a, c in seam_sides(g, g.V2)):
        assert_seams_equal(b, adj.result.V2)
    assert len(panels(b)) >= 1
    # ptailor takes its own output again
    run_garment(
        str(path),
        rec,
        tmp_path / "o",
        options=RunOptions(pattern_units=REAL[key][1], drape_units="cm", baseline=False),
    )
    again = run_garment(
        str(tmp_path / "o" / "garment.obj"),
        parse_recipe("steps: []"),
        tmp_path / "o2",
        options=RunOptions(pattern_units=REAL[key][1], drape_units="cm", baseline=False),
    )
    assert sum(p["triangles"] for p in again["panels"]) == b.n_faces


def test_polyline_side_at_a_shared_vertex_uses_the_pseudo_normal():
    from ptailor.edits.cut import polyline_side

    Q = np.array([[-8.0, 60.0], [0.0, 50.0], [8.0, 60.0]])  # a V, travelling left to right
    below = np.array([[23.3, 21.0], [-23.3, 21.0], [0.0, 0.0], [30.0, 10.0]])
    above = np.array([[0.0, 70.0], [0.0, 55.0]])
    assert np.all(polyline_side(below, Q) < 0)  # right of travel
    assert np.all(polyline_side(above, Q) > 0)


def test_near_layer_v_notch_removes_only_the_notch():
    g = cone_skirt()
    adj = adjustment(
        g,
        parse_recipe(
            "steps: [{op: cut, view: front, sketch: [[-8, 60], [0, 50], [8, 60]], remove: above,"
            " layers: near}]"
        ),
    )
    kept = adj.state.V3[np.unique(adj.state.base.F3)]
    # everything below the notch's tip is kept, front and back
    lost_area = g.n_faces - adj.state.base.n_faces
    assert 0 < adj.state.log[0]["removed_triangles"] < 200
    assert lost_area < 200
    assert kept[:, 1].min() == pytest.approx(g.V3[:, 1].min())


def test_a_cut_that_splits_a_panel_reports_each_part_with_its_share():
    """Issue 23, item 4: a V-neck through a collar split it into ``collar`` and ``collar_1``;
    the report gave ``collar`` -96 % area and ``collar_1`` ``area_before`` 0. The step
    record gives each panel's removed fraction and its parts' shares, the report each
    part's share of the original's area as ``area_before``, and a cut that removes most
    of a panel warns."""
    from ptailor.pipeline import solver_warnings
    from ptailor.recipe import parse_recipe
    from ptailor.report.build import build_report
    from ptailor.samples import bodice

    g = bodice()
    sketch = "[[-4, 80], [0, -20], [4, 80]]"  # a V through the front's whole height
    text = f"steps: [{{op: cut, view: front, sketch: {sketch}, remove: above, layers: near}}]"
    a = adjustment(g, parse_recipe(text), baseline=False)
    front = a.state.log[-1]["panels"]["front"]
    assert set(front["parts"]) == {"front", "front_1"}
    assert front["removed"] + sum(front["parts"].values()) == pytest.approx(1.0, abs=1e-6)
    assert "back" not in a.state.log[-1]["panels"]  # untouched
    r = build_report(a, inputs={}, units_note={}, warnings=[], timing_s={})
    by = {p["name"]: p for p in r["panels"]}
    for name in ("front", "front_1"):
        assert by[name]["area_after"] == pytest.approx(by[name]["area_before"], rel=1e-3)
    wide = text.replace("[[-4, 80], [0, -20], [4, 80]]", "[[-40, 80], [0, -20], [40, 80]]")
    a = adjustment(g, parse_recipe(wide), baseline=False)
    assert any("removes" in w and "of panel front" in w for w in solver_warnings(a))


def test_a_cut_keeps_the_names_of_the_seams_it_did_not_make():
    """Issue 23, item 4: a V-neck through the shared long-sleeve's collar renamed its seams
    (``collar_left`` -> ``yoke_front_left``, ``neckline_front`` -> ``neckline_left``). A
    seam of the cut garment that lies on a seam of the input keeps its name; the second
    piece of a seam the cut split is ``NAME_2``."""
    from ptailor.report.build import build_report

    g = load_garment(real_path("longsleeve"), pattern_units="auto", drape_units="cm").garment

    def seam_names_after(text: str) -> list[str]:
        a = adjustment(g, parse_recipe(text), baseline=False)
        r = build_report(a, inputs={}, units_note={}, warnings=[], timing_s={})
        return sorted(s["name"] for s in r["seams"])

    before = seam_names_after("units: cm\nsteps: []")
    cut = (
        "units: cm\nsteps: [{op: cut, view: front, sketch: [[-12, 150], [0, 118], [12, 150]], "
        "remove: above, layers: near}]"
    )
    after = seam_names_after(cut)
    assert set(before) <= set(after)
    assert all(n[:-2] in before and n.endswith("_2") for n in set(after) - set(before))


def test_a_sketch_measured_from_an_opening_cuts_the_same_wherever_the_garment_sits():
    """``origin: waist``: the sketch's [0, 0] is the waist's centre front (its lowest point
    on the near layer), so the same recipe cuts the same notch on a garment moved 30 cm up
    and 5 cm across, where drape coordinates would miss it."""
    import dataclasses

    from ptailor.pipeline import adjustment
    from ptailor.recipe import parse_recipe
    from ptailor.samples import cone_skirt

    text = (
        "steps: [{op: cut, view: front, origin: waist, sketch: [[-8, 1], [0, -8], [8, 1]], "
        "remove: above, layers: near}]"
    )
    g = cone_skirt()
    moved = dataclasses.replace(g, V3=g.V3 + np.array([5.0, 30.0, 0.0]))
    a, b = (adjustment(x, parse_recipe(text), baseline=False) for x in (g, moved))
    ra, rb = a.state.log[-1], b.state.log[-1]
    assert ra["removed_triangles"] == rb["removed_triangles"] > 0
    assert rb["origin"] == pytest.approx([ra["origin"][0] + 5.0, ra["origin"][1] + 30.0])
    assert ra["origin"][1] == pytest.approx(g.V3[:, 1].max())  # the waist's front point
    np.testing.assert_allclose(a.result.V2, b.result.V2, atol=1e-6)
    top = a.state.V3[np.unique(a.state.base.F3), 1].max() - a.state.V3[:, 1].min()
    assert top == pytest.approx(np.ptp(g.V3[:, 1]))  # the back keeps its full height


def test_a_sketch_origin_that_is_no_opening_names_the_openings():
    from ptailor.errors import PtailorError
    from ptailor.pipeline import adjustment
    from ptailor.recipe import parse_recipe
    from ptailor.samples import cone_skirt

    text = "steps: [{op: cut, view: front, origin: neckline, sketch: [[-8, 1], [8, 1]]}]"
    with pytest.raises(PtailorError, match=r"neckline.*(hem|waist)"):
        adjustment(cone_skirt(), parse_recipe(text), baseline=False)
