"""Symmetry: the sagittal plane, mirror panels, and symmetric recipe steps."""

from __future__ import annotations

import numpy as np
import pytest
from click.testing import CliRunner

from ptailor.cli.main import cli
from ptailor.edits import EditOptions, LoosenStep, ScaleSeamStep, ScaleStep, ShortenStep
from ptailor.edits.mirror import mirror_state, mirror_step
from ptailor.errors import PtailorError, RecipeError
from ptailor.geometry.triangles import signed_areas_2d, triangle_areas
from ptailor.model.frame import Frame
from ptailor.model.garment import Garment, panels
from ptailor.model.symmetry import SagittalPlane, mirror_points, panel_mirror_map, sagittal_plane
from ptailor.pipeline import adjustment, apply_steps
from ptailor.recipe import parse_recipe
from ptailor.samples import cone_skirt, cylinder, lantern_sleeve
from tests.conftest import real_path


def rotation(axis: str, deg: float) -> np.ndarray:
    t = np.radians(deg)
    c, s = np.cos(t), np.sin(t)
    i, j = {"x": (1, 2), "y": (2, 0), "z": (0, 1)}[axis]
    R = np.eye(3)
    R[i, i], R[i, j], R[j, i], R[j, j] = c, -s, s, c
    return R


def tee6():
    from ptailor.formats.garment import load_garment

    return load_garment(real_path("tee6")).garment


def pattern_areas(V2: np.ndarray, F2: np.ndarray, plist) -> np.ndarray:
    sa = np.abs(signed_areas_2d(V2, F2))
    return np.array([sa[p.faces].sum() for p in plist])


def drape_centroids(g: Garment) -> np.ndarray:
    a = triangle_areas(g.V3, g.F3)
    mid = g.V3[g.F3].mean(axis=1)
    return np.array(
        [(mid[p.faces] * a[p.faces, None]).sum(0) / a[p.faces].sum() for p in panels(g)]
    )


# ---------------------------------------------------------------------------------------
# the plane
# ---------------------------------------------------------------------------------------


def test_cone_skirt_plane_is_x_zero():
    g = cone_skirt()
    pl = sagittal_plane(g.V3, g.F3, frame=Frame((0, 1, 0), (0, 0, 1)))
    np.testing.assert_allclose(pl.normal, [1.0, 0.0, 0.0], atol=1e-6)  # the wearer's left
    assert abs(pl.point[0]) < 1e-6
    assert pl.rms < 1e-9 and pl.max < 1e-9
    # the left axis decides the sign: facing -z, the wearer's left is -x
    pl2 = sagittal_plane(g.V3, g.F3, frame=Frame((0, 1, 0), (0, 0, -1)))
    np.testing.assert_allclose(pl2.normal, [-1.0, 0.0, 0.0], atol=1e-6)


def test_shifted_tilted_skirt_gives_the_moved_plane():
    # tilted 8 degrees about the front axis and 5 about the left one, then shifted; the
    # fit starts from the untilted axes (normal x), 8 degrees off, and must find R x
    R = rotation("x", 5.0) @ rotation("z", 8.0)
    t = np.array([3.0, -2.0, 5.0])
    g = cone_skirt()
    V = g.V3 @ R.T + t
    pl = sagittal_plane(V, g.F3, frame=Frame((0, 1, 0), (0, 0, 1)))
    np.testing.assert_allclose(pl.normal, R[:, 0], atol=1e-6)
    assert abs((pl.point - t) @ pl.normal) < 1e-6
    assert pl.rms < 1e-6
    # no refinement: the starting plane is 8 degrees off and the match is poor
    pl0 = sagittal_plane(V, g.F3, frame=Frame((0, 1, 0), (0, 0, 1)), iterations=0)
    assert np.linalg.norm(pl0.normal - R[:, 0]) > 0.1 and pl0.rms > 0.5


