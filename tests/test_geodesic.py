"""Tests of the geodesic distance from a curve through source vertices (method.geodesic)."""

from __future__ import annotations

import numpy as np
import pytest

from ptailor.method.geodesic import geodesic_distance
from ptailor.samples import cone_skirt, cylinder, sample_for_triangles

# ---------------------------------------------------------------------------------------
# meshes


def grid(
    nx: int = 20,
    ny: int = 25,
    *,
    hx: float = 1.0,
    hy: float = 1.0,
    shear: float = 0.0,
    diagonals: str = "random",
    jitter: float = 0.0,
    seed: int = 0,
):
    """Planar ``nx x ny`` quad grid in z = 0, y from 0 up, split into triangles.

    ``diagonals`` is ``"random"`` (each quad's diagonal picked at random) or ``"anti"``
    (every quad split from its lower-right to its upper-left corner); ``shear`` moves row
    ``i`` by ``shear * i * hy`` in x; ``jitter`` moves interior vertices at random by up to
    that fraction of the spacing in x and y.
    """
    rng = np.random.default_rng(seed)
    x, y = np.meshgrid(np.arange(nx + 1) * hx, np.arange(ny + 1) * hy)
    x = x + shear * y
    V = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])
    idx = np.arange(V.shape[0]).reshape(ny + 1, nx + 1)
    a, b, c, d = idx[:-1, :-1], idx[:-1, 1:], idx[1:, 1:], idx[1:, :-1]
    if diagonals == "random":
        anti = (rng.random(a.shape) < 0.5)[..., None]
    else:
        anti = np.ones((*a.shape, 1), dtype=bool)
    t0 = np.where(anti, np.stack([a, b, d], -1), np.stack([a, b, c], -1))
    t1 = np.where(anti, np.stack([b, c, d], -1), np.stack([a, c, d], -1))
    F = np.concatenate([t0.reshape(-1, 3), t1.reshape(-1, 3)])
    col, row = idx % (nx + 1), idx // (nx + 1)
    inner = ((col > 0) & (col < nx) & (row > 0) & (row < ny)).ravel()
    V[inner, :2] += jitter * min(hx, hy) * rng.uniform(-1.0, 1.0, (inner.sum(), 2))
    return V, F


def max_angle_deg(V, F):
    P = V[F]
    a = P[:, [1, 2, 0]] - P
    b = P[:, [2, 0, 1]] - P
    cos = np.einsum("kcd,kcd->kc", a, b)
    cos /= np.linalg.norm(a, axis=2) * np.linalg.norm(b, axis=2)
    return float(np.degrees(np.arccos(cos.min())))


def bottom(V):
    return np.flatnonzero(V[:, 1] <= V[:, 1].min() + 1e-12)


# ---------------------------------------------------------------------------------------
# exact planar fronts


@pytest.mark.parametrize(
    "options",
    [
        {},  # right triangles, random diagonals
        {"hx": 0.7, "hy": 1.3},  # anisotropic spacing
        {"jitter": 0.1, "seed": 1},
        {"jitter": 0.3, "seed": 2},  # many obtuse triangles
    ],
)
def test_flat_grid_distance_from_bottom_edge_is_y(options):
    V, F = grid(**options)
    d = geodesic_distance(V, F, bottom(V))
    np.testing.assert_allclose(d, V[:, 1], rtol=1e-10, atol=1e-10)
    if options.get("jitter", 0.0) >= 0.3:
        assert max_angle_deg(V, F) > 120.0  # the case single-pass causality would reject


def test_front_from_an_edge_is_planar_without_vertical_edges():
    # a triangular lattice (every edge slanted or horizontal): the distance to the bottom
    # edge is y, although every edge path (Dijkstra) is sqrt(5) / 2 = 1.118 times longer
    # and the distance to the nearest source vertex differs off the lattice's columns
    V, F = grid(20, 25, shear=0.5, diagonals="anti")
    assert max_angle_deg(V, F) < 90.0
    d = geodesic_distance(V, F, bottom(V))
    # vertices whose whole upwind cone (half-width 0.5 per row) rests on the bottom edge
    inside = V[:, 0] + 0.5 * V[:, 1] <= 20.0 + 1e-9
    assert inside.sum() > 200
    np.testing.assert_allclose(d[inside], V[inside, 1], rtol=1e-10, atol=1e-10)
    # beyond the edge's end the front is the corner's circle: distance to the segment
    to_corner = np.hypot(V[:, 0] - 20.0, V[:, 1])
    exact = np.where(V[:, 0] <= 20.0, V[:, 1], to_corner)
    assert np.all(d >= exact - 1e-9)


