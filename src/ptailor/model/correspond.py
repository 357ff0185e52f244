"""Corresponding points of two closed outlines of one piece (two sizes of a graded nest, a
piece before and after an adjustment): point by point when they have the same points, else
by length along them between matched turn points (corners).

A place on an outline is a segment and a fraction along it (:class:`Places`); a field given
at an outline's points (its coordinates, a displacement per point) is read at places by
:func:`at_places`, linearly along each segment.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor import tolerances as tol
from ptailor.geometry.segments import segment_feet


@dataclass(frozen=True)
class Places:
    """Places on a closed outline of ``n`` points: segment ``seg`` runs from point ``seg`` to
    point ``seg + 1`` (the last back to the first), ``t`` the fraction along it.

    Attributes
    ----------
    seg : (q,) int array
    t : (q,) float array
        In ``[0, 1]``.
    how : str
        ``point by point``, ``by length between turn points`` or ``by length along the
        outline`` (no turn points matched), ``nearest`` (:func:`nearest_places`).
    """

    seg: np.ndarray
    t: np.ndarray
    how: str


def at_places(field: np.ndarray, places: Places) -> np.ndarray:
    """A per-point field ``(n, d)`` of a closed outline read at ``places``, ``(q, d)``."""
    field = np.asarray(field, dtype=float)
    nxt = (places.seg + 1) % len(field)
    return field[places.seg] + places.t[:, None] * (field[nxt] - field[places.seg])


def grade_fit(src: np.ndarray, dst: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """The affine map (row vectors: ``x @ A + t``) from outline ``src`` to ``dst`` taken
    point by point (``(k, 2)`` each), or None when they do not correspond: another number of
    points, or an RMS residual beyond ``DXF_GRADE_FIT_REL`` of ``dst``'s diagonal (a grade
    rule moves points, it does not renumber them)."""
    if len(src) != len(dst) or len(src) < 3:
        return None
    X = np.c_[src, np.ones(len(src))]
    M, *_ = np.linalg.lstsq(X, dst, rcond=None)  # (3, 2)
    rms = float(np.sqrt(np.mean(np.sum((X @ M - dst) ** 2, axis=1))))
    diag = float(np.hypot(*np.ptp(dst, axis=0)))
    return (M[:2], M[2]) if rms <= tol.DXF_GRADE_FIT_REL * max(diag, tol.TINY) else None


def point_by_point(src: np.ndarray, dst: np.ndarray) -> bool:
    """Whether outlines ``src`` and ``dst`` (``(k, 2)`` each) correspond point by point
    (:func:`grade_fit` finds a map)."""
    return grade_fit(src, dst) is not None


def _box_map(src: np.ndarray, dst: np.ndarray) -> np.ndarray:
    """``src`` put into ``dst``'s bounding box (per-axis scale and shift), ``(k, 2)``: a
    graded size laid over another to find which of their turn points meet."""
    k = np.ptp(dst, axis=0) / np.maximum(np.ptp(src, axis=0), tol.TINY)
    return (src - src.min(axis=0)) * k + dst.min(axis=0)


def _arc(P: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Each point's length along closed outline ``P`` from ``P[0]``, ``(n,)``, each
    segment's length, ``(n,)``, and the whole length."""
    seg = np.linalg.norm(np.roll(P, -1, axis=0) - P, axis=1)
    return np.r_[0.0, np.cumsum(seg)[:-1]], seg, max(float(seg.sum()), tol.TINY)


