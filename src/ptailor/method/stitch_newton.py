"""The Newton step of the stitching (:class:`_NewtonModel`, part of
:class:`ptailor.method.stitch._Problem`): the energy's projected Hessian and conjugate
gradients preconditioned by the local/global step's own system, taken where the
local/global steps crawl."""

from __future__ import annotations

import numpy as np

from ptailor.method.stitch_seams import _SeamStep


class _NewtonModel:
    """The Newton half of :class:`ptailor.method.stitch._Problem`."""

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
