"""Stitching: glue per-triangle targets into panels (ARAP local/global + ASAP boundary).

Minimises, over all panels at once (the system is block diagonal by panel)::

    E(x) = sum_i A_i |J_i(x) - R_i|_F^2                       as-rigid-as-possible
         + w_pin  sum_(c in C) |x_c - c|^2                     one pinned vertex per panel
         + w_asap sum_(k in B) (n_k . (x_(k+1) - x_(k-1)))^2   as-similar-as-possible

where ``J_i`` is the map from triangle ``i``'s target to its current position (so the first
term is Liu et al. 2008's triangle ARAP energy: cotangent-weighted edge terms), ``R_i`` a
rotation per triangle, ``n_k`` the unit normal of the original boundary chord at ``k``.
The matrix never changes: it is factored once and each iteration back-substitutes.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from ptailor import tolerances as tol
from ptailor.geometry.closed_forms import det2
from ptailor.method.anderson import Anderson
from ptailor.method.bend import SeamBend, seam_bend
from ptailor.method.ease import SeamEase
from ptailor.method.linear import SeamBlock, SeamFactor, bordered_solver, factor, seam_block
from ptailor.method.operators import asap_rows, gradient_operator, stitch_matrix

__all__ = ["StitchInfo", "stitch"]


@dataclass(frozen=True)
class StitchInfo:
    """What the solver did.

    Attributes
    ----------
    iterations : int
        Local/global iterations after the initial solve.
    energy : float
        Final value of ``E``.
    converged : bool
        True when every panel's last step fell below the tolerance.
    panel_residual : (n_panels,) float array
        Each panel's last step (largest vertex move, rigid motion removed) over its size.
    seam_violation : float
        Largest relative seam-length mismatch ``|L_b - r L_a| / L_b`` of the constraints
        (0 without them).
    history : tuple of float
        The largest panel residual before each iteration (convergence curve).
    stalled : bool
        The iterations stopped before ``max_iter`` because the largest residual made no
        progress over ``tol.ARAP_STALL_ITER`` iterations (not converged).
    newton_steps : int
        Iterations that were a Newton step (:meth:`_Problem.newton`), taken where the
        local/global steps crawl.
    """

    iterations: int
    energy: float
    converged: bool
    panel_residual: np.ndarray = field(default_factory=lambda: np.zeros(0))
    seam_violation: float = 0.0
    history: tuple[float, ...] = ()
    stalled: bool = False
    newton_steps: int = 0


def _vertex_panels(F2: np.ndarray, n: int, vertex_panel: np.ndarray | None) -> np.ndarray:
    """Panel per vertex, -1 for vertices no triangle uses (default: components of ``F2``)."""
    if vertex_panel is None:
        from scipy.sparse.csgraph import connected_components

        m = len(F2)
        adj = sp.csr_matrix(
            (np.ones(3 * m), (F2.ravel(), np.roll(F2, -1, axis=1).ravel())), shape=(n, n)
        )
        vertex_panel = connected_components(adj, directed=False)[1]
    used = np.zeros(n, dtype=bool)
    used[F2.ravel()] = True
    return np.where(used, vertex_panel, -1)


def _panel_sizes(V2: np.ndarray, vlab: np.ndarray, n_panels: int) -> np.ndarray:
    """Bounding-box diagonal per panel, for a scale-free convergence test."""
    size = np.ones(max(n_panels, 1))
    if n_panels:
        used = np.flatnonzero(vlab >= 0)
        order = used[np.argsort(vlab[used], kind="stable")]  # by panel: one segment each
        cnt = np.bincount(vlab[order], minlength=n_panels)
        has = cnt > 0
        start = np.concatenate([[0], np.cumsum(cnt[has])[:-1]]).astype(np.intp)
        lo = np.full((n_panels, 2), np.inf)
        hi = np.full((n_panels, 2), -np.inf)
        if len(order):  # extremes are exact in any order: the same as ufunc.at's, 3x faster
            lo[has] = np.minimum.reduceat(V2[order], start, axis=0)
            hi[has] = np.maximum.reduceat(V2[order], start, axis=0)
        size = np.maximum(np.linalg.norm(hi - lo, axis=1), 1e-300)
    return size


def _finite_or_fail(Y: np.ndarray) -> np.ndarray:
    if not np.all(np.isfinite(Y)):
        from ptailor.errors import PtailorError

        raise PtailorError(
            "flatten: the stitching solver diverged (non-finite positions); check the "
            "flatten weights and the edit"
        )
    return Y


def _solver(A: sp.csc_matrix, n: int):
    """``A^-1`` applied to columns over unknowns ``[x; y]``, from one factorisation of the
    stitching matrix's lower triangle ``A`` (``n x n`` when x and y decouple, ``2n x 2n``
    when coupled)."""
    solve = factor(A, lower=True)
    if A.shape[0] == 2 * n:
        return solve

    def solve_many(rhs: np.ndarray) -> np.ndarray:
        # x and y decouple: one n x n factor serves both coordinates
        c = rhs.shape[1]
        sol = solve(np.concatenate([rhs[:n], rhs[n:]], axis=1))
        return np.concatenate([sol[:, :c], sol[:, c:]], axis=0)

    return solve_many


class _SplitSolve:
    """``A^-1`` over unknowns ``[x; y]`` through a :class:`SeamFactor` that eliminates the
    seam unknowns ``U = [verts; verts + n]`` last: the constrained step's two solves in
    about the time of one (:class:`_Solved`), and the seam block of ``A^-1`` from the same
    factorisation (no second one when the seams switch on)."""

    def __init__(self, A: sp.csc_matrix, n: int, verts: np.ndarray) -> None:
        self.n, self.q = n, len(verts)
        self.coupled = A.shape[0] == 2 * n
        self.U = np.concatenate([verts, verts + n])
        self.fac = SeamFactor(A, self.U if self.coupled else verts)

    def _cols(self, v: np.ndarray, k: int) -> np.ndarray:
        """A vector over ``[x; y]`` (length ``2k``) as the factor's columns."""
        return v[:, None] if self.coupled else v.reshape(2, k).T

    def _vec(self, X: np.ndarray) -> np.ndarray:
        return X[:, 0] if self.coupled else X.T.ravel()

    def solve_many(self, rhs: np.ndarray) -> np.ndarray:
        if self.coupled:
            return self.fac(rhs)
        n, c = self.n, rhs.shape[1]
        sol = self.fac(np.concatenate([rhs[:n], rhs[n:]], axis=1))
        return np.concatenate([sol[:, :c], sol[:, c:]], axis=0)

    def forward(self, b: np.ndarray) -> list[np.ndarray]:
        return self.fac.forward(self._cols(b, self.n))

    def seam(self, Z: list[np.ndarray]) -> np.ndarray:
        """``(A^-1 b)[U]``, ``(2q,)``."""
        return self._vec(self.fac.seam_values(Z, 1 if self.coupled else 2))

    def finish(self, Z: list[np.ndarray], w: np.ndarray | None) -> np.ndarray:
        """``A^-1 (b - E_U w)``, ``(2n,)``."""
        c = 1 if self.coupled else 2
        return self._vec(self.fac.finish(Z, c, None if w is None else self._cols(w, self.q)))

    def seam_block(self) -> SeamBlock:
        blocks = self.fac.blocks()
        if not self.coupled:  # one n x n block per panel serves x and y
            blocks += [(g + self.q, G) for g, G in blocks]
        return SeamBlock(U=self.U, blocks=blocks)


