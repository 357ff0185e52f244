"""Panels and seams named from the drape's geometry (issue 11, named panels)."""

from __future__ import annotations

import json
import re
from dataclasses import replace
from functools import cache

import numpy as np
import pytest

from ptailor.geometry.triangles import signed_areas_2d, triangle_areas
from ptailor.model.frame import Frame
from ptailor.model.garment import Garment, panel_labels, panels, with_panel_names
from ptailor.model.names import panel_layout, seam_names
from ptailor.model.seams import seams
from ptailor.model.symmetry import panel_mirror_map, sagittal_plane
from ptailor.pipeline import adjustment
from ptailor.recipe import parse_recipe
from ptailor.samples import cone_skirt, lantern_sleeve
from tests.conftest import REAL, real_path

#: geometric names of the shared garments, in panel order (first triangle)
EXPECTED = {
    "tee6": [
        "sleeve_left_back",
        "sleeve_left_front",
        "sleeve_right_back",
        "sleeve_right_front",
        "back",
        "front",
    ],
    "tshirt": ["sleeve_left", "sleeve_right", "front", "back"],
    "longsleeve": ["front", "back", "sleeve_left", "sleeve_right", "collar_front", "collar_back"],
    "dress": [
        "bodice_back_left_side",
        "bodice_back_left",
        "bodice_back_right_side",
        "bodice_back_right",
        "strap_right",
        "strap_left",
        "bodice_front",
        "bodice_front_right",
        "bodice_front_left",
        "bodice_front_upper",
        "skirt_back_right",
        "skirt_front",
        "skirt_back_left",
    ],
}


@cache
def real(key: str) -> Garment:
    from ptailor.formats.garment import load_garment

    return load_garment(real_path(key), pattern_units=REAL[key][1]).garment


def names_of(g: Garment, **axes) -> list[str]:
    """The panels' names, the garment worn in ``Frame(**axes)`` when axes are given."""
    g = g.with_frame(Frame(**axes)) if axes else g
    return [p.name for p in panels(g)]


def layout_and_seams(g: Garment, **axes):
    g = g.with_frame(Frame(**axes)) if axes else g
    plist = panels(g)
    flab = panel_labels(plist, g.n_faces)
    lay = panel_layout(g.V3, g.F3, g.F2, flab, len(plist), frame=g.frame)
    sl = seams(g.F3, g.F2, flab)
    return plist, lay, sl, seam_names(g.V3, sl, lay, [p.name for p in plist])


def swap_sides(name: str) -> str:
    return re.sub(r"left|right", lambda m: "right" if m.group(0) == "left" else "left", name)


def mirrored(g: Garment) -> Garment:
    """The garment reflected across x = 0 (the wearer's left and right swapped)."""
    return replace(
        g,
        V3=g.V3 * np.array([-1.0, 1.0, 1.0]),
        F3=np.ascontiguousarray(g.F3[:, ::-1]),
        V2=g.V2 * np.array([-1.0, 1.0]),
        F2=np.ascontiguousarray(g.F2[:, ::-1]),
    )


# ---------------------------------------------------------------------------------------
# the shared garments
# ---------------------------------------------------------------------------------------


@pytest.mark.slow
@pytest.mark.parametrize("key", sorted(EXPECTED))
def test_real_garments_get_geometric_names(key):
    g = real(key)
    assert len(g.group_names) == 0 or key != "tee6"
    got = names_of(g)
    assert got == EXPECTED[key]
    assert len(set(got)) == len(got)


