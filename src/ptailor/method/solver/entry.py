"""Stitching: glue per-triangle targets into panels (ARAP local/global + ASAP boundary).

Minimises, over all panels at once (the system is block diagonal by panel)::

    E(x) = sum_i A_i |J_i(x) - R_i|_F^2                       as-rigid-as-possible
         + w_pin  sum_(c in C) |x_c - c|^2                     one pinned vertex per panel
         + w_asap sum_(k in B) (n_k . (x_(k+1) - x_(k-1)))^2   as-similar-as-possible

where ``J_i`` is the map from triangle ``i``'s target to its current position (so the first
term is Liu et al. 2008's triangle ARAP energy: cotangent-weighted edge terms), ``R_i`` a
rotation per triangle, ``n_k`` the unit normal of the original boundary chord at ``k``.
The matrix never changes: it is factored once and each iteration back-substitutes.

The parts: the seam constraints (:mod:`ptailor.method.solver.seams`), the Newton step
(:mod:`ptailor.method.solver.newton`) and the iteration
(:mod:`ptailor.method.solver.iteration`); the system
(:mod:`ptailor.method.solver.problem`); this module runs it (:func:`stitch`, the package's
entry).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ptailor.method import tolerances as method_tol
from ptailor.method.ease import SeamEase
from ptailor.method.solver.iteration import Iterate, finite_or_fail, iterate
from ptailor.method.solver.problem import Problem
from ptailor.method.solver.symbolic import SymbolicCache

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
        progress over ``method_tol.ARAP_STALL_ITER`` iterations (not converged).
    newton_steps : int
        Iterations that were a Newton step
        (:meth:`ptailor.method.solver.newton.NewtonModel.newton`), taken where the
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
    w_pin: float = method_tol.W_PIN,
    w_asap: float = method_tol.W_ASAP,
    max_iter: int = method_tol.ARAP_MAX_ITER,
    step_tol: float = method_tol.ARAP_STEP_TOL,
    history: int = method_tol.ANDERSON_HISTORY,
    newton_cg: int = method_tol.NEWTON_CG_MAX,
    progress: Callable[[int, float], None] | None = None,
    symbolic: SymbolicCache | None = None,
) -> tuple[np.ndarray, StitchInfo]:
    """Stitch per-triangle targets into continuous panels.

    Local/global iterations, Anderson-accelerated under Peng et al.'s safeguard, Newton
    steps where they crawl (:mod:`ptailor.method.solver.iteration`). The result is always
    a plain step's output, so the constraints hold at the last linearisation.

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
    asap_faces, asap_exclude : (k,) int array, (n,) bool array, optional
        Triangles of the panels that keep their outline shape (as-similar-as-possible),
        and outline vertices left free even on those panels.
    ease : SeamEase, optional
        Seam-length constraints (:func:`ptailor.method.ease.seam_ease`), enforced exactly
        with Lagrange multipliers and their curvature
        (:meth:`ptailor.method.solver.seams.SeamConstraints.constrained`) from
        the first iteration where a seam misses its ratio by more than
        ``method_tol.SEAM_EXACT_REL`` (an identity edit or a uniform scale never pays for them).
    panel_weight : (n_panels,) float array, optional
        Scales each panel's whole energy (default 1): where seam constraints tie panels,
        a heavier one takes less of the distortion.
    w_pin, w_asap : float
        Term weights.
    max_iter, step_tol : int, float
        Local/global iterations at most; converged when no panel's last step moved a
        vertex (rigid motion removed) by more than ``step_tol`` of the panel's size.
    history, newton_cg : int
        Anderson history length, and conjugate-gradient iterations at most of a Newton
        step (:meth:`ptailor.method.solver.newton.NewtonModel.newton`); 0 for plain
        local/global, or no Newton steps.
    progress : callable, optional
        ``progress(iteration, residual)`` once per iteration (the largest panel residual
        before it): a progress line's feed. Nothing else depends on it.
    symbolic : SymbolicCache, optional
        Symbolic analyses shared with the caller's other factorisations of this pattern.

    Returns
    -------
    X : (n, 2) float array
        Stitched positions; vertices no triangle uses keep their original position.
    info : StitchInfo
    """
    pb = Problem(
        V2, F2, targets, pins=pins, vertex_panel=vertex_panel, asap_faces=asap_faces,
        asap_exclude=asap_exclude, ease=ease, panel_weight=panel_weight, w_pin=w_pin,
        w_asap=w_asap, symbolic=symbolic,
    )  # fmt: skip
    X0 = pb.global_step(np.ones(len(F2)), np.zeros(len(F2)), None)  # identity rotations
    s = Iterate(pb, finite_or_fail(X0), history)
    kw = dict(max_iter=max_iter, step_tol=step_tol, history=history, newton_cg=newton_cg)
    return _result(pb, s, V2, *iterate(pb, s, **kw, progress=progress))


def _result(
    pb: Problem,
    s: Iterate,
    V2: np.ndarray,
    it: int,
    converged: bool,
    stalled: bool,
    hist: list[float],
    newton: int,
) -> tuple[np.ndarray, StitchInfo]:
    """The stitched positions and the solver's record after :func:`iterate`'s run."""
    # a plain step: the constraints hold at the last linearisation; a copy (its layout
    # kept), so that no measure the problem keeps of the iterate, by identity, is taken
    # for this one
    X = s.GX.copy(order="K")
    X[~pb.used] = V2[~pb.used]
    viol = float(pb.ease.violation(X).max()) if pb.ease is not None else 0.0
    if viol > method_tol.SEAM_EXACT_REL:
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
