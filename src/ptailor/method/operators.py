"""Sparse operators of the stitching energy: triangle Jacobians, the stitching matrix and the
as-similar-as-possible boundary rows (:mod:`ptailor.method.solver`)."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ptailor import tolerances as tol
from ptailor.geometry.closed_forms import inv2
from ptailor.method import tolerances as method_tol
from ptailor.model.boundary import boundary_loops


def gradient_operator(F: np.ndarray, targets: np.ndarray, n: int) -> sp.csr_matrix:
    """The sparse operator giving each triangle's Jacobian from vertex coordinates.

    Parameters
    ----------
    F : (m, 3) int array
    targets : (m, 2, 2) float array
        Target edge matrices ``[e01, e02]``.
    n : int
        Number of vertices.

    Returns
    -------
    D : (2m, n) sparse matrix
        ``D @ X`` for positions ``X (n, 2)`` stacks ``J[:, :, 0]`` over ``J[:, :, 1]``:
        ``J[:, c, j] = (D @ X)[j m : (j + 1) m, c]``.
    """
    m = len(F)
    Dm = np.array([[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]])
    G = Dm[None] @ inv2(targets)  # (m, 3, 2)
    # three entries per row, built in CSR form directly (no triplet conversion: at 300k
    # triangles its temporaries were ~100 MB the factorisation could not reuse)
    data = np.concatenate([G[:, :, 0].ravel(), G[:, :, 1].ravel()])
    indices = np.tile(F.ravel().astype(np.int32), 2)
    indptr = np.arange(0, 6 * m + 1, 3, dtype=np.int32)
    return sp.csr_matrix((data, indices, indptr), shape=(2 * m, n))


def _laplacian_lower(F: np.ndarray, targets: np.ndarray, area: np.ndarray, n: int):
    """The triangle ARAP matrix ``sum_i A_i G_i G_i^T`` (the cotangent Laplacian of the
    targets, ``G_i`` the hat-function gradients of target ``i``): its diagonal ``(n,)`` and
    its strictly lower entries as triplets (one per triangle edge, int32 indices)."""
    Dm = np.array([[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]])
    G = Dm[None] @ inv2(targets)  # (m, 3, 2) hat-function gradients
    diag = np.bincount(F.ravel(), (area[:, None] * np.einsum("mij,mij->mi", G, G)).ravel(), n)
    a, b = F[:, [0, 1, 2]], F[:, [1, 2, 0]]
    k = area[:, None] * np.einsum("mij,mij->mi", G, G[:, [1, 2, 0]])  # K[a, b] per edge
    rows = np.maximum(a, b).ravel().astype(np.int32)
    cols = np.minimum(a, b).ravel().astype(np.int32)
    return diag, rows, cols, k.ravel()


def stitch_matrix(
    F: np.ndarray,
    targets: np.ndarray,
    area: np.ndarray,
    diagonal: np.ndarray,
    B: sp.spmatrix | None = None,
    w_asap: float = 0.0,
) -> sp.csc_matrix:
    """The lower triangle of the stitching system: the ARAP matrix plus a diagonal, with
    the as-similar-as-possible rows ``w_asap B^T B`` over unknowns ``[x; y]`` when ``B`` is
    given.

    Assembled from triplets in one conversion, so explicit zeros stay in the pattern: two
    target sets on one pattern give one sparsity pattern (the baseline shares ours'
    symbolic factorisation, :class:`ptailor.method.solver.SymbolicCache`).

    Parameters
    ----------
    F : (m, 3) int array
    targets : (m, 2, 2) float array
    area : (m,) float array
        Per-triangle weights.
    diagonal : (n,) float array
        Added to the diagonal (of each coordinate's block).
    B : (b, 2n) sparse matrix, optional
    w_asap : float

    Returns
    -------
    (n, n) sparse matrix, or (2n, 2n) with ``B``
        Lower triangular (CSC, sorted indices, every diagonal entry present).
    """
    n = len(diagonal)
    diag, r, c, v = _laplacian_lower(F, targets, area, n)
    diag += diagonal
    d = np.arange(n, dtype=np.int32)
    if B is None:
        rows, cols, vals = (r, d), (c, d), (v, diag)
        size = n
    else:
        BtB = sp.tril(B.T @ B, format="coo")
        rows = (r, r + n, d, d + n, BtB.row.astype(np.int32))
        cols = (c, c + n, d, d + n, BtB.col.astype(np.int32))
        vals = (v, v, diag, diag, w_asap * BtB.data)
        size = 2 * n
    A = sp.csc_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(size, size)
    )
    # summing the duplicates leaves views of the triplets' length (each inner edge twice:
    # 1.7x the entries, 11 MB at 300,000 triangles, held through the solve): exact copies
    return A.copy()


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
    cos_turn = np.einsum("ij,ij->i", a, b) / np.maximum(na * nb, tol.TINY)
    keep = (length > 0) & (cos_turn >= np.cos(np.radians(method_tol.ASAP_CORNER_DEG)))
    if exclude is not None:
        keep &= ~exclude[cur]
    nrm = np.stack([-chord[:, 1], chord[:, 0]], 1)[keep] / length[keep, None]
    nxt, prv, b = nxt[keep], prv[keep], int(keep.sum())
    r = np.arange(b)
    rows = np.concatenate([r, r, r, r])
    cols = np.concatenate([nxt, nxt + n, prv, prv + n])
    vals = np.concatenate([nrm[:, 0], nrm[:, 1], -nrm[:, 0], -nrm[:, 1]])
    return sp.csr_matrix((vals, (rows, cols)), shape=(b, 2 * n))
