"""What an edit achieved: how far an edited edge moved from the opening it replaced."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ptailor.geometry.segments import nearest_segment_distance
from ptailor.geometry.topology import half_edges, loop_halfedges
from ptailor.model.garment import panel_labels, vertex_labels

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
