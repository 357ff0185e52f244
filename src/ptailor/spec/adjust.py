"""Carrying a pattern specification through an adjustment: the adjusted specification.

Every point of a specification panel (its vertices, and samples along each edge curve) is
located in its mesh panel's triangles and carried to the adjusted pattern at the same
barycentric coordinates. The carried panel is put back in the panel's own frame by undoing
the rotation and translation of the similarity that best fits its outline before onto
after; its scale stays, about the frame's origin. So an identity recipe gives every vertex
back, a uniform scale by ``k`` multiplies every vertex by ``k``, and an edit that moves only
the hem moves only the hem. Each curved edge's parameters are refitted to its carried
samples by least squares in the edge's own frame; a straight edge whose carried samples
leave the chord by more than :data:`~ptailor.tolerances.SPEC_BEND_CM` gets a curve.

A panel whose triangles changed (shorten, extend, cut) is read off the adjusted mesh
instead: each vertex of its outline is labelled with the input edge it lies on (or as new),
runs of one label become edges, and a run of new outline replaces the input edges that
left the outline (the hem a shorten moved keeps its id); stitches follow their edges.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ptailor import tolerances as tol
from ptailor.geometry.curves import chord_deviation, curve_points, fit_curve
from ptailor.geometry.triangles import signed_areas_2d
from ptailor.method.transfer import carry_points, locate_points
from ptailor.model.garment import Panel
from ptailor.model.polyline import signed_area
from ptailor.model.specification import SpecEdge, Specification, SpecPanel, Stitch
from ptailor.model.units import CM_PER
from ptailor.pieces.draw import outer_loop
from ptailor.spec.match import PanelMatch, SpecMatching

__all__ = ["AdjustedSpec", "PanelChange", "adjusted_specification"]

#: samples per edge carried to refit its curve
SAMPLES = 32
#: rounds of geometric refitting of a Bezier edge (:func:`ptailor.geometry.curves.fit_curve`)
REPARAMETRIZE = 8
#: a new outline run turns by more than this (degrees) at a corner: it is split there
CORNER_DEG = 35.0


@dataclass(frozen=True)
class PanelChange:
    """What the adjustment did to one specification panel.

    Attributes
    ----------
    name : str
    source : str
        The input panel it came from.
    how : str
        ``carried`` (same triangles: every point carried) or ``outline`` (its triangles
        changed: edges read off the adjusted mesh outline).
    edge_sources : tuple of int
        Per edge, the input edge it came from (``-1``: a new edge).
    bent : tuple of (int, float)
        Straight edges that got a curve, with their points' largest distance from the chord
        (specification units).
    refit : tuple of float
        Per edge, the largest distance of its carried points from the refitted curve
        (specification units).
    removed : tuple of int
        Input edges that left the outline.
    to_pattern : (A (2, 2), b (2,))
        Affine map from the new panel's frame to the adjusted pattern (computation units):
        ``Y = X @ A.T + b``.
    """

    name: str
    source: str
    how: str
    edge_sources: tuple[int, ...]
    bent: tuple[tuple[int, float], ...]
    refit: tuple[float, ...]
    removed: tuple[int, ...] = ()
    to_pattern: tuple = field(default=(), repr=False)
    panel: int = -1  # index into the adjusted garment's panels


@dataclass(frozen=True)
class AdjustedSpec:
    """The adjusted specification and what happened to it.

    Attributes
    ----------
    spec : Specification
    changes : tuple of PanelChange
        One per panel of ``spec``.
    stitch_sources : tuple of int
        Per stitch of ``spec``, the input stitch it is.
    dropped_stitches : tuple of int
        Input stitches whose edge left the pattern.
    removed_panels : tuple of str
        Input panels the adjustment removed whole.
    """

    spec: Specification
    changes: tuple[PanelChange, ...]
    stitch_sources: tuple[int, ...] = ()
    dropped_stitches: tuple[int, ...] = ()
    removed_panels: tuple[str, ...] = ()


#: rounds of the robust similarity fit (iteratively reweighted least squares)
IRLS_ROUNDS = 12


def _similarity(
    X: np.ndarray, W: np.ndarray, *, scale: float
) -> tuple[np.ndarray, np.ndarray, float]:
    """The similarity ``W ~ s X @ Q.T + b`` (rotation ``Q``, no reflection) fitted to the
    closed outline ``X -> W`` where it fits: least squares weighted by each point's share of
    the outline's length (so a finer mesh weighs the same), then :data:`IRLS_ROUNDS`
    reweightings by ``1 / (1 + (r / scale)^2)`` (Cauchy): the part of a panel an edit left
    alone holds it in place, however much the rest moved."""
    seg = np.linalg.norm(np.roll(X, -1, axis=0) - X, axis=1)
    length = 0.5 * (seg + np.roll(seg, 1))
    w = length / max(float(length.sum()), 1e-300)
    wk = w
    for _ in range(IRLS_ROUNDS + 1):
        cx, cw = wk @ X / wk.sum(), wk @ W / wk.sum()
        a, c = X - cx, W - cw
        H = (a * wk[:, None]).T @ c
        U, _, Vt = np.linalg.svd(H)
        D = np.diag([1.0, np.sign(np.linalg.det(Vt.T @ U.T)) or 1.0])
        Q = Vt.T @ D @ U.T
        s = float(np.sum(wk[:, None] * c * (a @ Q.T)) / max(float(wk @ (a * a).sum(1)), 1e-300))
        b = cw - s * (Q @ cx)
        r = np.linalg.norm(W - (s * X @ Q.T + b), axis=1)
        wk = w / (1.0 + (r / scale) ** 2)
    return Q, b, s


@dataclass(frozen=True)
class _Frame:
    """Pattern <-> new panel frame for one panel: ``Z = Q.T (to_spec(Y) - b)``."""

    m: PanelMatch
    k: float
    Q: np.ndarray
    b: np.ndarray

    def to_frame(self, Y: np.ndarray) -> np.ndarray:
        return (self.m.to_spec(Y, self.k) - self.b) @ self.Q

    def to_pattern(self, Z: np.ndarray) -> np.ndarray:
        return self.m.to_pattern(Z @ self.Q.T + self.b, self.k)

    def affine(self) -> tuple[np.ndarray, np.ndarray]:
        A = self.k * self.m.R @ self.Q
        b = self.m.to_pattern(self.b[None], self.k)[0]
        return A, b


def _frame_of(m: PanelMatch, k: float, Y0: np.ndarray, Y1: np.ndarray, *, scale: float) -> _Frame:
    """The frame that undoes the rotation and translation of the similarity taking the
    outline ``Y0`` (pattern before, computation units) onto ``Y1`` (after)."""
    X, W = m.to_spec(Y0, k), m.to_spec(Y1, k)
    Q, b, _ = _similarity(X, W, scale=scale)
    return _Frame(m, k, Q, b)


def _fit_edge(
    P0: np.ndarray, P1: np.ndarray, kind: str, t: np.ndarray, Z: np.ndarray, *, start=None
) -> tuple[str, np.ndarray, float, float]:
    """``(kind, params, refit error, chord deviation)`` of the edge of ``kind`` through
    points ``Z`` at parameters ``t`` (``start``: the input's parameters, an arc's first
    guess); the refit error is the points' largest distance from the fitted curve."""
    dev = chord_deviation(P0, P1, Z)
    if kind == "straight":
        return "straight", np.zeros(0), dev, dev
    params = fit_curve(P0, P1, kind, t, Z, start=start, reparametrize=REPARAMETRIZE)
    curve = curve_points(P0, P1, kind, params, np.linspace(0.0, 1.0, 513))
    err = float(np.max(_polyline_distance(Z, curve))) if len(Z) else 0.0
    return kind, params, err, dev


