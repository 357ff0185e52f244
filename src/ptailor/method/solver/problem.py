"""The stitching problem (:func:`ptailor.method.solver.stitch`'s system, :class:`Problem`):
the panels' index, the matrix and its factor, the local step, the energy; the seam
constraints and the Newton step come from :mod:`ptailor.method.solver.seams` and
:mod:`ptailor.method.solver.newton`, the iteration that drives it from
:mod:`ptailor.method.solver.iteration`.
"""

from __future__ import annotations

from functools import cached_property

import numpy as np
import scipy.sparse as sp

from ptailor import tolerances as tol
from ptailor.geometry.closed_forms import det2
from ptailor.method import tolerances as method_tol
from ptailor.method.bend import SeamBend, seam_bend
from ptailor.method.ease import SeamEase
from ptailor.method.operators import asap_rows, gradient_operator, stitch_matrix
from ptailor.method.solver.linear import factor
from ptailor.method.solver.newton import NewtonModel
from ptailor.method.solver.seam_block import SeamBlock
from ptailor.method.solver.seams import SeamConstraints, SeamStep, Solved, split_solver
from ptailor.method.solver.symbolic import SymbolicCache


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


def panel_sizes(V2: np.ndarray, vlab: np.ndarray, n_panels: int) -> np.ndarray:
    """Bounding-box diagonal per panel, for a scale-free convergence test.

    Parameters
    ----------
    V2 : (n, 2) float array
    vlab : (n,) int array
        Panel of each vertex, -1 for vertices no triangle uses.
    n_panels : int

    Returns
    -------
    (max(n_panels, 1),) float array
        Each panel's diagonal (1 where there is no panel; never 0).
    """
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
        size = np.maximum(np.linalg.norm(hi - lo, axis=1), tol.TINY)
    return size


def _solver(A: sp.csc_matrix, n: int, symbolic: SymbolicCache | None = None):
    """``A^-1`` applied to columns over unknowns ``[x; y]``, from one factorisation of the
    stitching matrix's lower triangle ``A`` (``n x n`` when x and y decouple, ``2n x 2n``
    when coupled; its analysis shared through ``symbolic``)."""
    solve = factor(A, lower=True, symbolic=symbolic)
    if A.shape[0] == 2 * n:
        return solve

    def solve_many(rhs: np.ndarray) -> np.ndarray:
        # x and y decouple: one n x n factor serves both coordinates
        c = rhs.shape[1]
        sol = solve(np.concatenate([rhs[:n], rhs[n:]], axis=1))
        return np.concatenate([sol[:, :c], sol[:, c:]], axis=0)

    return solve_many


class PanelIndex:
    """The used vertices grouped by panel, for per-panel rigid fits and maxima.

    Parameters
    ----------
    vlab : (n,) int array
        Panel of each vertex, -1 for vertices no triangle uses.
    n_panels : int
    """

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


