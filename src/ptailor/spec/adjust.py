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

The steps live in their own modules: :mod:`ptailor.spec.frame` (the panel's new frame),
:mod:`ptailor.spec.refit` (an edge refitted to its points), :mod:`ptailor.spec.carried` (a
panel on the same triangles), :mod:`ptailor.spec.resegment` and :mod:`ptailor.spec.outline`
(a panel read off its changed outline).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ptailor import tolerances as tol
from ptailor.geometry.triangles import signed_areas_2d
from ptailor.model.garment import Panel
from ptailor.model.specification import Specification, SpecPanel, Stitch
from ptailor.model.units import CM_PER
from ptailor.spec.carried import carried_panel
from ptailor.spec.change import PanelChange
from ptailor.spec.match import PanelMatch, SpecMatching
from ptailor.spec.outline import outline_panel

__all__ = ["AdjustedSpec", "PanelChange", "adjusted_specification"]


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
        same = (
            len(now) == 1
            and len(part.faces) == len(p0.faces)
            and abs(sb - s0) <= tol.ROUNDING_REL * s0
        )
        if same:
            new, ch = carried_panel(sp, m, k, adj, part, bend)
        else:
            new, ch = outline_panel(sp, m, k, adj, part, bend, g0.units)
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