def _polyline_distance(X: np.ndarray, P: np.ndarray) -> np.ndarray:
    """Distance from points ``X`` to the open polyline ``P``."""
    from ptailor.geometry.segments import segment_feet

    d, _ = segment_feet(X[:, None, :], P[None, :-1], P[None, 1:])
    return d.min(axis=1)


def _straight_or_bent(P0, P1, Z, t, bend: float) -> tuple[str, np.ndarray, float, float]:
    """A straight edge through carried points ``Z``: a quadratic when they bend."""
    dev = chord_deviation(P0, P1, Z)
    if dev <= bend or len(Z) < 3:
        return "straight", np.zeros(0), dev, dev
    kind, params, err, _ = _fit_edge(P0, P1, "quadratic", t, Z)
    return kind, params, err, dev


def _carried_panel(
    sp: SpecPanel, m: PanelMatch, k: float, adj, part: Panel, bend: float
) -> tuple[SpecPanel, PanelChange]:
    """A panel with the same triangles: every point carried."""
    base = adj.state.base
    Vb, Fb, Vn = base.V2, base.F2, adj.result.V2
    L = outer_loop(Fb, part.faces, Vb)
    frame = _frame_of(m, k, Vb[L], Vn[L], scale=bend)
    t = np.linspace(0.0, 1.0, SAMPLES + 1)[1:-1]
    pts = [m.to_pattern(sp.vertices, k)]
    pts += [m.to_pattern(sp.edge_points(i, t), k) for i in range(len(sp.edges))]
    Y = np.vstack(pts)
    loc = locate_points(Vb, Fb, Y, faces=part.faces)
    Z = frame.to_frame(carry_points(Vn, Fb, loc))
    nv = len(sp.vertices)
    V = Z[:nv]
    edges, bent, refit = [], [], []
    for i, e in enumerate(sp.edges):  # a loop over a panel's edges
        a, b = e.endpoints
        Ze = Z[nv + i * len(t) : nv + (i + 1) * len(t)]
        if e.kind == "straight":
            kind, params, err, dev = _straight_or_bent(V[a], V[b], Ze, t, bend)
            if kind != "straight":
                bent.append((i, dev))
        else:
            kind, params, err, _ = _fit_edge(V[a], V[b], e.kind, t, Ze, start=e.params)
        edges.append(replace(e, kind=kind, params=params))
        refit.append(err)
    new = replace(sp, vertices=V, edges=tuple(edges))
    change = PanelChange(
        name=sp.name,
        source=sp.name,
        how="carried",
        edge_sources=tuple(range(len(edges))),
        bent=tuple(bent),
        refit=tuple(refit),
        to_pattern=frame.affine(),
        panel=part.index,
    )
    return new, change


