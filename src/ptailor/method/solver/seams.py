"""The seam-length constraints of the stitching: the factorisation that eliminates the
seam unknowns last (:class:`SplitSolve`), a solve under way (:class:`Solved`), and the
constrained global step of :class:`ptailor.method.solver.problem.Problem`
(:class:`SeamConstraints`: a sequential-quadratic-programming step through a Schur
complement on the one factorisation)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from ptailor.method import tolerances as method_tol
from ptailor.method.solver.seam_block import SeamBlock, seam_block
from ptailor.method.solver.seam_factor import SeamFactor
from ptailor.method.solver.small_systems import bordered_solver
from ptailor.method.solver.symbolic import SymbolicCache


class SplitSolve:
    """``A^-1`` over unknowns ``[x; y]`` through a :class:`SeamFactor` that eliminates the
    seam unknowns ``U = [verts; verts + n]`` last: the constrained step's two solves in
    about the time of one (:class:`Solved`), and the seam block of ``A^-1`` from the same
    factorisation (no second one when the seams switch on).

    Parameters
    ----------
    A : sparse matrix
        Lower triangle of the stitching matrix, ``n x n`` when x and y decouple, ``2n x 2n``
        when coupled.
    n : int
        Pattern vertices.
    verts : (q,) int array
        The seam vertices.
    symbolic : SymbolicCache, optional
        Symbolic analyses shared with the caller's other factorisations.

    Raises
    ------
    ArithmeticError, ValueError, ImportError
        As :class:`SeamFactor` (:func:`split_solver` turns them into None).
    """

    def __init__(
        self,
        A: sp.csc_matrix,
        n: int,
        verts: np.ndarray,
        symbolic: SymbolicCache | None = None,
    ) -> None:
        self.n, self.q = n, len(verts)
        self.coupled = A.shape[0] == 2 * n
        self.U = np.concatenate([verts, verts + n])
        self.fac = SeamFactor(A, self.U if self.coupled else verts, symbolic=symbolic)

    def _cols(self, v: np.ndarray, k: int) -> np.ndarray:
        """A vector over ``[x; y]`` (length ``2k``) as the factor's columns."""
        return v[:, None] if self.coupled else v.reshape(2, k).T

    def _vec(self, X: np.ndarray) -> np.ndarray:
        return X[:, 0] if self.coupled else X.T.ravel()

    def solve_many(self, rhs: np.ndarray) -> np.ndarray:
        """``A^-1 rhs`` for columns over ``[x; y]``, ``(2n, c)``."""
        if self.coupled:
            return self.fac(rhs)
        n, c = self.n, rhs.shape[1]
        sol = self.fac(np.concatenate([rhs[:n], rhs[n:]], axis=1))
        return np.concatenate([sol[:, :c], sol[:, c:]], axis=0)

    def forward(self, b: np.ndarray) -> list[np.ndarray]:
        """The factor's forward substitutions of ``b`` ``(2n,)`` (:meth:`SeamFactor.forward`)."""
        return self.fac.forward(self._cols(b, self.n))

    def seam(self, Z: list[np.ndarray]) -> np.ndarray:
        """``(A^-1 b)[U]``, ``(2q,)``."""
        return self._vec(self.fac.seam_values(Z, 1 if self.coupled else 2))

    def finish(self, Z: list[np.ndarray], w: np.ndarray | None) -> np.ndarray:
        """``A^-1 (b - E_U w)``, ``(2n,)``."""
        c = 1 if self.coupled else 2
        return self._vec(self.fac.finish(Z, c, None if w is None else self._cols(w, self.q)))

    def seam_block(self) -> SeamBlock:
        """The seam block of ``A^-1`` from the factor's trailing blocks.

        Raises
        ------
        ArithmeticError
            The trailing factor is not usable (:meth:`SeamFactor.blocks`).
        """
        blocks = self.fac.blocks()
        if not self.coupled:  # one n x n block per panel serves x and y
            blocks += [(g + self.q, G) for g, G in blocks]
        return SeamBlock(U=self.U, blocks=blocks)


