"""A simulation mesh of bounded size for the re-drape check, and the map back.

A cloth solver's time per step grows with the triangles, and a production export (80k-300k
triangles) would take an hour on a CPU. The re-drape check does not need the export's
resolution: it compares how three patterns hang. So a garment larger than
``Settings.sim_faces`` is simulated on a decimated copy of its drape, built with pymeshlab's
quadric edge collapse (:func:`simulation_mesh`):

- every vertex on a pattern boundary (seams, hems, openings) is kept (only triangles with
  at most one boundary corner are selected for the collapse, and meshlab moves only
  vertices all of whose triangles are selected), so each panel keeps its outline and each
  seam its two sides' shared vertices: the simulation sews the same seams;
- vertices stay where they were (no optimal placement): each simulation vertex is a garment
  vertex, each simulation pattern vertex a pattern vertex, so the rest shapes of any
  pattern on the same triangles come from the same formula on the kept vertices;
- the result is carried back (:meth:`SimMesh.carry`) by each garment vertex's barycentric
  coordinates in the simulation triangle that holds its original pattern position (a point
  of its own panel: the map is piecewise affine on the pattern, as cloth between simulation
  vertices is).

The decimation is checked: every simulation pattern triangle must keep its panel's
orientation (all but ``PROXY_FOLD_TOL`` of them) and the pattern's area within
``PROXY_AREA_TOL``; a decimation that fails is tried again to twice as many triangles
(``PROXY_TARGETS``); when that fails too (or the collapse cannot get below ``max_faces`` by a
useful margin) :func:`simulation_mesh` returns None and the garment is simulated as it is.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor.geometry.labels import component_labels
from ptailor.geometry.triangles import signed_areas_2d
from ptailor.model.boundary import boundary_edges
from ptailor.verify import tolerances as verify_tol

__all__ = ["SimMesh", "simulation_mesh"]


@dataclass(frozen=True)
class SimMesh:
    """A decimated drape and its map back to the garment's vertices.

    Attributes
    ----------
    keep3 : (k3,) int array
        The garment's drape vertices kept, in simulation order.
    F3 : (mc, 3) int array
        Simulation triangles, into ``keep3``.
    keep2 : (k2,) int array
        The pattern vertices kept.
    F2 : (mc, 3) int array
        Simulation pattern triangles, into ``keep2`` (corner ``j`` of ``F2[t]`` is the
        pattern copy of corner ``j`` of ``F3[t]``).
    tri : (n3,) int array
        For each garment drape vertex, the simulation triangle that carries it (-1 for a
        vertex no face uses).
    bary : (n3, 3) float array
        Its barycentric coordinates there (sum 1).
    """

    keep3: np.ndarray
    F3: np.ndarray
    keep2: np.ndarray
    F2: np.ndarray
    tri: np.ndarray
    bary: np.ndarray

    @property
    def n_faces(self) -> int:
        """Simulation triangles."""
        return len(self.F3)

    def carry(self, X: np.ndarray) -> np.ndarray:
        """Values at the simulation vertices carried to every garment drape vertex.

        Parameters
        ----------
        X : (k3, d) or (k3,) float array
            In simulation vertex order.

        Returns
        -------
        (n3, d) or (n3,) float array
            Barycentric interpolation in each vertex's simulation triangle (a kept vertex
            gets its own value exactly); 0 for a vertex no face uses.
        """
        X = np.asarray(X, dtype=float)
        corners = X[self.F3[np.maximum(self.tri, 0)]]  # (n3, 3, ...)
        w = self.bary.reshape(self.bary.shape + (1,) * (X.ndim - 1))
        out = (w * corners).sum(axis=1)
        out[self.tri < 0] = 0.0
        out[self.keep3] = X  # exactly, not through the weights
        return out


def _boundary_vertices(F3: np.ndarray, F2: np.ndarray, n3: int) -> np.ndarray:
    """(n3,) bool: drape vertices on a pattern boundary edge (seams, hems, openings)."""
    p2v = np.zeros(int(F2.max()) + 1, dtype=np.int64)
    p2v[F2.reshape(-1)] = F3.reshape(-1)
    out = np.zeros(n3, dtype=bool)
    out[p2v[boundary_edges(F2)].reshape(-1)] = True
    return out


def _decimate(V3: np.ndarray, F3: np.ndarray, free: np.ndarray, max_faces: int):
    """pymeshlab's quadric edge collapse of the triangles with at least two free corners
    (meshlab moves only vertices whose every triangle is selected: a boundary vertex, which
    has a triangle on its boundary edge with two boundary corners, stays); returns
    (garment vertex index per simulation vertex, simulation faces into them)."""
    import pymeshlab

    m = pymeshlab.Mesh(
        vertex_matrix=np.asarray(V3, dtype=np.float64),
        face_matrix=np.asarray(F3, dtype=np.int32),
        v_scalar_array=free.astype(np.float64),
    )
    m.add_vertex_custom_scalar_attribute(np.arange(len(V3), dtype=np.float64), "ptailor_index")
    ms = pymeshlab.MeshSet()
    ms.add_mesh(m)
    ms.compute_selection_by_condition_per_face(condselect="(q0+q1+q2)>1.5")
    fixed = int((free[F3].sum(axis=1) < 2).sum())  # meshlab's target counts the selection
    ms.meshing_decimation_quadric_edge_collapse(
        targetfacenum=max(int(max_faces) - fixed, 1),
        qualitythr=0.5,
        preserveboundary=True,
        optimalplacement=False,
        preservetopology=True,
        planarquadric=True,
        selected=True,
        autoclean=True,
    )
    c = ms.current_mesh()
    idx = np.rint(c.vertex_custom_scalar_attribute_array("ptailor_index")).astype(np.int64)
    return idx, idx[np.asarray(c.face_matrix(), dtype=np.int64)]


def _copies(F3: np.ndarray, F2: np.ndarray, n3: int) -> np.ndarray:
    """(n3, K) int array: each drape vertex's pattern copies, -1 padded."""
    v3, v2 = F3.reshape(-1), F2.reshape(-1)
    pairs = np.unique(np.stack([v3, v2], axis=1), axis=0)
    start = np.searchsorted(pairs[:, 0], np.arange(n3))
    rank = np.arange(len(pairs)) - start[pairs[:, 0]]
    out = np.full((n3, int(rank.max()) + 1 if len(rank) else 1), -1, dtype=np.int64)
    out[pairs[:, 0], rank] = pairs[:, 1]
    return out