def _split_solver(A: sp.csc_matrix, n: int, verts: np.ndarray) -> _SplitSolve | None:
    """:class:`_SplitSolve` where CHOLMOD factors ``A`` with the seam unknowns last; None
    otherwise (no cvxopt, a block not positive definite: :func:`factor` decides)."""
    try:
        return _SplitSolve(A, n, verts)
    except (ImportError, ArithmeticError, ValueError):
        return None


class _Solved:
    """``y = A^-1 b`` under way: its seam values ``y[U]`` at once, the whole vector (less
    ``A^-1 E_U w`` for ``w`` on the seam unknowns) on request, from one forward and one
    back-substitution where the factor splits the seam unknowns off (:class:`_SplitSolve`),
    else from one solve (and one more for ``w``)."""

    def __init__(self, pb: _Problem, b: np.ndarray) -> None:
        self.pb, self.U = pb, pb.seam_block.U
        if pb._split is not None:
            self._Z = pb._split.forward(b)
            self.seam = pb._split.seam(self._Z)
        else:
            self._y = pb.solve(b)
            self.seam = self._y[self.U]

    def full(self, w: np.ndarray | None = None) -> np.ndarray:
        """``A^-1 (b - E_U w)`` over ``[x; y]``, ``(2n,)``."""
        pb = self.pb
        if pb._split is not None:
            return pb._split.finish(self._Z, w)
        if w is None:
            return self._y
        r = np.zeros(2 * pb.n)
        r[self.U] = w
        return self._y - pb.solve(r)


