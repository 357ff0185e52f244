"""``extend`` with ``measure: drape``: rows along the drape's tangent planes.

Each opening vertex grows a straight line of new vertices across the boundary; the pattern
columns follow with the intrinsic scale of the triangles they grow from (the pattern-to-drape
maps' pseudo-inverses), the copies of a seam vertex in their seam's length ratio.
"""

from __future__ import annotations

import numpy as np

from ptailor import tolerances as tol
from ptailor.edits import tolerances as edit_tol
from ptailor.edits.extend.continuation import continuation_directions, in_planes
from ptailor.edits.extend.rows import (
    RowPlan,
    Rows,
    quad_rows,
    shorter_diagonals,
)
from ptailor.edits.opening import OpeningEdges
from ptailor.edits.state import EditState
from ptailor.edits.truing import seam_copy_weights, seam_sides
from ptailor.errors import PtailorError
from ptailor.geometry.pattern_maps import pattern_jacobians, pseudo_inverses
from ptailor.geometry.topology import half_edges
from ptailor.geometry.triangles import signed_areas_2d, triangle_normals
from ptailor.model.seams import seam_halfedges


def edge_outward(V: np.ndarray, oe: OpeningEdges) -> np.ndarray:
    """Unit outward in-plane normal of each opening edge, ``(k, 3)``: ``t x (t x (o - a))``,
    perpendicular to the edge ``t``, in its triangle's plane, away from the opposite vertex
    ``o``."""
    A = V[oe.a3]
    t = V[oe.b3] - A
    w = V[oe.opposite] - A
    out = np.cross(t, np.cross(t, w))  # = t (t.w) - w |t|^2: in-plane, away from the face
    return out / np.maximum(np.linalg.norm(out, axis=1), tol.TINY)[:, None]


def outward_directions(V: np.ndarray, oe: OpeningEdges) -> np.ndarray:
    """Unit directions, tangent to the surface and across the boundary, at an opening.

    Parameters
    ----------
    V : (n, 3) float array
        Drape positions.
    oe : OpeningEdges

    Returns
    -------
    (k, 3) float array
        At vertex ``oe.a3[i]``: the normalised sum of the unit outward in-plane normals of
        its two boundary edges (:func:`edge_outward`).
    """
    out = edge_outward(V, oe)
    s = np.roll(out, 1, axis=0) + out  # edge i - 1 ends and edge i starts at a3[i]
    ns = np.linalg.norm(s, axis=1)
    cusp = ns < edit_tol.EXTEND_CUSP
    s[cusp] = out[cusp]
    ns[cusp] = 1.0
    return s / ns[:, None]


def surface_directions(V: np.ndarray, F: np.ndarray, oe: OpeningEdges) -> np.ndarray:
    """The surface's outward continuation at an opening's vertices, ``(k, 3)``
    (:func:`ptailor.edits.extend.continuation.continuation_directions`, the opening's own
    :func:`outward_directions` where no band answers)."""
    return continuation_directions(V, F, oe, outward_directions(V, oe))


def seam_scales(
    V3: np.ndarray, F3: np.ndarray, V2: np.ndarray, F2: np.ndarray, cols: np.ndarray
) -> np.ndarray:
    """Pattern/drape length ratio of the seam edges at some pattern vertices.

    Parameters
    ----------
    V3, F3, V2, F2
        The garment (drape ``V3``, the one the pattern was made for).
    cols : (c,) int array
        Pattern vertices.

    Returns
    -------
    (c,) float array
        Mean ``|e2| / |e3|`` over the seam half-edges (each side of a seam separately) that
        end at each vertex; NaN where no seam edge does.
    """
    pairs = seam_halfedges(F3, F2).ravel()
    sigma = np.full(len(cols), np.nan)
    if pairs.size == 0 or len(cols) == 0:
        return sigma
    h2 = half_edges(F2)[pairs]
    h3 = half_edges(F3)[pairs]
    l3 = np.linalg.norm(V3[h3[:, 1]] - V3[h3[:, 0]], axis=1)
    ratio = np.linalg.norm(V2[h2[:, 1]] - V2[h2[:, 0]], axis=1) / np.maximum(l3, tol.TINY)
    colid = np.full(len(V2), -1, dtype=np.int64)
    colid[cols] = np.arange(len(cols))
    ids = colid[h2].ravel()
    vals = np.repeat(ratio, 2)
    ok = ids >= 0
    total = np.bincount(ids[ok], vals[ok], len(cols))
    count = np.bincount(ids[ok], minlength=len(cols))
    has = count > 0
    sigma[has] = total[has] / count[has]
    return sigma


