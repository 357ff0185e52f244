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
