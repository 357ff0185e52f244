"""Stitching: glue per-triangle targets into panels (ARAP local/global + ASAP boundary).

Minimises, over all panels at once (the system is block diagonal by panel)::

    E(x) = sum_i A_i |J_i(x) - R_i|_F^2                       as-rigid-as-possible
         + w_pin  sum_(c in C) |x_c - c|^2                     one pinned vertex per panel
         + w_asap sum_(k in B) (n_k . (x_(k+1) - x_(k-1)))^2   as-similar-as-possible

where ``J_i`` is the map from triangle ``i``'s target to its current position (so the first
term is Liu et al. 2008's triangle ARAP energy: cotangent-weighted edge terms), ``R_i`` a
rotation per triangle, ``n_k`` the unit normal of the original boundary chord at ``k``.
The matrix never changes: it is factored once and each iteration back-substitutes.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ptailor import tolerances as tol
from ptailor.geometry.closed_forms import det2, inv2
from ptailor.geometry.rotations import closest_rotations, rigid_fit_groups
from ptailor.method.anderson import Anderson
from ptailor.method.ease import SeamEase
from ptailor.model.boundary import boundary_loops


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
        progress over ``tol.ARAP_STALL_ITER`` iterations (not converged).
    """

    iterations: int
    energy: float
    converged: bool
    panel_residual: np.ndarray = field(default_factory=lambda: np.zeros(0))
    seam_violation: float = 0.0
    history: tuple[float, ...] = ()
    stalled: bool = False


def gradient_operators(F: np.ndarray, targets: np.ndarray, n: int) -> tuple[sp.csr_matrix, ...]:
    """Sparse operators giving each triangle's Jacobian from vertex coordinates.

    Parameters
    ----------
    F : (m, 3) int array
    targets : (m, 2, 2) float array
        Target edge matrices ``[e01, e02]``.
    n : int
        Number of vertices.

    Returns
    -------
    D0, D1 : (m, n) sparse matrices
        ``J[:, c, j] = Dj @ X[:, c]`` for positions ``X (n, 2)``.
    """
    m = len(F)
    Dm = np.array([[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]])
    G = Dm[None] @ inv2(targets)  # (m, 3, 2)
    rows = np.repeat(np.arange(m), 3)
    cols = F.ravel()
    return tuple(sp.csr_matrix((G[:, :, j].ravel(), (rows, cols)), shape=(m, n)) for j in range(2))


def laplacian(F: np.ndarray, targets: np.ndarray, area: np.ndarray, n: int) -> sp.csc_matrix:
    """The triangle ARAP matrix ``sum_i A_i G_i G_i^T`` (cotangent Laplacian of the targets).

    Parameters
    ----------
    F : (m, 3) int array
    targets : (m, 2, 2) float array
        Target edge matrices.
    area : (m,) float array
        Target areas.
    n : int

    Returns
    -------
    (n, n) sparse matrix
    """
    Dm = np.array([[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]])
    G = Dm[None] @ inv2(targets)  # (m, 3, 2) hat-function gradients
    K = area[:, None, None] * (G @ np.swapaxes(G, 1, 2))  # (m, 3, 3)
    rows = np.repeat(F, 3, axis=1).ravel()
    cols = np.tile(F, (1, 3)).ravel()
    return sp.csc_matrix((K.ravel(), (rows, cols)), shape=(n, n))