def _labels(sp: SpecPanel, X: np.ndarray, reach: float) -> tuple[np.ndarray, np.ndarray]:
    """Per point ``X`` (panel frame) the edge it lies on within ``reach`` (-1: none) and
    its parameter there."""
    from scipy.spatial import cKDTree

    n = 512
    P, edge, t = sp.outline(n)
    d, idx = cKDTree(P).query(X)
    lab = np.where(d <= reach, edge[idx], -1)
    tt = t[idx]
    # the sample at t = 0 of the next edge is t = 1 of this one: nearest ends stay on
    return lab, tt


def _runs(lab: np.ndarray) -> list[tuple[int, np.ndarray]]:
    """Cyclic runs of equal labels ``(label, positions)``, starting at a label change."""
    n = len(lab)
    change = np.flatnonzero(lab != np.roll(lab, 1))
    if len(change) == 0:
        return [(int(lab[0]), np.arange(n))]
    start = change[0]
    order = (np.arange(n) + start) % n
    lab_r = lab[order]
    cuts = np.flatnonzero(np.diff(lab_r)) + 1
    return [(int(g[0]), order[s]) for g, s in
            zip(np.split(lab_r, cuts), np.split(np.arange(n), cuts), strict=True)]  # fmt: skip


def _corners(Z: np.ndarray, window: float) -> np.ndarray:
    """Interior positions of an open polyline ``Z`` that are corners: where the chords
    ``window`` long before and after a vertex turn by more than :data:`CORNER_DEG`, the
    sharpest vertex of each such stretch (a cut line's zigzag through the triangles is no
    corner; pieces shorter than ``window`` are not split off)."""
    if len(Z) < 3:
        return np.zeros(0, dtype=np.int64)
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(Z, axis=0), axis=1))])
    inner = np.arange(1, len(Z) - 1)
    ok = (s[inner] >= window) & (s[inner] <= s[-1] - window)
    if not ok.any():
        return np.zeros(0, dtype=np.int64)
    inner = inner[ok]

    def at(x):
        return np.stack([np.interp(x, s, Z[:, 0]), np.interp(x, s, Z[:, 1])], axis=1)

    a = Z[inner] - at(s[inner] - window)
    b = at(s[inner] + window) - Z[inner]
    turn = np.degrees(np.abs(np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], (a * b).sum(1))))
    sharp = turn > CORNER_DEG
    out = []
    for grp in np.split(np.arange(len(inner)), np.flatnonzero(np.diff(sharp.astype(int))) + 1):
        if len(grp) and sharp[grp[0]]:  # one corner per stretch: its sharpest vertex
            out.append(int(inner[grp[np.argmax(turn[grp])]]))
    return np.array(out, dtype=np.int64)