def test_an_asymmetric_garment_has_a_positive_rms():
    g = cone_skirt()
    V = g.V3.copy()
    V[V[:, 0] > 0, 0] *= 1.1  # the left side bulges
    pl = sagittal_plane(V, g.F3, frame=Frame())
    # the best plane splits the difference (the hem's half-widths are 30 and 33)
    assert 0.0 < pl.point[0] < 3.0 and pl.normal[0] > 0.999
    assert pl.rms > 0.1 and pl.max > 0.5
    assert sagittal_plane(g.V3, g.F3, frame=Frame()).rms < 1e-9


def test_a_symmetric_surface_is_measured_without_searching_triangles(monkeypatch):
    # mirrored vertices that land on vertices need no closest-point search on triangles
    # (nor trimesh's import, about 0.2 s of CPU in a fresh process)
    import trimesh.triangles

    def refuse(*args, **kwargs):
        raise AssertionError("closest_point searched on a mirror-symmetric surface")

    monkeypatch.setattr(trimesh.triangles, "closest_point", refuse)
    g = cone_skirt()
    pl = sagittal_plane(g.V3, g.F3, frame=Frame())
    assert pl.rms < 1e-9 and pl.max < 1e-9
    V = g.V3.copy()
    V[V[:, 0] > 0, 0] *= 1.1  # asymmetric: the triangles are searched
    with pytest.raises(AssertionError, match="closest_point"):
        sagittal_plane(V, g.F3, frame=Frame())


def test_body_plane_is_fitted_to_the_body():
    import trimesh

    body = trimesh.creation.box(extents=(30.0, 60.0, 20.0))
    body.apply_translation((7.0, 0.0, 0.0))
    g = cone_skirt()  # centred on x = 0; the body is not
    pl = sagittal_plane(g.V3, g.F3, body=body, frame=Frame())
    np.testing.assert_allclose(np.abs(pl.normal), [1.0, 0.0, 0.0], atol=1e-6)
    assert pl.point[0] == pytest.approx(7.0, abs=1e-6)


def test_mirror_points_reflects():
    pl = SagittalPlane(
        point=np.array([1.0, 0.0, 0.0]), normal=np.array([1.0, 0.0, 0.0]), rms=0.0, max=0.0
    )
    P = np.array([[3.0, 1.0, 2.0], [1.0, 5.0, 5.0]])
    np.testing.assert_allclose(mirror_points(P, pl), [[-1.0, 1.0, 2.0], [1.0, 5.0, 5.0]])
    np.testing.assert_allclose(mirror_points(mirror_points(P, pl), pl), P)


def test_mirror_state_keeps_normals_outward_and_pattern_orientation():
    g = cone_skirt()
    pl = sagittal_plane(g.V3, g.F3, frame=Frame())
    st = apply_steps(g, parse_recipe("steps: []"), options=EditOptions())
    m = mirror_state(st, pl)

    def normals(V, F):
        return np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])

    n0, n1 = normals(g.V3, g.F3), normals(m.base.V3, m.base.F3)
    # a face's normal on the mirror image is the mirror image of its normal
    np.testing.assert_allclose(n1, n0 - 2.0 * (n0 @ pl.normal)[:, None] * pl.normal, atol=1e-9)
    np.testing.assert_array_equal(
        np.sign(signed_areas_2d(m.base.V2, m.base.F2)), np.sign(signed_areas_2d(g.V2, g.F2))
    )
    back = mirror_state(m, pl)
    np.testing.assert_array_equal(back.base.F3, g.F3)
    np.testing.assert_allclose(back.V3, g.V3, atol=1e-12)


# ---------------------------------------------------------------------------------------
# mirror panels
# ---------------------------------------------------------------------------------------


def test_skirt_panels_are_their_own_mirrors():
    g = cone_skirt()
    pl = sagittal_plane(g.V3, g.F3, frame=Frame())
    np.testing.assert_array_equal(panel_mirror_map(g, pl), [0, 1])


