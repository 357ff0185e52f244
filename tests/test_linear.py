"""The stitching's sparse factorisation: CHOLMOD with a shared symbolic analysis."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from ptailor.errors import PtailorError
from ptailor.method.solver import SymbolicCache, factor
from ptailor.method.solver.cholesky import superlu_solver
from ptailor.method.solver.seam_block import schur_inverses, seam_block
from ptailor.method.solver.seam_factor import SeamFactor


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
    solve = factor(A, lower=True)
    np.testing.assert_allclose(A @ solve(b), b, atol=1e-12)
    np.testing.assert_allclose(A @ solve(b[:, 0]), b[:, 0], atol=1e-12)
    assert solve(b[:, 0]).shape == (50,)


def test_a_symbolic_cache_reuses_the_analysis_and_keeps_each_solve_exact():
    A, B = spd(40, 0), spd(40, 2)  # one pattern, other values
    b = np.arange(40.0)
    cache = SymbolicCache()
    sa = factor(A, symbolic=cache)
    sb = factor(B, symbolic=cache)
    assert len(cache) == 1  # one analysis for both
    np.testing.assert_allclose(B @ sb(b), b, atol=1e-10)
    np.testing.assert_allclose(A @ sa(b), b, atol=1e-10)  # refactors its own values
    np.testing.assert_allclose(B @ sb(b), b, atol=1e-10)


def test_analyses_are_shared_only_through_the_cache_passed():
    """Two garments flattened in threads of one process (a Dask worker) never share an
    analysis: nothing is shared but the cache a caller passes (no hidden state)."""
    import threading

    seen: dict[int, int] = {}
    barrier = threading.Barrier(2)

    def run(k: int) -> None:
        A = spd(60 + k, k)  # different patterns
        cache = SymbolicCache()
        solve = factor(A, symbolic=cache)
        barrier.wait()  # both at once
        seen[k] = len(cache)
        b = np.ones(60 + k)
        np.testing.assert_allclose(A @ solve(b), b, atol=1e-10)
        barrier.wait()

    threads = [threading.Thread(target=run, args=(k,)) for k in (0, 1)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert seen == {0: 1, 1: 1}


def test_factor_falls_back_to_lu_when_not_positive_definite():
    A = sp.csc_matrix(np.array([[0.0, 1.0], [1.0, 0.0]]))  # symmetric, indefinite
    np.testing.assert_allclose(factor(A)(np.array([2.0, 3.0])), [3.0, 2.0])
    with pytest.raises(PtailorError, match="cannot be factored"):
        factor(sp.csc_matrix(np.zeros((3, 3))))


@pytest.mark.parametrize("coupled", [False, True])
def test_seam_block_from_the_schur_complement_matches_back_substitution(coupled):
    from ptailor.geometry.triangles import edge_matrices
    from ptailor.method.ease import seam_ease
    from ptailor.method.flatten import central_vertices
    from ptailor.method.operators import asap_rows, stitch_matrix
    from ptailor.model.garment import panel_labels, panels, vertex_labels
    from ptailor.samples import lantern_sleeve

    g = lantern_sleeve()
    plist = panels(g)
    n, m = len(g.V2), len(g.F2)
    vlab = vertex_labels(plist, n)
    ease = seam_ease(g.F3, g.F2, g.V2, face_panel=panel_labels(plist, m))
    pin_w = np.zeros(n)
    pin_w[central_vertices(g.V2, vlab, len(plist))] = 1000.0
    targets = edge_matrices(g.V2, g.F2)
    area = 0.5 * np.abs(np.linalg.det(targets))
    B = asap_rows(g.V2, g.F2, np.arange(m)) if coupled else None
    A = stitch_matrix(g.F2, targets, area, pin_w, B, 1000.0)
    solve = factor(A, lower=True)

    def solve_many(rhs):
        if coupled:
            return solve(rhs)
        c = rhs.shape[1]
        sol = solve(np.concatenate([rhs[:n], rhs[n:]], axis=1))
        return np.concatenate([sol[:, :c], sol[:, c:]], axis=0)

    fast = seam_block(solve_many, ease, vlab, n, coupled=coupled, A=A)
    slow = seam_block(solve_many, ease, vlab, n, coupled=coupled)
    np.testing.assert_array_equal(fast.U, slow.U)
    assert len(fast.blocks) == len(slow.blocks) == (len(plist) if coupled else 2 * len(plist))
    for (i, G), (j, H) in zip(fast.blocks, slow.blocks, strict=True):
        np.testing.assert_array_equal(i, j)
        np.testing.assert_allclose(G, H, rtol=1e-9, atol=1e-12 * np.abs(H).max())
    C = ease.rows(g.V2)[:, fast.U]
    np.testing.assert_allclose(fast.schur(C), slow.schur(C), rtol=1e-9, atol=1e-12)


def test_factor_of_a_lower_triangle_solves_the_symmetric_matrix():
    A = spd(30, 3)
    L = sp.tril(A, format="csc")
    b = np.linspace(-1.0, 2.0, 30)
    np.testing.assert_allclose(A @ factor(L, lower=True)(b), b, atol=1e-12)
    np.testing.assert_allclose(A @ superlu_solver(L, lower=True)(b), b, atol=1e-12)


def test_without_cvxopt_superlu_and_back_substitution_serve(monkeypatch):
    import sys

    A = spd(30, 4)
    b = np.linspace(0.0, 1.0, 30)
    expected = factor(A)(b)
    monkeypatch.setitem(sys.modules, "cvxopt", None)  # import cvxopt fails
    np.testing.assert_allclose(factor(A)(b), expected, rtol=1e-10)
    assert schur_inverses(A, np.array([3, 7]), [np.array([0, 1])]) is None
    with pytest.raises(PtailorError, match="cannot be factored"):
        factor(sp.csc_matrix(np.zeros((3, 3))))


def scattered_blocks(seed: int) -> tuple[sp.csc_matrix, int]:
    """Two SPD blocks on interleaved unknowns plus three isolated unknowns (identity rows:
    the vertices no triangle uses), as the stitching matrix of two panels; and how many
    blocks the factorisation should see (two components, the singletons as one)."""
    M = sp.block_diag([spd(30, seed), spd(20, seed + 1), 2.0 * sp.eye(3)], format="csc")
    q = np.random.default_rng(seed).permutation(M.shape[0])
    A = sp.csc_matrix(M[q][:, q])
    assert A.nnz == M.nnz  # the explicit zeros kept: each path one component
    return A, 3


def test_factor_by_component_matches_the_whole_solve():
    A, blocks = scattered_blocks(3)
    b = np.random.default_rng(4).normal(size=(A.shape[0], 2))
    expected = np.linalg.solve(A.toarray(), b)
    for solve in (factor(A), factor(sp.tril(A, format="csc"), lower=True)):
        np.testing.assert_allclose(solve(b), expected, rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(solve(b[:, 1]), expected[:, 1], rtol=1e-10, atol=1e-12)
    cache = SymbolicCache()
    sa = factor(A, symbolic=cache)
    sb = factor(2.0 * A, symbolic=cache)  # same pattern: every block's analysis is shared
    assert len(cache) == blocks
    np.testing.assert_allclose(sa(b), expected, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(sb(b), 0.5 * expected, rtol=1e-10, atol=1e-12)


def test_factor_by_component_falls_back_to_lu_for_an_indefinite_block():
    A, _ = scattered_blocks(5)
    A = A.tolil()
    i = int(np.flatnonzero(A.diagonal() == 2.0)[0])  # an isolated unknown
    A[i, i] = -2.0  # that block is no longer positive definite: LU solves the whole
    A = sp.csc_matrix(A)
    b = np.random.default_rng(6).normal(size=A.shape[0])
    np.testing.assert_allclose(factor(A)(b), np.linalg.solve(A.toarray(), b), rtol=1e-9)


def test_blocks_of_one_pattern_keep_their_own_factors(monkeypatch):
    """Two panels of one mesh (front and back) give blocks of one pattern: each keeps its
    own factor, so solving does not refactor one over the other."""
    from cvxopt import cholmod

    A = sp.block_diag([spd(20, 1), spd(20, 2)], format="csc")
    b = np.random.default_rng(7).normal(size=40)
    calls = []
    numeric = cholmod.numeric
    monkeypatch.setattr(cholmod, "numeric", lambda *a: calls.append(1) or numeric(*a))
    cache = SymbolicCache()
    solve = factor(A, symbolic=cache)
    assert len(cache) == 2
    for _ in range(3):
        np.testing.assert_allclose(A @ solve(b), b, atol=1e-10)
    assert len(calls) == 2  # one numeric factorisation per block, none per solve


def test_equal_blocks_share_one_factor_and_solve_together(monkeypatch):
    """x and y of a panel the as-similar-as-possible rows leave apart are two equal blocks
    of the coupled matrix: factored once and solved as two columns, with the same answer
    as separate factors; a block of equal pattern but other values keeps its own."""
    from cvxopt import cholmod

    a, b2 = spd(30, 3), spd(30, 4)
    A = sp.block_diag([a, b2, a], format="csc")  # blocks 0 and 2 equal, 1 not
    rhs = np.random.default_rng(8).normal(size=(90, 3))
    calls = []
    numeric = cholmod.numeric
    monkeypatch.setattr(cholmod, "numeric", lambda *x: calls.append(1) or numeric(*x))
    solve = factor(A)
    assert len(calls) == 2
    expected = np.linalg.solve(A.toarray(), rhs)
    np.testing.assert_allclose(solve(rhs), expected, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(solve(rhs[:, 0]), expected[:, 0], rtol=1e-10, atol=1e-12)


def test_seam_factor_splits_the_constrained_solve_exactly():
    """With the seam unknowns last in each block's factor: the whole solve, the seam values
    from the forward substitution alone, the solve less a seam correction from the same
    forward substitution, and the seam block of the inverse all match dense algebra; equal
    blocks with the same seam unknowns share one factor."""
    a, b2 = spd(30, 3), spd(40, 4)
    A = sp.block_diag([a, b2, a, 2.0 * sp.identity(3)], format="csc")
    N = A.shape[0]
    Ai = np.linalg.inv(A.toarray())
    rng = np.random.default_rng(9)
    b = rng.normal(size=(N, 2))
    for last, parts in ((rng.choice(N, 25, replace=False), 4), (np.r_[1, 5, 7, 71, 75, 77], 3)):
        f = SeamFactor(sp.tril(A, format="csc"), last)
        assert len(f._parts) == parts
        E = np.zeros((N, len(last)))
        E[last, np.arange(len(last))] = 1.0
        w = rng.normal(size=(len(last), 2))
        np.testing.assert_allclose(f(b), Ai @ b, atol=1e-12)
        G = np.zeros((len(last), len(last)))
        for idx, Gb in f.blocks():
            G[np.ix_(idx, idx)] = Gb
        np.testing.assert_allclose(G, Ai[np.ix_(last, last)], atol=1e-12)
        Z = f.forward(b)
        np.testing.assert_allclose(f.seam_values(Z, 2), (Ai @ b)[last], atol=1e-12)
        np.testing.assert_allclose(f.finish(Z, 2, w), Ai @ (b - E @ w), atol=1e-12)
        np.testing.assert_allclose(f.finish(Z, 2), Ai @ b, atol=1e-12)  # Z unchanged


def test_seam_factor_refuses_an_indefinite_block():
    A = spd(20, 5).tolil()
    A[3, 3] = -5.0
    with pytest.raises(ArithmeticError):
        SeamFactor(sp.tril(sp.csc_matrix(A), format="csc"), np.array([0, 1]))


def test_stitch_matrix_holds_no_triplet_sized_arrays():
    """The assembled matrix's arrays are its own size, not views of the triplets' (each
    inner edge comes twice), which would stay resident through the whole solve."""
    from ptailor.method.operators import stitch_matrix

    F = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 4]])
    targets = np.tile(np.eye(2), (3, 1, 1))
    A = stitch_matrix(F, targets, np.ones(3), np.ones(5))
    for arr in (A.data, A.indices):
        assert arr.base is None or np.asarray(arr.base).size == A.nnz
