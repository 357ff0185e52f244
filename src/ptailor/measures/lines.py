"""Material lines: polylines drawn on the cloth, one segment per triangle, with barycentric
ends, so the same line has a length in the drape and in the pattern.

A point of measure is a material line: a plane's section of some triangles (a girth, a
length down a panel) or a chain of triangle edges (an opening, a seam). Its drape length sums
its segments in ``V3`` and its pattern length the same segments in ``V2``: each segment lies
in one triangle, whose pattern image is that triangle in ``F2``, so the pattern length is
what a pattern maker measures on the flat pieces the line crosses.

Examples
--------
>>> V3 = np.array([[0.0, 0, 0], [2, 0, 0], [0, 2, 0]])
>>> F = np.array([[0, 1, 2]])
>>> line = plane_section(V3, F, point=[0, 1, 0], normal=[0, 1, 0])
>>> round(line_length(line, V3, F), 6)
1.0
>>> round(line_length(line, 2 * V3[:, :2], F), 6)
2.0
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ptailor.measures import tolerances as measures_tol


@dataclass(frozen=True)
class MaterialLine:
    """Segments on the cloth, each inside one triangle.

    Attributes
    ----------
    face : (k,) int array
        The triangle each segment lies in.
    P, Q : (k, 3) float arrays
        Barycentric coordinates of each segment's ends in its triangle (rows sum to 1).
    key_p, key_q : (k,) int arrays
        An id of each end's place on the drape (the drape edge or vertex it lies on), equal
        where two segments meet: what :func:`line_pieces` chains segments by.
    """

    face: np.ndarray
    P: np.ndarray
    Q: np.ndarray
    key_p: np.ndarray
    key_q: np.ndarray

    def __len__(self) -> int:
        return len(self.face)

    def subset(self, keep) -> MaterialLine:
        """The segments selected by a boolean mask or index array ``keep``."""
        return MaterialLine(
            self.face[keep], self.P[keep], self.Q[keep], self.key_p[keep], self.key_q[keep]
        )


EMPTY = MaterialLine(
    np.zeros(0, dtype=np.int64),
    np.zeros((0, 3)),
    np.zeros((0, 3)),
    np.zeros(0, dtype=np.int64),
    np.zeros(0, dtype=np.int64),
)


def line_points(line: MaterialLine, V: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Both ends of every segment in positions ``V`` (drape or pattern).

    Parameters
    ----------
    line : MaterialLine
    V : (n, d) float array
    F : (m, 3) int array
        ``F3`` with ``V3``, ``F2`` with ``V2``.

    Returns
    -------
    ((k, d) float array, (k, d) float array)
    """
    C = np.asarray(V, dtype=np.float64)[np.asarray(F)[line.face]]  # (k, 3, d)
    return np.einsum("kc,kcd->kd", line.P, C), np.einsum("kc,kcd->kd", line.Q, C)


def line_length(line: MaterialLine, V: np.ndarray, F: np.ndarray) -> float:
    """Total length of the line's segments in positions ``V`` with triangles ``F``."""
    if len(line) == 0:
        return 0.0
    A, B = line_points(line, V, F)
    return float(np.linalg.norm(B - A, axis=1).sum())


def _edge_key(a: np.ndarray, b: np.ndarray, n: int) -> np.ndarray:
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    return lo.astype(np.int64) * (n + 1) + hi


def plane_section(V3, F3, *, point, normal, faces=None) -> MaterialLine:
    """The section of triangles by a plane.

    Parameters
    ----------
    V3 : (n, 3) float array
    F3 : (m, 3) int array
    point : (3,) float array
        A point of the plane.
    normal : (3,) float array
        The plane's normal (any length but zero).
    faces : (m,) bool array or int array, optional
        The triangles to cut (all when None).

    Returns
    -------
    MaterialLine
        One segment per triangle the plane crosses. A vertex on the plane (within
        ``PLANE_SNAP`` of the size of ``V3``'s bounding box) counts as on its positive side,
        so a triangle edge lying in the plane is counted once (in the triangle on the negative
        side), never twice, and a triangle touching the plane at one corner has no segment.
    """
    V3 = np.asarray(V3, dtype=np.float64)
    F3 = np.asarray(F3, dtype=np.int64).reshape(-1, 3)
    idx = np.arange(len(F3)) if faces is None else np.asarray(faces)
    if idx.dtype == bool:
        idx = np.flatnonzero(idx)
    n = np.asarray(normal, dtype=np.float64)
    d = (V3 - np.asarray(point, dtype=np.float64)) @ (n / np.linalg.norm(n))
    size = float(np.linalg.norm(np.ptp(V3, axis=0))) if len(V3) else 0.0
    d[np.abs(d) <= measures_tol.PLANE_SNAP * size] = 0.0
    Fi = F3[idx]
    D = d[Fi]  # (k, 3)
    pos = D >= 0.0
    cross = pos != np.roll(pos, -1, axis=1)  # edge c -> c+1 crosses
    hit = cross.sum(axis=1) == 2
    Fi, D, cross, idx = Fi[hit], D[hit], cross[hit], idx[hit]
    k = len(idx)
    if k == 0:
        return EMPTY
    # the two crossed edges of each triangle, in corner order
    c = np.sort(np.argsort(~cross, axis=1, kind="stable")[:, :2], axis=1)
    rows = np.arange(k)[:, None]
    c0, c1 = c, (c + 1) % 3
    d0, d1 = D[rows, c0], D[rows, c1]
    t = d0 / (d0 - d1)
    W = np.zeros((k, 2, 3))
    W[rows, [0, 1], c0] = 1.0 - t
    W[rows, [0, 1], c1] += t
    nV = len(V3)
    keys = _edge_key(Fi[rows, c0], Fi[rows, c1], nV)
    # an end at a vertex (t of 0 or 1) is keyed by the vertex, so segments meeting there chain
    at0, at1 = t == 0.0, t == 1.0
    vkey = -1 - np.where(at0, Fi[rows, c0], Fi[rows, c1])
    keys = np.where(at0 | at1, vkey, keys)
    real = keys[:, 0] != keys[:, 1]  # not a triangle touching the plane at one corner
    return MaterialLine(idx[real], W[real, 0], W[real, 1], keys[real, 0], keys[real, 1])


