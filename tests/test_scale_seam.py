"""scale_seam: the paper's lantern sleeve, moving the sleeve/cuff seam line."""

from __future__ import annotations

import numpy as np
import pytest

from ptailor.errors import PtailorError
from ptailor.formats.garment import load_garment
from ptailor.pipeline import adjustment
from ptailor.recipe import parse_recipe
from ptailor.samples import lantern_sleeve
from tests.conftest import real_path
from tests.garment_checks import assert_valid


def edge_length(V2, V0, verts, which) -> float:
    y = V0[verts, 1]
    idx = verts[np.isclose(y, which(y))]
    o = idx[np.argsort(V0[idx, 0])]
    return float(np.linalg.norm(np.diff(V2[o], axis=0), axis=1).sum())


def step(direction: str, factor: float = 1.3, fix: str = "[top]") -> str:
    return (
        f"steps: [{{op: scale_seam, seam: [sleeve, cuff], part: sleeve, "
        f"direction: {direction}, factor: {factor}, fix: {fix}}}]"
    )


@pytest.mark.slow
def test_around_widens_the_sleeve_bottom_keeps_the_top_and_the_cuff():
    g = lantern_sleeve()  # openings: cuff (cuff bottom) and top (sleeve top, the armhole)
    adj = adjustment(g, parse_recipe(step("around")))
    sleeve, cuff = adj.state.panels
    V, V0 = adj.result.V2, g.V2
    assert edge_length(V, V0, sleeve.vertices, np.max) == pytest.approx(28.0, rel=1e-3)
    assert edge_length(V, V0, sleeve.vertices, np.min) == pytest.approx(1.3 * 28.0, rel=1e-3)
    # the cuff's pattern is kept (exactly at the fixed point: 40 x 8 to 1e-12 iterated to a
    # step of 1e-13; to 2e-5 at the solver's step tolerance of 1e-7, its convergence rate
    # about 0.95 here: the seam's new ratio is met edge by edge, the kept cuff 100x stiffer
    # than the edited sleeve)
    np.testing.assert_allclose(np.ptp(V[cuff.vertices], axis=0), [40.0, 8.0], rtol=3e-5)
    # the armhole did not move in 3D
    top = np.isclose(g.V3[:, 1], g.V3[:, 1].max())
    np.testing.assert_allclose(adj.state.V3[top], g.V3[top], atol=1e-9)
    assert_valid(adj.state.base, V2=V)
    rec = adj.state.log[0]
    assert rec["pattern_kept"] == "cuff" and rec["seam_vertices"] == 48


def test_along_lengthens_the_sleeve_and_carries_the_cuff():
    g = lantern_sleeve()
    adj = adjustment(g, parse_recipe(step("along")))
    sleeve, cuff = adj.state.panels
    np.testing.assert_allclose(np.ptp(adj.result.V2[sleeve.vertices], axis=0), [28, 52], rtol=1e-6)
    np.testing.assert_allclose(np.ptp(adj.result.V2[cuff.vertices], axis=0), [40, 8], rtol=1e-9)
    cuff3 = np.unique(g.F3[cuff.faces])
    assert np.ptp(adj.state.V3[cuff3, 1]) == pytest.approx(8.0, rel=1e-9)  # moved, not stretched


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            "steps: [{op: scale_seam, seam: [sleeve, cuff], part: collar, factor: 1.2}]",
            "not one of the seam's panels",
        ),
        (
            "steps: [{op: scale_seam, seam: [sleeve], part: sleeve, factor: 1.2}]",
            "expected two panel names",
        ),
    ],
)
def test_recipe_errors(text, message):
    with pytest.raises(PtailorError, match=message):
        parse_recipe(text)


def test_panels_without_a_seam():
    g = lantern_sleeve()
    with pytest.raises(PtailorError, match="no panel named"):
        adjustment(
            g,
            parse_recipe(
                "steps: [{op: scale_seam, seam: [sleeve, collar], part: sleeve, factor: 1.2}]"
            ),
        )


@pytest.mark.slow
def test_tee6_armhole_seam_stays_valid():
    g = load_garment(real_path("tee6")).garment
    adj = adjustment(
        g,
        parse_recipe(
            "steps: [{op: scale_seam, seam: [sleeve_left_back, back], part: sleeve_left_back,"
            " direction: around,"
            " factor: 1.1, fix: [cuff_left, cuff_right]}]"
        ),
        baseline=False,
    )
    assert_valid(adj.state.base, V2=adj.result.V2)
    assert "back" in adj.state.frozen


