"""Seam-allowance cut lines: a closed outline offset outward, always a simple polygon.

The offset is made by GEOS (through shapely), never by moving each point along its mitre:
that hand offset crossed itself where a concave stretch of short edges lies closer than
the allowance to itself (the diffavatar tshirt's back at 2.5 cm grew an 18 mm2 loop behind
its armhole). One allowance for the whole outline is GEOS's mitre buffer of the piece. An
allowance per edge (a hem 3 cm, the seams 1 cm) is the union, by GEOS, of the piece and one
strip per edge, the edge moved out by its own allowance, with a mitre wedge at each convex
corner (where the two offset lines meet, clipped at the mitre limit; a step where two
different allowances meet on nearly straight edges). Every part of that union lies within
its edge's allowance (the mitre limit's reach at corners) and touches the piece, so its
outer boundary is one simple closed line, whatever the outline's shape.

Examples
--------
>>> P = np.array([[0.0, 0], [4, 0], [4, 2], [0, 2]])
>>> offset_closed(P, 1.0).tolist()
[[-1.0, -1.0], [5.0, -1.0], [5.0, 3.0], [-1.0, 3.0]]
>>> offset_closed(P, np.array([3.0, 1, 1, 1])).tolist()  # the bottom edge: 3
[[-1.0, 3.0], [-1.0, -3.0], [5.0, -3.0], [5.0, 3.0]]
"""

from __future__ import annotations

import numpy as np
import shapely

from ptailor import tolerances as tol
from ptailor.model import tolerances as model_tol
from ptailor.model.polyline import dedupe_closed, signed_area


def offset_closed(
    P: np.ndarray, d: float | np.ndarray, *, miter_limit: float = tol.MITER_LIMIT
) -> np.ndarray:
    """The closed outline ``P`` offset outward by ``d`` (a seam allowance), corners mitred.

    Parameters
    ----------
    P : (k, 2) float array
        A closed outline, either orientation, first point not repeated; it may touch or
        cross itself (its area is taken as GEOS makes it valid).
    d : float or (k,) float array
        The allowance, ``>= 0``: one for the whole outline, or one per edge (edge ``i``
        runs from ``P[i]`` to ``P[i + 1]``; 0 leaves the edge as it is: a fold).
    miter_limit : float
        A corner's mitre reaches at most this many allowances (the larger of its two
        edges') from the corner; GEOS clips it there.

    Returns
    -------
    (j, 2) float array
        The cut line, a simple closed polyline in ``P``'s orientation from its point
        nearest ``P[0]`` (first point not repeated); points closer than
        ``OFFSET_SIMPLIFY_REL`` of the diagonal to the line through their neighbours are
        dropped.
    """
    P = np.asarray(P, dtype=np.float64)
    k0 = len(P)
    keep = dedupe_closed(P)
    P = P[keep]
    dd = np.broadcast_to(np.asarray(d, dtype=np.float64), (k0,))
    # the edge leaving kept point m ends at the next kept point: the last of the original
    # edges between them (the others have no length)
    dd = dd[(np.roll(keep, -1) - 1) % k0]
    if len(P) < 3 or not dd.any():
        return P.copy()
    base = shapely.Polygon(P)
    if not base.is_valid:
        base = shapely.make_valid(base)
    if np.all(dd == dd[0]):
        grown = base.buffer(float(dd[0]), join_style="mitre", mitre_limit=miter_limit)
    else:
        # on a grid (GEOS's fixed-precision overlay, a power of ten near OFFSET_GRID_REL of
        # the diagonal): in floating point, the union of a piece's many thin strips lost
        # one's area (measured: a 16x longsleeve front, its cut line down on the sew line)
        diag = float(np.hypot(*np.ptp(P, axis=0)))
        grid = 10.0 ** np.floor(np.log10(model_tol.OFFSET_GRID_REL * diag))
        parts = np.concatenate([[base], edge_strips(P, dd, miter_limit)])
        grown = shapely.union_all(parts, grid_size=grid)
    return _outer_line(grown, ccw=signed_area(P) > 0, start=P[0])


