"""``loosen`` / ``tighten``: ease a region along its normals, or over-sketch a silhouette.

Two forms of one step; both ops accept both, and in the silhouette form the op name is
only the user's intent (the sketch decides whether the outline moves in or out)::

    - {op: loosen, region: {panels: [front, back]}, by: 2}
    - {op: tighten, view: front, silhouette: [[-22, 95], [-19, 80], [-21, 60]]}

*Offset* (``region`` + ``by``): the region moves along its outward normals, smoothed so
that wrinkles and folds ride along instead of folding over, by ``+by`` (loosen) or ``-by``
(tighten), falling off smoothly to zero at its border with the rest of the garment, which
stays where it is.

*Silhouette* (``view`` + ``silhouette``): the garment's outline in the view is found row by
row (the left and right extremes of each horizontal band of the image, per connected piece
of the garment in the sketch's rows); outline points in the sketch's rows and near it move
horizontally onto it, and each one's horizontal ring follows, scaled about its centre so a
round cross-section stays round; the rest follows by as-rigid-as-possible deformation.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.sparse.csgraph import breadth_first_order, connected_components

from ptailor.edits.checks import number, region
from ptailor.edits.cut import sketch_spec, view_frame, view_spec
from ptailor.edits.region import region_axis, region_centroid, region_faces
from ptailor.edits.registry import Param, register
from ptailor.edits.state import EditOptions, EditState
from ptailor.errors import PtailorError
from ptailor.method.deform import arap_deform, cotangent_weights
from ptailor.method.geodesic import geodesic_distance
from ptailor.model.garment import Panel
from ptailor.model.seams import half_edges, seam_halfedges

#: the offset falls off to zero over a band this many mean edge lengths wide ...
FALLOFF_EDGES = 3.0
#: ... or this many times ``by``, whichever is wider (the offset's slope stays below 0.75)
FALLOFF_BY = 2.0
#: height of the image rows the outline is sampled in, in mean edge lengths
ROW_EDGES = 1.5
#: an outline point matches when the sketch, in its row, is within this fraction of the
#: sketch's span (and within its ring's half-width: a sketch never grabs the far outline)
MATCH_REL = 0.5
#: smallest ring scale a sketch may ask for (below it the outline collapses)
MIN_RING_SCALE = 0.05
#: the offset follows normals smoothed over this many times ``|by|`` ...
SMOOTH_BY = 1.0
#: ... or this many mean edge lengths, whichever is wider
SMOOTH_EDGES = 2.0
#: implicit diffusion steps at the first smoothing width
SMOOTH_STEPS = 4
#: smoothing widths tried, each twice the last, before an offset is refused
SMOOTH_LEVELS = 3
#: the smoothed normals must keep this area-weighted mean cosine to the raw ones on every
#: panel that moves (below it the smoothing is wider than the panel: a thin sleeve's normals
#: cancel out and leak in from the rest)
NORMAL_AGREEMENT = 0.6
#: lumped vertex mass floor, relative to the mean (vertices of degenerate triangles only)
MASS_FLOOR_REL = 1e-9


# ---------------------------------------------------------------------------------------
# outward normals
# ---------------------------------------------------------------------------------------


def face_panels(F3: np.ndarray, plist: list[Panel]) -> np.ndarray:
    """Panel index of every triangle, ``(m,)``."""
    lab = np.full(len(F3), -1, dtype=np.int64)
    for p in plist:  # a loop over panels, not triangles
        lab[p.faces] = p.index
    return lab


def panel_orientation(
    F3: np.ndarray, F2: np.ndarray, plist: list[Panel]
) -> tuple[np.ndarray, np.ndarray]:
    """Flips that orient the drape triangles of all panels consistently.

    Within a panel the drape triangles are consistently oriented because its pattern
    triangles are. Across a seam two panels agree when the shared drape edge runs in
    opposite directions in their two triangles; each pair of panels takes the majority of
    its seam edges, and the flips are propagated breadth first over the panel graph.

    Parameters
    ----------
    F3, F2 : (m, 3) int arrays
    plist : list of Panel

    Returns
    -------
    sign : (n_panels,) float array
        ``+1`` or ``-1`` per panel; the first panel of each group keeps ``+1``.
    group : (n_panels,) int array
        Connected groups of panels (joined by seams).
    """
    n_p = len(plist)
    fp = face_panels(F3, plist)
    pairs = seam_halfedges(F3, F2)
    h3 = half_edges(F3)
    pa, pb = fp[pairs[:, 0] // 3], fp[pairs[:, 1] // 3]
    agree = np.where(h3[pairs[:, 0], 0] == h3[pairs[:, 1], 0], -1.0, 1.0)
    other = pa != pb
    link = sp.coo_matrix((agree[other], (pa[other], pb[other])), shape=(n_p, n_p)).tocsr()
    votes = np.sign((link + link.T).toarray())
    pairs_p = sp.coo_matrix((np.ones(int(other.sum())), (pa[other], pb[other])), shape=(n_p, n_p))
    graph = sp.csr_matrix((pairs_p + pairs_p.T) > 0)
    _, group = connected_components(graph, directed=False)
    sign = np.zeros(n_p)
    for start in range(n_p):  # loops over panels, not triangles
        if sign[start]:
            continue
        order, pred = breadth_first_order(graph, start, directed=False)
        sign[start] = 1.0
        for p in order[1:]:
            sign[p] = sign[pred[p]] * (votes[pred[p], p] or 1.0)
    return sign, group


def outward_normals(
    V: np.ndarray, F3: np.ndarray, F2: np.ndarray, plist: list[Panel]
) -> np.ndarray:
    """Outward, area-weighted unit vertex normals of a drape.

    Triangles are oriented consistently (:func:`panel_orientation`); then each connected
    group of panels is turned so that its normals point away from the garment's axis: the
    sum over its triangles of ``2 area n . r``, with ``r`` the offset of the triangle's
    centroid from the axis line (perpendicular to it), is made positive. For a closed-ish
    garment that sum is about twice the enclosed volume when the normals point outward, so
    an offset along them by ``+by`` increases the distance from the axis. The axis is the
    whole garment's principal axis (:func:`ptailor.edits.region.region_axis`) through its
    area-weighted centroid.

    Parameters
    ----------
    V : (n, 3) float array
    F3, F2 : (m, 3) int arrays
    plist : list of Panel

    Returns
    -------
    (n, 3) float array
        Unit normals (the sum of the oriented face normals times twice the face areas,
        normalised); zero at vertices no triangle uses.
    """
    sign, group = panel_orientation(F3, F2, plist)
    fp = face_panels(F3, plist)
    a, b, c = V[F3[:, 0]], V[F3[:, 1]], V[F3[:, 2]]
    cross = np.cross(b - a, c - a) * sign[fp][:, None]
    every = np.arange(len(F3))
    ax = region_axis(V, F3, every)
    r = (a + b + c) / 3.0 - region_centroid(V, F3, every)
    r -= (r @ ax)[:, None] * ax
    fg = group[fp]
    outward = np.bincount(fg, weights=np.einsum("ij,ij->i", cross, r), minlength=group.max() + 1)
    cross *= np.where(outward[fg] < 0.0, -1.0, 1.0)[:, None]
    corners = F3.ravel()
    N = np.stack(
        [
            np.bincount(corners, weights=np.repeat(cross[:, k], 3), minlength=len(V))
            for k in range(3)
        ],
        axis=1,
    )
    length = np.linalg.norm(N, axis=1)
    return N / np.where(length > 0.0, length, 1.0)[:, None]


# ---------------------------------------------------------------------------------------
# offset form
# ---------------------------------------------------------------------------------------


def falloff_weights(V: np.ndarray, F3: np.ndarray, faces: np.ndarray, *, band: float) -> np.ndarray:
    """Offset weights of a region's vertices: 0 on its border, rising smoothly to 1.

    The border is the region's vertices that also belong to triangles outside it (the
    garment's own open edges are not a border). The weight is ``smoothstep(d / band)``
    with ``d`` the geodesic distance within the region from its border.

    Parameters
    ----------
    V : (n, 3) float array
    F3 : (m, 3) int array
    faces : (k,) int array
        The region's triangles.
    band : float, keyword-only
        Width of the falloff.

    Returns
    -------
    (n,) float array
        Weights in ``[0, 1]``; 1 everywhere when the region has no border (it is the whole
        garment or whole connected pieces of it), 0 at vertices outside the region.
    """
    n = len(V)
    inside = np.zeros(len(F3), dtype=bool)
    inside[faces] = True
    in_region = np.zeros(n, dtype=bool)
    in_region[F3[faces]] = True
    on_outside = np.zeros(n, dtype=bool)
    on_outside[F3[~inside]] = True
    border = np.flatnonzero(in_region & on_outside)
    w = in_region.astype(float)
    if border.size == 0:
        return w
    d = geodesic_distance(V, F3[faces], border, limit=band)
    t = np.clip(d / band, 0.0, 1.0)
    return np.where(in_region, t * t * (3.0 - 2.0 * t), 0.0)


def normal_smoother(
    V: np.ndarray, F: np.ndarray, *, tau: float
) -> Callable[[np.ndarray], np.ndarray]:
    """One implicit heat-diffusion step on a drape, factored once.

    The step is ``X -> (M + tau L)^-1 M X`` with ``L`` the cotangent stiffness matrix
    (:func:`ptailor.method.deform.cotangent_weights`, positive semi-definite for any mesh)
    and ``M`` the lumped (barycentric) vertex areas, over the vertices ``F`` uses. ``s``
    steps low-pass a field with the response ``(1 + tau k^2)^-s`` at a spatial wavenumber
    ``k``: about a Gaussian of width ``sigma = sqrt(2 s tau)``. A field that is an
    eigenfunction of ``L`` keeps its direction: the normals of a tube (radial) only
    shrink, so after normalising they are unchanged.

    Parameters
    ----------
    V : (n, 3) float array
    F : (m, 3) int array
    tau : float, keyword-only
        Diffusion time of one step, in squared length units.

    Returns
    -------
    callable
        ``step(X)`` for an ``(n, c)`` float array: the diffused field, ``(n, c)``; rows of
        vertices no triangle uses are returned unchanged.
    """
    n = len(V)
    used = np.unique(F)
    loc = np.full(n, -1, dtype=np.int64)
    loc[used] = np.arange(used.size)
    Fl = loc[F]
    Vl = V[used]
    W = cotangent_weights(Vl, Fl)
    L = sp.diags(np.asarray(W.sum(axis=1)).ravel()) - W
    a, b, c = Vl[Fl[:, 0]], Vl[Fl[:, 1]], Vl[Fl[:, 2]]
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    mass = np.bincount(Fl.ravel(), weights=np.repeat(area / 3.0, 3), minlength=used.size)
    # a vertex whose triangles are all degenerate keeps its value (positive diagonal)
    mass = np.maximum(mass, MASS_FLOOR_REL * max(float(mass.mean()), 1e-300))
    lu = spla.splu(
        (sp.diags(mass) + tau * L).tocsc(),
        permc_spec="MMD_AT_PLUS_A",
        diag_pivot_thresh=0.0,
        options={"SymmetricMode": True},
    )

    def step(X: np.ndarray) -> np.ndarray:
        out = X.copy()
        out[used] = lu.solve(np.asfortranarray(mass[:, None] * X[used]))
        return out

    return step


def unit_rows(X: np.ndarray) -> np.ndarray:
    """Rows of ``X (n, 3)`` scaled to unit length; zero rows stay zero."""
    length = np.linalg.norm(X, axis=1)
    return X / np.where(length > 0.0, length, 1.0)[:, None]


def turned_faces(before: np.ndarray, after: np.ndarray, T: np.ndarray) -> np.ndarray:
    """Triangles turned over (normal rotated by 90 degrees or more), ``(k,)`` bool.

    Parameters
    ----------
    before, after : (n, 3) float arrays
        Vertex positions.
    T : (k, 3) int array

    Returns
    -------
    (k,) bool array
        ``n_before . n_after <= 0``, already degenerate triangles left aside.
    """

    def cross(X: np.ndarray) -> np.ndarray:
        return np.cross(X[T[:, 1]] - X[T[:, 0]], X[T[:, 2]] - X[T[:, 0]])

    c0 = cross(before)
    return (np.einsum("ij,ij->i", c0, cross(after)) <= 0.0) & np.any(c0 != 0.0, axis=1)


def where_faces(
    V: np.ndarray, F3: np.ndarray, plist: list[Panel], mask: np.ndarray, *, up: np.ndarray
) -> str:
    """Where some triangles are, in words: their panels and their heights.

    Parameters
    ----------
    V : (n, 3) float array
    F3 : (m, 3) int array
    plist : list of Panel
    mask : (m,) bool array
        The triangles (at least one).
    up : (3,) float array, keyword-only
        The garment's up axis: heights are the centroids' coordinates along it.

    Returns
    -------
    str
        ``"panel 'front', 'back', height 12.0 to 31.5"``: the (up to three) panels holding
        most of them, most first.
    """
    fp = face_panels(F3, plist)[mask]
    count = np.bincount(fp[fp >= 0], minlength=len(plist))
    worst = np.argsort(-count, kind="stable")[: min(3, int((count > 0).sum()))]
    height = V[F3[mask]].mean(axis=1) @ (up / np.linalg.norm(up))
    names = ", ".join(f"'{plist[i].name}'" for i in worst) or "(none)"
    lo, hi = float(height.min()), float(height.max())
    at = f"{lo:.1f}" if hi - lo < 0.05 else f"{lo:.1f} to {hi:.1f}"
    return f"panel {names}, height {at}"


def offset_error(
    V: np.ndarray,
    F3: np.ndarray,
    plist: list[Panel],
    mask: np.ndarray,
    *,
    by: float,
    sigma: float,
    up: np.ndarray,
    washed_out: bool,
) -> PtailorError:
    """The error for an offset that cannot be made, naming the panels and heights.

    Parameters
    ----------
    V : (n, 3) float array
        Drape before the offset.
    F3 : (m, 3) int array
    plist : list of Panel
    mask : (m,) bool array
        The triangles to name: turned over, or those whose smoothed normals no longer
        follow their surface.
    by : float, keyword-only
        Signed offset.
    sigma : float, keyword-only
        The widest smoothing tried.
    up : (3,) float array, keyword-only
    washed_out : bool, keyword-only
        True when the smoothing an offset of this size needs is wider than the panels
        (their smoothed normals no longer point out of them), False when triangles turn
        over even at the widest smoothing.
    """
    verb = "loosening" if by > 0 else "tightening"
    where = where_faces(V, F3, plist, mask, up=up)
    if washed_out:
        return PtailorError(
            f"{verb} by {abs(by):g} needs the normals smoothed over about {sigma:.3g},"
            f" more than the garment allows ({where}: the smoothed normals no longer point"
            " out of the surface); use a smaller 'by'"
        )
    return PtailorError(
        f"{verb} by {abs(by):g} turns part of the region inside out ({where}): the surface"
        f" there curves more tightly than {abs(by):g}, even smoothed over {sigma:.3g};"
        " use a smaller 'by'"
    )


def offset_region(
    V: np.ndarray,
    F3: np.ndarray,
    F2: np.ndarray,
    plist: list[Panel],
    faces: np.ndarray,
    *,
    by: float,
    up: tuple[float, float, float] = (0.0, 1.0, 0.0),
) -> tuple[np.ndarray, float]:
    """Offset a region along its smoothed outward normals.

    Every vertex moves by ``by w n_s``: ``w`` its falloff weight (:func:`falloff_weights`,
    band ``max(FALLOFF_EDGES h, FALLOFF_BY |by|)`` with ``h`` the region's mean edge
    length) and ``n_s`` the outward normals (:func:`outward_normals`) diffused over the
    whole drape (:func:`normal_smoother`: ``SMOOTH_STEPS`` steps of total width
    ``sigma = max(SMOOTH_BY |by|, SMOOTH_EDGES h)``), normalised.

    Why smoothed: a simulated drape's wrinkles and folds curve far more tightly (radius
    well below 1 cm) than any useful ease, and offsetting them along their own normals
    folds them over. A smooth displacement field carries them along unchanged instead
    (detail preservation, after Nealen et al.): the surface under the wrinkles is offset
    by ``by``, which adds ``2 pi by`` around a closed region (the wrinkled cloth itself
    gains a little less, about the mean cosine of its wrinkles' slopes: 0.92 to 1.0 of it
    measured on simulated tees, shirts and a dress). On a tube the diffused
    normals are exactly the radial ones, so a cylinder offset by ``by`` gains exactly
    ``2 pi by`` of circumference.

    When the offset still turns a region triangle over, the field is diffused further
    (four times as long: twice ``sigma``), up to ``SMOOTH_LEVELS`` widths and as long as
    the smoothed normals still follow every panel that moves (area-weighted mean cosine to
    the raw normals at least ``NORMAL_AGREEMENT``: wider smoothing than a thin sleeve
    washes its normals out), before the offset is refused.

    The rest of the garment does not move: the weight is 0 on the region's border, so the
    displacement is continuous there (an as-rigid-as-possible solve for the rest would
    only pull the rings next to the border in).

    Parameters
    ----------
    V : (n, 3) float array
        Drape.
    F3, F2 : (m, 3) int arrays
    plist : list of Panel
    faces : (k,) int array
        The region's triangles.
    by : float, keyword-only
        Signed offset: positive outward (loosen), negative inward (tighten).
    up : (3,) float tuple, keyword-only
        The garment's up axis, for the error message.

    Returns
    -------
    V_new : (n, 3) float array
        The edited drape.
    sigma : float
        Width of the normal smoothing that was used (recorded in the step's log).

    Raises
    ------
    PtailorError
        When the offset turns a triangle over even at the widest smoothing (tightening by
        more than the surface's radius, loosening into a tight concave fold), or needs a
        smoothing wider than a panel, naming the panels and the heights where it happens.
    """
    T = F3[faces]
    h = float(np.linalg.norm(V[T] - V[np.roll(T, -1, axis=1)], axis=2).mean())
    band = max(FALLOFF_EDGES * h, FALLOFF_BY * abs(by))
    w = falloff_weights(V, F3, faces, band=band)
    moving = np.flatnonzero(w > 0.0)
    sigma = max(SMOOTH_BY * abs(by), SMOOTH_EDGES * h)
    step = normal_smoother(V, F3, tau=sigma * sigma / (2.0 * SMOOTH_STEPS))
    N0 = outward_normals(V, F3, F2, plist)
    # region triangles that move, their panels and areas: the smoothed normals must still
    # follow each panel's surface (area-weighted mean cosine to the raw normals)
    live = (w[T] > 0.0).any(axis=1)
    fp = face_panels(F3, plist)[faces]
    area = np.linalg.norm(np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]]), axis=1)
    wt = np.where(live & (fp >= 0), area, 0.0)
    total = np.bincount(np.maximum(fp, 0), weights=wt, minlength=len(plist))
    up_v = np.asarray(up, float)
    N, done, turned = N0, 0, np.zeros(len(T), dtype=bool)
    for level in range(SMOOTH_LEVELS):  # a loop over smoothing levels
        for _ in range(SMOOTH_STEPS * 4**level - done):  # over diffusion steps
            N = step(N)
        done = SMOOTH_STEPS * 4**level
        Nu = unit_rows(N)
        cos = np.einsum("ij,ij->i", Nu, N0)[T].mean(axis=1)
        agree = np.bincount(np.maximum(fp, 0), weights=wt * cos, minlength=len(plist))
        lost = agree < NORMAL_AGREEMENT * total  # panels the smoothing washed out
        if lost.any() and level == 0:
            bad = np.zeros(len(F3), dtype=bool)
            bad[faces[live & lost[np.maximum(fp, 0)] & (fp >= 0)]] = True
            raise offset_error(V, F3, plist, bad, by=by, sigma=sigma, up=up_v, washed_out=True)
        if lost.any():
            break
        V_new = V.copy()
        V_new[moving] += (by * w[moving])[:, None] * Nu[moving]
        turned = turned_faces(V, V_new, T)
        if not turned.any():
            return V_new, sigma * 2.0**level
    bad = np.zeros(len(F3), dtype=bool)
    bad[faces[turned]] = True
    tried = sigma * 2.0 ** (level - int(lost.any()))
    raise offset_error(V, F3, plist, bad, by=by, sigma=tried, up=up_v, washed_out=False)


# ---------------------------------------------------------------------------------------
# silhouette form
# ---------------------------------------------------------------------------------------


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


def view_name(view: Any) -> str:
    """A view as the user wrote it: ``front`` or ``[x, y, z]``."""
    return view if isinstance(view, str) else "[" + ", ".join(f"{float(x):g}" for x in view) + "]"


# ---------------------------------------------------------------------------------------
# the recipe step
# ---------------------------------------------------------------------------------------


def one_form(step: dict, where: str) -> list[str]:
    """Exactly one of ``by`` (with ``region``) or ``silhouette`` (with ``view``)."""
    op = step["op"]
    has_by, has_sketch = step.get("by") is not None, step.get("silhouette") is not None
    if has_by == has_sketch:
        return [
            f"{where}: {op} needs exactly one of 'by' (with 'region') or 'silhouette' (with 'view')"
        ]
    if has_by and step.get("view") is not None:
        return [f"{where}: 'view' goes with 'silhouette', not with 'by'"]
    if has_sketch and step.get("region") is not None:
        return [f"{where}: 'region' goes with 'by', not with 'silhouette'"]
    return []


PARAMS = {
    "region": Param(region, doc="all | {panels: [...]} | {box: {min, max}} (with by; default all)"),
    "by": Param(number(gt=0.0), doc="offset along the surface normals, recipe units"),
    "view": Param(
        view_spec, doc="front | back | left | right | top | bottom | [x, y, z] (default front)"
    ),
    "silhouette": Param(
        sketch_spec, doc="over-sketched outline [[u, v], ...] in the view's image plane"
    ),
}


def moved_panels_uneven(state: EditState, V_new: np.ndarray) -> np.ndarray:
    """``state.even`` with every panel whose drape vertices moved set to False."""
    changed = np.any(V_new != state.V3, axis=1)
    moved = np.zeros(len(state.panels), dtype=bool)
    fp = face_panels(state.base.F3, state.panels)
    hit = changed[state.base.F3].any(axis=1)
    moved[np.unique(fp[hit & (fp >= 0)])] = True
    return state.even & ~moved


def loosen(state: EditState, step: dict, *, options: EditOptions) -> EditState:
    """Loosen or tighten: offset a region along its normals, or over-sketch a silhouette.

    Offset form: see :func:`offset_region` (``+by`` for loosen, ``-by`` for tighten).
    Silhouette form: see :func:`silhouette_targets`; the rest of the drape follows by
    :func:`ptailor.method.deform.arap_deform` with the moved rings as handles. Every panel
    whose drape moved loses ``even`` (its outline is free when flattened).
    """
    g, V3 = state.base, state.V3
    if step.get("by") is not None:
        faces = region_faces(step.get("region") or "all", g, V3, state.panels)
        by = float(step["by"]) * (1.0 if step["op"] == "loosen" else -1.0)
        V_new, sigma = offset_region(V3, g.F3, g.F2, state.panels, faces, by=by, up=options.up)
        rec = {
            "op": step["op"],
            "by": float(step["by"]),
            "triangles": int(faces.size),
            "smoothing": round(sigma, 6),
        }
    else:
        view = step.get("view") or "front"
        frame = view_frame(view, up=options.up, front=options.front)
        X = V3 @ frame.T
        T = g.F3
        h = float(np.linalg.norm(V3[T] - V3[np.roll(T, -1, axis=1)], axis=2).mean())
        handles, targets, change = silhouette_targets(
            X,
            T,
            np.asarray(step["silhouette"], float),
            row=ROW_EDGES * h,
            view_name=view_name(view),
        )
        moved = targets @ frame
        used = np.unique(T)
        if handles.size == used.size and np.array_equal(handles, used):
            V_new = V3.copy()
            V_new[handles] = moved
        else:
            V_new = arap_deform(V3, T, handles, moved)
        rec = {
            "op": step["op"],
            "view": view,
            "outline_points": int(change.size),
            "handles": int(handles.size),
            "change_mean": round(float(change.mean()), 6),
            "change_max": round(float(change[np.argmax(np.abs(change))]), 6),
        }
    even = moved_panels_uneven(state, V_new)
    return replace(state, V3=V_new, even=even, log=(*state.log, rec))


register("loosen", PARAMS, check=one_form)(loosen)
register("tighten", PARAMS, check=one_form)(loosen)