@pytest.mark.slow
def test_body_axis_drives_auto_axes():
    """With a body, axis: auto is the body's local axis near the region, not the garment's."""
    import trimesh

    from ptailor.edits import EditOptions
    from ptailor.edits.region import region_axis

    g = lantern_sleeve()
    faces = np.arange(g.n_faces)
    np.testing.assert_allclose(np.abs(region_axis(g.V3, g.F3, faces)), [0, 1, 0], atol=1e-6)
    # an "arm" inside the sleeve, tilted 30 degrees in the x-y plane
    d = np.array([np.sin(np.pi / 6), np.cos(np.pi / 6), 0.0])
    T = trimesh.geometry.align_vectors([0, 0, 1], d)
    T[:3, 3] = [0, 24, 0]
    arm = trimesh.creation.cylinder(radius=2.0, height=80.0, sections=32, transform=T)
    ax = region_axis(g.V3, g.F3, faces, body=arm)
    assert abs(ax @ d) > 0.99
    adj = adjustment(
        g,
        parse_recipe("steps: [{op: scale, direction: along, factor: 1.1}]"),
        options=EditOptions(body=arm),
        baseline=False,
    )
    assert abs(np.asarray(adj.state.log[0]["axis"]) @ d) > 0.99


def test_a_fix_on_the_seam_being_moved_is_an_error_not_ignored():
    """Issue 22: ``fix`` naming the seam the step scales was silently ignored
    (``fixed_vertices: 0``)."""
    g = lantern_sleeve()
    with pytest.raises(PtailorError, match=r"lies on the seam \[sleeve, cuff\] this step moves"):
        adjustment(g, parse_recipe(step("around", fix="[[sleeve, cuff]]")), baseline=False)
    a = adjustment(g, parse_recipe(step("around")), baseline=False)  # fix: [top] holds
    assert a.state.log[-1]["fixed_vertices"] > 0


def opening_moved(g, a, name: str) -> float:
    """How far the adjustment ``a`` of ``g`` moved the opening ``name``, over g's size."""
    from ptailor.edits.opening import find_opening
    from ptailor.edits.state import EditState
    from ptailor.model.structure import structure

    plist = structure(g).panels
    state = EditState(base=g, V3=g.V3.copy(), panels=plist, even=np.ones(len(plist), bool))
    loop = find_opening(state, name)[1]
    size = float(np.linalg.norm(np.ptp(g.V3, axis=0)))
    return float(np.abs(a.state.V3[loop] - g.V3[loop]).max()) / size


def test_what_fix_names_stays_put_exactly():
    """Issue 23, item 2: the fixed far opening moved with the part's scaled field (2 mm on
    a real sleeve's cuff). Now it stays where it is to 1e-6 of the garment's size."""
    g = lantern_sleeve()
    a = adjustment(g, parse_recipe(step("around", fix="[top]")), baseline=False)
    assert opening_moved(g, a, "top") < 1e-6


def test_a_fix_inside_the_scaled_part_is_an_error_saying_why():
    g = lantern_sleeve()
    with pytest.raises(PtailorError, match=r"lies inside the scaled part sleeve"):
        adjustment(g, parse_recipe(step("around", fix="[[sleeve, sleeve]]")), baseline=False)


@pytest.mark.slow  # the real long-sleeved shirt: 0.3-0.6 s
def test_the_shared_long_sleeves_fixed_cuff_stays_put_under_an_armhole_gather():
    """Issue 23's reproduction: the gather moved the fixed cuff opening by 2.4 mm."""
    path = real_path("longsleeve")
    g = load_garment(path, pattern_units="auto", drape_units="cm").garment
    text = (
        "units: cm\nsteps: [{op: scale_seam, seam: [front, sleeve_left], part: sleeve_left, "
        "direction: around, factor: 1.2, fix: [cuff_left]}]"
    )
    a = adjustment(g, parse_recipe(text), baseline=False)
    assert opening_moved(g, a, "cuff_left") < 1e-6


def two_panels_on_one_sleeve():
    """A tube (``sleeve``) whose top row is two panels, ``front`` (x > 0) and ``back``:
    one seam line (an armhole) in two halves."""
    from ptailor.samples import cylinder
    from tests.garment_checks import regrouped

    g = cylinder(circumference=40.0, n_around=24, n_along=8)
    cent = g.V3[g.F3].mean(axis=1)
    top = cent[:, 1] > g.V3[:, 1].max() - 20.0 / 8 - 1e-9
    grp = np.where(top, np.where(cent[:, 0] > 0, 1, 2), 0)
    return regrouped(g, grp, ("sleeve", "front", "back"))