def edge_strips(P: np.ndarray, d: np.ndarray, miter_limit: float) -> np.ndarray:
    """The strips and corner wedges whose union with the piece is its per-edge offset.

    Parameters
    ----------
    P : (k, 2) float array
        A closed outline, no two consecutive points equal.
    d : (k,) float array
        Per edge allowance (edge ``i``: ``P[i] -> P[i + 1]``), ``>= 0``.
    miter_limit : float

    Returns
    -------
    (s,) array of shapely Polygons
        One rectangle per edge with an allowance (the edge and the edge moved out by it),
        one wedge per convex or straight corner between two such strips.
    """
    A, B = P, np.roll(P, -1, axis=0)
    t = (B - A) / np.linalg.norm(B - A, axis=1)[:, None]
    sign = 1.0 if signed_area(P) > 0 else -1.0  # outward: the edge turned clockwise (CCW)
    n = sign * np.stack([t[:, 1], -t[:, 0]], axis=1)
    rect = np.stack([A, B, B + d[:, None] * n, A + d[:, None] * n], axis=1)
    rects = shapely.polygons(rect[d > 0])
    # the corner at P[i], between edge i - 1 (in) and edge i (out)
    t_in, n_in, d_in = np.roll(t, 1, axis=0), np.roll(n, 1, axis=0), np.roll(d, 1)
    wedge = _wedges(P, t_in, n_in, d_in, t, n, d, miter_limit)
    # every convex corner gets its wedge, however thin, and the wedge reaches half way back
    # along both edges (inside their strips and the piece): its strips overlap it over an
    # area, never touch it along a line only, so the sliver between two strips of a nearly
    # straight stretch (one allowance stepping to another) leaves no slit in the union
    step = 0.5 * np.linalg.norm(B - A, axis=1)
    back = np.minimum(np.roll(step, 1), step)[:, None]
    wedge = np.concatenate([(P - back * t_in)[:, None], wedge[:, 1:], (P + back * t)[:, None]], 1)
    turn = sign * (t_in[:, 0] * t[:, 1] - t_in[:, 1] * t[:, 0])  # > 0: convex
    use = (turn > -model_tol.MITER_PARALLEL) & (np.maximum(d_in, d) > 0)  # convex or straight
    return np.concatenate([rects, shapely.make_valid(shapely.polygons(wedge[use]))])


def _wedges(C, t_in, n_in, d_in, t_out, n_out, d_out, miter_limit) -> np.ndarray:
    """Per corner ``C`` ``(k, 2)``, the wedge ``(k, 5, 2)`` filling it outside the two
    strips: the corner, the incoming strip's outer end, the mitre (two points: clipped at
    ``miter_limit`` times the larger allowance, else both the mitre point), the outgoing
    strip's outer start. Where the offset lines meet behind either strip's end (nearly
    straight edges, two allowances), the wedge is the triangle between the strips' ends."""
    a = C + d_in[:, None] * n_in
    b = C + d_out[:, None] * n_out
    # M - C solves (M - C) . n_in = d_in, (M - C) . n_out = d_out
    det = n_in[:, 0] * n_out[:, 1] - n_in[:, 1] * n_out[:, 0]
    ok = np.abs(det) > model_tol.MITER_PARALLEL
    safe = np.where(ok, det, 1.0)
    mx = (d_in * n_out[:, 1] - d_out * n_in[:, 1]) / safe
    my = (n_in[:, 0] * d_out - n_out[:, 0] * d_in) / safe
    m = C + np.stack([mx, my], axis=1)
    ok &= (((m - a) * t_in).sum(axis=1) >= 0) & (((m - b) * t_out).sum(axis=1) <= 0)
    reach = np.linalg.norm(m - C, axis=1)
    h = miter_limit * np.maximum(d_in, d_out)
    u = (m - C) / np.maximum(reach, tol.TINY)[:, None]
    # the clip line (X - C) . u = h meets the incoming offset line at pa, the outgoing at pb
    sa = (h - ((a - C) * u).sum(axis=1)) / np.maximum((t_in * u).sum(axis=1), tol.TINY)
    sb = (h - ((b - C) * u).sum(axis=1)) / np.maximum(-(t_out * u).sum(axis=1), tol.TINY)
    clip = (reach > h)[:, None]
    pa = np.where(clip, a + sa[:, None] * t_in, m)
    pb = np.where(clip, b - sb[:, None] * t_out, m)
    pa = np.where(ok[:, None], pa, a)
    pb = np.where(ok[:, None], pb, b)
    return np.stack([C, a, pa, pb, b], axis=1)


def _outer_line(grown, *, ccw: bool, start: np.ndarray) -> np.ndarray:
    """The outer boundary ``(j, 2)`` of GEOS's result (its largest polygon), oriented
    counter-clockwise when ``ccw``, from its point nearest ``start``, near-collinear points
    dropped (topology kept)."""
    polys = [g for g in shapely.get_parts(grown) if isinstance(g, shapely.Polygon)]
    shell = shapely.Polygon(max(polys, key=lambda g: g.area).exterior)
    x0, y0, x1, y1 = shell.bounds
    eps = model_tol.OFFSET_SIMPLIFY_REL * float(np.hypot(x1 - x0, y1 - y0))
    shell = shapely.simplify(shell, eps, preserve_topology=True)
    Q = np.asarray(shell.exterior.coords, dtype=np.float64)[:-1]
    if (signed_area(Q) > 0) != ccw:
        Q = Q[::-1]
    return np.roll(Q, -int(np.argmin(np.linalg.norm(Q - start, axis=1))), axis=0)