def _components(F2: np.ndarray, n2: int) -> np.ndarray:
    """(n2,) int array: each pattern vertex's panel (connected component of the pattern)."""
    out = np.zeros(n2, dtype=np.int64)
    out[F2] = component_labels(F2, n2)[:, None]
    return out


def _pattern_corners(Fc3, F3, F2, V2, copies, panel) -> np.ndarray | None:
    """The pattern copy of each simulation corner (mc, 3), or None when one is ambiguous.

    A simulation face that is a garment face takes its pattern face; a corner with one copy
    takes it; a seam corner of a new face takes its copy in the panel of the face's
    one-copy corners (the nearest one in the pattern when a panel holds two, as a tube's
    own seam does).
    """
    # garment faces by their sorted corners, one int64 key each
    n = int(max(F3.max(), Fc3.max())) + 1
    code = lambda F: (np.sort(F, axis=1) * [n * n, n, 1]).sum(axis=1)  # noqa: E731
    gk = code(F3)
    order = np.argsort(gk, kind="stable")
    ck = code(Fc3)
    pos = np.minimum(np.searchsorted(gk[order], ck), len(gk) - 1)
    found = gk[order][pos] == ck
    out = np.full(Fc3.shape, -1, dtype=np.int64)
    f = order[pos[found]]
    # corner j of the simulation face is at the position of the same vertex in F3[f]
    at = np.argmax(F3[f][:, None, :] == Fc3[found][:, :, None], axis=2)
    out[found] = np.take_along_axis(F2[f], at, axis=1)
    # new faces: unique copies first
    new = ~found
    C = copies[Fc3[new]]  # (k, 3, K)
    single = (C[:, :, 1:] < 0).all(axis=2) if C.shape[2] > 1 else np.ones(C.shape[:2], bool)
    corner = np.where(single, C[:, :, 0], -1)
    ref = np.argmax(single, axis=1)  # a one-copy corner of each face
    has = single.any(axis=1)
    if not has.all():
        return None
    rows = np.arange(len(C))
    refv = corner[rows, ref]
    want = panel[refv]
    cand = C  # (k, 3, K)
    ok = (cand >= 0) & (panel[np.maximum(cand, 0)] == want[:, None, None])
    d = np.linalg.norm(V2[np.maximum(cand, 0)] - V2[refv][:, None, None, :], axis=3)
    d = np.where(ok, d, np.inf)
    pick = np.take_along_axis(cand, np.argmin(d, axis=2)[:, :, None], axis=2)[:, :, 0]
    if not np.isfinite(d.min(axis=2)).all():
        return None
    out[new] = np.where(single, corner, pick)
    return out


def _locate(P, labels, V2, F2s, tri_label):
    """For points ``P`` (n, 2) of panels ``labels``: the simulation pattern triangle (into
    ``F2s``, pattern indices into ``V2``) of the same panel holding each, or the nearest,
    and the barycentric coordinates there. The candidates are the triangles with the
    nearest centroids; a point outside all of them (next to a long sliver) is tried again
    with eight times as many."""
    from scipy.spatial import cKDTree

    T = V2[F2s]  # (mc, 3, 2)
    big = 10.0 * float(np.ptp(V2, axis=0).max() + 1.0)  # panels apart in a third coordinate
    tree = cKDTree(np.c_[T.mean(axis=1), big * tri_label])
    tri, W = _nearest_holding(tree, big, T, P, labels, tri_label, verify_tol.PROXY_CANDIDATES)
    out = W.min(axis=1) < -verify_tol.PROXY_OUTSIDE_BARY
    if out.any():
        tri[out], W[out] = _nearest_holding(
            tree, big, T, P[out], labels[out], tri_label, 8 * verify_tol.PROXY_CANDIDATES
        )
    return tri, W


