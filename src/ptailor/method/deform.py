"""Detail-preserving surface deformation: as-rigid-as-possible surface modelling.

The shared 3D core of the garment edits (scale of a region while the rest follows,
seam-line scale, tighten / loosen): some vertices (the *handles*) are moved to prescribed
positions and every other vertex follows so that the surface around each vertex stays as
rigid as possible (Sorkine & Alexa, "As-Rigid-As-Possible Surface Modeling", SGP 2007).

Pure functions over arrays in the libigl / gpytoolbox style: inputs are never mutated,
there is no hidden state, and there is no Python loop over vertices or triangles.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
import scipy.sparse.linalg as spla

from ptailor import tolerances as tol
from ptailor.geometry.rotations import max_trace_rotations, rigid_fits_3d

__all__ = ["arap_deform", "cotangent_weights"]

DEGENERATE_REL = tol.DEFORM_DEGENERATE_REL
UNIFORM_REG = tol.DEFORM_UNIFORM_REG
COLLINEAR_REL = tol.DEFORM_COLLINEAR_REL


def _corner_cotangents(V: np.ndarray, F: np.ndarray, eps: float) -> np.ndarray:
    """Cotangent of each triangle corner, ``(m, 3)``, zero for degenerate triangles."""
    c0, c1, c2 = F[:, [0, 1, 2]].T, F[:, [1, 2, 0]].T, F[:, [2, 0, 1]].T  # (3, m) each
    a = V[c1] - V[c0]  # (3, m, d): the two edges leaving each corner
    b = V[c2] - V[c0]
    dot = np.einsum("kmd,kmd->km", a, b)
    aa = np.einsum("kmd,kmd->km", a, a)
    bb = np.einsum("kmd,kmd->km", b, b)
    # |a x b| in any dimension through Lagrange's identity; it is the same at all corners
    area2 = np.sqrt(np.maximum(aa[0] * bb[0] - dot[0] ** 2, 0.0))
    good = area2 > eps * np.max(aa, axis=0)
    cot = np.divide(dot, area2, out=np.zeros_like(dot), where=good[None, :])
    return np.ascontiguousarray(cot.T)


def _edge_matrix(F: np.ndarray, w: np.ndarray, n: int) -> sp.csr_matrix:
    """Symmetric ``(n, n)`` matrix summing per-triangle edge weights ``w (m, 3)``.

    ``w[t, k]`` belongs to the edge opposite corner ``k`` of triangle ``t``.
    """
    a = F[:, [1, 2, 0]].ravel()
    b = F[:, [2, 0, 1]].ravel()
    keep = a != b  # a triangle with a repeated index yields no self-loop
    rows = np.concatenate([a[keep], b[keep]])
    cols = np.concatenate([b[keep], a[keep]])
    vals = np.concatenate([w.ravel()[keep], w.ravel()[keep]])
    W = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
    W.sum_duplicates()
    return W


def cotangent_weights(
    V: np.ndarray, F: np.ndarray, *, eps: float = DEGENERATE_REL
) -> sp.csr_matrix:
    """Symmetric cotangent weights of a triangle mesh.

    For an interior edge ``(i, j)`` with opposite angles ``a`` and ``b``,
    ``w_ij = (cot a + cot b) / 2``; a boundary edge has only its one term. Negative weights
    (opposite angles summing to more than pi) are kept as they are: ``diag(W 1) - W`` is
    then the linear finite-element stiffness matrix, positive semi-definite for any mesh.

    Parameters
    ----------
    V : (n, d) float array
        Vertex positions, ``d >= 2``.
    F : (m, 3) int array
        Triangles.
    eps : float, keyword-only
        A triangle whose doubled area is at most ``eps`` times its longest squared edge
        (an angle below about ``eps`` radians) is degenerate and contributes nothing, so
        collinear or coincident corners give no ``inf`` or NaN.

    Returns
    -------
    (n, n) scipy.sparse.csr_matrix
        Symmetric with zero diagonal. Its sparsity pattern is the set of mesh edges (an
        edge whose terms cancel, or that lies only in degenerate triangles, is an explicit
        zero); unreferenced vertices have empty rows.
    """
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64).reshape(-1, 3)
    return _edge_matrix(F, 0.5 * _corner_cotangents(V, F, eps), V.shape[0])


def _check_inputs(V, F, handles, handle_positions):
    V = np.asarray(V, dtype=np.float64)
    if V.ndim != 2 or V.shape[1] != 3:
        raise ValueError(f"V must have shape (n, 3), got {V.shape}")
    n = V.shape[0]
    F = np.asarray(F)
    if F.size == 0:
        F = np.zeros((0, 3), dtype=np.int64)
    if F.ndim != 2 or F.shape[1] != 3 or not np.issubdtype(F.dtype, np.integer):
        raise ValueError(f"F must be an (m, 3) integer array, got {F.dtype} {F.shape}")
    F = F.astype(np.int64, copy=False)
    if F.size and (F.min() < 0 or F.max() >= n):
        raise ValueError(f"F indexes vertices outside 0..{n - 1}")
    handles = np.asarray(handles)
    if handles.size == 0:
        handles = np.zeros(0, dtype=np.int64)
    if handles.ndim != 1 or not np.issubdtype(handles.dtype, np.integer):
        raise ValueError(
            f"handles must be an (h,) integer array, got {handles.dtype} {handles.shape}"
        )
    handles = handles.astype(np.int64, copy=False)
    if handles.size and (handles.min() < 0 or handles.max() >= n):
        raise ValueError(f"handles index vertices outside 0..{n - 1}")
    if np.unique(handles).size != handles.size:
        raise ValueError("handles has repeated vertex indices")
    Q = np.asarray(handle_positions, dtype=np.float64)
    if Q.size == 0 and handles.size == 0:
        Q = np.zeros((0, 3))
    if Q.shape != (handles.size, 3):
        raise ValueError(f"handle_positions must have shape ({handles.size}, 3), got {Q.shape}")
    if not (np.isfinite(V).all() and np.isfinite(Q).all()):
        raise ValueError("V and handle_positions must be finite")
    return V, F, handles, Q


def arap_deform(
    V: np.ndarray,
    F: np.ndarray,
    handles: np.ndarray,
    handle_positions: np.ndarray,
    *,
    iterations: int = 10,
    tol: float = 1e-6,
) -> np.ndarray:
    """As-rigid-as-possible surface deformation with hard handle constraints.

    Minimises, over the free positions ``x`` and one rotation ``R_i`` per vertex,

        E = sum_i sum_(t incident to i) sum_((a,b) edge of t) w_ab^t |x_a - x_b - R_i (v_a - v_b)|^2

    with ``w_ab^t`` half the cotangent of the angle of ``t`` opposite ``(a, b)``: the
    as-rigid-as-possible energy of Sorkine & Alexa (2007) with the "spokes and rims" cells
    of Chao et al. (2010), the libigl default for surfaces. Each triangle's term is a
    Dirichlet energy and so non-negative even where cotangents are negative, which keeps
    the rest pose an exact fixed point on obtuse meshes (the spokes-only cells can turn a
    vertex at rest by 180 degrees there). Local step: all rotations at once from a batched
    3x3 SVD. Global step: the handles are eliminated and the free-free block of the
    cotangent Laplacian (symmetric positive definite) is factored once with SuperLU; each
    iteration is one back-substitution with 3 right-hand sides.

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
    tol : float, keyword-only
        Stop early when the energy decreases by less than ``tol`` times its previous value,
        or is below ``1e-14`` of its scale ``sum w |e|^2`` (zero to rounding: every edge
        within about ``1e-7`` of a rigid motion of its cells).

    Returns
    -------
    (n, 3) float array
        Deformed positions, a new array; handles are exactly at ``handle_positions``.
        Vertices of components (connected through ``F``) holding no handle, and
        unreferenced vertices that are not handles, keep their rest positions.

    Raises
    ------
    ValueError
        On malformed shapes, indices out of range, repeated handles or non-finite input.

    Notes
    -----
    Degenerate triangles (see :func:`cotangent_weights`) contribute no cotangent term; a
    uniform weight of relative size ``UNIFORM_REG`` on every triangle edge keeps their
    vertices attached to the rest. Only the rotations that reach a free vertex are computed
    (vertices of triangles with a free corner); the energy used for the stopping test
    leaves out the other cells, which are constant.

    The energy is evaluated as ``sum w (|e'|^2 + |e|^2) - 2 sum_i trace(R_i S_i)`` from the
    singular values, so it costs nothing extra but is only accurate to about ``1e-16`` of
    its scale; relative changes below ``tol`` are resolved while the energy is above
    about ``1e-16 / tol`` of the scale.
    """
    V, F, handles, Q = _check_inputs(V, F, handles, handle_positions)
    n = V.shape[0]
    X = V.copy()
    X[handles] = Q
    if handles.size == 0 or F.shape[0] == 0:
        return X

    # ---- the components that hold handles, numbered free vertices first -------------
    W_adj = _edge_matrix(F, np.ones(F.shape), n)
    ncomp, comp = csgraph.connected_components(W_adj, directed=False)
    has_handle = np.zeros(ncomp, dtype=bool)
    has_handle[comp[handles]] = True
    is_handle = np.zeros(n, dtype=bool)
    is_handle[handles] = True
    free = np.flatnonzero(has_handle[comp] & ~is_handle)
    if free.size == 0:
        return X
    order = np.concatenate([free, handles])
    loc = np.full(n, -1, dtype=np.int64)
    loc[order] = np.arange(order.size)
    na, nf = order.size, free.size
    Fa = loc[F[has_handle[comp[F[:, 0]]]]]  # triangles of those components, local indices
    P = V[order]

    # ---- which triangles and rotations can change -----------------------------------
    # T1: triangles with a free corner, the only ones in the free rows of the global step;
    # their corners' rotations are needed ("cells"), and a cell sums over all of its
    # triangles (T2). Other rotations only add a constant to the energy.
    T1 = (Fa < nf).any(axis=1)
    is_cell = np.zeros(na, dtype=bool)
    is_cell[Fa[T1]] = True
    cells = np.flatnonzero(is_cell)
    T2 = is_cell[Fa].any(axis=1)
    F2 = Fa[T2]
    m2 = F2.shape[0]
    in1 = T1[T2]  # which rows of F2 are in T1

    # ---- per-triangle edge weights and the Laplacian, factored once ------------------
    half_cot = 0.5 * _corner_cotangents(P, F2, DEGENERATE_REL)
    mean_abs = float(np.abs(half_cot).mean()) if half_cot.size else 0.0
    w = half_cot + UNIFORM_REG * (mean_abs if mean_abs > 0.0 else 1.0)  # (m2, 3)
    Wm = _edge_matrix(F2[in1], w[in1], na)
    L = (sp.diags(np.asarray(Wm.sum(axis=1)).ravel()) - Wm).tocsr()
    Lff = L[:nf, :nf].tocsc()
    Lfh = L[:nf, nf:].tocsr()
    lu = spla.splu(
        Lff, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True}
    )

    def solve(rhs: np.ndarray) -> np.ndarray:
        return lu.solve(np.asfortranarray(rhs))

    # ---- initial guess: per-component rigid fit, then harmonic residual --------------
    ucomp, hlabel = np.unique(comp[handles], return_inverse=True)
    cmap = np.full(ncomp, -1, dtype=np.int64)
    cmap[ucomp] = np.arange(ucomp.size)
    Rc, cp, cq = rigid_fits_3d(
        V[handles], Q, hlabel.ravel(), ucomp.size, collinear_rel=COLLINEAR_REL
    )
    lab = cmap[comp[order]]
    Xa = np.einsum("kab,kb->ka", Rc[lab], P - cp[lab]) + cq[lab]
    Xa[:nf] += solve(-(Lfh @ (Q - Xa[nf:])))
    Xa[nf:] = Q
    rhs_h = Lfh @ Q  # the handles' constant share of every global step

    # ---- constant operators over the triangle edges ----------------------------------
    ea = F2[:, [1, 2, 0]]  # edge k of triangle t runs from ea[t, k] to eb[t, k]
    eb = F2[:, [2, 0, 1]]
    E0 = P[ea] - P[eb]  # rest edge vectors, (m2, 3, 3)
    wE0 = w[:, :, None] * E0
    wE0T = np.ascontiguousarray(np.swapaxes(wE0, 1, 2))
    # cell incidence: (N @ y)[c] sums y over the triangle corners at cell vertex c
    cell_of = np.full(na, -1, dtype=np.int64)
    cell_of[cells] = np.arange(cells.size)
    corner_cell = cell_of[F2.ravel()]
    ok = corner_cell >= 0
    N = sp.csr_matrix(
        (np.ones(ok.sum()), (corner_cell[ok], np.repeat(np.arange(m2), 3)[ok])),
        shape=(cells.size, m2),
    )
    # corners per triangle that are cells: how often each triangle enters the energy
    ncorner = ok.reshape(m2, 3).sum(axis=1).astype(np.float64)
    wn = ncorner[:, None] * w
    rest_part = float(np.einsum("tk,tka,tka->", wn, E0, E0))
    # signed edge incidence over T1, free rows only: (D @ y)[i] = y leaving i - y entering i
    e1a, e1b = ea[in1].ravel(), eb[in1].ravel()
    k1 = np.arange(e1a.size)
    sel_a, sel_b = e1a < nf, e1b < nf
    D = sp.csr_matrix(
        (
            np.r_[np.ones(sel_a.sum()), -np.ones(sel_b.sum())],
            (np.r_[e1a[sel_a], e1b[sel_b]], np.r_[k1[sel_a], k1[sel_b]]),
        ),
        shape=(nf, e1a.size),
    )
    F1c = cell_of[F2[in1]]  # T1 corners as cell indices (all are cells)
    wE0_1 = wE0[in1]

    # energy = sum over cells c, triangles t at c, edges k of t of w |e'_k - R_c e_k|^2
    #        = sum ncorner_t w (|e'|^2 + |e|^2) - 2 sum_c trace(R_c S_c)
    # (the constant cells of handles surrounded by handles are left out)
    scale = 2.0 * float(np.einsum("tk,tka,tka->", np.abs(wn), E0, E0))
    E_prev = np.inf
    for _ in range(iterations):
        # local step: S_c = sum over the triangles at c of sum_k w_k e_k e'_k^T
        E1 = Xa[ea] - Xa[eb]
        St = wE0T @ E1
        R, tr = max_trace_rotations((N @ St.reshape(m2, 9)).reshape(cells.size, 3, 3))
        deformed_part = float(np.einsum("tk,tka,tka->", wn, E1, E1))
        energy = rest_part + deformed_part - 2.0 * float(tr.sum())
        # the sum cancels to about 1e-16 * scale; below a few times that it is zero
        if energy <= 1e-14 * scale or (np.isfinite(E_prev) and E_prev - energy <= tol * E_prev):
            break
        E_prev = energy
        # global step: L x = b / 3, b_a = sum over edges (a, b) of w (R_c0 + R_c1 + R_c2) e_ab
        Rsum = R[F1c].sum(axis=1)  # (m1, 3, 3)
        b = D @ (wE0_1 @ np.swapaxes(Rsum, 1, 2)).reshape(-1, 3)
        Xa[:nf] = solve(b / 3.0 - rhs_h)

    X[order] = Xa
    return X
