"""The geometry package: known answers, and every docstring example runs."""

from __future__ import annotations

import doctest
import importlib

import numpy as np
import pytest

from ptailor.geometry import (
    closest_rotations,
    component_labels,
    det2,
    edge_matrices,
    extent_axis,
    inv2,
    least_squares_preimages,
    nearest_segment_distance,
    normal_tensor,
    pattern_jacobians,
    pseudo_inverses,
    rigid_fit,
    rigid_fit_groups,
    scatter_labels,
    segment_feet,
    signed_areas_2d,
    sqrt_spd2,
    triangle_areas,
    triangle_normals,
    tube_axis,
)

MODULES = [
    "closed_forms",
    "labels",
    "pattern_maps",
    "rotations",
    "segments",
    "triangles",
    "tube_axis",
]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    mod = importlib.import_module(f"ptailor.geometry.{name}")
    res = doctest.testmod(mod, extraglobs={"np": np}, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert res.attempted > 0 and res.failed == 0


def rot2(a):
    return np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])


def test_unit_right_triangle_areas_and_normals():
    V3 = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    F = np.array([[0, 1, 2], [0, 2, 1]])
    assert np.allclose(triangle_areas(V3, F), 0.5)
    assert np.allclose(triangle_areas(V3, F, robust=True), 0.5)
    assert np.allclose(triangle_areas(V3[:, :2], F), 0.5)
    assert np.allclose(signed_areas_2d(V3[:, :2], F), [0.5, -0.5])
    assert np.allclose(triangle_normals(V3, F), [[0, 0, 1], [0, 0, -1]])
    assert np.allclose(triangle_normals(V3 * 3, F, unit=False), [[0, 0, 9], [0, 0, -9]])
    # a degenerate triangle: zero area, zero normal
    Vd = np.array([[0.0, 0, 0], [1, 0, 0], [2, 0, 0]])
    assert triangle_areas(Vd, F[:1])[0] == 0.0
    assert np.all(triangle_normals(Vd, F[:1]) == 0.0)


def test_robust_areas_do_not_overflow():
    V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]) * 1e160
    F = np.array([[0, 1, 2]])
    with np.errstate(over="ignore"):
        assert np.isinf(triangle_areas(V, F)[0])
    a = triangle_areas(V / 1e20, F, robust=True)[0]
    assert np.isclose(a, 0.5e280)


def test_robust_areas_are_the_scaled_cross_product_bit_for_bit():
    """The written-out robust areas equal ``|a/s x b/s| s^2`` through np.cross and
    np.linalg.norm exactly (any scale, zero, NaN and infinite coordinates)."""
    rng = np.random.default_rng(7)
    V = rng.normal(size=(400, 3)) * 10.0 ** rng.integers(-150, 150, size=(400, 1))
    V[3] = np.nan
    V[5] = [np.inf, 0.0, 1.0]
    V[8:11] = 0.0
    F = np.vstack([rng.integers(0, 400, size=(2000, 3)), [[8, 9, 10], [3, 4, 6], [5, 6, 7]]])
    a = V[F[:, 1]] - V[F[:, 0]]
    b = V[F[:, 2]] - V[F[:, 0]]
    with np.errstate(all="ignore"):
        s = np.maximum(np.abs(a).max(axis=1), np.abs(b).max(axis=1))
        s = np.where(s > 0, s, 1.0)
        want = 0.5 * np.linalg.norm(np.cross(a / s[:, None], b / s[:, None]), axis=1) * s * s
        got = triangle_areas(V, F, robust=True)
    assert np.array_equal(got, want, equal_nan=True)
    assert got[-3] == 0.0 and np.isnan(got[-2])


def test_closed_forms():
    rng = np.random.default_rng(1)
    A = rng.normal(size=(50, 2, 2))
    assert np.allclose(det2(A), np.linalg.det(A))
    assert np.allclose(inv2(A), np.linalg.inv(A))
    C = A @ np.swapaxes(A, 1, 2) + 0.1 * np.eye(2)
    U = sqrt_spd2(C)
    assert np.allclose(U @ U, C)
    assert np.allclose(U, np.swapaxes(U, 1, 2))
    assert np.all(np.linalg.eigvalsh(U) > 0)