class _PanelIndex:
    """The used vertices grouped by panel, for per-panel rigid fits and maxima."""

    def __init__(self, vlab: np.ndarray, n_panels: int) -> None:
        used = np.flatnonzero(vlab >= 0)
        self.order = used[np.argsort(vlab[used], kind="stable")]
        self.lab = vlab[self.order]
        cnt = np.bincount(self.lab, minlength=n_panels)
        self.nonempty = cnt > 0
        self.count = cnt[self.nonempty]  # members of each non-empty panel
        self.start = np.concatenate([[0], np.cumsum(self.count)[:-1]]).astype(np.intp)
        self.n_panels = n_panels

    def rigid_misfit(self, P: np.ndarray, Q: np.ndarray) -> np.ndarray:
        """Per panel, the largest distance from ``Q`` of ``P`` moved by its panel's best
        rotation and translation onto ``Q``, ``(n_panels,)`` (0 for an empty panel).

        The members are sorted by panel: each panel's sums are one segment's
        (``reduceat``), its centroid and rotation spread back by ``repeat``."""
        k, start, cnt = self.n_panels, self.start, self.count
        out = np.zeros(k)
        if not len(self.lab):
            return out
        pq = np.concatenate((P, Q), axis=1)[self.order]  # (N, 4): p, q per member
        pq -= np.repeat(np.add.reduceat(pq, start, axis=0) / cnt[:, None], cnt, axis=0)
        a0, a1, b0, b1 = pq.T
        dot = np.add.reduceat(a0 * b0 + a1 * b1, start)
        crs = np.add.reduceat(a0 * b1 - a1 * b0, start)
        r = np.hypot(dot, crs)
        ok = r > 0
        inv = np.divide(1.0, r, out=np.zeros_like(r), where=ok)
        c = np.repeat(np.where(ok, dot * inv, 1.0), cnt)
        s = np.repeat(crs * inv, cnt)
        dx, dy = c * a0 - s * a1 - b0, s * a0 + c * a1 - b1
        d = dx * dx + dy * dy  # squared: the square root of the maxima only
        out[self.nonempty] = np.sqrt(np.maximum.reduceat(d, start))
        return out


