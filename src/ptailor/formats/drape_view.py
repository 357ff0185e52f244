"""A drape seen from the front: orthographic projection along the garment's front axis, and
which points of it are seen (a depth buffer, numpy only).

The view's coordinates are the wearer's left (to the viewer's right: the wearer faces the
viewer) and up; a point's depth is its distance behind the frontmost plane (smaller is
nearer the viewer).

Examples
--------
>>> from ptailor.samples import cylinder
>>> g = cylinder()
>>> P, depth = front_view(g.V3, g.frame)
>>> buf = depth_buffer(P, depth, g.F3)
>>> front, back = depth < np.median(depth), depth > np.percentile(depth, 75)
>>> bool(buf.seen(P[front], depth[front]).all()), bool(buf.seen(P[back], depth[back]).any())
(True, False)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor import tolerances as tol
from ptailor.formats.raster import box_pixels
from ptailor.model.frame import Frame


def front_view(V3: np.ndarray, frame: Frame) -> tuple[np.ndarray, np.ndarray]:
    """Points of the drape in the front view.

    Parameters
    ----------
    V3 : (n, 3) float array
    frame : Frame
        The garment's (:attr:`ptailor.model.Garment.frame`).

    Returns
    -------
    P : (n, 2) float array
        ``(left, up)``: x to the viewer's right, y up.
    depth : (n,) float array
        Along the wearer's back (``-front``): larger is further from the viewer.
    """
    X = np.asarray(V3, dtype=np.float64) @ frame.matrix().T
    return X[:, :2].copy(), -X[:, 2]


@dataclass(frozen=True)
class DepthBuffer:
    """The nearest depth of the drape at each pixel of the front view.

    Attributes
    ----------
    origin : (2,) float array
        The view point at the corner of pixel ``(0, 0)``.
    pixel : float
        A pixel's side, in view units.
    Z : (h, w) float array
        Row ``i`` covers ``origin[1] + [i, i + 1) * pixel`` (up), column ``j``
        ``origin[0] + [j, j + 1) * pixel``: the nearest depth at the pixel centres of it and
        its eight neighbours; ``inf`` where no triangle is.
    slack : float
        How far behind the nearest depth a point still counts as seen: the drape's
        thickness at a seam, a pixel's worth of slope.
    """

    origin: np.ndarray
    pixel: float
    Z: np.ndarray
    slack: float

    def seen(self, Q: np.ndarray, depth: np.ndarray) -> np.ndarray:
        """Whether each point is seen from the front.

        Parameters
        ----------
        Q : (k, 2) float array
            View points.
        depth : (k,) float array

        Returns
        -------
        (k,) bool array
            True where no part of the drape lies more than ``slack`` in front of it.
        """
        h, w = self.Z.shape
        ij = np.floor((np.asarray(Q, dtype=np.float64) - self.origin) / self.pixel).astype(int)
        j = np.clip(ij[:, 0], 0, w - 1)
        i = np.clip(ij[:, 1], 0, h - 1)
        return np.asarray(depth) <= self.Z[i, j] + self.slack


def depth_buffer(
    P: np.ndarray, depth: np.ndarray, F: np.ndarray, *, pixels: int = 600, slack: float = 0.03
) -> DepthBuffer:
    """The depth buffer of triangles in the front view.

    Parameters
    ----------
    P : (n, 2) float array
        View points (:func:`front_view`).
    depth : (n,) float array
    F : (m, 3) int array
    pixels : int
        Pixels along the view's longer side (a picture's resolution, not a result's).
    slack : float
        :attr:`DepthBuffer.slack` as a share of the view's longer side.

    Returns
    -------
    DepthBuffer
        Each pixel's centre takes the nearest depth of the triangles covering it (depth
        interpolated linearly); triangles seen edge-on cover none.
    """
    P = np.asarray(P, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64).reshape(-1, 3)
    used = P[F.ravel()] if len(F) else P
    origin = used.min(axis=0) if len(used) else np.zeros(2)
    size = float(np.ptp(used, axis=0).max()) if len(used) else 1.0
    size = max(size, tol.TINY)
    pixel = size / pixels
    shape = (
        tuple(int(np.ceil(x / pixel)) + 1 for x in np.ptp(used, axis=0)[::-1])
        if len(used)
        else (1, 1)
    )
    Z = np.full(shape, np.inf)
    T = P[F] - origin  # (m, 3, 2)
    D = np.asarray(depth, dtype=np.float64)[F]
    e1, e2 = T[:, 1] - T[:, 0], T[:, 2] - T[:, 0]
    det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    flat = np.abs(det) > tol.TINY
    tri, i, j = box_pixels(T[flat].min(axis=1) / pixel, T[flat].max(axis=1) / pixel, shape)
    tri = np.flatnonzero(flat)[tri]
    q = (np.stack([j, i], axis=1) + 0.5) * pixel - T[tri, 0]
    b1 = (q[:, 0] * e2[tri, 1] - q[:, 1] * e2[tri, 0]) / det[tri]
    b2 = (e1[tri, 0] * q[:, 1] - e1[tri, 1] * q[:, 0]) / det[tri]
    inside = (b1 >= 0.0) & (b2 >= 0.0) & (b1 + b2 <= 1.0)
    z = D[tri, 0] + b1 * (D[tri, 1] - D[tri, 0]) + b2 * (D[tri, 2] - D[tri, 0])
    np.minimum.at(Z.reshape(-1), (i * shape[1] + j)[inside], z[inside])
    return DepthBuffer(origin, pixel, _min_filter(Z), slack * size)


def _min_filter(Z: np.ndarray) -> np.ndarray:
    """Each pixel's minimum over its 3 x 3 neighbourhood: a point on the drape's outline
    (half a pixel outside the centres its triangles cover) still finds its depth."""
    h, w = Z.shape
    pad = np.pad(Z, 1, constant_values=np.inf)
    return np.min([pad[a : a + h, b : b + w] for a in range(3) for b in range(3)], axis=0)