def _turns(Zl: np.ndarray, a: np.ndarray, b: np.ndarray, window: float) -> bool:
    """Whether the outline turns a corner where run ``a`` (loop positions) meets the run
    ``b`` after it: a corner within half a window of the junction's ends."""
    P = np.vstack([Zl[a], Zl[b]])
    c = _corners(P, window)
    if not len(c):
        return False
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(P, axis=0), axis=1))])
    j = len(a)  # the junction: the outline's edge from a's last vertex to b's first
    near = np.minimum(np.abs(s[c] - s[j - 1]), np.abs(s[c] - s[j]))
    return bool(np.any(near <= 0.5 * window))


def _run_of(runs, r, pos):
    """The loop positions of the run after the run ``(r, pos)``."""
    i = next(k for k, (rr, pp) in enumerate(runs) if rr == r and pp is pos)
    return runs[(i + 1) % len(runs)][1]


def _cleaned(lab: np.ndarray, Zl: np.ndarray, window: float) -> np.ndarray:
    """Labels with runs of an input edge shorter than ``window`` next to new outline made
    new (a corner of the new outline that touches an old edge is no part of that edge)."""
    lab = lab.copy()
    runs = _runs(lab)
    for i, (r, pos) in enumerate(runs):  # a loop over the outline's runs
        nb = (runs[i - 1][0], runs[(i + 1) % len(runs)][0])
        short = len(pos) <= 2 or np.linalg.norm(np.diff(Zl[pos], axis=0), axis=1).sum() < window
        if r >= 0 and short and -1 in nb and len(runs) > 2:
            lab[pos] = -1
    return lab


def _outline_panel(
    sp: SpecPanel, m: PanelMatch, k: float, adj, part: Panel, bend: float, units: str
) -> tuple[SpecPanel, PanelChange]:
    """A panel whose triangles changed: edges read off its adjusted outline."""
    base = adj.state.base
    Vb, Fb, Vn = base.V2, base.F2, adj.result.V2
    L = outer_loop(Fb, part.faces, Vb)
    X = m.to_spec(Vb[L], k)
    if np.sign(signed_area(X)) != np.sign(signed_area(sp.outline(16)[0])):
        L, X = L[::-1], X[::-1]  # the loop runs the way the specification's edges do
    frame = _frame_of(m, k, Vb[L], Vn[L], scale=bend)
    Zl = frame.to_frame(Vn[L])
    reach = (max(3.0 * m.distance, 0.05 / CM_PER[units]) + 1e-9) / k
    window = 1.0 / CM_PER[units] / k  # 1 cm: what a corner of the new outline is seen over
    lab = _cleaned(_labels(sp, X, reach)[0], Zl, window)
    segs = _segments(lab, Zl, len(sp.edges), window)
    # an input vertex still in the panel: where its two edges meet, carried
    loc_v = locate_points(Vb, Fb, m.to_pattern(sp.vertices, k), faces=part.faces)
    # (a corner off the mesh by the input's own fit is still there)
    kept_v = loc_v.distance <= 3.0 * m.distance + 1e-6 * max(float(np.ptp(Vb[L])), 1e-300)
    Zv = frame.to_frame(carry_points(Vn, Fb, loc_v))
    P, O = _junctions(sp, segs, X, Zl, Zv, kept_v)
    sources: list[int] = []
    for src, _, _ in segs:  # an edge split in two (a cut through it): its second part is new
        sources.append(src if src < 0 or src not in sources else -1)
    kept_ids = [s for s in sources if s >= 0]
    if kept_ids:  # start the loop at the lowest input edge (a replaced edge keeps its place)
        r = sources.index(min(kept_ids))
        segs, sources = segs[r:] + segs[:r], sources[r:] + sources[:r]
        P, O = np.roll(P, -r, axis=0), np.roll(O, -r, axis=0)
    idx = _vertex_indices(sp, sources)
    V = np.zeros((int(idx.max()) + 1, 2))
    V[idx] = P

    def carried(e: int, ta: float, tb: float, t: np.ndarray) -> np.ndarray:
        Yo = m.to_pattern(sp.edge_points(e, ta + t * (tb - ta)), k)
        return frame.to_frame(carry_points(Vn, Fb, locate_points(Vb, Fb, Yo, faces=part.faces)))

    edges, bent, refit = _segment_edges(sp, segs, sources, P, O, Zl, idx, carried, bend)
    removed = sorted(set(range(len(sp.edges))) - {s for s in sources if s >= 0})
    new = replace(sp, vertices=V, edges=tuple(edges))
    change = PanelChange(
        name=sp.name,
        source=sp.name,
        how="outline",
        edge_sources=tuple(int(x) for x in sources),
        bent=tuple(bent),
        refit=tuple(refit),
        removed=tuple(int(r) for r in removed),
        to_pattern=frame.affine(),
        panel=part.index,
    )
    return new, change


