"""Distances measured in the pattern, for ``shorten`` and ``extend`` with ``measure: pattern``.

:class:`PatternDistance` is the distance, in each panel's own 2D pattern, from an opening's
pattern edges in that panel, carried across seams into panels the opening does not touch;
:func:`refine_crossings` places a split exactly on one of its iso-lines.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor import tolerances as tol
from ptailor.edits import tolerances as edit_tol
from ptailor.geometry.topology import half_edges
from ptailor.model.garment import Garment, Panel

#: Point-segment pairs evaluated at once by :func:`weighted_segment_distance`.
_PAIR_CHUNK = 1 << 21


def weighted_segment_distance(
    P: np.ndarray, A: np.ndarray, B: np.ndarray, wa: np.ndarray, wb: np.ndarray
) -> np.ndarray:
    """Distance from points to segments that carry a linear head start.

    Parameters
    ----------
    P : (p, 2) float array
    A, B : (s, 2) float arrays
        Segment ends.
    wa, wb : (s,) float arrays
        The value at ``A`` and at ``B``; in between it varies linearly (zero on a plain
        segment, the distance already travelled on a seam a front crosses).

    Returns
    -------
    (p,) float array
        ``min over segments, over X on the segment, of w(X) + |P - X|`` (exact: the
        function is convex along a segment), ``+inf`` when there are no segments.
    """
    out = np.full(len(P), np.inf)
    if len(P) == 0 or len(A) == 0:
        return out
    AB = B - A
    L = np.linalg.norm(AB, axis=1)
    e = AB / np.where(L > 0, L, 1.0)[:, None]
    # slope of the head start along the segment, kept inside (-1, 1): |g| >= 1 puts the
    # minimum at an end, which the clipped optimum below then reaches
    g = np.clip((wb - wa) / np.where(L > 0, L, 1.0), -1.0 + 1e-12, 1.0 - 1e-12)
    lean = g / np.sqrt(1.0 - g * g)
    step = max(1, _PAIR_CHUNK // len(A))
    for i in range(0, len(P), step):  # chunks of points, not single points
        AP = P[i : i + step, None, :] - A[None]
        tau0 = np.einsum("psd,sd->ps", AP, e)
        h = np.sqrt(np.maximum(np.einsum("psd,psd->ps", AP, AP) - tau0 * tau0, 0.0))
        tau = np.clip(tau0 - lean[None] * h, 0.0, L[None])
        val = wa[None] + g[None] * tau + np.sqrt((tau - tau0) ** 2 + h * h)
        out[i : i + step] = val.min(axis=1)
    return out


@dataclass(frozen=True)
class PatternDistance:
    """Distance in the pattern from an opening's edges, panel by panel.

    In a panel the opening runs along, the distance is the straight 2D distance from the
    opening's pattern edges in that panel: what a ruler on that pattern piece measures.
    A panel the opening does not run along but whose seams come within reach gets the
    distance carried over its seams: the seam's distance on the other side plus the 2D
    distance from the seam (segments with a linear head start, an upper bound of the exact
    front through the seam).

    Attributes
    ----------
    A, B : (s, 2) float arrays
        Source segments in the pattern.
    wa, wb : (s,) float arrays
        Head start at each end (zero on the opening's own edges).
    panel : (s,) int array
        Panel index each segment measures in.
    own : (s,) bool array
        True for the opening's own edges (zero head start).
    """

    A: np.ndarray
    B: np.ndarray
    wa: np.ndarray
    wb: np.ndarray
    panel: np.ndarray
    own: np.ndarray

    def at(self, P: np.ndarray, panel: np.ndarray, *, own_only: bool = False) -> np.ndarray:
        """Distance of points, each measured in its own panel.

        Parameters
        ----------
        P : (p, 2) float array
        panel : (p,) int array
        own_only : bool, keyword-only
            Only the opening's own edges (no distance carried over seams).

        Returns
        -------
        (p,) float array
            ``+inf`` in panels the distance does not reach.
        """
        out = np.full(len(P), np.inf)
        for q in np.unique(panel):  # a loop over panels
            sel = panel == q
            seg = (self.panel == q) & (self.own | (not own_only))
            out[sel] = weighted_segment_distance(
                P[sel], self.A[seg], self.B[seg], self.wa[seg], self.wb[seg]
            )
        return out


def edge_distance(
    V2: np.ndarray, a2: np.ndarray, b2: np.ndarray, edge_panel: np.ndarray
) -> PatternDistance:
    """The pattern distance from some edges, in their own panels only (nothing carried).

    Parameters
    ----------
    V2 : (n2, 2) float array
    a2, b2 : (k,) int arrays
        Edge ends.
    edge_panel : (k,) int array

    Returns
    -------
    PatternDistance
    """
    z = np.zeros(len(a2))
    return PatternDistance(
        A=V2[a2],
        B=V2[b2],
        wa=z,
        wb=z,
        panel=np.asarray(edge_panel, dtype=np.int64),
        own=np.ones(len(a2), bool),
    )


def outline_halfedges(F2: np.ndarray) -> np.ndarray:
    """Pattern half-edges without a twin (the panels' outlines), ``(b, 2)``."""
    h = half_edges(F2)
    n = int(F2.max(initial=0)) + 1
    fwd = h[:, 0].astype(np.int64) * n + h[:, 1]
    bwd = h[:, 1].astype(np.int64) * n + h[:, 0]
    return h[~np.isin(fwd, bwd)]


def opening_pattern_distance(
    g: Garment,
    plist: list[Panel],
    a2: np.ndarray,
    b2: np.ndarray,
    edge_panel: np.ndarray,
    *,
    reach: float,
) -> tuple[PatternDistance, np.ndarray]:
    """The pattern distance from an opening, and its value at every pattern vertex.

    Parameters
    ----------
    g : Garment
    plist : list of Panel
        ``panels(g)``.
    a2, b2 : (k,) int arrays
        The opening's pattern edges.
    edge_panel : (k,) int array
        Panel of each edge.
    reach : float, keyword-only
        The distance is carried over a seam into a further panel only where the seam is
        nearer than this.

    Returns
    -------
    field : PatternDistance
    d : (n2,) float array
        ``field`` at the pattern vertices near the opening (all those nearer than
        ``reach``, and some farther), ``+inf`` at the others.
    """
    V2, n2 = g.V2, len(g.V2)
    vlab = np.full(n2, -1, dtype=np.int64)
    for p in plist:  # a loop over panels
        vlab[p.vertices] = p.index
    v3of2 = np.zeros(n2, dtype=np.int64)
    v3of2[g.F2.ravel()] = g.F3.ravel()
    A, B = [V2[a2]], [V2[b2]]
    wa, wb = [np.zeros(len(a2))], [np.zeros(len(a2))]
    seg_panel, own = [np.asarray(edge_panel, dtype=np.int64)], [np.ones(len(a2), bool)]
    d = np.full(n2, np.inf)
    done = np.zeros(len(plist), bool)
    wave = np.unique(edge_panel)
    bnd = None
    while wave.size:  # waves of panels, each reached over the seams of the ones before
        field = PatternDistance(
            A=np.concatenate(A),
            B=np.concatenate(B),
            wa=np.concatenate(wa),
            wb=np.concatenate(wb),
            panel=np.concatenate(seg_panel),
            own=np.concatenate(own),
        )
        sel = _near_sources(field, V2, vlab, wave, reach=reach)
        d[sel] = field.at(V2[sel], vlab[sel])
        done[wave] = True
        carried = _carried(d, v3of2, len(g.V3))
        near = (carried < reach) & ~done[np.maximum(vlab, 0)] & (vlab >= 0)
        wave = np.unique(vlab[near])
        if not wave.size:
            break
        if bnd is None:
            bnd = outline_halfedges(g.F2)
        ends = _seam_sources(bnd, vlab, wave, carried)
        A.append(V2[ends[:, 0]])
        B.append(V2[ends[:, 1]])
        wa.append(carried[ends[:, 0]])
        wb.append(carried[ends[:, 1]])
        seg_panel.append(vlab[ends[:, 0]])
        own.append(np.zeros(len(ends), bool))
    return field, d


def _near_sources(
    field: PatternDistance, V2: np.ndarray, vlab: np.ndarray, wave: np.ndarray, *, reach: float
) -> np.ndarray:
    """The pattern vertices of the panels ``wave`` that may lie within ``reach`` of the
    field's sources in those panels: near a source segment's midpoint (a k-d tree query).

    Parameters
    ----------
    field : PatternDistance
    V2 : (n2, 2) float array
    vlab : (n2,) int array
        Panel of each pattern vertex (-1: none).
    wave : (w,) int array
        Panels.
    reach : float, keyword-only

    Returns
    -------
    (s,) int array
        The vertices, ascending.
    """
    from scipy.spatial import cKDTree  # imported when needed (costly)

    sel = np.flatnonzero(np.isin(vlab, wave))
    src = np.isin(field.panel, wave)
    mid = 0.5 * (field.A[src] + field.B[src])
    half = 0.5 * float(np.linalg.norm(field.B[src] - field.A[src], axis=1).max(initial=0.0))
    dq, _ = cKDTree(mid).query(V2[sel], distance_upper_bound=1.5 * reach + 4.0 * half)
    return sel[np.isfinite(dq)]


def _carried(d: np.ndarray, v3of2: np.ndarray, n3: int) -> np.ndarray:
    """The distance ``(n2,)`` each pattern vertex's drape vertex has reached so far, the
    least over its pattern copies (``d`` ``(n2,)``; ``v3of2`` ``(n2,)`` their drape
    vertices, of ``n3``)."""
    d3 = np.full(n3, np.inf)
    fin = np.isfinite(d)
    np.minimum.at(d3, v3of2[fin], d[fin])
    return d3[v3of2]


def _seam_sources(
    bnd: np.ndarray, vlab: np.ndarray, wave: np.ndarray, carried: np.ndarray
) -> np.ndarray:
    """The seam sources of the next wave of panels: outline edges with both ends reached
    (segments) and reached outline vertices on no such edge (points, as ``[v, v]``).

    Parameters
    ----------
    bnd : (b, 2) int array
        Outline half-edges (:func:`outline_halfedges`).
    vlab : (n2,) int array
    wave : (w,) int array
        The next wave's panels.
    carried : (n2,) float array
        :func:`_carried`.

    Returns
    -------
    (s, 2) int array
        Pattern vertices at the start and end of each source.
    """
    on = np.isin(vlab[bnd[:, 0]], wave) & np.isfinite(carried[bnd]).all(1)
    seg = bnd[on]
    pts = np.flatnonzero(np.isin(vlab, wave) & np.isfinite(carried))
    pts = pts[~np.isin(pts, seg)]
    return np.concatenate([seg, np.stack([pts, pts], 1)])


def refine_crossings(
    field: PatternDistance,
    V2: np.ndarray,
    a2: np.ndarray,
    b2: np.ndarray,
    t: np.ndarray,
    panel: np.ndarray,
    level: float,
) -> np.ndarray:
    """Where pattern edges cross an iso-line of a pattern distance.

    Regula falsi with the Illinois modification on each edge whose ends the iso-line
    separates, vectorised over the edges, until the value is within ``1e-12 level`` (or
    the bracket within ``1e-13`` of the edge).

    Parameters
    ----------
    field : PatternDistance
    V2 : (n2, 2) float array
    a2, b2 : (r,) int arrays
        Edge ends.
    t : (r,) float array
        A first estimate (from ``a2``), kept where the field does not change sign along
        the edge (a seam vertex whose sides disagree).
    panel : (r,) int array
        The panel each edge measures in.
    level : float
        The iso-value.

    Returns
    -------
    (r,) float array
    """
    A, B = V2[a2], V2[b2]
    fa = field.at(A, panel) - level
    fb = field.at(B, panel) - level
    ok = (fa * fb < 0) & np.isfinite(fa) & np.isfinite(fb)
    out = t.copy()
    if not ok.any():
        return out
    A, B, pan = A[ok], B[ok], panel[ok]
    lo, hi = np.zeros(len(A)), np.ones(len(A))
    flo, fhi = fa[ok], fb[ok]
    x = np.clip(t[ok], 0.0, 1.0)
    side = np.zeros(len(A), dtype=np.int8)  # which end was kept last (-1 lo, +1 hi)
    todo = np.arange(len(A))
    tol_f = edit_tol.PATTERN_LEVEL_TOL_REL * max(level, tol.TINY)
    for _ in range(edit_tol.PATTERN_REFINE_STEPS):  # iterations, vectorised over the open edges
        if not todo.size:
            break
        i = todo
        fx = field.at(A[i] + x[i, None] * (B[i] - A[i]), pan[i]) - level
        done = (np.abs(fx) <= tol_f) | (hi[i] - lo[i] <= edit_tol.PATTERN_BRACKET_MIN)
        left = fx * flo[i] > 0  # the root lies in (x, hi)
        # Illinois: halve the value of an end kept twice in a row
        fhi[i] = np.where(left & (side[i] == 1), 0.5 * fhi[i], fhi[i])
        flo[i] = np.where(~left & (side[i] == -1), 0.5 * flo[i], flo[i])
        lo[i], flo[i] = np.where(left, x[i], lo[i]), np.where(left, fx, flo[i])
        hi[i], fhi[i] = np.where(left, hi[i], x[i]), np.where(left, fhi[i], fx)
        side[i] = np.where(left, 1, -1)
        nxt = (lo[i] * fhi[i] - hi[i] * flo[i]) / (fhi[i] - flo[i])
        bad = ~np.isfinite(nxt) | (nxt <= lo[i]) | (nxt >= hi[i])
        x[i] = np.where(done, x[i], np.where(bad, 0.5 * (lo[i] + hi[i]), nxt))
        todo = i[~done]
    out[ok] = x
    return out
