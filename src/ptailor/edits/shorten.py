"""``shorten``: remove a strip of given width along an opening.

The width is measured on the drape (``measure: drape``, the paper's: the iso-line of surface
distance from the opening) or in the pattern (``measure: pattern``, a pattern maker's: the
iso-line of 2D distance from the opening's edge in each panel, so a straight hem stays
straight and moves up by exactly ``by``).

Or the step asks a length measure: ``measure: body_length, to: 60`` (instead of ``by``) cuts
on the drape the width that brings the measure to that length
(:func:`ptailor.edits.asks.length_to`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ptailor.edits.achieved import edge_offsets
from ptailor.edits.asks import length_to, measure_check
from ptailor.edits.checks import number
from ptailor.edits.limits import check_by
from ptailor.edits.opening import find_opening, opening_edges, opening_spec
from ptailor.edits.pattern_distance import (
    PatternDistance,
    edge_distance,
    opening_pattern_distance,
    refine_crossings,
)
from ptailor.edits.registry import Step, checked, register
from ptailor.edits.state import EditOptions, EditState
from ptailor.edits.surgery import SplitResult, split_keep
from ptailor.errors import PtailorError
from ptailor.geometry.labels import used_indices
from ptailor.method.geodesic import geodesic_distance
from ptailor.model.garment import panel_labels

#: Where ``by`` is measured.
MEASURES = ("drape", "pattern")
#: The recipe check and description of ``shorten``'s and ``extend``'s ``measure``.
MEASURE = checked(
    measure_check("length", also=MEASURES),
    "where `by` is measured: drape (along the 3D surface, the paper's) | pattern "
    "(in each panel's 2D pattern: the new edge lies exactly `by` from the old one); or a "
    "length measure (body_length, skirt_length, sleeve_length_left, ...) brought `to` a "
    "length, instead of by",
)
#: The recipe check and description of ``shorten``'s and ``extend``'s ``to``.
TO = checked(
    number(gt=0.0),
    "the length measure's asked length, recipe units (with measure)",
    echo_none=False,
)


def length_form(step: Any, where: str) -> list[str]:
    """``by`` (with ``measure: drape`` or ``pattern``) or ``to`` (with a length measure's
    name), exactly one: the whole-step check of ``shorten`` and ``extend``."""
    if step.measure in MEASURES:
        if step.to is not None:
            return [
                f"{where}: 'to' goes with a length measure (measure: body_length, ...), not "
                f"with measure: {step.measure}"
            ]
        return [] if step.by is not None else [f"{where}: {step.op} needs 'by' (or measure + to)"]
    if step.by is not None:
        return [f"{where}: measure {step.measure} goes with 'to' (the length asked), not with 'by'"]
    return [] if step.to is not None else [f"{where}: measure {step.measure} needs 'to'"]


def spread_stats(d: np.ndarray) -> dict:
    """``{"min", "median", "max"}`` of distances, rounded for the report.

    Parameters
    ----------
    d : (k,) float array

    Returns
    -------
    dict
        Zeros for no distances.
    """
    if d.size == 0:
        return {"min": 0.0, "median": 0.0, "max": 0.0}
    return {
        "min": round(float(d.min()), 6),
        "median": round(float(np.median(d)), 6),
        "max": round(float(d.max()), 6),
    }


def drape_value(v3: np.ndarray, values: np.ndarray, n3: int) -> np.ndarray:
    """One value per drape vertex from its pattern copies: the mean of the finite ones.

    Parameters
    ----------
    v3 : (c,) int array
        The drape vertex of each pattern vertex.
    values : (c,) float array
        The value at each pattern vertex (``+inf`` where unknown).
    n3 : int
        Number of drape vertices.

    Returns
    -------
    (n3,) float array
        NaN where no copy has a finite value (seam vertices get the mean of their sides).
    """
    ok = np.isfinite(values)
    total = np.bincount(v3[ok], values[ok], n3)
    count = np.bincount(v3[ok], minlength=n3)
    out = np.full(n3, np.nan)
    out[count > 0] = total[count > 0] / count[count > 0]
    return out


def _pattern_field(state: EditState, loop: np.ndarray, by: float) -> tuple:
    """The pattern distance from an opening, its value per drape vertex, face panels."""

    g = state.base
    oe = opening_edges(g.F3, g.F2, loop)
    flab = panel_labels(state.panels, g.n_faces)
    field, d2 = opening_pattern_distance(g, state.panels, oe.a2, oe.b2, flab[oe.face], reach=by)
    used = used_indices(g.F2, len(g.V2))
    v3of2 = np.zeros(len(g.V2), dtype=np.int64)
    v3of2[g.F2.ravel()] = g.F3.ravel()
    return field, drape_value(v3of2[used], d2[used], len(g.V3)), flab


def pattern_amounts(
    field: PatternDistance, V2: np.ndarray, verts2: np.ndarray, vpanel: np.ndarray, names: dict
) -> dict:
    """Per panel spread of some pattern vertices' distance from the opening's own edges.

    Parameters
    ----------
    field : PatternDistance
        In the numbering of ``V2``'s panels (``vpanel``).
    V2 : (n2, 2) float array
    verts2 : (k,) int array
        The new edge's pattern vertices.
    vpanel : (k,) int array
        The panel (as ``field`` numbers them) each vertex measures in.
    names : dict
        Panel index to name.

    Returns
    -------
    dict
        Panel name to :func:`spread_stats`, for panels the opening runs along and that
        have new edge vertices (not a panel the step removed whole).
    """
    d = field.at(V2[verts2], vpanel, own_only=True)
    out = {}
    for q in np.unique(field.panel[field.own]):  # a loop over panels
        sel = (vpanel == q) & np.isfinite(d)
        if sel.any():
            out[names[int(q)]] = spread_stats(d[sel])
    return out


def _drape_amount(
    state: EditState, res: SplitResult, loop: np.ndarray, by: float, d: np.ndarray | None
) -> dict:
    """Surface distance on the edited drape from the old opening to the new edge."""
    e = np.concatenate([res.edge3, np.stack([res.source3, res.source3], 1)])
    t = np.concatenate([res.t3, np.zeros(len(res.source3))])
    if d is None:
        limit = 3.0 * by
        d = geodesic_distance(state.V3, state.base.F3, loop, limit=limit)
        if not np.all(d[e] < limit):  # the new edge lies farther: measure all the way
            d = geodesic_distance(state.V3, state.base.F3, loop)
    val = (1.0 - t) * d[e[:, 0]] + t * d[e[:, 1]]
    return spread_stats(val[np.isfinite(val)])


@dataclass(frozen=True, kw_only=True)
class ShortenStep(Step):
    """A ``shorten`` step (see :func:`shorten`).

    Attributes
    ----------
    opening : str or dict
        An opening's name or ``{loop: k}``.
    by : float or None
        The width removed, recipe units (None: found from ``measure`` and ``to``).
    measure : str
        Where ``by`` is measured (``drape``, ``pattern``), or a length measure's name
        (:data:`ptailor.measures.MEASURES`) brought ``to`` a length.
    to : float or None
        That measure's asked length, recipe units.
    """

    op = "shorten"
    opening: str | dict[str, Any] = field(
        metadata=checked(opening_spec, "hem | neckline | ... | {loop: k}")
    )
    by: float | None = field(
        default=None,
        metadata=checked(
            number(gt=0.0), "width removed, recipe units (see measure)", echo_none=False
        ),
    )
    measure: str = field(default="drape", metadata=MEASURE)
    to: float | None = field(default=None, metadata=TO)


@register(ShortenStep, check=length_form)
def shorten(state: EditState, step: ShortenStep, *, options: EditOptions) -> EditState:
    """Cut the garment on the iso-line at distance ``by`` from an opening; remove the strip.

    With a length measure and ``to`` instead of ``by``: the drape ``by`` that brings the
    measure to ``to`` (:func:`ptailor.edits.asks.length_to`); the record adds ``asked``,
    ``before``, ``target``, ``achieved`` (the measure's, cm) and ``tries``, and its
    ``achieved`` below is then ``edge_offset``.

    ``measure: drape``: distances are measured on the edited drape from the opening's curve
    (geodesic); every triangle the iso-line crosses is split exactly on it and the strip is
    removed, in 3D and 2D. ``measure: pattern``: a pattern vertex's distance is its 2D
    distance from the opening's pattern edges in its own panel, carried over seams into
    panels the opening does not run along (:func:`opening_pattern_distance`); each crossed
    pattern edge is cut exactly on that panel's iso-line (:func:`refine_crossings`) and the
    drape by the same split (a seam edge, whose two sides may meet the iso-line a little
    apart, at the mean of the two).

    The log record's ``amount`` gives what was removed both ways: ``pattern``, per panel
    the opening runs along, the ``min``, ``median`` and ``max`` distance of the new edge's
    pattern vertices from the old edge; ``drape``, the same of their surface distance from
    the old opening on the edited drape.
    """
    if step.to is not None:
        return length_to(state, step, shorten, options=options)
    name, loop = find_opening(state, step.opening)
    by = float(step.by)
    measure = step.measure
    g = state.base
    used = used_indices(g.F3, len(g.V3))
    lv = state.V3 if measure != "pattern" else None
    if lv is not None:
        ring = lv[loop]
        edge = float(np.linalg.norm(ring - np.roll(ring, -1, axis=0), axis=1).mean())
    else:
        Fp = g.F2
        edge = float(np.linalg.norm(g.V2[Fp] - g.V2[np.roll(Fp, -1, axis=1)], axis=2).mean())
    check_by(by, edge, what=f"shorten {name}")
    d = None
    if measure == "pattern":
        field, d3, flab = _pattern_field(state, loop, by)
        phi = np.where(np.isnan(d3), by, d3 - by)  # panels out of reach are kept
        far = np.any(phi[used] > 0)
    else:
        d = geodesic_distance(state.V3, g.F3, loop, limit=1.5 * by)
        phi = d - by
        far = np.any(d[used] > by)
    if not far:
        raise PtailorError(
            f"shorten {name} by {by:g}: the garment is nowhere farther than that from its {name}"
            + (" (in the pattern)" if measure == "pattern" else "")
        )
    if measure == "pattern":

        def crossing(a2: np.ndarray, b2: np.ndarray, t: np.ndarray, face: np.ndarray):
            return refine_crossings(field, g.V2, a2, b2, t, flab[face], by)

        res = split_keep(state, phi, crossing=crossing, true_seams=True)
    else:
        res = split_keep(state, phi, true_seams=True)
    rec = {
        "op": "shorten",
        "opening": name,
        "by": by,
        "removed_triangles": res.removed_triangles,
        "split_triangles": res.split_triangles,
        "new_edge_vertices": len(res.new_vertices3),
        "achieved": edge_offsets(state, res, loop),
        "measure": measure,
        "amount": _amounts(state, res, loop, by, d, field if measure == "pattern" else None),
    }
    return replace(res.state, log=(*state.log, rec))


def _amounts(
    state: EditState,
    res: SplitResult,
    loop: np.ndarray,
    by: float,
    d: np.ndarray | None,
    field: PatternDistance | None,
) -> dict:
    """The record's ``amount``: removed width in the pattern (per panel) and on the drape."""
    if field is None:
        g = state.base
        oe = opening_edges(g.F3, g.F2, loop)
        flab = panel_labels(state.panels, g.n_faces)
        field = edge_distance(g.V2, oe.a2, oe.b2, flab[oe.face])
    # each new pattern vertex measures in the input panel its panel was cut from
    source = {p.name: p.index for p in state.panels}
    vsrc = np.full(len(res.state.base.V2), -1, dtype=np.int64)
    for q in res.state.panels:  # a loop over panels
        base_name = q.name if q.name in source else q.name.rsplit("_", 1)[0]
        vsrc[q.vertices] = source.get(base_name, -1)
    # new pattern vertices sit where the split put them, in the input pattern's frame
    nv = np.concatenate([res.new_vertices2, res.on_level2])
    names = {p.index: p.name for p in state.panels}
    pattern = pattern_amounts(field, res.state.base.V2, nv, vsrc[nv], names)
    kept = {int(i) for i in np.unique(vsrc[vsrc >= 0])}
    removed = [p.name for p in state.panels if p.index not in kept]
    return {
        "pattern": pattern,
        "drape": _drape_amount(state, res, loop, by, d),
        "removed_panels": removed,
    }
