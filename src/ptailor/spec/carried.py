"""A specification panel whose triangles the adjustment kept: every point carried.

Every point of the panel (its vertices, and samples along each edge curve) is located in its
mesh panel's triangles and carried to the adjusted pattern at the same barycentric
coordinates, then put in the panel's new frame (:mod:`ptailor.spec.frame`); each edge is
refitted to its carried samples (:mod:`ptailor.spec.refit`).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ptailor.method.transfer import carry_points, locate_points
from ptailor.model.garment import Panel
from ptailor.model.specification import SpecPanel
from ptailor.pieces.draw import outer_loop
from ptailor.spec.change import PanelChange
from ptailor.spec.frame import panel_frame
from ptailor.spec.match import PanelMatch
from ptailor.spec.refit import fit_edge, sample_params, straight_or_bent

__all__ = ["carried_panel"]


def carried_panel(
    sp: SpecPanel, m: PanelMatch, k: float, adj, part: Panel, bend: float
) -> tuple[SpecPanel, PanelChange]:
    """A panel with the same triangles: every point carried.

    Parameters
    ----------
    sp : SpecPanel
        The input specification panel.
    m : PanelMatch
        Its match to the input mesh panel.
    k : float
        Specification-to-computation unit scale.
    adj : Adjustment
    part : Panel
        The adjusted panel it is (on the same triangles).
    bend : float
        A straight edge whose carried points leave the chord by more than this
        (specification units) gets a curve.

    Returns
    -------
    (SpecPanel, PanelChange)
    """
    base = adj.state.base
    Vb, Fb, Vn = base.V2, base.F2, adj.result.V2
    L = outer_loop(Fb, part.faces, Vb)
    frame = panel_frame(m, k, Vb[L], Vn[L], scale=bend)
    t = sample_params()
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
            kind, params, err, dev = straight_or_bent(V[a], V[b], Ze, t, bend)
            if kind != "straight":
                bent.append((i, dev))
        else:
            kind, params, err, _ = fit_edge(V[a], V[b], e.kind, t, Ze, start=e.params)
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