def _segments(lab: np.ndarray, Zl: np.ndarray, n_e: int, window: float) -> list[list]:
    """The outline's segments ``[source edge or -1, loop positions, how]`` in loop order,
    from the first run of the lowest surviving edge; ``how`` is ``kept`` (part of an input
    edge), ``extended`` (an input edge the new outline goes on from) or ``new``. A run of
    new outline is split at its corners; pieces that go on straight from the edge before
    or after extend it; the rest replace, in order, the input edges between its two
    neighbours that left the outline (the hem a shorten moved keeps its id), or are new."""
    runs = _runs(lab)
    present = {r for r, _ in runs if r >= 0}
    if present:
        i0 = next(i for i, (r, _) in enumerate(runs) if r == min(present))
        runs = runs[i0:] + runs[:i0]
    segs: list[list] = []
    for r, pos in runs:  # a loop over the outline's runs
        if r >= 0:
            segs.append([r, pos, "kept"])
            continue
        prev_r = segs[-1][0] if segs else runs[-1][0]
        after = _run_of(runs, r, pos) if len(runs) > 1 else None
        nxt = int(lab[after[0]]) if after is not None else -1
        gone = _between(prev_r, nxt, n_e, present)
        ext = np.concatenate([pos[:1] - 1, pos, pos[-1:] + 1]) % len(lab)
        cut = _corners(Zl[ext], window) - 1
        cut = cut[(cut > 0) & (cut < len(pos))]
        mids, tail = (np.split(pos, cut) if len(cut) else [pos]), None
        if prev_r >= 0 and segs and not _turns(Zl, segs[-1][1], mids[0], window):
            segs[-1][1] = np.concatenate([segs[-1][1], mids.pop(0)])  # it goes on: extended
            segs[-1][2] = "extended"
        if mids and nxt >= 0 and after is not None and not _turns(Zl, mids[-1], after, window):
            tail = mids.pop()
        for j, pc in enumerate(mids):  # the pieces of a new outline run
            segs.append([gone[j] if j < len(gone) else -1, pc, "new"])
        if tail is not None:
            segs.append([nxt, tail, "lead"])
    return _merged_leads(segs)


def _merged_leads(segs: list[list]) -> list[list]:
    """A piece leading straight into the run of its edge joins that run (``extended``)."""
    merged: list[list] = []
    for s in segs:  # a loop over segments
        if merged and s[2] != "new" and merged[-1][2] == "lead" and merged[-1][0] == s[0]:
            merged[-1] = [s[0], np.concatenate([merged[-1][1], s[1]]), "extended"]
        else:
            merged.append(s)
    if len(merged) > 1 and merged[-1][2] == "lead" and merged[0][0] == merged[-1][0]:
        last = merged.pop()  # the run it leads into is the first one
        merged[0] = [last[0], np.concatenate([last[1], merged[0][1]]), "extended"]
    return [[s[0], s[1], "extended" if s[2] == "lead" else s[2]] for s in merged]


