"""The stitching iteration's parts against plain reference computations."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ptailor.geometry.triangles import edge_lengths
from ptailor.method.anderson import Anderson
from ptailor.method.flatten import panel_strain
from ptailor.method.solver import factor
from ptailor.method.solver.problem import PanelIndex, panel_sizes


def _reference_mix(fs: list[np.ndarray], gs: list[np.ndarray], m: int) -> np.ndarray:
    """Anderson's next iterate from the last ``m + 1`` residuals and images, directly."""
    dF = np.stack([b - a for a, b in zip(fs[-m - 1 : -1], fs[-m:], strict=True)], 1)
    dG = np.stack([b - a for a, b in zip(gs[-m - 1 : -1], gs[-m:], strict=True)], 1)
    gamma = np.linalg.lstsq(dF, fs[-1], rcond=None)[0]
    return gs[-1] - dG @ gamma


def test_anderson_matches_least_squares_after_the_history_wraps():
    rng = np.random.default_rng(3)
    n, m = 12, 3
    A = 0.5 * rng.normal(size=(n, n)) / np.sqrt(n)
    b = rng.normal(size=n)
    acc = Anderson(m=m)
    x = rng.normal(size=n)
    fs, gs = [], []
    for step in range(10):  # the ring of 3 rows is overwritten twice over
        gx = A @ x + b
        fs.append(gx - x)
        gs.append(gx)
        out = acc.next(x, gx)
        if step == 0:
            assert out is gx
        else:
            k = min(step, m)
            np.testing.assert_allclose(out, _reference_mix(fs, gs, k), rtol=1e-6, atol=1e-9)
        x = out + 1e-3 * rng.normal(size=n)  # not the fixed-point path: every row differs
    acc.reset()  # a single iterate again: the plain image itself
    gx = A @ x + b
    assert acc.next(x, gx) is gx


def _procrustes_misfit(P: np.ndarray, Q: np.ndarray) -> float:
    """Largest distance from ``Q`` of ``P`` after the best 2D rotation and translation."""
    a, b = P - P.mean(0), Q - Q.mean(0)
    U, _, Vt = np.linalg.svd(a.T @ b)
    R = U @ Vt
    if np.linalg.det(R) < 0:
        R = U @ np.diag([1.0, -1.0]) @ Vt
    return float(np.linalg.norm(a @ R - b, axis=1).max())


def test_rigid_misfit_matches_per_panel_procrustes():
    rng = np.random.default_rng(5)
    n, k = 90, 5
    vlab = rng.integers(0, k, n)
    vlab[vlab == 3] = 4  # panel 3 is empty
    vlab[rng.random(n) < 0.1] = -1  # unused vertices
    Q = rng.normal(size=(n, 2))
    P = np.empty_like(Q)
    for p in range(k):  # each panel: a rigid motion plus a panel-sized wobble
        t = rng.uniform(0, 2 * np.pi)
        R = np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]])
        sel = vlab == p
        wobble = 0.01 * (p + 1) * rng.normal(size=(sel.sum(), 2))
        P[sel] = Q[sel] @ R.T + rng.normal(size=2) + wobble
    P[vlab < 0] = 1e6  # unused vertices never count
    got = PanelIndex(vlab, k).rigid_misfit(P, Q)
    want = [_procrustes_misfit(P[vlab == p], Q[vlab == p]) if np.any(vlab == p) else 0.0
            for p in range(k)]  # fmt: skip
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-12)
    assert got[3] == 0.0 and np.all(got[[0, 1, 2, 4]] > 0)


def test_edge_lengths_are_the_norms_bit_for_bit():
    rng = np.random.default_rng(7)
    V = rng.normal(size=(40, 3)) * 10.0 ** rng.integers(-3, 4, (40, 1))
    F = rng.integers(0, 40, (60, 3))
    E = np.stack([F, np.roll(F, -1, axis=1)], axis=2)
    assert np.array_equal(edge_lengths(V, F), np.linalg.norm(V[E[..., 1]] - V[E[..., 0]], axis=2))
    V2 = V[:, :2]  # and in the plane
    ref2 = np.linalg.norm(V2[E[..., 1]] - V2[E[..., 0]], axis=2)
    assert np.array_equal(edge_lengths(V2, F), ref2)
    strain = panel_strain(V, 1.5 * V, F, np.arange(60) % 2, 3)
    np.testing.assert_allclose(strain, [0.5, 0.5, 0.0])


def test_blockwise_solve_with_consecutive_and_interleaved_components():
    rng = np.random.default_rng(9)
    n = 30
    label = np.r_[np.zeros(10, int), np.ones(10, int), np.arange(10) % 2 + 2]  # 2 blocks, then
    A = np.zeros((n, n))  # two interleaved ones
    for c in range(4):
        idx = np.flatnonzero(label == c)
        B = rng.normal(size=(len(idx), len(idx)))
        A[np.ix_(idx, idx)] = B @ B.T + len(idx) * np.eye(len(idx))
    solve = factor(sp.csc_matrix(np.tril(A)), lower=True)
    b = rng.normal(size=(n, 2))
    np.testing.assert_allclose(solve(b), np.linalg.solve(A, b), rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(solve(b[:, 0]), np.linalg.solve(A, b[:, 0]), rtol=1e-10)


def test_blockwise_leaves_an_unsorted_matrix_as_it_was():
    A = np.diag([4.0, 5.0, 6.0, 7.0])
    A[1, 0] = A[0, 1] = 1.0  # components {0, 1} and {2, 3}
    A[3, 2] = A[2, 3] = 2.0
    L = sp.csc_matrix(np.tril(A))
    for j in range(4):  # each column's rows in decreasing order
        lo, hi = L.indptr[j], L.indptr[j + 1]
        L.indices[lo:hi] = L.indices[lo:hi][::-1].copy()
        L.data[lo:hi] = L.data[lo:hi][::-1].copy()
    L.has_sorted_indices = False
    before = (L.indices.copy(), L.data.copy())
    b = np.arange(1.0, 5.0)
    np.testing.assert_allclose(factor(L, lower=True)(b), np.linalg.solve(A, b), rtol=1e-12)
    assert np.array_equal(L.indices, before[0]) and np.array_equal(L.data, before[1])


def test_panel_sizes_are_the_bounding_box_diagonals():
    rng = np.random.default_rng(11)
    vlab = np.array([2, 0, -1, 2, 0, 0, 2, -1])  # panel 1 is empty
    V = rng.normal(size=(8, 2))
    V[vlab < 0] = 1e6  # unused vertices never count
    got = panel_sizes(V, vlab, 3)
    for p in (0, 2):
        box = np.ptp(V[vlab == p], axis=0)
        assert got[p] == np.linalg.norm(box)
    assert got[1] == np.inf  # no vertices: an infinite size, no step ever counts