def skirt_with_pocket() -> Garment:
    """A cone skirt plus a small tube on its left side: a panel without a mirror."""
    s, c = cone_skirt(), cylinder(circumference=10.0, height=6.0, n_around=12, n_along=3)
    V3c = c.V3 + np.array([35.0, 20.0, 0.0])
    n3, n2 = len(s.V3), len(s.V2)
    return Garment(
        V3=np.concatenate([s.V3, V3c]),
        F3=np.concatenate([s.F3, c.F3 + n3]),
        V2=np.concatenate([s.V2, c.V2 + np.array([0.0, 100.0])]),
        F2=np.concatenate([s.F2, c.F2 + n2]),
        face_group=np.concatenate([s.face_group, np.full(len(c.F3), 2)]),
        group_names=("front", "back", "pocket"),
    )


def test_a_panel_without_mirror_maps_to_minus_one():
    g = skirt_with_pocket()
    pl = sagittal_plane(cone_skirt().V3, cone_skirt().F3, frame=Frame())
    np.testing.assert_array_equal(panel_mirror_map(g, pl), [0, 1, -1])
    recipe = parse_recipe(
        "symmetric: true\nsteps: [{op: scale, region: {panels: [pocket]}, factor: 1.1}]"
    )
    with pytest.raises(PtailorError, match="panel 'pocket' has no mirror image"):
        apply_steps(g, recipe, options=EditOptions())
    # one-sided, the same step is fine
    one = parse_recipe("steps: [{op: scale, region: {panels: [pocket]}, factor: 1.1}]")
    apply_steps(g, one, options=EditOptions())


# ---------------------------------------------------------------------------------------
# symmetric steps on a generated skirt
# ---------------------------------------------------------------------------------------

BOX_STEP = (
    "{op: scale, region: {box: {min: [20, -1, -40], max: [40, 30, 40]}}, "
    "direction: uniform, factor: 1.1%s}"
)


def mirror_gap(V: np.ndarray, used: np.ndarray) -> float:
    """How far a drape is from x-mirror symmetric (max nearest-vertex distance)."""
    from scipy.spatial import cKDTree

    P = V[used]
    d, _ = cKDTree(P).query(P * np.array([-1.0, 1.0, 1.0]))
    return float(d.max())


@pytest.mark.slow
def test_symmetric_recipe_mirrors_a_one_sided_step():
    g = cone_skirt()
    used = np.unique(g.F3)
    one = apply_steps(g, parse_recipe(f"steps: [{BOX_STEP % ''}]"), options=EditOptions())
    both = apply_steps(
        g, parse_recipe(f"symmetric: true\nsteps: [{BOX_STEP % ''}]"), options=EditOptions()
    )
    gap = mirror_gap(one.V3, used)
    assert gap > 2.0  # one-sided: only the left side of the hem grew
    # mirrored: both sides alike, up to what the first application's follow-through moved
    # on the other side before the mirror image was applied (the box selects by position)
    assert mirror_gap(both.V3, used) < 0.15 * gap
    assert -both.V3[:, 0].min() > -g.V3[:, 0].min() + 1.0
    sym, rec = both.log
    assert sym["op"] == "symmetry" and sym["fitted_to"] == "drape" and sym["rms"] < 1e-9
    np.testing.assert_allclose(np.abs(sym["plane"]["normal"]), [1, 0, 0], atol=1e-6)
    assert rec["op"] == "scale" and rec["mirrored"] is True
    # the mirror application's record is in the garment's coordinates: the right side
    mc = np.asarray(rec["mirror"]["centroid"]) * [-1.0, 1.0, 1.0]
    np.testing.assert_allclose(mc, rec["centroid"], atol=1.0)
    # the box takes a few more triangles on the right, pushed out by the first application
    assert rec["mirror"]["triangles"] == pytest.approx(rec["triangles"], rel=0.15)
    assert one.log[0].get("mirrored") is None


