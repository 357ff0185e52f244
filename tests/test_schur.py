"""method.schur: the block of A^-1 on chosen unknowns from a seam-last Cholesky."""

import numpy as np
import pytest
import scipy.sparse as sp

pytest.importorskip("cvxopt")

from ptailor.errors import PtailorError
from ptailor.method.schur import schur_inverse


def _spd(n: int, seed: int) -> sp.csc_matrix:
    """A sparse SPD matrix: a random graph Laplacian plus a positive diagonal."""
    rng = np.random.default_rng(seed)
    i = rng.integers(0, n, 4 * n)
    j = rng.integers(0, n, 4 * n)
    W = sp.coo_matrix((rng.uniform(0.1, 1.0, 4 * n), (i, j)), shape=(n, n))
    W = (W + W.T).tocsr()
    W.setdiag(0)
    Lap = sp.diags(np.asarray(W.sum(axis=1)).ravel()) - W
    return sp.csc_matrix(Lap + sp.diags(rng.uniform(0.01, 0.1, n)))


def test_matches_the_dense_inverse():
    A = _spd(300, 0)
    U = np.random.default_rng(1).choice(300, 40, replace=False)
    G = schur_inverse(A, U)
    Ginv = np.linalg.inv(A.toarray())[np.ix_(U, U)]
    assert np.allclose(G, Ginv, rtol=1e-10, atol=1e-12 * np.abs(Ginv).max())
    assert np.allclose(G, G.T)


def test_block_diagonal_labels_give_the_within_block_inverse():
    A1, A2 = _spd(120, 2), _spd(150, 3)
    A = sp.csc_matrix(sp.block_diag([A1, A2]))
    rng = np.random.default_rng(4)
    U = np.concatenate(
        [rng.choice(120, 15, replace=False), 120 + rng.choice(150, 20, replace=False)]
    )
    U = rng.permutation(U)  # labels interleaved in U's order
    lab = (U >= 120).astype(int)
    G = schur_inverse(A, U, block=lab)
    full = np.linalg.inv(A.toarray())[np.ix_(U, U)]
    assert np.allclose(G, full, rtol=1e-10, atol=1e-12 * np.abs(full).max())
    assert np.all(G[np.ix_(lab == 0, lab == 1)] == 0.0)


def test_all_unknowns_and_none():
    A = _spd(50, 5)
    assert np.allclose(schur_inverse(A, np.arange(50)), np.linalg.inv(A.toarray()))
    assert schur_inverse(A, np.zeros(0, dtype=int)).shape == (0, 0)


def test_not_positive_definite_is_a_ptailor_error_and_options_are_restored():
    from cvxopt import cholmod

    before = dict(cholmod.options)
    A = sp.csc_matrix(np.array([[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]]))
    with pytest.raises(PtailorError, match="not positive definite"):
        schur_inverse(A, np.array([0]))
    assert dict(cholmod.options) == before


def test_inputs_are_not_mutated():
    A = _spd(80, 6)
    data = A.data.copy()
    U = np.array([5, 3, 70])
    schur_inverse(A, U)
    assert np.array_equal(A.data, data)
    assert list(U) == [5, 3, 70]