def test_closest_rotations_recover_rotation_of_a_scaled_rotation():
    angles = np.array([0.3, -2.0, 3.0])
    J = np.stack([2.5 * rot2(a) for a in angles])
    assert np.allclose(closest_rotations(J), np.stack([rot2(a) for a in angles]))


def test_rigid_fit_recovers_rotation_and_translation():
    rng = np.random.default_rng(2)
    A = rng.normal(size=(20, 2))
    R0, t0 = rot2(1.1), np.array([3.0, -2.0])
    R, t = rigid_fit(A, A @ R0.T + t0)
    assert np.allclose(R, R0) and np.allclose(t, t0)
    # a reflection, when allowed
    M = rot2(0.4) @ np.diag([1.0, -1.0])
    R, t = rigid_fit(A, A @ M.T + t0, reflect=True)
    assert np.allclose(R, M) and np.allclose(t, t0)
    assert np.linalg.det(R) < 0
    # not allowed: the best rotation, not the reflection
    R, _ = rigid_fit(A, A @ M.T + t0)
    assert np.isclose(np.linalg.det(R), 1.0)
    # 3D
    A3 = rng.normal(size=(20, 3))
    c, s = np.cos(0.7), np.sin(0.7)
    R3 = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    R, t = rigid_fit(A3, A3 @ R3.T + 1.0)
    assert np.allclose(R, R3) and np.allclose(t, 1.0)


def test_rigid_fit_groups_moves_each_group():
    rng = np.random.default_rng(3)
    X = rng.normal(size=(30, 2))
    lab = np.repeat([0, 1, -1], 10)
    Y = X.copy()
    Y[:10] = X[:10] @ rot2(0.5).T + [1, 2]
    Y[10:20] = X[10:20] @ rot2(-1.0).T - 4
    out = rigid_fit_groups(X, Y, lab, 2)
    assert np.allclose(out[:20], Y[:20])
    assert np.array_equal(out[20:], X[20:])


def test_segment_feet_and_distances():
    A, B = np.array([0.0, 0.0]), np.array([2.0, 0.0])
    P = np.array([[-1.0, 1.0], [1.0, 2.0], [5.0, 0.0]])
    d, foot = segment_feet(P, A, B)
    assert np.allclose(foot, [[0, 0], [1, 0], [2, 0]])
    assert np.allclose(d, [np.sqrt(2.0), 2.0, 3.0])
    # a zero-length segment: its end is the foot
    d, foot = segment_feet(P[:1], A, A)
    assert np.allclose(foot, [[0, 0]]) and np.allclose(d, np.sqrt(2.0))
    # nearest of several segments, and no segment at all
    A2 = np.array([[0.0, 0], [10, 0]])
    B2 = np.array([[2.0, 0], [10, 5]])
    assert np.allclose(nearest_segment_distance(P, A2, B2), [np.sqrt(2.0), 2.0, 3.0])
    assert nearest_segment_distance(P, A2[:0], B2[:0]).tolist() == [0.0, 0.0, 0.0]


def cylinder(axis, n=24, rings=6):
    t = np.linspace(0.0, 2 * np.pi, n + 1)[:-1]
    z = np.linspace(0.0, 5.0, rings)
    V = np.stack([np.cos(t)[None].repeat(rings, 0), np.sin(t)[None].repeat(rings, 0),
                  z[:, None].repeat(n, 1)], -1).reshape(-1, 3)  # fmt: skip
    i = np.arange(n)
    F = []
    for r in range(rings - 1):
        a, b = r * n + i, r * n + (i + 1) % n
        F += [np.stack([a, b, a + n], 1), np.stack([b, b + n, a + n], 1)]
    F = np.concatenate(F)
    # rotate z onto the axis
    axis = axis / np.linalg.norm(axis)
    v = np.cross([0.0, 0.0, 1.0], axis)
    s, c = np.linalg.norm(v), float(axis[2])
    K = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    R = np.eye(3) + K + K @ K * ((1 - c) / s**2) if s > 0 else np.eye(3)
    return V @ R.T, F