def _turn_pairs(
    src: np.ndarray, src_turn: np.ndarray, dst: np.ndarray, dst_turn: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Matched turn points, ``(p,)`` indices into ``src`` and into ``dst``, in order round
    both: mutual nearest turn points (``src`` laid over ``dst``'s bounding box) within
    ``GRADE_TURN_MATCH_REL`` of the diagonal, kept only when they run the same way round
    both outlines. Without any: ``src``'s first point and the ``dst`` point nearest it."""
    S = _box_map(src, dst)
    ts, td = np.flatnonzero(src_turn), np.flatnonzero(dst_turn)
    diag = max(float(np.hypot(*np.ptp(dst, axis=0))), tol.TINY)
    fallback = (np.array([0]), np.array([int(np.argmin(np.linalg.norm(dst - S[0], axis=1)))]))
    if not len(ts) or not len(td):
        return fallback
    d = np.linalg.norm(S[ts][:, None] - dst[td][None], axis=2)  # (ms, md)
    j = np.argmin(d, axis=1)
    mutual = (np.argmin(d, axis=0)[j] == np.arange(len(ts))) & (
        d[np.arange(len(ts)), j] <= tol.GRADE_TURN_MATCH_REL * diag
    )
    a, b = ts[mutual], td[j[mutual]]
    if not len(a):
        return fallback
    step = np.mod(b - b[0], len(dst))  # in order round dst, starting where src's first is
    if len(a) > 1 and not np.all(np.diff(step) > 0):
        return a[:1], b[:1]
    return a, b


def by_length(
    src: np.ndarray, src_turn: np.ndarray, dst: np.ndarray, dst_turn: np.ndarray
) -> Places:
    """Where each point of outline ``src`` falls on outline ``dst``: at the same fraction of
    the length between the same two turn points (corners, matched by :func:`_turn_pairs`).

    Parameters
    ----------
    src, dst : (n, 2), (m, 2) float arrays
        Closed outlines, the same way round (both counter-clockwise).
    src_turn, dst_turn : (n,), (m,) bool arrays
        Their turn points.

    Returns
    -------
    Places
        ``(n,)`` places on ``dst``.
    """
    a, b = _turn_pairs(src, src_turn, dst, dst_turn)
    cs, _, Ls = _arc(src)
    cd, segd, Ld = _arc(dst)
    U = np.mod(cs[a] - cs[a[0]], Ls)  # (p,) anchors' lengths round src from the first
    W = np.mod(cd[b] - cd[b[0]], Ld)
    U, W = np.r_[U, Ls], np.r_[W, Ld]
    u = np.mod(cs - cs[a[0]], Ls)  # (n,)
    i = np.clip(np.searchsorted(U, u, side="right") - 1, 0, len(a) - 1)
    f = (u - U[i]) / np.maximum(U[i + 1] - U[i], tol.TINY)
    pos = np.mod(W[i] + f * (W[i + 1] - W[i]) + cd[b[0]], Ld)
    seg = np.clip(np.searchsorted(cd, pos, side="right") - 1, 0, len(dst) - 1)
    t = np.clip((pos - cd[seg]) / np.maximum(segd[seg], tol.TINY), 0.0, 1.0)
    how = "by length between turn points" if len(a) > 1 else "by length along the outline"
    return Places(seg, t, how)


def corresponding(
    src: np.ndarray, src_turn: np.ndarray, dst: np.ndarray, dst_turn: np.ndarray
) -> Places:
    """Where each point of ``src`` falls on ``dst``: itself when the outlines correspond
    point by point (:func:`point_by_point`), else :func:`by_length`."""
    if point_by_point(src, dst):
        return Places(np.arange(len(src)), np.zeros(len(src)), "point by point")
    return by_length(src, src_turn, dst, dst_turn)


def nearest_places(P: np.ndarray, X: np.ndarray) -> Places:
    """The place on closed outline ``P`` (``(n, 2)``) nearest each of ``X`` (``(q, 2)``)."""
    X = np.asarray(X, dtype=float).reshape(-1, 2)
    A, B = P, np.roll(P, -1, axis=0)
    if not len(X):
        return Places(np.zeros(0, dtype=np.int64), np.zeros(0), "nearest")
    d, foot = segment_feet(X[:, None, :], A[None], B[None])  # (q, n)
    seg = np.argmin(d, axis=1)
    r = np.arange(len(X))
    e = B[seg] - A[seg]
    t = np.einsum("ij,ij->i", foot[r, seg] - A[seg], e) / np.maximum(
        np.einsum("ij,ij->i", e, e), tol.TINY
    )
    return Places(seg, np.clip(t, 0.0, 1.0), "nearest")
