"""Carry points drawn on a pattern to the adjusted pattern by barycentric coordinates."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

#: Candidate triangles examined per point (nearest by centroid).
_CANDIDATES = 32


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


def segment_feet(P: np.ndarray, A: np.ndarray, B: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The nearest point of each segment ``AB`` to each point ``P``, and the distance.

    Parameters
    ----------
    P, A, B : (..., 2) float arrays
        Broadcast against each other (a point and its candidate segments).

    Returns
    -------
    distance : (...,) float array
    foot : (..., 2) float array
    """
    d = B - A
    dd = np.einsum("...i,...i->...", d, d)
    t = np.einsum("...i,...i->...", P - A, d) / np.where(dd > 0, dd, 1.0)
    foot = A + np.clip(t, 0.0, 1.0)[..., None] * d
    return np.linalg.norm(P - foot, axis=-1), foot


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


def locate_points(
    V: np.ndarray, F: np.ndarray, P: np.ndarray, *, faces: np.ndarray | None = None
) -> PointLocation:
    """The triangle each point lies in (or is nearest to), with barycentric coordinates.

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
    """
    P = np.asarray(P, dtype=np.float64).reshape(-1, 2)
    cand_faces = np.arange(len(F)) if faces is None else np.asarray(faces, dtype=np.int64)
    k = len(P)
    if k == 0 or len(cand_faces) == 0:
        return PointLocation(
            face=np.full(k, -1, dtype=np.int64),
            bary=np.zeros((k, 3)),
            distance=np.full(k, np.inf),
        )
    T = V[F[cand_faces]]  # (j, 3, 2)
    kk = min(_CANDIDATES, len(cand_faces))
    _, idx = cKDTree(T.mean(axis=1)).query(P, k=kk)
    idx = np.asarray(idx).reshape(k, kk)
    Tc = T[idx]  # (k, kk, 3, 2)
    Pc = np.broadcast_to(P[:, None, :], (k, kk, 2))
    bary = barycentric_2d(Pc, Tc)
    inside = np.all(bary >= -1e-12, axis=-1)
    dist = np.min(
        np.stack(
            [segment_feet(Pc, Tc[..., i, :], Tc[..., (i + 1) % 3, :])[0] for i in range(3)],
            axis=-1,
        ),
        axis=-1,
    )
    dist = np.where(inside, 0.0, dist)
    best = np.argmin(dist, axis=1)
    rows = np.arange(k)
    return PointLocation(
        face=cand_faces[idx[rows, best]],
        bary=bary[rows, best],
        distance=dist[rows, best],
    )


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
