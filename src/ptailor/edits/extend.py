"""``extend``: add rows of cloth beyond an opening (the paper's Extend, after Brouet et al.).

The rows continue the surface along the tangent planes of the triangles at the opening; the
new pattern strip takes the intrinsic scale of the triangles it grows from, and the final
flattening glues it to its panels (outline free along the new cloth).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ptailor.edits import EditOptions, EditState, Param, register
from ptailor.edits.checks import number
from ptailor.edits.opening import find_opening, opening_spec
from ptailor.errors import PtailorError
from ptailor.method.flatten import panel_labels
from ptailor.method.intrinsic import edge_matrices, inv2
from ptailor.model.garment import Garment, panels, signed_areas_2d
from ptailor.model.seams import half_edges, seam_halfedges

#: Smoothing passes of the row directions tried before giving up on crossing rows.
_MAX_SMOOTHING = 200


@dataclass(frozen=True)
class OpeningEdges:
    """The boundary edges of one opening, with their triangles.

    Attributes
    ----------
    a3, b3 : (k,) int arrays
        Drape ends of edge ``i``: ``loop[i]`` and ``loop[i + 1]`` (half-edge order, so the
        triangle is on the left of ``a3 -> b3``).
    a2, b2 : (k,) int arrays
        The same ends in the pattern (the triangle's pattern corners).
    face : (k,) int array
        The triangle of each edge.
    opposite : (k,) int array
        Drape vertex of that triangle opposite the edge.
    """

    a3: np.ndarray
    b3: np.ndarray
    a2: np.ndarray
    b2: np.ndarray
    face: np.ndarray
    opposite: np.ndarray


def opening_edges(F3: np.ndarray, F2: np.ndarray, loop: np.ndarray) -> OpeningEdges:
    """Triangles and pattern edges along an ordered boundary loop.

    Parameters
    ----------
    F3, F2 : (m, 3) int arrays
        Drape and pattern triangles.
    loop : (k,) int array
        Ordered drape vertices of a boundary loop, in either direction.

    Returns
    -------
    OpeningEdges

    Raises
    ------
    PtailorError
        When consecutive loop vertices are not a boundary edge of ``F3``.
    """
    loop = np.asarray(loop, dtype=np.int64)
    h3 = half_edges(F3)
    n = int(max(F3.max(initial=0), loop.max(initial=0))) + 1
    keys = h3[:, 0] * n + h3[:, 1]
    order = np.argsort(keys, kind="stable")
    sorted_keys = keys[order]

    def lookup(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        q = a * n + b
        pos = np.minimum(np.searchsorted(sorted_keys, q), len(sorted_keys) - 1)
        return np.where(sorted_keys[pos] == q, order[pos], -1)

    a, b = loop, np.roll(loop, -1)
    he = lookup(a, b)
    if np.any(he < 0):  # the loop was given against its half-edges: walk it the other way
        loop = loop[::-1]
        a, b = loop, np.roll(loop, -1)
        he = lookup(a, b)
    if len(loop) < 3 or np.any(he < 0) or np.any(lookup(b, a) >= 0):
        raise PtailorError("the opening is not a boundary loop of the drape")
    f, c = he // 3, he % 3
    return OpeningEdges(
        a3=a,
        b3=b,
        a2=F2[f, c],
        b2=F2[f, (c + 1) % 3],
        face=f,
        opposite=F3[f, (c + 2) % 3],
    )


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
        its two boundary edges (``t x (t x (o - a))``: perpendicular to the edge ``t``, in
        its triangle's plane, away from the opposite vertex ``o``).
    """
    A = V[oe.a3]
    t = V[oe.b3] - A
    w = V[oe.opposite] - A
    out = np.cross(t, np.cross(t, w))  # = t (t.w) - w |t|^2: in-plane, away from the face
    out /= np.maximum(np.linalg.norm(out, axis=1), 1e-300)[:, None]
    s = np.roll(out, 1, axis=0) + out  # edge i - 1 ends and edge i starts at a3[i]
    ns = np.linalg.norm(s, axis=1)
    cusp = ns < 1e-6
    s[cusp] = out[cusp]
    ns[cusp] = 1.0
    return s / ns[:, None]


def pattern_maps(V3: np.ndarray, F3: np.ndarray, V2: np.ndarray, F2: np.ndarray) -> np.ndarray:
    """Pseudo-inverses of the pattern-to-drape maps of triangles.

    Parameters
    ----------
    V3 : (n3, 3) float array
    F3 : (k, 3) int array
    V2 : (n2, 2) float array
    F2 : (k, 3) int array

    Returns
    -------
    (k, 2, 3) float array
        ``J+ = (J^T J)^-1 J^T`` with ``J = E3 E2^-1``: a 3D displacement in the triangle's
        plane to the pattern displacement of the same cloth.
    """
    J = edge_matrices(V3, F3) @ inv2(edge_matrices(V2, F2))
    Jt = np.swapaxes(J, 1, 2)
    return inv2(Jt @ J) @ Jt


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
    ratio = np.linalg.norm(V2[h2[:, 1]] - V2[h2[:, 0]], axis=1) / np.maximum(l3, 1e-300)
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
    ``kappa`` the mean of ``|disp_c| / sigma_c`` over the copies of that vertex.

    Parameters
    ----------
    disp : (c, 2) float array
        Pattern step per unit 3D step, per pattern copy.
    vert3 : (c,) int array
        Drape vertex of each copy.
    sigma : (c,) float array
        Seam length ratio per copy (:func:`seam_scales`), NaN for none.

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
    return disp * (new_len / np.maximum(length, 1e-300))[:, None]


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
    ok = n > 1e-12
    out = D.copy()
    out[ok] = S[ok] / n[ok, None]
    return out


def face_normals(V: np.ndarray, F: np.ndarray) -> np.ndarray:
    """Unit normals of triangles, ``(m, 3)`` (zero for degenerate ones)."""
    N = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    return N / np.maximum(np.linalg.norm(N, axis=1), 1e-300)[:, None]


def column_steps(
    Jp: np.ndarray, dirs: np.ndarray, inv: np.ndarray, vert3: np.ndarray, sigma: np.ndarray
) -> np.ndarray:
    """Pattern step of each pattern vertex on an opening per unit 3D step along its row.

    Parameters
    ----------
    Jp : (k, 2, 3) float array
        :func:`pattern_maps` of the opening's triangles.
    dirs : (k, 3) float array
        3D direction at each opening vertex (``a3[i]``).
    inv : (2k,) int array
        Pattern column of the start (first ``k``) and end (last ``k``) of each edge.
    vert3 : (c,) int array
        Drape vertex of each column.
    sigma : (c,) float array
        Seam ratios (:func:`seam_scales`).

    Returns
    -------
    (c, 2) float array
        Mean of ``J+ dir`` over each column's triangles, seam copies matched
        (:func:`match_seam_steps`).
    """
    nc = len(vert3)
    d_a = (Jp @ dirs[:, :, None])[:, :, 0]
    d_b = (Jp @ np.roll(dirs, -1, axis=0)[:, :, None])[:, :, 0]
    D = np.concatenate([d_a, d_b])
    cnt = np.bincount(inv, minlength=nc).astype(float)
    disp = np.stack([np.bincount(inv, D[:, c], nc) for c in range(2)], 1) / cnt[:, None]
    return match_seam_steps(disp, vert3, sigma)


def quad_rows(A: np.ndarray, B: np.ndarray, use_b: np.ndarray) -> np.ndarray:
    """Triangulate the quads between consecutive rows of vertex indices.

    Parameters
    ----------
    A, B : (r + 1, k) int arrays
        Row ``j`` holds the vertex at the start and at the end of each opening edge; row 0
        is the opening, whose half-edge ``A[0] -> B[0]`` has its triangle on the left.
    use_b : (r, k) bool array
        Split each quad along ``A[j] - B[j + 1]`` (else ``B[j] - A[j + 1]``).

    Returns
    -------
    (2 r k, 3) int array
        Two triangles per quad, row by row; oriented like the triangles at the opening
        (each row's edge ``B[j] -> A[j]`` is the twin of the row below).
    """
    a0, a1, b0, b1 = A[:-1], A[1:], B[:-1], B[1:]
    u = use_b[..., None]
    t0 = np.where(u, np.stack([b0, a0, b1], -1), np.stack([b0, a0, a1], -1))
    t1 = np.where(u, np.stack([a0, a1, b1], -1), np.stack([b0, a1, b1], -1))
    return np.stack([t0, t1], axis=2).reshape(-1, 3)


def _default_clearance(options: EditOptions, mean_edge: float) -> float:
    c = getattr(options, "clearance", None)
    return 0.5 * mean_edge if c is None else float(c)


@register(
    "extend",
    {
        "opening": Param(opening_spec, required=True, doc="hem | neckline | ... | {loop: k}"),
        "by": Param(
            number(gt=0.0), required=True, doc="length added (recipe units, on the surface)"
        ),
        "clearance": Param(
            number(ge=0.0),
            default=None,
            doc="distance kept from the body (with a body); default half an edge",
        ),
    },
)
def extend(state: EditState, step: dict, *, options: EditOptions) -> EditState:
    """Add rows of triangles beyond an opening, continuing the surface, ``by`` long.

    Each opening vertex grows a straight line of new vertices along the unit direction
    tangent to the surface and across the boundary (:func:`outward_directions`), ``rows``
    rows of height ``by / rows`` near the opening's mean edge length. Where rows would cross
    (a 2D triangle flipped or a 3D one folded back at a concave corner of the opening), the
    directions are smoothed along the opening (:func:`smooth_directions`), pass by pass,
    until they do not; after ``_MAX_SMOOTHING`` passes the step fails. The edited drape
    ``state.V3`` grows from its own opening; the original drape ``state.base.V3`` grows the
    same rows from its opening, so the new cloth follows earlier edits like the cloth it
    continues (after a first step both are the same). With a body (``options.body``, a
    ``trimesh.Trimesh``), new edited vertices inside it or within ``clearance`` of it are
    pushed out (:func:`ptailor.edits.body.push_out`).

    Pattern: every pattern vertex on the opening (one per panel side, so seams continue
    into the new rows) grows a column ``v2 + j (by / rows) d`` with ``d`` the mean of
    ``J+ dir`` over its boundary triangles (:func:`pattern_maps`, original drape), so the
    new triangles take the intrinsic scale of the triangles they grow from; the copies of a
    seam vertex get steps in their seam's length ratio (:func:`match_seam_steps`). These
    are the new triangles' original pattern; the final flattening glues them. The new
    pattern vertices are outline-free; panels keep their ``even`` flag.
    """
    name, loop = find_opening(state, step["opening"], options=options)
    by = float(step["by"])
    g = state.base
    Ve, Vb, V2 = state.V3, g.V3, g.V2
    n3, n2, m = len(Vb), len(V2), g.n_faces
    oe = opening_edges(g.F3, g.F2, loop)
    k = len(oe.a3)

    # rows: straight lines along the outward directions, smoothed along the opening only as
    # much as it takes to keep the rows from crossing (concave corners)
    Fo = g.F3[oe.face]
    mean_edge = float(np.linalg.norm(Ve[Fo] - Ve[np.roll(Fo, -1, axis=1)], axis=2).mean())
    rows = max(1, int(np.rint(by / mean_edge)))
    h = by / rows
    steps = (h * np.arange(1, rows + 1))[:, None, None]  # (rows, 1, 1)
    Jp = pattern_maps(Vb, Fo, V2, g.F2[oe.face])
    cols, inv = np.unique(np.concatenate([oe.a2, oe.b2]), return_inverse=True)
    nc = len(cols)
    ca, cb = inv[:k], inv[k:]
    vert3 = np.empty(nc, dtype=np.int64)
    vert3[ca], vert3[cb] = oe.a3, oe.b3
    sigma = seam_scales(Vb, g.F3, V2, g.F2, cols)
    flab = panel_labels(state.panels, m)
    orient = np.where([p.mirrored for p in state.panels], -1.0, 1.0)[flab[oe.face]]
    n_src = face_normals(Ve, Fo)
    grid3 = np.vstack([oe.a3[None], n3 + np.arange(rows * k).reshape(rows, k)])
    grid2 = np.vstack([cols[None], n2 + np.arange(rows * nc).reshape(rows, nc)])
    A3, B3 = grid3, grid3[:, np.roll(np.arange(k), -1)]
    A2, B2 = grid2[:, ca], grid2[:, cb]
    odd = (np.arange(rows)[:, None] + np.arange(k)[None, :]) % 2 == 1
    dir_e, dir_b = outward_directions(Ve, oe), outward_directions(Vb, oe)
    for smoothing in range(_MAX_SMOOTHING + 1):  # iterations, not vertices
        if smoothing:
            dir_e, dir_b = smooth_directions(dir_e), smooth_directions(dir_b)
        new_e = (Ve[oe.a3][None] + steps * dir_e[None]).reshape(-1, 3)
        new_b = (Vb[oe.a3][None] + steps * dir_b[None]).reshape(-1, 3)
        disp = column_steps(Jp, dir_b, inv, vert3, sigma)
        new_2 = (V2[cols][None] + steps * disp[None]).reshape(-1, 2)
        # triangles: each quad split along its shorter 3D diagonal (ties: checkerboard)
        Vall = np.concatenate([Ve, new_e])
        dA = np.linalg.norm(Vall[A3[1:]] - Vall[B3[:-1]], axis=2)
        dB = np.linalg.norm(Vall[A3[:-1]] - Vall[B3[1:]], axis=2)
        tie = np.abs(dA - dB) <= 1e-9 * (dA + dB)
        use_b = np.where(tie, odd, dB < dA)
        F3_new = quad_rows(A3, B3, use_b)
        F2_new = quad_rows(A2, B2, use_b)
        src = np.broadcast_to(np.arange(k)[None, :, None], (rows, k, 2)).reshape(-1)
        V2all = np.concatenate([V2, new_2])
        a2 = signed_areas_2d(V2all, F2_new) * orient[src]
        fold = np.einsum("ij,ij->i", face_normals(Vall, F3_new), n_src[src])
        if np.all(a2 > 1e-9 * h * h) and np.all(fold > 0.0):
            break
    else:
        raise PtailorError(
            f"extend {name} by {by:g}: the new rows would cross (the opening turns too "
            "sharply for that length); extend by less"
        )
    body = getattr(options, "body", None)
    if body is not None:
        from ptailor.edits.body import push_out

        clearance = step.get("clearance")
        if clearance is None:
            clearance = _default_clearance(options, mean_edge)
        new_e = push_out(new_e, body, clearance=float(clearance))

    lab_new = np.broadcast_to(flab[oe.face][None, :, None], (rows, k, 2)).reshape(-1)
    base = Garment(
        V3=np.concatenate([Vb, new_b]),
        F3=np.concatenate([g.F3, F3_new]),
        V2=np.concatenate([V2, new_2]),
        F2=np.concatenate([g.F2, F2_new]),
        face_group=np.concatenate([flab, lab_new]),
        group_names=tuple(p.name for p in state.panels),
        units=g.units,
    )
    new_panels = panels(base)
    old_even = {p.name: bool(state.even[p.index]) for p in state.panels}
    even = np.array([old_even.get(q.name, False) for q in new_panels], dtype=bool)
    free = np.ones(len(base.V2), dtype=bool)
    free[:n2] = False if state.outline_free is None else state.outline_free

    # achieved lengths: the new edge's distance from the old opening, in 3D and per panel
    from ptailor.report.outline import distance_stats, point_segment_distance

    top3 = new_e[(rows - 1) * k :]
    d3 = point_segment_distance(top3, Ve[oe.a3], Ve[oe.b3])
    col_panel = np.empty(nc, dtype=np.int64)
    col_panel[ca], col_panel[cb] = flab[oe.face], flab[oe.face]
    top2 = new_2[(rows - 1) * nc :]
    edge_panel = flab[oe.face]
    achieved_pattern = {}
    for p in state.panels:  # a loop over panels
        sel = edge_panel == p.index
        if sel.any():
            d2 = point_segment_distance(top2[col_panel == p.index], V2[oe.a2[sel]], V2[oe.b2[sel]])
            achieved_pattern[p.name] = distance_stats(d2)
    rec = {
        "op": "extend",
        "opening": name,
        "by": by,
        "rows": rows,
        "new_triangles": len(F3_new),
        "smoothing": smoothing,
        "achieved": {"3d": distance_stats(d3), "pattern": achieved_pattern},
    }
    return replace(
        state,
        base=base,
        V3=np.concatenate([Ve, new_e]),
        panels=new_panels,
        even=even,
        log=(*state.log, rec),
        outline_free=free,
    )
