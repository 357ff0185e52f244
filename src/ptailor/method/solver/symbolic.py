"""The symbolic analyses (ordering, supernodes) of CHOLMOD factorisations, the cache that
lets factorisations of one sparsity pattern share one (:class:`SymbolicCache`), and the one
way to set CHOLMOD's process-wide options (:func:`cholmod_options`)."""

from __future__ import annotations

import threading
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp


@dataclass(eq=False)
class Symbolic:
    """One CHOLMOD analysis: the pattern it is for, the matrix and factor objects, and the
    factorisation whose values the factor holds now.

    Attributes
    ----------
    indptr, indices : int arrays
        The pattern (CSC, sorted) of the lower triangle it analyses.
    S : cvxopt.spmatrix
        The lower triangle, values of the factorisation that made it (None once nobody
        refactors it: :func:`ptailor.method.solver.cholesky.factor_part`).
    F : cvxopt CHOLMOD factor
        The analysis, and the values of :attr:`owner`'s factorisation.
    owner : object
        Token of the factorisation whose values ``F`` holds now (None: none yet).
    perm : int array or None
        The ordering asked for (None: CHOLMOD's choice).
    """

    indptr: np.ndarray
    indices: np.ndarray
    S: object  # cvxopt.spmatrix, lower triangle
    F: object  # cvxopt CHOLMOD factor
    owner: object = None
    perm: np.ndarray | None = None  # the ordering asked for (None: CHOLMOD's choice)


@dataclass(eq=False)
class SymbolicCache:
    """Symbolic analyses shared by the factorisations it is given to (``symbolic=`` of
    :func:`ptailor.method.solver.linear.factor` and the functions that call it): matrices of one
    sparsity pattern share one analysis, so the uniform baseline's matrix, which has ours'
    pattern, costs only its numeric factorisation. Solves stay exact: a solve whose factor
    was overwritten by a later factorisation refactors its own values first.

    The caller creates one per garment run and passes it down; without one (None) every
    factorisation analyses its own matrix and keeps no copy of it for later.

    Attributes
    ----------
    analyses : list of Symbolic
        The analyses made so far, in order.
    """

    analyses: list[Symbolic] = field(default_factory=list)

    def __len__(self) -> int:
        return len(self.analyses)

    def __contains__(self, sym: object) -> bool:
        return any(sym is s for s in self.analyses)

    def find(
        self, L: sp.csc_matrix, perm: np.ndarray | None, taken: list[Symbolic]
    ) -> Symbolic | None:
        """The analysis of ``L``'s pattern in the ordering ``perm`` (None: CHOLMOD's
        choice), never one of ``taken``; None where there is none."""
        for sym in self.analyses:
            if any(sym is t for t in taken):
                continue
            if (
                np.array_equal(sym.indptr, L.indptr)
                and np.array_equal(sym.indices, L.indices)
                and (sym.perm is None) == (perm is None)
                and (perm is None or np.array_equal(sym.perm, perm))
            ):
                return sym
        return None

    def add(self, sym: Symbolic) -> None:
        """Keep ``sym`` for the factorisations that come after."""
        self.analyses.append(sym)


#: ``cvxopt.cholmod.options`` is one dict per process: :func:`cholmod_options` sets it,
#: lets CHOLMOD run and restores it under this lock, so a concurrent analysis never runs
#: with another's options
_OPTIONS = threading.Lock()


@contextmanager
def cholmod_options(cholmod, **options: object) -> Iterator[None]:
    """CHOLMOD's process-wide ``options`` updated with ``options`` for the ``with`` block,
    under this module's lock, and restored after it (whatever the block raises).

    Parameters
    ----------
    cholmod : module
        ``cvxopt.cholmod``.
    **options
        The settings (``supernodal``, ``nmethods``, ``postorder``), applied in order.
    """
    with _OPTIONS:
        saved = dict(cholmod.options)
        cholmod.options.update(options)
        try:
            yield
        finally:
            cholmod.options.clear()
            cholmod.options.update(saved)


def cvx_matrix(L: sp.csc_matrix):
    """A CSC matrix (sorted indices) as a cvxopt ``spmatrix``."""
    from cvxopt import matrix, spmatrix

    n = L.shape[0]
    cols = np.repeat(np.arange(n), np.diff(L.indptr))
    return spmatrix(matrix(L.data), matrix(L.indices.astype(int)), matrix(cols), (n, n))


def symbolic_analysis(
    L: sp.csc_matrix,
    cholmod,
    taken: list[Symbolic],
    perm: np.ndarray | None = None,
    symbolic: SymbolicCache | None = None,
) -> Symbolic:
    """The analysis for ``L``'s pattern (in the ordering ``perm``, default CHOLMOD's
    choice): ``symbolic``'s, else a new one (added to ``symbolic``); never one of ``taken``
    (the other blocks of one matrix: two panels of one mesh have one pattern, but each
    needs its own factor)."""
    if symbolic is not None:
        sym = symbolic.find(L, perm, taken)
        if sym is not None:
            return sym
    S = cvx_matrix(L)
    sym = Symbolic(L.indptr, L.indices, S, cholmod_analysis(S, cholmod, perm), perm=perm)
    if symbolic is not None:
        symbolic.add(sym)
    return sym


def cholmod_analysis(S, cholmod, perm: np.ndarray | None):
    """CHOLMOD's symbolic analysis of ``S`` (supernodal): the least fill of three
    orderings, or ``perm`` as it is (no postordering, so its last unknowns stay last)."""
    from cvxopt import matrix

    if perm is None:
        with cholmod_options(cholmod, supernodal=2, nmethods=3):
            return cholmod.symbolic(S, uplo="L")
    with cholmod_options(cholmod, supernodal=2, nmethods=1, postorder=False):
        return cholmod.symbolic(S, p=matrix(perm.astype(int)), uplo="L")