def test_tee6_names_match_its_specification():
    """Each panel lies where the GarmentCode spec placed the panel of that name."""
    p = real_path("tee6").with_name("tee6_specification.json")
    spec = json.loads(p.read_text())
    spec = spec.get("pattern", spec)["panels"]
    true_name = {
        "front": "front",
        "back": "back",
        "lfsleeve": "sleeve_left_front",
        "lbsleeve": "sleeve_left_back",
        "rfsleeve": "sleeve_right_front",
        "rbsleeve": "sleeve_right_back",
    }
    g = real("tee6")
    plist = panels(g)
    a = np.abs(signed_areas_2d(g.V2, g.F2))  # any weights will do for a centroid
    mid = g.V3[g.F3].mean(axis=1)
    c = np.array([(mid[p.faces] * a[p.faces, None]).sum(0) / a[p.faces].sum() for p in plist])
    keys = sorted(spec)
    t = np.array([spec[k]["translation"] for k in keys], dtype=float)
    # the spec's initial placement and the drape share the frame (x left, z front): match
    # panels to spec panels by their (x, z) places, each axis scaled to its largest value
    cx, tx = c[:, [0, 2]] - c[:, [0, 2]].mean(0), t[:, [0, 2]] - t[:, [0, 2]].mean(0)
    cx, tx = cx / np.abs(cx).max(0), tx / np.abs(tx).max(0)
    from scipy.optimize import linear_sum_assignment

    rows, cols = linear_sum_assignment(np.linalg.norm(cx[:, None] - tx[None], axis=2))
    got = {plist[r].name: true_name[keys[k]] for r, k in zip(rows, cols, strict=True)}
    assert got == {n: n for n in got}


def test_tee6_seam_names():
    _, _, sl, names = layout_and_seams(real("tee6"))
    assert sorted(names) == sorted(
        [
            *(f"sleeve_{s}_{w}" for s in ("left", "right") for w in ("upper", "lower")),
            *(f"armhole_{s}_{w}" for s in ("left", "right") for w in ("front", "back")),
            "side_left",
            "side_right",
            "shoulder_left",
            "shoulder_right",
        ]
    )
    by_name = dict(zip(names, sl, strict=True))
    # the side seams are long, the shoulders short, the underarm shorter than the overarm
    assert len(by_name["side_left"].edges3) > 3 * len(by_name["shoulder_left"].edges3)
    assert len(by_name["sleeve_left_upper"].edges3) > len(by_name["sleeve_left_lower"].edges3)


@pytest.mark.parametrize(
    ("key", "expected"),
    [
        (
            "tshirt",
            {
                "sleeve_left",
                "sleeve_right",
                "armhole_left_front",
                "armhole_left_back",
                "armhole_right_front",
                "armhole_right_back",
                "side_left",
                "side_right",
                "shoulder_left",
                "shoulder_right",
            },
        ),
        (
            "longsleeve",
            {
                "sleeve_left",
                "sleeve_right",
                "armhole_left_front",
                "armhole_left_back",
                "armhole_right_front",
                "armhole_right_back",
                "side_left",
                "side_right",
                "shoulder_left",
                "shoulder_right",
                "neckline_front",
                "neckline_back",
                "collar_left",
                "collar_right",
            },
        ),
    ],
)
def test_real_seam_names(key, expected):
    _, _, _, names = layout_and_seams(real(key))
    assert set(names) == expected and len(names) == len(expected)


@pytest.mark.slow
def test_dress_seam_names_are_unique_and_find_the_waist():
    plist, _, sl, names = layout_and_seams(real("dress"))
    assert len(set(names)) == len(names) == len(sl)
    waist = [n for n in names if n.startswith("waist")]
    assert len(waist) == 7  # every bodice panel above the skirt
    for n in ("skirt_center_back", "skirt_side_left", "skirt_side_right", "bodice_center_back"):
        assert n in names
    for n, s in zip(names, sl, strict=True):
        a, b = (plist[i].name for i in s.panels)
        if n.startswith("waist"):
            assert {a.split("_")[0], b.split("_")[0]} == {"bodice", "skirt"}


# ---------------------------------------------------------------------------------------
# rules: the file wins, the frame, mirror images, determinism
# ---------------------------------------------------------------------------------------


def test_names_from_the_file_win():
    g = lantern_sleeve()
    assert names_of(g) == ["sleeve", "cuff"]
    # a panel the groups leave unnamed gets a geometric name, the other keeps the file's
    fg = g.face_group.copy()
    fg[fg == 1] = -1
    assert names_of(replace(g, face_group=fg))[0] == "sleeve"
    assert names_of(replace(g, face_group=fg))[1] == "cuff"  # the geometry agrees
    assert names_of(cone_skirt()) == ["front", "back"]


def test_a_skirt_without_groups_is_named_as_a_skirt():
    g = cone_skirt()
    g = replace(g, face_group=np.full(g.n_faces, -1), group_names=())
    assert names_of(g) == ["skirt_front", "skirt_back"]


