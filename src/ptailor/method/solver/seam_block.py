"""The seam unknowns' block of the stitching matrix's inverse (:class:`SeamBlock`), and
the small Schur-complement products of the seam constraints through it."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from ptailor.method import tolerances as method_tol
from ptailor.method.ease import SeamEase
from ptailor.method.solver.cholesky import groups_of
from ptailor.method.solver.count import counted
from ptailor.method.solver.symbolic import cholmod_options, cvx_matrix


@dataclass(frozen=True)
class SeamBlock:
    """The seam unknowns' block of ``A^-1``, dense per block of ``A`` (zero across).

    Attributes
    ----------
    U : (2q,) int array
        The seam unknowns (indices into ``[x; y]``).
    blocks : list of ((k,) int array, (k, k) float array)
        Positions in ``U`` of one block's unknowns, and ``A^-1`` restricted to them.
    """

    U: np.ndarray
    blocks: list[tuple[np.ndarray, np.ndarray]]

    @cached_property
    def _by_block(self) -> tuple[np.ndarray, np.ndarray]:
        """Positions in ``U`` block after block, and each block's range in that order."""
        order = np.concatenate([idx for idx, _ in self.blocks]) if self.blocks else self.U[:0]
        bounds = np.cumsum([0] + [len(idx) for idx, _ in self.blocks])
        return order, bounds

    @cached_property
    def _local(self) -> np.ndarray:
        """Position in ``U`` of each unknown (-1 off the seams), ``(max(U) + 1,)`` int."""
        local = np.full(int(self.U.max(initial=-1)) + 1, -1, dtype=np.int64)
        local[self.U] = np.arange(len(self.U))
        return local

    def restrict(self, C: sp.spmatrix) -> sp.csr_matrix:
        """Rows over all unknowns ``[x; y]`` that touch only seam unknowns, as rows over
        ``U`` (``C[:, U]``, by renumbering the columns: no column search)."""
        C = sp.csr_matrix(C)
        cols = self._local[C.indices]
        return sp.csr_matrix((C.data, cols, C.indptr), shape=(C.shape[0], len(self.U)))

    def products(self, C: sp.spmatrix) -> tuple[int, list]:
        """Per block, the rows of ``C (r, 2q)`` over ``U`` that touch the block, cut to its
        unknowns, and their product with the block's ``G``: the pieces of :meth:`schur`,
        kept to pair the same rows with others without multiplying them again.

        Returns
        -------
        (r, list of ((r_b,) int array, (r_b, k_b) sparse, (r_b, k_b) float array))
            The rows of ``C``, and per block with rows the rows' positions, the rows and
            their product (a row touches few blocks: the products are ``r_b x k_b``, not
            ``r x k_b``, 60 MB apiece at 300,000 triangles)."""
        order, bounds = self._by_block
        Cb_all = sp.csc_matrix(C)[:, order]  # block after block: each block is a slice
        out = []
        for k, (_, G) in enumerate(self.blocks):
            Cb = Cb_all[:, bounds[k] : bounds[k + 1]]
            if not Cb.nnz:
                continue
            rows = np.unique(Cb.indices)  # CSC: its row indices, renumbered onto ``rows``
            Cr = sp.csc_matrix(
                (Cb.data, np.searchsorted(rows, Cb.indices), Cb.indptr),
                shape=(len(rows), Cb.shape[1]),
            )
            out.append((k, rows, Cr, Cr @ G))
        return C.shape[0], out

    def schur(self, C, D=None, *, out: np.ndarray | None = None) -> np.ndarray:
        """``C G D^T`` (default ``D = C``) for rows ``C (r, 2q)`` and ``D (t, 2q)`` over
        ``U`` (sparse, or their :meth:`products`), ``(r, t)`` dense; added to ``out`` (a
        zero view of a larger matrix, say) where given."""
        Cp = C if isinstance(C, tuple) else self.products(C)
        Dp = Cp if D is None else D if isinstance(D, tuple) else self.products(D)
        M = np.zeros((Cp[0], Dp[0])) if out is None else out
        d_by_block = {k: (rows, DG) for k, rows, _, DG in Dp[1]}
        for k, rows, Cr, _ in Cp[1]:
            if k in d_by_block:
                drows, DG = d_by_block[k]
                M[np.ix_(rows, drows)] += Cr @ DG.T  # G is symmetric: C G D^T = C (D G)^T
        return M