def levels_across(V, F, faces, *, axis, count: int) -> np.ndarray:
    """``count`` evenly spaced levels along ``axis`` over the extent of some triangles (none at
    its very ends: each in the middle of its ``1 / count`` slice).

    Parameters
    ----------
    V : (n, 3) float array
    F : (m, 3) int array
    faces : (k,) int array
        The triangles.
    axis : (3,) float array
        Unit vector.
    count : int

    Returns
    -------
    (count,) float array
        Positions along ``axis`` (a plane through ``t * axis`` with normal ``axis``).
    """
    h = np.asarray(V, dtype=np.float64)[np.unique(np.asarray(F)[faces])] @ np.asarray(axis)
    lo, hi = float(h.min()), float(h.max())
    return lo + (np.arange(count) + 0.5) / count * (hi - lo)


def edge_line(F3, halfedges) -> MaterialLine:
    """Triangle edges as a material line (an opening, one side of a seam).

    Parameters
    ----------
    F3 : (m, 3) int array
    halfedges : (k,) int array
        Half-edge ids ``3 * face + corner``: the edge from corner ``c`` to ``c + 1``.

    Returns
    -------
    MaterialLine
        Ends keyed by their drape vertices.
    """
    F3 = np.asarray(F3, dtype=np.int64).reshape(-1, 3)
    h = np.asarray(halfedges, dtype=np.int64)
    face, c = h // 3, h % 3
    k = len(h)
    P = np.zeros((k, 3))
    Q = np.zeros((k, 3))
    P[np.arange(k), c] = 1.0
    Q[np.arange(k), (c + 1) % 3] = 1.0
    return MaterialLine(face, P, Q, -1 - F3[face, c], -1 - F3[face, (c + 1) % 3])


def line_pieces(line: MaterialLine) -> tuple[np.ndarray, int, np.ndarray]:
    """The connected pieces of a line and whether each is a closed loop.

    Returns
    -------
    label : (k,) int array
        Piece per segment.
    count : int
    closed : (count,) bool array
        True where every end of the piece's segments meets exactly one other end.
    """
    k = len(line)
    if k == 0:
        return np.zeros(0, dtype=np.int64), 0, np.zeros(0, dtype=bool)
    keys, inv = np.unique(np.r_[line.key_p, line.key_q], return_inverse=True)
    seg = np.r_[np.arange(k), np.arange(k)]
    # segments x keys incidence; pieces are components of the bipartite graph
    n = k + len(keys)
    A = coo_matrix((np.ones(2 * k), (seg, k + inv)), shape=(n, n))
    _, lab = connected_components(A, directed=False)
    label = lab[:k]
    uniq, label = np.unique(label, return_inverse=True)
    degree = np.bincount(inv, minlength=len(keys))
    touching = np.empty(len(keys), dtype=np.int64)
    touching[inv] = seg  # a segment at each key
    key_piece = label[touching]
    open_piece = np.zeros(len(uniq), dtype=bool)
    np.logical_or.at(open_piece, key_piece, degree != 2)
    return label, len(uniq), ~open_piece


def line_piece_lengths(line: MaterialLine, V, F) -> np.ndarray:
    """Length of each piece of :func:`line_pieces` in positions ``V``."""
    label, count, _ = line_pieces(line)
    if count == 0:
        return np.zeros(0)
    A, B = line_points(line, V, F)
    return np.bincount(label, weights=np.linalg.norm(B - A, axis=1), minlength=count)