class Problem(SeamConstraints, NewtonModel):
    """The stitching energy of one pattern: its factored matrix, steps and measures (the
    seam constraints' steps from :class:`SeamConstraints`, the Newton step from
    :class:`NewtonModel`).

    The arguments are :func:`ptailor.method.solver.stitch`'s. What the package's other
    modules read besides the steps: ``V2``, ``n``, ``m``, ``pins``, ``vlab``, ``used``
    (vertices a triangle uses), ``area`` (each triangle's weighted target area), ``pin_w``,
    ``B`` and ``w_asap`` (the as-similar-as-possible rows and weight), ``D`` and :attr:`Dt`
    (the gradient operator and its transpose), ``ease``, ``bend`` and ``bend_H`` (the seam
    sides' bending and its ``(n, n)`` matrix), ``split`` (the factor that orders the seam
    unknowns last, or None), ``seam_block`` (None until the seams switch on) and
    ``seam_step`` (the last constrained step's rows, :meth:`constrained`'s).

    Iterates are never changed in place: :meth:`rotations` keeps the last ``X``'s by
    identity.
    """

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
        symbolic: SymbolicCache | None = None,
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
        self.size = panel_sizes(V2, vlab, n_panels)
        self.bend: SeamBend | None = None
        if self.ease is not None and method_tol.SEAM_BEND > 0:
            mu = np.zeros(n)
            mu[used] = method_tol.SEAM_BEND * self.size[vlab[used]] ** 3 * stiff[vlab[used]]
            self.bend = seam_bend(F2, targets, self.ease.vertices(), mu, np.maximum(vlab, 0))
        self.bend_H = None if self.bend is None else self.bend.matrix()  # (n, n)
        self._bend_M = None if self.bend is None else sp.tril(self.bend_H)
        # the seam block, if the seams switch on, factors the matrix once more: assembled
        # again then rather than held through the iterations (15 MB at 300k triangles)
        self._F2, self._targets = F2, targets
        A = self.matrix()
        # with seam constraints, one factorisation that eliminates the seam unknowns last
        verts = None if self.ease is None else self.ease.vertices()
        self.split = None if verts is None else split_solver(A, n, verts, symbolic)
        split = self.split
        self.solve_many = split.solve_many if split is not None else _solver(A, n, symbolic)
        del A
        # the seam constraints switch on at the first iteration that misses a seam (an
        # identity edit or a uniform scale never pays for them)
        self.seam_block: SeamBlock | None = None
        self.pin_rhs = pin_w[:, None] * V2
        self._panels = PanelIndex(vlab, n_panels)
        self._rot: tuple = (None, None)  # the last iterate's rotations, for reuse
        self.seam_step: SeamStep | None = None  # the last constrained step's rows

    def _asap(self, V2, F2, asap_faces, asap_exclude, panel_weight, stiff):
        """The as-similar-as-possible rows (weighted by panel), or None without any."""
        B = None
        if asap_faces is not None and len(asap_faces):
            B = asap_rows(V2, F2, np.asarray(asap_faces), exclude=asap_exclude)
            if panel_weight is not None and B.shape[0]:
                B = sp.diags(np.sqrt(stiff[self.vlab[B.indices[B.indptr[:-1]] % self.n]])) @ B
        return None if B is None or B.shape[0] == 0 else B

    def matrix(self) -> sp.csc_matrix:
        """The lower triangle of the stitching system (with the seam sides' bending),
        assembled again on each call."""
        A = stitch_matrix(self._F2, self._targets, self.area, self.pin_w, self.B, self.w_asap)
        if self._bend_M is None:
            return A
        L = self._bend_M if A.shape[0] == self.n else sp.block_diag([self._bend_M] * 2)
        return sp.csc_matrix(A + L)

    @cached_property
    def Dt(self) -> sp.csc_matrix:
        """``D^T``, a view of ``D``'s arrays (the transpose object built once, not per step)."""
        return self.D.T

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """``A^-1 rhs`` for one vector over ``[x; y]``, ``(2n,)``."""
        return self.solve_many(rhs[:, None])[:, 0]

    def rotations(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(J, cos, sin)``: the Jacobians ``(2m, 2)`` (``D @ X``) and the closest rotation
        to each (closed form, ``atan2(J10 - J01, J00 + J11)``; identity for ``J = 0``),
        kept for the next call with the same ``X`` (the object: iterates are new arrays)."""
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
        """``E(X)`` (:func:`ptailor.method.solver.stitch`'s energy, with the bending)."""
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
        rhs = self.Dt @ W + self.pin_rhs
        if self.bend is not None:
            rhs = rhs + self.bend.rhs(X_lin)
        if self.seam_block is not None and X_lin is not None:
            y = self.constrained(Solved(self, rhs.T.ravel()), X_lin)
        else:
            y = self.solve(rhs.T.ravel())
        return y.reshape(2, self.n).T

    def step(self, X: np.ndarray) -> np.ndarray:
        """The plain local/global step from ``X`` (the seams linearised at ``X``)."""
        _, cos, sin = self.rotations(X)
        return self.global_step(cos, sin, X)

    def residual(self, X: np.ndarray, GX: np.ndarray) -> np.ndarray:
        """Per panel: the largest vertex move of the step, rigid motion removed, / size."""
        return self._panels.rigid_misfit(GX, X) / self.size
