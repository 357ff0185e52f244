"""Detail-preserving surface deformation: as-rigid-as-possible surface modelling.

The shared 3D core of the garment edits (scale of a region while the rest follows,
seam-line scale, tighten / loosen): some vertices (the *handles*) are moved to prescribed
positions and every other vertex follows so that the surface around each vertex stays as
rigid as possible (Sorkine & Alexa, "As-Rigid-As-Possible Surface Modeling", SGP 2007).

Pure functions over arrays in the libigl / gpytoolbox style: inputs are never mutated,
there is no hidden state, and there is no Python loop over vertices or triangles. As in
libigl, what the handles' positions do not change is computed once
(:func:`~ptailor.method.arap.arap_precompute`) and solved for any positions
(:func:`~ptailor.method.arap.arap_solve`); :func:`arap_deform` composes the two. The
cotangent weights are :mod:`ptailor.method.cotangent`'s, the cells' rotations
:mod:`ptailor.method.cell_rotations`'.
"""

from __future__ import annotations

import numpy as np

from ptailor.method import tolerances as method_tol
from ptailor.method.arap import (
    ANDERSON,
    COLLINEAR_REL,
    ITERATIONS,
    SIMILAR_MAX,
    UNIFORM_REG,
    ArapPrecompute,
    arap_precompute,
    arap_solve,
    check_arap_inputs,
)
from ptailor.method.cell_rotations import warm_rotations
from ptailor.method.cotangent import DEGENERATE_REL, cotangent_weights
from ptailor.method.solver import SymbolicCache

__all__ = [
    "ANDERSON",
    "COLLINEAR_REL",
    "DEGENERATE_REL",
    "ITERATIONS",
    "SIMILAR_MAX",
    "UNIFORM_REG",
    "ArapPrecompute",
    "arap_deform",
    "arap_precompute",
    "arap_solve",
    "cotangent_weights",
    "warm_rotations",
]


def arap_deform(
    V: np.ndarray,
    F: np.ndarray,
    handles: np.ndarray,
    handle_positions: np.ndarray,
    *,
    iterations: int = ITERATIONS,
    tol: float = method_tol.ARAP_ENERGY_TOL,
    anderson: int = ANDERSON,
    similar: np.ndarray | None = None,
    symbolic: SymbolicCache | None = None,
) -> np.ndarray:
    """As-rigid-as-possible surface deformation with hard handle constraints.

    Minimises, over the free positions ``x`` and one rotation ``R_i`` per vertex,

        E = sum_i sum_(t incident to i) sum_((a,b) edge of t) w_ab^t |x_a - x_b - R_i (v_a - v_b)|^2

    with ``w_ab^t`` half the cotangent of the angle of ``t`` opposite ``(a, b)``: the
    as-rigid-as-possible energy of Sorkine & Alexa (2007) with the "spokes and rims" cells
    of Chao et al. (2010), the libigl default for surfaces. Each triangle's term is a
    Dirichlet energy and so non-negative even where cotangents are negative, which keeps
    the rest pose an exact fixed point on obtuse meshes (the spokes-only cells can turn a
    vertex at rest by 180 degrees there). Local step: all rotations at once by Newton
    steps from the previous ones (:func:`warm_rotations`; the first time from each
    component's rigid fit), the same maxima as a batched 3x3 SVD at a fraction of its cost.
    Global step: the handles are eliminated and the free-free block of the
    cotangent Laplacian (symmetric positive definite) is factored once
    (:func:`ptailor.method.solver.factor`, a sparse Cholesky); each
    iteration is one back-substitution with 3 right-hand sides. The iterations are
    Anderson-accelerated (Peng et al. 2018): a mix of the last iterates whose energy comes
    out higher than its predecessor's is replaced by the plain step (an extra local step),
    and the last iteration is a plain step, so the energy of the result never exceeds that
    of an earlier iterate.

    Initial guess, so that few iterations already give a smooth result: each connected
    component holding handles first moves by the rigid motion best fitting its handles
    (Kabsch; translation only when they are collinear or a single vertex), then the
    handles' remaining displacements are interpolated harmonically with the same
    factorisation. A rigid motion of the handles is thus reproduced exactly.

    Parameters
    ----------
    V : (n, 3) float array
        Rest positions.
    F : (m, 3) int array
        Triangles; the mesh may have boundaries, several components, unreferenced vertices
        and degenerate triangles.
    handles : (h,) int array
        Distinct vertex indices held at ``handle_positions``.
    handle_positions : (h, 3) float array
        Target positions of the handles.
    iterations : int, keyword-only
        Maximum number of local/global iterations (global solves); 0 returns the initial
        guess.
    anderson : int, keyword-only
        Anderson history length; 0 for plain local/global iterations.
    tol : float, keyword-only
        Stop early when the energy decreases by less than ``tol`` times its previous value,
        or is below ``1e-14`` of its scale ``sum w |e|^2`` (zero to rounding: every edge
        within about ``1e-7`` of a rigid motion of its cells).
    similar, symbolic : keyword-only
        As :func:`arap_precompute`'s (cells allowed a uniform scale; shared analyses).

    Returns
    -------
    (n, 3) float array
        Deformed positions, a new array; handles are exactly at ``handle_positions``.
        Vertices of components (connected through ``F``) holding no handle, and
        unreferenced vertices that are not handles, keep their rest positions.

    Raises
    ------
    ValueError
        On malformed shapes, indices out of range, repeated handles or non-finite input
        (degenerate triangles, accuracy: the notes of :func:`arap_precompute`, :func:`arap_solve`).
    """
    V, F, handles, Q = check_arap_inputs(V, F, handles, handle_positions)
    pre = arap_precompute(V, F, handles, similar=similar, symbolic=symbolic)
    return arap_solve(pre, Q, iterations=iterations, tol=tol, anderson=anderson)
