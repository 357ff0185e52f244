"""Carry points drawn on a pattern to the adjusted pattern by barycentric coordinates."""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from ptailor import tolerances as tol
from ptailor.errors import PtailorError
from ptailor.geometry.segments import segment_feet
from ptailor.method import tolerances as method_tol


@dataclass(frozen=True)
class PointLocation:
    """Where points sit on a triangulated pattern.

    Attributes
    ----------
    face : (k,) int array
        Index (into the full ``F``) of the triangle each point is in, or nearest to.
    bary : (k, 3) float array
        Barycentric coordinates in that triangle (negative outside it: the triangle's
        affine map is extended, so points just off the mesh keep their offset).
    distance : (k,) float array
        Distance from the point to that triangle (0 inside).
    """

    face: np.ndarray
    bary: np.ndarray
    distance: np.ndarray


def barycentric_2d(P: np.ndarray, T: np.ndarray) -> np.ndarray:
    """Barycentric coordinates of points in triangles.

    Parameters
    ----------
    P : (..., 2) float array
    T : (..., 3, 2) float array
        Triangle corners, broadcast against ``P``.

    Returns
    -------
    (..., 3) float array
        Coordinates summing to 1; a degenerate triangle gives its first corner's (1, 0, 0).
    """
    a, b, c = T[..., 0, :], T[..., 1, :], T[..., 2, :]
    u, v, w = b - a, c - a, P - a
    det = u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]
    ok = np.abs(det) > 0
    s = np.where(ok, (w[..., 0] * v[..., 1] - w[..., 1] * v[..., 0]) / np.where(ok, det, 1), 0)
    t = np.where(ok, (u[..., 0] * w[..., 1] - u[..., 1] * w[..., 0]) / np.where(ok, det, 1), 0)
    return np.stack([1.0 - s - t, s, t], axis=-1)