def test_a_gather_acts_on_the_whole_seam_line():
    """Issue 23, item 1: a gather named by one half of an armhole gathered that half, and
    the other half grew on both sides (the back panel's armhole +14 % on a real tee). The
    seam line is the whole armhole: 1.2 on every seam of it, and the panels across it keep
    their pattern length there."""
    from ptailor.report.build import build_report

    g = two_panels_on_one_sleeve()
    text = (
        "steps: [{op: scale_seam, seam: [front, sleeve], part: sleeve, direction: around, "
        "factor: 1.2}]"
    )
    a = adjustment(g, parse_recipe(text), baseline=False)
    assert a.state.log[-1]["seam_line"] == ["front", "back"]
    r = build_report(a, inputs={}, units_note={}, warnings=[], timing_s={})
    line = [s for s in r["seams"] if "sleeve" in s["panels"] and s["panels"] != ["sleeve"] * 2]
    assert len(line) == 2
    for s in line:
        i = s["panels"].index("sleeve")
        assert s["length_after"][i] == pytest.approx(1.2 * s["length_before"][i], rel=1e-4)
        assert s["length_after"][1 - i] == pytest.approx(s["length_before"][1 - i], rel=1e-4)


@pytest.mark.slow  # the real long-sleeved shirt: 0.3-0.6 s
def test_the_shared_long_sleeves_back_armhole_keeps_its_length_under_a_front_gather():
    from ptailor.report.build import build_report

    g = load_garment(real_path("longsleeve"), pattern_units="auto", drape_units="cm").garment
    text = (
        "units: cm\nsteps: [{op: scale_seam, seam: [front, sleeve_left], part: sleeve_left, "
        "direction: around, factor: 1.2}]"
    )
    a = adjustment(g, parse_recipe(text), baseline=False)
    assert a.result.info.converged
    r = build_report(a, inputs={}, units_note={}, warnings=[], timing_s={})
    (back,) = [s for s in r["seams"] if sorted(s["panels"]) == ["back", "sleeve_left"]]
    i = back["panels"].index("back")
    before, after = back["length_before"], back["length_after"]
    assert after[i] == pytest.approx(before[i], rel=2e-3)  # was +13 %
    assert after[1 - i] == pytest.approx(1.2 * before[1 - i], rel=1e-2)


def test_a_seam_line_named_by_its_stem_scales_like_its_seam():
    """Issue 23: a seam line is named by the stem of its seams' names (``inspect`` lists
    it); ``seam: NAME`` with ``part`` acts on the whole line, the same as naming one of its
    seams by its panels."""
    from ptailor.model.names import seam_names
    from ptailor.model.seam_lines import seam_lines
    from ptailor.model.structure import structure

    g = two_panels_on_one_sleeve()
    st = structure(g)
    names = seam_names(g.V3, st.seams, st.layout, [p.name for p in st.panels])
    (line,) = [
        ln for ln in seam_lines(g.V3, st.seams, names) if st.panels[ln.part].name == "sleeve"
    ]
    assert len(line.seams) == 2 and {st.panels[i].name for i in line.panels} == {"front", "back"}
    results = []
    for seam in (f"{line.name}", "[front, sleeve]", names[line.seams[1]]):
        text = f"steps: [{{op: scale_seam, seam: {seam}, part: sleeve, factor: 1.2}}]"
        a = adjustment(g, parse_recipe(text), baseline=False)
        assert a.state.log[-1]["seam_line"] in (["front", "back"], ["back", "front"])
        results.append(a.result.V2)
    np.testing.assert_allclose(results[0], results[1], atol=1e-9)
    np.testing.assert_allclose(results[2], results[1], atol=1e-6)  # the line from its other half


def test_an_unknown_seam_name_lists_the_parts_seams_and_lines():
    g = two_panels_on_one_sleeve()
    text = "steps: [{op: scale_seam, seam: armhole, part: sleeve, factor: 1.2}]"
    with pytest.raises(
        PtailorError, match=r"no seam or seam line named 'armhole' on sleeve.*lines: waist"
    ):
        adjustment(g, parse_recipe(text), baseline=False)
    text = "steps: [{op: scale_seam, seam: waistband_front, part: sleeve, factor: 1.2}]"
    with pytest.raises(PtailorError, match=r"joins .* not sleeve"):
        adjustment(g, parse_recipe(text), baseline=False)


