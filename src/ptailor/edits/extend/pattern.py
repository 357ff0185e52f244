"""``extend`` with ``measure: pattern``: the new edge exactly ``by`` from the opening in the
pattern, the drape rows built to match."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor import tolerances as tol
from ptailor.edits import tolerances as edit_tol
from ptailor.edits.extend.chain import chain_order, nearest_fn, place_offset_chain
from ptailor.edits.extend.drape import match_seam_steps
from ptailor.edits.extend.rows import (
    RowPlan,
    Rows,
    crossing_error,
    quad_rows,
    shorter_diagonals,
)
from ptailor.edits.opening import OpeningEdges
from ptailor.edits.pattern_distance import PatternDistance, outline_halfedges
from ptailor.edits.state import EditState
from ptailor.edits.truing import seam_copy_weights, seam_sides
from ptailor.errors import PtailorError
from ptailor.geometry.pattern_maps import pattern_jacobians
from ptailor.geometry.triangles import signed_areas_2d, triangle_normals

#: ``measure: pattern``: the cosine of :data:`ptailor.edits.tolerances.EXTEND_SEAM_MAX_DEG`
_SEAM_MIN_COS = float(np.cos(np.radians(edit_tol.EXTEND_SEAM_MAX_DEG)))


def edge_normals_2d(V2: np.ndarray, F2: np.ndarray, oe: OpeningEdges) -> np.ndarray:
    """Unit outward normals of an opening's pattern edges, ``(k, 2)``.

    Perpendicular to ``a2 -> b2``, away from the edge's triangle (its pattern corner
    opposite the edge), so mirrored panels need no special case.
    """
    F = F2[oe.face]
    corner = np.argmax(oe.a2[:, None] == F, axis=1)
    opp = F[np.arange(len(F)), (corner + 2) % 3]
    t = V2[oe.b2] - V2[oe.a2]
    n = np.stack([t[:, 1], -t[:, 0]], 1)
    n *= np.where(np.einsum("ij,ij->i", n, V2[opp] - V2[oe.a2]) > 0, -1.0, 1.0)[:, None]
    return n / np.maximum(np.linalg.norm(n, axis=1), tol.TINY)[:, None]


def outline_neighbours(F2: np.ndarray, n2: int) -> tuple[np.ndarray, np.ndarray]:
    """Previous and next vertex along the pattern outlines.

    Parameters
    ----------
    F2 : (m, 3) int array
    n2 : int

    Returns
    -------
    prev, nxt : (n2,) int arrays
        For an outline half-edge ``u -> v`` (no twin, oriented like its triangle),
        ``prev[v] = u`` and ``nxt[u] = v``; -1 off the outline.
    """
    b = outline_halfedges(F2)
    prev = np.full(n2, -1, dtype=np.int64)
    nxt = np.full(n2, -1, dtype=np.int64)
    prev[b[:, 1]], nxt[b[:, 0]] = b[:, 0], b[:, 1]
    return prev, nxt


def offset_lengths(
    field: PatternDistance, P: np.ndarray, U: np.ndarray, panel: np.ndarray, by: float
) -> np.ndarray:
    """How far along each direction a point reaches distance ``by`` from the opening.

    Parameters
    ----------
    field : PatternDistance
        Its own edges (the opening's, per panel) are measured.
    P : (c, 2) float array
        Points on the opening.
    U : (c, 2) float array
        Unit directions.
    panel : (c,) int array
    by : float

    Returns
    -------
    (c,) float array
        ``s`` with ``distance(P + s U) = by`` (by bisection; ``s >= by`` since the distance
        from ``P`` itself is at most ``s``); NaN where the distance stays below ``by`` out
        to ``_MAX_REACH * by`` (an opening narrower than that in the pattern).
    """

    def dist(s: np.ndarray) -> np.ndarray:
        return field.at(P + s[:, None] * U, panel, own_only=True)

    lo = np.zeros(len(P))
    hi = np.full(len(P), by)
    short = dist(hi) < by
    for _ in range(edit_tol.EXTEND_REACH_DOUBLINGS):  # iterations, vectorised over the columns
        if not short.any():
            break
        lo = np.where(short, hi, lo)
        hi = np.where(short, 2.0 * hi, hi)
        short = dist(hi) < by
    for _ in range(edit_tol.EXTEND_BISECTION_STEPS):
        mid = 0.5 * (lo + hi)
        below = dist(mid) < by
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    out = 0.5 * (lo + hi)
    out[short] = np.nan
    return out


def _smooth_masked(
    D: np.ndarray, prev: np.ndarray, nxt: np.ndarray, mask: np.ndarray
) -> np.ndarray:
    """One ``[1, 2, 1] / 4`` pass of vectors along chains, on the masked entries only."""
    S = 0.25 * (D[prev] + 2.0 * D + D[nxt])
    return np.where(mask[:, None], S, D)


@dataclass(frozen=True)
class ColumnDirections:
    """The direction each column (a pattern vertex on the opening) moves along.

    Attributes
    ----------
    U : (c, 2) float array
        Unit directions: inside a chain of opening edges, the mean of its two edges'
        outward normals; at a chain's end, the seam continued (or the end edge's normal).
    n_end : (c, 2) float array
        At a chain's end, the outward normal of its end edge.
    inner : (c,) bool array
        Columns inside a chain (an opening edge on each side).
    prev_c, next_c : (c,) int arrays
        The columns before and after each along its chain (itself at a chain's end).
    """

    U: np.ndarray
    n_end: np.ndarray
    inner: np.ndarray
    prev_c: np.ndarray
    next_c: np.ndarray


def column_directions(V2: np.ndarray, F2: np.ndarray, plan: RowPlan) -> ColumnDirections:
    """Where each column of an opening moves in the pattern (see :class:`ColumnDirections`).

    A seam reaching the opening is continued straight when its continuation is within
    ``EXTEND_SEAM_MAX_DEG`` of the end edge's outward normal, else the end moves along
    that normal (a corner in the seam).
    """
    oe, cols, ca, cb, nc = plan.oe, plan.cols, plan.ca, plan.cb, plan.nc
    k = len(oe.a3)
    # chains of opening edges per panel: each column's edges before and after it
    n_e = edge_normals_2d(V2, F2, oe)
    e_in = np.full(nc, -1, dtype=np.int64)
    e_out = np.full(nc, -1, dtype=np.int64)
    e_in[cb], e_out[ca] = np.arange(k), np.arange(k)
    inner = (e_in >= 0) & (e_out >= 0)
    prev_c = np.where(e_in >= 0, ca[np.maximum(e_in, 0)], np.arange(nc))
    next_c = np.where(e_out >= 0, cb[np.maximum(e_out, 0)], np.arange(nc))
    U = np.zeros((nc, 2))
    U[inner] = n_e[e_in[inner]] + n_e[e_out[inner]]
    cusp = inner & (np.linalg.norm(U, axis=1) < edit_tol.EXTEND_CUSP)
    U[cusp] = n_e[e_out[cusp]]
    # chain ends: continue the seam (the outline edge before the start / after the end)
    o_prev, o_next = outline_neighbours(F2, len(V2))
    start = e_in < 0
    n_end = np.where(start[:, None], n_e[np.maximum(e_out, 0)], n_e[np.maximum(e_in, 0)])
    other = np.where(start, o_prev[cols], o_next[cols])
    seam_dir = V2[cols] - V2[np.maximum(other, 0)]
    seam_dir /= np.maximum(np.linalg.norm(seam_dir, axis=1), tol.TINY)[:, None]
    along = (other >= 0) & (np.einsum("ij,ij->i", seam_dir, n_end) >= _SEAM_MIN_COS)
    U[~inner] = np.where(along[~inner, None], seam_dir[~inner], n_end[~inner])
    U /= np.maximum(np.linalg.norm(U, axis=1), tol.TINY)[:, None]
    return ColumnDirections(U=U, n_end=n_end, inner=inner, prev_c=prev_c, next_c=next_c)


def _seam_weights(
    state: EditState, plan: RowPlan, inner: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Each column's drape vertex ``(c,)`` and, at a chain's end on a seam, its seam side's
    input length ``(c,)`` (NaN elsewhere): the copies of a seam vertex grow their seam in
    the input's ratio (trued, :func:`ptailor.edits.extend.drape.match_seam_steps`)."""
    vert3 = np.empty(plan.nc, dtype=np.int64)
    vert3[plan.ca], vert3[plan.cb] = plan.oe.a3, plan.oe.b3
    weight = seam_copy_weights(seam_sides(state.base), plan.cols, vert3)
    return vert3, np.where(inner, np.nan, weight)


def pattern_offsets(
    state: EditState, plan: RowPlan, dirs: ColumnDirections
) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """The new edge in the pattern, exactly ``by`` from the opening, and the rows up to it.

    Returns
    -------
    D2 : (c, 2) float array
        Each column's offset.
    new_2 : (rows c, 2) float array
        The new pattern vertices, row by row (the rows divide each column evenly).
    use_b : (rows, k) bool array
        Quad diagonals (:func:`quad_rows`).
    passes : int
        Smoothing passes of the directions.

    Raises
    ------
    PtailorError
        An opening narrower than twice ``by`` in some panel's pattern, or rows that
        still cross after ``EXTEND_MAX_SMOOTHING`` passes.
    """
    V2 = state.base.V2
    oe, name, by, rows = plan.oe, plan.name, plan.by, plan.rows
    cols, ca, cb, nc = plan.cols, plan.ca, plan.cb, plan.nc
    flab, orient, src, field = plan.flab, plan.orient, plan.src, plan.field
    col_panel = plan.col_panel
    names = {p.index: p.name for p in state.panels}
    U, n_end, inner, prev_c, next_c = dirs.U, dirs.n_end, dirs.inner, dirs.prev_c, dirs.next_c
    # where a continued seam runs along the opening instead of meeting its offset near the
    # end, the end goes along the end edge's normal (a corner in the seam)
    Q_end = V2[cols] + offset_lengths(field, V2[cols], n_end, col_panel, by)[:, None] * n_end
    frac = (np.arange(1, rows + 1) / rows)[:, None, None]
    vert3, weight = _seam_weights(state, plan, inner)
    order, chain, closed = chain_order(oe)
    seqs = []
    for ch in range(int(chain.max()) + 1):  # a loop over chains (a few per panel)
        E = order[chain == ch]
        seq = ca[E] if closed else np.append(ca[E], cb[E[-1]])
        own = field.own & (field.panel == flab[oe.face[E[0]]])
        seqs.append((seq, nearest_fn(field.A[own], field.B[own])))

    mask = np.zeros(nc, bool)
    for p_pass in range(edit_tol.EXTEND_MAX_SMOOTHING + 1):  # iterations, not vertices
        if p_pass:
            U = _smooth_masked(U, prev_c, next_c, mask & inner)
            U /= np.maximum(np.linalg.norm(U, axis=1), tol.TINY)[:, None]
        s_len = offset_lengths(field, V2[cols], U, col_panel, by)
        Q = V2[cols] + s_len[:, None] * U
        for seq, near in seqs:  # a loop over chains
            Q[seq] = place_offset_chain(
                V2[cols[seq]], Q[seq], by, near=near, closed=closed, ends=Q_end[seq[[0, -1]]]
            )
        if np.isnan(Q).any():
            bad = np.unique(col_panel[np.isnan(Q).any(axis=1)])
            raise PtailorError(
                f"extend {name} by {by:g}: in the pattern of "
                f"{', '.join(names[int(q)] for q in bad)} the opening is narrower than "
                f"twice that: offset by {by:g} its edge closes on itself; extend by less"
            )
        D2 = match_seam_steps(Q - V2[cols], vert3, weight)
        new_2 = (V2[cols][None] + frac * D2[None]).reshape(-1, 2)
        V2all = np.concatenate([V2, new_2])
        use_b = shorter_diagonals(V2all, plan.A2, plan.B2, plan.odd)
        F2_new = quad_rows(plan.A2, plan.B2, use_b)
        h2 = by / rows
        ok2 = (
            signed_areas_2d(V2all, F2_new) * orient[src]
            > edit_tol.EXTEND_ROW_AREA_MIN_REL * h2 * h2
        )
        if ok2.all():
            break
        bad_cols = np.unique(np.concatenate([ca[src[~ok2]], cb[src[~ok2]]]))
        mask[bad_cols] = True
        mask |= mask[prev_c] | mask[next_c]
    else:
        bad = np.unique(flab[oe.face[src[~ok2]]])
        raise crossing_error(name, by, "in the pattern of " + ", ".join(names[int(q)] for q in bad))
    return D2, new_2, use_b, p_pass


def lift_offsets(
    state: EditState, plan: RowPlan, D2: np.ndarray, use_b: np.ndarray
) -> tuple[np.ndarray, np.ndarray, int]:
    """The drape rows matching pattern offsets, on the edited and the original drape.

    Each opening vertex's pattern offset goes through its triangles' pattern-to-drape
    maps; where the rows would fold over, the offsets are smoothed along the opening.

    Returns
    -------
    new_e, new_b : (rows k, 3) float arrays
        Edited and original drape positions, row by row.
    passes : int
        Smoothing passes.

    Raises
    ------
    PtailorError
        Rows that still fold over after ``EXTEND_MAX_SMOOTHING`` passes.
    """
    g = state.base
    V2, Ve, Vb = g.V2, state.V3, g.V3
    oe, name, by, rows = plan.oe, plan.name, plan.by, plan.rows
    ca, cb, n_src, src = plan.ca, plan.cb, plan.n_src, plan.src
    k = len(oe.a3)
    frac = (np.arange(1, rows + 1) / rows)[:, None, None]
    # the drape: each opening vertex's pattern offset through its triangles' maps
    Fo, Fo2 = g.F3[oe.face], g.F2[oe.face]
    Je = pattern_jacobians(Ve, Fo, V2, Fo2)[0]  # (k, 3, 2)
    Jb = pattern_jacobians(Vb, Fo, V2, Fo2)[0]

    def lift(J: np.ndarray) -> np.ndarray:
        at_a = (J @ D2[ca][:, :, None])[:, :, 0]  # edge i's map at its start a3[i]
        at_b = (J @ D2[cb][:, :, None])[:, :, 0]  # ... at its end a3[i + 1]
        return 0.5 * (at_a + np.roll(at_b, 1, axis=0))

    D3e, D3b = lift(Je), lift(Jb)
    F3_new = quad_rows(plan.A3, plan.B3, use_b)
    ring = np.arange(k)
    r_prev, r_next = np.roll(ring, 1), np.roll(ring, -1)
    mask3 = np.zeros(k, bool)
    for smoothing in range(edit_tol.EXTEND_MAX_SMOOTHING + 1):  # iterations, not vertices
        if smoothing:
            D3e = _smooth_masked(D3e, r_prev, r_next, mask3)
            D3b = _smooth_masked(D3b, r_prev, r_next, mask3)
        new_e = (Ve[oe.a3][None] + frac * D3e[None]).reshape(-1, 3)
        Vall = np.concatenate([Ve, new_e])
        fold = np.einsum("ij,ij->i", triangle_normals(Vall, F3_new), n_src[src])
        if np.all(fold > 0.0):
            break
        bad = np.unique(np.concatenate([src[fold <= 0.0], (src[fold <= 0.0] + 1) % k]))
        mask3[bad] = True
        mask3 |= mask3[r_prev] | mask3[r_next]
    else:
        raise crossing_error(name, by, "in the drape")
    new_b = (Vb[oe.a3][None] + frac * D3b[None]).reshape(-1, 3)
    return new_e, new_b, smoothing


def pattern_rows(state: EditState, plan: RowPlan) -> Rows:
    """Rows laid out in the pattern exactly ``by`` beyond the opening, the drape to match.

    Pattern: every column (a pattern vertex on the opening) moves along a direction, as
    far as it takes to lie exactly ``by`` from the opening's edges in its panel
    (:func:`offset_lengths`): inside a chain of opening edges along the mean of its two
    edges' outward normals; at a chain's end (a seam) along the seam's own direction, so
    the seam continues straight, unless it runs within 15 degrees of the opening's edge or
    along the opening instead of meeting the offset near the end (then along the end
    edge's normal, a corner in the seam). Columns whose points come out crossed (a concave
    opening, a seam continued over it) are re-placed along the iso-line
    (:func:`place_offset_chain`); where the rows would still cross, the directions there
    are smoothed along the chain, pass by pass. Intermediate rows divide each column
    evenly.

    Drape: each opening vertex moves by its pattern offset mapped through the
    pattern-to-drape maps of its boundary triangles (the mean over its pattern copies'
    triangles, on the edited and on the original drape alike), so the new cloth continues
    the tangent planes with the intrinsic scale of the cloth it grows from; where the rows
    would fold over in the drape, those offsets are smoothed along the opening.
    """
    dirs = column_directions(state.base.V2, state.base.F2, plan)
    D2, new_2, use_b, p_pass = pattern_offsets(state, plan, dirs)
    new_e, new_b, smoothing = lift_offsets(state, plan, D2, use_b)
    return Rows(
        new_e=new_e,
        new_b=new_b,
        new_2=new_2,
        use_b=use_b,
        smoothing=smoothing,
        pattern_smoothing=p_pass,
    )
