"""Cotangent weights of triangle meshes in any dimension: per corner, per edge, and the
symmetric weight matrix of the cotangent Laplacian (:func:`cotangent_weights`)."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ptailor.method import tolerances as method_tol

__all__ = ["corner_cotangents", "cotangent_weights", "edge_matrix"]

DEGENERATE_REL = method_tol.DEFORM_DEGENERATE_REL


def corner_cotangents(V: np.ndarray, F: np.ndarray, eps: float) -> np.ndarray:
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


def edge_matrix(F: np.ndarray, w: np.ndarray, n: int) -> sp.csr_matrix:
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
    return edge_matrix(F, 0.5 * corner_cotangents(V, F, eps), V.shape[0])