@pytest.mark.parametrize("seam", [3, "", ["front"], [1, 2]])
def test_a_seam_that_is_neither_two_panels_nor_a_name_is_refused(seam):
    from ptailor.recipe import validate

    recipe, probs = validate(
        {"steps": [{"op": "scale_seam", "seam": seam, "part": "sleeve", "factor": 1.2}]}
    )
    assert recipe is None and any("seam line's name" in p for p in probs), probs


@pytest.mark.slow
def test_the_shared_long_sleeves_armhole_by_name_symmetric_too():
    """On the shared long-sleeve, ``seam: armhole_left`` (the line ``inspect`` lists) gives
    the pattern of ``[front, sleeve_left]``; with ``symmetric: true`` the name resolves
    before it is mirrored (the right armhole)."""
    g = load_garment(real_path("longsleeve"), pattern_units="auto", drape_units="cm").garment
    out = {}
    for seam in ("armhole_left", "[front, sleeve_left]"):
        text = (
            f"units: cm\nsteps: [{{op: scale_seam, seam: {seam}, part: sleeve_left, "
            "factor: 1.2, symmetric: true}]"
        )
        a = adjustment(g, parse_recipe(text), baseline=False)
        assert a.result.info.converged
        out[seam] = a.result.V2
    np.testing.assert_allclose(out["armhole_left"], out["[front, sleeve_left]"], atol=1e-9)


def test_inspect_names_the_shared_long_sleeves_seam_lines():
    from ptailor.report.inspection import garment_summary, summary_text

    loaded = load_garment(real_path("longsleeve"), pattern_units="auto", drape_units="cm")
    info = garment_summary(loaded)
    lines = {(ln["name"], ln["part"]): ln for ln in info["seam_lines"]}
    for side in ("left", "right"):
        ln = lines[(f"armhole_{side}", f"sleeve_{side}")]
        assert sorted(ln["seams"]) == [f"armhole_{side}_back", f"armhole_{side}_front"]
        assert sorted(ln["panels"]) == ["back", "front"]
    assert "seam lines" in summary_text(info) and "armhole_left " in summary_text(info)


def test_seam_name_stems_are_whole_words():
    from ptailor.model.seam_lines import name_stem

    assert name_stem(["armhole_left_front", "armhole_left_back"]) == "armhole_left"
    assert name_stem(["waist_front", "waist_front_left", "waist_back_left"]) == "waist"
    assert name_stem(["side_left", "sides_left"]) == ""
    assert name_stem(["collar"]) == "collar"


def far_move(g, a, part: str, other: str, beyond: float) -> float:
    """The largest pattern move (after a rigid fit) of ``part``'s vertices further than
    ``beyond`` from its seam with ``other`` in the input pattern."""
    from scipy.spatial import cKDTree

    from ptailor.geometry.rotations import rigid_fit_groups

    st = a.state
    ip, io = (next(p.index for p in st.panels if p.name == n) for n in (part, other))
    sides = [
        s.edges_a if s.panels[0] == ip else s.edges_b
        for s in st.structure.seams
        if s.panels == tuple(sorted((ip, io)))
    ]
    v = st.panels[ip].vertices
    far = v[cKDTree(g.V2[np.unique(np.concatenate(sides))]).query(g.V2[v])[0] > beyond]
    X = rigid_fit_groups(a.result.V2[far], g.V2[far], np.zeros(len(far), int), 1)
    return float(np.linalg.norm(X - g.V2[far], axis=1).max())