@dataclass(frozen=True)
class _SeamStep:
    """The seam rows of one linearisation and the solver of their Woodbury system, kept
    to project further right-hand sides onto the same constraints (:meth:`_Problem.newton`).

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


class _Problem:
    """The stitching energy of one pattern: its factored matrix, steps and measures."""

    def __init__(
        self,
        V2: np.ndarray,
        F2: np.ndarray,
        targets: np.ndarray,
        *,
        pins: np.ndarray,
        vertex_panel: np.ndarray | None,
        asap_faces: np.ndarray | None,
        asap_exclude: np.ndarray | None,
        ease: SeamEase | None,
        panel_weight: np.ndarray | None,
        w_pin: float,
        w_asap: float,
    ) -> None:
        n = len(V2)
        self.V2, self.n, self.pins, self.w_asap = V2, n, pins, w_asap
        vlab = self.vlab = _vertex_panels(F2, n, vertex_panel)
        n_panels = self.n_panels = int(vlab.max()) + 1 if n else 0
        self.m = len(F2)
        self.D = gradient_operator(F2, targets, n)
        used = self.used = vlab >= 0
        stiff = np.ones(max(n_panels, 1)) if panel_weight is None else np.asarray(panel_weight)
        # each panel's whole energy scaled by its weight: alone, a panel's solution is the
        # same; sewn to others by the seam constraints, a stiffer panel takes less of the
        # distortion
        self.area = 0.5 * np.abs(det2(targets)) * stiff[vlab[F2[:, 0]]]
        # unused vertices: identity rows so the system stays non-singular and they stay put
        pin_w = self.pin_w = np.zeros(n)
        pin_w[pins] = w_pin * stiff[vlab[pins]]
        pin_w[~used] = 1.0
        self.B = self._asap(V2, F2, asap_faces, asap_exclude, panel_weight, stiff)
        self.ease = None if ease is not None and not ease.n_rows else ease
        self.size = _panel_sizes(V2, vlab, n_panels)
        self.bend: SeamBend | None = None
        if self.ease is not None and tol.SEAM_BEND > 0:
            mu = np.zeros(n)
            mu[used] = tol.SEAM_BEND * self.size[vlab[used]] ** 3 * stiff[vlab[used]]
            self.bend = seam_bend(F2, targets, self.ease.vertices(), mu, np.maximum(vlab, 0))
        self._bend_H = None if self.bend is None else self.bend.matrix()  # (n, n)
        self._bend_M = None if self.bend is None else sp.tril(self._bend_H)
        # the seam block, if the seams switch on, factors the matrix once more: assembled
        # again then rather than held through the iterations (15 MB at 300k triangles)
        self._F2, self._targets = F2, targets
        A = self._matrix()
        # with seam constraints, one factorisation that eliminates the seam unknowns last
        self._split = None if self.ease is None else _split_solver(A, n, self.ease.vertices())
        self.solve_many = self._split.solve_many if self._split is not None else _solver(A, n)
        del A
        # the seam constraints switch on at the first iteration that misses a seam (an
        # identity edit or a uniform scale never pays for them)
        self.seam_block: SeamBlock | None = None
        self.pin_rhs = pin_w[:, None] * V2
        self._panels = _PanelIndex(vlab, n_panels)
        self._rot: tuple = (None, None)  # the last iterate's rotations, for reuse
        self._twist_at: tuple | None = None  # and their Hessian's twist weights
        self._seam_step: _SeamStep | None = None  # the last constrained step's rows

    def _asap(self, V2, F2, asap_faces, asap_exclude, panel_weight, stiff):
        """The as-similar-as-possible rows (weighted by panel), or None without any."""
        B = None
        if asap_faces is not None and len(asap_faces):
            B = asap_rows(V2, F2, np.asarray(asap_faces), exclude=asap_exclude)
            if panel_weight is not None and B.shape[0]:
                B = sp.diags(np.sqrt(stiff[self.vlab[B.indices[B.indptr[:-1]] % self.n]])) @ B
        return None if B is None or B.shape[0] == 0 else B

    def _matrix(self) -> sp.csc_matrix:
        """The lower triangle of the stitching system (with the seam sides' bending)."""
        A = stitch_matrix(self._F2, self._targets, self.area, self.pin_w, self.B, self.w_asap)
        if self._bend_M is None:
            return A
        L = self._bend_M if A.shape[0] == self.n else sp.block_diag([self._bend_M] * 2)
        return sp.csc_matrix(A + L)

    @cached_property
    def _Dt(self) -> sp.csc_matrix:
        """``D^T``, a view of ``D``'s arrays (the transpose object built once, not per step)."""
        return self.D.T

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        return self.solve_many(rhs[:, None])[:, 0]

    def rotations(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(J, cos, sin)``: the Jacobians ``(2m, 2)`` (``D @ X``) and the closest rotation
        to each (closed form, ``atan2(J10 - J01, J00 + J11)``; identity for ``J = 0``)."""
        if self._rot[0] is X:
            return self._rot[1]
        m = self.m
        J = self.D @ X  # rows [0, m): J[:, :, 0]; rows [m, 2m): J[:, :, 1]
        x = J[:m, 0] + J[m:, 1]
        y = J[:m, 1] - J[m:, 0]
        r = np.hypot(x, y)
        ok = r > 0
        inv = 1.0 / np.where(ok, r, np.inf)  # 0 where r is 0 (or NaN)
        cos = np.where(ok, x * inv, 1.0)
        sin = y * inv
        self._rot = (X, (J, cos, sin))
        return J, cos, sin

    def energy(self, X: np.ndarray) -> float:
        J, cos, sin = self.rotations(X)
        m, pins = self.m, self.pins
        # |J - R|_F^2 per triangle, (a^2 + b^2) + (c^2 + d^2) in place (4 temporaries)
        d = J[:m, 0] - cos
        d *= d
        t = J[:m, 1] - sin
        t *= t
        d += t
        t = J[m:, 0] + sin
        t *= t
        u = J[m:, 1] - cos
        u *= u
        t += u
        d += t
        e = float(self.area @ d)
        e += float((self.pin_w[pins, None] * (X[pins] - self.V2[pins]) ** 2).sum())
        if self.B is not None:
            e += float(self.w_asap * ((self.B @ X.T.ravel()) ** 2).sum())
        if self.bend is not None:
            e += self.bend.energy(X)
        return e

    def global_step(self, cos: np.ndarray, sin: np.ndarray, X_lin: np.ndarray | None) -> np.ndarray:
        """The global step for rotations ``[[cos, -sin], [sin, cos]]`` per triangle."""
        ac, as_ = self.area * cos, self.area * sin
        W = np.empty((2 * self.m, 2))  # the rotations stacked like the Jacobians
        W[: self.m, 0], W[: self.m, 1] = ac, as_
        W[self.m :, 0], W[self.m :, 1] = -as_, ac
        rhs = self._Dt @ W + self.pin_rhs
        if self.bend is not None:
            rhs = rhs + self.bend.rhs(X_lin)
        if self.seam_block is not None and X_lin is not None:
            y = self._constrained(_Solved(self, rhs.T.ravel()), X_lin)
        else:
            y = self.solve(rhs.T.ravel())
        return y.reshape(2, self.n).T

    def _constrained(self, sol: _Solved, X_lin: np.ndarray) -> np.ndarray:
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
        self._seam_step = None
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
                    self._seam_step = _SeamStep(X_lin, C, full, P, kappa, (PR, CR))
                    return y_c
        y_c = sol.full(CR.T @ lam)  # no curvature (none, or its solve failed)
        if not np.all(np.isfinite(y_c)):
            return sol.full()
        self._seam_step = _SeamStep(X_lin, C, cc, None, np.zeros(0), (CR,))
        return y_c

    def _project(self, R: np.ndarray, seam: _SeamStep | None) -> np.ndarray:
        """``z`` minimising ``1/2 z^T (A + P^T kappa P) z - R . z`` with ``C z`` on the
        seams' linearisation ``seam`` (its curves' factors free), ``(n, 2)``: the
        local/global step's own system, applied to another right-hand side ``R (n, 2)``."""
        if seam is None:
            return self.solve(R.T.ravel()).reshape(2, self.n).T
        sol = _Solved(self, R.T.ravel())
        nu = seam.solve(seam.QU @ sol.seam)
        y = sol.full() if nu is None else sol.full(seam.QU.T @ nu)
        return y.reshape(2, self.n).T

    def _rotation_hessian(self, X: np.ndarray, V: np.ndarray) -> np.ndarray:
        """The part of the energy's Hessian the local/global step leaves out, applied to
        ``V (n, 2)``: ``sum_i A_i alpha_i (t_i . J_i(V)) D_i^T t_i`` (half-energy units).

        At the closest rotation ``R_i`` (angle ``theta``) of ``J_i``, ``R_i`` turns with
        ``J_i`` along ``t_i = dR/dtheta`` only, at the rate ``1 / r_i`` (``r_i = s1 + s2``,
        the sum of ``J_i``'s singular values): the Hessian of ``|J - R(J)|^2 / 2`` is
        ``I - t t^T / r``, whose one eigenvalue below 1 is the twist's, ``1 - 2 / r``.
        Projected onto the positive semi-definite cone (Teran et al.'s per-element
        projection): ``alpha = 1 / r`` where ``r >= 2``, ``1/2`` (the twist free) where
        the triangle is compressed."""
        return self._Dt @ self._rotation_weights(X, self.D @ V)

    def _rotation_weights(self, X: np.ndarray, JV: np.ndarray) -> np.ndarray:
        """:meth:`_rotation_hessian` before ``D^T``, from ``JV = D V``, ``(2m, 2)``."""
        cos, sin, w = self._twist(X)
        m = self.m
        # t = [[-sin, -cos], [cos, -sin]] in J's (coordinate, target axis) layout
        coef = w * (cos * (JV[:m, 1] - JV[m:, 0]) - sin * (JV[:m, 0] + JV[m:, 1]))
        W = np.empty((2 * m, 2))
        W[:m, 0], W[:m, 1] = -sin * coef, cos * coef
        W[m:, 0], W[m:, 1] = -cos * coef, -sin * coef
        return W

    def _twist(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(cos, sin, area * alpha)`` of :meth:`_rotation_hessian` at ``X`` (kept for the
        conjugate-gradient iterations of one Newton step, all at one ``X``)."""
        cached = self._twist_at
        if cached is not None and cached[0] is X:
            return cached[1]
        J, cos, sin = self.rotations(X)
        m = self.m
        r = np.hypot(J[:m, 0] + J[m:, 1], J[:m, 1] - J[m:, 0])
        alpha = np.where(r >= 2.0, 1.0 / np.maximum(r, 2.0), 0.5)
        out = (cos, sin, self.area * alpha)
        self._twist_at = (X, out)
        return out

    def _hessian(self, X: np.ndarray, V: np.ndarray, seam: _SeamStep | None) -> np.ndarray:
        """The projected Hessian of the half energy with the seams' curvature at ``X``,
        applied to ``V (n, 2)``: one product with ``D`` and one with ``D^T``."""
        JV = self.D @ V
        W = self._rotation_weights(X, JV)
        JV[: self.m] *= self.area[:, None]
        JV[self.m :] *= self.area[:, None]
        JV -= W
        out = self._Dt @ JV + self.pin_w[:, None] * V
        if self._bend_H is not None:
            out += self._bend_H @ V
        v = None
        if self.B is not None:
            v = V.T.ravel()
            out += (self.w_asap * (self.B.T @ (self.B @ v))).reshape(2, self.n).T
        if seam is not None and seam.P is not None:
            v = V.T.ravel() if v is None else v
            out += (seam.P.T @ (seam.kappa * (seam.P @ v))).reshape(2, self.n).T
        return out

    def newton(
        self, X: np.ndarray, GX: np.ndarray, *, max_cg: int, rtol: float
    ) -> tuple[np.ndarray, int] | None:
        """A Newton step from ``X`` and the conjugate-gradient iterations it took; None
        where the seam constraints were skipped at ``X`` (no model to refine).

        The step minimises the quadratic model of the energy at ``X`` with its projected
        Hessian (:meth:`_rotation_hessian`; the seams' curvature and linearised
        constraints as the local/global step has them) by conjugate gradients
        preconditioned by the local/global step's own system (a constraint
        preconditioner: every iterate meets the linearised seams), started from the
        local/global step ``GX - X``, which minimises the model with that system's
        Hessian. Where the two Hessians agree the start is the answer; where they do not
        (a slender panel's bending: the local/global step's matrix is stiff there and the
        iterations crawl) a few iterations find what hundreds of local/global steps
        would. Stops when the preconditioned residual has fallen by ``rtol``, after
        ``max_cg`` iterations, or at a direction without positive curvature.
        ``GX`` must be the step from ``X`` (the seams linearised at ``X``)."""
        seam = None
        if self.seam_block is not None:
            seam = self._seam_step
            if seam is None or seam.X is not X:
                return None
        d = GX - X
        res = -self._rotation_hessian(X, d)  # the model's gradient at d, C^T lam left out
        z = self._project(res, seam)
        rz = rz0 = float((res * z).sum())
        if not rz > 0:
            return GX, 0
        p = -z
        k = 0
        while k < max_cg:
            k += 1
            Hp = self._hessian(X, p, seam)
            curv = float((p * Hp).sum())
            if not curv > 0:
                break
            a = rz / curv
            d += a * p
            res += a * Hp
            z = self._project(res, seam)
            rz_new = float((res * z).sum())
            if not rz_new > rtol * rtol * rz0:
                break
            p = -z + (rz_new / rz) * p
            rz = rz_new
        return X + d, k

    def step(self, X: np.ndarray) -> np.ndarray:
        _, cos, sin = self.rotations(X)
        return self.global_step(cos, sin, X)

    def residual(self, X: np.ndarray, GX: np.ndarray) -> np.ndarray:
        """Per panel: the largest vertex move of the step, rigid motion removed, / size."""
        return self._panels.rigid_misfit(GX, X) / self.size

    def seams_pending(self, GX: np.ndarray) -> bool:
        """Seam constraints exist, are off, and a seam misses its ratio."""
        return (
            self.ease is not None
            and self.seam_block is None
            and self.ease.violation(GX).max() > tol.SEAM_EXACT_REL
        )

    def seams_settled(self, GX: np.ndarray) -> bool:
        """Seam constraints are on, absent, or every seam meets its ratio (not NaN)."""
        return bool(
            self.seam_block is not None
            or self.ease is None
            or self.ease.violation(GX).max() <= tol.SEAM_EXACT_REL
        )

    def seams_on(self) -> None:
        """Switch the seam constraints on: the seam block of ``A^-1``, once."""
        if self._split is not None:
            try:
                self.seam_block = self._split.seam_block()
                return
            except ArithmeticError:  # the trailing factor is not usable: solve as before
                self._split = None
        self.seam_block = seam_block(
            self.solve_many, self.ease, np.maximum(self.vlab, 0), self.n,
            coupled=self.B is not None, A=self._matrix(),
        )  # fmt: skip


class _Iterate:
    """The iteration's current point ``X``, its plain step ``GX`` and their measures."""

    def __init__(self, pb: _Problem, X: np.ndarray, history: int) -> None:
        self.pb, self.history = pb, history
        self.X = X
        self.GX = _finite_or_fail(pb.step(X))
        self.res = pb.residual(self.X, self.GX)
        self.e_gx = pb.energy(self.GX) if history else 0.0

    def plain(self) -> None:
        """Move to the plain step's output and take the next plain step."""
        pb = self.pb
        self.X = self.GX
        self.GX = _finite_or_fail(pb.step(self.X))
        self.res = pb.residual(self.X, self.GX)
        self.e_gx = pb.energy(self.GX) if self.history else 0.0

    def accelerated(self, acc: Anderson) -> bool:
        """Peng et al.'s safeguard, on the plain steps' outputs: those meet the seam
        constraints, so their energies compare (mixed iterates' do not). True when the
        accelerated iterate was kept; else the history restarts."""
        pb = self.pb
        Xa = acc.next(self.X.ravel(), self.GX.ravel()).reshape(pb.n, 2)
        GXa = pb.step(Xa) if np.all(np.isfinite(Xa)) else Xa
        e_a = pb.energy(GXa) if np.all(np.isfinite(GXa)) else np.inf
        if e_a < self.e_gx:
            self.X, self.GX, self.e_gx = Xa, GXa, e_a
            self.res = pb.residual(self.X, self.GX)
            return True
        acc.reset()
        return False

    def newton(self, *, max_cg: int, rtol: float) -> tuple[bool, float]:
        """A Newton step (:meth:`_Problem.newton`) from ``X``, kept, like an accelerated
        iterate, when the energy after a plain step from it is below the plain step's;
        where it is not, the step halved up to ``tol.NEWTON_BACKTRACK`` times (a
        backtracking line search). ``(kept, the largest panel move over the panel's size
        of the last step tried)``."""
        pb = self.pb
        if self.pb._seam_step is not None and self.pb._seam_step.X is not self.X:
            self.GX = pb.step(self.X)  # the seams linearised at X again (after a rejection)
        step = pb.newton(self.X, self.GX, max_cg=max_cg, rtol=rtol)
        if step is None:  # no model: the plain step's move is all there is to judge by
            return False, float(self.res.max(initial=0.0))
        d = step[0] - self.X
        if not np.all(np.isfinite(d)):
            return False, np.inf
        e_gx = self.e_gx if self.history else pb.energy(self.GX)
        t, move = 1.0, 0.0
        for _ in range(tol.NEWTON_BACKTRACK + 1):
            Xn = self.X + t * d
            mv = pb.residual(self.X, Xn)
            move = float(mv.max(initial=0.0))
            GXn = pb.step(Xn)
            e_n = pb.energy(GXn) if np.all(np.isfinite(GXn)) else np.inf
            if e_n < e_gx:
                # the step is the Newton move and the plain step after it, whichever is larger
                res = np.maximum(mv, pb.residual(Xn, GXn))
                self.X, self.GX, self.e_gx, self.res = Xn, GXn, e_n, res
                return True, move
            t *= 0.5
        return False, move


def _crawls(h: list[float], last: int) -> bool:
    """The largest residual fell by less than ``tol.NEWTON_CRAWL`` over the last
    ``tol.NEWTON_WINDOW`` iterations, none of them a Newton step (``last``: the iteration
    count at the last one)."""
    w = tol.NEWTON_WINDOW
    return len(h) - last > w and h[-1] > tol.NEWTON_CRAWL * h[-1 - w]


def _stalls(h: list[float]) -> bool:
    """The largest residual of the last ``ARAP_STALL_ITER`` iterations is no real gain."""
    w = tol.ARAP_STALL_ITER
    return len(h) > 2 * w and min(h[-w:]) > (1.0 - tol.ARAP_STALL_GAIN) * min(h[:-w])


def _iterate(
    pb: _Problem,
    s: _Iterate,
    *,
    max_iter: int,
    step_tol: float,
    history: int,
    newton_cg: int = tol.NEWTON_CG_MAX,
    progress: Callable[[int, float], None] | None = None,
) -> tuple[int, bool, bool, list[float], int]:
    """Local/global iterations from ``s`` (updated); ``(iterations, converged, stalled,
    residual history, Newton steps)``. ``progress(iteration, residual)`` is called once
    per iteration."""
    acc = Anderson(m=history)
    it, converged, stalled, since, last, newton = 0, False, False, 0, 0, 0
    hist: list[float] = []
    while it < max_iter:
        it += 1
        hist.append(float(s.res.max(initial=0.0)))
        if progress is not None:
            progress(it, hist[-1])
        stall = _stalls(hist[since:])
        done = not len(s.res) or s.res.max() <= step_tol
        if stall and pb.seams_settled(s.GX):
            stalled = True  # a long run that no longer improves: stop (deterministically)
            break
        if pb.seams_pending(s.GX):  # from the first iteration that misses a seam
            since = last = len(hist)  # the constrained iterations get their own windows
            pb.seams_on()
            acc.reset()
            s.plain()
            continue
        # Where the steps crawl, a Newton step; and a run that took one ends only when a
        # Newton step moves no more than the tolerance either (a crawl's small steps say
        # little of the distance left). A run that converges fast never takes one.
        if newton_cg and (_crawls(hist, last) or (done and newton)):
            last = len(hist)
            kept, move = s.newton(max_cg=newton_cg, rtol=tol.NEWTON_CG_RTOL)
            newton += kept
            if done and (move <= step_tol or not kept):
                # converged: the Newton step is below the tolerance, or no step along it
                # lowers the energy (the model has nothing better than the plain steps)
                converged = True
                break
            if kept:
                acc.reset()
                continue
        if done and not newton:
            converged = True
            break
        if history and s.accelerated(acc):
            continue
        s.plain()
    return it, converged, stalled, hist, newton


def stitch(
    V2: np.ndarray,
    F2: np.ndarray,
    targets: np.ndarray,
    *,
    pins: np.ndarray,
    vertex_panel: np.ndarray | None = None,
    asap_faces: np.ndarray | None = None,
    asap_exclude: np.ndarray | None = None,
    ease: SeamEase | None = None,
    panel_weight: np.ndarray | None = None,
    w_pin: float = tol.W_PIN,
    w_asap: float = tol.W_ASAP,
    max_iter: int = tol.ARAP_MAX_ITER,
    step_tol: float = tol.ARAP_STEP_TOL,
    history: int = tol.ANDERSON_HISTORY,
    newton_cg: int = tol.NEWTON_CG_MAX,
    progress: Callable[[int, float], None] | None = None,
) -> tuple[np.ndarray, StitchInfo]:
    """Stitch per-triangle targets into continuous panels.

    Local/global iterations (Liu et al. 2008) accelerated by Anderson mixing (Peng et al.
    2018) with their safeguard: an accelerated iterate is kept only when the energy after
    a plain step from it falls below the energy after the plain step it replaces (both
    meet the seam constraints, so they compare); else the history restarts. The result
    is always a plain step's output, so the constraints hold at the last linearisation.

    Parameters
    ----------
    V2 : (n, 2) float array
        Original pattern (counter-clockwise triangles); the start, the pin positions and
        the as-similar-as-possible chord normals come from it.
    F2 : (m, 3) int array
    targets : (m, 2, 2) float array
        Target edge matrices in the original pattern's frame.
    pins : (p,) int array
        One pinned vertex per panel.
    vertex_panel : (n,) int array, optional
        Panel of each vertex (-1 unused); default the connected components of ``F2``.
    asap_faces : (k,) int array, optional
        Triangles of the panels that keep their outline shape (as-similar-as-possible).
    asap_exclude : (n,) bool array, optional
        Outline vertices left free even on those panels.
    ease : SeamEase, optional
        Seam-length constraints (:func:`ptailor.method.ease.seam_ease`), enforced exactly
        with Lagrange multipliers and their curvature: each global step is a
        sequential-quadratic-programming step solved through a Schur complement on the one
        factorisation (:meth:`_Problem._constrained`). They switch on at the first
        iteration where a seam misses its ratio by more than ``tol.SEAM_EXACT_REL`` (an
        identity edit or a uniform scale never pays for them).
    panel_weight : (n_panels,) float array, optional
        Each panel's whole energy (ARAP, pin, as-similar-as-possible) is scaled by its
        weight. A panel alone comes out the same; where seam constraints tie panels, a
        heavier one takes less of the distortion. Default all 1.
    w_pin, w_asap : float
        Term weights.
    max_iter : int
        Local/global iterations at most.
    step_tol : float
        Converged when no panel's last step moved a vertex (after removing the panel's
        rigid motion) by more than this fraction of the panel's size.
    history : int
        Anderson history length; 0 for plain local/global.
    newton_cg : int
        Conjugate-gradient iterations at most of a Newton step (:meth:`_Problem.newton`),
        taken where the largest residual fell by less than ``tol.NEWTON_CRAWL`` over
        ``tol.NEWTON_WINDOW`` iterations; 0 for none.
    progress : callable, optional
        ``progress(iteration, residual)``, called once per iteration (the largest panel
        residual before it): a progress line's feed. Nothing else depends on it.

    Returns
    -------
    X : (n, 2) float array
        Stitched positions; vertices no triangle uses keep their original position.
    info : StitchInfo
    """
    pb = _Problem(
        V2,
        F2,
        targets,
        pins=pins,
        vertex_panel=vertex_panel,
        asap_faces=asap_faces,
        asap_exclude=asap_exclude,
        ease=ease,
        panel_weight=panel_weight,
        w_pin=w_pin,
        w_asap=w_asap,
    )
    X0 = pb.global_step(np.ones(len(F2)), np.zeros(len(F2)), None)  # identity rotations
    s = _Iterate(pb, _finite_or_fail(X0), history)
    it, converged, stalled, hist, newton = _iterate(
        pb,
        s,
        max_iter=max_iter,
        step_tol=step_tol,
        history=history,
        newton_cg=newton_cg,
        progress=progress,
    )
    X = s.GX  # a plain step: the constraints hold at the last linearisation
    X[~pb.used] = V2[~pb.used]
    pb._rot, pb._twist_at = (None, None), None  # X changed in place
    viol = float(pb.ease.violation(X).max()) if pb.ease is not None else 0.0
    if viol > tol.SEAM_EXACT_REL:
        converged = False  # the cap came before the seams were enforced, or they were skipped
    return X, StitchInfo(
        iterations=it,
        energy=pb.energy(X),
        converged=converged,
        panel_residual=s.res,
        seam_violation=viol,
        history=tuple(hist),
        stalled=stalled,
        newton_steps=newton,
    )
