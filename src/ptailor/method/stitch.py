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

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ptailor import tolerances as tol
from ptailor.method.intrinsic import det2, inv2
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
        True when the relative energy change fell below the tolerance.
    """

    iterations: int
    energy: float
    converged: bool


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


@dataclass(frozen=True)
class SeamSprings:
    """Springs on both sides of each seam edge that keep the sides' length ratio.

    Attributes
    ----------
    E : (2s, n) sparse matrix
        Edge-difference operator: rows ``0..s-1`` the a-side edges, ``s..2s-1`` the b-side.
    rho : (s,) float array
        Original length ratio ``|e_b| / |e_a|`` (the ease).
    target : (2s, 2) float array
        Current target edge vectors.
    """

    E: sp.csr_matrix
    rho: np.ndarray
    target: np.ndarray

    @staticmethod
    def build(
        V2: np.ndarray, F2: np.ndarray, targets: np.ndarray, pairs: np.ndarray
    ) -> SeamSprings:
        """Springs for half-edge ``pairs``, starting at the target triangles' edges."""
        from ptailor.model.seams import half_edges

        h2 = half_edges(F2)
        ends = np.concatenate([h2[pairs[:, 0]], h2[pairs[:, 1]]])  # (2s, 2)
        s2 = len(ends)
        r = np.arange(s2)
        E = sp.csr_matrix(
            (np.concatenate([-np.ones(s2), np.ones(s2)]), (np.concatenate([r, r]), ends.T.ravel())),
            shape=(s2, len(V2)),
        )
        length0 = np.linalg.norm(E @ V2, axis=1)
        s = s2 // 2
        rho = length0[s:] / np.maximum(length0[:s], 1e-300)
        # start: the edge as its target triangle has it (corner positions 0, e01, e02)
        P = np.concatenate([np.zeros((len(targets), 1, 2)), np.swapaxes(targets, 1, 2)], axis=1)
        h = np.concatenate([pairs[:, 0], pairs[:, 1]])
        f, c = h // 3, h % 3
        start = P[f, (c + 1) % 3] - P[f, c]
        return SeamSprings(E=E, rho=rho, target=start)

    def local_step(self, X: np.ndarray) -> SeamSprings:
        """Targets along the current edges, at the common length that best fits both sides."""
        e = self.E @ X
        length = np.maximum(np.linalg.norm(e, axis=1), 1e-300)
        s = len(self.rho)
        la, lb = length[:s], length[s:]
        common = (la / self.rho + lb) / (1.0 / self.rho**2 + 1.0)  # the b-side length
        want = np.concatenate([common / self.rho, common])
        return SeamSprings(E=self.E, rho=self.rho, target=e * (want / length)[:, None])


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


def closest_rotations(J: np.ndarray) -> np.ndarray:
    """Closest rotations (det +1) to 2x2 matrices, in closed form.

    Parameters
    ----------
    J : (m, 2, 2) float array

    Returns
    -------
    (m, 2, 2) float array
    """
    ang = np.arctan2(J[:, 1, 0] - J[:, 0, 1], J[:, 0, 0] + J[:, 1, 1])
    c, s = np.cos(ang), np.sin(ang)
    return np.stack([np.stack([c, -s], 1), np.stack([s, c], 1)], 1)


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

    lu = splu(
        sp.csc_matrix(A),
        permc_spec="MMD_AT_PLUS_A",
        diag_pivot_thresh=0.0,
        options={"SymmetricMode": True},
    )
    return lu.solve