def test_cylinder_distance_from_bottom_ring_is_height():
    g = cylinder(circumference=30.0, height=20.0, n_around=40, n_along=16)
    d = geodesic_distance(g.V3, g.F3, bottom(g.V3))
    np.testing.assert_allclose(d, g.V3[:, 1], rtol=1e-9, atol=1e-12)


def test_cone_skirt_distance_from_hem_is_slant_distance():
    length, hem, waist, n = 60.0, 30.0, 12.0, 64
    g = cone_skirt(waist_radius=waist, hem_radius=hem, length=length, n_around=n, n_along=30)
    V = g.V3
    d = geodesic_distance(V, g.F3, bottom(V))
    drop = np.sqrt(length**2 - (hem - waist) ** 2)
    slant = V[:, 1] * length / drop
    # the task's accuracy: 1 % of the slant distance
    np.testing.assert_allclose(d, slant, rtol=1e-2, atol=1e-12)
    # in fact exact: a ring vertex at slant s is s cos(alpha / 2) from the hem polygon's
    # nearest edge (alpha: the development's angle between two columns)
    alpha = 2.0 * np.arcsin(np.sin(np.pi / n) * (hem - waist) / length)
    np.testing.assert_allclose(d, slant * np.cos(alpha / 2.0), rtol=1e-10, atol=1e-10)


def test_point_source_first_order_overestimate():
    # not the use case, but a curved front: never below the Euclidean distance on a
    # convex planar domain, and within a few percent away from the source
    for jitter in (0.0, 0.25):
        V, F = grid(40, 40, jitter=jitter)
        c = 20 * 41 + 20
        exact = np.linalg.norm(V - V[c], axis=1)
        d = geodesic_distance(V, F, [c])
        assert np.all(d >= exact - 1e-12)
        far = exact > 10.0
        assert np.max(d[far] / exact[far]) < 1.06
        assert np.mean(d[far] / exact[far]) < 1.03


# ---------------------------------------------------------------------------------------
# limit (narrow band)


@pytest.mark.parametrize("limit", [0.0, 1.7, 5.0, 12.3])
def test_limit_matches_unlimited_below_limit(limit):
    g = sample_for_triangles(6000)
    V, F = g.V3, g.F3
    src = bottom(V)
    full = geodesic_distance(V, F, src)
    d = geodesic_distance(V, F, src, limit=limit)
    below = full < limit
    np.testing.assert_allclose(d[below], full[below], rtol=1e-12, atol=0.0)
    assert np.all(d >= full)  # above the limit: upper bounds
    E = V[F] - V[F[:, [1, 2, 0]]]
    longest = np.linalg.norm(E, axis=2).max()
    far = full > limit + 10.0 * longest
    assert far.sum() > len(V) / 3
    assert np.all(np.isinf(d[far]))  # the work stayed in the band


@pytest.mark.parametrize("seed", [0, 1])
def test_limit_matches_unlimited_on_curved_obtuse_mesh(seed):
    # a value may depend on a neighbour's slightly larger one through an obtuse triangle:
    # without the band's margin these meshes differ by up to 0.23 below the limit
    V, F = grid(30, 30, jitter=0.35, seed=seed)
    V[:, 2] = 0.3 * np.sin(0.7 * V[:, 0]) * np.cos(0.5 * V[:, 1])
    src = bottom(V)
    full = geodesic_distance(V, F, src)
    for limit in (3.3, 7.7, 12.1):
        d = geodesic_distance(V, F, src, limit=limit)
        below = full < limit
        np.testing.assert_allclose(d[below], full[below], rtol=1e-10, atol=0.0)
        assert np.all(d >= full)


