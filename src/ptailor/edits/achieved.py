"""What an edit achieved: how far an edited edge moved from the opening it replaced, how far
a cut reaches."""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from ptailor.geometry.segments import nearest_segment_distance
from ptailor.geometry.topology import edge_keys, half_edges, loop_halfedges
from ptailor.measures import garment_measures
from ptailor.model.garment import Garment, panel_labels, vertex_labels

if TYPE_CHECKING:
    from ptailor.edits.opening import OpeningEdges
    from ptailor.edits.state import EditState
    from ptailor.edits.surgery import SplitResult


def distance_stats(d: np.ndarray) -> dict:
    """``{"mean", "min", "max"}`` of distances, rounded for the report."""
    if d.size == 0:
        return {"mean": 0.0, "min": 0.0, "max": 0.0}
    return {
        "mean": round(float(d.mean()), 6),
        "min": round(float(d.min()), 6),
        "max": round(float(d.max()), 6),
    }


def edge_offsets(before: EditState, res: SplitResult, loop: np.ndarray) -> dict:
    """Distance of a new edge from the opening it replaced, in 3D and per panel in 2D.

    Parameters
    ----------
    before : EditState
        The state the opening was found on.
    res : SplitResult
        The split that made the new edge.
    loop : (k,) int array
        The opening's drape vertices in ``before``.

    Returns
    -------
    dict
        ``{"3d": {mean, min, max}, "pattern": {panel: {mean, min, max}}}``; 3D distances
        are straight-line distances from the new edge to the old opening's polyline.
    """
    g0 = before.base
    nxt = np.roll(loop, -1)
    # the new edge: vertices the split made, and those already on the level
    new3 = res.state.V3[np.concatenate([res.new_vertices3, res.on_level3])]
    out = {"3d": distance_stats(nearest_segment_distance(new3, before.V3[loop], before.V3[nxt]))}
    he = loop_halfedges(g0.F3, loop)
    h2 = half_edges(g0.F2)
    face_old = he // 3
    flab_old = panel_labels(before.panels, len(g0.F3))
    vlab_new = vertex_labels(res.state.panels, len(res.state.base.V2))
    pattern = {}
    new2 = np.concatenate([res.new_vertices2, res.on_level2])
    for p in before.panels:
        segs = he[flab_old[face_old] == p.index]
        if segs.size == 0:
            continue
        mine = [
            q.index for q in res.state.panels if q.name == p.name or q.name.startswith(p.name + "_")
        ]
        pts = new2[np.isin(vlab_new[new2], mine)]
        d = nearest_segment_distance(res.state.base.V2[pts], g0.V2[h2[segs, 0]], g0.V2[h2[segs, 1]])
        pattern[p.name] = distance_stats(d)
    out["pattern"] = pattern
    return out


def row_offsets(
    before: EditState,
    oe: OpeningEdges,
    top3: np.ndarray,
    top2: np.ndarray,
    col_panel: np.ndarray,
) -> dict:
    """Distance of a grown edge from the opening it grew from, in 3D and per panel in 2D.

    Parameters
    ----------
    before : EditState
        The state the opening was found on.
    oe : OpeningEdges
        The opening's edges in ``before``.
    top3 : (k, 3) float array
        The new edge's edited drape vertices.
    top2 : (c, 2) float array
        Its pattern vertices, one per column.
    col_panel : (c,) int array
        Panel of each column.

    Returns
    -------
    dict
        ``{"3d": {mean, min, max}, "pattern": {panel: {mean, min, max}}}``; straight-line
        distances to the old opening's polyline (3D) and to its pattern edges in the same
        panel (2D).
    """
    V3, V2 = before.V3, before.base.V2
    d3 = nearest_segment_distance(top3, V3[oe.a3], V3[oe.b3])
    edge_panel = panel_labels(before.panels, before.base.n_faces)[oe.face]
    pattern = {}
    for p in before.panels:  # a loop over panels
        sel = edge_panel == p.index
        if sel.any():
            d2 = nearest_segment_distance(
                top2[col_panel == p.index], V2[oe.a2[sel]], V2[oe.b2[sel]]
            )
            pattern[p.name] = distance_stats(d2)
    return {"3d": distance_stats(d3), "pattern": pattern}


def sketch_reach(
    res: SplitResult,
    *,
    rows: np.ndarray,
    sketch: np.ndarray,
    origin: np.ndarray,
    remove: str,
    near: Callable[[np.ndarray], np.ndarray],
) -> dict:
    """How far a sketch cut reaches from its origin into the garment, asked and achieved.

    Along the view's down for ``remove: above`` (up for ``below``, right for ``left``, left
    for ``right``): asked, the sketch's farthest point; achieved, the new edge's farthest
    point (its drape vertices where the sketch cuts, ``near``: those the split made, and
    those it passed through that are left on the garment's edge), both from the origin.

    Parameters
    ----------
    res : SplitResult
    rows : (3, 3) float array
        The view's rows (right, up, direction).
    sketch : (k, 2) float array
        The sketch, relative to ``origin``.
    origin : (2,) float array
    remove : str
    near : callable
        ``(n, 3) -> (n,) bool``: the drape points the sketch cuts (not the layers' middle).

    Returns
    -------
    dict
        ``{"along", "asked", "achieved"}`` (lengths in the garment's units; ``achieved``
        None where the new edge has no such point).
    """
    # the direction the cut reaches in, by the side it removes (image axes: right, up)
    name, t = {
        "above": ("down", np.array([0.0, -1.0])),
        "below": ("up", np.array([0.0, 1.0])),
        "left": ("right", np.array([1.0, 0.0])),
        "right": ("left", np.array([-1.0, 0.0])),
    }[remove]
    # the vertices the level passed through that the cut left on the edge
    F = res.state.base.F3
    E = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    _, first, count = np.unique(
        edge_keys(E, n=len(res.state.V3)), return_index=True, return_counts=True
    )
    on_edge = np.isin(res.on_level3, E[first[count == 1]])
    X = res.state.V3[np.concatenate([res.new_vertices3, res.on_level3[on_edge]])]
    X = X[np.asarray(near(X), bool)]
    far = (X @ rows[:2].T - origin) @ t
    return {
        "along": name,
        "asked": round(float(np.max(sketch @ t)), 6),
        "achieved": round(float(far.max()), 6) if far.size else None,
    }


def neck_drop(g: Garment, V3: np.ndarray) -> float | None:
    """The ``neck_drop`` point of measure of a garment draped as ``V3`` (drape, the
    garment's units; :mod:`ptailor.measures`), None where it has none."""
    m = [x for x in garment_measures(g.with_drape(V3)) if x.name == "neck_drop"]
    return round(float(m[0].drape), 6) if m else None
