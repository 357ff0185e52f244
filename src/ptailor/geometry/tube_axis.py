"""The axis of a tube-like surface (a sleeve, a skirt), from its normals."""

from __future__ import annotations

import numpy as np

from ptailor import tolerances as tol
from ptailor.geometry.triangles import triangle_normals


def normal_tensor(V: np.ndarray, F: np.ndarray) -> np.ndarray:
    """The area-weighted normal tensor ``sum 2 A n n^T``, normalised to unit trace.

    Parameters
    ----------
    V : (n, 3) float array
    F : (m, 3) int array

    Returns
    -------
    (3, 3) float array
        Symmetric, trace 1 (zero for a surface without area).

    Examples
    --------
    >>> V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    >>> normal_tensor(V, np.array([[0, 1, 2]]))[2]
    array([0., 0., 1.])
    """
    cr = triangle_normals(V, F, unit=False)  # |cr| = 2 area, so cr cr^T / |cr| = 2 area n n^T
    w = np.linalg.norm(cr, axis=1)
    nrm = cr / np.maximum(w, tol.TINY)[:, None]
    N = (nrm * w[:, None]).T @ nrm
    return N / max(np.trace(N), tol.TINY)


def tube_axis(
    V: np.ndarray,
    F: np.ndarray,
    *,
    min_eig: float = tol.GRAIN_TUBE_MIN,
    ratio: float = tol.GRAIN_TUBE_RATIO,
) -> np.ndarray | None:
    """The direction the normals of a tube-like surface avoid, or None for a sheet.

    The surface is tube-like when the middle eigenvalue of its :func:`normal_tensor`
    exceeds ``min_eig`` and ``ratio`` times the smallest; its axis is then the eigenvector
    of the smallest eigenvalue.

    Parameters
    ----------
    V : (n, 3) float array
    F : (m, 3) int array
        The surface's triangles.
    min_eig, ratio : float
        ``tolerances.GRAIN_TUBE_MIN`` and ``GRAIN_TUBE_RATIO`` (the ``axis: auto`` rule of
        the edits and the grain line of the pieces).

    Returns
    -------
    (3,) float array or None
        Unit vector, of either sign.

    Examples
    --------
    >>> t = np.linspace(0, 2 * np.pi, 13)[:-1]
    >>> ring = np.stack([np.cos(t), np.sin(t), np.zeros(12)], 1)
    >>> V = np.concatenate([ring, ring + [0, 0, 3]])
    >>> i, j = np.arange(12), (np.arange(12) + 1) % 12
    >>> F = np.concatenate([np.stack([i, j, i + 12], 1), np.stack([j, j + 12, i + 12], 1)])
    >>> np.abs(tube_axis(V, F)).round(12)
    array([0., 0., 1.])
    >>> tube_axis(V, F[:1]) is None
    True
    """
    lam, vec = np.linalg.eigh(normal_tensor(V, F))
    if lam[1] > min_eig and lam[1] > ratio * lam[0]:
        return vec[:, 0]
    return None


def extent_axis(P: np.ndarray) -> np.ndarray:
    """The direction of largest extent of points (principal axis of their scatter).

    Parameters
    ----------
    P : (k, 3) float array

    Returns
    -------
    (3,) float array
        Unit vector, of either sign.

    Examples
    --------
    >>> np.abs(extent_axis(np.array([[0.0, 0, 0], [0, 5, 0], [0, 2, 0]]))).round(12)
    array([0., 1., 0.])
    """
    P = P - P.mean(axis=0)
    return np.linalg.eigh(P.T @ P)[1][:, -1]
