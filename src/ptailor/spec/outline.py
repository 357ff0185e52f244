"""A specification panel whose triangles the adjustment changed: edges read off its outline.

The panel's adjusted outline is read into segments (:mod:`ptailor.spec.resegment`); each
segment starts at a junction (an input vertex still there, carried, or a corner of the new
outline) and becomes an edge: a kept part of an input edge refitted to its own carried
points, a new or extended one to the adjusted outline's vertices (:mod:`ptailor.spec.refit`).
Vertices keep their input indices where they are still there; new ones come last.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ptailor import tolerances as tol
from ptailor.method.transfer import carry_points, locate_points
from ptailor.model.garment import Panel
from ptailor.model.polyline import signed_area
from ptailor.model.specification import SpecEdge, SpecPanel
from ptailor.model.units import CM_PER
from ptailor.pieces.draw import outer_loop
from ptailor.spec.change import PanelChange
from ptailor.spec.frame import panel_frame
from ptailor.spec.match import PanelMatch
from ptailor.spec.refit import chord_params, fit_edge, param_at, sample_params, straight_or_bent
from ptailor.spec.resegment import cleaned_labels, edge_labels, outline_segments

__all__ = ["outline_panel"]


def outline_panel(
    sp: SpecPanel, m: PanelMatch, k: float, adj, part: Panel, bend: float, units: str
) -> tuple[SpecPanel, PanelChange]:
    """A panel whose triangles changed: edges read off its adjusted outline."""
    base = adj.state.base
    Vb, Fb, Vn = base.V2, base.F2, adj.result.V2
    L = outer_loop(Fb, part.faces, Vb)
    X = m.to_spec(Vb[L], k)
    if np.sign(signed_area(X)) != np.sign(signed_area(sp.outline(16)[0])):
        L, X = L[::-1], X[::-1]  # the loop runs the way the specification's edges do
    frame = panel_frame(m, k, Vb[L], Vn[L], scale=bend)
    Zl = frame.to_frame(Vn[L])
    reach = (
        max(tol.SPEC_REACH_FITS * m.distance, tol.SPEC_REACH_MIN_CM / CM_PER[units]) + 1e-9
    ) / k
    window = 1.0 / CM_PER[units] / k  # 1 cm: what a corner of the new outline is seen over
    lab = cleaned_labels(edge_labels(sp, X, reach)[0], Zl, window)
    segs = outline_segments(lab, Zl, len(sp.edges), window)
    # an input vertex still in the panel: where its two edges meet, carried
    loc_v = locate_points(Vb, Fb, m.to_pattern(sp.vertices, k), faces=part.faces)
    # (a corner off the mesh by the input's own fit is still there)
    kept_v = (
        loc_v.distance
        <= tol.SPEC_CORNER_KEEP_FITS * m.distance
        + tol.SPEC_CORNER_KEEP_REL * max(float(np.ptp(Vb[L])), tol.TINY)
    )
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
    t = sample_params()
    n_s = len(segs)
    edges, bent, refit = [], [], []
    for i, (src, pos, how) in enumerate(segs):  # a loop over segments
        P0, P1 = P[i], P[(i + 1) % n_s]
        old = sp.edges[src] if src >= 0 else None
        if how == "kept" and old is not None:  # part of an input edge: its own points
            ta, tb = param_at(sp, src, O[i]), param_at(sp, src, O[(i + 1) % n_s])
            Zs, s = carried(src, ta, tb, t), t
        else:  # new or extended: the adjusted outline's vertices
            Zs = Zl[pos]
            s = chord_params(np.vstack([P0, Zs, P1]))[1:-1]
        kind0 = old.kind if old is not None else "straight"
        if kind0 == "straight":
            kind, params, err, dev = straight_or_bent(P0, P1, Zs, s, bend)
            if kind != "straight" and old is not None:
                bent.append((i, dev))
        else:
            kind, params, err, _ = fit_edge(P0, P1, kind0, s, Zs, start=old.params)
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