@pytest.mark.slow  # 1.9 s
def test_a_gather_with_no_fixed_end_spreads_near_its_seam_and_keeps_the_rest():
    """Issue 42, item 5: a gather grew its whole part (the part tapered in the drape from
    its far end): now the drape is kept and the part's pattern takes the extra length in a
    band along the seam; the kept cuff's drape is the asked scale, not an error."""
    from ptailor.model.garment import panel_labels
    from ptailor.report.build import triangle_errors

    g = lantern_sleeve()
    a = adjustment(g, parse_recipe(step("around", fix="[]")), baseline=False)
    assert a.state.log[0]["spread"] == "band" and a.state.log[0]["band"] > 0
    np.testing.assert_allclose(a.state.V3, g.V3)  # the drape kept
    sleeve, cuff = a.state.panels
    V = a.result.V2
    assert edge_length(V, g.V2, sleeve.vertices, np.min) == pytest.approx(1.3 * 28.0, rel=1e-3)
    assert edge_length(V, g.V2, sleeve.vertices, np.max) == pytest.approx(28.0, rel=2e-2)
    # beyond twice the band the sleeve moves 0.87 cm (the taper moved it 3.28 cm)
    assert far_move(g, a, "sleeve", "cuff", 2 * a.state.log[0]["band"]) < 1.0
    np.testing.assert_allclose(np.ptp(V[cuff.vertices], axis=0), [40.0, 8.0], rtol=1e-4)
    err = triangle_errors(a)
    assert err[panel_labels(a.state.panels, g.n_faces) == cuff.index].max() < 1e-3


@pytest.mark.slow
def test_a_tapered_gathers_kept_cuff_is_no_error():
    """The lantern (a fixed top: the sleeve tapers): the cuff's pattern kept, its drape
    stretched 1.3 on purpose: the preview painted it red (30 %)."""
    from ptailor.model.garment import panel_labels
    from ptailor.report.build import triangle_errors

    g = lantern_sleeve()
    a = adjustment(g, parse_recipe(step("around")), baseline=False)
    assert a.state.log[0]["spread"] == "taper"
    cuff = a.state.panels[1]
    err = triangle_errors(a)
    assert err[panel_labels(a.state.panels, g.n_faces) == cuff.index].max() < 1e-3


def neckline_gather():
    g = load_garment(real_path("longsleeve"), pattern_units="auto", drape_units="cm").garment
    text = "units: cm\nsteps: [{op: scale_seam, seam: neckline, part: front, factor: 1.2}]"
    return g, adjustment(g, parse_recipe(text), baseline=False)


@pytest.mark.slow  # the real long-sleeved shirt: 3 s
def test_the_shared_long_sleeves_neckline_gather_keeps_the_other_panels():
    """Issue 42, item 5: the front's neckline gathered x1.2 grew the front's pattern from
    62.4 to 71.6 cm wide and the back's, not named, to 69.9; the front beyond 5 cm of the
    neckline moved 5.1 cm. Now the back, sleeves and collars do not move (< 0.1 mm), the
    front grows 0.5 cm wide (the neckline deeper and wider), the seam's ratio exact."""
    from ptailor.report.build import build_report

    g, a = neckline_gather()
    assert a.result.info.converged
    V = a.result.V2
    for p in a.state.panels:
        w0, w1 = np.ptp(g.V2[p.vertices], axis=0), np.ptp(V[p.vertices], axis=0)
        if p.name != "front":
            np.testing.assert_allclose(w1, w0, atol=0.01)
    front = next(p for p in a.state.panels if p.name == "front")
    assert np.ptp(V[front.vertices, 0]) - np.ptp(g.V2[front.vertices, 0]) < 1.0  # was 9.2
    r = build_report(a, inputs={}, units_note={}, warnings=[], timing_s={})
    (neck,) = [s for s in r["seams"] if sorted(s["panels"]) == ["collar_front", "front"]]
    i = neck["panels"].index("front")
    assert neck["length_after"][i] == pytest.approx(1.2 * neck["length_before"][i], rel=1e-4)
    assert neck["length_after"][1 - i] == pytest.approx(neck["length_before"][1 - i], rel=1e-4)
    # the preview paints the asked gather as no error (the old taper: the whole front red);
    # what is left is the band's distortion at the neckline's ends (22 % at most, 14 triangles)
    from ptailor.model.garment import panel_labels
    from ptailor.report.build import triangle_errors

    err, lab = triangle_errors(a), panel_labels(a.state.panels, g.n_faces)
    assert err[lab != front.index].max() < 1e-3
    assert np.percentile(err[lab == front.index], 95) < 0.02


@pytest.mark.slow
def test_the_shared_long_sleeves_neckline_gather_keeps_the_front_beyond_the_band():
    """The ask: the front moves <= 1 cm away from the neckline (5.05 cm before; 2.3 cm with
    the band's stretch field, not a map: the notch's sides turned apart). The gather's map
    grows the neckline curve itself, deeper and wider, the rest held: 0.68 cm."""
    g, a = neckline_gather()
    assert far_move(g, a, "front", "collar_front", 5.0) <= 1.0
