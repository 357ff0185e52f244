"""When a re-drape has settled: speed and displacement over a window.

A re-drape is settled when, at ``settle_checks`` settle checks in a row (``check_every``
steps apart), the free vertices' 95th-percentile speed is below ``settle_speed``, and their
95th-percentile displacement over the last ``settle_window`` steps is below
``settle_move``. The speed alone reads the velocity at the check's instant (damped each
step by the drag); the displacement over a window sees a garment that creeps or swings
between the checks. :class:`Settle` counts the checks and says why it settled or not
(:meth:`Settle.record`), without the engine: it sees only positions and velocities.
"""

from __future__ import annotations

from collections import deque

import numpy as np

__all__ = ["Settle"]


def _p95(x: np.ndarray) -> float:
    """The 95th percentile of ``x`` (0 for none)."""
    return float(np.percentile(x, 95)) if len(x) else 0.0


class Settle:
    """Settle checks of one re-drape (SI units: m, m/s).

    Parameters
    ----------
    settings : ptailor.verify.engine.Settings
        ``check_every``, ``settle_speed``, ``settle_checks``, ``settle_window``,
        ``settle_move`` (a window of 0 or a move of 0 turns the displacement test off).
    free : (n,) bool array
        The vertices that may move (not pinned, used by a face).

    Attributes
    ----------
    speed : (n,) float array
        Every vertex's speed at the last check (0 for the others), m/s.
    speed_p95 : float
        The free vertices' 95th-percentile speed at the last check, m/s.
    move_p95 : float or None
        Their 95th-percentile displacement over the last window, m (None until a window
        has passed).
    """

    def __init__(self, settings, free: np.ndarray) -> None:
        self.s = settings
        self.free = np.asarray(free, dtype=bool)
        self.run = 0
        self.speed = np.zeros(len(self.free))
        self.speed_p95 = 0.0
        self.move_p95: float | None = None
        self.window_steps = self._window_checks() * settings.check_every
        self.history: deque = deque(maxlen=self._window_checks() + 1)

    def _window_checks(self) -> int:
        """Checks per window (0: no displacement test)."""
        s = self.s
        if s.settle_window <= 0 or s.settle_move <= 0:
            return 0
        return max(int(np.ceil(s.settle_window / s.check_every)), 1)

    def check(self, q: np.ndarray, qd: np.ndarray) -> bool:
        """Record one check of positions ``q`` and velocities ``qd`` (n, 3); True once
        settled."""
        self.speed = np.where(self.free, np.linalg.norm(qd, axis=1), 0.0)
        self.speed_p95 = _p95(self.speed[self.free])
        if self.history.maxlen > 1:
            self.history.append(np.asarray(q, dtype=float)[self.free])
            if len(self.history) == self.history.maxlen:
                self.move_p95 = _p95(np.linalg.norm(self.history[-1] - self.history[0], axis=1))
        slow = self.speed_p95 < self.s.settle_speed
        self.run = self.run + 1 if slow else 0
        return self.run >= self.s.settle_checks and self.still()

    def still(self) -> bool:
        """Whether the displacement test passes (always, when it is off)."""
        if self.history.maxlen <= 1:
            return True
        return self.move_p95 is not None and self.move_p95 < self.s.settle_move

    def record(self, *, settled: bool, steps: int, units_m: float) -> dict:
        """Why it settled or did not, in the garment's units.

        Parameters
        ----------
        settled : bool
        steps : int
            Steps taken.
        units_m : float
            Metres per garment unit.

        Returns
        -------
        dict
            ``{"speed_p95", "speed_limit"}`` (garment units per second) and, with the
            displacement test, ``{"move_p95", "move_limit"}`` (garment units) over
            ``"window_steps"``; ``"why"``: a sentence.
        """
        s = self.s
        out = {
            "speed_p95": self.speed_p95 / units_m,
            "speed_limit": s.settle_speed / units_m,
        }
        slow = self.run >= s.settle_checks
        reasons = [
            f"speed p95 {1000 * self.speed_p95:.3g} mm/s "
            f"{'<' if self.speed_p95 < s.settle_speed else '>='} {1000 * s.settle_speed:g}"
            + ("" if slow or settled else f" (slow on {self.run} of {s.settle_checks} checks)")
        ]
        if self.window_steps:
            out.update(window_steps=self.window_steps, move_limit=s.settle_move / units_m)
            if self.move_p95 is None:
                out["move_p95"] = None
                reasons.append(f"fewer than {self.window_steps} steps: no displacement window")
            else:
                out["move_p95"] = self.move_p95 / units_m
                sign = "<" if self.move_p95 < s.settle_move else ">="
                reasons.append(
                    f"moved p95 {1000 * self.move_p95:.3g} mm over the last "
                    f"{self.window_steps} steps {sign} {1000 * s.settle_move:g}"
                )
        head = f"settled at step {steps}" if settled else f"not settled at the cap ({steps} steps)"
        out["why"] = f"{head}: {'; '.join(reasons)}"
        return out