def match_seam_steps(disp: np.ndarray, vert3: np.ndarray, sigma: np.ndarray) -> np.ndarray:
    """Give the pattern copies of one drape vertex steps in their seam's length ratio.

    Where a seam reaches the opening, its drape vertex has one pattern copy per side and the
    new rows continue the seam: both sides' new edges come from the same 3D edge, so their
    2D lengths should keep the seam's ratio (equal on a plain seam, the ease on an eased
    one). Each copy keeps its direction; its length becomes ``sigma_c * kappa`` with
    ``kappa`` the mean of ``|disp_c| / sigma_c`` over the copies of that vertex. With
    ``sigma`` the input lengths of the seam's two sides
    (:func:`ptailor.edits.truing.seam_copy_weights`) the grown seam keeps the input's
    ratio as a whole, however its ease is spread (trued); with the seam edges' local
    pattern/drape ratios (:func:`seam_scales`, where three panels meet), the new edges
    keep that of the edges they continue.

    Parameters
    ----------
    disp : (c, 2) float array
        Pattern step per unit 3D step, per pattern copy.
    vert3 : (c,) int array
        Drape vertex of each copy.
    sigma : (c,) float array
        Weight of each copy (a seam side's length, or :func:`seam_scales`), NaN for none.

    Returns
    -------
    (c, 2) float array
        ``disp`` with matched lengths where every copy of a drape vertex with two or more
        copies has a seam ratio; unchanged elsewhere.
    """
    _, grp = np.unique(vert3, return_inverse=True)
    n_g = int(grp.max()) + 1 if grp.size else 0
    length = np.linalg.norm(disp, axis=1)
    valid = np.isfinite(sigma) & (sigma > 0) & (length > 0)
    copies = np.bincount(grp, minlength=n_g)
    good = np.bincount(grp, valid.astype(float), n_g)
    apply = (copies[grp] >= 2) & (good[grp] == copies[grp])
    if not apply.any():
        return disp
    q = np.where(valid, length / np.where(valid, sigma, 1.0), 0.0)
    kappa = np.bincount(grp, q, n_g) / np.maximum(copies, 1)
    new_len = np.where(apply, np.where(valid, sigma, 0.0) * kappa[grp], length)
    return disp * (new_len / np.maximum(length, tol.TINY))[:, None]


def smooth_directions(D: np.ndarray) -> np.ndarray:
    """One ``[1, 2, 1] / 4`` smoothing pass of unit vectors along a closed loop.

    Parameters
    ----------
    D : (k, 3) float array

    Returns
    -------
    (k, 3) float array
        Unit vectors (a vector that averages to zero keeps its old value).
    """
    S = np.roll(D, 1, axis=0) + 2.0 * D + np.roll(D, -1, axis=0)
    n = np.linalg.norm(S, axis=1)
    ok = n > edit_tol.EXTEND_SMOOTH_ZERO
    out = D.copy()
    out[ok] = S[ok] / n[ok, None]
    return out


def column_steps(
    Jp: np.ndarray,
    dirs: np.ndarray,
    inv: np.ndarray,
    vert3: np.ndarray,
    sigma: np.ndarray,
    *,
    planes: tuple[np.ndarray, np.ndarray] | None = None,
) -> np.ndarray:
    """Pattern step of each pattern vertex on an opening per unit 3D step along its row.

    Parameters
    ----------
    Jp : (k, 2, 3) float array
        Pseudo-inverses of the pattern-to-drape maps of the opening's triangles
        (:func:`ptailor.geometry.pattern_maps.pseudo_inverses`).
    dirs : (k, 3) float array
        3D direction at each opening vertex (``a3[i]``).
    inv : (2k,) int array
        Pattern column of the start (first ``k``) and end (last ``k``) of each edge.
    vert3 : (c,) int array
        Drape vertex of each column.
    sigma : (c,) float array
        Weights (:func:`match_seam_steps`).
    planes : ((k, 3), (k, 3)) float arrays, optional, keyword-only
        The unit normals of the opening's triangles and their edges' outward directions
        (:func:`edge_outward`): each direction is first projected into its triangle's plane
        and made unit (:func:`ptailor.edits.extend.continuation.in_planes`), so a row
        leaving that plane still steps its full length in the pattern.

    Returns
    -------
    (c, 2) float array
        Mean of ``J+ dir`` over each column's triangles, seam copies matched
        (:func:`match_seam_steps`).
    """
    nc = len(vert3)
    dir_a, dir_b = dirs, np.roll(dirs, -1, axis=0)
    if planes is not None:
        dir_a, dir_b = in_planes(dir_a, *planes), in_planes(dir_b, *planes)
    d_a = (Jp @ dir_a[:, :, None])[:, :, 0]
    d_b = (Jp @ dir_b[:, :, None])[:, :, 0]
    D = np.concatenate([d_a, d_b])
    cnt = np.bincount(inv, minlength=nc).astype(float)
    disp = np.stack([np.bincount(inv, D[:, c], nc) for c in range(2)], 1) / cnt[:, None]
    return match_seam_steps(disp, vert3, sigma)