def split_solver(
    A: sp.csc_matrix, n: int, verts: np.ndarray, symbolic: SymbolicCache | None = None
) -> SplitSolve | None:
    """:class:`SplitSolve` where CHOLMOD factors ``A`` with the seam unknowns last; None
    otherwise (no cvxopt, a block not positive definite: the caller's :func:`factor`
    decides)."""
    try:
        return SplitSolve(A, n, verts, symbolic)
    except (ImportError, ArithmeticError, ValueError):
        return None


class Solved:
    """``y = A^-1 b`` under way: its seam values ``y[U]`` at once, the whole vector (less
    ``A^-1 E_U w`` for ``w`` on the seam unknowns) on request, from one forward and one
    back-substitution where the factor splits the seam unknowns off (:class:`SplitSolve`),
    else from one solve (and one more for ``w``).

    Parameters
    ----------
    pb : Problem
        The stitching problem (:class:`ptailor.method.solver.problem.Problem`) with its seam
        constraints on: its ``seam_block``, ``split``, ``n`` and ``solve`` are read.
    b : (2n,) float array

    Attributes
    ----------
    seam : (2q,) float array
        ``y[U]``.
    """

    def __init__(self, pb, b: np.ndarray) -> None:
        self.pb, self.U = pb, pb.seam_block.U
        if pb.split is not None:
            self._Z = pb.split.forward(b)
            self.seam = pb.split.seam(self._Z)
        else:
            self._y = pb.solve(b)
            self.seam = self._y[self.U]

    def full(self, w: np.ndarray | None = None) -> np.ndarray:
        """``A^-1 (b - E_U w)`` over ``[x; y]``, ``(2n,)``."""
        pb = self.pb
        if pb.split is not None:
            return pb.split.finish(self._Z, w)
        if w is None:
            return self._y
        r = np.zeros(2 * pb.n)
        r[self.U] = w
        return self._y - pb.solve(r)


@dataclass(frozen=True)
class SeamStep:
    """The seam rows of one linearisation and the solver of their Woodbury system, kept
    to project further right-hand sides onto the same constraints
    (:meth:`ptailor.method.solver.newton.NewtonModel.newton`).

    Attributes
    ----------
    X : (n, 2) float array
        Where the constraints were linearised (the object itself: compared by identity).
    C : (k + t, 2n) sparse matrix
        The constraint rows.
    solve : callable
        ``nu = solve(QU y[U])``: the multipliers of the rows :attr:`QU` for the plain
        solution ``y``.
    P : (p, 2n) sparse matrix or None
        The curvature rows (None without).
    kappa : (p,) float array
        Their weights.
    parts : tuple of sparse matrices
        ``P`` (where given) and ``C`` over the seam unknowns, the pieces of :attr:`QU`.
    """

    X: np.ndarray
    C: sp.csr_matrix
    solve: Callable[[np.ndarray], np.ndarray | None]
    P: sp.csr_matrix | None
    kappa: np.ndarray
    parts: tuple[sp.csr_matrix, ...] = ()

    @cached_property
    def QU(self) -> sp.csr_matrix:
        """The curvature rows over the constraint rows, ``[P; C]``, over the seam unknowns
        ``U`` (built when a Newton step needs them, not every step)."""
        return self.parts[0] if len(self.parts) == 1 else sp.vstack(self.parts).tocsr()