def _nearest_holding(tree, big, T, P, labels, tri_label, k):
    """:func:`_locate` with ``k`` candidates per point (``big``: the panels' spacing in
    the tree's third coordinate)."""
    k = min(k, len(T))
    _, cand = tree.query(np.c_[P, big * labels], k=k)
    cand = cand.reshape(len(P), k)
    a, b, c = T[cand, 0], T[cand, 1], T[cand, 2]  # (n, k, 2)
    v0, v1, v2 = b - a, c - a, P[:, None, :] - a
    den = v0[..., 0] * v1[..., 1] - v0[..., 1] * v1[..., 0]
    den = np.where(np.abs(den) > 0, den, np.inf)
    l1 = (v2[..., 0] * v1[..., 1] - v2[..., 1] * v1[..., 0]) / den
    l2 = (v0[..., 0] * v2[..., 1] - v0[..., 1] * v2[..., 0]) / den
    W = np.stack([1.0 - l1 - l2, l1, l2], axis=-1)  # (n, k, 3)
    score = np.where(tri_label[cand] == labels[:, None], W.min(axis=2), -np.inf)
    best = np.argmax(score, axis=1)
    rows = np.arange(len(P))
    return cand[rows, best].copy(), W[rows, best].copy()


def _checked(V3, F3, V2, F2, free, panel, copies, target):
    """One decimation to ``target`` faces and its checks: (simulation faces, their pattern
    corners), or None when it does not help or fails a check."""
    _, Fc3 = _decimate(V3, F3, free, target)
    if len(Fc3) == 0 or len(Fc3) > verify_tol.PROXY_MIN_GAIN * len(F3):
        return None
    corners = _pattern_corners(Fc3, F3, F2, V2, copies, panel)
    if corners is None:
        return None
    a_fine, a_sim = signed_areas_2d(V2, F2), signed_areas_2d(V2, corners)
    sign = np.zeros(int(panel.max()) + 1)
    np.add.at(sign, panel[F2[:, 0]], a_fine)
    if (np.sign(a_sim) != np.sign(sign[panel[corners[:, 0]]])).mean() > verify_tol.PROXY_FOLD_TOL:
        return None  # folded simulation triangles
    if (
        abs(np.abs(a_sim).sum() - np.abs(a_fine).sum())
        > verify_tol.PROXY_AREA_TOL * np.abs(a_fine).sum()
    ):
        return None
    return Fc3, corners


def simulation_mesh(
    V3: np.ndarray, F3: np.ndarray, V2: np.ndarray, F2: np.ndarray, *, max_faces: int
) -> SimMesh | None:
    """The decimated drape to simulate a garment on, when it has more than ``max_faces``.

    Parameters
    ----------
    V3 : (n3, 3) float array
        A drape of the garment (its shape decides the collapse).
    F3 : (m, 3) int array
    V2 : (n2, 2) float array
        A pattern on the same triangles (its panels and boundaries are kept; the carry
        map is built on it).
    F2 : (m, 3) int array
    max_faces : int
        The most simulation triangles wanted (the collapse stops earlier where every
        remaining triangle touches a pattern boundary).

    Returns
    -------
    SimMesh or None
        None when the garment has at most ``max_faces`` triangles, or when the decimation
        would not help or fails its checks (simulate the garment as it is).
    """
    V3 = np.asarray(V3, dtype=float)
    F3 = np.asarray(F3, dtype=np.int64)
    V2 = np.asarray(V2, dtype=float)
    F2 = np.asarray(F2, dtype=np.int64)
    if len(F3) <= max_faces:
        return None
    free = ~_boundary_vertices(F3, F2, len(V3))
    panel = _components(F2, len(V2))
    copies = _copies(F3, F2, len(V3))
    for k in verify_tol.PROXY_TARGETS:
        found = _checked(V3, F3, V2, F2, free, panel, copies, int(k * max_faces))
        if found is not None:
            break
    else:
        return None
    Fc3, corners = found
    keep3, F3s = np.unique(Fc3, return_inverse=True)
    keep2, F2s = np.unique(corners, return_inverse=True)
    F3s, F2s = F3s.reshape(-1, 3), F2s.reshape(-1, 3)
    # each drape vertex at its first pattern copy
    first = copies[:, 0]
    used = first >= 0
    tri = np.full(len(V3), -1, dtype=np.int64)
    bary = np.zeros((len(V3), 3))
    t, w = _locate(V2[first[used]], panel[first[used]], V2, corners, panel[corners[:, 0]])
    tri[used], bary[used] = t, w
    return SimMesh(keep3=keep3, F3=F3s, keep2=keep2, F2=F2s, tri=tri, bary=bary)
