"""``loosen``'s silhouette form: the garment's outline in a view, row by row, moved onto an
over-sketched one."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ptailor.errors import PtailorError
from ptailor.geometry.topology import half_edges

#: height of the image rows the outline is sampled in, in mean edge lengths
ROW_EDGES = 1.5
#: an outline point matches when the sketch, in its row, is within this fraction of the
#: sketch's span (and within its ring's half-width: a sketch never grabs the far outline)
MATCH_REL = 0.5
#: smallest ring scale a sketch may ask for (below it the outline collapses)
MIN_RING_SCALE = 0.05


def row_crossings(P: np.ndarray, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Where a polyline crosses each point's image row, nearest to the point.

    Parameters
    ----------
    P : (p, 2) float array
        Image points ``(u, v)``.
    Q : (k, 2) float array
        Polyline, ``k >= 2``.

    Returns
    -------
    u : (p,) float array
        The ``u`` of the polyline at height ``P[:, 1]`` nearest to ``P[:, 0]`` (a
        horizontal segment in the row counts with its nearest point); NaN where the
        polyline does not reach the row.
    found : (p,) bool array
    """
    A, B = Q[:-1], Q[1:]
    dv = B[:, 1] - A[:, 1]
    eps = 1e-9 * (1.0 + float(np.abs(Q).max()))
    flat = np.abs(dv) <= eps
    t = (P[:, 1:2] - A[None, :, 1]) / np.where(flat, 1.0, dv)[None]
    du = B[:, 0] - A[:, 0]
    t_flat = np.clip((P[:, 0:1] - A[None, :, 0]) / np.where(du == 0.0, 1.0, du)[None], 0.0, 1.0)
    t = np.where(flat[None], t_flat, t)
    rel = eps / np.maximum(np.abs(dv), eps)
    ok = np.where(
        flat[None],
        np.abs(P[:, 1:2] - A[None, :, 1]) <= eps,
        (t >= -rel[None]) & (t <= 1.0 + rel[None]),
    )
    u = A[None, :, 0] + np.clip(t, 0.0, 1.0) * du[None]
    dist = np.where(ok, np.abs(u - P[:, 0:1]), np.inf)
    j = np.argmin(dist, axis=1)
    r = np.arange(len(P))
    found = np.isfinite(dist[r, j])
    return np.where(found, u[r, j], np.nan), found


def outline_rows(
    X: np.ndarray, F: np.ndarray, slab: np.ndarray, *, row: float
) -> dict[str, np.ndarray]:
    """The garment's outline, row by row, in the image plane of a view.

    The vertices in ``slab`` are grouped by connected piece (of the sub-mesh of edges with
    both ends in the slab) and by image row (bands ``row`` high); each group is a *ring*,
    whose leftmost and rightmost vertices are the outline points.

    Parameters
    ----------
    X : (n, 3) float array
        Vertices in view coordinates ``(right, up, depth)``.
    F : (m, 3) int array
    slab : (n,) bool array
        The vertices to look at (used vertices in the sketch's rows).
    row : float, keyword-only
        Height of an image row.

    Returns
    -------
    dict of arrays, one entry per ring (``g`` rings)
        ``left``, ``right`` (g,) vertex indices of the extremes; ``centre`` (g,) the
        midpoint of their ``u``; ``depth`` (g,) the midpoint of the ring's depth range;
        ``piece`` (g,) its connected piece; and ``vertex_piece`` (n,) the piece of every
        vertex (-1 outside the slab).
    """
    n = len(X)
    E = half_edges(F)
    keep = slab[E[:, 0]] & slab[E[:, 1]]
    A = sp.coo_matrix((np.ones(int(keep.sum())), (E[keep, 0], E[keep, 1])), shape=(n, n))
    from scipy.sparse.csgraph import connected_components

    _, comp = connected_components(A, directed=False)
    sv = np.flatnonzero(slab)
    r = np.floor((X[sv, 1] - X[sv, 1].min()) / row).astype(np.int64)
    key = comp[sv] * (int(r.max()) + 1) + r
    order = np.lexsort((X[sv, 0], key))
    ks = key[order]
    starts = np.flatnonzero(np.r_[True, ks[1:] != ks[:-1]])
    ends = np.r_[starts[1:], len(ks)] - 1
    left, right = sv[order[starts]], sv[order[ends]]
    z = X[sv[order], 2]
    depth = 0.5 * (np.minimum.reduceat(z, starts) + np.maximum.reduceat(z, starts))
    vertex_piece = np.full(n, -1, dtype=np.int64)
    vertex_piece[sv] = comp[sv]
    return {
        "left": left,
        "right": right,
        "centre": 0.5 * (X[left, 0] + X[right, 0]),
        "depth": depth,
        "piece": comp[left],
        "vertex_piece": vertex_piece,
    }


