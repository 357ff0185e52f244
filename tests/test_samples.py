"""Tests of the procedurally generated sample garments."""

from __future__ import annotations

import numpy as np
import pytest

from ptailor.geometry.triangles import signed_areas_2d
from ptailor.model import Garment
from ptailor.model.boundary import boundary_loops
from ptailor.model.garment import panels
from ptailor.model.seams import seams
from ptailor.samples import (
    PANEL_GAP,
    SAMPLES,
    cone_skirt,
    cylinder,
    lantern_sleeve,
    sample_for_triangles,
)


def edge_lengths(V: np.ndarray, F: np.ndarray) -> np.ndarray:
    """(m, 3) lengths of edges (0-1, 1-2, 2-0) of each triangle."""
    return np.linalg.norm(V[np.roll(F, -1, axis=1)] - V[F], axis=2)


def face_panel(g: Garment) -> np.ndarray:
    fp = np.full(g.n_faces, -1, dtype=np.int64)
    for p in panels(g):
        fp[p.faces] = p.index
    assert (fp >= 0).all()
    return fp


def assert_isometric(g: Garment, faces: np.ndarray | None = None) -> None:
    faces = np.arange(g.n_faces) if faces is None else faces
    e3 = edge_lengths(g.V3, g.F3[faces])
    e2 = edge_lengths(g.V2, g.F2[faces])
    np.testing.assert_allclose(e3, e2, rtol=1e-9, atol=0)


