"""The frame of an adjusted specification panel: its carried outline with the rotation and
translation undone.

The carried panel is put back in the panel's own frame by undoing the rotation and
translation of the similarity that best fits its outline before onto after; its scale stays,
about the frame's origin.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor import tolerances as tol
from ptailor.spec.match import PanelMatch

__all__ = ["PanelFrame", "panel_frame", "similarity"]


def similarity(
    X: np.ndarray, W: np.ndarray, *, scale: float
) -> tuple[np.ndarray, np.ndarray, float]:
    """The similarity ``W ~ s X @ Q.T + b`` (rotation ``Q``, no reflection) fitted to the
    closed outline ``X -> W`` where it fits: least squares weighted by each point's share of
    the outline's length (so a finer mesh weighs the same), then
    :data:`ptailor.tolerances.SPEC_IRLS_ROUNDS` reweightings by ``1 / (1 + (r / scale)^2)``
    (Cauchy): the part of a panel an edit left alone holds it in place, however much the
    rest moved.

    Parameters
    ----------
    X, W : (n, 2) float arrays
        The outline before and after, point for point.
    scale : float, keyword-only
        The residual at which a point's weight halves.

    Returns
    -------
    Q : (2, 2) float array
    b : (2,) float array
    s : float
    """
    seg = np.linalg.norm(np.roll(X, -1, axis=0) - X, axis=1)
    length = 0.5 * (seg + np.roll(seg, 1))
    w = length / max(float(length.sum()), tol.TINY)
    wk = w
    for _ in range(tol.SPEC_IRLS_ROUNDS + 1):
        cx, cw = wk @ X / wk.sum(), wk @ W / wk.sum()
        a, c = X - cx, W - cw
        H = (a * wk[:, None]).T @ c
        U, _, Vt = np.linalg.svd(H)
        D = np.diag([1.0, np.sign(np.linalg.det(Vt.T @ U.T)) or 1.0])
        Q = Vt.T @ D @ U.T
        s = float(np.sum(wk[:, None] * c * (a @ Q.T)) / max(float(wk @ (a * a).sum(1)), tol.TINY))
        b = cw - s * (Q @ cx)
        r = np.linalg.norm(W - (s * X @ Q.T + b), axis=1)
        wk = w / (1.0 + (r / scale) ** 2)
    return Q, b, s


@dataclass(frozen=True)
class PanelFrame:
    """Pattern <-> new panel frame for one panel: ``Z = Q.T (to_spec(Y) - b)``."""

    m: PanelMatch
    k: float
    Q: np.ndarray
    b: np.ndarray

    def to_frame(self, Y: np.ndarray) -> np.ndarray:
        """Adjusted pattern points ``(j, 2)`` to the new panel's frame."""
        return (self.m.to_spec(Y, self.k) - self.b) @ self.Q

    def to_pattern(self, Z: np.ndarray) -> np.ndarray:
        """Points ``(j, 2)`` of the new panel's frame to the adjusted pattern."""
        return self.m.to_pattern(Z @ self.Q.T + self.b, self.k)

    def affine(self) -> tuple[np.ndarray, np.ndarray]:
        """``(A (2, 2), b (2,))``: the frame to the pattern, ``Y = X @ A.T + b``."""
        A = self.k * self.m.R @ self.Q
        b = self.m.to_pattern(self.b[None], self.k)[0]
        return A, b


def panel_frame(
    m: PanelMatch, k: float, Y0: np.ndarray, Y1: np.ndarray, *, scale: float
) -> PanelFrame:
    """The frame that undoes the rotation and translation of the similarity taking the
    outline ``Y0`` (pattern before, computation units) onto ``Y1`` (after)."""
    X, W = m.to_spec(Y0, k), m.to_spec(Y1, k)
    Q, b, _ = similarity(X, W, scale=scale)
    return PanelFrame(m, k, Q, b)