def test_a_mirrored_loosen_analyses_its_matrix_pattern_once(monkeypatch):
    # both applications diffuse normals over the same triangles: one symbolic analysis
    from cvxopt import cholmod

    calls = []
    symbolic = cholmod.symbolic

    def counted(*args, **kwargs):
        calls.append(1)
        return symbolic(*args, **kwargs)

    monkeypatch.setattr(cholmod, "symbolic", counted)
    g = lantern_sleeve()
    box = "{box: {min: [0, 18, -50], max: [50, 38, 50]}}"
    rec = parse_recipe(f"steps: [{{op: loosen, region: {box}, by: 1, symmetric: true}}]")
    st = apply_steps(g, rec, options=EditOptions())
    assert st.log[-1]["mirrored"] is True and "smoothing" in st.log[-1]["mirror"]
    assert len(calls) == 1


def test_symmetric_steps_with_a_body_use_its_plane_and_its_mirror():
    import trimesh

    g = cone_skirt()
    body = trimesh.creation.box(extents=(20.0, 50.0, 16.0))
    body.apply_translation((0.0, 30.0, 0.0))
    opts = EditOptions(body=body)
    st = apply_steps(g, parse_recipe(f"symmetric: true\nsteps: [{BOX_STEP % ''}]"), options=opts)
    sym, rec = st.log
    assert sym["fitted_to"] == "body" and sym["rms"] < 1e-9
    assert sym["plane"]["point"][0] == pytest.approx(0.0, abs=1e-9)
    # the body's axis (up) serves both sides: the mirror image of the body is the body
    assert np.abs(rec["axis"]) == pytest.approx(np.abs(rec["mirror"]["axis"]), abs=1e-6)
    one = apply_steps(g, parse_recipe(f"steps: [{BOX_STEP % ''}]"), options=opts)
    assert mirror_gap(st.V3, np.unique(g.F3)) < 0.15 * mirror_gap(one.V3, np.unique(g.F3))


def test_step_symmetric_overrides_the_recipe():
    g = cone_skirt()
    used = np.unique(g.F3)
    off = parse_recipe(f"symmetric: true\nsteps: [{BOX_STEP % ', symmetric: false'}]")
    assert off.steps[0].symmetric is False and off.symmetric is True
    st = apply_steps(g, off, options=EditOptions())
    gap = mirror_gap(st.V3, used)
    assert gap > 2.0  # kept one-sided
    assert [r["op"] for r in st.log] == ["scale"]  # no plane was needed
    on = parse_recipe(f"steps: [{BOX_STEP % ', symmetric: true'}]")
    assert on.steps[0].symmetric is True and on.symmetric is False
    assert mirror_gap(apply_steps(g, on, options=EditOptions()).V3, used) < 0.15 * gap


def test_recipe_level_symmetric_turns_on_cuts_own_mirror():
    g = cone_skirt()
    cut = "{op: cut, view: front, sketch: [[10, 0], [10, 60]], remove: right}"
    one = adjustment(g, parse_recipe(f"steps: [{cut}]"), baseline=False)
    both = adjustment(g, parse_recipe(f"symmetric: true\nsteps: [{cut}]"), baseline=False)
    X1 = one.state.V3[np.unique(one.state.base.F3), 0]
    X2 = both.state.V3[np.unique(both.state.base.F3), 0]
    assert X1.min() < -25 and X1.max() == pytest.approx(10, abs=1e-3)
    assert X2.min() == pytest.approx(-10, abs=1e-3) and X2.max() == pytest.approx(10, abs=1e-3)
    assert both.state.log[-1]["mirrored"] is True


def two_sleeves(**resolution: int) -> Garment:
    """Two lantern sleeves along x, mirror images: panels sleeve, cuff, sleeve_1, cuff_1
    (``resolution``: :func:`lantern_sleeve`'s triangle counts)."""
    g = lantern_sleeve(axis="x", **resolution)  # cuff at x in [0, 8], sleeve to x = 48
    V = g.V3 + np.array([10.0, 0.0, 0.0])
    n3, n2 = len(V), len(g.V2)
    return Garment(
        V3=np.concatenate([V, V * [-1.0, 1.0, 1.0]]),
        F3=np.concatenate([g.F3, g.F3[:, ::-1] + n3]),
        V2=np.concatenate([g.V2, g.V2 * [-1.0, 1.0] - [5.0, 0.0]]),
        F2=np.concatenate([g.F2, g.F2[:, ::-1] + n2]),
        face_group=np.concatenate([g.face_group, g.face_group]),
        group_names=g.group_names,
    )