@pytest.mark.parametrize("key", ["tee6", "dress"])
def test_names_follow_the_axes_not_the_coordinates(key):
    """Rotated (z up, -y front), moved and scaled, the garment keeps its names."""
    g = real(key)
    R = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])  # y -> z, z -> -y
    V3 = 2.5 * g.V3 @ R.T + np.array([10.0, -3.0, 7.0])
    h = replace(g, V3=V3)
    assert names_of(h, up=(0, 0, 1), front=(0, -1, 0)) == EXPECTED[key]
    assert names_of(h) != EXPECTED[key]  # the default axes do not fit


@pytest.mark.parametrize("key", sorted(EXPECTED))
def test_mirror_image_swaps_left_and_right(key):
    got = names_of(mirrored(real(key)))
    assert got == [swap_sides(n) for n in EXPECTED[key]]


def test_names_do_not_depend_on_face_order():
    g = real("tshirt")
    perm = np.random.default_rng(0).permutation(g.n_faces)
    h = replace(g, F3=g.F3[perm], F2=g.F2[perm])
    by_faces = {p.name: frozenset(perm[p.faces].tolist()) for p in panels(h)}
    assert by_faces == {p.name: frozenset(p.faces.tolist()) for p in panels(g)}


def test_with_panel_names_keeps_them_through_edits():
    g = real("tshirt")
    named = with_panel_names(g)
    assert names_of(named) == EXPECTED["tshirt"]
    # a drape moved out of recognition keeps the written names
    assert names_of(replace(named, V3=named.V3[:, ::-1].copy())) == EXPECTED["tshirt"]


# ---------------------------------------------------------------------------------------
# recipes use the names
# ---------------------------------------------------------------------------------------


def pattern_areas(V2, F2, plist) -> dict[str, float]:
    a = np.abs(signed_areas_2d(V2, F2))
    return {p.name: float(a[p.faces].sum()) for p in plist}


@pytest.mark.slow
def test_tshirt_recipe_scales_the_left_sleeve_by_its_name():
    g = real("tshirt")
    adj = adjustment(
        g,
        parse_recipe(
            "steps: [{op: scale, region: {panels: [sleeve_left]}, direction: around,"
            " axis: auto, factor: 1.2}]"
        ),
        baseline=False,
    )
    plist = adj.state.panels
    assert [p.name for p in plist] == EXPECTED["tshirt"]
    a0 = pattern_areas(g.V2, g.F2, plist)
    a1 = pattern_areas(adj.result.V2, adj.state.base.F2, plist)
    assert a1["sleeve_left"] / a0["sleeve_left"] > 1.1
    assert a1["sleeve_right"] / a0["sleeve_right"] == pytest.approx(1.0, abs=0.01)
    # the adjusted garment keeps the names (written as groups), whatever its drape
    assert names_of(adj.garment) == EXPECTED["tshirt"]


@pytest.mark.slow
def test_tee6_symmetric_recipe_by_names_grows_both_sleeves():
    g = real("tee6")
    plist = panels(g)
    mm = panel_mirror_map(g, sagittal_plane(g.V3, g.F3, frame=Frame()))
    mirror = {p.name: plist[int(mm[p.index])].name for p in plist}
    assert mirror["sleeve_left_front"] == "sleeve_right_front"
    assert mirror["sleeve_left_back"] == "sleeve_right_back"
    assert mirror["front"] == "front" and mirror["back"] == "back"
    adj = adjustment(
        g,
        parse_recipe(
            "symmetric: true\n"
            "steps: [{op: scale, region: {panels: [sleeve_left_front, sleeve_left_back]},"
            " direction: around, factor: 1.2}]"
        ),
        baseline=False,
    )
    a0 = pattern_areas(g.V2, g.F2, plist)
    a1 = pattern_areas(adj.result.V2, adj.state.base.F2, adj.state.panels)
    for side in ("front", "back"):
        left, right = f"sleeve_left_{side}", f"sleeve_right_{side}"
        assert a1[left] / a0[left] > 1.1
        assert a1[right] / a0[right] == pytest.approx(a1[left] / a0[left], rel=0.01)