def silhouette_targets(
    X: np.ndarray, F: np.ndarray, Q: np.ndarray, *, row: float, view_name: str
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Handles and their targets (view coordinates) for a silhouette over-sketch.

    1. The outline in the sketch's rows (:func:`outline_rows`).
    2. Matching: an outline point matches when the sketch crosses its row within
       ``min(MATCH_REL * span, half-width of its ring)`` of it, ``span`` the diagonal of
       the sketch's bounding box.
    3. Each matched point's target is that crossing (a horizontal move in the image; its
       height and depth are kept): points are matched row by row, so they move along
       their row, which keeps the rings below consistent.
    4. Rings: each ring with a matched point is scaled about its centre (``u`` and
       depth, not height) so the matched point lands on its target; with both of its
       outline points matched, it is scaled and shifted onto both. Every vertex of a
       connected piece holding matched points, in the sketch's rows, takes the scale and
       centre interpolated linearly in height between its piece's matched rings, so a
       round cross-section stays round and the far side follows symmetrically.

    Parameters
    ----------
    X : (n, 3) float array
        Vertices in view coordinates ``(right, up, depth)``.
    F : (m, 3) int array
    Q : (k, 2) float array
        The sketch.
    row : float, keyword-only
        Height of an image row.
    view_name : str, keyword-only
        For the error message.

    Returns
    -------
    handles : (h,) int array
        Vertices with targets, ascending.
    targets : (h, 3) float array
        Their positions, view coordinates.
    change : (c,) float array
        Outward move of each matched outline point (negative: inward).

    Raises
    ------
    PtailorError
        When the sketch matches no outline point, or would shrink a ring to nothing.
    """
    used = np.zeros(len(X), dtype=bool)
    used[F] = True
    eps = 1e-9 * (1.0 + float(np.abs(Q).max()))
    v_lo, v_hi = Q[:, 1].min() - eps, Q[:, 1].max() + eps
    slab = used & (X[:, 1] >= v_lo) & (X[:, 1] <= v_hi)
    nomatch = PtailorError(
        f"the silhouette sketch matches no outline of the garment in the {view_name} view"
    )
    if not slab.any():
        raise nomatch
    rings = outline_rows(X, F, slab, row=row)
    left, right, c = rings["left"], rings["right"], rings["centre"]
    half = 0.5 * (X[right, 0] - X[left, 0])
    g = len(left)
    cand = np.r_[left, right]
    u_to, found = row_crossings(X[cand, :2], Q)
    span = float(np.linalg.norm(np.ptp(Q, axis=0)))
    tol = np.minimum(MATCH_REL * span, np.r_[half, half])
    match = found & (np.abs(u_to - X[cand, 0]) <= tol) & (np.r_[half, half] > 0.0)
    if not match.any():
        raise nomatch
    mL, mR = match[:g], match[g:]
    uL, uR = u_to[:g], u_to[g:]
    both = mL & mR
    ring = mL | mR
    new_half = np.where(both, 0.5 * (uR - uL), np.where(mR, uR - c, c - uL))
    new_c = np.where(both, 0.5 * (uR + uL), c)
    scale = np.divide(new_half, half, out=np.ones(g), where=ring)
    if np.any(scale[ring] < MIN_RING_SCALE):
        raise PtailorError(
            "the silhouette sketch shrinks the garment's outline to nothing"
            f" in the {view_name} view"
        )
    height = np.where(both, 0.5 * (X[left, 1] + X[right, 1]), np.where(mR, X[right, 1], X[left, 1]))

    # interpolate scale and centres in height within each piece: one np.interp over the
    # pieces laid end to end (heights offset by the piece's rank times more than the span)
    rg = np.flatnonzero(ring)
    pieces = np.unique(rings["piece"][rg])
    rank = np.full(int(rings["vertex_piece"].max()) + 1, -1, dtype=np.int64)
    rank[pieces] = np.arange(pieces.size)
    stride = 2.0 * (v_hi - v_lo) + 1.0
    xp = rank[rings["piece"][rg]] * stride + (height[rg] - v_lo)
    o = np.argsort(xp, kind="stable")
    xp, rg = xp[o], rg[o]
    vp = rings["vertex_piece"]
    verts = np.flatnonzero((vp >= 0) & (rank[np.maximum(vp, 0)] >= 0))
    vr = rank[vp[verts]]
    lo = np.full(pieces.size, np.inf)
    hi = np.full(pieces.size, -np.inf)
    np.minimum.at(lo, rank[rings["piece"][rg]], height[rg])
    np.maximum.at(hi, rank[rings["piece"][rg]], height[rg])
    x = vr * stride + (np.clip(X[verts, 1], lo[vr], hi[vr]) - v_lo)

    def at(values: np.ndarray) -> np.ndarray:
        return np.interp(x, xp, values[rg])

    k, c0, c1, zc = at(scale), at(c), at(new_c), at(rings["depth"])
    T = X.copy()
    T[verts, 0] = c1 + k * (X[verts, 0] - c0)
    T[verts, 2] = zc + k * (X[verts, 2] - zc)
    mv = cand[match]
    T[mv, 0] = u_to[match]
    T[mv, 2] = X[mv, 2]
    side = np.r_[-np.ones(g), np.ones(g)][match]
    handles = np.union1d(verts, mv)
    return handles, T[handles], side * (u_to[match] - X[mv, 0])