@pytest.mark.slow
def test_symmetric_scale_seam_renames_seam_part_and_fixed_loop():
    g = two_sleeves()
    # loop 1 is the left sleeve's outer end (x = 58), loop 3 the right one's (x = -58)
    step = (
        "{op: scale_seam, seam: [sleeve, cuff], part: sleeve, direction: around, "
        "factor: 1.3, fix: [{loop: 1}]}"
    )
    one = adjustment(g, parse_recipe(f"steps: [{step}]"), baseline=False)
    both = adjustment(g, parse_recipe(f"symmetric: true\nsteps: [{step}]"), baseline=False)
    used = np.unique(g.F3)
    assert mirror_gap(one.state.V3, used) > 1.0
    assert mirror_gap(both.state.V3, used) < 1e-6  # disjoint sleeves: exactly mirrored
    rec = both.state.log[1]
    assert rec["mirror"]["seam"] == ["sleeve_1", "cuff_1"] and rec["mirror"]["part"] == "sleeve_1"
    assert rec["mirror"]["pattern_kept"] == "cuff_1"
    assert both.state.frozen == {"cuff", "cuff_1"}
    plist = both.state.panels
    a0 = pattern_areas(g.V2, g.F2, plist)
    a1 = pattern_areas(both.result.V2, both.state.base.F2, plist)
    assert a1[0] / a0[0] > 1.05  # the sleeve widened at the seam
    assert a1[2] == pytest.approx(a1[0], rel=1e-6)
    np.testing.assert_allclose(a1[[1, 3]], a0[[1, 3]], rtol=1e-6)  # cuffs' patterns kept


def test_mirror_step_renames_panels_and_loops():
    g = two_sleeves()
    st = apply_steps(g, parse_recipe("steps: []"), options=EditOptions())
    pl = sagittal_plane(g.V3, g.F3, frame=Frame())
    m = mirror_state(st, pl)

    def mirrored(step):
        return mirror_step(step, before=st, mirrored=m, plane=pl, options=EditOptions())

    fix = [{"loop": 1}, ["sleeve", "cuff"], "hem"]
    seam = ScaleSeamStep(seam=["cuff", "sleeve"], part="sleeve", factor=1.2, fix=fix)
    assert mirrored(seam) == ScaleSeamStep(
        seam=["cuff_1", "sleeve_1"],
        part="sleeve_1",
        factor=1.2,
        fix=[{"loop": 3}, ["sleeve_1", "cuff_1"], "hem"],  # names are found on the mirror
    )
    loop = ShortenStep(opening={"loop": 0}, by=2)
    assert mirrored(loop) == ShortenStep(opening={"loop": 2}, by=2)
    region = ScaleStep(region={"panels": ["sleeve_1"]}, factor=1.1)
    assert mirrored(region) == ScaleStep(region={"panels": ["sleeve"]}, factor=1.1)
    sketch = LoosenStep(view="left", silhouette=[[0, 0], [0, 1]])
    assert mirrored(sketch) == sketch  # geometric: the mirrored garment's left is the other side


# ---------------------------------------------------------------------------------------
# recipe validation
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("symmetric: maybe\nsteps: []", "symmetric: expected true or false, got 'maybe'"),
        (
            "steps: [{op: scale, factor: 1.1, symmetric: 2}]",
            "steps[1].symmetric: expected true or false, got 2",
        ),
        (
            "steps: [{op: cut, plane: {point: [0, 0, 0], normal: [0, 1, 0]}, symmetric: 1}]",
            "steps[1].symmetric: expected true or false",
        ),
    ],
)
def test_symmetric_must_be_a_boolean(text, needle):
    with pytest.raises(RecipeError) as exc:
        parse_recipe(text)
    assert any(needle in p for p in exc.value.problems), exc.value.problems


