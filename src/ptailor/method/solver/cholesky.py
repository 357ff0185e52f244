"""Sparse Cholesky building blocks of the stitching's solves: a matrix cut into the
connected blocks of its pattern, one CHOLMOD factorisation per block (its symbolic
analysis from :mod:`ptailor.method.solver.symbolic`), and SuperLU where CHOLMOD cannot."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.sparse as sp

from ptailor.method.solver.count import counted
from ptailor.method.solver.symbolic import (
    Symbolic,
    SymbolicCache,
    cholmod_analysis,
    symbolic_analysis,
)


def check_finite(A: sp.csc_matrix) -> None:
    """Refuse a matrix with a non-finite stored entry before it is factored.

    Raises
    ------
    NumericError
        Degenerate target triangles or extreme flatten weights made an entry non-finite.
    """
    from ptailor.errors import NumericError

    if not np.all(np.isfinite(A.data)):
        raise NumericError(
            "the sparse system to factor has non-finite entries (degenerate target "
            "triangles or extreme flatten weights)"
        )


def components(L: sp.csc_matrix) -> tuple[list[np.ndarray], np.ndarray]:
    """The connected components of ``L``'s pattern (explicit zeros count), singletons
    together as one diagonal block, and each unknown's position in its component."""
    from scipy.sparse.csgraph import connected_components

    ones = np.ones(len(L.indices), dtype=np.int8)
    k, label = connected_components(sp.csc_matrix((ones, L.indices, L.indptr), L.shape), False)
    size = np.bincount(label, minlength=k)
    label = np.where(size[label] > 1, label, k)
    groups = groups_of(label)
    local = np.empty(L.shape[0], dtype=np.int32)
    for g in groups:
        local[g] = np.arange(len(g), dtype=np.int32)
    return groups, local


def equal_matrices(a: sp.csc_matrix, b: sp.csc_matrix) -> bool:
    """The same pattern and values (sorted CSC)."""
    return (
        np.array_equal(a.indptr, b.indptr)
        and np.array_equal(a.indices, b.indices)
        and np.array_equal(a.data, b.data)
    )


def column_block(L: sp.csc_matrix, g: slice | np.ndarray, local: np.ndarray) -> sp.csc_matrix:
    """The columns ``g`` of ``L`` over their own rows (``local``: each row's position in
    its component): for a slice, cut from ``L``'s arrays (the same entries in the same
    order as indexing gives, without its copies; views: only of sorted columns, which
    the factorisation never sorts in place)."""
    if isinstance(g, slice) and L.has_sorted_indices:
        a, b = L.indptr[g.start], L.indptr[g.stop]
        k = g.stop - g.start
        ptr = L.indptr[g.start : g.stop + 1] - a
        return sp.csc_matrix((L.data[a:b], L.indices[a:b] - g.start, ptr), shape=(k, k))
    if isinstance(g, slice):
        g = np.arange(g.start, g.stop)
    C = L[:, g]
    return sp.csc_matrix((C.data, local[C.indices], C.indptr), shape=(len(g), len(g)))


def as_slice(g: np.ndarray) -> slice | np.ndarray:
    """``g`` (increasing indices) as a slice when they are consecutive, else ``g``."""
    if len(g) and g[-1] - g[0] == len(g) - 1:
        return slice(int(g[0]), int(g[-1]) + 1)
    return g


def groups_of(label: np.ndarray) -> list[np.ndarray]:
    """Positions of each label's members, labels in increasing order."""
    order = np.argsort(label, kind="stable")
    cuts = np.flatnonzero(np.diff(label[order])) + 1
    return np.split(order, cuts)


def factor_part(
    L: sp.csc_matrix,
    cholmod,
    taken: list[Symbolic] | None = None,
    perm=None,
    symbolic: SymbolicCache | None = None,
) -> tuple[Callable[..., np.ndarray], Callable[[], object]]:
    """CHOLMOD's solve function of ``L`` (lower triangle), ``solve(b, sys=0)``
    (CHOLMOD's ``sys``: 0 the whole solve, 4 and 5 ``L`` and ``L^T``, 7 and 8 the
    permutation and its inverse), in the ordering ``perm`` (default CHOLMOD's), and
    ``getfactor()``: the factor ``L`` as a cvxopt sparse matrix (with a ``perm``, the
    matrix is kept for it: CHOLMOD's factor turns symbolic when read out, and is factored
    again). The analysis comes from ``symbolic`` where it holds one of the pattern."""
    from cvxopt import matrix

    L.sort_indices()
    data = L.data
    taken = [] if taken is None else taken
    sym = symbolic_analysis(L, cholmod, taken, perm, symbolic)
    taken.append(sym)
    token = object()

    def refactor() -> None:
        if sym.owner is not token:  # new, or another factorisation of this pattern came since
            if sym.owner is not None:
                sym.S.V = matrix(data)
                counted(again=True)  # this block's values factored once more
            cholmod.numeric(sym.S, sym.F)
            sym.owner = token

    refactor()
    if perm is None and (symbolic is None or sym not in symbolic):
        # nobody else refactors it: the factor alone serves the solves (the matrix's
        # copies go: 16 MB at 300k triangles)
        sym.S, data = None, None

    def solve(b: np.ndarray, sys: int = 0) -> np.ndarray:
        refactor()
        B = matrix(np.asarray(b, dtype=float).reshape(len(b), -1, order="F"))
        cholmod.solve(sym.F, B, sys=sys)
        return np.asarray(B).reshape(np.shape(b))

    def getfactor():
        refactor()  # this matrix's values in the factor and in sym.S
        Lf = cholmod.getfactor(sym.F)
        # reading it out leaves CHOLMOD's factor unusable: analysed and factored again
        # (in the same ordering: the same factor)
        sym.F = cholmod_analysis(sym.S, cholmod, perm)
        cholmod.numeric(sym.S, sym.F)
        counted(again=True)
        return Lf

    return solve, getfactor


def superlu_solver(A: sp.csc_matrix, *, lower: bool = False):
    """SuperLU's solve function for ``A`` (symmetric mode; ``lower``: ``A`` is the lower
    triangle of the symmetric matrix)."""
    from scipy.sparse.linalg import splu

    from ptailor.errors import NumericError

    if lower:
        A = sp.csc_matrix(A + sp.tril(A, -1).T)
    counted(sp.tril(A, format="csc"))

    try:
        lu = splu(
            A,
            permc_spec="MMD_AT_PLUS_A",
            diag_pivot_thresh=0.0,
            options={"SymmetricMode": True},
        )
    except RuntimeError as exc:
        # SuperLU has no exception type of its own: a singular matrix is a RuntimeError
        # "Factor is exactly singular" (scipy's gstrf wrapper, info <= n), as is any abort
        # inside SuperLU. Only the first is the matrix's; the others pass (a bug), so the
        # message decides here, for this one call.
        if "singular" not in str(exc):
            raise
        raise NumericError(
            f"the sparse system cannot be factored (SuperLU: {exc}): degenerate target "
            "triangles or extreme flatten weights"
        ) from None
    return lu.solve