def asap_rows(
    V2: np.ndarray, F2: np.ndarray, faces: np.ndarray, *, exclude: np.ndarray | None = None
) -> sp.csr_matrix:
    """Rows of the linear as-similar-as-possible term for the boundary of some triangles.

    Parameters
    ----------
    V2 : (n, 2) float array
        Original pattern.
    F2 : (m, 3) int array
    faces : (k,) int array
        Triangles whose boundary loops get the term (whole panels).
    exclude : (n,) bool array, optional
        Boundary vertices that get no term (an outline being edited there).

    Returns
    -------
    (b, 2n) sparse matrix
        Row ``k`` is ``n_k . (x_(k+1) - x_(k-1))`` over unknowns ``[x; y]``.
    """
    n = len(V2)
    loops = boundary_loops(F2[faces]) if len(faces) else []
    loops = [lp for lp in loops if len(lp) >= 3]
    if not loops:
        return sp.csr_matrix((0, 2 * n))
    nxt = np.concatenate([np.roll(lp, -1) for lp in loops])
    prv = np.concatenate([np.roll(lp, 1) for lp in loops])
    cur = np.concatenate(loops)
    chord = V2[nxt] - V2[prv]
    length = np.linalg.norm(chord, axis=1)
    # a corner has no tangent: skip vertices where the outline turns sharply
    a, b = V2[cur] - V2[prv], V2[nxt] - V2[cur]
    na, nb = np.linalg.norm(a, axis=1), np.linalg.norm(b, axis=1)
    cos_turn = np.einsum("ij,ij->i", a, b) / np.maximum(na * nb, 1e-300)
    keep = (length > 0) & (cos_turn >= np.cos(np.radians(tol.ASAP_CORNER_DEG)))
    if exclude is not None:
        keep &= ~exclude[cur]
    nrm = np.stack([-chord[:, 1], chord[:, 0]], 1)[keep] / length[keep, None]
    nxt, prv, b = nxt[keep], prv[keep], int(keep.sum())
    r = np.arange(b)
    rows = np.concatenate([r, r, r, r])
    cols = np.concatenate([nxt, nxt + n, prv, prv + n])
    vals = np.concatenate([nrm[:, 0], nrm[:, 1], -nrm[:, 0], -nrm[:, 1]])
    return sp.csr_matrix((vals, (rows, cols)), shape=(b, 2 * n))


def factor(A: sp.spmatrix):
    """Factor a sparse symmetric positive definite matrix once; return a solve function."""
    from scipy.sparse.linalg import splu

    from ptailor.errors import PtailorError

    A = sp.csc_matrix(A)
    if not np.all(np.isfinite(A.data)):
        raise PtailorError(
            "flatten: the stitching matrix has non-finite entries (degenerate target "
            "triangles or extreme flatten weights)"
        )
    try:
        lu = splu(
            A,
            permc_spec="MMD_AT_PLUS_A",
            diag_pivot_thresh=0.0,
            options={"SymmetricMode": True},
        )
    except RuntimeError as exc:  # SuperLU: "Factor is exactly singular"
        raise PtailorError(
            f"flatten: the stitching matrix cannot be factored ({exc}): degenerate target "
            "triangles or extreme flatten weights"
        ) from None
    return lu.solve


