"""Polylines sketched in a view: which side of one a point lies on, whether one meets a box."""

from __future__ import annotations

import numpy as np

from ptailor import tolerances as tol


def polyline_side(P: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """Signed distance of 2D points to a polyline extended straight beyond its ends.

    Positive on the left of the direction of travel. Uses the nearest segment (the end
    segments extended to infinity), so a polyline that crosses the garment splits it.

    Parameters
    ----------
    P : (n, 2) float array
    Q : (k, 2) float array
        Polyline, ``k >= 2``.

    Returns
    -------
    (n,) float array
    """
    A, B = Q[:-1], Q[1:]
    AB = B - A
    L2 = np.maximum((AB * AB).sum(1), tol.TINY)
    AP = P[:, None, :] - A[None]
    t = (AP * AB[None]).sum(2) / L2[None]
    lo = np.where(np.arange(len(A)) == 0, -np.inf, 0.0)
    hi = np.where(np.arange(len(A)) == len(A) - 1, np.inf, 1.0)
    t = np.clip(t, lo[None], hi[None])
    D = AP - t[..., None] * AB[None]
    dist = np.sqrt((D * D).sum(2))
    j = np.argmin(dist, axis=1)
    r = np.arange(len(P))
    side = AB[j, 0] * AP[r, j, 1] - AB[j, 1] * AP[r, j, 0]
    # nearest to an inner vertex: the side comes from the vertex's pseudo-normal (the sum of
    # its two segments' left normals), since either segment alone can give the wrong sign
    tj = t[r, j]
    vtx = np.where(tj >= 1.0, j + 1, np.where(tj <= 0.0, j, -1))
    inner = (vtx > 0) & (vtx < len(Q) - 1)
    nl = np.stack([-AB[:, 1], AB[:, 0]], 1) / np.sqrt(L2)[:, None]
    vi = vtx[inner]
    n_v = nl[vi - 1] + nl[vi]
    side[inner] = ((P[inner] - Q[vi]) * n_v).sum(1)
    return np.where(side >= 0, 1.0, -1.0) * dist[r, j]


def segments_meet_box(Q: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> bool:
    """Whether any segment of a 2D polyline meets an axis-aligned box (Liang-Barsky).

    Parameters
    ----------
    Q : (k, 2) float array
    lo, hi : (2,) float arrays
    """
    A, D = Q[:-1], Q[1:] - Q[:-1]
    t0 = np.zeros(len(A))
    t1 = np.ones(len(A))
    ok = np.ones(len(A), dtype=bool)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for c in range(2):  # the two coordinates
            flat = D[:, c] == 0
            ok &= ~(flat & ((A[:, c] < lo[c]) | (A[:, c] > hi[c])))
            ta = (lo[c] - A[:, c]) / D[:, c]
            tb = (hi[c] - A[:, c]) / D[:, c]
            t0 = np.where(flat, t0, np.maximum(t0, np.minimum(ta, tb)))
            t1 = np.where(flat, t1, np.minimum(t1, np.maximum(ta, tb)))
    return bool(np.any(ok & (t0 <= t1)))