def _junctions(
    sp: SpecPanel,
    segs: list[list],
    X: np.ndarray,
    Zl: np.ndarray,
    Zv: np.ndarray,
    kept_v: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Each segment's start, in the new frame (``P``) and in the input frame (``O``): the
    input vertex where two consecutive input edges still meet (carried), else the last
    vertex of a kept edge that new outline follows (the cut's crossing), else the
    segment's first (a corner of the new outline)."""
    n_e = len(sp.edges)
    P, O = [], []
    for i, (src, pos, how) in enumerate(segs):  # a loop over segments
        prev = segs[i - 1]
        if how != "new" and prev[2] != "new" and prev[0] >= 0 and src >= 0:
            v = sp.edges[src].endpoints[0]
            if (prev[0] + 1) % n_e == src and kept_v[v]:
                P.append(Zv[v])
                O.append(sp.vertices[v])
                continue
        # a kept edge meets new outline where it was cut (its last vertex lies on it); an
        # extended one at the corner the new outline turns (the new piece's first vertex)
        j = prev[1][-1] if prev[2] == "kept" and how == "new" else pos[0]
        P.append(Zl[j])
        O.append(X[j])
    return np.array(P), np.array(O)


def _segment_edges(sp, segs, sources, P, O, Zl, idx, carried, bend):
    """The edges of the segments: a kept part of an input edge refitted (its kind) to its
    own carried points between its ends' parameters on it; new and extended ones to the
    adjusted outline's vertices (straight unless they bend, or the input edge's kind)."""
    t = np.linspace(0.0, 1.0, SAMPLES + 1)[1:-1]
    n_s = len(segs)
    edges, bent, refit = [], [], []
    for i, (src, pos, how) in enumerate(segs):  # a loop over segments
        P0, P1 = P[i], P[(i + 1) % n_s]
        old = sp.edges[src] if src >= 0 else None
        if how == "kept" and old is not None:  # part of an input edge: its own points
            ta, tb = _param_at(sp, src, O[i]), _param_at(sp, src, O[(i + 1) % n_s])
            Zs, s = carried(src, ta, tb, t), t
        else:  # new or extended: the adjusted outline's vertices
            Zs = Zl[pos]
            s = _chord_params(np.vstack([P0, Zs, P1]))[1:-1]
        kind0 = old.kind if old is not None else "straight"
        if kind0 == "straight":
            kind, params, err, dev = _straight_or_bent(P0, P1, Zs, s, bend)
            if kind != "straight" and old is not None:
                bent.append((i, dev))
        else:
            kind, params, err, _ = _fit_edge(P0, P1, kind0, s, Zs, start=old.params)
        enc = old.encoding if old is not None else "none"
        edges.append(SpecEdge((int(idx[i]), int(idx[(i + 1) % n_s])), kind, params, enc))
        refit.append(err)
    return edges, bent, refit


def _vertex_indices(sp: SpecPanel, sources: list[int]) -> np.ndarray:
    """The vertex index of each segment's start: the input vertex where the segment's own
    input edge starts, else where the previous segment's input edge ends, else a new index;
    then renumbered in the input's order (vertices gone dropped, new ones last)."""
    n = len(sources)
    idx = np.full(n, -1, dtype=np.int64)
    used: set[int] = set()
    for i, s in enumerate(sources):  # a loop over segments
        prev = sources[i - 1]
        for v in (
            sp.edges[s].endpoints[0] if s >= 0 else -1,
            sp.edges[prev].endpoints[1] if prev >= 0 else -1,
        ):
            if v >= 0 and v not in used:
                idx[i] = v
                used.add(v)
                break
    fresh = idx < 0
    idx[fresh] = len(sp.vertices) + np.arange(int(fresh.sum()))
    _, dense = np.unique(idx, return_inverse=True)  # the input's order kept, new ones last
    return dense.astype(np.int64)


def _chord_params(P: np.ndarray) -> np.ndarray:
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(P, axis=0), axis=1))])
    return s / max(float(s[-1]), 1e-300)


def _param_at(sp: SpecPanel, e: int, X: np.ndarray) -> float:
    """The parameter of the point of input edge ``e`` nearest ``X`` (input frame)."""
    t = np.linspace(0.0, 1.0, 4097)
    return float(t[int(np.argmin(np.linalg.norm(sp.edge_points(e, t) - X, axis=1)))])


