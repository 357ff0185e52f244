"""A CHOLMOD factorisation that eliminates the seam unknowns last (:class:`SeamFactor`):
the constrained step's two solves in about the time of one, and the seam unknowns' block
of the inverse from the trailing factor."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ptailor.method.solver.cholesky import (
    as_slice,
    check_finite,
    column_block,
    components,
    equal_matrices,
    factor_part,
)
from ptailor.method.solver.count import counted
from ptailor.method.solver.symbolic import Symbolic, SymbolicCache, cvx_matrix


class SeamFactor:
    """``A^-1`` from CHOLMOD factors that eliminate the seam unknowns last, so that the
    seam step's two solves cost about one.

    The matrix is factored per connected block (:func:`factor`'s blocks; equal blocks
    once, solved together), each in AMD's order with its seam unknowns moved to the end:
    ``P A P^T = L L^T`` with the trailing block ``T`` of ``L`` the Cholesky factor of the
    Schur complement onto the seam unknowns. Then ``A^-1`` restricted to them is
    ``T^-T T^-1`` (:meth:`blocks`), the seam values of ``A^-1 b`` follow from the forward
    substitution ``z = L^-1 P b`` by ``T^-T z_s`` (:meth:`seam_values`), and
    ``A^-1 (b - E w)`` for ``w`` on the seam unknowns from the same ``z`` by
    ``z_s -= T^-1 w`` and one back-substitution (:meth:`finish`): the constrained step
    ``x = A^-1 b - A^-1 C^T nu`` with ``nu`` from ``C A^-1 b`` takes one forward and one
    back-substitution instead of two of each.

    Parameters
    ----------
    L : (N, N) sparse matrix
        Lower triangle of the symmetric positive definite matrix.
    last : (s,) int array
        The seam unknowns (distinct), in the order :meth:`seam_values` uses.
    symbolic : SymbolicCache, optional
        Symbolic analyses to share with other factorisations of the same pattern
        (default: none shared).

    Raises
    ------
    ArithmeticError
        A block is not positive definite, or CHOLMOD did not keep the seam unknowns last
        (the caller factors otherwise).
    """

    def __init__(
        self, L: sp.spmatrix, last: np.ndarray, *, symbolic: SymbolicCache | None = None
    ) -> None:
        from cvxopt import amd, cholmod

        L = sp.csc_matrix(L)
        check_finite(L)
        if not L.has_sorted_indices:
            L = L.sorted_indices()  # a copy: the caller's matrix stays as it was
        counted(L)  # one factorisation of the matrix, however many blocks it has
        N = L.shape[0]
        self.N, self.last = N, np.asarray(last, dtype=np.int64)
        slot = np.full(N, -1, dtype=np.int64)
        slot[self.last] = np.arange(len(self.last))
        groups, local = components(L)
        self._parts: list[dict] = []
        taken: list[Symbolic] = []
        seen: dict[tuple[int, int], list[tuple[sp.csc_matrix, dict]]] = {}  # by shape
        for g in groups:
            g = as_slice(g)
            block = column_block(L, g, local)
            sl = slot[g]
            seam = np.flatnonzero(sl >= 0)
            seam = seam[np.argsort(sl[seam], kind="stable")]  # in the order of ``last``
            key = (block.shape[0], block.nnz)
            twin = next(
                (
                    q
                    for other, q in seen.get(key, ())
                    if np.array_equal(q["seam"], seam) and equal_matrices(other, block)
                ),
                None,
            )
            if twin is not None:
                twin["members"].append(g)
                twin["slots"].append(sl[twin["order"]])
                continue
            perm = None
            if len(seam):
                p0 = np.asarray(amd.order(cvx_matrix(block))).ravel()
                is_seam = np.zeros(block.shape[0], dtype=bool)
                is_seam[seam] = True
                perm = np.concatenate([p0[~is_seam[p0]], seam])
            solve, getfactor = factor_part(block, cholmod, taken, perm, symbolic)
            part = {"members": [g], "solve": solve, "seam": seam, "T": None}
            order = seam
            if len(seam):
                k, ns = block.shape[0], len(seam)
                pos = solve(np.arange(k, dtype=float), 8)  # each unknown's place in the factor
                pos = np.rint(pos).astype(np.int64)
                order = np.argsort(pos[seam], kind="stable")
                ib = pos[seam][order]
                if not np.array_equal(ib, np.arange(k - ns, k)):
                    raise ArithmeticError("the seam unknowns are not last in the factor")
                order = seam[order]
                part["trailing"] = (getfactor, ib)
            part.update(order=order, slots=[sl[order]])  # each member's places in ``last``
            seen.setdefault(key, []).append((block, part))
            self._parts.append(part)

    @staticmethod
    def _T(part: dict) -> np.ndarray | None:
        """The block's trailing factor ``T`` (read out of CHOLMOD's factor once, when the
        seam step first needs it), None without seam unknowns."""
        if part["T"] is None and "trailing" in part:
            from cvxopt import matrix

            getfactor, ib = part.pop("trailing")
            Lf = getfactor()
            idx = matrix(ib.astype(int))
            part["T"] = np.tril(np.array(matrix(Lf[idx, idx])))
        return part["T"]

    def __call__(self, b: np.ndarray) -> np.ndarray:
        """``A^-1 b`` for ``b`` ``(N,)`` or ``(N, c)``."""
        rhs = np.asarray(b, dtype=float).reshape(len(b), -1)
        c = rhs.shape[1]
        out = np.empty_like(rhs)
        for part in self._parts:
            sol = part["solve"](np.concatenate([rhs[g] for g in part["members"]], axis=1))
            for j, g in enumerate(part["members"]):
                out[g] = sol[:, j * c : (j + 1) * c]
        return out.reshape(np.shape(b))

    def forward(self, b: np.ndarray) -> list[np.ndarray]:
        """The forward substitutions ``z = L^-1 P b`` of each block, ``b`` ``(N, c)``."""
        out = []
        for part in self._parts:
            rhs = np.concatenate([b[g] for g in part["members"]], axis=1)
            out.append(part["solve"](part["solve"](rhs, 7), 4))
        return out

    def seam_values(self, Z: list[np.ndarray], c: int) -> np.ndarray:
        """``(A^-1 b)`` at the seam unknowns, ``(s, c)`` in the order of ``last``, from
        :meth:`forward`'s ``Z`` (``c`` columns of ``b``)."""
        from scipy.linalg import solve_triangular

        out = np.zeros((len(self.last), c))
        for part, z in zip(self._parts, Z, strict=True):
            T = self._T(part)
            if T is None:
                continue
            ns = len(T)
            ys = solve_triangular(T, z[-ns:], lower=True, trans="T", check_finite=False)
            for j, slots in enumerate(part["slots"]):
                out[slots] = ys[:, j * c : (j + 1) * c]
        return out

    def finish(self, Z: list[np.ndarray], c: int, w: np.ndarray | None = None) -> np.ndarray:
        """``A^-1 (b - E w)`` from :meth:`forward`'s ``Z`` for ``w`` ``(s, c)`` on the seam
        unknowns (``E`` their columns of the identity; None: ``A^-1 b``), ``(N, c)``.
        ``Z`` is not changed."""
        from scipy.linalg import solve_triangular

        out = np.empty((self.N, c))
        for part, z in zip(self._parts, Z, strict=True):
            T = self._T(part) if w is not None else None
            if T is not None:
                ns = len(T)
                ws = np.concatenate([w[slots] for slots in part["slots"]], axis=1)
                z = z.copy()
                z[-ns:] -= solve_triangular(T, ws, lower=True, check_finite=False)
            sol = part["solve"](part["solve"](z, 5), 8)
            for j, g in enumerate(part["members"]):
                out[g] = sol[:, j * c : (j + 1) * c]
        return out

    def blocks(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """``A^-1`` on each block's seam unknowns: (positions in ``last``, ``(k, k)``
        dense), one per member of a block with seam unknowns (zero across blocks)."""
        from scipy.linalg import lapack

        out = []
        for part in self._parts:
            T = self._T(part)
            if T is None:
                continue
            G, info = lapack.dpotri(T, lower=1)
            if info != 0 or not np.all(np.isfinite(G)):
                raise ArithmeticError("the seam block of the inverse is not finite")
            G = np.tril(G) + np.tril(G, -1).T
            out += [(slots, G) for slots in part["slots"]]
        return out