def test_every_op_accepts_symmetric():
    from ptailor.edits import OPERATIONS

    r = parse_recipe("steps: [{op: scale, factor: 1.1}]")
    assert r.steps[0].symmetric is False and r.symmetric is False
    with pytest.raises(RecipeError) as exc:
        parse_recipe("steps: [{op: scale, factor: 1.1, mirror: true}]")
    assert "symmetric" in exc.value.problems[0]  # listed among the known keys
    for name in OPERATIONS:
        with pytest.raises(RecipeError) as exc:
            parse_recipe(f"steps: [{{op: {name}, symmetric: true}}]")
        assert not any("unknown key 'symmetric'" in p for p in exc.value.problems)


# ---------------------------------------------------------------------------------------
# the real T-shirt
# ---------------------------------------------------------------------------------------


def test_tee6_plane_and_mirror_panels():
    g = tee6()
    pl = sagittal_plane(g.V3, g.F3, frame=Frame((0, 1, 0), (0, 0, 1)))
    # close to x = 0 (the garment spans x in [-90, 90]), matched to about a centimetre
    assert pl.normal[0] > 0.999
    assert abs(pl.point[0]) < 1.0
    assert 0.5 < pl.rms < 2.0 and pl.max < 12.0
    mm = panel_mirror_map(g, pl)
    # sleeve halves (0, 1 on the left), then the back and front
    np.testing.assert_array_equal(mm, [2, 3, 0, 1, 4, 5])
    assert np.all(mm[mm] == np.arange(6))


SLEEVE = "{op: scale, region: {panels: [%s, %s]}, direction: around, factor: 1.2%s}"


@pytest.fixture(scope="module")
def tee6_runs():
    g = tee6()
    pl = panels(g)
    left = [p.name for p, c in zip(pl, drape_centroids(g), strict=True) if c[0] > 20.0]
    assert len(left) == 2
    runs = {}
    for key, top, extra in (
        ("symmetric", "symmetric: true\n", ""),
        ("one_sided", "", ""),
        ("overridden", "symmetric: true\n", ", symmetric: false"),
    ):
        text = f"{top}steps: [{SLEEVE % (*left, extra)}]"
        runs[key] = adjustment(g, parse_recipe(text), baseline=False)
    return g, left, runs


@pytest.mark.slow
def test_tee6_symmetric_sleeve_scale_changes_both_sleeves_alike(tee6_runs):
    g, left, runs = tee6_runs
    adj = runs["symmetric"]
    plist = adj.state.panels
    pl = sagittal_plane(g.V3, g.F3, frame=Frame())
    mm = panel_mirror_map(g, pl)
    a0 = pattern_areas(g.V2, g.F2, plist)
    a1 = pattern_areas(adj.result.V2, adj.state.base.F2, plist)
    idx = [p.index for p in plist if p.name in left]
    for i in idx:
        j = int(mm[i])
        assert j not in idx
        # the left sleeve's panels grew, and their mirror panels the same way
        assert a1[i] / a0[i] > 1.1
        assert a1[j] == pytest.approx(a1[i], rel=0.01)
        assert a1[j] / a0[j] == pytest.approx(a1[i] / a0[i], rel=0.01)
    assert adj.state.log[0]["op"] == "symmetry" and adj.state.log[1]["mirrored"] is True


@pytest.mark.slow
@pytest.mark.parametrize("key", ["one_sided", "overridden"])
def test_tee6_one_sided_sleeve_scale_keeps_the_right_sleeve(tee6_runs, key):
    g, left, runs = tee6_runs
    adj = runs[key]
    plist = adj.state.panels
    mm = panel_mirror_map(g, sagittal_plane(g.V3, g.F3, frame=Frame()))
    a0 = pattern_areas(g.V2, g.F2, plist)
    a1 = pattern_areas(adj.result.V2, adj.state.base.F2, plist)
    for p in plist:
        if p.name in left:
            j = int(mm[p.index])
            assert a1[p.index] / a0[p.index] > 1.1
            assert a1[j] == pytest.approx(a0[j], rel=0.005)
    assert [r["op"] for r in adj.state.log] == ["scale"]