def test_dress_skirt_by_names():
    """A recipe region by geometric names picks the skirt (the edit alone: no flattening)."""
    from ptailor.edits import EditOptions
    from ptailor.pipeline import apply_steps

    g = real("dress")
    skirt = [n for n in EXPECTED["dress"] if n.startswith("skirt_")]
    text = "steps: [{op: scale, region: {panels: [" + ", ".join(skirt) + "]}, factor: 1.1}]"
    st = apply_steps(g, parse_recipe(text), options=EditOptions())
    a0, a1 = triangle_areas(g.V3, g.F3), triangle_areas(st.V3, g.F3)
    growth = {p.name: a1[p.faces].sum() / a0[p.faces].sum() for p in st.panels}
    for n in skirt:
        assert growth[n] == pytest.approx(1.21, abs=0.02)  # 1.1 in every direction
    assert abs(growth["bodice_front"] - 1.0) < 0.1


# ---------------------------------------------------------------------------------------
# inspect and report.json
# ---------------------------------------------------------------------------------------


def test_inspect_shows_positions_and_seam_names():
    from ptailor.formats.garment import load_garment
    from ptailor.report.inspection import garment_summary, summary_text

    info = garment_summary(load_garment(real_path("tee6")))
    pos = {p["name"]: p["position"] for p in info["panels"]}
    assert pos["sleeve_left_back"].startswith("left, back")
    assert pos["front"].startswith("centre, front")
    assert {s["name"] for s in info["seams"]} >= {"side_left", "shoulder_right"}
    text = summary_text(info)
    assert "armhole_left_front" in text and "centre, back" in text


def with_cuffs(g: Garment, depth: float = 4.0) -> Garment:
    """The garment with a band ``depth`` deep at each cuff opening cut off as its own panel.

    The band's triangles get their own copies of their pattern vertices: the drape is
    unchanged, the pattern splits, and the band is sewn to the sleeve by a new seam.
    """
    from ptailor.model.openings import openings

    sleeve = np.zeros(g.n_faces, dtype=bool)
    for p in panels(g):
        sleeve[p.faces] = p.name.startswith("sleeve_")
    cuff = np.zeros(g.n_faces, dtype=bool)
    mid = g.V3[g.F3].mean(axis=1)
    for o in openings(g.V3, g.F3, frame=Frame()):
        if o.name.startswith("cuff_"):
            P = g.V3[o.loop]
            n = np.linalg.svd(P - P.mean(0))[2][-1]
            near = np.linalg.norm(mid - o.centroid, axis=1) < 0.5 * o.length
            cuff |= sleeve & near & (np.abs((mid - o.centroid) @ n) < depth)
    used = np.unique(g.F2[cuff])
    remap = np.full(len(g.V2), -1, dtype=np.int64)
    remap[used] = len(g.V2) + np.arange(len(used))
    F2 = g.F2.copy()
    F2[cuff] = remap[g.F2[cuff]]
    return replace(g, V2=np.concatenate([g.V2, g.V2[used]]), F2=F2)


def test_a_band_at_the_cuff_opening_is_a_cuff():
    g = with_cuffs(real("tshirt"))
    plist, lay, sl, seam_name = layout_and_seams(g)
    assert sorted(p.name for p in plist) == sorted(
        ["sleeve_left", "sleeve_right", "front", "back", "cuff_left", "cuff_right"]
    )
    assert sorted(lay.role) == ["body", "body", "cuff", "cuff", "sleeve", "sleeve"]
    pair = {n: {plist[i].name for i in s.panels} for n, s in zip(seam_name, sl, strict=True)}
    assert pair["cuff_left"] == {"cuff_left", "sleeve_left"}
    assert pair["cuff_right_end"] == {"cuff_right"}
    assert pair["sleeve_left"] == {"sleeve_left"}


# ---------------------------------------------------------------------------------------
# the command line: a recipe by names, report.json seam names, outputs keep the names
# ---------------------------------------------------------------------------------------