def seam_block(
    solve_many,
    ease: SeamEase,
    vertex_panel: np.ndarray,
    n: int,
    *,
    coupled: bool,
    A: sp.spmatrix | None = None,
) -> SeamBlock:
    """The seam vertices' block of ``A^-1``, computed once per factorisation.

    With ``A`` (and CHOLMOD): from a Cholesky factorisation that eliminates the seam
    unknowns last, where the trailing block of the factor is the Cholesky factor of the
    Schur complement ``S`` onto them and ``A^-1`` restricted to them is ``S^-1`` (one
    factorisation and a dense inverse per block, instead of a back-substitution per seam
    unknown). Otherwise by back-substitution: ``A`` is block diagonal by panel (and by
    coordinate when x and y decouple), so one right-hand side serves one seam unknown of
    every block at once.

    Parameters
    ----------
    solve_many : callable
        ``(2n, c) -> (2n, c)``: ``A^-1`` applied to columns over unknowns ``[x; y]``.
    ease : SeamEase
    vertex_panel : (n,) int array
        Panel of each pattern vertex.
    n : int
    coupled : bool
        Whether ``A`` couples x and y (the as-similar-as-possible term).
    A : sparse matrix, optional
        The factored matrix (``2n x 2n`` when coupled, else ``n x n``).

    Returns
    -------
    SeamBlock
    """
    verts = ease.vertices()
    U = np.concatenate([verts, verts + n])
    q = len(verts)
    pan = vertex_panel[verts].astype(np.int64)
    if coupled:
        groups = groups_of(np.concatenate([pan, pan]))
        unknowns = U
    else:  # one n x n block per panel serves x and y
        groups = groups_of(pan)
        unknowns = verts
    inv = schur_inverses(A, unknowns, groups) if A is not None else None
    if inv is None:
        inv = _solved_inverses(solve_many, U if coupled else U[:q], groups, 2 * n)
    blocks = list(zip(groups, inv, strict=True))
    if not coupled:
        blocks += [(g + q, G) for g, G in blocks]
    return SeamBlock(U=U, blocks=blocks)


def _solved_inverses(solve_many, U: np.ndarray, groups, size: int) -> list[np.ndarray]:
    """Per group, ``A^-1`` on its unknowns by back-substitution: right-hand side ``j``
    holds the ``j``-th unknown of every group (the groups are separate blocks of ``A``)."""
    slot = np.empty(len(U), dtype=np.int64)
    for g in groups:
        slot[g] = np.arange(len(g))
    out = [np.empty((len(g), len(g))) for g in groups]
    n_slots = max(len(g) for g in groups)
    for s0 in range(0, n_slots, method_tol.SEAM_BLOCK_CHUNK):  # chunks of right-hand sides
        s1 = min(s0 + method_tol.SEAM_BLOCK_CHUNK, n_slots)
        pick = (slot >= s0) & (slot < s1)
        rhs = np.zeros((size, s1 - s0))
        rhs[U[pick], slot[pick] - s0] = 1.0
        sol = solve_many(rhs)
        for g, G in zip(groups, out, strict=True):
            e = min(s1, len(g))
            if e > s0:
                G[:, s0:e] = sol[U[g], : e - s0]
    return [0.5 * (G + G.T) for G in out]


def schur_inverses(A: sp.spmatrix, unknowns: np.ndarray, groups) -> list[np.ndarray] | None:
    """Per group, ``A^-1`` on its unknowns from the Schur complements of a CHOLMOD
    factorisation that orders them last (:func:`seam_block`'s fast path).

    Parameters
    ----------
    A : (N, N) sparse matrix
        Symmetric positive definite (its lower triangle is read).
    unknowns : (k,) int array
        The seam unknowns, rows of ``A``.
    groups : list of int arrays
        Positions in ``unknowns`` of each separate block's unknowns.

    Returns
    -------
    list of (k_g, k_g) float arrays or None
        None without cvxopt or where the factorisation fails.
    """
    try:
        from cvxopt import amd, cholmod, matrix
    except ImportError:  # pragma: no cover - cvxopt is a dependency
        return None
    from scipy.linalg import lapack

    L = sp.tril(sp.csc_matrix(A), format="csc")
    L.sort_indices()
    counted(L)
    N = L.shape[0]
    S = cvx_matrix(L)
    p0 = np.asarray(amd.order(S)).ravel()
    last = np.zeros(N, dtype=bool)
    last[unknowns] = True
    p = np.concatenate([p0[~last[p0]], unknowns[np.concatenate(groups)]])
    with cholmod_options(cholmod, supernodal=2, nmethods=1):  # this order, not AMD's
        try:
            F = cholmod.symbolic(S, p=matrix(p.astype(int)), uplo="L")
            cholmod.numeric(S, F)
        except (ArithmeticError, ValueError):
            return None
    pos = matrix(np.arange(N, dtype=float))
    cholmod.solve(F, pos, sys=8)  # where each unknown sits in the (postordered) factor
    pos = np.rint(np.asarray(pos).ravel()).astype(np.int64)
    Lf = cholmod.getfactor(F)
    out = []
    for g in groups:
        ib = pos[unknowns[g]]
        o = np.argsort(ib)
        idx = matrix(ib[o].astype(int))
        T = np.array(matrix(Lf[idx, idx]))  # Cholesky factor of the Schur complement
        Ginv, info = lapack.dpotri(T, lower=1)
        if info != 0 or not np.all(np.isfinite(Ginv)):
            return None
        Ginv = np.tril(Ginv) + np.tril(Ginv, -1).T
        back = np.empty_like(o)
        back[o] = np.arange(len(o))
        out.append(Ginv[np.ix_(back, back)])
    return out
