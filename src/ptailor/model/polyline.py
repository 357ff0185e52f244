"""Closed 2D polylines (piece outlines): area, corners, resampling, folds, clipping.

(The seam-allowance offset is :mod:`ptailor.model.offset`'s, made by GEOS.)
"""

from __future__ import annotations

import numpy as np

from ptailor import tolerances as tol
from ptailor.model import tolerances as model_tol


def signed_area(P: np.ndarray) -> float:
    """Shoelace area of a closed polyline; positive when counter-clockwise.

    Parameters
    ----------
    P : (k, 2) float array
        The first point not repeated.
    """
    x, y = P[:, 0], P[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def dedupe_closed(P: np.ndarray, *, rel: float = model_tol.POLYLINE_DUPLICATE_REL) -> np.ndarray:
    """Indices of the points kept after dropping points equal to their predecessor.

    Parameters
    ----------
    P : (k, 2) float array
    rel : float
        Points closer than this times the polyline's extent count as equal.

    Returns
    -------
    (j,) int array
    """
    if len(P) == 0:
        return np.zeros(0, dtype=np.int64)
    eps = rel * max(float(np.ptp(P, axis=0).max()), tol.TINY)
    step = np.linalg.norm(P - np.roll(P, 1, axis=0), axis=1)
    keep = step > eps
    if not keep.any():
        keep[0] = True
    return np.flatnonzero(keep)


def turn_angles(P: np.ndarray) -> np.ndarray:
    """Unsigned turn at each point of a closed polyline, in degrees (0 = straight on).

    Parameters
    ----------
    P : (k, 2) float array
        No two consecutive points equal.

    Returns
    -------
    (k,) float array
    """
    a = P - np.roll(P, 1, axis=0)
    b = np.roll(P, -1, axis=0) - P
    cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    dot = (a * b).sum(axis=1)
    return np.degrees(np.abs(np.arctan2(cross, dot)))


def corners(P: np.ndarray, *, deg: float = tol.CORNER_DEG) -> np.ndarray:
    """Points where a closed polyline turns by more than ``deg`` degrees.

    Returns
    -------
    (k,) bool array
    """
    if len(P) < 3:
        return np.ones(len(P), dtype=bool)
    return turn_angles(P) > deg


def resample_closed(P: np.ndarray, n: int) -> np.ndarray:
    """``n`` points evenly spaced by arc length along a closed polyline, from ``P[0]``.

    Returns
    -------
    (n, 2) float array
    """
    Q = np.vstack([P, P[:1]])
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(Q, axis=0), axis=1))])
    t = np.linspace(0.0, s[-1], n, endpoint=False)
    return np.stack([np.interp(t, s, Q[:, 0]), np.interp(t, s, Q[:, 1])], axis=1)


def _line_side(P: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Signed distance of points ``(k, 2)`` from the line through ``a`` and ``b`` (left > 0)."""
    d = np.asarray(b, dtype=float) - np.asarray(a, dtype=float)
    n = np.array([-d[1], d[0]]) / max(float(np.hypot(*d)), tol.TINY)
    return (np.asarray(P, dtype=float) - a) @ n


def reflect(P: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Points ``(k, 2)`` mirrored across the line through ``a`` and ``b``."""
    d = np.asarray(b, dtype=float) - np.asarray(a, dtype=float)
    u = d / max(float(np.hypot(*d)), tol.TINY)
    q = np.asarray(P, dtype=float) - a
    return a + 2.0 * np.outer(q @ u, u) - q


def unfold(
    P: np.ndarray, a: np.ndarray, b: np.ndarray, *, rel: float = model_tol.FOLD_ON_LINE_REL
) -> np.ndarray | None:
    """The whole outline of a piece cut on the fold: the half and its mirror image.

    Parameters
    ----------
    P : (k, 2) float array
        The half's closed outline (first point not repeated), counter-clockwise.
    a, b : (2,) float arrays
        The fold (mirror) line's ends.
    rel : float
        Outline points closer to the line than this fraction of the outline's diagonal lie
        on the fold.

    Returns
    -------
    (j, 2) float array or None
        The unfolded outline, counter-clockwise; None when the fold line does not run
        along the outline (two or more consecutive outline points on it).
    """
    P = np.asarray(P, dtype=float)
    k = len(P)
    diag = float(np.hypot(*np.ptp(P, axis=0)))
    on = np.abs(_line_side(P, a, b)) <= rel * max(diag, tol.TINY)
    if on.all() or on.sum() < 2:
        return None
    # the longest cyclic run of points on the line: the fold edge, from i to j
    start = int(np.flatnonzero(~on)[0])
    order = np.roll(np.arange(k), -start)  # begins off the line
    o = on[order]
    edges = np.diff(np.r_[0, o.astype(np.int8), 0])
    s, e = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)  # run [s, e)
    r = int(np.argmax(e - s))
    if e[r] - s[r] < 2:
        return None
    i, j = int(order[s[r]]), int(order[e[r] - 1])  # the fold edge runs i -> j
    chain = P[np.roll(np.arange(k), -j)[: (i - j) % k + 1]]  # j ... i, off the fold
    mirrored = reflect(chain[1:-1], a, b)[::-1]
    whole = np.vstack([chain, mirrored])
    return whole if signed_area(whole) > 0 else whole[::-1].copy()


def clip_half_plane(P: np.ndarray, a: np.ndarray, b: np.ndarray, side: float) -> np.ndarray:
    """The part of a closed outline on one side of the line through ``a`` and ``b``.

    Parameters
    ----------
    P : (k, 2) float array
    a, b : (2,) float arrays
    side : float
        Keep where the signed distance (left of ``a -> b`` positive) has this sign.

    Returns
    -------
    (j, 2) float array
        The clipped outline (one convex cut: Sutherland-Hodgman against one line).
    """
    P = np.asarray(P, dtype=float)
    s = _line_side(P, a, b) * np.sign(side)
    Q, sq = np.roll(P, -1, axis=0), np.roll(s, -1)
    inside = s >= 0
    cross = (s >= 0) != (sq >= 0)
    t = s / np.where(cross, s - sq, 1.0)
    X = P + t[:, None] * (Q - P)
    pts = np.stack([P, X], axis=1).reshape(-1, 2)
    keep = np.stack([inside, cross], axis=1).reshape(-1)
    return pts[keep]