@pytest.mark.slow
def test_cli_adjust_by_names_reports_named_seams(tmp_path):
    from click.testing import CliRunner

    from ptailor.cli.main import cli
    from ptailor.formats.garment import load_garment

    src = real_path("tshirt")
    recipe = tmp_path / "r.yaml"
    recipe.write_text(
        "symmetric: true\n"
        "steps: [{op: scale, region: {panels: [sleeve_left]}, direction: around, factor: 1.1}]\n"
    )
    out = tmp_path / "out"
    args = ["adjust", src, recipe, "-o", out, "--pattern-units", "auto", "--formats", "obj"]
    r = CliRunner().invoke(cli, [str(a) for a in args], catch_exceptions=False)
    assert r.exit_code == 0, r.output
    rep = json.loads((out / "report.json").read_text())
    assert [p["name"] for p in rep["panels"]] == EXPECTED["tshirt"]
    seams_by = {s["name"]: s["panels"] for s in rep["seams"]}
    assert seams_by["armhole_left_front"] == ["sleeve_left", "front"]
    assert seams_by["sleeve_right"] == ["sleeve_right", "sleeve_right"]
    grow = {p["name"]: p["area_after"] / p["area_before"] for p in rep["panels"]}
    assert (
        grow["sleeve_right"] == pytest.approx(grow["sleeve_left"], rel=0.01)
        and grow["sleeve_left"] > 1.05
    )
    # the adjusted garment.obj names its panels as groups: read back, same names
    back = load_garment(out / "garment.obj", pattern_units="auto").garment
    assert set(back.group_names) == set(EXPECTED["tshirt"])
    assert [p.name for p in panels(back)] == EXPECTED["tshirt"]

    r = CliRunner().invoke(
        cli, ["inspect", str(src), "--pattern-units", "auto", "--json"], catch_exceptions=False
    )
    info = json.loads(r.output)
    assert {p["name"]: p["position"] for p in info["panels"]}["sleeve_left"] == "left, upper"
    assert {s["name"] for s in info["seams"]} == set(seams_by)


@pytest.mark.slow
@pytest.mark.parametrize("key", sorted(EXPECTED))
def test_mirror_image_swaps_the_seam_names(key):
    _, _, _, names = layout_and_seams(real(key))
    _, _, _, mirror = layout_and_seams(mirrored(real(key)))
    assert sorted(mirror) == sorted(swap_sides(n) for n in names)
    # and the garment's own names are left/right symmetric (the drapes are nearly so)
    assert sorted(names) == sorted(swap_sides(n) for n in names)


def test_panel_measures_extents_and_centroids_are_the_plain_reductions():
    """The per-panel extents and centroids, computed corner by corner, equal the plain
    reductions over each face's corners exactly (shuffled faces, an empty panel label)."""
    from ptailor.model.names.measures import panel_measures

    g = cone_skirt()
    rng = np.random.default_rng(3)
    perm = rng.permutation(g.n_faces)
    F3 = g.F3[perm]
    lab = panel_labels(panels(g), g.n_faces)[perm]
    lab = np.where(lab > 0, lab + 1, lab)  # label 1 unused
    n_p = int(lab.max()) + 1
    frame = Frame().matrix()
    pm = panel_measures(g.V3, F3, lab, n_p, frame)
    Xc = (g.V3 @ frame.T)[F3]
    for p in range(n_p):
        sel = lab == p
        if not sel.any():
            assert np.all(pm.lo_abs[p] == np.inf) and np.all(pm.hi_abs[p] == -np.inf)
            continue
        assert np.array_equal(pm.lo_abs[p], Xc[sel].min(axis=(0, 1)))
        assert np.array_equal(pm.hi_abs[p], Xc[sel].max(axis=(0, 1)))
    area = triangle_areas(g.V3, F3)
    At = np.bincount(lab, area, minlength=n_p)
    fc = Xc.mean(axis=1)
    cen = np.stack([np.bincount(lab, area * fc[:, k], minlength=n_p) for k in range(3)], 1)
    assert np.array_equal(pm.cen_abs, cen / np.maximum(At, 1e-300)[:, None])


# ---------------------------------------------------------------------------------------
# names that hold on garments the rules were not tuned on (issue 24)
# ---------------------------------------------------------------------------------------


def rotated_about_up(g: Garment, deg: float) -> Garment:
    t = np.radians(deg)
    R = np.array([[np.cos(t), 0.0, np.sin(t)], [0.0, 1.0, 0.0], [-np.sin(t), 0.0, np.cos(t)]])
    return replace(g, V3=g.V3 @ R.T, face_group=np.full(g.n_faces, -1), group_names=())