def test_centred_step_is_applied_once():
    """region: all is its own mirror image: symmetric must not scale it twice."""
    import numpy as _np

    from ptailor.pipeline import adjustment as _adjust
    from ptailor.recipe import parse_recipe as _parse
    from ptailor.samples import lantern_sleeve

    g = lantern_sleeve()
    adj = _adjust(
        g,
        _parse(
            "symmetric: true\nsteps: [{op: scale, direction: around, axis: [0,1,0], factor: 1.2}]"
        ),
    )
    cuff = adj.state.panels[1]
    _np.testing.assert_allclose(_np.ptp(adj.result.V2[cuff.vertices], axis=0), [48, 8], rtol=1e-6)
    assert adj.state.log[-1]["mirrored"] == "self"


@pytest.mark.slow
def test_a_region_of_mirror_pairs_is_applied_once():
    """[sleeve, sleeve_1] mirrors to [sleeve_1, sleeve]: the same panels, so a symmetric
    step is applied once (it used to be applied twice, in the listed order's mirror: the
    dress's skirt widened by 1.1 twice)."""
    g = two_sleeves(n_around=24, n_sleeve=10, n_cuff=2)  # a quarter of the triangles
    step = "{op: scale, region: {panels: [sleeve, sleeve_1]}, direction: around, factor: 1.2}"
    one = adjustment(g, parse_recipe(f"steps: [{step}]"), baseline=False)
    both = adjustment(g, parse_recipe(f"symmetric: true\nsteps: [{step}]"), baseline=False)
    assert both.state.log[-1]["mirrored"] == "self"
    np.testing.assert_allclose(both.state.V3, one.state.V3, atol=1e-9)
    np.testing.assert_allclose(both.result.V2, one.result.V2, atol=1e-6)


def test_is_centred_compares_the_panels_a_region_selects():
    from types import SimpleNamespace

    from ptailor.edits.mirror import is_centred

    plist = [
        SimpleNamespace(name=n) for n in ("skirt_front", "skirt_back_left", "skirt_back_right")
    ]
    a = ScaleStep(region={"panels": ["skirt"]}, factor=1.1)
    b = ScaleStep(
        region={"panels": ["skirt_front", "skirt_back_right", "skirt_back_left"]}, factor=1.1
    )
    c = ScaleStep(region={"panels": ["skirt_front", "skirt_back_right"]}, factor=1.1)
    assert is_centred(a, b, panels=plist)
    assert not is_centred(a, c, panels=plist)


def test_a_symmetric_region_that_overlaps_its_mirror_is_refused():
    from types import SimpleNamespace

    from ptailor.edits.mirror import overlap_error

    plist = [SimpleNamespace(name=n) for n in ("front", "sleeve_left", "sleeve_right")]
    step = LoosenStep(region={"panels": ["front", "sleeve_left"]}, by=1.0)
    mstep = LoosenStep(region={"panels": ["front", "sleeve_right"]}, by=1.0)
    err = overlap_error(step, mstep, panels=plist)
    assert err is not None and "front" in str(err) and "sleeve_left" in str(err)
    other = LoosenStep(region={"panels": ["sleeve_right"]}, by=1.0)
    assert overlap_error(step, other, panels=plist) is None


def test_tee6_symmetric_loosen_of_front_and_one_sleeve_exits_2(tmp_path):
    rec = tmp_path / "r.yaml"
    rec.write_text(
        "units: cm\nsteps: [{op: loosen, region: {panels: [front, sleeve_left_front]}, by: 1,"
        " symmetric: true}]\n"
    )
    res = CliRunner().invoke(
        cli,
        ["adjust", str(real_path("tee6")), str(rec), "-o", str(tmp_path / "o"),
         "--pattern-units", "0.3333cm", "--drape-units", "0.3333cm", "--no-baseline"],
    )  # fmt: skip
    assert res.exit_code == 2, res.output
    assert "own mirror" in res.output and "front" in res.output
    assert not (tmp_path / "o").exists()
