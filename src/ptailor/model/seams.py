"""Seams: 3D edges whose triangles use different 2D edges, chained into curves.

A drape edge of two triangles is a seam when their pattern edges differ. A drape edge of
three or more triangles is a T-seam (a placket, pocket or strip sewn onto the middle of a
panel, or a piece inserted into a seam): each piece sewn on is a seam with the panel it is
sewn to, see :func:`seam_halfedges`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ptailor.geometry.topology import edge_groups, edge_keys, half_edges


@dataclass(frozen=True)
class Seam:
    """One seam curve between two panels (or a panel and itself).

    Attributes
    ----------
    panels : tuple of int
        Panel indices ``(a, b)``, ``a <= b``.
    edges3 : (k, 2) int array
        The seam's edges in the drape, indices into ``V3``.
    edges_a, edges_b : (k, 2) int arrays
        The same edges in the pattern on panel ``a``'s and panel ``b``'s side, into ``V2``.
    """

    panels: tuple[int, int]
    edges3: np.ndarray
    edges_a: np.ndarray
    edges_b: np.ndarray

    def lengths(self, V2: np.ndarray) -> tuple[float, float]:
        """Total 2D length of each side for pattern positions ``V2``."""

        def total(E: np.ndarray) -> float:
            return float(np.linalg.norm(V2[E[:, 1]] - V2[E[:, 0]], axis=1).sum())

        return total(self.edges_a), total(self.edges_b)


def seam_halfedges(F3: np.ndarray, F2: np.ndarray) -> np.ndarray:
    """Pairs of half-edges on the two sides of every seam edge.

    Parameters
    ----------
    F3, F2 : (m, 3) int arrays
        Drape and pattern triangles.

    Returns
    -------
    (k, 2) int array
        Half-edge ids (``3 * face + corner``, see
        :func:`~ptailor.geometry.topology.half_edges`), the smaller id first,
        ordered by drape edge (then by the pattern edges of the sewn-on side).

    Notes
    -----
    A drape edge of two faces whose pattern edges differ gives one pair. A drape edge of
    ``k > 2`` faces (a T-seam: a placket, pocket or strip sewn onto the middle of a panel,
    or a piece inserted into a seam) is split into its *sides*: the half-edges that use one
    pattern edge (the panel's two faces at an interior edge of that panel are one side: one
    2D edge, so no seam between them). The side with the most half-edges (ties: the
    smallest pattern edge) is the *base*; every other side is a seam with it, one pair
    each, so ``k - 1`` sides give ``k - 2`` or ``k - 1`` independent pairs and never a
    cycle (a cycle would make the seam-ease constraints redundant). Each side is
    represented by its smallest half-edge id, the base by one of its half-edges that runs
    against the other side's (so the pair is consistently oriented where the cloth is),
    else its smallest. Faces with a repeated drape vertex are ignored.
    """
    F3 = np.asarray(F3, dtype=np.int64).reshape(-1, 3)
    F2 = np.asarray(F2, dtype=np.int64).reshape(-1, 3)
    return _seam_halfedges(F3, F2)


def _seam_halfedges(F3: np.ndarray, F2: np.ndarray) -> np.ndarray:
    """:func:`seam_halfedges` of int64 ``(m, 3)`` arrays, computed."""
    h3, h2 = half_edges(F3), half_edges(F2)
    if len(h3) == 0:
        return np.zeros((0, 2), dtype=np.int64)
    proper = np.repeat((F3[:, 0] != F3[:, 1]) & (F3[:, 1] != F3[:, 2]) & (F3[:, 2] != F3[:, 0]), 3)
    k3 = np.where(proper, edge_keys(h3), -1)
    order, inv, cnt = edge_groups(k3)
    c = np.where(proper, cnt[inv], 0)
    idx = order[c[order] == 2]  # by edge, then by half-edge id
    first, second = idx[0::2], idx[1::2]
    same_dir = h3[first, 0] == h3[second, 0]
    e2_second = np.where(same_dir[:, None], h2[second], h2[second][:, ::-1])
    is_seam = np.any(h2[first] != e2_second, axis=1)
    pairs = np.stack([first[is_seam], second[is_seam]], axis=1)
    multi = np.flatnonzero(c >= 3)
    if len(multi):
        tp = _multi_seam_pairs(h3, h2, inv, multi, int(F2.max()) + 1)
        pairs = np.concatenate([pairs, tp])
        edge = inv[pairs[:, 0]]
        k2 = edge_keys(h2[pairs.max(axis=1)], n=int(F2.max()) + 1)
        pairs = pairs[np.lexsort((k2, edge))]
    return pairs


def _multi_seam_pairs(
    h3: np.ndarray, h2: np.ndarray, inv: np.ndarray, multi: np.ndarray, n2: int
) -> np.ndarray:
    """Seam pairs at drape edges of three or more faces (:func:`seam_halfedges` notes).

    Parameters
    ----------
    h3, h2 : (3m, 2) int arrays
        Drape and pattern half-edges.
    inv : (3m,) int array
        Drape edge id of each half-edge.
    multi : (q,) int array
        Half-edge ids on drape edges of three or more faces.
    n2 : int
        Bound on the pattern vertex indices.

    Returns
    -------
    (p, 2) int array
        Half-edge pairs, the smaller id first.
    """
    e = inv[multi]
    k2 = edge_keys(h2[multi], n=n2)
    # sides: (drape edge, pattern edge) groups
    o = np.lexsort((multi, k2, e))
    s_e, s_k, s_h = e[o], k2[o], multi[o]
    new_side = np.r_[True, (s_e[1:] != s_e[:-1]) | (s_k[1:] != s_k[:-1])]
    side = np.cumsum(new_side) - 1
    side_size = np.bincount(side)
    side_rep = s_h[new_side]  # smallest half-edge id of each side
    side_e, side_k = s_e[new_side], s_k[new_side]
    # the base side of each drape edge: most half-edges, then smallest pattern edge
    so = np.lexsort((side_k, -side_size, side_e))
    is_base = np.zeros(len(side_rep), dtype=bool)
    is_base[so[np.r_[True, side_e[so][1:] != side_e[so][:-1]]]] = True
    # the base's representatives for each direction (drape half-edge runs low -> high)
    fwd = h3[s_h, 0] < h3[s_h, 1]
    n_e = int(inv.max()) + 1
    big = np.iinfo(np.int64).max
    rep_dir = np.full((n_e, 2), big, dtype=np.int64)
    on_base = is_base[side]
    np.minimum.at(rep_dir, (s_e[on_base], fwd[on_base].astype(np.int64)), s_h[on_base])
    others = ~is_base
    if not others.any():
        return np.zeros((0, 2), dtype=np.int64)
    oh = side_rep[others]
    oe = side_e[others]
    ofwd = (h3[oh, 0] < h3[oh, 1]).astype(np.int64)
    against = rep_dir[oe, 1 - ofwd]
    along = rep_dir[oe, ofwd]
    base_h = np.where(against != big, against, along)
    return np.sort(np.stack([base_h, oh], axis=1), axis=1)


def _chain(e3: np.ndarray, key: np.ndarray) -> np.ndarray:
    """Curve label of each seam edge: edges of one key sharing a drape vertex chain."""
    from scipy.sparse.csgraph import connected_components  # (imports scipy.sparse.linalg)

    k = len(e3)
    node_key = np.repeat(key.astype(np.int64), 2) * (int(e3.max()) + 1) + e3.ravel()
    _, kinv = np.unique(node_key, return_inverse=True)
    B = sp.coo_matrix(
        (np.ones(2 * k), (np.repeat(np.arange(k), 2), kinv.ravel())), shape=(k, kinv.max() + 1)
    ).tocsr()
    return connected_components(B @ B.T, directed=False)[1]


def seam_curve_labels(F3: np.ndarray, pairs: np.ndarray, face_panel: np.ndarray) -> np.ndarray:
    """Seam curve of each half-edge pair (:func:`seam_halfedges`), ``(s,)`` int from 0.

    Pairs between the same two panels whose drape edges share a vertex form one curve,
    as in :func:`seams`.
    """
    if len(pairs) == 0:
        return np.zeros(0, dtype=np.int64)
    e3 = half_edges(F3)[pairs[:, 0]]
    pa, pb = face_panel[pairs[:, 0] // 3], face_panel[pairs[:, 1] // 3]
    n_p = int(face_panel.max()) + 1
    key = np.minimum(pa, pb) * n_p + np.maximum(pa, pb)
    return np.unique(_chain(e3, key), return_inverse=True)[1].ravel()


def seams(
    F3: np.ndarray,
    F2: np.ndarray,
    face_panel: np.ndarray,
    *,
    halfedges: np.ndarray | None = None,
) -> list[Seam]:
    """Find the seams of a garment, T-seams included (:func:`seam_halfedges`).

    Parameters
    ----------
    F3, F2 : (m, 3) int arrays
        Drape and pattern triangles.
    face_panel : (m,) int array
        Panel index of each triangle.
    halfedges : (k, 2) int array, optional
        ``seam_halfedges(F3, F2)`` when the caller already has it (a garment's
        structure); computed here otherwise.

    Returns
    -------
    list of Seam
        Sorted by panel pair, then by the smallest drape vertex on the curve.
    """
    m = len(F3)
    if m == 0:
        return []
    h3 = half_edges(F3)
    h2 = half_edges(F2)
    face = np.repeat(np.arange(m), 3)
    pairs = seam_halfedges(F3, F2) if halfedges is None else halfedges
    first, second = pairs[:, 0], pairs[:, 1]
    # align the second side's 2D edge to the first side's 3D direction
    same_dir = h3[first, 0] == h3[second, 0]
    e3 = h3[first]
    ea = h2[first]
    eb = np.where(same_dir[:, None], h2[second], h2[second][:, ::-1])
    pa, pb = face_panel[face[first]], face_panel[face[second]]
    swap = pa > pb
    pa, pb = np.where(swap, pb, pa), np.where(swap, pa, pb)
    ea, eb = np.where(swap[:, None], eb, ea), np.where(swap[:, None], ea, eb)
    k = len(e3)
    if k == 0:
        return []
    n_p = int(face_panel.max()) + 1
    pair = pa * n_p + pb
    lab = _chain(e3, pair)
    order = np.lexsort((e3.min(axis=1), pair, lab))
    out: list[Seam] = []
    lab_sorted = lab[order]
    cuts = np.flatnonzero(np.diff(lab_sorted)) + 1
    for grp in np.split(order, cuts):
        out.append(
            Seam(
                panels=(int(pa[grp[0]]), int(pb[grp[0]])),
                edges3=e3[grp],
                edges_a=ea[grp],
                edges_b=eb[grp],
            )
        )
    out.sort(key=lambda s: (s.panels, int(s.edges3.min())))
    return out