def test_tube_axis_of_a_generated_cylinder():
    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    V, F = cylinder(axis=axis)
    ax = tube_axis(V, F)
    assert ax is not None and np.isclose(abs(ax @ axis), 1.0)
    N = normal_tensor(V, F)
    assert np.isclose(np.trace(N), 1.0) and np.allclose(N, N.T)
    # a flat sheet is not a tube; its extent axis is its long side
    S = np.array([[0.0, 0, 0], [10, 0, 0], [10, 1, 0], [0, 1, 0]])
    Fs = np.array([[0, 1, 2], [0, 2, 3]])
    assert tube_axis(S, Fs) is None
    assert np.isclose(abs(extent_axis(S)[0]), 1.0)
    # the thresholds are the tolerances' (a stricter ratio refuses the cylinder)
    assert tube_axis(V, F, ratio=1e30) is None


def test_pattern_maps_of_a_scaled_copy():
    V2 = np.array([[0.0, 0], [1, 0], [0, 1], [1, 1]])
    F = np.array([[0, 1, 2], [1, 3, 2]])
    M = np.array([[2.0, 0.0], [0.0, 3.0], [0.0, 0.0]])
    V3 = V2 @ M.T
    J, ok = pattern_jacobians(V3, F, V2, F)
    assert ok.all() and np.allclose(J, M)
    P = pseudo_inverses(J)
    assert np.allclose(P @ J, np.eye(2))
    X, good = least_squares_preimages(J, np.array([[2.0, 3.0, 7.0], [0.0, 6.0, 0.0]]), ok)
    assert good.all() and np.allclose(X, [[1, 1], [0, 2]])
    # a degenerate pattern triangle is flagged, not divided by zero
    V2d = V2.copy()
    V2d[2] = [2.0, 0.0]
    J, ok = pattern_jacobians(V3, F, V2d, F)
    assert ok.tolist() == [False, True] and np.all(np.isfinite(J))
    _, good = least_squares_preimages(J, np.ones((2, 3)), ok)
    assert not good[0]


def test_labels_of_two_disjoint_triangles():
    F = np.array([[0, 1, 2], [3, 4, 5]])
    assert component_labels(F, 6).tolist() == [0, 1]
    # numbered by first appearance, whatever the vertex numbers
    assert component_labels(F[::-1], 6).tolist() == [0, 1]
    assert component_labels(np.array([[0, 1, 2], [2, 3, 4]]), 5).tolist() == [0, 0]
    assert component_labels(np.zeros((0, 3), dtype=np.int64), 0).tolist() == []
    assert scatter_labels([np.array([1]), np.array([0])], 3).tolist() == [1, 0, -1]
    assert scatter_labels([np.array([0, 1])], 2, labels=[4], fill=9).tolist() == [4, 4]


def test_edge_matrices():
    V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 2, 0]])
    E = edge_matrices(V, np.array([[0, 1, 2]]))
    assert E.shape == (1, 3, 2) and np.allclose(E[0], [[1, 0], [0, 2], [0, 0]])


def test_segment_moments_are_the_curves_not_the_vertices():
    """A polyline's centroid and second moment by arc length: splitting its segments at
    their midpoints changes neither, while its vertices' mean moves toward the split part."""
    from ptailor.geometry.segments import segment_moments

    rng = np.random.default_rng(5)
    V = np.cumsum(rng.uniform(0.1, 2.0, (9, 3)), axis=0)
    E = np.stack([np.arange(8), np.arange(1, 9)], axis=1)
    c, S = segment_moments(V, E)
    # split the first three segments at their midpoints
    mid = 0.5 * (V[E[:3, 0]] + V[E[:3, 1]])
    W = np.concatenate([V, mid])
    k = np.arange(9, 12)
    E2 = np.concatenate([np.stack([E[:3, 0], k], 1), np.stack([k, E[:3, 1]], 1), E[3:]])
    c2, S2 = segment_moments(W, E2)
    np.testing.assert_allclose(c2, c, rtol=1e-12)
    np.testing.assert_allclose(S2, S, rtol=1e-12, atol=1e-12)
    assert np.linalg.norm(W.mean(axis=0) - V.mean(axis=0)) > 1e-2  # the vertices' mean moves
    # a straight segment: centroid at its middle, second moment L^2 / 12 along it
    c1, S1 = segment_moments(np.array([[0.0, 0, 0], [2.0, 0, 0]]), np.array([[0, 1]]))
    np.testing.assert_allclose(c1, [1.0, 0, 0])
    np.testing.assert_allclose(S1, np.diag([4.0 / 12, 0, 0]), atol=1e-15)