def stitch(
    V2: np.ndarray,
    F2: np.ndarray,
    targets: np.ndarray,
    *,
    pins: np.ndarray,
    asap_faces: np.ndarray | None = None,
    asap_exclude: np.ndarray | None = None,
    seam_pairs: np.ndarray | None = None,
    w_pin: float = tol.W_PIN,
    w_asap: float = tol.W_ASAP,
    w_seam: float = tol.W_SEAM,
    max_iter: int = tol.ARAP_MAX_ITER,
    rel_tol: float = tol.ARAP_REL_TOL,
) -> tuple[np.ndarray, StitchInfo]:
    """Stitch per-triangle targets into continuous panels.

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
    asap_faces : (k,) int array, optional
        Triangles of the panels that keep their outline shape (as-similar-as-possible).
    asap_exclude : (n,) bool array, optional
        Outline vertices left free even on those panels.
    seam_pairs : (s, 2) int array, optional
        Half-edge pairs on the two sides of each seam edge
        (:func:`ptailor.model.seams.seam_halfedges`). Each side gets a spring toward a
        common length chosen in the local step so the two sides keep their original
        length ratio (ease): ``w_seam sum |e_a - (l / rho) d_a|^2 + |e_b - l d_b|^2``.
    w_pin, w_asap, w_seam : float
        Term weights.
    max_iter : int
        Local/global iterations at most.
    rel_tol : float
        Stop when the relative energy change falls below this.

    Returns
    -------
    X : (n, 2) float array
        Stitched positions; vertices no triangle uses keep their original position.
    info : StitchInfo
    """
    n = len(V2)
    D0, D1 = gradient_operators(F2, targets, n)
    area = 0.5 * np.abs(det2(targets))
    used = np.zeros(n, dtype=bool)
    used[F2.ravel()] = True
    # unused vertices: identity rows so the system stays non-singular and they stay put
    pin_w = np.zeros(n)
    pin_w[pins] = w_pin
    pin_w[~used] = 1.0
    L = laplacian(F2, targets, area, n) + sp.diags(pin_w)
    seam = None
    if seam_pairs is not None and len(seam_pairs):
        seam = SeamSprings.build(V2, F2, targets, np.asarray(seam_pairs))
        L = L + w_seam * (seam.E.T @ seam.E)
    B = None
    if asap_faces is not None and len(asap_faces):
        B = asap_rows(V2, F2, np.asarray(asap_faces), exclude=asap_exclude)
    if B is None or B.shape[0] == 0:
        # x and y decouple: one n x n factor serves both coordinates
        B = None
        solve_L = factor(L)

        def solve(rhs: np.ndarray) -> np.ndarray:
            return solve_L(rhs.reshape(2, n).T).T.ravel()

    else:
        solve = factor(sp.block_diag([L, L]) + w_asap * (B.T @ B))
    pin_rhs = pin_w[:, None] * V2

    def jacobians(X: np.ndarray) -> np.ndarray:
        return np.stack([D0 @ X, D1 @ X], axis=2)  # (m, 2, 2): J[:, c, j] = Dj @ X[:, c]

    def energy(X: np.ndarray, J: np.ndarray, R: np.ndarray) -> float:
        e = float(area @ ((J - R) ** 2).sum(axis=(1, 2)))
        if seam is not None:
            e += float(w_seam * ((seam.E @ X - seam.target) ** 2).sum())
        e += float(w_pin * ((X[pins] - V2[pins]) ** 2).sum())
        if B is not None:
            e += float(w_asap * ((B @ X.T.ravel()) ** 2).sum())
        return e

    def global_step(R: np.ndarray) -> np.ndarray:
        rhs = np.empty((n, 2))
        for c in range(2):
            rhs[:, c] = D0.T @ (area * R[:, c, 0]) + D1.T @ (area * R[:, c, 1])
        rhs += pin_rhs
        if seam is not None:
            rhs += w_seam * (seam.E.T @ seam.target)
        return solve(rhs.T.ravel()).reshape(2, n).T

    R = np.broadcast_to(np.eye(2), (len(F2), 2, 2)).copy()
    X = global_step(R)
    scale = float(area.sum()) + 1e-300
    e_prev = np.inf
    it, converged = 0, False
    for it in range(1, max_iter + 1):  # noqa: B007 - iterations, not triangles
        J = jacobians(X)
        R = closest_rotations(J)
        if seam is not None:
            seam = seam.local_step(X)
        e = energy(X, J, R)
        if e <= tol.ARAP_ZERO_ENERGY * scale or abs(e_prev - e) <= rel_tol * max(e, 1e-300):
            converged = True
            break
        X = global_step(R)
        e_prev = e
    X[~used] = V2[~used]
    return X, StitchInfo(iterations=it, energy=energy(X, jacobians(X), R), converged=converged)