def _between(a: int, b: int, n: int, present: set[int]) -> list[int]:
    """Input edges strictly between ``a`` and ``b`` in loop order that no run holds."""
    if a < 0 or b < 0:
        return []
    out, i = [], (a + 1) % n
    while i != b and len(out) < n:
        if i not in present:
            out.append(i)
        i = (i + 1) % n
    return out


def adjusted_specification(
    adj, matching: SpecMatching, original_panels: list[Panel], source: dict[str, int]
) -> AdjustedSpec:
    """The specification of the adjusted pattern.

    Parameters
    ----------
    adj : Adjustment
    matching : SpecMatching
        Made on the input garment (``adj.original``).
    original_panels : list of Panel
        The input garment's panels (``matching`` indexes them).
    source : dict
        Adjusted panel name to the input panel it came from
        (:func:`ptailor.pieces.plan.source_panels`).

    Returns
    -------
    AdjustedSpec
    """
    spec, k = matching.spec, matching.scale
    g0 = adj.original if adj.original is not None else adj.state.base
    parts: dict[int, list[Panel]] = {}
    for p in adj.state.panels:  # a loop over panels
        if p.name in source:
            parts.setdefault(source[p.name], []).append(p)
    panels, changes, removed = [], [], []
    edge_map: dict[str, dict[int, int]] = {}
    for m in matching.panels:  # a loop over spec panels
        sp = spec.panels[m.spec]
        now = parts.get(m.panel, [])
        if not now:
            removed.append(sp.name)
            continue
        got = _versions(adj, sp, m, k, original_panels[m.panel], now, g0)
        for new, ch in got:  # the parts of one panel (one unless a cut split it)
            panels.append(new)
            changes.append(ch)
        # stitches follow the first part (the one keeping the name)
        emap = edge_map.setdefault(sp.name, {})
        for i, e in enumerate(got[0][1].edge_sources):  # a loop over edges
            if e >= 0:
                emap.setdefault(e, i)
    stitches, kept, dropped = _stitches(spec, edge_map)
    new_spec = replace(spec, panels=tuple(panels), stitches=tuple(stitches))
    return AdjustedSpec(
        spec=new_spec,
        changes=tuple(changes),
        stitch_sources=tuple(kept),
        dropped_stitches=tuple(dropped),
        removed_panels=tuple(removed),
    )


def _versions(adj, sp: SpecPanel, m: PanelMatch, k: float, p0: Panel, now: list[Panel], g0):
    """The specification panel ``sp`` on each adjusted panel its mesh panel ``p0`` became:
    carried when its triangles are the same, else read off the adjusted outline; parts
    after the first named ``sp.name`` with the part's suffix."""
    base = adj.state.base
    bend = tol.SPEC_BEND_CM / CM_PER[g0.units] / k
    s0 = float(np.abs(signed_areas_2d(g0.V2, g0.F2[p0.faces])).sum())
    out = []
    for j, part in enumerate(now):  # the parts of one panel (one unless a cut split it)
        sb = float(np.abs(signed_areas_2d(base.V2, base.F2[part.faces])).sum())
        same = len(now) == 1 and len(part.faces) == len(p0.faces) and abs(sb - s0) <= 1e-9 * s0
        if same:
            new, ch = _carried_panel(sp, m, k, adj, part, bend)
        else:
            new, ch = _outline_panel(sp, m, k, adj, part, bend, g0.units)
        if j:
            suffix = part.name[len(p0.name) :] if part.name.startswith(p0.name) else f"_{j}"
            new, ch = replace(new, name=sp.name + suffix), replace(ch, name=sp.name + suffix)
        out.append((new, ch))
    return out


def _stitches(spec: Specification, edge_map: dict[str, dict[int, int]]):
    """The stitches whose two edges are still there, renumbered; the input stitch each is;
    the input stitches dropped."""
    stitches, kept, dropped = [], [], []
    for si, st in enumerate(spec.stitches):  # a loop over stitches
        sides = [(n, edge_map.get(n, {}).get(e)) for n, e in st.sides]
        if all(i is not None for _, i in sides):
            stitches.append(Stitch((sides[0], sides[1])))  # type: ignore[arg-type]
            kept.append(si)
        else:
            dropped.append(si)
    return stitches, kept, dropped
