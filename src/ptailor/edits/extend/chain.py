"""Offset chains of ``extend``'s pattern mode: the opening's edges in runs, and new points
ordered along the offset's iso-line."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ptailor import tolerances as tol
from ptailor.edits.opening import OpeningEdges


def chain_order(oe: OpeningEdges) -> tuple[np.ndarray, np.ndarray, bool]:
    """The opening's edges grouped into chains: runs that share pattern vertices.

    Consecutive edges of the loop belong to one chain while the end of one is the start of
    the next in the pattern (a seam, or a change of panel, breaks it).

    Parameters
    ----------
    oe : OpeningEdges

    Returns
    -------
    order : (k,) int array
        Edge indices, each chain's edges contiguous and in loop order.
    chain : (k,) int array
        Chain index of each edge of ``order`` (0, 1, ... in that order).
    closed : bool
        True when the whole opening is one closed chain (no seam crosses it).
    """
    k = len(oe.a2)
    ends = oe.b2 != np.roll(oe.a2, -1)  # edge i ends a chain
    if not ends.any():
        return np.arange(k), np.zeros(k, dtype=np.int64), True
    first = (int(np.flatnonzero(ends)[0]) + 1) % k
    order = np.roll(np.arange(k), -first)
    starts = np.roll(ends, 1)[order]
    return order, np.cumsum(starts) - 1, False


def nearest_on(P: np.ndarray, A: np.ndarray, B: np.ndarray, cum: np.ndarray) -> tuple:
    """Nearest point of a polyline to each point.

    Parameters
    ----------
    P : (p, 2) float array
    A, B : (s, 2) float arrays
        The polyline's segments, in order.
    cum : (s,) float array
        Arc length at each segment's start.

    Returns
    -------
    distance : (p,) float array
    sigma : (p,) float array
        Arc length of the nearest point.
    foot : (p, 2) float array
        The nearest point.
    """
    d = B - A
    L2 = np.einsum("ij,ij->i", d, d)
    t = np.einsum("psd,sd->ps", P[:, None] - A[None], d) / np.where(L2 > 0, L2, 1.0)
    t = np.clip(t, 0.0, 1.0)
    F = A[None] + t[..., None] * d[None]
    dist = np.linalg.norm(P[:, None] - F, axis=2)
    j = np.argmin(dist, axis=1)
    r = np.arange(len(P))
    return dist[r, j], cum[j] + t[r, j] * np.sqrt(L2[j]), F[r, j]


def nearest_fn(A: np.ndarray, B: np.ndarray) -> Callable:
    """``near(X) -> (distance, foot)``: the nearest point of some segments to points."""
    zeros = np.zeros(len(A))

    def near(X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        d, _, foot = nearest_on(X, A, B, zeros)
        return d, foot

    return near


def place_offset_chain(
    P: np.ndarray,
    Q: np.ndarray,
    by: float,
    *,
    near: Callable,
    closed: bool,
    ends: np.ndarray | None = None,
) -> np.ndarray:
    """Order an offset chain's new points along the iso-line, re-placing crossed ones.

    Parameters
    ----------
    P : (c, 2) float array
        The chain's pattern vertices, in order (an open chain's ends are seam ends).
    Q : (c, 2) float array
        Each vertex's candidate new point, exactly ``by`` from the opening (NaN where its
        direction never gets that far).
    by : float
    near : callable, keyword-only
        ``near(X) -> (distance, foot)`` for ``X`` ``(p, 2)``: the distance to the panel's
        opening edges and the nearest point on them.
    closed : bool, keyword-only
        A closed chain (vertex ``c - 1`` joins vertex 0).
    ends : (2, 2) float array, optional, keyword-only
        Other new points for an open chain's two ends, used where ``Q``'s (a seam
        continued) is not nearest to the chain's end edge: the seam runs too close along
        the opening to meet the offset near its end.

    Returns
    -------
    (c, 2) float array
        New points in the chain's order, each ``by`` from the opening; NaN everywhere
        when an open chain's end has no candidate nearest to its own end edge (the offset
        closes the opening first), or no point of a closed one is nearest to its own. An
        interior point is kept when its nearest point on the chain lies on its own two
        edges, in order with the kept points around it and between the two ends' (a seam
        continued beyond the opening clips the offset there); the others are spread along
        the chord between the kept points around them by the old chain's arc length, and
        pushed onto the iso-line from their nearest point.
    """
    if closed:
        return _place_closed(P, Q, by, near=near)
    Q = _settled_ends(P, Q, by, near=near, ends=ends)
    if Q is None:  # the offset closes the opening before it reaches an end
        return np.full((len(P), 2), np.nan)
    return _place_open(P, Q, by, near=near)


def _place_closed(P: np.ndarray, Q: np.ndarray, by: float, *, near: Callable) -> np.ndarray:
    """:func:`place_offset_chain` of a closed chain: opened at its first point nearest to
    its own two edges, placed as an open chain from there and back to it."""
    c = len(P)
    finite = np.all(np.isfinite(Q), axis=1)
    Qs = np.where(finite[:, None], Q, P)
    # walk the loop from a point that is kept, and back to it
    Pc = np.vstack([P, P[:1]])
    cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(Pc, axis=0), axis=1))])
    dist, sigma, _ = nearest_on(Qs, Pc[:-1], Pc[1:], cum)
    idx = np.arange(c)
    tol_s = tol.ROUNDING_REL * (cum[-1] + by)
    seg = np.diff(cum)
    # arc length from its own vertex, around the loop either way
    off = (sigma - cum[idx] + 0.5 * cum[-1]) % cum[-1] - 0.5 * cum[-1]
    own = finite & (off >= -np.roll(seg, 1) - tol_s) & (off <= seg + tol_s)
    own &= dist <= near(Qs)[0] + tol_s
    if not own.any():
        return np.full((c, 2), np.nan)
    r = int(np.flatnonzero(own)[0])
    Pr, Qr = np.roll(P, -r, axis=0), np.roll(Q, -r, axis=0)
    out = _place_open(np.vstack([Pr, Pr[:1]]), np.vstack([Qr, Qr[:1]]), by, near=near, loop=True)
    return np.roll(out[:c], r, axis=0)


def _settled_ends(
    P: np.ndarray, Q: np.ndarray, by: float, *, near: Callable, ends: np.ndarray | None
) -> np.ndarray | None:
    """An open chain's candidate points with its two ends settled: each end's own
    candidate where it lies nearest to the chain's end edge, else its ``ends`` one where
    that does; None where neither does for an end (see :func:`place_offset_chain`)."""
    cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(P, axis=0), axis=1))])
    tol_s = tol.ROUNDING_REL * (cum[-1] + by)

    def own_end(E: np.ndarray) -> np.ndarray:
        """Which of two end points lie nearest to their own end edge of the chain."""
        ok = np.all(np.isfinite(E), axis=1)
        E = np.where(ok[:, None], E, P[[0, -1]])
        dist, sigma, _ = nearest_on(E, P[:-1], P[1:], cum)
        ok &= dist <= near(E)[0] + tol_s
        return ok & np.array([sigma[0] <= cum[1] + tol_s, sigma[1] >= cum[-2] - tol_s])

    alt = Q[[0, -1]] if ends is None else ends
    use = np.where(own_end(Q[[0, -1]]), 0, np.where(own_end(alt), 1, 2))
    if np.any(use == 2):
        return None
    Q = Q.copy()
    Q[[0, -1]] = np.where((use == 0)[:, None], Q[[0, -1]], alt)
    return Q


def _place_open(
    P: np.ndarray, Q: np.ndarray, by: float, *, near: Callable, loop: bool = False
) -> np.ndarray:
    """:func:`place_offset_chain` of an open chain whose two end points are settled.

    ``loop``: the chain is a closed one opened at a kept point (its last vertex repeats
    its first), so the ends' arc lengths are its ends', 0 and the whole length.
    """
    c = len(P)
    cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(P, axis=0), axis=1))])
    tol_s = tol.ROUNDING_REL * (cum[-1] + by)
    finite = np.all(np.isfinite(Q), axis=1)
    Qs = np.where(finite[:, None], Q, P)
    dist, sigma, _ = nearest_on(Qs, P[:-1], P[1:], cum)
    if loop:
        sigma[[0, -1]] = cum[[0, -1]]
    idx = np.arange(c)
    ok = finite.copy()
    ok &= sigma >= cum[np.maximum(idx - 1, 0)] - tol_s  # the nearest point is on its own
    ok &= sigma <= cum[np.minimum(idx + 1, c - 1)] + tol_s  # two edges ...
    ok &= dist <= near(Qs)[0] + tol_s  # ... and not on another chain
    ok &= (sigma > sigma[0]) & (sigma < sigma[-1])  # between the ends' (clipped by seams)
    ok[[0, -1]] = True
    for _ in range(c):  # iterations: drop kept pairs out of order until none is
        kept = np.flatnonzero(ok)
        bad = np.diff(sigma[kept]) <= 0
        if not bad.any():
            break
        drop = np.union1d(kept[:-1][bad], kept[1:][bad])
        ok[drop[(drop > 0) & (drop < c - 1)]] = False
    left = np.maximum.accumulate(np.where(ok, idx, 0))
    right = np.minimum.accumulate(np.where(ok, idx, c - 1)[::-1])[::-1]
    span = cum[right] - cum[left]
    f = np.where(span > 0, (cum - cum[left]) / np.where(span > 0, span, 1.0), 0.0)
    X = Qs[left] + f[:, None] * (Qs[right] - Qs[left])
    _, foot = near(X)
    away = X - foot
    n = np.linalg.norm(away, axis=1)
    X = np.where((n > 0)[:, None], foot + by * away / np.where(n > 0, n, 1.0)[:, None], X)
    return np.where(ok[:, None], Qs, X)