def test_max_iter_gives_upper_bounds():
    V, F = grid(10, 10)
    src = bottom(V)
    full = geodesic_distance(V, F, src)
    d0 = geodesic_distance(V, F, src, max_iter=0)
    assert np.array_equal(np.isfinite(d0), np.isin(np.arange(len(V)), src))
    d1 = geodesic_distance(V, F, src, max_iter=1)
    assert np.all(d1 >= full)
    assert np.isfinite(d1).sum() == 2 * 11  # the sources and the row above them
    assert np.isinf(d1).sum() > 0


# ---------------------------------------------------------------------------------------
# topology and contract


def test_unreferenced_vertices_and_other_components_are_inf():
    V, F = grid(6, 6)
    nv = len(V)
    # a second, shifted copy and two unreferenced vertices
    V2 = np.concatenate([V, V + np.array([100.0, 0.0, 0.0]), [[5.0, 5.0, 5.0], [0.0, 0.0, 0.0]]])
    F2 = np.concatenate([F, F + nv])
    d = geodesic_distance(V2, F2, bottom(V))
    np.testing.assert_allclose(d[:nv], V[:, 1], atol=1e-12)
    assert np.all(np.isinf(d[nv:]))


def test_no_sources_gives_inf():
    V, F = grid(3, 3)
    d = geodesic_distance(V, F, np.array([], dtype=int))
    assert d.shape == (len(V),)
    assert np.all(np.isinf(d))


def test_inputs_not_mutated_and_read_only_accepted():
    V, F = grid(8, 8, jitter=0.2)
    src = bottom(V)
    copies = (V.copy(), F.copy(), src.copy())
    for a in (V, F, src):
        a.setflags(write=False)
    geodesic_distance(V, F, src, limit=3.0)
    for a, b in zip((V, F, src), copies, strict=True):
        assert np.array_equal(a, b)


def test_independent_of_face_order_orientation_and_source_order():
    V, F = grid(12, 9, jitter=0.2, seed=4)
    V[:, 2] = 0.2 * np.sin(V[:, 0])
    src = bottom(V)
    d = geodesic_distance(V, F, src)
    rng = np.random.default_rng(5)
    F2 = F[rng.permutation(len(F))][:, [0, 2, 1]]
    src2 = np.concatenate([src[::-1], src[:3]])  # reversed, with duplicates
    np.testing.assert_allclose(geodesic_distance(V, F2, src2), d, rtol=1e-12, atol=1e-14)


def test_degenerate_triangles_are_harmless():
    V, F = grid(5, 5)
    # a zero-area sliver and a triangle with a repeated corner
    V2 = np.concatenate([V, [[2.0, 2.0, 0.0]]])
    F2 = np.concatenate([F, [[13, 14, len(V)], [7, 7, 8]]])
    d = geodesic_distance(V2, F2, bottom(V))
    np.testing.assert_allclose(d[: len(V)], V[:, 1], atol=1e-12)
    assert d[-1] == pytest.approx(2.0)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"sources": [-1]}, "sources"),
        ({"sources": [10**6]}, "sources"),
        ({"sources": [0.5]}, "sources"),
        ({"limit": float("nan")}, "limit"),
        ({"limit": -1.0}, "limit"),
        ({"max_iter": -1}, "max_iter"),
    ],
)
def test_bad_arguments(kwargs, match):
    V, F = grid(3, 3)
    args = {"sources": [0]} | kwargs
    src = args.pop("sources")
    with pytest.raises(ValueError, match=match):
        geodesic_distance(V, F, src, **args)


def test_bad_meshes():
    V, F = grid(3, 3)
    with pytest.raises(ValueError, match="F"):
        geodesic_distance(V, F + len(V), [0])
    with pytest.raises(ValueError, match="F"):
        geodesic_distance(V, F[:, :2], [0])
    with pytest.raises(ValueError, match="V"):
        geodesic_distance(V[:, :1], F, [0])
    Vn = V.copy()
    Vn[3, 0] = np.nan
    with pytest.raises(ValueError, match="V"):
        geodesic_distance(Vn, F, [0])
