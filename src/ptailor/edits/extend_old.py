"""``extend``: add rows of cloth beyond an opening (the paper's Extend, after Brouet et al.).

The rows continue the surface along the tangent planes of the triangles at the opening; the
new pattern strip takes the intrinsic scale of the triangles it grows from, and the final
flattening glues it to its panels (outline free along the new cloth).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from ptailor.edits import EditOptions, EditState, Param, register
from ptailor.edits.checks import number
from ptailor.edits.limits import check_by, check_new_triangles
from ptailor.edits.opening import find_opening, opening_spec
from ptailor.edits.shorten import MEASURE_PARAM, pattern_amounts, spread_stats
from ptailor.edits.surgery import PatternDistance, edge_distance
from ptailor.errors import PtailorError
from ptailor.method.flatten import panel_labels
from ptailor.method.intrinsic import edge_matrices, inv2
from ptailor.model.garment import Garment, panels, signed_areas_2d
from ptailor.model.seams import half_edges, seam_halfedges

#: Smoothing passes of the row directions tried before giving up on crossing rows.
_MAX_SMOOTHING = 200
#: ``measure: pattern``: a seam reaching the opening is continued straight when its
#: continuation is within 75 degrees of the end edge's outward normal (cos 75 deg) ...
_SEAM_MIN_COS = float(np.cos(np.radians(75.0)))
#: ... a column's offset is searched out to 2^8 ``by`` along its direction ...
_REACH_DOUBLINGS = 8
#: ... and placed by this many bisection steps.
_BISECTION_STEPS = 60


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
    return n / np.maximum(np.linalg.norm(n, axis=1), 1e-300)[:, None]


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
    h = half_edges(F2)
    fwd = h[:, 0].astype(np.int64) * n2 + h[:, 1]
    bwd = h[:, 1].astype(np.int64) * n2 + h[:, 0]
    b = h[~np.isin(fwd, bwd)]
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
    for _ in range(_REACH_DOUBLINGS):  # iterations, vectorised over the columns
        if not short.any():
            break
        lo = np.where(short, hi, lo)
        hi = np.where(short, 2.0 * hi, hi)
        short = dist(hi) < by
    for _ in range(_BISECTION_STEPS):
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


def chain_order(oe: OpeningEdges) -> tuple[np.ndarray, np.ndarray, bool]:
    """The opening's edges grouped into chains: runs that share pattern vertices.

    Consecutive edges of the loop belong to one chain while the end of one is the start of
    the next in the pattern (a seam, or a change of panel, breaks it).

    Parameters
    ----------
    oe : OpeningEdges

    Returns
    -------
    order : (k,) int array
        Edge indices, each chain's edges contiguous and in loop order.
    chain : (k,) int array
        Chain index of each edge of ``order`` (0, 1, ... in that order).
    closed : bool
        True when the whole opening is one closed chain (no seam crosses it).
    """
    k = len(oe.a2)
    ends = oe.b2 != np.roll(oe.a2, -1)  # edge i ends a chain
    if not ends.any():
        return np.arange(k), np.zeros(k, dtype=np.int64), True
    first = (int(np.flatnonzero(ends)[0]) + 1) % k
    order = np.roll(np.arange(k), -first)
    starts = np.roll(ends, 1)[order]
    return order, np.cumsum(starts) - 1, False


def _nearest_on(P: np.ndarray, A: np.ndarray, B: np.ndarray, cum: np.ndarray) -> tuple:
    """Nearest point of a polyline to each point.

    Parameters
    ----------
    P : (p, 2) float array
    A, B : (s, 2) float arrays
        The polyline's segments, in order.
    cum : (s,) float array
        Arc length at each segment's start.

    Returns
    -------
    distance : (p,) float array
    sigma : (p,) float array
        Arc length of the nearest point.
    foot : (p, 2) float array
        The nearest point.
    """
    d = B - A
    L2 = np.einsum("ij,ij->i", d, d)
    t = np.einsum("psd,sd->ps", P[:, None] - A[None], d) / np.where(L2 > 0, L2, 1.0)
    t = np.clip(t, 0.0, 1.0)
    F = A[None] + t[..., None] * d[None]
    dist = np.linalg.norm(P[:, None] - F, axis=2)
    j = np.argmin(dist, axis=1)
    r = np.arange(len(P))
    return dist[r, j], cum[j] + t[r, j] * np.sqrt(L2[j]), F[r, j]


def _nearest_fn(A: np.ndarray, B: np.ndarray) -> Callable:
    """``near(X) -> (distance, foot)``: the nearest point of some segments to points."""
    zeros = np.zeros(len(A))

    def near(X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        d, _, foot = _nearest_on(X, A, B, zeros)
        return d, foot

    return near


def place_offset_chain(
    P: np.ndarray,
    Q: np.ndarray,
    by: float,
    *,
    near: Callable,
    closed: bool,
    ends: np.ndarray | None = None,
) -> np.ndarray:
    """Order an offset chain's new points along the iso-line, re-placing crossed ones.

    Parameters
    ----------
    P : (c, 2) float array
        The chain's pattern vertices, in order (an open chain's ends are seam ends).
    Q : (c, 2) float array
        Each vertex's candidate new point, exactly ``by`` from the opening (NaN where its
        direction never gets that far).
    by : float
    near : callable, keyword-only
        ``near(X) -> (distance, foot)`` for ``X`` ``(p, 2)``: the distance to the panel's
        opening edges and the nearest point on them.
    closed : bool, keyword-only
        A closed chain (vertex ``c - 1`` joins vertex 0).
    ends : (2, 2) float array, optional, keyword-only
        Other new points for an open chain's two ends, used where ``Q``'s (a seam
        continued) is not nearest to the chain's end edge: the seam runs too close along
        the opening to meet the offset near its end.

    Returns
    -------
    (c, 2) float array
        New points in the chain's order, each ``by`` from the opening; NaN everywhere
        when an open chain's end has no candidate nearest to its own end edge (the offset
        closes the opening first), or no point of a closed one is nearest to its own. An
        interior point is kept when its nearest point on the chain lies on its own two
        edges, in order with the kept points around it and between the two ends' (a seam
        continued beyond the opening clips the offset there); the others are spread along
        the chord between the kept points around them by the old chain's arc length, and
        pushed onto the iso-line from their nearest point.
    """
    c = len(P)
    finite = np.all(np.isfinite(Q), axis=1)
    Qs = np.where(finite[:, None], Q, P)
    if closed:
        # walk the loop from a point that is kept, and back to it
        Pc = np.vstack([P, P[:1]])
        cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(Pc, axis=0), axis=1))])
        dist, sigma, _ = _nearest_on(Qs, Pc[:-1], Pc[1:], cum)
        idx = np.arange(c)
        tol_s = 1e-9 * (cum[-1] + by)
        seg = np.diff(cum)
        # arc length from its own vertex, around the loop either way
        off = (sigma - cum[idx] + 0.5 * cum[-1]) % cum[-1] - 0.5 * cum[-1]
        own = finite & (off >= -np.roll(seg, 1) - tol_s) & (off <= seg + tol_s)
        own &= dist <= near(Qs)[0] + tol_s
        if not own.any():
            return np.full((c, 2), np.nan)
        r = int(np.flatnonzero(own)[0])
        Pr, Qr = np.roll(P, -r, axis=0), np.roll(Q, -r, axis=0)
        out = _place_open(
            np.vstack([Pr, Pr[:1]]), np.vstack([Qr, Qr[:1]]), by, near=near, loop=True
        )
        return np.roll(out[:c], r, axis=0)
    cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(P, axis=0), axis=1))])
    tol_s = 1e-9 * (cum[-1] + by)

    def own_end(E: np.ndarray) -> np.ndarray:
        """Which of two end points lie nearest to their own end edge of the chain."""
        ok = np.all(np.isfinite(E), axis=1)
        E = np.where(ok[:, None], E, P[[0, -1]])
        dist, sigma, _ = _nearest_on(E, P[:-1], P[1:], cum)
        ok &= dist <= near(E)[0] + tol_s
        return ok & np.array([sigma[0] <= cum[1] + tol_s, sigma[1] >= cum[-2] - tol_s])

    alt = Q[[0, -1]] if ends is None else ends
    use = np.where(own_end(Q[[0, -1]]), 0, np.where(own_end(alt), 1, 2))
    if np.any(use == 2):  # the offset closes the opening before it reaches an end
        return np.full((c, 2), np.nan)
    Q = Q.copy()
    Q[[0, -1]] = np.where((use == 0)[:, None], Q[[0, -1]], alt)
    return _place_open(P, Q, by, near=near)


def _place_open(
    P: np.ndarray, Q: np.ndarray, by: float, *, near: Callable, loop: bool = False
) -> np.ndarray:
    """:func:`place_offset_chain` of an open chain whose two end points are settled.

    ``loop``: the chain is a closed one opened at a kept point (its last vertex repeats
    its first), so the ends' arc lengths are its ends', 0 and the whole length.
    """
    c = len(P)
    cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(P, axis=0), axis=1))])
    tol_s = 1e-9 * (cum[-1] + by)
    finite = np.all(np.isfinite(Q), axis=1)
    Qs = np.where(finite[:, None], Q, P)
    dist, sigma, _ = _nearest_on(Qs, P[:-1], P[1:], cum)
    if loop:
        sigma[[0, -1]] = cum[[0, -1]]
    idx = np.arange(c)
    ok = finite.copy()
    ok &= sigma >= cum[np.maximum(idx - 1, 0)] - tol_s  # the nearest point is on its own
    ok &= sigma <= cum[np.minimum(idx + 1, c - 1)] + tol_s  # two edges ...
    ok &= dist <= near(Qs)[0] + tol_s  # ... and not on another chain
    ok &= (sigma > sigma[0]) & (sigma < sigma[-1])  # between the ends' (clipped by seams)
    ok[[0, -1]] = True
    for _ in range(c):  # iterations: drop kept pairs out of order until none is
        kept = np.flatnonzero(ok)
        bad = np.diff(sigma[kept]) <= 0
        if not bad.any():
            break
        drop = np.union1d(kept[:-1][bad], kept[1:][bad])
        ok[drop[(drop > 0) & (drop < c - 1)]] = False
    left = np.maximum.accumulate(np.where(ok, idx, 0))
    right = np.minimum.accumulate(np.where(ok, idx, c - 1)[::-1])[::-1]
    span = cum[right] - cum[left]
    f = np.where(span > 0, (cum - cum[left]) / np.where(span > 0, span, 1.0), 0.0)
    X = Qs[left] + f[:, None] * (Qs[right] - Qs[left])
    _, foot = near(X)
    away = X - foot
    n = np.linalg.norm(away, axis=1)
    X = np.where((n > 0)[:, None], foot + by * away / np.where(n > 0, n, 1.0)[:, None], X)
    return np.where(ok[:, None], Qs, X)


@dataclass(frozen=True)
class Rows:
    """New rows beyond an opening, in the drape (edited and original) and the pattern.

    Attributes
    ----------
    new_e, new_b : (rows k, 3) float arrays
        Edited and original drape positions, row by row (``k`` per row, opening order).
    new_2 : (rows c, 2) float array
        Pattern positions, ``c`` columns per row.
    use_b : (rows, k) bool array
        Quad diagonals (:func:`quad_rows`).
    smoothing : int
        Smoothing passes of the drape rows.
    pattern_smoothing : int
        Smoothing passes of the pattern directions (``measure: pattern``).
    """

    new_e: np.ndarray
    new_b: np.ndarray
    new_2: np.ndarray
    use_b: np.ndarray
    smoothing: int
    pattern_smoothing: int = 0


def _crossing_error(name: str, by: float, where: str) -> PtailorError:
    return PtailorError(
        f"extend {name} by {by:g}: the new rows would cross {where} (the opening turns too "
        "sharply for that length); extend by less"
    )


def _pattern_rows(
    state: EditState,
    oe: OpeningEdges,
    geo: dict,
    *,
    name: str,
    by: float,
    rows: int,
) -> Rows:
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
    g = state.base
    V2, Ve, Vb = g.V2, state.V3, g.V3
    k = len(oe.a3)
    cols, ca, cb, nc = geo["cols"], geo["ca"], geo["cb"], geo["nc"]
    flab, orient, n_src = geo["flab"], geo["orient"], geo["n_src"]
    col_panel = np.empty(nc, dtype=np.int64)
    col_panel[ca], col_panel[cb] = flab[oe.face], flab[oe.face]
    names = {p.index: p.name for p in state.panels}
    field = geo["field"]

    # chains of opening edges per panel: each column's edges before and after it
    n_e = edge_normals_2d(V2, g.F2, oe)
    e_in = np.full(nc, -1, dtype=np.int64)
    e_out = np.full(nc, -1, dtype=np.int64)
    e_in[cb], e_out[ca] = np.arange(k), np.arange(k)
    inner = (e_in >= 0) & (e_out >= 0)
    prev_c = np.where(e_in >= 0, ca[np.maximum(e_in, 0)], np.arange(nc))
    next_c = np.where(e_out >= 0, cb[np.maximum(e_out, 0)], np.arange(nc))
    U = np.zeros((nc, 2))
    U[inner] = n_e[e_in[inner]] + n_e[e_out[inner]]
    cusp = inner & (np.linalg.norm(U, axis=1) < 1e-6)
    U[cusp] = n_e[e_out[cusp]]
    # chain ends: continue the seam (the outline edge before the start / after the end)
    o_prev, o_next = outline_neighbours(g.F2, len(V2))
    start = e_in < 0
    n_end = np.where(start[:, None], n_e[np.maximum(e_out, 0)], n_e[np.maximum(e_in, 0)])
    other = np.where(start, o_prev[cols], o_next[cols])
    seam_dir = V2[cols] - V2[np.maximum(other, 0)]
    seam_dir /= np.maximum(np.linalg.norm(seam_dir, axis=1), 1e-300)[:, None]
    along = (other >= 0) & (np.einsum("ij,ij->i", seam_dir, n_end) >= _SEAM_MIN_COS)
    U[~inner] = np.where(along[~inner, None], seam_dir[~inner], n_end[~inner])
    U /= np.maximum(np.linalg.norm(U, axis=1), 1e-300)[:, None]
    # where a continued seam runs along the opening instead of meeting its offset near the
    # end, the end goes along the end edge's normal (a corner in the seam)
    Q_end = V2[cols] + offset_lengths(field, V2[cols], n_end, col_panel, by)[:, None] * n_end

    # triangles of the rows, in the pattern and the drape
    grid3 = np.vstack([oe.a3[None], len(Vb) + np.arange(rows * k).reshape(rows, k)])
    grid2 = np.vstack([cols[None], len(V2) + np.arange(rows * nc).reshape(rows, nc)])
    A3, B3 = grid3, grid3[:, np.roll(np.arange(k), -1)]
    A2, B2 = grid2[:, ca], grid2[:, cb]
    frac = (np.arange(1, rows + 1) / rows)[:, None, None]
    src = np.broadcast_to(np.arange(k)[None, :, None], (rows, k, 2)).reshape(-1)
    odd = (np.arange(rows)[:, None] + np.arange(k)[None, :]) % 2 == 1

    order, chain, closed = chain_order(oe)
    seqs = []
    for ch in range(int(chain.max()) + 1):  # a loop over chains (a few per panel)
        E = order[chain == ch]
        seq = ca[E] if closed else np.append(ca[E], cb[E[-1]])
        own = field.own & (field.panel == flab[oe.face[E[0]]])
        seqs.append((seq, _nearest_fn(field.A[own], field.B[own])))

    mask = np.zeros(nc, bool)
    for p_pass in range(_MAX_SMOOTHING + 1):  # iterations, not vertices
        if p_pass:
            U = _smooth_masked(U, prev_c, next_c, mask & inner)
            U /= np.maximum(np.linalg.norm(U, axis=1), 1e-300)[:, None]
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
        D2 = Q - V2[cols]
        new_2 = (V2[cols][None] + frac * D2[None]).reshape(-1, 2)
        V2all = np.concatenate([V2, new_2])
        dA = np.linalg.norm(V2all[A2[1:]] - V2all[B2[:-1]], axis=2)
        dB = np.linalg.norm(V2all[A2[:-1]] - V2all[B2[1:]], axis=2)
        tie = np.abs(dA - dB) <= 1e-9 * (dA + dB)
        use_b = np.where(tie, odd, dB < dA)
        F2_new = quad_rows(A2, B2, use_b)
        h2 = by / rows
        ok2 = signed_areas_2d(V2all, F2_new) * orient[src] > 1e-9 * h2 * h2
        if ok2.all():
            break
        bad_cols = np.unique(np.concatenate([ca[src[~ok2]], cb[src[~ok2]]]))
        mask[bad_cols] = True
        mask |= mask[prev_c] | mask[next_c]
    else:
        bad = np.unique(flab[oe.face[src[~ok2]]])
        raise _crossing_error(
            name, by, "in the pattern of " + ", ".join(names[int(q)] for q in bad)
        )

    # the drape: each opening vertex's pattern offset through its triangles' maps
    Fo, Fo2 = g.F3[oe.face], g.F2[oe.face]
    E2inv = inv2(edge_matrices(V2, Fo2))
    Je, Jb = edge_matrices(Ve, Fo) @ E2inv, edge_matrices(Vb, Fo) @ E2inv  # (k, 3, 2)

    def lift(J: np.ndarray) -> np.ndarray:
        at_a = (J @ D2[ca][:, :, None])[:, :, 0]  # edge i's map at its start a3[i]
        at_b = (J @ D2[cb][:, :, None])[:, :, 0]  # ... at its end a3[i + 1]
        return 0.5 * (at_a + np.roll(at_b, 1, axis=0))

    D3e, D3b = lift(Je), lift(Jb)
    F3_new = quad_rows(A3, B3, use_b)
    ring = np.arange(k)
    r_prev, r_next = np.roll(ring, 1), np.roll(ring, -1)
    mask3 = np.zeros(k, bool)
    for smoothing in range(_MAX_SMOOTHING + 1):  # iterations, not vertices
        if smoothing:
            D3e = _smooth_masked(D3e, r_prev, r_next, mask3)
            D3b = _smooth_masked(D3b, r_prev, r_next, mask3)
        new_e = (Ve[oe.a3][None] + frac * D3e[None]).reshape(-1, 3)
        Vall = np.concatenate([Ve, new_e])
        fold = np.einsum("ij,ij->i", face_normals(Vall, F3_new), n_src[src])
        if np.all(fold > 0.0):
            break
        bad = np.unique(np.concatenate([src[fold <= 0.0], (src[fold <= 0.0] + 1) % k]))
        mask3[bad] = True
        mask3 |= mask3[r_prev] | mask3[r_next]
    else:
        raise _crossing_error(name, by, "in the drape")
    new_b = (Vb[oe.a3][None] + frac * D3b[None]).reshape(-1, 3)
    return Rows(
        new_e=new_e,
        new_b=new_b,
        new_2=new_2,
        use_b=use_b,
        smoothing=smoothing,
        pattern_smoothing=p_pass,
    )


def _drape_rows(
    state: EditState,
    oe: OpeningEdges,
    geo: dict,
    *,
    name: str,
    by: float,
    rows: int,
) -> Rows:
    """Rows continuing the drape along its tangent planes, ``by`` long on the surface.

    Each opening vertex grows a straight line of new vertices along the unit direction
    tangent to the surface and across the boundary (:func:`outward_directions`). Where
    rows would cross (a 2D triangle flipped or a 3D one folded back at a concave corner of
    the opening), the directions are smoothed along the opening (:func:`smooth_directions`),
    pass by pass, until they do not. Pattern columns step by ``J+ dir``
    (:func:`column_steps`).
    """
    g = state.base
    Ve, Vb, V2 = state.V3, g.V3, g.V2
    n3, n2 = len(Vb), len(V2)
    k = len(oe.a3)
    cols, inv, ca, cb, nc = geo["cols"], geo["inv"], geo["ca"], geo["cb"], geo["nc"]
    orient, n_src = geo["orient"], geo["n_src"]
    h = by / rows
    steps = (h * np.arange(1, rows + 1))[:, None, None]  # (rows, 1, 1)
    Fo = g.F3[oe.face]
    Jp = pattern_maps(Vb, Fo, V2, g.F2[oe.face])
    vert3 = np.empty(nc, dtype=np.int64)
    vert3[ca], vert3[cb] = oe.a3, oe.b3
    sigma = seam_scales(Vb, g.F3, V2, g.F2, cols)
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
            "sharply for that length); extend by less, or lay the rows out in the "
            "pattern (measure: pattern)"
        )
    return Rows(new_e=new_e, new_b=new_b, new_2=new_2, use_b=use_b, smoothing=smoothing)


@register(
    "extend",
    {
        "opening": Param(opening_spec, required=True, doc="hem | neckline | ... | {loop: k}"),
        "by": Param(number(gt=0.0), required=True, doc="length added, recipe units (see measure)"),
        "clearance": Param(
            number(ge=0.0),
            default=None,
            doc="distance kept from the body (with a body); default half an edge",
        ),
        "measure": MEASURE_PARAM,
    },
)
def extend(state: EditState, step: dict, *, options: EditOptions) -> EditState:
    """Add rows of triangles beyond an opening, continuing the surface, ``by`` long.

    ``measure: drape`` (the paper's): each opening vertex grows a straight line of new
    vertices along the unit direction tangent to the surface and across the boundary,
    ``by`` long on the drape (:func:`_drape_rows`); the pattern columns follow with the
    intrinsic scale of the triangles they grow from (``J+ dir``, :func:`pattern_maps`,
    original drape), the copies of a seam vertex in their seam's length ratio
    (:func:`match_seam_steps`). ``measure: pattern``: the new edge is laid out in each
    panel's pattern exactly ``by`` from the old one (the offset of the opening's pattern
    edges, seams continued straight where they meet it) and the drape rows are built to
    match through the pattern-to-drape maps of the triangles they grow from
    (:func:`_pattern_rows`).

    There are ``rows`` rows, about the opening's mean edge length apart; where rows would
    cross (a concave opening) the directions there are smoothed, pass by pass, and after
    ``_MAX_SMOOTHING`` passes the step fails naming where; an opening whose offset closes
    on itself is refused. The edited drape ``state.V3`` grows from its own opening; the
    original drape ``state.base.V3`` grows the same rows from its opening, so the new cloth
    follows earlier edits like the cloth it continues (after a first step both are the
    same). With a body (``options.body``, a ``trimesh.Trimesh``), new edited vertices
    inside it or within ``clearance`` of it are pushed out
    (:func:`ptailor.edits.body.push_out`). The new pattern vertices are the new
    triangles' original pattern (the final flattening glues them) and are outline-free;
    panels keep their ``even`` flag.

    The log record's ``amount`` gives the length added both ways: ``pattern``, per panel
    the opening runs along, the ``min``, ``median`` and ``max`` distance of the new edge's
    pattern vertices from the old edge; ``drape``, the same of their surface distance from
    the old opening.
    """
    name, loop = find_opening(state, step["opening"], options=options)
    by = float(step["by"])
    measure = step.get("measure") or "drape"
    g = state.base
    Ve, Vb, V2 = state.V3, g.V3, g.V2
    n2, m = len(V2), g.n_faces
    oe = opening_edges(g.F3, g.F2, loop)
    k = len(oe.a3)
    Fo = g.F3[oe.face]
    flab = panel_labels(state.panels, m)
    cols, inv = np.unique(np.concatenate([oe.a2, oe.b2]), return_inverse=True)
    nc = len(cols)
    ca, cb = inv[:k], inv[k:]
    field = edge_distance(V2, oe.a2, oe.b2, flab[oe.face])
    geo = {
        "cols": cols,
        "inv": inv,
        "ca": ca,
        "cb": cb,
        "nc": nc,
        "flab": flab,
        "orient": np.where([p.mirrored for p in state.panels], -1.0, 1.0)[flab[oe.face]],
        "n_src": face_normals(Ve, Fo),
        "field": field,
    }
    if measure == "pattern":
        Fo2 = g.F2[oe.face]
        mean_edge = float(np.linalg.norm(V2[Fo2] - V2[np.roll(Fo2, -1, axis=1)], axis=2).mean())
    else:
        mean_edge = float(np.linalg.norm(Ve[Fo] - Ve[np.roll(Fo, -1, axis=1)], axis=2).mean())
    check_by(by, mean_edge, what=f"extend {name}")
    rows_f = max(1.0, float(np.rint(by / mean_edge)))
    check_new_triangles(2.0 * rows_f * k, m, what=f"extend {name} by {by:g}")
    rows = int(rows_f)
    make = _pattern_rows if measure == "pattern" else _drape_rows
    built = make(state, oe, geo, name=name, by=by, rows=rows)
    new_e, new_b, new_2 = built.new_e, built.new_b, built.new_2
    grid3 = np.vstack([oe.a3[None], len(Vb) + np.arange(rows * k).reshape(rows, k)])
    grid2 = np.vstack([cols[None], n2 + np.arange(rows * nc).reshape(rows, nc)])
    F3_new = quad_rows(grid3, grid3[:, np.roll(np.arange(k), -1)], built.use_b)
    F2_new = quad_rows(grid2[:, ca], grid2[:, cb], built.use_b)
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
    V3_new = np.concatenate([Ve, new_e])

    # achieved lengths: the new edge's distance from the old opening, in 3D and per panel
    from ptailor.method.geodesic import geodesic_distance
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
    names = {p.index: p.name for p in state.panels}
    top_ids = len(Vb) + (rows - 1) * k + np.arange(k)
    surf = geodesic_distance(V3_new, base.F3, loop, limit=3.0 * by)[top_ids]
    if not np.all(surf < 3.0 * by):  # pushed far out by the body: measure all the way
        surf = geodesic_distance(V3_new, base.F3, loop)[top_ids]
    rec = {
        "op": "extend",
        "opening": name,
        "by": by,
        "rows": rows,
        "new_triangles": len(F3_new),
        "smoothing": built.smoothing,
        "achieved": {"3d": distance_stats(d3), "pattern": achieved_pattern},
        "measure": measure,
        "pattern_smoothing": built.pattern_smoothing,
        "amount": {
            "pattern": pattern_amounts(field, top2, np.arange(nc), col_panel, names),
            "drape": spread_stats(surf[np.isfinite(surf)]),
        },
    }
    return replace(
        state,
        base=base,
        V3=V3_new,
        panels=new_panels,
        even=even,
        log=(*state.log, rec),
        outline_free=free,
    )