def seam_block(
    solve_many, ease: SeamEase, vertex_panel: np.ndarray, n: int, *, coupled: bool
) -> tuple[np.ndarray, sp.csr_matrix]:
    """The seam vertices' block of ``A^-1``, computed once per factorisation.

    ``A`` is block diagonal by panel (and by coordinate when x and y decouple), so one
    right-hand side serves one seam unknown of every block at once: the number of
    back-substitutions is the most seam unknowns any one block has, not their total.

    Parameters
    ----------
    solve_many : callable
        ``(2n, c) -> (2n, c)``: ``A^-1`` applied to columns over unknowns ``[x; y]``.
    ease : SeamEase
    vertex_panel : (n,) int array
        Panel of each pattern vertex.
    n : int
    coupled : bool
        Whether ``A`` couples x and y (the as-similar-as-possible term).

    Returns
    -------
    U : (2q,) int array
        The seam unknowns (indices into ``[x; y]``).
    G : (2q, 2q) sparse matrix
        ``A^-1`` restricted to them (zero across blocks).
    """
    verts = ease.vertices()
    U = np.concatenate([verts, verts + n])
    pan = vertex_panel[verts].astype(np.int64)
    n_p = int(vertex_panel.max()) + 1
    blk = np.concatenate([pan, pan]) if coupled else np.concatenate([pan, pan + n_p])
    order = np.argsort(blk, kind="stable")
    sb = blk[order]
    start = np.searchsorted(sb, sb)  # first position of each block in sorted order
    slot = np.empty(len(U), dtype=np.int64)
    slot[order] = np.arange(len(U)) - start
    # all (i, j) pairs within a block
    cnt = np.bincount(sb)
    first = np.concatenate([[0], np.cumsum(cnt)])[sb]  # per sorted position
    rep = cnt[sb]
    I_sorted = np.repeat(np.arange(len(U)), rep)
    J_sorted = np.repeat(first, rep) + (np.arange(rep.sum()) - np.repeat(np.cumsum(rep) - rep, rep))
    Ii, Jj = order[I_sorted], order[J_sorted]
    vals = np.empty(len(Ii))
    n_slots = int(slot.max()) + 1
    for s0 in range(0, n_slots, tol.SEAM_BLOCK_CHUNK):  # chunks of right-hand sides
        s1 = min(s0 + tol.SEAM_BLOCK_CHUNK, n_slots)
        pick = (slot >= s0) & (slot < s1)
        rhs = np.zeros((2 * n, s1 - s0))
        rhs[U[pick], slot[pick] - s0] = 1.0
        sol = solve_many(rhs)
        mine = (slot[Jj] >= s0) & (slot[Jj] < s1)
        vals[mine] = sol[U[Ii[mine]], slot[Jj[mine]] - s0]
    G = sp.csr_matrix((vals, (Ii, Jj)), shape=(len(U), len(U)))
    return U, G


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
    w_pin: float = tol.W_PIN,
    w_asap: float = tol.W_ASAP,
    max_iter: int = tol.ARAP_MAX_ITER,
    step_tol: float = tol.ARAP_STEP_TOL,
    history: int = tol.ANDERSON_HISTORY,
) -> tuple[np.ndarray, StitchInfo]:
    """Stitch per-triangle targets into continuous panels.

    Local/global iterations (Liu et al. 2008) accelerated by Anderson mixing (Peng et al.
    2018) with their safeguard: an accelerated iterate is kept only when the energy after
    a plain step from it falls below the energy after the plain step it replaces (both
    meet the seam constraints, so they compare); else the history restarts. The result
    is always a plain step's output, so the constraints hold at the last linearisation.

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
    asap_faces : (k,) int array, optional
        Triangles of the panels that keep their outline shape (as-similar-as-possible).
    asap_exclude : (n,) bool array, optional
        Outline vertices left free even on those panels.
    ease : SeamEase, optional
        Seam-length constraints (:func:`ptailor.method.ease.seam_ease`), enforced exactly
        with Lagrange multipliers: each global step solves the KKT system through a Schur
        complement on the one factorisation. They switch on once the free iterations
        settle (last step below ``tol.SEAM_START_STEP``, or half of ``max_iter``) and
        only when a seam misses its ratio by more than ``tol.SEAM_EXACT_REL``.
    panel_weight : (n_panels,) float array, optional
        Each panel's whole energy (ARAP, pin, as-similar-as-possible) is scaled by its
        weight. A panel alone comes out the same; where seam constraints tie panels, a
        heavier one takes less of the distortion. Default all 1.
    w_pin, w_asap : float
        Term weights.
    max_iter : int
        Local/global iterations at most.
    step_tol : float
        Converged when no panel's last step moved a vertex (after removing the panel's
        rigid motion) by more than this fraction of the panel's size.
    history : int
        Anderson history length; 0 for plain local/global.

    Returns
    -------
    X : (n, 2) float array
        Stitched positions; vertices no triangle uses keep their original position.
    info : StitchInfo
    """
    n = len(V2)
    if vertex_panel is None:
        from scipy.sparse.csgraph import connected_components

        m = len(F2)
        adj = sp.csr_matrix(
            (np.ones(3 * m), (F2.ravel(), np.roll(F2, -1, axis=1).ravel())), shape=(n, n)
        )
        vertex_panel = connected_components(adj, directed=False)[1]
    vlab = np.where(np.isin(np.arange(n), F2), vertex_panel, -1)
    n_panels = int(vlab.max()) + 1 if n else 0
    D0, D1 = gradient_operators(F2, targets, n)
    used = vlab >= 0
    stiff = np.ones(max(n_panels, 1)) if panel_weight is None else np.asarray(panel_weight)
    # each panel's whole energy scaled by its weight: alone, a panel's solution is the same;
    # sewn to others by the seam constraints, a stiffer panel takes less of the distortion
    area = 0.5 * np.abs(det2(targets)) * stiff[vlab[F2[:, 0]]]
    # unused vertices: identity rows so the system stays non-singular and they stay put
    pin_w = np.zeros(n)
    pin_w[pins] = w_pin * stiff[vlab[pins]]
    pin_w[~used] = 1.0
    L = laplacian(F2, targets, area, n) + sp.diags(pin_w)
    B = None
    if asap_faces is not None and len(asap_faces):
        B = asap_rows(V2, F2, np.asarray(asap_faces), exclude=asap_exclude)
        if panel_weight is not None and B.shape[0]:
            B = sp.diags(np.sqrt(stiff[vlab[B.indices[B.indptr[:-1]] % n]])) @ B
    if B is None or B.shape[0] == 0:
        # x and y decouple: one n x n factor serves both coordinates
        B = None
        solve_L = factor(L)

        def solve_many(rhs: np.ndarray) -> np.ndarray:
            c = rhs.shape[1]
            sol = solve_L(np.concatenate([rhs[:n], rhs[n:]], axis=1))
            return np.concatenate([sol[:, :c], sol[:, c:]], axis=0)

    else:
        solve_2n = factor(sp.block_diag([L, L]) + w_asap * (B.T @ B))

        def solve_many(rhs: np.ndarray) -> np.ndarray:
            return solve_2n(rhs)

    def solve(rhs: np.ndarray) -> np.ndarray:
        return solve_many(rhs[:, None])[:, 0]

    if ease is not None and not ease.n_rows:
        ease = None
    # the seam constraints switch on once the free iterations have settled and only if
    # they miss a seam (an identity edit or a uniform scale never pays for them)
    seam_block_: list = []
    pin_rhs = pin_w[:, None] * V2

    def jacobians(X: np.ndarray) -> np.ndarray:
        return np.stack([D0 @ X, D1 @ X], axis=2)  # (m, 2, 2): J[:, c, j] = Dj @ X[:, c]

    def energy(X: np.ndarray) -> float:
        J = jacobians(X)
        e = float(area @ ((J - closest_rotations(J)) ** 2).sum(axis=(1, 2)))
        e += float((pin_w[pins, None] * (X[pins] - V2[pins]) ** 2).sum())
        if B is not None:
            e += float(w_asap * ((B @ X.T.ravel()) ** 2).sum())
        return e

    def global_step(R: np.ndarray, X_lin: np.ndarray | None) -> np.ndarray:
        rhs = np.empty((n, 2))
        for c in range(2):
            rhs[:, c] = D0.T @ (area * R[:, c, 0]) + D1.T @ (area * R[:, c, 1])
        rhs += pin_rhs
        y = solve(rhs.T.ravel())
        if seam_block_ and X_lin is not None:
            U, G = seam_block_
            C = ease.rows(X_lin)
            Cs = C[:, U]
            M = (Cs @ G @ Cs.T).toarray()
            lam = _solve_spd(M, C @ y)
            if lam is not None:
                y_c = y - solve(C.T @ lam)
                if np.all(np.isfinite(y_c)):
                    y = y_c  # else the constraints are skipped this step (reported)
        return y.reshape(2, n).T

    def step(X: np.ndarray) -> np.ndarray:
        return global_step(closest_rotations(jacobians(X)), X)

    # panel sizes, for a scale-free convergence test
    size = np.ones(max(n_panels, 1))
    if n_panels:
        lo = np.full((n_panels, 2), np.inf)
        hi = np.full((n_panels, 2), -np.inf)
        np.minimum.at(lo, vlab[used], V2[used])
        np.maximum.at(hi, vlab[used], V2[used])
        size = np.maximum(np.linalg.norm(hi - lo, axis=1), 1e-300)

    def residual(X: np.ndarray, GX: np.ndarray) -> np.ndarray:
        """Per panel: the largest vertex move of the step, rigid motion removed, / size."""
        d = np.linalg.norm(rigid_fit_groups(GX, X, vlab, n_panels) - X, axis=1)
        out = np.zeros(n_panels)
        np.maximum.at(out, vlab[used], d[used])
        return out / size

    def finite_or_fail(Y: np.ndarray) -> np.ndarray:
        if not np.all(np.isfinite(Y)):
            from ptailor.errors import PtailorError

            raise PtailorError(
                "flatten: the stitching solver diverged (non-finite positions); check the "
                "flatten weights and the edit"
            )
        return Y

    R0 = np.broadcast_to(np.eye(2), (len(F2), 2, 2)).copy()
    X = finite_or_fail(global_step(R0, None))
    GX = finite_or_fail(step(X))
    res = residual(X, GX)
    acc = Anderson(m=history)
    e_gx = energy(GX) if history else 0.0
    it, converged = 0, False
    hist: list[float] = []
    stalled, since = False, 0
    for it in range(1, max_iter + 1):
        hist.append(float(res.max(initial=0.0)))
        w, h = tol.ARAP_STALL_ITER, hist[since:]
        stall = len(h) > 2 * w and min(h[-w:]) > (1.0 - tol.ARAP_STALL_GAIN) * min(h[:-w])
        done = not len(res) or res.max() <= step_tol
        settled = done or stall or res.max() <= tol.SEAM_START_STEP or it > max_iter // 2
        if stall and (
            seam_block_ or ease is None or ease.violation(GX).max() <= tol.SEAM_EXACT_REL
        ):
            stalled = True  # a long run that no longer improves: stop (deterministically)
            break
        if stall:
            since = len(hist)  # the seams switch on below; give them their own window
        if (
            settled
            and ease is not None
            and not seam_block_
            and ease.violation(GX).max() > tol.SEAM_EXACT_REL
        ):
            seam_block_.extend(
                seam_block(solve_many, ease, np.maximum(vlab, 0), n, coupled=B is not None)
            )
            acc.reset()
            X = GX
            GX = finite_or_fail(step(X))
            res = residual(X, GX)
            e_gx = energy(GX) if history else 0.0
            continue
        if done:
            converged = True
            break
        if history:
            # Peng et al.'s safeguard, on the plain steps' outputs: those meet the seam
            # constraints, so their energies compare (mixed iterates' do not)
            Xa = acc.next(X.ravel(), GX.ravel()).reshape(n, 2)
            GXa = step(Xa) if np.all(np.isfinite(Xa)) else Xa
            e_a = energy(GXa) if np.all(np.isfinite(GXa)) else np.inf
            if e_a < e_gx:
                X, GX, e_gx = Xa, GXa, e_a
                res = residual(X, GX)
                continue
            acc.reset()
        X = GX
        GX = finite_or_fail(step(X))
        res = residual(X, GX)
        e_gx = energy(GX) if history else 0.0
    X = GX  # a plain step: the constraints hold at the last linearisation
    X[~used] = V2[~used]
    viol = float(ease.violation(X).max()) if ease is not None else 0.0
    if not seam_block_ and viol > tol.SEAM_EXACT_REL:
        converged = False  # the cap came before the seams could be enforced
    return X, StitchInfo(
        iterations=it,
        energy=energy(X),
        converged=converged,
        panel_residual=res,
        seam_violation=viol,
        history=tuple(hist),
        stalled=stalled,
    )


def _solve_spd(M: np.ndarray, r: np.ndarray) -> np.ndarray | None:
    """Solve a small symmetric positive (semi-)definite system, least squares if singular.

    None when there is no finite solution (the caller skips the constraints).
    """
    import scipy.linalg as sla

    if not (np.all(np.isfinite(M)) and np.all(np.isfinite(r))):
        return None
    try:
        return sla.cho_solve(sla.cho_factor(M), r)
    except (sla.LinAlgError, ValueError):
        pass
    try:
        out = np.linalg.lstsq(M, r, rcond=None)[0]
    except (np.linalg.LinAlgError, ValueError):
        return None
    return out if np.all(np.isfinite(out)) else None
