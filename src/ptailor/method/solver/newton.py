"""The Newton step of the stitching (:class:`NewtonModel`, part of
:class:`ptailor.method.solver.problem.Problem`): the energy's projected Hessian and
conjugate gradients preconditioned by the local/global step's own system, taken where the
local/global steps crawl."""

from __future__ import annotations

import numpy as np

from ptailor.method.solver.seams import SeamStep

#: ``(cos, sin, area * alpha)`` per triangle at one iterate (:meth:`NewtonModel._twist`)
Twist = tuple[np.ndarray, np.ndarray, np.ndarray]


class NewtonModel:
    """The Newton half of :class:`ptailor.method.solver.problem.Problem` (a mixin: it reads
    the problem's public attributes, ``D``, ``Dt``, ``m``, ``n``, ``area``, ``pin_w``,
    ``bend_H``, ``B``, ``w_asap``, ``seam_block``, ``seam_step``, and its
    :meth:`rotations` and :meth:`project`), keeping nothing between calls."""

    def _rotation_hessian(self, tw: Twist, V: np.ndarray) -> np.ndarray:
        """The part of the energy's Hessian the local/global step leaves out, applied to
        ``V (n, 2)``: ``sum_i A_i alpha_i (t_i . J_i(V)) D_i^T t_i`` (half-energy units).

        At the closest rotation ``R_i`` (angle ``theta``) of ``J_i``, ``R_i`` turns with
        ``J_i`` along ``t_i = dR/dtheta`` only, at the rate ``1 / r_i`` (``r_i = s1 + s2``,
        the sum of ``J_i``'s singular values): the Hessian of ``|J - R(J)|^2 / 2`` is
        ``I - t t^T / r``, whose one eigenvalue below 1 is the twist's, ``1 - 2 / r``.
        Projected onto the positive semi-definite cone (Teran et al.'s per-element
        projection): ``alpha = 1 / r`` where ``r >= 2``, ``1/2`` (the twist free) where
        the triangle is compressed. ``tw``: :meth:`_twist` at the iterate."""
        return self.Dt @ self._rotation_weights(tw, self.D @ V)

    def _rotation_weights(self, tw: Twist, JV: np.ndarray) -> np.ndarray:
        """:meth:`_rotation_hessian` before ``D^T``, from ``JV = D V``, ``(2m, 2)``."""
        cos, sin, w = tw
        m = self.m
        # t = [[-sin, -cos], [cos, -sin]] in J's (coordinate, target axis) layout
        coef = w * (cos * (JV[:m, 1] - JV[m:, 0]) - sin * (JV[:m, 0] + JV[m:, 1]))
        W = np.empty((2 * m, 2))
        W[:m, 0], W[:m, 1] = -sin * coef, cos * coef
        W[m:, 0], W[m:, 1] = -cos * coef, -sin * coef
        return W

    def _twist(self, X: np.ndarray) -> Twist:
        """``(cos, sin, area * alpha)`` of :meth:`_rotation_hessian` at ``X`` (computed once
        per Newton step: its conjugate-gradient iterations are all at one ``X``)."""
        J, cos, sin = self.rotations(X)
        m = self.m
        r = np.hypot(J[:m, 0] + J[m:, 1], J[:m, 1] - J[m:, 0])
        alpha = np.where(r >= 2.0, 1.0 / np.maximum(r, 2.0), 0.5)
        return cos, sin, self.area * alpha

    def hessian(
        self, X: np.ndarray, V: np.ndarray, seam: SeamStep | None, tw: Twist | None = None
    ) -> np.ndarray:
        """The projected Hessian of the half energy with the seams' curvature at ``X``,
        applied to ``V (n, 2)``: one product with ``D`` and one with ``D^T``.

        Parameters
        ----------
        X, V : (n, 2) float arrays
            The iterate, and the direction.
        seam : SeamStep or None
            The seams' linearisation at ``X`` (its curvature rows), None without.
        tw : tuple of arrays, optional
            :meth:`_twist` at ``X``, where the caller has it (default: computed).

        Returns
        -------
        (n, 2) float array
        """
        JV = self.D @ V
        W = self._rotation_weights(self._twist(X) if tw is None else tw, JV)
        JV[: self.m] *= self.area[:, None]
        JV[self.m :] *= self.area[:, None]
        JV -= W
        out = self.Dt @ JV + self.pin_w[:, None] * V
        if self.bend_H is not None:
            out += self.bend_H @ V
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
            seam = self.seam_step
            if seam is None or seam.X is not X:
                return None
        d = GX - X
        tw = self._twist(X)
        res = -self._rotation_hessian(tw, d)  # the model's gradient at d, C^T lam left out
        z = self.project(res, seam)
        rz = rz0 = float((res * z).sum())
        if not rz > 0:
            return GX, 0
        p = -z
        k = 0
        while k < max_cg:
            k += 1
            Hp = self.hessian(X, p, seam, tw)
            curv = float((p * Hp).sum())
            if not curv > 0:
                break
            a = rz / curv
            d += a * p
            res += a * Hp
            z = self.project(res, seam)
            rz_new = float((res * z).sum())
            if not rz_new > rtol * rtol * rz0:
                break
            p = -z + (rz_new / rz) * p
            rz = rz_new
        return X + d, k