def drape_rows(state: EditState, plan: RowPlan) -> Rows:
    """Rows continuing the drape along its tangent planes, ``by`` long on the surface.

    Each opening vertex grows a straight line of new vertices along the surface's outward
    continuation, read from a band of cloth behind the opening and perpendicular to it
    (:func:`surface_directions`; the last row of a simulated drape alone is often bent or
    flared). Where rows would cross (a 2D triangle flipped, or a 3D one turned against the
    plane of its row's direction and the opening, at a concave corner of the opening), the
    directions are smoothed along the opening (:func:`smooth_directions`), pass by pass,
    until they do not. Pattern columns step by ``J+ dir``, ``dir`` in the plane of the
    triangle it grows from (:func:`column_steps`).
    """
    g = state.base
    Ve, Vb, V2 = state.V3, g.V3, g.V2
    oe, name, by, rows = plan.oe, plan.name, plan.by, plan.rows
    cols, inv, ca, cb, nc = plan.cols, plan.inv, plan.ca, plan.cb, plan.nc
    orient, src = plan.orient, plan.src
    A3, B3, A2, B2 = plan.A3, plan.B3, plan.A2, plan.B2
    h = by / rows
    steps = (h * np.arange(1, rows + 1))[:, None, None]  # (rows, 1, 1)
    Fo = g.F3[oe.face]
    Jp = pseudo_inverses(pattern_jacobians(Vb, Fo, V2, g.F2[oe.face])[0])
    vert3 = np.empty(nc, dtype=np.int64)
    vert3[ca], vert3[cb] = oe.a3, oe.b3
    trued = seam_copy_weights(seam_sides(g), cols, vert3)  # a seam's two sides: trued
    sigma = np.where(np.isfinite(trued), trued, seam_scales(Vb, g.F3, V2, g.F2, cols))
    dir_e, dir_b = surface_directions(Ve, g.F3, oe), surface_directions(Vb, g.F3, oe)
    planes = (triangle_normals(Vb, Fo), edge_outward(Vb, oe))
    t_e = Ve[oe.b3] - Ve[oe.a3]
    for smoothing in range(edit_tol.EXTEND_MAX_SMOOTHING + 1):  # iterations, not vertices
        if smoothing:
            dir_e, dir_b = smooth_directions(dir_e), smooth_directions(dir_b)
        new_e = (Ve[oe.a3][None] + steps * dir_e[None]).reshape(-1, 3)
        new_b = (Vb[oe.a3][None] + steps * dir_b[None]).reshape(-1, 3)
        disp = column_steps(Jp, dir_b, inv, vert3, sigma, planes=planes)
        new_2 = (V2[cols][None] + steps * disp[None]).reshape(-1, 2)
        # triangles: each quad split along its shorter 3D diagonal (ties: checkerboard)
        Vall = np.concatenate([Ve, new_e])
        use_b = shorter_diagonals(Vall, A3, B3, plan.odd)
        F3_new = quad_rows(A3, B3, use_b)
        F2_new = quad_rows(A2, B2, use_b)
        V2all = np.concatenate([V2, new_2])
        a2 = signed_areas_2d(V2all, F2_new) * orient[src]
        # each new triangle against the plane of its row's direction and the opening edge
        n_row = np.cross(dir_e + np.roll(dir_e, -1, axis=0), t_e)
        fold = np.einsum("ij,ij->i", triangle_normals(Vall, F3_new), n_row[src])
        if np.all(a2 > edit_tol.EXTEND_ROW_AREA_MIN_REL * h * h) and np.all(fold > 0.0):
            break
    else:
        raise PtailorError(
            f"extend {name} by {by:g}: the new rows would cross (the opening turns too "
            "sharply for that length); extend by less, or lay the rows out in the "
            "pattern (measure: pattern)"
        )
    return Rows(new_e=new_e, new_b=new_b, new_2=new_2, use_b=use_b, smoothing=smoothing)