class SeamConstraints:
    """The seam-constraint half of :class:`ptailor.method.solver.problem.Problem` (a mixin:
    it reads the problem's public attributes, ``ease``, ``seam_block``, ``split``, ``n``,
    ``vlab``, ``B``, ``solve_many``, and its :meth:`solve` and :meth:`matrix`): switching
    them on, the constrained global step, and its system applied to other right-hand
    sides (the Newton step's preconditioner). It fills ``seam_step`` (and ``seam_block``,
    once), the problem's state it owns."""

    def constrained(self, sol: Solved, X_lin: np.ndarray) -> np.ndarray:
        """The global step ``y = A^-1 b`` under the seam constraints linearised at
        ``X_lin``, a sequential-quadratic-programming step.

        First the multipliers of the plain projection, ``lam = (C S C^T)^-1 C y`` (``S``
        the seam block of ``A^-1``). Then the step with the constraints' curvature under
        those multipliers (:meth:`SeamEase.curvature`: ``1/2 sum kappa (P (x - X_lin))^2``
        added to the energy) and the constraints, by Woodbury on the seam block: with the
        rows ``Q = [P; C]``,

            (Q S Q^T + diag(1/kappa, 0)) nu = Q y - [P X_lin; 0],   x = y - A^-1 Q^T nu

        one back-substitution and two small dense solves. Without the curvature the
        linearised constraints let a compressed seam side zigzag (its edges turn and keep
        their projected length), and the iterations crawl on fine meshes: the 100-iteration
        cap at 82k triangles where 21 do with it."""
        blk, ease = self.seam_block, self.ease
        self.seam_step = None
        C = ease.rows(X_lin)
        B = ease.total_columns(X_lin)  # each curve's factor free within the step
        CR = blk.restrict(C)  # over the seam unknowns U, as y's seam values
        CU = blk.products(CR)
        M_cc = blk.schur(CU)
        cc = bordered_solver(M_cc, B)
        ys = sol.seam
        lam = None if cc is None else cc(CR @ ys)
        if lam is None:
            return sol.full()  # the constraints are skipped this step (reported)
        P, kappa = ease.curvature(X_lin, lam)
        if len(kappa):
            PR = blk.restrict(P)
            PU = blk.products(PR)
            kp = len(kappa)
            M = np.zeros((kp + len(M_cc), kp + len(M_cc)))  # [[P S P^T, P S C^T], [., M_cc]]
            blk.schur(PU, out=M[:kp, :kp])
            blk.schur(PU, CU, out=M[:kp, kp:])
            M[kp:, :kp] = M[:kp, kp:].T
            M[kp:, kp:] = M_cc
            M[np.arange(kp), np.arange(kp)] += 1.0 / kappa
            BP = None if B is None else np.vstack([np.zeros((len(kappa), B.shape[1])), B])
            full = bordered_solver(M, BP)
            nu = None
            if full is not None:
                nu = full(np.concatenate([PR @ (ys - X_lin.T.ravel()[blk.U]), CR @ ys]))
            if nu is not None:
                y_c = sol.full(PR.T @ nu[: len(kappa)] + CR.T @ nu[len(kappa) :])
                if np.all(np.isfinite(y_c)):
                    self.seam_step = SeamStep(X_lin, C, full, P, kappa, (PR, CR))
                    return y_c
        y_c = sol.full(CR.T @ lam)  # no curvature (none, or its solve failed)
        if not np.all(np.isfinite(y_c)):
            return sol.full()
        self.seam_step = SeamStep(X_lin, C, cc, None, np.zeros(0), (CR,))
        return y_c

    def project(self, R: np.ndarray, seam: SeamStep | None) -> np.ndarray:
        """``z`` minimising ``1/2 z^T (A + P^T kappa P) z - R . z`` with ``C z`` on the
        seams' linearisation ``seam`` (its curves' factors free), ``(n, 2)``: the
        local/global step's own system, applied to another right-hand side ``R (n, 2)``."""
        if seam is None:
            return self.solve(R.T.ravel()).reshape(2, self.n).T
        sol = Solved(self, R.T.ravel())
        nu = seam.solve(seam.QU @ sol.seam)
        y = sol.full() if nu is None else sol.full(seam.QU.T @ nu)
        return y.reshape(2, self.n).T

    def seams_pending(self, GX: np.ndarray) -> bool:
        """Seam constraints exist, are off, and a seam misses its ratio."""
        return (
            self.ease is not None
            and self.seam_block is None
            and self.ease.violation(GX).max() > method_tol.SEAM_EXACT_REL
        )

    def seams_settled(self, GX: np.ndarray) -> bool:
        """Seam constraints are on, absent, or every seam meets its ratio (not NaN)."""
        return bool(
            self.seam_block is not None
            or self.ease is None
            or self.ease.violation(GX).max() <= method_tol.SEAM_EXACT_REL
        )

    def seams_on(self) -> None:
        """Switch the seam constraints on: the seam block of ``A^-1``, once."""
        if self.split is not None:
            try:
                self.seam_block = self.split.seam_block()
                return
            except ArithmeticError:  # the trailing factor is not usable: solve as before
                self.split = None
        self.seam_block = seam_block(
            self.solve_many, self.ease, np.maximum(self.vlab, 0), self.n,
            coupled=self.B is not None, A=self.matrix(),
        )  # fmt: skip
