"""The stitching's iteration: local/global steps from an iterate, with Newton steps where
they crawl (:func:`iterate` over an :class:`Iterate`).

Local/global iterations (Liu et al. 2008) accelerated by Anderson mixing (Peng et al.
2018) with their safeguard: an accelerated iterate is kept only when the energy after a
plain step from it falls below the energy after the plain step it replaces (both meet the
seam constraints, so they compare); else the history restarts.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ptailor.method import tolerances as method_tol
from ptailor.method.anderson import Anderson


def finite_or_fail(Y: np.ndarray) -> np.ndarray:
    """``Y`` itself where every entry is finite.

    Raises
    ------
    PtailorError
        A non-finite entry: the solver diverged.
    """
    if not np.all(np.isfinite(Y)):
        from ptailor.errors import NumericError

        raise NumericError(
            "the stitching solver diverged (non-finite positions); check the "
            "flatten weights and the edit"
        )
    return Y


class Iterate:
    """The iteration's current point and its plain step, with their measures.

    Parameters
    ----------
    pb : Problem
        The stitching problem (:class:`ptailor.method.solver.problem.Problem`).
    X : (n, 2) float array
        The first point.
    history : int
        Anderson history length (0: the plain steps' energies are not needed).

    Attributes
    ----------
    X, GX : (n, 2) float arrays
        The current point and the plain step from it (new arrays on every move: never
        changed in place).
    res : (n_panels,) float array
        Each panel's move from ``X`` to ``GX``, rigid motion removed, over its size.
    e_gx : float
        The energy at ``GX`` (0 without a history).
    """

    def __init__(self, pb, X: np.ndarray, history: int) -> None:
        self.pb, self.history = pb, history
        self.X = X
        self.GX = finite_or_fail(pb.step(X))
        self.res = pb.residual(self.X, self.GX)
        self.e_gx = pb.energy(self.GX) if history else 0.0

    def plain(self) -> None:
        """Move to the plain step's output and take the next plain step."""
        pb = self.pb
        self.X = self.GX
        self.GX = finite_or_fail(pb.step(self.X))
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
        """A Newton step (:meth:`ptailor.method.solver.newton.NewtonModel.newton`) from
        ``X``, kept, like an accelerated iterate, when the energy after a plain step from it
        is below the plain step's; where it is not, the step halved up to
        ``method_tol.NEWTON_BACKTRACK`` times (a backtracking line search). ``(kept, the largest
        panel move over the panel's size of the last step tried)``."""
        pb = self.pb
        if pb.seam_step is not None and pb.seam_step.X is not self.X:
            self.GX = pb.step(self.X)  # the seams linearised at X again (after a rejection)
        step = pb.newton(self.X, self.GX, max_cg=max_cg, rtol=rtol)
        if step is None:  # no model: the plain step's move is all there is to judge by
            return False, float(self.res.max(initial=0.0))
        d = step[0] - self.X
        if not np.all(np.isfinite(d)):
            return False, np.inf
        e_gx = self.e_gx if self.history else pb.energy(self.GX)
        t, move = 1.0, 0.0
        for _ in range(method_tol.NEWTON_BACKTRACK + 1):
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
    """The largest residual fell by less than ``method_tol.NEWTON_CRAWL`` over the last
    ``method_tol.NEWTON_WINDOW`` iterations, none of them a Newton step (``last``: the iteration
    count at the last one)."""
    w = method_tol.NEWTON_WINDOW
    return len(h) - last > w and h[-1] > method_tol.NEWTON_CRAWL * h[-1 - w]


def _stalls(h: list[float]) -> bool:
    """The largest residual of the last ``ARAP_STALL_ITER`` iterations is no real gain."""
    w = method_tol.ARAP_STALL_ITER
    return len(h) > 2 * w and min(h[-w:]) > (1.0 - method_tol.ARAP_STALL_GAIN) * min(h[:-w])


def iterate(
    pb,  # the stitching problem, ptailor.method.solver.problem.Problem
    s: Iterate,
    *,
    max_iter: int,
    step_tol: float,
    history: int,
    newton_cg: int = method_tol.NEWTON_CG_MAX,
    progress: Callable[[int, float], None] | None = None,
) -> tuple[int, bool, bool, list[float], int]:
    """Local/global iterations from ``s`` (updated).

    Parameters
    ----------
    pb : Problem
        The stitching problem (:class:`ptailor.method.solver.problem.Problem`).
    s : Iterate
        The start; the last point on return.
    max_iter, step_tol, history, newton_cg : int, float, int, int
        :func:`ptailor.method.solver.stitch`'s settings.
    progress : callable, optional
        ``progress(iteration, residual)``, called once per iteration.

    Returns
    -------
    tuple
        ``(iterations, converged, stalled, residual history, Newton steps)``.
    """
    acc = Anderson(m=history)
    it, converged, stalled, since, last, newton = 0, False, False, 0, 0, 0
    short = True  # a confirming Newton step may stop early, until one of them moves on
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
            # a step that only confirms (done) needs the slowest mode alone: few iterations
            confirm = done and short
            cg = min(newton_cg, method_tol.NEWTON_CONFIRM_CG) if confirm else newton_cg
            kept, move = s.newton(max_cg=cg, rtol=method_tol.NEWTON_CG_RTOL)
            short = short and not (confirm and kept and move > step_tol)
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