@pytest.mark.parametrize("deg", [0.0, 30.0, 45.0, 60.0])
def test_two_halves_whose_seams_sit_off_the_sides_are_front_and_back(deg):
    """A skirt's halves turned about up (side seams 45 degrees towards the back, as a
    simulated tee's may sit): each still shares its tier with the other, so it is front or
    back, never the tube name 'skirt' (the wrap rule fired on both before)."""
    g = rotated_about_up(cone_skirt(), deg)
    assert sorted(names_of(g)) == ["skirt_back", "skirt_front"]


def test_a_lone_tube_panel_is_still_named_by_its_tier():
    from ptailor.samples import cylinder

    g = cylinder()
    g = replace(g, face_group=np.full(g.n_faces, -1), group_names=())
    assert names_of(g) == ["skirt"]


def test_every_name_says_why():
    plist, lay, _, _ = layout_and_seams(
        replace(cone_skirt(), face_group=np.full(cone_skirt().n_faces, -1), group_names=())
    )
    assert len(lay.why) == len(plist)
    assert all("body (length/width" in w for w in lay.why)
    front = lay.names.index("skirt_front")
    assert "front (centroid" in lay.why[front] and "ahead of its tier's mean" in lay.why[front]
    assert "centre (reaches" in lay.why[front]


def test_mirror_names_and_pairs():
    from ptailor.model.names.roles import mirror_name, mirror_pairs, mirrored_names

    assert mirror_name("bodice_front_left_side") == "bodice_front_right_side"
    assert mirror_name("leftover") == "leftover"
    cen = np.array([[10.0, 5.0, 1.0], [-10.2, 5.0, 1.0], [0.0, 3.0, 0.0]])
    ext = np.full((3, 3), 20.0)
    pairs = mirror_pairs(cen, np.array([1.0, 1.05, 3.0]), ext, ["left", "right", "centre"])
    assert pairs == [(0, 1)]
    assert mirrored_names(["yoke_left", "yoke_right_upper", "front"], pairs) == [
        "yoke_left",
        "yoke_right",
        "front",
    ]


@pytest.mark.parametrize("key", sorted(EXPECTED))
def test_the_inspect_json_says_why_for_every_panel(key, tmp_path):
    from click.testing import CliRunner

    from ptailor.cli.main import cli

    units = ["--pattern-units", REAL[key][1], "--drape-units", "cm"]
    r = CliRunner().invoke(cli, ["inspect", str(real_path(key)), "--json", *units])
    assert r.exit_code == 0, r.output
    info = json.loads(r.output)
    assert all(p["why"] for p in info["panels"])
    assert "drape's coordinates" in info["frame"]


@pytest.mark.parametrize("key", sorted(EXPECTED))
def test_front_back_and_sleeve_left_select_those_parts_on_every_garment(key):
    """One recipe for a catalogue: ``front``/``back`` select every front/back torso panel
    (the dress's bodice and skirt panels too), ``sleeve_left`` the left sleeve's."""
    from ptailor.edits.region import panels_named

    plist = panels(real(key))
    fronts = {p.name for p in panels_named(["front"], plist)}
    backs = {p.name for p in panels_named(["back"], plist)}
    assert fronts and backs and not fronts & backs
    assert all("front" in n.split("_") for n in fronts)
    assert all("back" in n.split("_") for n in backs)
    if any(n.startswith("sleeve_left") for n in EXPECTED[key]):
        assert {p.name for p in panels_named(["sleeve_left"], plist)} == {
            n for n in EXPECTED[key] if n.startswith("sleeve_left")
        }


def test_a_lone_sleeve_is_a_sleeve_with_a_cuff_and_a_top():
    """The lantern sample without its groups: a tube 48 long and 28 around is a limb, not a
    skirt (it was 'skirt', 'skirt_lower', openings 'waist' and 'hem')."""
    from ptailor.model.openings import openings

    g = lantern_sleeve()
    bare = replace(g, face_group=np.full(g.n_faces, -1), group_names=())
    _, lay, _, snames = layout_and_seams(bare)
    assert lay.names == ["sleeve", "cuff"] and lay.role == ["sleeve", "cuff"]
    assert sorted(snames) == ["cuff", "cuff_end", "sleeve"]
    ops = {o.name: o for o in openings(g.V3, g.F3, F2=g.F2, frame=Frame())}
    assert sorted(ops) == ["cuff", "top"]
    assert ops["top"].centroid[1] > ops["cuff"].centroid[1]
    assert "reaches cuff" in lay.why[1]


