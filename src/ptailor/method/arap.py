"""As-rigid-as-possible surface deformation in libigl's two halves: what the handles'
positions do not change, computed once (:func:`arap_precompute`: the components holding
handles, the cells whose rotations can change, the cotangent Laplacian's free-free block
factored, the constant edge operators), and the local/global iterations for given
positions (:func:`arap_solve`). :func:`ptailor.method.deform.arap_deform` composes them.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ptailor.geometry.rotations import rigid_fits_3d
from ptailor.method import tolerances as method_tol
from ptailor.method.anderson import Anderson
from ptailor.method.cell_rotations import warm_rotations
from ptailor.method.cotangent import DEGENERATE_REL, corner_cotangents, edge_matrix
from ptailor.method.solver import SymbolicCache

__all__ = ["ArapPrecompute", "arap_precompute", "arap_solve"]

SIMILAR_MAX = method_tol.ARAP_SIMILAR_MAX
UNIFORM_REG = method_tol.DEFORM_UNIFORM_REG
COLLINEAR_REL = method_tol.DEFORM_COLLINEAR_REL
#: see :data:`ptailor.method.tolerances.ARAP_ITERATIONS`
ITERATIONS = method_tol.ARAP_ITERATIONS
ANDERSON = method_tol.ARAP_ANDERSON


def check_arap_inputs(V, F, handles, handle_positions):
    """``(V, F, handles, handle_positions)`` checked and as arrays (``V`` (n, 3) float,
    ``F`` (m, 3) int, ``handles`` (h,) int, ``handle_positions`` (h, 3) float) for
    :func:`arap` and :func:`ptailor.method.deform.arap_deform`.

    Raises
    ------
    ValueError
        Naming the first argument of the wrong shape, type or range.
    """
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
    seen = np.zeros(n, dtype=bool)
    seen[handles] = True
    if np.count_nonzero(seen) != handles.size:
        raise ValueError("handles has repeated vertex indices")
    Q = _checked_positions(handle_positions, handles.size)
    if not (np.isfinite(V).all() and np.isfinite(Q).all()):
        raise ValueError("V and handle_positions must be finite")
    return V, F, handles, Q


def _checked_positions(handle_positions, h: int) -> np.ndarray:
    """``handle_positions`` as an ``(h, 3)`` float array (ValueError otherwise)."""
    Q = np.asarray(handle_positions, dtype=np.float64)
    if Q.size == 0 and h == 0:
        Q = np.zeros((0, 3))
    if Q.shape != (h, 3):
        raise ValueError(f"handle_positions must have shape ({h}, 3), got {Q.shape}")
    return Q


@dataclass(frozen=True, eq=False)
class _ArapSystem:
    """The constant part of the local/global iterations over the components that hold
    handles (:func:`arap_precompute`), vertices numbered free ones first.

    Attributes
    ----------
    order : (na,) int array
        The vertices of those components: the ``nf`` free ones, then the handles.
    nf : int
    P : (na, 3) float array
        Their rest positions.
    lab, hlabel : (na,) and (h,) int arrays
        Component (among those holding handles) of each ordered vertex and each handle.
    n_comp : int
    solve : callable
        ``(nf, 3) -> (nf, 3)``: the free-free block of the Laplacian, factored once.
    Lfh : (nf, h) sparse matrix
        Its free-handle block.
    cells : (c,) int array
        The ordered vertices whose rotations are needed (corners of triangles with a
        free corner).
    G, N, D, C : sparse matrices
        Edge vectors ``(G @ x).reshape(m2, 3, 3) = x[ea] - x[eb]``, cell incidence (sums
        over a cell's triangle corners), signed edge incidence of the free rows, and the
        sum of a triangle's three cell rotations (:func:`_edge_operators`).
    w_e0t, w_e0_1 : (m2, 3, 3) and (m1, 3, 3) float arrays
        Weighted rest edge vectors, transposed, and of the triangles with a free corner.
    wn : (m2, 3) float array
        Edge weights times how often each triangle enters the energy.
    rest_part, scale : float
        The energy's rest term, and the scale of its stopping test.
    sim, rho : (c,) bool and float arrays, or None
        Cells allowed a uniform scale, and their rest sums ``w |e|^2``.
    """

    order: np.ndarray
    nf: int
    P: np.ndarray
    lab: np.ndarray
    hlabel: np.ndarray
    n_comp: int
    solve: Callable[[np.ndarray], np.ndarray]
    Lfh: sp.csr_matrix
    cells: np.ndarray
    G: sp.csr_matrix
    N: sp.csr_matrix
    D: sp.csr_matrix
    C: sp.csr_matrix
    w_e0t: np.ndarray
    w_e0_1: np.ndarray
    wn: np.ndarray
    rest_part: float
    scale: float
    sim: np.ndarray | None = None
    rho: np.ndarray | None = None


@dataclass(frozen=True, eq=False)
class ArapPrecompute:
    """A mesh and its handles prepared for :func:`arap_solve` (:func:`arap_precompute`).

    Attributes
    ----------
    V : (n, 3) float array
        Rest positions.
    handles : (h,) int array
    system : _ArapSystem or None
        The factored system; None when no vertex is free to move (no handle, no
        triangle, or every vertex of the components holding handles is one).
    """

    V: np.ndarray
    handles: np.ndarray
    system: _ArapSystem | None


def arap_precompute(
    V: np.ndarray,
    F: np.ndarray,
    handles: np.ndarray,
    *,
    similar: np.ndarray | None = None,
    symbolic: SymbolicCache | None = None,
) -> ArapPrecompute:
    """What :func:`arap_solve` needs that the handles' positions do not change: the
    components holding handles, the cells whose rotations can change, the cotangent
    Laplacian's free-free block factored once, and the constant edge operators.

    Parameters
    ----------
    V, F, handles
        As :func:`arap_deform`'s.
    similar : (n,) bool array, optional
        Vertices whose cells may take a uniform scale (up to ``SIMILAR_MAX``) as well as
        a rotation; default none.
    symbolic : SymbolicCache, optional
        Symbolic analyses shared with the caller's other factorisations of this pattern.

    Returns
    -------
    ArapPrecompute

    Raises
    ------
    ValueError
        As :func:`arap_deform`.

    Notes
    -----
    Degenerate triangles (see :func:`cotangent_weights`) contribute no cotangent term; a
    uniform weight of relative size ``UNIFORM_REG`` on every triangle edge keeps their
    vertices attached to the rest. Only the rotations that reach a free vertex are computed
    (vertices of triangles with a free corner); the energy used for the stopping test
    leaves out the other cells, which are constant.
    """
    from ptailor.method.solver import factor

    V, F, handles, _ = check_arap_inputs(V, F, handles, np.zeros((np.size(handles), 3)))
    numbering = None
    if handles.size and F.shape[0]:
        numbering = _numbering(V, F, handles)
    if numbering is None:
        return ArapPrecompute(V=V, handles=handles, system=None)
    order, nf, Fa, lab, hlabel, n_comp = numbering
    P = V[order]
    cells, F2, in1 = _cells(Fa, nf, order.size)
    w = _edge_weights(P, F2)
    Lff, Lfh = _laplacian(F2[in1], w[in1], order.size, nf)
    ops = _edge_operators(P, F2, w, cells, in1, nf)
    sim, rho = None, None
    if similar is not None and np.any(similar):
        sim = np.asarray(similar, dtype=bool)[order][cells]  # cells allowed a uniform scale
        rho = ops["N"] @ np.einsum("tk,tka,tka->t", w, ops["E0"], ops["E0"])  # rest sum w|e|^2
        rho = np.where(sim & (rho > 0), rho, 1.0)
    del ops["E0"]
    system = _ArapSystem(
        order=order, nf=nf, P=P, lab=lab, hlabel=hlabel, n_comp=n_comp,
        solve=factor(Lff, symbolic=symbolic),  # CHOLMOD; SuperLU where cvxopt is missing
        Lfh=Lfh, cells=cells, sim=sim, rho=rho, **ops,
    )  # fmt: skip
    return ArapPrecompute(V=V, handles=handles, system=system)


def _numbering(V: np.ndarray, F: np.ndarray, handles: np.ndarray):
    """The components that hold handles, numbered free vertices first: ``(order, nf, Fa,
    lab, hlabel, n_comp)`` (``Fa`` their triangles in local indices), None when none of
    their vertices is free."""
    from scipy.sparse.csgraph import connected_components

    n = V.shape[0]
    # two edges per triangle connect its corners; duplicates are harmless here
    W_adj = sp.csr_matrix(
        (np.ones(2 * F.shape[0]), (F[:, [0, 1]].ravel(), F[:, [1, 2]].ravel())), shape=(n, n)
    )
    ncomp, comp = connected_components(W_adj, directed=False)
    has_handle = np.zeros(ncomp, dtype=bool)
    has_handle[comp[handles]] = True
    is_handle = np.zeros(n, dtype=bool)
    is_handle[handles] = True
    free = np.flatnonzero(has_handle[comp] & ~is_handle)
    if free.size == 0:
        return None
    order = np.concatenate([free, handles])
    loc = np.full(n, -1, dtype=np.int64)
    loc[order] = np.arange(order.size)
    Fa = loc[F[has_handle[comp[F[:, 0]]]]]  # triangles of those components, local indices
    ucomp, hlabel = np.unique(comp[handles], return_inverse=True)
    cmap = np.full(ncomp, -1, dtype=np.int64)
    cmap[ucomp] = np.arange(ucomp.size)
    return order, free.size, Fa, cmap[comp[order]], hlabel.ravel(), ucomp.size


def _cells(Fa: np.ndarray, nf: int, na: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Which triangles and rotations can change: ``(cells, F2, in1)``.

    T1: triangles with a free corner, the only ones in the free rows of the global step;
    their corners' rotations are needed ("cells"), and a cell sums over all of its
    triangles (T2, the rows of ``F2``; ``in1`` which of them are in T1). Other rotations
    only add a constant to the energy."""
    T1 = (Fa < nf).any(axis=1)
    is_cell = np.zeros(na, dtype=bool)
    is_cell[Fa[T1]] = True
    cells = np.flatnonzero(is_cell)
    T2 = is_cell[Fa].any(axis=1)
    return cells, Fa[T2], T1[T2]


def _edge_weights(P: np.ndarray, F2: np.ndarray) -> np.ndarray:
    """Per-triangle edge weights ``(m2, 3)``: half cotangents plus ``UNIFORM_REG`` of
    their mean magnitude (which keeps degenerate triangles' vertices attached)."""
    half_cot = 0.5 * corner_cotangents(P, F2, DEGENERATE_REL)
    mean_abs = float(np.abs(half_cot).mean()) if half_cot.size else 0.0
    return half_cot + UNIFORM_REG * (mean_abs if mean_abs > 0.0 else 1.0)


def _laplacian(
    F1: np.ndarray, w1: np.ndarray, na: int, nf: int
) -> tuple[sp.csc_matrix, sp.csr_matrix]:
    """The free-free and free-handle blocks of the Laplacian of the triangles ``F1``
    (those with a free corner) with edge weights ``w1``."""
    Wm = edge_matrix(F1, w1, na)
    L = (sp.diags(np.asarray(Wm.sum(axis=1)).ravel()) - Wm).tocsr()
    return L[:nf, :nf].tocsc(), L[:nf, nf:].tocsr()


def _edge_operators(
    P: np.ndarray, F2: np.ndarray, w: np.ndarray, cells: np.ndarray, in1: np.ndarray, nf: int
) -> dict:
    """The constant operators over the triangle edges (:class:`_ArapSystem`'s ``G``,
    ``N``, ``D``, ``C``, ``w_e0t``, ``w_e0_1``, ``wn``, ``rest_part``, ``scale``) and the
    rest edge vectors ``E0 (m2, 3, 3)``."""
    na, m2 = P.shape[0], F2.shape[0]
    ea = F2[:, [1, 2, 0]]  # edge k of triangle t runs from ea[t, k] to eb[t, k]
    eb = F2[:, [2, 0, 1]]
    # edge vectors as one sparse product: (G @ x).reshape(m2, 3, 3) = x[ea] - x[eb]
    G = sp.csr_matrix(
        (
            np.tile([1.0, -1.0], 3 * m2),
            np.stack([ea.ravel(), eb.ravel()], axis=1).ravel(),
            np.arange(0, 6 * m2 + 1, 2),
        ),
        shape=(3 * m2, na),
    )
    E0 = (G @ P).reshape(m2, 3, 3)  # rest edge vectors
    wE0 = w[:, :, None] * E0
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
    wn = ok.reshape(m2, 3).sum(axis=1).astype(np.float64)[:, None] * w
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
    m1 = F1c.shape[0]
    # (C @ R.reshape(-1, 9))[t] sums the rotations of triangle t's three cells
    C = sp.csr_matrix(
        (np.ones(3 * m1), F1c.ravel(), np.arange(0, 3 * m1 + 1, 3)), shape=(m1, cells.size)
    )
    # energy = sum over cells c, triangles t at c, edges k of t of w |e'_k - R_c e_k|^2
    #        = sum ncorner_t w (|e'|^2 + |e|^2) - 2 sum_c trace(R_c S_c)
    # (the constant cells of handles surrounded by handles are left out)
    return dict(
        G=G, N=N, D=D, C=C, E0=E0, wn=wn, w_e0_1=wE0[in1],
        w_e0t=np.ascontiguousarray(np.swapaxes(wE0, 1, 2)),
        rest_part=float(np.einsum("tk,tka,tka->", wn, E0, E0)),
        scale=2.0 * float(np.einsum("tk,tka,tka->", np.abs(wn), E0, E0)),
    )  # fmt: skip


def arap_solve(
    pre: ArapPrecompute,
    handle_positions: np.ndarray,
    *,
    iterations: int = ITERATIONS,
    tol: float = method_tol.ARAP_ENERGY_TOL,
    anderson: int = ANDERSON,
) -> np.ndarray:
    """The as-rigid-as-possible deformation of a precomputed mesh (:func:`arap_precompute`)
    with its handles at ``handle_positions (h, 3)``: :func:`arap_deform`'s initial guess
    and iterations (its ``iterations``, ``tol`` and ``anderson``).

    Returns
    -------
    (n, 3) float array
        Deformed positions, a new array (as :func:`arap_deform`'s).

    Raises
    ------
    ValueError
        ``handle_positions`` of the wrong shape or not finite.

    Notes
    -----
    The energy is evaluated as ``sum w (|e'|^2 + |e|^2) - 2 sum_i trace(R_i S_i)`` from the
    singular values, so it costs nothing extra but is only accurate to about ``1e-16`` of
    its scale; relative changes below ``tol`` are resolved while the energy is above
    about ``1e-16 / tol`` of the scale.
    """
    Q = _checked_positions(handle_positions, pre.handles.size)
    if not np.isfinite(Q).all():
        raise ValueError("V and handle_positions must be finite")
    X = pre.V.copy()
    X[pre.handles] = Q
    sys = pre.system
    if sys is None:
        return X
    Xa, R = _initial_guess(sys, pre.V[pre.handles], Q)
    _iterate(sys, Xa, R, Q, iterations=iterations, tol=tol, anderson=anderson)
    X[sys.order] = Xa
    return X


def _initial_guess(
    sys: _ArapSystem, Vh: np.ndarray, Q: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Per-component rigid fit of the handles (rest ``Vh``, targets ``Q``), then the
    harmonic residual: the start ``(na, 3)`` and the cells' rotations (their component's
    rigid fit)."""
    Rc, cp, cq = rigid_fits_3d(Vh, Q, sys.hlabel, sys.n_comp, collinear_rel=COLLINEAR_REL)
    lab, nf = sys.lab, sys.nf
    Xa = np.einsum("kab,kb->ka", Rc[lab], sys.P - cp[lab]) + cq[lab]
    Xa[:nf] += sys.solve(-(sys.Lfh @ (Q - Xa[nf:])))
    Xa[nf:] = Q
    return Xa, Rc[lab[sys.cells]]


def _local_step(
    sys: _ArapSystem, Xa: np.ndarray, R: np.ndarray
) -> tuple[np.ndarray, float, np.ndarray | None]:
    """Best rotations (and, on ``similar`` cells, uniform scales) for ``Xa`` (S_c = sum
    over the triangles at c of w e e'^T), and the energy with them: ``(R, energy, s)``."""
    m2, c = sys.wn.shape[0], sys.cells.size
    E1 = (sys.G @ Xa).reshape(m2, 3, 3)
    Sc = (sys.N @ (sys.w_e0t @ E1).reshape(m2, 9)).reshape(c, 3, 3)
    R, tr = warm_rotations(Sc, R)
    deformed_part = float(np.einsum("tk,tka,tka->", sys.wn, E1, E1))
    if sys.sim is None:
        return R, sys.rest_part + deformed_part - 2.0 * float(tr.sum()), None
    sim, rho = sys.sim, sys.rho
    # s = tr(R S) / rho minimises |e' - s R e|^2 over the cell: energy s^2 rho - 2 s tr
    s = np.where(sim, np.clip(tr / rho, 1.0 / SIMILAR_MAX, SIMILAR_MAX), 1.0)
    extra = float(((s * s - 1.0) * rho * sim).sum() - 2.0 * ((s - 1.0) * tr).sum())
    return R, sys.rest_part + deformed_part - 2.0 * float(tr.sum()) + extra, s


def _iterate(
    sys: _ArapSystem,
    Xa: np.ndarray,
    R: np.ndarray,
    Q: np.ndarray,
    *,
    iterations: int,
    tol: float,
    anderson: int,
) -> None:
    """The local/global iterations from ``Xa`` (its free rows updated in place),
    Anderson-accelerated; the last iteration is a plain step."""
    nf = sys.nf
    m1 = sys.C.shape[0]
    rhs_h = sys.Lfh @ Q  # the handles' constant share of every global step
    acc = Anderson(m=anderson)
    E_prev, x_plain, mixed = np.inf, None, False
    for it in range(iterations):
        R, energy, s = _local_step(sys, Xa, R)
        if mixed and energy > E_prev:  # the mix did worse: its plain step is no worse
            Xa[:nf] = x_plain
            acc.reset()
            R, energy, s = _local_step(sys, Xa, R)
        # the sum cancels to about 1e-16 * scale: ARAP_ZERO_ENERGY_REL
        if energy <= method_tol.ARAP_ZERO_ENERGY_REL * sys.scale or (
            np.isfinite(E_prev) and E_prev - energy <= tol * E_prev
        ):
            break
        E_prev = energy
        # global step: L x = b / 3, b_a = sum over edges (a, b) of w (R_c0 + R_c1 + R_c2) e_ab
        Rs = R if s is None else R * s[:, None, None]
        RsumT = (sys.C @ np.swapaxes(Rs, 1, 2).reshape(-1, 9)).reshape(m1, 3, 3)  # contiguous
        b = sys.D @ (sys.w_e0_1 @ RsumT).reshape(-1, 3)
        x_plain = sys.solve(b / 3.0 - rhs_h)
        if it == iterations - 1:  # the result is a plain step: its energy is no higher
            Xa[:nf] = x_plain
            break
        g_x = x_plain.ravel()
        x_next = acc.next(Xa[:nf].ravel().copy(), g_x)
        mixed = x_next is not g_x
        Xa[:nf] = x_next.reshape(nf, 3)
