"""Anderson acceleration of a fixed-point iteration ``x <- g(x)``.

Peng et al. 2018, "Anderson Acceleration for Geometry Optimization and Physics
Simulation": keep the last ``m`` iterates and their images, and step to the image of the
combination of iterates whose residual ``g(x) - x`` is least. The caller safeguards each
accelerated step (it keeps the plain image ``g(x)`` to fall back on).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class Anderson:
    """History of a fixed-point iteration and its accelerated next iterate.

    Attributes
    ----------
    m : int
        History length (differences kept).
    """

    m: int = 5
    _x: list[np.ndarray] = field(default_factory=list)
    _g: list[np.ndarray] = field(default_factory=list)

    def reset(self) -> None:
        """Forget the history (after a rejected step)."""
        self._x.clear()
        self._g.clear()

    def next(self, x: np.ndarray, gx: np.ndarray) -> np.ndarray:
        """Record ``(x, g(x))`` and return the accelerated next iterate.

        Parameters
        ----------
        x, gx : (N,) float arrays
            An iterate and its image.

        Returns
        -------
        (N,) float array
            ``gx`` itself while the history holds a single iterate.
        """
        self._x.append(x)
        self._g.append(gx)
        if len(self._x) > self.m + 1:
            self._x.pop(0)
            self._g.pop(0)
        if len(self._x) < 2:
            return gx
        X = np.stack(self._x, 1)
        G = np.stack(self._g, 1)
        F = G - X
        dF = np.diff(F, axis=1)
        dG = np.diff(G, axis=1)
        # least squares min |f_k - dF gamma|, scaled columns and a tiny ridge for stability
        with np.errstate(all="ignore"):
            s = np.maximum(np.linalg.norm(dF, axis=0), 1e-300)
            A = dF / s
            H = A.T @ A
            H[np.diag_indices_from(H)] += 1e-10
            try:
                gamma = np.linalg.solve(H, A.T @ F[:, -1]) / s
            except (np.linalg.LinAlgError, ValueError):
                gamma = np.full(len(s), np.nan)
            out = gx - dG @ gamma if np.all(np.isfinite(gamma)) else gx
        if out is gx or not np.all(np.isfinite(out)):
            self.reset()  # a non-finite mix: fall back to the plain step
            return gx
        return out