@pytest.mark.parametrize(("height", "kind"), [(20.0, ["hem", "waist"]), (40.0, ["cuff", "top"])])
def test_a_lone_tube_is_a_limb_when_it_is_as_long_as_it_is_around(height, kind):
    from ptailor.model.openings import openings
    from ptailor.samples import cylinder

    g = cylinder(circumference=30.0, height=height)
    assert sorted(o.name for o in openings(g.V3, g.F3, F2=g.F2, frame=Frame())) == kind


def flat_square(n: int = 8, size: float = 60.0) -> Garment:
    """One flat square panel standing in the x-y plane (a curtain): its one loop faces
    front, so no opening rule names it."""
    u = np.linspace(0.0, size, n + 1)
    X, Y = np.meshgrid(u, u)
    V2 = np.stack([X.ravel(), Y.ravel()], axis=1)
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    a, b, c, d = (
        idx[:-1, :-1].ravel(),
        idx[:-1, 1:].ravel(),
        idx[1:, 1:].ravel(),
        idx[1:, :-1].ravel(),
    )
    F = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    V3 = np.concatenate([V2, np.zeros((len(V2), 1))], axis=1)
    return Garment(V3=V3, F3=F, V2=V2, F2=F, face_group=np.full(len(F), -1), group_names=())


