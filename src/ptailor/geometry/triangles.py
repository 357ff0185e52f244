"""Per-triangle measures of a mesh ``(V, F)``: edge matrices, areas, normals."""

from __future__ import annotations

import numpy as np

from ptailor import tolerances as tol


def edge_matrices(V: np.ndarray, F: np.ndarray) -> np.ndarray:
    """Edge matrices of triangles.

    Parameters
    ----------
    V : (n, d) float array
    F : (m, 3) int array

    Returns
    -------
    (m, d, 2) float array
        Columns ``p1 - p0`` and ``p2 - p0``.

    Examples
    --------
    >>> edge_matrices(np.array([[0.0, 0], [1, 0], [0, 2]]), np.array([[0, 1, 2]]))[0]
    array([[1., 0.],
           [0., 2.]])
    """
    p0 = V[F[:, 0]]
    return np.stack([V[F[:, 1]] - p0, V[F[:, 2]] - p0], axis=2)


def edge_lengths(V: np.ndarray, F: np.ndarray) -> np.ndarray:
    """Lengths of the three edges of each triangle.

    Parameters
    ----------
    V : (n, d) float array
    F : (m, 3) int array

    Returns
    -------
    (m, 3) float array
        Edge ``k`` runs from corner ``k`` to corner ``k + 1 (mod 3)``.

    Examples
    --------
    >>> edge_lengths(np.array([[0.0, 0], [3, 0], [0, 4]]), np.array([[0, 1, 2]]))
    array([[3., 5., 4.]])
    """
    d = V[F[:, [1, 2, 0]]] - V[F]
    # the squares summed coordinate by coordinate: what norm(axis=2) sums, in the same
    # order (bit for bit), without its slow reduction over a short axis (3x the time)
    sq = d[..., 0] * d[..., 0]
    for k in range(1, d.shape[2]):
        sq += d[..., k] * d[..., k]
    return np.sqrt(sq)


def signed_areas_2d(V2: np.ndarray, F2: np.ndarray) -> np.ndarray:
    """Signed areas of 2D triangles.

    Parameters
    ----------
    V2 : (n, 2) float array
    F2 : (m, 3) int array

    Returns
    -------
    (m,) float array
        Positive for counter-clockwise triangles.

    Examples
    --------
    >>> signed_areas_2d(np.array([[0.0, 0], [1, 0], [0, 1]]), np.array([[0, 1, 2], [0, 2, 1]]))
    array([ 0.5, -0.5])
    """
    a, b, c = V2[F2[:, 0]], V2[F2[:, 1]], V2[F2[:, 2]]
    u, v = b - a, c - a
    return 0.5 * (u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])


def triangle_normals(V: np.ndarray, F: np.ndarray, *, unit: bool = True) -> np.ndarray:
    """Normals of 3D triangles.

    Parameters
    ----------
    V : (n, 3) float array
    F : (m, 3) int array
    unit : bool
        True: unit normals (zero for a degenerate triangle); False: the cross products
        ``(p1 - p0) x (p2 - p0)``, whose length is twice the area.

    Returns
    -------
    (m, 3) float array

    Examples
    --------
    >>> triangle_normals(np.array([[0.0, 0, 0], [2, 0, 0], [0, 2, 0]]), np.array([[0, 1, 2]]))
    array([[0., 0., 1.]])
    """
    a = V[F[:, 0]]
    cr = np.cross(V[F[:, 1]] - a, V[F[:, 2]] - a)
    if not unit:
        return cr
    return cr / np.maximum(np.linalg.norm(cr, axis=1), tol.TINY)[:, None]


def triangle_areas(V: np.ndarray, F: np.ndarray, *, robust: bool = False) -> np.ndarray:
    """Unsigned areas of triangles in 2D or 3D.

    Parameters
    ----------
    V : (n, 2) or (n, 3) float array
    F : (m, 3) int array
    robust : bool
        Scale each triangle's edges by their largest coordinate first, so that the area of
        any finite triangle is computed without overflow or underflow in the squares (for
        edited drapes that a step may have blown up or collapsed). The default is the plain
        ``|(p1 - p0) x (p2 - p0)| / 2``. Ignored in 2D (signed areas' magnitudes).

    Returns
    -------
    (m,) float array

    Examples
    --------
    >>> V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    >>> triangle_areas(V, np.array([[0, 1, 2]]))
    array([0.5])
    >>> triangle_areas(V * 1e100, np.array([[0, 1, 2]]), robust=True)
    array([5.e+199])
    """
    if V.shape[1] == 2:
        return np.abs(signed_areas_2d(V, F))
    a = V[F[:, 0]]
    u, w = V[F[:, 1]] - a, V[F[:, 2]] - a
    if not robust:
        return 0.5 * _cross_norm(u, w)
    # the largest |coordinate| of the two edges, as max over columns (exact), column by column
    s = np.abs(u[:, 0])
    for col in (u[:, 1], u[:, 2], w[:, 0], w[:, 1], w[:, 2]):
        s = np.maximum(s, np.abs(col))
    s = np.where(s > 0, s, 1.0)
    return 0.5 * _cross_norm(u / s[:, None], w / s[:, None]) * s * s


def _cross_norm(u: np.ndarray, w: np.ndarray) -> np.ndarray:
    """``|u x w|`` per row of two ``(m, 3)`` arrays, written out: the same operations as
    ``np.linalg.norm(np.cross(u, w), axis=1)`` (bit for bit), a third of their time."""
    c0 = u[:, 1] * w[:, 2] - u[:, 2] * w[:, 1]
    c1 = u[:, 2] * w[:, 0] - u[:, 0] * w[:, 2]
    c2 = u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0]
    return np.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
