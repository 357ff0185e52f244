"""The rotations of as-rigid-as-possible cells: the rotation maximising ``trace(R S)``
for a stack of 3x3 matrices, by Newton steps from a guess (:func:`warm_rotations`), the
previous iteration's rotations in :func:`ptailor.method.deform.arap_deform`."""

from __future__ import annotations

import numpy as np

from ptailor.geometry.rotations import max_trace_rotations
from ptailor.method import tolerances as method_tol

__all__ = ["warm_rotations"]

#: see :data:`ptailor.method.tolerances.ROTATION_DONE`
ROTATION_DONE = method_tol.ROTATION_DONE


def _newton_step(M: np.ndarray):
    """One Newton step towards the rotation maximising ``trace(R S)``, from ``M = S R0``.

    Near the maximum, ``trace(R0 exp([w]) S) = trace(E M)`` is about
    ``tr M + g.w - w^T H w / 2`` with ``g = (M12 - M21, M20 - M02, M01 - M10)`` and
    ``H = tr(M) I - sym(M)``; the step is ``w = H^-1 g`` (3x3 adjugate).

    Returns
    -------
    w : (3, k) float array
        The steps (rotation vectors, radians); zero where ``H`` is not positive definite.
    pd : (k,) bool array
        ``H`` is positive definite: ``R0`` is near the maximum, which is unique.
    trace : (k,) float array
        ``trace(R0 exp([w]) S)`` predicted by the quadratic model, ``tr M + g.w / 2``.
    """
    m00, m01, m02, m10, m11, m12, m20, m21, m22 = np.ascontiguousarray(M.reshape(-1, 9).T)
    t = m00 + m11 + m22
    h00, h11, h22 = t - m00, t - m11, t - m22
    h01, h02, h12 = -0.5 * (m01 + m10), -0.5 * (m02 + m20), -0.5 * (m12 + m21)
    g0, g1, g2 = m12 - m21, m20 - m02, m01 - m10
    c00 = h11 * h22 - h12 * h12
    c01 = h02 * h12 - h01 * h22
    c02 = h01 * h12 - h02 * h11
    c11 = h00 * h22 - h02 * h02
    c12 = h01 * h02 - h00 * h12
    c22 = h00 * h11 - h01 * h01
    det = h00 * c00 + h01 * c01 + h02 * c02
    pd = (h00 > 0.0) & (c22 > 0.0) & (det > method_tol.ROTATION_PD_REL * t**3)
    inv = np.divide(1.0, det, out=np.zeros_like(det), where=pd)
    w = np.stack(
        [
            (c00 * g0 + c01 * g1 + c02 * g2) * inv,
            (c01 * g0 + c11 * g1 + c12 * g2) * inv,
            (c02 * g0 + c12 * g1 + c22 * g2) * inv,
        ]
    )
    return w, pd, t + 0.5 * (g0 * w[0] + g1 * w[1] + g2 * w[2])


def _cayley(w: np.ndarray) -> np.ndarray:
    """Rotations ``(k, 3, 3)`` from rotation vectors ``w (3, k)`` by the Cayley transform.

    Exactly orthogonal; the angle is ``2 atan(|w| / 2)``, ``|w|`` to third order, which
    keeps Newton's convergence.
    """
    x, y, z = 0.5 * w
    xx, yy, zz = x * x, y * y, z * z
    c = 2.0 / (1.0 + xx + yy + zz)
    xy, xz, yz = c * x * y, c * x * z, c * y * z
    x, y, z = c * x, c * y, c * z
    E = np.empty((9, w.shape[1]))
    E[0] = 1.0 - c * (yy + zz)
    E[4] = 1.0 - c * (xx + zz)
    E[8] = 1.0 - c * (xx + yy)
    E[1], E[3] = xy - z, xy + z
    E[2], E[6] = xz + y, xz - y
    E[5], E[7] = yz - x, yz + x
    return np.ascontiguousarray(E.T).reshape(-1, 3, 3)  # contiguous: a fast matmul


def warm_rotations(
    S: np.ndarray,
    R0: np.ndarray,
    *,
    steps: int = method_tol.ROTATION_STEPS,
    done: float = ROTATION_DONE,
) -> tuple[np.ndarray, np.ndarray]:
    """Rotations maximising ``trace(R S)`` for a stack ``S (k, 3, 3)``, from guesses ``R0``.

    The same maxima as :func:`ptailor.geometry.rotations.max_trace_rotations` (batched
    SVD), found by Newton steps on the rotations started at ``R0``: in ARAP, the previous
    iteration's rotations, a few hundredths of a radian away, where two or three steps of
    about a tenth of an SVD's cost reach rounding. A rotation is accepted once its last
    step is at most ``done`` radians (the next would be below rounding) and the Hessian
    there is positive definite, which makes it the unique maximum; the others (a guess
    beyond the basin, rank-deficient ``S``) are computed by SVD.

    Parameters
    ----------
    S : (k, 3, 3) float array
    R0 : (k, 3, 3) float array
        Rotations near the maxima.
    steps : int, keyword-only
        Newton steps at most; the loop stops once all but 1 % are accepted.
    done : float, keyword-only

    Returns
    -------
    R : (k, 3, 3) float array
        Proper rotations.
    trace : (k,) float array
        ``trace(R S)``.
    """
    k = S.shape[0]
    R, todo = R0, np.arange(k)
    tr = np.empty(k)
    for _ in range(steps):
        if todo.size <= k // method_tol.ROTATION_SVD_SHARE:
            break
        if (
            method_tol.ROTATION_GATHER_SHARE * todo.size > k
        ):  # most still move: a step on all is cheaper than gathering
            w, pd, tr[:] = _newton_step(S @ R)
            R = R @ _cayley(w)
            todo = np.flatnonzero(~(pd & (np.abs(w).max(axis=0) <= done)))
        else:
            Ra = R[todo]
            w, pd, tr[todo] = _newton_step(S[todo] @ Ra)
            R[todo] = Ra @ _cayley(w)
            todo = todo[~(pd & (np.abs(w).max(axis=0) <= done))]
    if todo.size:
        R = R.copy() if R is R0 else R
        R[todo], tr[todo] = max_trace_rotations(S[todo])
    return R, tr