def test_a_garment_no_rule_recognises_gets_plain_names_and_a_warning(tmp_path):
    from click.testing import CliRunner

    from ptailor.cli.main import cli
    from ptailor.formats.obj import write_garment

    g = flat_square()
    _, lay, _, _ = layout_and_seams(g)
    assert lay.names == ["panel_0"] and "no rule recognised" in lay.why[0]
    write_garment(tmp_path / "square.obj", g)
    (tmp_path / "r.yaml").write_text("steps: []\n")
    r = CliRunner().invoke(
        cli,
        ["adjust", str(tmp_path / "square.obj"), str(tmp_path / "r.yaml"), "-o",
         str(tmp_path / "o"), "--formats", "obj"],
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    report = json.loads((tmp_path / "o" / "report.json").read_text())
    assert any("panel_0" in w and "no rule recognised" in w for w in report["warnings"])


@pytest.mark.parametrize(
    ("gores", "expected"),
    [
        (2, ["skirt_front", "skirt_back"]),
        (4, ["skirt_front_right", "skirt_front_left", "skirt_back_left", "skirt_back_right"]),
        (6, ["skirt_front_right", "skirt_front", "skirt_front_left", "skirt_back_left",
             "skirt_back", "skirt_back_right"]),
    ],
)  # fmt: skip
def test_gored_skirts_are_named_front_back_and_by_side(gores, expected):
    """Skirts of 2-6 gores the rules were not tuned on: front/back by side, mirror gores
    and seams named alike, and ``front``/``back`` select every front/back gore."""
    from ptailor.edits.region import panels_named
    from ptailor.model.names.roles import mirror_name
    from ptailor.samples import gored_skirt

    g = gored_skirt(gores=gores)
    plist, lay, _, snames = layout_and_seams(g)
    assert lay.names == expected
    for name in lay.names + snames:  # every left name has its right mirror
        assert mirror_name(name) in lay.names + snames
    fronts = {p.name for p in panels_named(["front"], plist)}
    assert fronts == {n for n in expected if "_front" in n}
    assert "skirt_side_left" in snames and "skirt_side_right" in snames


def test_a_front_in_halves_is_selected_by_front_and_sewn_at_the_centre_front():
    from ptailor.edits.region import panels_named
    from ptailor.samples import halved_bodice

    g = halved_bodice()
    plist, lay, _, snames = layout_and_seams(g)
    assert sorted(lay.names) == ["skirt_back", "skirt_front_left", "skirt_front_right"]
    assert {p.name for p in panels_named(["front"], plist)} == {
        "skirt_front_left",
        "skirt_front_right",
    }
    assert "skirt_center_front" in snames


@pytest.mark.parametrize("make", ["gored_skirt", "halved_bodice"])
def test_one_recipe_for_front_and_back_runs_on_the_generated_kinds(make):
    from ptailor import samples

    g = getattr(samples, make)()
    rec = parse_recipe("units: cm\nsteps: [{op: loosen, region: {panels: [front, back]}, by: 1}]")
    a = adjustment(g, rec, baseline=False)
    assert a.result.info.converged and a.result.info.seam_violation < 1e-6


TEE_NAMES = {
    "two": ["sleeve_right_front", "front", "sleeve_left_front", "sleeve_right_back", "back",
            "sleeve_left_back"],
    "one": ["sleeve_right", "front", "sleeve_left", "back"],
    "none": ["front", "back"],
}  # fmt: skip


@pytest.mark.parametrize("sleeves", sorted(TEE_NAMES))
def test_a_generated_tee_is_named_front_back_and_sleeves(sleeves):
    from ptailor.samples import flat_tee

    g = flat_tee(sleeves=sleeves)
    _, lay, _, snames = layout_and_seams(g)
    assert lay.names == TEE_NAMES[sleeves]
    assert {"shoulder_left", "shoulder_right", "side_left", "side_right"} <= set(snames)
    assert ("armhole_left_front" in snames) == (sleeves != "none")
    assert sorted(o.name for o in lay.openings) == ["cuff_left", "cuff_right", "hem", "neckline"]


@pytest.mark.parametrize("sleeves", ["two", "one"])
def test_the_tees_names_hold_when_it_is_turned_mirrored_and_subdivided(sleeves):
    """The same tee turned 20 degrees about up, mirrored, subdivided (4x) and written in mm:
    the same names (left and right swapped in the mirror)."""
    from ptailor.samples import flat_tee

    g = flat_tee(sleeves=sleeves)
    want = TEE_NAMES[sleeves]
    assert layout_and_seams(rotated_about_up(g, 20.0))[1].names == want
    assert layout_and_seams(mirrored(g))[1].names == [swap_sides(n) for n in want]
    fine = subdivided_garment(g)
    assert layout_and_seams(fine)[1].names == want
    big = replace(g, V3=g.V3 * 10.0, V2=g.V2 * 10.0)  # mm: the rules are scale-free
    assert layout_and_seams(big)[1].names == want


def subdivided_garment(g: Garment) -> Garment:
    import sys

    from tests.conftest import ROOT

    sys.path.insert(0, str(ROOT / "bench"))
    from subdivide import subdivide_garment

    V3, F3, V2, F2, parent = subdivide_garment(g.V3, g.F3, g.V2, g.F2, levels=1)
    return replace(g, V3=V3, F3=F3, V2=V2, F2=F2, face_group=g.face_group[parent])


@pytest.mark.slow
def test_one_catalogue_recipe_runs_on_the_generated_tee():
    from ptailor.samples import flat_tee

    g = flat_tee(sleeves="two")
    rec = parse_recipe(
        "units: cm\nsteps:\n  - {op: loosen, region: {panels: [front, back]}, by: 1}\n"
        "  - {op: scale, region: {panels: [sleeve_left]}, direction: around, axis: auto,"
        " factor: 1.1}\n"
    )
    a = adjustment(g, rec, baseline=False)
    assert a.result.info.converged and a.result.info.seam_violation < 1e-6


@pytest.mark.slow
@pytest.mark.parametrize("key", sorted(EXPECTED))
def test_one_catalogue_recipe_runs_on_every_shared_garment(key):
    """Acceptance (issue 24): ``{panels: [front, back]}`` and, where the garment has one,
    ``{panels: [sleeve_left]}`` run as they stand on each shared garment."""
    g = real(key)
    steps = ["  - {op: loosen, region: {panels: [front, back]}, by: 1}"]
    if any(n.startswith("sleeve_left") for n in EXPECTED[key]):
        steps.append(
            "  - {op: scale, region: {panels: [sleeve_left]}, direction: around, axis: auto,"
            " factor: 1.1}"
        )
    a = adjustment(g, parse_recipe("units: cm\nsteps:\n" + "\n".join(steps) + "\n"), baseline=False)
    assert a.result.info.converged and a.result.info.seam_violation < 1e-6
