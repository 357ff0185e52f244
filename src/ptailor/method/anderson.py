"""Anderson acceleration of a fixed-point iteration ``x <- g(x)``.

Peng et al. 2018, "Anderson Acceleration for Geometry Optimization and Physics
Simulation": keep the last ``m`` iterates and their images, and step to the image of the
combination of iterates whose residual ``g(x) - x`` is least. The caller safeguards each
accelerated step (it keeps the plain image ``g(x)`` to fall back on).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ptailor import tolerances as tol
from ptailor.method import tolerances as method_tol


@dataclass
class Anderson:
    """History of a fixed-point iteration and its accelerated next iterate.

    The differences of the last residuals and images are kept with their Gram matrix,
    updated by one column per step: a step costs ``O(m N)``, not ``O(m^2 N)``.

    Attributes
    ----------
    m : int
        History length (differences kept).
    """

    m: int = 5
    _gram: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    _f: np.ndarray | None = None
    _g: np.ndarray | None = None
    _DF: np.ndarray | None = None  # (m, N): row j the j-th residual difference (ring buffer)
    _DG: np.ndarray | None = None  # (m, N): the image differences, same rows
    _slot: list[int] = field(default_factory=list)  # buffer row of each kept difference

    def reset(self) -> None:
        """Forget the history (after a rejected step)."""
        self._slot.clear()
        self._gram = np.zeros((0, 0))
        self._f = self._g = None

    def _record(self, f: np.ndarray, gx: np.ndarray) -> None:
        """Append the differences to the last residual and image; drop the oldest."""
        if self._f is not None:
            if self._DF is None or self._DF.shape[1] != len(f):
                self._DF = np.empty((self.m, len(f)))
                self._DG = np.empty((self.m, len(f)))
            H = self._gram
            slot = len(self._slot)
            if slot == self.m:  # the oldest row is reused
                slot = self._slot.pop(0)
                H = H[1:, 1:]
            df, dg = self._DF[slot], self._DG[slot]
            np.subtract(f, self._f, out=df)
            np.subtract(gx, self._g, out=dg)
            self._slot.append(slot)
            col = self._DF[self._slot] @ df  # one matrix-vector product for the new column
            k = len(col)
            Hn = np.empty((k, k))
            Hn[:-1, :-1] = H
            Hn[-1], Hn[:, -1] = col, col
            self._gram = Hn
        self._f, self._g = f, gx

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
        if not self.m:
            return gx
        with np.errstate(all="ignore"):
            f = gx - x
            self._record(f, gx)
            if not self._slot:
                return gx
            # least squares min |f_k - dF gamma|, scaled columns and a tiny ridge for stability
            s = np.maximum(np.sqrt(np.diag(self._gram)), tol.TINY)
            H = self._gram / s[:, None] / s[None, :]
            H[np.diag_indices_from(H)] += method_tol.ANDERSON_RIDGE
            rhs = (self._DF[self._slot] @ f) / s
            try:
                gamma = np.linalg.solve(H, rhs) / s
            except (np.linalg.LinAlgError, ValueError):
                gamma = np.full(len(s), np.nan)
            out = gx
            if np.all(np.isfinite(gamma)):
                out = gx - gamma @ self._DG[self._slot]
        if out is gx or not np.all(np.isfinite(out)):
            self.reset()  # a non-finite mix: fall back to the plain step
            return gx
        return out
