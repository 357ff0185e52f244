"""How many sparse factorisations a run makes (:func:`counting`, :class:`FactorCount`).

Every factorisation of a matrix goes through :func:`counted` (CHOLMOD's per-block
factorisations of one matrix together count once; a block factored again, because another
matrix of its pattern overwrote its factor or its factor was read out, counts again), so a
caller can see what a run, or one of its stages, costs in factorisations, and whether a
matrix was factored twice (:attr:`FactorCount.repeated`). Nothing is counted outside a
:func:`counting` block.

Inside a :func:`reusing` block (a run's edits), :func:`ptailor.method.solver.linear.factor`
keeps the factors of the last matrices it factored and hands one back for the same matrix
(:func:`kept_solve`, :func:`keep_solve`): the same answer, no second factorisation.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

__all__ = [
    "FactorCount",
    "counted",
    "counted_so_far",
    "counting",
    "keep_solve",
    "kept_solve",
    "reusing",
]


@dataclass(eq=False)
class FactorCount:
    """The factorisations counted so far.

    Attributes
    ----------
    total : int
        Numeric factorisations of a matrix (one per matrix factored, one more per block
        factored again).
    repeated : int
        Those of a matrix (pattern and values) already factored inside the same
        :func:`counting` block: the work a reused factor would have saved.
    """

    total: int = 0
    repeated: int = 0
    seen: set[tuple] = field(default_factory=set, repr=False)


_ACTIVE: ContextVar[FactorCount | None] = ContextVar("ptailor_factor_count", default=None)
_KEPT: ContextVar[OrderedDict | None] = ContextVar("ptailor_kept_factors", default=None)


@contextmanager
def counting() -> Iterator[FactorCount]:
    """Count the factorisations made inside the block (this thread's; nested blocks each
    count their own, the outer ones not).

    Yields
    ------
    FactorCount
        Filled as factorisations happen; read it during or after the block.
    """
    count = FactorCount()
    token = _ACTIVE.set(count)
    try:
        yield count
    finally:
        _ACTIVE.reset(token)


def counted(A: sp.spmatrix | None = None, *, again: bool = False) -> None:
    """Note one factorisation of ``A`` (its pattern and values identify it; None: a
    matrix not compared) in the active :class:`FactorCount`, if any.

    Parameters
    ----------
    A : (N, N) sparse matrix, optional
        The matrix factored (as factored: its lower triangle where only that is read).
    again : bool, keyword-only
        A factorisation of a matrix factored before (a block refactored).
    """
    count = _ACTIVE.get()
    if count is None:
        return
    count.total += 1
    if again:
        count.repeated += 1
        return
    if A is None:
        return
    A = sp.csc_matrix(A)
    key = (A.shape, A.nnz, _fingerprint(A))
    if key in count.seen:
        count.repeated += 1
    count.seen.add(key)


@contextmanager
def reusing() -> Iterator[None]:
    """Keep, inside the block, the factors of the last ``REUSE_FACTORS`` matrices
    :func:`ptailor.method.solver.linear.factor` factored, for :func:`kept_solve` (they go
    with the block)."""
    token = _KEPT.set(OrderedDict())
    try:
        yield
    finally:
        _KEPT.reset(token)


def kept_solve(L: sp.csc_matrix) -> tuple[Callable | None, tuple | None]:
    """The kept solve function of the matrix ``L`` (its lower triangle, as factored) and
    its key; ``(None, key)`` when none is kept (then factor it and :func:`keep_solve` it);
    ``(None, None)`` outside a :func:`reusing` block (nothing is kept there)."""
    kept = _KEPT.get()
    if kept is None:
        return None, None
    key = (L.shape, L.nnz, _fingerprint(L))
    if key in kept:
        kept.move_to_end(key)
        return kept[key], key
    return None, key


def keep_solve(key: tuple | None, solve: Callable) -> Callable:
    """``solve`` kept under ``key`` (:func:`kept_solve`'s), the oldest kept one dropped
    beyond ``REUSE_FACTORS``; returned as it is (nothing kept for a ``None`` key)."""
    from ptailor.method import tolerances as method_tol

    kept = _KEPT.get()
    if kept is None or key is None:
        return solve
    kept[key] = solve
    while len(kept) > method_tol.REUSE_FACTORS:
        kept.popitem(last=False)
    return solve


def counted_so_far() -> int:
    """The active :class:`FactorCount`'s ``total`` (0 outside a :func:`counting` block):
    read before and after a stage, the stage's factorisations."""
    count = _ACTIVE.get()
    return 0 if count is None else count.total


def _fingerprint(A: sp.csc_matrix) -> bytes:
    """A 128-bit BLAKE2 digest of ``A``'s pattern and values (sorted CSC): what tells two
    factored matrices apart, a few milliseconds a million entries."""
    import hashlib

    A = A.sorted_indices() if not A.has_sorted_indices else A
    h = hashlib.blake2b(digest_size=16)
    for part in (A.indptr.astype(np.int64), A.indices.astype(np.int64), A.data):
        h.update(np.ascontiguousarray(part))
    return h.digest()
