"""Loosen / tighten: offset a region along its normals, or over-sketch a silhouette."""

from __future__ import annotations

import numpy as np
import pytest
import yaml

import ptailor.edits.loosen  # noqa: F401  (registers the ops until _load_all does)
from ptailor.adjust import adjust, apply_steps
from ptailor.edits import EditOptions
from ptailor.edits.loosen import falloff_weights, outward_normals, row_crossings
from ptailor.edits.region import region_faces
from ptailor.errors import PtailorError, RecipeError
from ptailor.formats.garment import load_garment
from ptailor.model.garment import Garment, panels, signed_areas_2d
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


@pytest.mark.parametrize("s", [1.0, 1.25])
@pytest.mark.parametrize("op, sign", [("loosen", 1.0), ("tighten", -1.0)])
def test_cylinder_pattern_width_grows_by_2_pi_d_over_s(s, op, sign):
    d = 2.0
    g = cylinder(stretch=s)
    W = width(g.V2)
    adj = adjust(g, recipe({"op": op, "region": "all", "by": d}))
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
    assert adj.state.log == ({"op": op, "by": d, "triangles": g.n_faces},)
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


def test_lantern_middle_ring_grows_by_by_and_the_ends_stay():
    by = 2.0
    g = lantern_sleeve()  # sleeve y 8..48, cuff y 0..8, rows 1 cm apart
    adj = adjust(g, recipe({"op": "loosen", "region": LANTERN_BOX, "by": by}))
    V0, V1, y = g.V3, adj.state.V3, g.V3[:, 1]
    dr = radii(V1) - radii(V0)
    middle = np.abs(y - 28.0) < 1e-9
    assert dr[middle] == pytest.approx(by, rel=0.01)
    move = np.linalg.norm(V1 - V0, axis=1)
    for end in (0.0, 48.0):  # the cuff's hem and the armhole
        assert move[np.abs(y - end) < 1e-9].max() < 0.1 * by
    # the region's border rings do not move; the offset rises smoothly inside it
    for border in (18.0, 38.0):
        assert np.abs(dr[np.abs(y - border) < 1e-9]).max() < 1e-6
    ring_dr = [dr[np.abs(y - k) < 1e-9].mean() for k in range(18, 29)]
    assert np.all(np.diff(ring_dr)[:4] > 0) and np.all(np.diff(ring_dr) >= -1e-12)
    assert np.all(np.diff(ring_dr) < 0.8 * by)  # no step: at most ~0.75 by per cm here
    assert_valid(adj.state.base, V2=adj.result.V2)
    # seams: the sleeve's and cuff's own back seams stay equal, the eased sleeve-to-cuff
    # seam (28 against 40) keeps its cuff side and about its ease
    sides = sorted(seam_sides(adj.state.base, adj.result.V2), key=lambda ab: -max(ab))
    (la, lb), (ma, mb), (ka, kb) = sides
    assert abs(la - lb) <= 1e-6 * la and abs(ka - kb) <= 1e-6 * ka
    assert max(ma, mb) == pytest.approx(40.0, rel=0.01)
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


def test_tightening_past_the_axis_is_an_error():
    g = cylinder()  # radius about 4.8
    with pytest.raises(PtailorError, match="inside out"):
        apply_steps(g, recipe({"op": "tighten", "by": 10.0}), options=EditOptions())


# ---------------------------------------------------------------------------------------
# silhouette form
# ---------------------------------------------------------------------------------------


def skirt_rings(V3: np.ndarray, n_around: int = 64) -> np.ndarray:
    """A cone skirt's drape as ``(rings, n_around, 3)``, ring 0 the hem."""
    return V3.reshape(-1, n_around, 3)


def test_silhouette_tightens_the_skirt_onto_the_sketch():
    g = cone_skirt()  # y up, hem at y = 0, waist at the top; front view: u = x, v = y
    R = skirt_rings(g.V3)
    right, left = np.argmax(R[0, :, 0]), np.argmin(R[0, :, 0])
    top = R[:, 0, 1].max()
    upper = R[:, 0, 1] >= 0.5 * top - 1e-9
    change = 3.0
    outline = R[upper, right, :2]
    sketch = (outline - [change, 0.0])[::-1].tolist()  # the right outline, 3 cm in
    adj = adjust(g, recipe({"op": "tighten", "view": "front", "silhouette": sketch}))
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


def test_tee6_loosen_all_is_valid():
    g = load_garment(real_path("tee6")).garment
    adj = adjust(g, recipe({"op": "loosen", "region": "all", "by": 1.0}, flatten={"seams": "keep"}))
    assert_valid(adj.state.base, V2=adj.result.V2)
    for la, lb in seam_sides(adj.state.base, adj.result.V2):
        assert abs(la - lb) <= 1e-3 * max(la, lb)
    # every panel gets wider: a tube of a half-sleeve gains about pi per half
    for p in adj.state.panels:
        assert width(adj.result.V2[p.vertices]) > width(g.V2[p.vertices]) + 1.0
