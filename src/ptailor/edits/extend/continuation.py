"""Where the surface goes beyond an opening, and whether ``extend``'s new rows fold back.

The direction of the new rows is the surface's outward continuation read from a band of
cloth behind the opening (the distance-from-the-opening field's gradient, averaged near
each opening vertex), not from the opening's last triangles alone: a simulated drape's
last row is often bent or flared, and continuing it straight folded the new rows back or
flared them (a tee's cuff +25 % / +40 % for 4 cm). A new row folded back against the row
before it, or growing against the continuation, is reported (:func:`fold_check`).
"""

from __future__ import annotations

import numpy as np

from ptailor import tolerances as tol
from ptailor.edits import tolerances as edit_tol
from ptailor.edits.opening import OpeningEdges
from ptailor.geometry.triangles import triangle_normals
from ptailor.method.geodesic import geodesic_distance


def distance_gradients(V: np.ndarray, F: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Gradient of a per-vertex field on each triangle, in its plane.

    Parameters
    ----------
    V : (n, 3) float array
    F : (m, 3) int array
    d : (n,) float array

    Returns
    -------
    (m, 3) float array
        ``sum_i d_i (n x e_i) / (2 A)``, ``e_i`` the edge opposite corner ``i`` (zero on a
        degenerate triangle).
    """
    P = V[F]
    N = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
    a2 = np.linalg.norm(N, axis=1)
    n = N / np.maximum(a2, tol.TINY)[:, None]
    g = np.zeros((len(F), 3))
    for i in range(3):  # the three corners, not vertices
        e = P[:, (i + 2) % 3] - P[:, (i + 1) % 3]
        g += d[F[:, i]][:, None] * np.cross(n, e)
    return np.where((a2 > tol.TINY)[:, None], g / np.maximum(a2, tol.TINY)[:, None], 0.0)


def opening_tangents(V: np.ndarray, oe: OpeningEdges) -> np.ndarray:
    """Unit tangent of the opening at each of its vertices ``a3[i]``, ``(k, 3)``:
    along the chord from the vertex before to the vertex after."""
    t = V[oe.b3] - V[np.roll(oe.a3, 1)]
    return t / np.maximum(np.linalg.norm(t, axis=1), tol.TINY)[:, None]


def continuation_directions(
    V: np.ndarray, F: np.ndarray, oe: OpeningEdges, local: np.ndarray
) -> np.ndarray:
    """The surface's outward continuation at each opening vertex.

    The geodesic distance from the opening is computed over a band
    :data:`ptailor.edits.tolerances.EXTEND_BAND_EDGES` mean edge lengths (of the opening's
    triangles) deep; each
    opening vertex takes the mean of minus its gradient (pointing out of the cloth, across
    the opening) over the band's triangles, area-weighted with a Gaussian of their distance
    to the vertex along the opening (their 3D distance less their depth; a mean edge length
    as its width: wider, a cone's fanning directions shorten the mean's flare), every depth
    alike, made perpendicular to the opening
    (:func:`opening_tangents`). Where that mean vanishes (no band) the ``local`` direction
    is kept.

    Parameters
    ----------
    V : (n, 3) float array
        Drape positions.
    F : (m, 3) int array
    oe : OpeningEdges
    local : (k, 3) float array
        The tangent-plane directions of the opening's own triangles (the fallback).

    Returns
    -------
    (k, 3) float array
        Unit directions.
    """
    a = V[oe.a3]
    P = V[F[oe.face]]
    edge = float(np.linalg.norm(P - np.roll(P, 1, axis=1), axis=2).mean())
    depth = edit_tol.EXTEND_BAND_EDGES * edge
    d = geodesic_distance(V, F, oe.a3, limit=2.0 * depth)
    band = np.flatnonzero(np.all(d[F] <= depth, axis=1))
    grad = -distance_gradients(V, F[band], d)
    area = 0.5 * np.linalg.norm(
        np.cross(V[F[band, 1]] - V[F[band, 0]], V[F[band, 2]] - V[F[band, 0]]), axis=1
    )
    c = V[F[band]].mean(axis=1)
    r2 = np.einsum("kmd,kmd->km", a[:, None] - c[None], a[:, None] - c[None])
    lateral = np.maximum(r2 - d[F[band]].mean(axis=1)[None] ** 2, 0.0)  # along the opening
    w = area[None] * np.exp(-lateral / max(edge * edge, tol.TINY))
    s = w @ grad
    t = opening_tangents(V, oe)
    s -= np.einsum("ij,ij->i", s, t)[:, None] * t
    ns = np.linalg.norm(s, axis=1)
    ok = ns > edit_tol.EXTEND_SMOOTH_ZERO * np.maximum(w.sum(axis=1), tol.TINY)
    out = local.copy()
    out[ok] = s[ok] / ns[ok, None]
    return out


def in_planes(dirs: np.ndarray, normals: np.ndarray, local: np.ndarray) -> np.ndarray:
    """Directions projected into triangles' planes, unit, for the pattern's steps.

    Parameters
    ----------
    dirs : (k, 3) float array
        3D directions.
    normals : (k, 3) float array
        Unit normals of the triangles.
    local : (k, 3) float array
        Each triangle's own outward direction, kept where the projection vanishes or points
        into the triangle (the drape turns back there).

    Returns
    -------
    (k, 3) float array
    """
    p = dirs - np.einsum("ij,ij->i", dirs, normals)[:, None] * normals
    n = np.linalg.norm(p, axis=1)
    ok = (n > edit_tol.EXTEND_SMOOTH_ZERO) & (np.einsum("ij,ij->i", p, local) > 0.0)
    out = local.copy()
    out[ok] = p[ok] / n[ok, None]
    return out


def fold_check(
    V: np.ndarray,
    F_new: np.ndarray,
    n_src: np.ndarray,
    grid: np.ndarray,
    cont: np.ndarray,
) -> dict | None:
    """Where an extension's new rows fold back.

    Parameters
    ----------
    V : (n, 3) float array
        The drape with the new rows.
    F_new : (2 rows k, 3) int array
        The new triangles (:func:`ptailor.edits.extend.rows.quad_rows`, row by row).
    n_src : (k, 3) float array
        Unit normals of the opening's triangles.
    grid : (rows + 1, k) int array
        Drape vertex of each row (row 0: the opening) and opening vertex.
    cont : (k, 3) float array
        The surface's outward continuation at the opening's vertices.

    Returns
    -------
    dict or None
        None when no new row folds; else ``{"edges": how many opening edges have a folded
        row, "columns": how many new columns grow against the continuation, "min_cos": the
        smallest cosine between a new triangle and the one before it, "row": the first
        folded row (1 = beside the opening), "at": [x, y, z] the mean position of the
        opening vertices concerned}``.
    """
    rows, k = grid.shape[0] - 1, grid.shape[1]
    N = triangle_normals(V, F_new).reshape(rows, k, 2, 3)
    prev = np.concatenate([np.broadcast_to(n_src[None, :, None], (1, k, 2, 3)), N[:-1]])
    cos = np.einsum("rktd,rktd->rkt", N, prev).min(axis=2)  # (rows, k)
    folded = cos < edit_tol.EXTEND_FOLD_COS
    grow = V[grid[1:]] - V[grid[:-1]]  # (rows, k, 3)
    against = np.einsum("rkd,kd->rk", grow, cont) <= 0.0
    bad_edge = folded.any(axis=0)
    bad_col = against.any(axis=0)
    if not (bad_edge.any() or bad_col.any()):
        return None
    where = bad_edge | np.roll(bad_edge, 1) | bad_col  # an edge's two ends, each column
    first = np.flatnonzero((folded | against).any(axis=1))[0] + 1
    return {
        "edges": int(bad_edge.sum()),
        "columns": int(bad_col.sum()),
        "min_cos": round(float(cos.min()), 6),
        "row": int(first),
        "at": [round(float(x), 6) for x in V[grid[0, where]].mean(axis=0)],
    }


def fold_warning(name: str, by: float, folds: dict, units: str) -> str:
    """The warning of an extension whose new rows fold back (:func:`fold_check`)."""
    at = ", ".join(f"{x:.4g}" for x in folds["at"])
    return (
        f"extend {name} by {by:g}: the new rows fold back against the cloth at the opening "
        f"'{name}' ({folds['edges']} edge(s) folded, {folds['columns']} column(s) growing "
        f"against the surface, from row {folds['row']}, near ({at}) {units}): the drape "
        "turns back there; check the new cloth or extend by less"
    )