def bbox(g: Garment, vertices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    P = g.V2[vertices]
    return P.min(axis=0), P.max(axis=0)


ALL_SAMPLES = [
    pytest.param(lantern_sleeve, id="lantern_sleeve"),
    pytest.param(cylinder, id="cylinder"),
    pytest.param(cone_skirt, id="cone_skirt"),
    pytest.param(lambda: cone_skirt(n_around=10, n_along=3), id="cone_skirt_coarse"),
]


# --- structure common to every sample ---------------------------------------------------


def test_registry() -> None:
    assert set(SAMPLES) == {"lantern_sleeve", "cylinder", "cone_skirt", "bodice", "skirt"}
    for name, make in SAMPLES.items():
        assert isinstance(make(), Garment), name


@pytest.mark.parametrize("make", ALL_SAMPLES)
def test_arrays_well_formed(make) -> None:
    g = make()
    m = g.n_faces
    assert g.V3.dtype == np.float64 and g.V3.ndim == 2 and g.V3.shape[1] == 3
    assert g.V2.dtype == np.float64 and g.V2.ndim == 2 and g.V2.shape[1] == 2
    assert g.F3.shape == (m, 3) and g.F2.shape == (m, 3)
    assert g.F3.dtype == np.int64 and g.F2.dtype == np.int64
    assert g.face_group.shape == (m,)
    assert set(np.unique(g.face_group)) == set(range(len(g.group_names)))
    assert g.units == "cm"
    # every vertex is used, no triangle repeats a vertex
    assert np.array_equal(np.unique(g.F3), np.arange(len(g.V3)))
    assert np.array_equal(np.unique(g.F2), np.arange(len(g.V2)))
    for F in (g.F3, g.F2):
        assert (F[:, 0] != F[:, 1]).all() and (F[:, 1] != F[:, 2]).all()
        assert (F[:, 2] != F[:, 0]).all()
    assert np.isfinite(g.V3).all() and np.isfinite(g.V2).all()


@pytest.mark.parametrize("make", ALL_SAMPLES)
def test_pattern_counter_clockwise(make) -> None:
    g = make()
    assert (signed_areas_2d(g.V2, g.F2) > 0).all()
    assert not any(p.mirrored for p in panels(g))


@pytest.mark.parametrize("make", ALL_SAMPLES)
def test_deterministic(make) -> None:
    a, b = make(), make()
    for name in ("V3", "F3", "V2", "F2", "face_group"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert a.group_names == b.group_names


@pytest.mark.parametrize("make", ALL_SAMPLES)
def test_diagonals_alternate(make) -> None:
    # the two triangles of a quad share its diagonal; in a checkerboard, neighbouring quads
    # of a row use different diagonals, so the diagonal's 2D direction alternates in sign
    g = make()
    F2 = g.F2.reshape(-1, 2, 3)  # quads
    shared = np.array([np.intersect1d(q[0], q[1]) for q in F2[:50]])
    d = g.V2[shared[:, 1]] - g.V2[shared[:, 0]]
    slope_sign = np.sign(d[:, 0] * d[:, 1])
    assert (slope_sign != 0).all()
    assert (slope_sign[1:] != slope_sign[:-1]).any()
    assert (slope_sign == 1).any() and (slope_sign == -1).any()


@pytest.mark.parametrize("make", ALL_SAMPLES)
def test_panels_do_not_overlap(make) -> None:
    g = make()
    ps = panels(g)
    boxes = [bbox(g, p.vertices) for p in ps]
    for i in range(len(boxes)):
        for j in range(i + 1, len(boxes)):
            (lo_a, hi_a), (lo_b, hi_b) = boxes[i], boxes[j]
            disjoint = (hi_a < lo_b) | (hi_b < lo_a)
            assert disjoint.any(), (ps[i].name, ps[j].name)


# --- lantern sleeve ---------------------------------------------------------------------


def test_sleeve_counts() -> None:
    g = lantern_sleeve()
    assert g.n_faces == 2 * 48 * (40 + 8)
    assert len(g.V3) == 48 * (40 + 8 + 1)
    assert len(g.V2) == 49 * (41 + 9)
    g = lantern_sleeve(n_around=7, n_sleeve=3, n_cuff=2)
    assert g.n_faces == 2 * 7 * 5
    assert len(g.V3) == 7 * 6


def test_sleeve_panels_and_groups() -> None:
    g = lantern_sleeve()
    ps = panels(g)
    assert [p.name for p in ps] == ["sleeve", "cuff"]
    assert g.group_names == ("sleeve", "cuff")
    assert len(ps[0].faces) == 2 * 48 * 40 and len(ps[1].faces) == 2 * 48 * 8
    assert (g.face_group[ps[0].faces] == 0).all() and (g.face_group[ps[1].faces] == 1).all()


def test_sleeve_pattern_sizes_and_layout() -> None:
    g = lantern_sleeve()
    sleeve, cuff = panels(g)
    lo, hi = bbox(g, cuff.vertices)
    np.testing.assert_allclose(lo, [0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(hi - lo, [40.0, 8.0], rtol=1e-12)
    lo_s, hi_s = bbox(g, sleeve.vertices)
    np.testing.assert_allclose(hi_s - lo_s, [28.0, 40.0], rtol=1e-12)
    np.testing.assert_allclose(lo_s[0], hi[0] + PANEL_GAP, rtol=1e-12)


def test_sleeve_drape_is_a_cylinder() -> None:
    g = lantern_sleeve()
    n = 48
    r = np.hypot(g.V3[:, 0], g.V3[:, 2])
    np.testing.assert_allclose(r, r[0], rtol=1e-12)
    # the ring polygon's perimeter is the circumference; the radius is close to C / 2 pi
    ring = g.V3[:n]
    perimeter = np.linalg.norm(np.roll(ring, -1, axis=0) - ring, axis=1).sum()
    np.testing.assert_allclose(perimeter, 28.0, rtol=1e-12)
    assert abs(r[0] - 28.0 / (2 * np.pi)) / r[0] < 1e-3
    np.testing.assert_allclose([g.V3[:, 1].min(), g.V3[:, 1].max()], [0.0, 48.0], atol=1e-12)
    # the cuff is below the sleeve
    sleeve, cuff = panels(g)
    assert g.V3[np.unique(g.F3[cuff.faces]), 1].max() == pytest.approx(8.0)
    assert g.V3[np.unique(g.F3[sleeve.faces]), 1].min() == pytest.approx(8.0)


def test_sleeve_is_isometric_and_cuff_is_elastic() -> None:
    g = lantern_sleeve()
    sleeve, cuff = panels(g)
    assert_isometric(g, sleeve.faces)
    e3 = edge_lengths(g.V3, g.F3[cuff.faces])
    e2 = edge_lengths(g.V2, g.F2[cuff.faces])
    d2 = g.V2[np.roll(g.F2[cuff.faces], -1, axis=1)] - g.V2[g.F2[cuff.faces]]
    around = np.abs(d2[..., 1]) < 1e-12
    along = np.abs(d2[..., 0]) < 1e-12
    assert around.any() and along.any()
    np.testing.assert_allclose(e3[around], 0.7 * e2[around], rtol=1e-9)
    np.testing.assert_allclose(e3[along], e2[along], rtol=1e-9)
    # and the cuff is NOT isometric (the test above can fail)
    assert not np.allclose(e3, e2, rtol=1e-3)


def test_sleeve_seams() -> None:
    g = lantern_sleeve()
    fp = face_panel(g)
    found = {s.panels: s for s in seams(g.F3, g.F2, fp)}
    assert set(found) == {(0, 0), (0, 1), (1, 1)}
    ring, self_sleeve, self_cuff = found[(0, 1)], found[(0, 0)], found[(1, 1)]
    assert len(ring.edges3) == 48
    assert len(self_sleeve.edges3) == 40
    assert len(self_cuff.edges3) == 8
    # the seam ring is the top of the cuff (y = 8) in the drape, shared by both panels
    np.testing.assert_allclose(g.V3[ring.edges3.ravel(), 1], 8.0, atol=1e-12)
    la, lb = ring.lengths(g.V2)
    assert la == pytest.approx(28.0, rel=1e-12)  # sleeve side
    assert lb == pytest.approx(40.0, rel=1e-12)  # cuff side (gathered)
    for s, length in ((self_sleeve, 40.0), (self_cuff, 8.0)):
        a, b = s.lengths(g.V2)
        assert a == pytest.approx(length, rel=1e-12) and b == pytest.approx(length, rel=1e-12)
        # the vertical self-seam joins the pattern's left and right edges
        xa, xb = g.V2[s.edges_a[:, 0], 0], g.V2[s.edges_b[:, 0], 0]
        assert np.abs(xa - xb).min() > 20.0


def test_sleeve_openings() -> None:
    g = lantern_sleeve()
    loops = boundary_loops(g.F3)
    assert len(loops) == 2
    assert [len(loop) for loop in loops] == [48, 48]
    heights = sorted(float(g.V3[loop, 1].mean()) for loop in loops)
    assert heights == pytest.approx([0.0, 48.0])


@pytest.mark.parametrize("axis", ["x", "z"])
def test_sleeve_axis(axis: str) -> None:
    base = lantern_sleeve()
    g = lantern_sleeve(axis=axis)
    k = "xyz".index(axis)
    np.testing.assert_allclose(g.V3[:, k], base.V3[:, 1])
    np.testing.assert_allclose(np.linalg.norm(g.V3, axis=1), np.linalg.norm(base.V3, axis=1))
    assert np.array_equal(g.F3, base.F3) and np.array_equal(g.V2, base.V2)

    # a rotation: triangle orientation (normals' handedness) is kept
    def normals(G: Garment) -> np.ndarray:
        a, b, c = (G.V3[G.F3[:, i]] for i in range(3))
        return np.cross(b - a, c - a)

    radial_base = base.V3[base.F3[:, 0]].copy()
    radial_base[:, 1] = 0.0
    radial = g.V3[g.F3[:, 0]].copy()
    radial[:, k] = 0.0
    assert ((normals(base) * radial_base).sum(axis=1) > 0).all()  # outward
    assert ((normals(g) * radial).sum(axis=1) > 0).all()


def test_sleeve_rejects_bad_options() -> None:
    with pytest.raises(ValueError):
        lantern_sleeve(axis="w")
    with pytest.raises(ValueError):
        lantern_sleeve(cuff_ratio=0.0)
    with pytest.raises(ValueError):
        lantern_sleeve(n_around=2)
    with pytest.raises(TypeError):
        lantern_sleeve(28.0)  # keyword-only


# --- cylinder ---------------------------------------------------------------------------


def test_cylinder_counts_and_isometry() -> None:
    g = cylinder()
    assert g.n_faces == 2 * 40 * 16
    assert [p.name for p in panels(g)] == ["tube"]
    assert_isometric(g)
    lo, hi = bbox(g, np.arange(len(g.V2)))
    np.testing.assert_allclose(hi - lo, [30.0, 20.0], rtol=1e-12)


def test_cylinder_stretch() -> None:
    g = cylinder(stretch=1.25)
    lo, hi = bbox(g, np.arange(len(g.V2)))
    np.testing.assert_allclose(hi - lo, [30.0 / 1.25, 20.0], rtol=1e-12)
    e3 = edge_lengths(g.V3, g.F3)
    e2 = edge_lengths(g.V2, g.F2)
    d2 = g.V2[np.roll(g.F2, -1, axis=1)] - g.V2[g.F2]
    around = np.abs(d2[..., 1]) < 1e-12
    along = np.abs(d2[..., 0]) < 1e-12
    np.testing.assert_allclose(e3[around], 1.25 * e2[around], rtol=1e-9)
    np.testing.assert_allclose(e3[along], e2[along], rtol=1e-9)


def test_cylinder_mirrored() -> None:
    g, m = cylinder(), cylinder(mirrored=True)
    assert (signed_areas_2d(m.V2, m.F2) < 0).all()
    assert [p.mirrored for p in panels(m)] == [True]
    assert np.array_equal(g.V3, m.V3) and np.array_equal(g.F3, m.F3)
    assert np.array_equal(g.F2, m.F2)
    np.testing.assert_allclose(m.V2[:, 0], 30.0 - g.V2[:, 0], atol=1e-12)
    assert_isometric(m)


def test_cylinder_seam_and_openings() -> None:
    g = cylinder(n_around=12, n_along=5)
    (s,) = seams(g.F3, g.F2, face_panel(g))
    assert s.panels == (0, 0) and len(s.edges3) == 5
    # the closing seam is at the back
    assert (g.V3[s.edges3.ravel(), 2] < 0).all()
    loops = boundary_loops(g.F3)
    assert [len(loop) for loop in loops] == [12, 12]


# --- cone skirt -------------------------------------------------------------------------


def test_cone_skirt_counts_panels_groups() -> None:
    g = cone_skirt()
    assert g.n_faces == 2 * 64 * 30
    assert len(g.V3) == 64 * 31
    assert len(g.V2) == 2 * 33 * 31
    ps = panels(g)
    assert [p.name for p in ps] == ["front", "back"]
    front3 = g.V3[np.unique(g.F3[ps[0].faces])]
    back3 = g.V3[np.unique(g.F3[ps[1].faces])]
    assert (front3[:, 2] > -1e-9).all() and (back3[:, 2] < 1e-9).all()


@pytest.mark.parametrize(
    "options",
    [
        {},
        {"n_around": 10, "n_along": 3},
        {"waist_radius": 20.0, "hem_radius": 20.0},  # a cylinder: a rectangle
        {"waist_radius": 20.0, "hem_radius": 20.0 + 1e-7},  # nearly one
        {"waist_radius": 30.0, "hem_radius": 10.0, "length": 25.0},  # flares upwards
        {"waist_radius": 5.0, "hem_radius": 80.0, "length": 80.0, "n_around": 16},
    ],
)
def test_cone_skirt_is_exactly_isometric(options: dict) -> None:
    g = cone_skirt(**options)
    assert_isometric(g)
    assert (signed_areas_2d(g.V2, g.F2) > 0).all()


def test_cone_skirt_geometry() -> None:
    g = cone_skirt(waist_radius=12.0, hem_radius=30.0, length=60.0)
    r = np.hypot(g.V3[:, 0], g.V3[:, 2])
    y = g.V3[:, 1]
    drop = np.sqrt(60.0**2 - 18.0**2)
    np.testing.assert_allclose([y.min(), y.max()], [0.0, drop], atol=1e-12)
    # waist at the top, hem at the bottom, radius linear in height
    np.testing.assert_allclose(r, 30.0 - 18.0 * y / drop, rtol=1e-12)
    ps = panels(g)
    # the centre column (hem to waist) of the development is the slant length
    F = g.F2[ps[0].faces]
    lo, hi = bbox(g, np.unique(F))
    assert hi[1] - lo[1] >= 60.0 - 1e-9
    # the development is an annular sector of half-angle ~ pi * (hem - waist) / length / 2
    P = g.V2[ps[0].vertices]
    n_row = 64 // 2 + 1
    hem, waist = P[:n_row], P[-n_row:]
    apex_dist = 60.0 * 30.0 / 18.0
    chord = np.linalg.norm(hem[-1] - hem[0])
    angle = 2 * np.arcsin(chord / (2 * apex_dist))
    assert angle == pytest.approx(np.pi * 18.0 / 60.0, rel=2e-3)
    # hem and waist are arcs about one apex
    centre = np.array([hem[n_row // 2, 0], hem[n_row // 2, 1] + apex_dist])
    np.testing.assert_allclose(np.linalg.norm(hem - centre, axis=1), apex_dist, rtol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(waist - centre, axis=1), apex_dist - 60.0, rtol=1e-9)


def test_cone_skirt_seams_and_openings() -> None:
    g = cone_skirt(n_around=16, n_along=6)
    found = seams(g.F3, g.F2, face_panel(g))
    assert [s.panels for s in found] == [(0, 1), (0, 1)]
    xs = sorted(float(g.V3[s.edges3.ravel(), 0].mean()) for s in found)
    for s in found:
        assert len(s.edges3) == 6
        x = g.V3[s.edges3.ravel()]
        np.testing.assert_allclose(x[:, 2], 0.0, atol=1e-9)  # side seams in the x-y plane
        a, b = s.lengths(g.V2)
        assert a == pytest.approx(60.0, rel=1e-12) and b == pytest.approx(60.0, rel=1e-12)
    assert xs[0] < 0 < xs[1]
    loops = boundary_loops(g.F3)
    assert [len(loop) for loop in loops] == [16, 16]


def test_cone_skirt_rejects_bad_options() -> None:
    with pytest.raises(ValueError):
        cone_skirt(n_around=15)
    with pytest.raises(ValueError):
        cone_skirt(waist_radius=10.0, hem_radius=80.0, length=60.0)


# --- benchmark sizes --------------------------------------------------------------------


@pytest.mark.parametrize("n", [100, 137, 1_000, 4_999, 20_000, 100_000])
def test_sample_for_triangles(n: int) -> None:
    g = sample_for_triangles(n)
    assert abs(g.n_faces - n) <= 0.05 * n
    assert [p.name for p in panels(g)] == ["sleeve", "cuff"]


def test_sample_for_triangles_all_small_sizes_within_5_percent() -> None:
    counts = np.array([sample_for_triangles(n).n_faces for n in range(100, 400, 7)])
    req = np.arange(100, 400, 7)
    assert (np.abs(counts - req) <= 0.05 * req).all()


def test_split_pattern_duplicates_only_the_vertices_on_the_cut():
    from ptailor.samples.grid import split_pattern

    V2 = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    F2 = np.array([[0, 1, 2], [0, 2, 3]])
    W, G, src = split_pattern(V2, F2, np.array([0, 1]))
    assert len(W) == 6  # 0 and 2 are on the cut: one copy per side
    np.testing.assert_array_equal(W[G], V2[F2])  # the same triangles
    assert set(G[0]) & set(G[1]) == set()
    np.testing.assert_array_equal(W, V2[src])


def test_gored_skirt_is_the_cone_skirt_cut_and_refuses_odd_gores():
    from ptailor.samples import cone_skirt, gored_skirt

    g, s = cone_skirt(), gored_skirt(gores=6)
    np.testing.assert_array_equal(s.V3, g.V3)
    np.testing.assert_array_equal(s.V2[s.F2], g.V2[g.F2])
    with pytest.raises(ValueError, match="even"):
        gored_skirt(gores=3)
