"""Nearest points on line segments."""

from __future__ import annotations

import numpy as np


def segment_feet(P: np.ndarray, A: np.ndarray, B: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The nearest point (foot) of each segment ``AB`` to each point ``P``, and the distance.

    Parameters
    ----------
    P, A, B : (..., d) float arrays
        Broadcast against each other (a point and its candidate segments). A segment of
        zero length has its end ``A`` as foot.

    Returns
    -------
    distance : (...,) float array
    foot : (..., d) float array

    Examples
    --------
    >>> d, foot = segment_feet(np.array([0.5, 1.0]), np.array([0.0, 0]), np.array([2.0, 0]))
    >>> float(d), foot
    (1.0, array([0.5, 0. ]))
    """
    d = B - A
    dd = np.einsum("...i,...i->...", d, d)
    t = np.einsum("...i,...i->...", P - A, d) / np.where(dd > 0, dd, 1.0)
    foot = A + np.clip(t, 0.0, 1.0)[..., None] * d
    return np.linalg.norm(P - foot, axis=-1), foot


def nearest_segment_distance(P: np.ndarray, A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """Distance from each point to the nearest of some segments.

    Parameters
    ----------
    P : (p, d) float array
    A, B : (s, d) float arrays
        Segment ends.

    Returns
    -------
    (p,) float array
        Zeros when there are no segments.

    Examples
    --------
    >>> A, B = np.array([[0.0, 0], [0, 0]]), np.array([[1.0, 0], [0, 1]])
    >>> nearest_segment_distance(np.array([[2.0, 0], [0.5, 0.5]]), A, B)
    array([1. , 0.5])
    """
    if len(P) == 0 or len(A) == 0:
        return np.zeros(len(P))
    d, _ = segment_feet(P[:, None, :], A[None], B[None])
    return d.min(axis=1)


def segment_moments(V: np.ndarray, E: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Centroid and second moment of a set of straight segments as a curve, by arc length.

    ``c = sum |e| m_e / L`` (``m_e`` the midpoint, ``L`` the total length) and
    ``S = sum |e| ((m_e - c)(m_e - c)^T + d_e d_e^T / 12) / L`` (``d_e`` the segment's
    vector): the moments of the curve itself, so splitting a segment at its midpoint
    changes neither (a mesh's seam vertices weighted equally would shift toward its
    finely meshed parts).

    Parameters
    ----------
    V : (n, k) float array
    E : (e, 2) int array
        Segments by their end vertices.

    Returns
    -------
    c : (k,) float array
    S : (k, k) float array
        Both of the vertices' mean and scatter (per vertex) when every segment has zero
        length.
    """
    A, B = V[E[:, 0]], V[E[:, 1]]
    d = B - A
    w = np.linalg.norm(d, axis=1)
    total = float(w.sum())
    if not total > 0:
        P = V[np.unique(E)]
        c = P.mean(axis=0)
        return c, (P - c).T @ (P - c) / max(len(P), 1)
    m = 0.5 * (A + B)
    c = (w @ m) / total
    r = m - c
    S = ((r * w[:, None]).T @ r + (d * w[:, None]).T @ d / 12.0) / total
    return c, S
