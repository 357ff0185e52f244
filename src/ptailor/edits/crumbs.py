"""Crumbs: pieces a cut leaves smaller than a few triangles, dropped with a warning.

A cut through a strap or a corner of a panel can leave a piece of one or two triangles
(a V-neck through a dress left ``strap_right_1``, a triangle of 0.04 cm2 in the pattern):
no pattern maker keeps it, and the flattening gains nothing from it. :func:`drop_crumbs`
removes every piece of a panel the cut touched whose pattern area is under
``edit_tol.CUT_CRUMB_TRIANGLES`` times its panel's median triangle area (before the cut),
and says which.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ptailor import tolerances as tol
from ptailor.edits import tolerances as edit_tol
from ptailor.edits.state import EditState
from ptailor.edits.surgery import SplitResult
from ptailor.geometry.triangles import signed_areas_2d
from ptailor.model.garment import Garment, panel_labels
from ptailor.model.structure import structure


def crumb_panels(before: EditState, res: SplitResult) -> tuple[np.ndarray, np.ndarray]:
    """The panels of a split's result that are crumbs.

    Returns
    -------
    crumbs : (c,) int array
        Panel indices (in ``res.state.panels``) of the pieces under
        ``edit_tol.CUT_CRUMB_TRIANGLES`` median triangles of the panel they come from,
        that panel touched by the split (some of it removed, or cut in several pieces).
    area : (n_panels,) float array
        Pattern area of every panel of the result.
    """
    g0, g1 = before.base, res.state.base
    n0, n1 = len(before.panels), len(res.state.panels)
    lab0 = panel_labels(before.panels, g0.n_faces)
    a0 = np.abs(signed_areas_2d(g0.V2, g0.F2))
    lab1 = panel_labels(res.state.panels, g1.n_faces)
    a1 = np.abs(signed_areas_2d(g1.V2, g1.F2))
    area = np.bincount(lab1, a1, n1)
    src = lab0[res.face_parent]
    # a panel's median triangle: sort by (panel, area), take each panel's middle row
    order = np.lexsort((a0, lab0))
    count = np.bincount(lab0, minlength=n0)
    start = np.concatenate([[0], np.cumsum(count)[:-1]])
    med = a0[order][np.minimum(start + count // 2, len(a0) - 1)]
    source = np.zeros(n1, int)
    source[lab1] = src  # the panel each piece comes from (a piece has one)
    parts = np.bincount(source, minlength=n0)
    kept = np.bincount(src, a1, n0)
    total = np.bincount(lab0, a0, n0)
    touched = (kept < total * (1.0 - tol.ROUNDING_REL)) | (parts > 1)
    small = area < edit_tol.CUT_CRUMB_TRIANGLES * med[source]
    return np.flatnonzero(small & touched[source]), area


def drop_crumbs(before: EditState, res: SplitResult) -> tuple[SplitResult, dict]:
    """Drop the pieces a split left smaller than a few triangles (:func:`crumb_panels`).

    Parameters
    ----------
    before : EditState
        The state that was split.
    res : SplitResult

    Returns
    -------
    res : SplitResult
        Without the crumbs (vertices renumbered; the new edge's vertices on them gone).
    dropped : dict
        ``{"pieces": [{"piece", "area", "triangles"}], "warnings": [...]}`` (areas in the
        garment's units squared, in the pattern).
    """
    crumbs, area = crumb_panels(before, res)
    g = res.state.base
    lab = panel_labels(res.state.panels, g.n_faces)
    keep = ~np.isin(lab, crumbs)
    if len(crumbs) == 0 or not keep.any():
        return res, {"pieces": [], "warnings": []}
    pieces = [
        {
            "piece": res.state.panels[int(c)].name,
            "area": round(float(area[c]), 6),
            "triangles": int((lab == c).sum()),
        }
        for c in crumbs  # a loop over the few crumbs
    ]
    u = g.units
    warnings = [
        f"drops piece {p['piece']} ({p['area']:.3g} {u}2 of pattern, {p['triangles']} "
        f"triangle{'s' if p['triangles'] != 1 else ''}): the cut left it smaller than "
        f"{edit_tol.CUT_CRUMB_TRIANGLES} of its panel's triangles"
        for p in pieces
    ]
    return drop_faces(before, res, keep), {"pieces": pieces, "warnings": warnings}


def drop_faces(before: EditState, res: SplitResult, keep: np.ndarray) -> SplitResult:
    """``res`` with only the triangles ``keep`` ``(m,)`` bool: vertices renumbered, the new
    edge's vertices on the dropped ones gone, the panels named as the split would have
    named them without the dropped triangles.

    Parameters
    ----------
    before : EditState
        The state that was split.
    res : SplitResult
    keep : (m,) bool array
        Per triangle of ``res.state.base``.

    Returns
    -------
    SplitResult
    """
    s, g = res.state, res.state.base
    F3, F2 = g.F3[keep], g.F2[keep]
    used3 = np.zeros(len(g.V3), bool)
    used3[F3.ravel()] = True
    used2 = np.zeros(len(g.V2), bool)
    used2[F2.ravel()] = True
    map3 = np.where(used3, np.cumsum(used3) - 1, -1)
    map2 = np.where(used2, np.cumsum(used2) - 1, -1)
    parent = res.face_parent[keep]
    lab0 = panel_labels(before.panels, before.base.n_faces)
    base = Garment(
        V3=g.V3[used3],
        F3=map3[F3],
        V2=g.V2[used2],
        F2=map2[F2],
        face_group=lab0[parent],
        group_names=tuple(p.name for p in before.panels),
        units=g.units,
        frame=g.frame,
    )
    panels = structure(base).panels
    even = {p.name: bool(s.even[p.index]) for p in s.panels}
    free = None if s.outline_free is None else s.outline_free[used2]
    state = replace(
        s,
        base=base,
        V3=s.V3[used3],
        panels=panels,
        even=np.array([even.get(q.name, False) for q in panels]),
        outline_free=free,
    )
    k3 = map3[res.new_vertices3] >= 0
    k_on = map3[res.on_level3] >= 0
    n2, o2 = map2[res.new_vertices2], map2[res.on_level2]
    return replace(
        res,
        state=state,
        face_parent=parent,
        new_vertices2=n2[n2 >= 0],
        new_vertices3=map3[res.new_vertices3][k3],
        edge3=res.edge3[k3],
        t3=res.t3[k3],
        on_level3=map3[res.on_level3][k_on],
        on_level2=o2[o2 >= 0],
        source3=res.source3[k_on],
    )
