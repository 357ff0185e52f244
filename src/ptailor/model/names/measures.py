"""What panel naming measures on the drape: per-panel areas, centroids and extents in the
wearer's frame, the boundary and seam edges between panels, and where openings touch them."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor import tolerances as tol
from ptailor.geometry.topology import edge_keys, half_edges
from ptailor.geometry.triangles import triangle_areas
from ptailor.model import tolerances as model_tol
from ptailor.model.openings import Opening


@dataclass(frozen=True)
class PanelMeasures:
    """Areas and positions of the panels in the wearer's frame ``(left, up, front)``.

    Attributes
    ----------
    X : (n3, 3) float array
        Drape positions in the frame.
    area : (m,) float array
        Triangle areas.
    At : (n_p,) float array
        Panel areas.
    cen_abs : (n_p, 3) float array
        Area-weighted panel centroids (absolute, in the frame).
    lo_abs, hi_abs : (n_p, 3) float arrays
        Per-panel extents (absolute).
    s0, f0 : float
        The centre line's left and front coordinates (area-weighted means).
    h0, H : float
        The garment's lowest height and its height.
    """

    X: np.ndarray
    area: np.ndarray
    At: np.ndarray
    cen_abs: np.ndarray
    lo_abs: np.ndarray
    hi_abs: np.ndarray
    s0: float
    f0: float
    h0: float
    H: float


def _per_panel_extent(X: np.ndarray, lab: np.ndarray, n_p: int) -> tuple[np.ndarray, np.ndarray]:
    """Per-panel min and max of face-corner coordinates.

    Parameters
    ----------
    X : (m, 3, 3) float array
        Corner coordinates per face.
    lab : (m,) int array
    n_p : int

    Returns
    -------
    lo, hi : (n_p, 3) float arrays
    """
    lo = np.full((n_p, 3), np.inf)
    hi = np.full((n_p, 3), -np.inf)
    if len(lab) == 0:
        return lo, hi
    order = np.argsort(lab, kind="stable")
    sl = lab[order]
    starts = np.flatnonzero(np.r_[True, sl[1:] != sl[:-1]])
    present = sl[starts]
    # per face over its three corners, corner by corner (exact; twice as fast as the
    # reduction over the middle axis)
    lo_f = np.minimum(np.minimum(X[:, 0], X[:, 1]), X[:, 2])
    hi_f = np.maximum(np.maximum(X[:, 0], X[:, 1]), X[:, 2])
    lo[present] = np.minimum.reduceat(lo_f[order], starts, axis=0)
    hi[present] = np.maximum.reduceat(hi_f[order], starts, axis=0)
    return lo, hi


def panel_measures(
    V3: np.ndarray, F3: np.ndarray, lab: np.ndarray, n_p: int, frame: np.ndarray
) -> PanelMeasures:
    """Measure the panels ``lab`` (per triangle) of a drape in the frame ``frame`` (rows)."""
    X = V3 @ frame.T  # (n3, 3): left, up, front
    Xc = X[F3]  # (m, 3, 3)
    area = triangle_areas(V3, F3)
    At = np.bincount(lab, area, minlength=n_p)
    Atot = max(float(At.sum()), 1e-300)
    fc = (Xc[:, 0] + Xc[:, 1] + Xc[:, 2]) / 3.0  # Xc.mean(axis=1) bit for bit, 1/4 the time
    cen_abs = np.stack([np.bincount(lab, area * fc[:, k], minlength=n_p) for k in range(3)], 1)
    cen_abs = cen_abs / np.maximum(At, 1e-300)[:, None]
    lo_abs, hi_abs = _per_panel_extent(Xc, lab, n_p)
    s0 = float((area * fc[:, 0]).sum() / Atot)
    f0 = float((area * fc[:, 2]).sum() / Atot)
    used = np.flatnonzero(np.bincount(F3.ravel(), minlength=len(V3)) > 0)
    h0 = float(X[used, 1].min()) if used.size else 0.0
    H = float(X[used, 1].max()) - h0 if used.size else 0.0
    return PanelMeasures(X, area, At, cen_abs, lo_abs, hi_abs, s0, f0, h0, H)


@dataclass(frozen=True)
class EdgeGraph:
    """The drape's boundary and seam half-edges, with their 3D lengths and panels.

    Attributes
    ----------
    h3 : (3m, 2) int array
        Drape half-edges.
    hlen : (3m,) float array
        Their lengths.
    hpan : (3m,) int array
        Their panels.
    bnd : (b,) int array
        Boundary half-edges, ascending.
    perim : (n_p,) float array
        Per panel, the length of its boundary and seam edges.
    W : (n_p, n_p) float array
        Seam length between each two panels (symmetric).
    """

    h3: np.ndarray
    hlen: np.ndarray
    hpan: np.ndarray
    bnd: np.ndarray
    perim: np.ndarray
    W: np.ndarray


def edge_graph(
    V3: np.ndarray, F3: np.ndarray, F2: np.ndarray, lab: np.ndarray, n_p: int
) -> EdgeGraph:
    """Boundary and seam half-edges, panel perimeters and the seam adjacency of panels.

    One sort of the drape's edges: runs of one are boundary, runs of two interior edges (a
    seam when the two pattern edges differ); T-seams (3+ faces) are sewn, never boundary
    (as ``openings()`` has them), and give no adjacency (enough to name panels).
    """
    h3 = half_edges(F3)
    hlen = np.linalg.norm(V3[h3[:, 1]] - V3[h3[:, 0]], axis=1)
    hpan = np.repeat(lab, 3)
    h2 = half_edges(np.asarray(F2, dtype=np.int64).reshape(-1, 3))
    key = edge_keys(h3)
    order = np.argsort(key, kind="stable")
    ks = key[order]
    start = np.r_[True, ks[1:] != ks[:-1]] if len(ks) else np.zeros(0, dtype=bool)
    run_id = np.cumsum(start) - 1
    run_len = np.bincount(run_id)[run_id] if len(ks) else np.zeros(0, dtype=np.int64)
    bnd = np.sort(order[run_len == 1])
    two = np.flatnonzero(start & (run_len == 2))
    first, second = order[two], order[two + 1]
    same_dir = h3[first, 0] == h3[second, 0]
    e2 = np.where(same_dir[:, None], h2[second], h2[second][:, ::-1])
    is_seam = np.any(h2[first] != e2, axis=1)
    pairs = np.stack([first[is_seam], second[is_seam]], axis=1)
    sh = pairs.ravel()
    perim = np.bincount(hpan[bnd], hlen[bnd], minlength=n_p) + np.bincount(
        hpan[sh], hlen[sh], minlength=n_p
    )
    # seam adjacency (3D length between panels)
    W = np.zeros((n_p, n_p))
    if len(pairs):
        np.add.at(W, (hpan[pairs[:, 0]], hpan[pairs[:, 1]]), hlen[pairs[:, 0]])
    W = W + W.T
    return EdgeGraph(h3, hlen, hpan, bnd, perim, W)


def inscribed_radius(V2: np.ndarray, F2: np.ndarray, lab: np.ndarray, n_p: int) -> np.ndarray:
    """Each panel's largest distance, in the pattern, from a triangle's centroid to the
    panel's own boundary: about half its width where it is widest.

    A strip of width ``w`` gives ``w / 2`` (``w / 3`` when it is one triangle across), a
    disc its radius; a notch or a V cut into a panel's edge leaves it as it was, where the
    outline's length grows with every cut (the dress's front bodice, a V 10 cm deep cut in
    it, read 4.7 long for its width by area and outline, 2.1 by this).

    Parameters
    ----------
    V2 : (n2, 2) float array
    F2 : (m, 3) int array
    lab : (m,) int array
        Panel per triangle.
    n_p : int

    Returns
    -------
    (n_p,) float array
        In pattern units; 0 for a panel without triangles. The boundary is sampled at its
        vertices and ``NAMES_EDGE_SAMPLES`` points along each edge.
    """
    from scipy.spatial import cKDTree

    F2 = np.asarray(F2, dtype=np.int64).reshape(-1, 3)
    h2 = half_edges(F2)
    _, inv, cnt = np.unique(edge_keys(h2), return_inverse=True, return_counts=True)
    bnd = np.flatnonzero(cnt[inv] == 1)
    k = model_tol.NAMES_EDGE_SAMPLES
    t = np.arange(k + 1) / (k + 1)
    A, B = V2[h2[bnd, 0]], V2[h2[bnd, 1]]
    S = (A[:, None, :] + (B - A)[:, None, :] * t[None, :, None]).reshape(-1, 2)
    slab = np.repeat(np.repeat(lab, 3)[bnd], k + 1)
    # candidates: the triangles nearly as far from the boundary along the mesh's edges as
    # the panel's farthest (edge paths are longer than straight lines by less than
    # 1 / NAMES_WIDTH_CANDIDATES - 1, so the farthest in a straight line is among them)
    g = _boundary_graph_distance(V2, F2, np.unique(h2[bnd].ravel()))
    gt = g[F2].max(axis=1)
    far = np.zeros(n_p)
    np.maximum.at(far, np.maximum(lab, 0), np.where(lab >= 0, gt, 0.0))
    cand = (lab >= 0) & (gt >= model_tol.NAMES_WIDTH_CANDIDATES * far[np.maximum(lab, 0)])
    C = V2[F2[cand]].mean(axis=1)
    cl = lab[cand]
    r = np.zeros(n_p)
    for p in np.unique(cl):  # a loop over the panels (a few dozen at most)
        mine = slab == p
        if mine.any():
            r[p] = float(cKDTree(S[mine]).query(C[cl == p])[0].max())
    return r


def _boundary_graph_distance(V2: np.ndarray, F2: np.ndarray, sources: np.ndarray) -> np.ndarray:
    """Each pattern vertex's shortest path along the mesh's edges to any of ``sources``,
    ``(n2,)`` (inf where none is reachable)."""
    import scipy.sparse as sp
    from scipy.sparse.csgraph import dijkstra

    E = F2[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    w = np.linalg.norm(V2[E[:, 1]] - V2[E[:, 0]], axis=1) + tol.TINY
    n = len(V2)
    W = sp.coo_matrix((w, (E[:, 0], E[:, 1])), shape=(n, n)).tocsr()
    if sources.size == 0:
        return np.full(n, np.inf)
    return dijkstra(W, directed=False, indices=sources, min_only=True)


def pattern_shape(
    V2: np.ndarray, F2: np.ndarray, lab: np.ndarray, n_p: int
) -> tuple[np.ndarray, np.ndarray]:
    """Each panel's area and outline length in the pattern.

    The pattern is the panel's own shape: a box mesh's seam rows, stretched across the gaps
    between the placed panels, inflate the drape's (a bodice front 2 wide for its length
    reads 4 to 5 in 3D), never the pattern's.

    Parameters
    ----------
    V2 : (n2, 2) float array
        Pattern positions.
    F2 : (m, 3) int array
        Pattern triangles.
    lab : (m,) int array
        Panel per triangle.
    n_p : int

    Returns
    -------
    area, perim : (n_p,) float arrays
        Panel areas and the lengths of their pattern boundary edges (outline, darts and
        cuts), in pattern units.
    """
    V2 = np.asarray(V2, dtype=np.float64)
    F2 = np.asarray(F2, dtype=np.int64).reshape(-1, 3)
    d1, d2 = V2[F2[:, 1]] - V2[F2[:, 0]], V2[F2[:, 2]] - V2[F2[:, 0]]
    cross = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    area = np.bincount(lab, 0.5 * np.abs(cross), minlength=n_p)
    h2 = half_edges(F2)
    key = edge_keys(h2)
    order = np.argsort(key, kind="stable")
    ks = key[order]
    start = np.r_[True, ks[1:] != ks[:-1]] if len(ks) else np.zeros(0, dtype=bool)
    run_id = np.cumsum(start) - 1
    bnd = order[(np.bincount(run_id)[run_id] == 1)] if len(ks) else np.zeros(0, np.int64)
    blen = np.linalg.norm(V2[h2[bnd, 1]] - V2[h2[bnd, 0]], axis=1)
    perim = np.bincount(np.repeat(lab, 3)[bnd], blen, minlength=n_p)
    return area, perim


class OpeningTouch:
    """How long each opening's loop runs along each panel."""

    def __init__(self, ops: list[Opening], n3: int, g: EdgeGraph, n_p: int) -> None:
        n_o = len(ops)
        vid = np.full(n3, -1, dtype=np.int64)
        for k, o in enumerate(ops):  # a loop over openings
            vid[o.loop] = k
        a, b = vid[g.h3[g.bnd, 0]], vid[g.h3[g.bnd, 1]]
        on = (a >= 0) & (a == b)
        touch = np.zeros((max(n_o, 1), n_p))
        np.add.at(touch, (a[on], g.hpan[g.bnd][on]), g.hlen[g.bnd][on])
        self.touch = touch
        self.index = {o.name: k for k, o in enumerate(ops)}
        self.n_p = n_p

    def __call__(self, name: str) -> np.ndarray:
        """``(n_p,)``: the length of opening ``name``'s loop on each panel (0 if none)."""
        k = self.index.get(name)
        return self.touch[k] if k is not None else np.zeros(self.n_p)