def _pair_distance(P: np.ndarray, T: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distance from points to triangles (0 inside) and the barycentric coordinates.

    Parameters
    ----------
    P : (..., 2) float array
    T : (..., 3, 2) float array

    Returns
    -------
    distance : (...,) float array
    bary : (..., 3) float array
    """
    bary = barycentric_2d(P, T)
    inside = np.all(bary >= -method_tol.TRANSFER_INSIDE_BARY, axis=-1)
    dist = np.min(
        np.stack(
            [segment_feet(P, T[..., i, :], T[..., (i + 1) % 3, :])[0] for i in range(3)],
            axis=-1,
        ),
        axis=-1,
    )
    return np.where(inside, 0.0, dist), bary


def locate_points(
    V: np.ndarray, F: np.ndarray, P: np.ndarray, *, faces: np.ndarray | None = None
) -> PointLocation:
    """The triangle each point lies in (or is nearest to), with barycentric coordinates.

    Exact for any mix of triangle sizes: a first guess among the triangles with the
    nearest centroids bounds each point's distance to the mesh by ``d``; then every
    triangle that can be within ``d`` is examined. Triangles are grouped by size (their
    centroid-to-corner radius ``r``, in powers of two), one k-d tree of centroids per
    group, queried within ``d + r_max`` of the group: a triangle at distance ``<= d`` has
    its centroid within ``d + r``. Points found inside a triangle by the first guess are
    done (distance 0).

    Parameters
    ----------
    V : (n, 2) float array
    F : (m, 3) int array
    P : (k, 2) float array
        Points to locate.
    faces : (j,) int array, optional
        Only these triangles are candidates (a panel's); default all.

    Returns
    -------
    PointLocation
        Ties (a point on an edge shared by two triangles) go to the triangle whose
        centroid is nearest.

    Raises
    ------
    PtailorError
        A point, or a vertex of a candidate triangle, that is not a finite number (a k-d
        tree cannot hold it).
    """
    P = np.asarray(P, dtype=np.float64).reshape(-1, 2)
    cand_faces = np.arange(len(F)) if faces is None else np.asarray(faces, dtype=np.int64)
    if not np.isfinite(P).all():
        bad = int(np.flatnonzero(~np.isfinite(P).all(axis=1))[0])
        raise PtailorError(f"cannot place marks: point {bad} is not a finite number")
    if len(cand_faces) and not np.isfinite(V[F[cand_faces]]).all():
        raise PtailorError(
            "cannot place marks: the pattern has a vertex that is not a finite number"
        )
    k = len(P)
    if k == 0 or len(cand_faces) == 0:
        return PointLocation(
            face=np.full(k, -1, dtype=np.int64),
            bary=np.zeros((k, 3)),
            distance=np.full(k, np.inf),
        )
    T = V[F[cand_faces]]  # (j, 3, 2)
    C = T.mean(axis=1)  # (j, 2)
    face, dist, bary = _first_guess(P, T, C)
    todo = np.flatnonzero(dist > 0)
    if len(todo):
        _nearest_within(P, T, C, todo, face, dist, bary)
    return PointLocation(face=cand_faces[face], bary=bary, distance=dist)


def _first_guess(
    P: np.ndarray, T: np.ndarray, C: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per point of ``P (k, 2)``, the nearest of the triangles ``T (j, 3, 2)`` with the
    ``TRANSFER_CANDIDATES`` nearest centroids ``C (j, 2)``: ``(face (k,), distance (k,),
    bary (k, 3))``, faces as positions in ``T``."""
    from scipy.spatial import cKDTree  # imported when needed (costly)

    k = len(P)
    kk = min(method_tol.TRANSFER_CANDIDATES, len(T))
    _, idx = cKDTree(C).query(P, k=kk)
    idx = np.asarray(idx).reshape(k, kk)
    d0, b0 = _pair_distance(np.broadcast_to(P[:, None, :], (k, kk, 2)), T[idx])
    best0 = np.argmin(d0, axis=1)
    rows = np.arange(k)
    return idx[rows, best0], d0[rows, best0], b0[rows, best0]


def _nearest_within(
    P: np.ndarray,
    T: np.ndarray,
    C: np.ndarray,
    todo: np.ndarray,
    face: np.ndarray,
    dist: np.ndarray,
    bary: np.ndarray,
) -> None:
    """The exact search for the points ``todo``: every triangle whose centroid is within
    ``d + r`` of the point (``d`` its first guess's distance, ``r`` the triangle's
    centroid-to-corner radius), by size group; ``face``, ``dist`` and ``bary`` updated in
    place where a nearer triangle is found (ties: the nearest centroid)."""
    from scipy.spatial import cKDTree  # imported when needed (costly)

    r = np.linalg.norm(T - C[:, None, :], axis=2).max(axis=1)  # (j,)
    group = np.floor(np.log2(np.maximum(r, tol.TINY) / max(float(r.max()), tol.TINY)))
    group = np.maximum(group, -60.0).astype(np.int64)
    pt_parts, tri_parts = [], []
    for g in np.unique(group).tolist():  # a loop over size groups (a few dozen at most)
        members = np.flatnonzero(group == g)
        lists = cKDTree(C[members]).query_ball_point(
            P[todo], r=dist[todo] + float(r[members].max()) * (1 + tol.ROUNDING_REL)
        )
        counts = np.fromiter((len(a) for a in lists), dtype=np.int64, count=len(todo))
        flat = np.fromiter(
            itertools.chain.from_iterable(lists), dtype=np.int64, count=int(counts.sum())
        )
        pt_parts.append(np.repeat(todo, counts))
        tri_parts.append(members[flat])
    pt = np.concatenate(pt_parts)
    tri = np.concatenate(tri_parts)
    dp, bp = _pair_distance(P[pt], T[tri])
    dc = np.linalg.norm(P[pt] - C[tri], axis=1)
    order = np.lexsort((dc, dp, pt))
    first = order[np.unique(pt[order], return_index=True)[1]]
    better = dp[first] < dist[pt[first]]
    sel = first[better]
    face[pt[sel]] = tri[sel]
    dist[pt[sel]] = dp[sel]
    bary[pt[sel]] = bp[sel]


def carry_points(V_new: np.ndarray, F: np.ndarray, loc: PointLocation) -> np.ndarray:
    """Points at the same barycentric coordinates in the new pattern's triangles.

    Parameters
    ----------
    V_new : (n, 2) float array
        The new pattern, same triangles ``F`` as the one the points were located in.
    F : (m, 3) int array
    loc : PointLocation

    Returns
    -------
    (k, 2) float array
    """
    if len(loc.face) == 0:
        return np.zeros((0, 2))
    return np.einsum("ki,kij->kj", loc.bary, V_new[F[loc.face]])
