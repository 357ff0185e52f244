"""``loosen``'s silhouette form: the garment's outline in a view, row by row, moved onto an
over-sketched one."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ptailor import tolerances as tol
from ptailor.edits import tolerances as edit_tol
from ptailor.errors import PtailorError
from ptailor.geometry.topology import half_edges


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
    eps = tol.ROUNDING_REL * (1.0 + float(np.abs(Q).max()))
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
       ``min(SILHOUETTE_MATCH_REL * span, half-width of its ring)`` of it, ``span`` the diagonal of
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
    eps = tol.ROUNDING_REL * (1.0 + float(np.abs(Q).max()))
    v_lo, v_hi = Q[:, 1].min() - eps, Q[:, 1].max() + eps
    slab = used & (X[:, 1] >= v_lo) & (X[:, 1] <= v_hi)
    nomatch = PtailorError(
        f"the silhouette sketch matches no outline of the garment in the {view_name} view"
    )
    if not slab.any():
        raise nomatch
    rings = outline_rows(X, F, slab, row=row)
    cand, u_to, match = _outline_matches(X, rings, Q)
    if not match.any():
        raise nomatch
    ring, scale, new_c, height = _ring_fits(X, rings, u_to, match)
    if np.any(scale[ring] < edit_tol.SILHOUETTE_MIN_RING_SCALE):
        raise PtailorError(
            "the silhouette sketch shrinks the garment's outline to nothing"
            f" in the {view_name} view"
        )
    where = _height_interpolation(X, rings, ring, height, lo=v_lo, hi=v_hi)
    verts, T = _scaled_pieces(X, rings, where, scale=scale, new_c=new_c)
    g = len(rings["left"])
    mv = cand[match]
    T[mv, 0] = u_to[match]
    T[mv, 2] = X[mv, 2]
    side = np.r_[-np.ones(g), np.ones(g)][match]
    handles = np.union1d(verts, mv)
    return handles, T[handles], side * (u_to[match] - X[mv, 0])


def _outline_matches(
    X: np.ndarray, rings: dict, Q: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Step 2 of :func:`silhouette_targets`: which outline points the sketch matches.

    Returns
    -------
    cand : (2 g,) int array
        The rings' left outline points, then their right ones.
    u_to : (2 g,) float array
        Where the sketch crosses each one's row (see :func:`row_crossings`).
    match : (2 g,) bool array
        Crossed within ``min(SILHOUETTE_MATCH_REL * span, half-width of its ring)``.
    """
    left, right = rings["left"], rings["right"]
    half = 0.5 * (X[right, 0] - X[left, 0])
    cand = np.r_[left, right]
    u_to, found = row_crossings(X[cand, :2], Q)
    span = float(np.linalg.norm(np.ptp(Q, axis=0)))
    tol = np.minimum(edit_tol.SILHOUETTE_MATCH_REL * span, np.r_[half, half])
    match = found & (np.abs(u_to - X[cand, 0]) <= tol) & (np.r_[half, half] > 0.0)
    return cand, u_to, match


def _ring_fits(
    X: np.ndarray, rings: dict, u_to: np.ndarray, match: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Step 4 of :func:`silhouette_targets`, per ring: the scale about its centre that
    lands its matched point on its target, or with both matched, scale and shifted centre.

    Returns
    -------
    ring : (g,) bool array
        Rings with a matched point.
    scale : (g,) float array
        New over old half-width (1 where not ``ring``).
    new_c : (g,) float array
        New centre.
    height : (g,) float array
        Height of the matched points (their mean with both).
    """
    left, right, c = rings["left"], rings["right"], rings["centre"]
    half = 0.5 * (X[right, 0] - X[left, 0])
    g = len(left)
    mL, mR = match[:g], match[g:]
    uL, uR = u_to[:g], u_to[g:]
    both = mL & mR
    ring = mL | mR
    new_half = np.where(both, 0.5 * (uR - uL), np.where(mR, uR - c, c - uL))
    new_c = np.where(both, 0.5 * (uR + uL), c)
    scale = np.divide(new_half, half, out=np.ones(g), where=ring)
    height = np.where(both, 0.5 * (X[left, 1] + X[right, 1]), np.where(mR, X[right, 1], X[left, 1]))
    return ring, scale, new_c, height


def _height_interpolation(
    X: np.ndarray, rings: dict, ring: np.ndarray, height: np.ndarray, *, lo: float, hi: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Where each vertex of a piece holding matched rings lies between them in height.

    Interpolating scale and centres in height within each piece is one ``np.interp`` over
    the pieces laid end to end (heights offset by the piece's rank times more than the
    sketch's height range ``lo..hi``); a vertex above or below its piece's matched rings
    takes the nearest one's.

    Returns
    -------
    verts : (v,) int array
        The vertices of pieces holding matched rings.
    x : (v,) float array
        Their abscissae, and ``xp`` ``(r,)`` the matched rings' (ascending).
    rg : (r,) int array
        The matched rings in the order of ``xp``: ``np.interp(x, xp, values[rg])``
        interpolates a value ``(g,)`` per ring at the vertices.
    """
    rg = np.flatnonzero(ring)
    pieces = np.unique(rings["piece"][rg])
    rank = np.full(int(rings["vertex_piece"].max()) + 1, -1, dtype=np.int64)
    rank[pieces] = np.arange(pieces.size)
    stride = 2.0 * (hi - lo) + 1.0
    xp = rank[rings["piece"][rg]] * stride + (height[rg] - lo)
    o = np.argsort(xp, kind="stable")
    xp, rg = xp[o], rg[o]
    vp = rings["vertex_piece"]
    verts = np.flatnonzero((vp >= 0) & (rank[np.maximum(vp, 0)] >= 0))
    vr = rank[vp[verts]]
    h_lo = np.full(pieces.size, np.inf)
    h_hi = np.full(pieces.size, -np.inf)
    np.minimum.at(h_lo, rank[rings["piece"][rg]], height[rg])
    np.maximum.at(h_hi, rank[rings["piece"][rg]], height[rg])
    x = vr * stride + (np.clip(X[verts, 1], h_lo[vr], h_hi[vr]) - lo)
    return verts, x, xp, rg


def _scaled_pieces(
    X: np.ndarray, rings: dict, where: tuple, *, scale: np.ndarray, new_c: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The vertices of the pieces holding matched rings scaled about their centres (``u``
    and depth, not height), scale and centres interpolated in height between the rings.

    Parameters
    ----------
    X : (n, 3) float array
    rings : dict
        :func:`outline_rows`.
    where : tuple
        :func:`_height_interpolation` ``(verts, x, xp, rg)``.
    scale, new_c : (g,) float arrays
        Each ring's scale and new centre (:func:`_ring_fits`).

    Returns
    -------
    verts : (v,) int array
    T : (n, 3) float array
        ``X`` with ``verts`` moved.
    """
    verts, x, xp, rg = where

    def at(values: np.ndarray) -> np.ndarray:
        return np.interp(x, xp, values[rg])

    k, c0, c1, zc = at(scale), at(rings["centre"]), at(new_c), at(rings["depth"])
    T = X.copy()
    T[verts, 0] = c1 + k * (X[verts, 0] - c0)
    T[verts, 2] = zc + k * (X[verts, 2] - zc)
    return verts, T
