"""The stitching's sparse factorisation: CHOLMOD with a shared symbolic analysis."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from ptailor.errors import PtailorError
from ptailor.method import linear
from ptailor.method.linear import factor, shared_symbolic


def spd(n: int, seed: int) -> sp.csc_matrix:
    """A sparse SPD matrix (a path Laplacian plus a positive diagonal) with an explicit zero."""
    rng = np.random.default_rng(seed)
    w = rng.uniform(0.5, 2.0, n - 1)
    w[n // 2] = 0.0  # an explicit zero: still part of the pattern
    i = np.arange(n - 1)
    rows = np.concatenate([i, i + 1, i, i + 1, np.arange(n)])
    cols = np.concatenate([i + 1, i, i, i + 1, np.arange(n)])
    vals = np.concatenate([-w, -w, w, w, rng.uniform(0.1, 1.0, n)])
    return sp.csc_matrix((vals, (rows, cols)), shape=(n, n))


def test_factor_solves_vectors_and_blocks():
    A = spd(50, 0)
    b = np.random.default_rng(1).normal(size=(50, 3))
    solve = factor(A)
    np.testing.assert_allclose(A @ solve(b), b, atol=1e-12)
    np.testing.assert_allclose(A @ solve(b[:, 0]), b[:, 0], atol=1e-12)
    assert solve(b[:, 0]).shape == (50,)


def test_shared_symbolic_reuses_the_analysis_and_keeps_each_solve_exact():
    A, B = spd(40, 0), spd(40, 2)  # one pattern, other values
    b = np.arange(40.0)
    with shared_symbolic():
        sa = factor(A)
        sb = factor(B)
        assert len(linear._SHARED) == 1  # one analysis for both
        np.testing.assert_allclose(B @ sb(b), b, atol=1e-10)
        np.testing.assert_allclose(A @ sa(b), b, atol=1e-10)  # refactors its own values
        np.testing.assert_allclose(B @ sb(b), b, atol=1e-10)
    assert linear._SHARED is None


def test_factor_falls_back_to_lu_when_not_positive_definite():
    A = sp.csc_matrix(np.array([[0.0, 1.0], [1.0, 0.0]]))  # symmetric, indefinite
    np.testing.assert_allclose(factor(A)(np.array([2.0, 3.0])), [3.0, 2.0])
    with pytest.raises(PtailorError, match="cannot be factored"):
        factor(sp.csc_matrix(np.zeros((3, 3))))
