"""``extend``: add rows of cloth beyond an opening (the paper's Extend, after Brouet et al.).

The rows continue the surface along the tangent planes of the triangles at the opening; the
new pattern strip takes the intrinsic scale of the triangles it grows from, and the final
flattening glues it to its panels (outline free along the new cloth).

Or the step asks a length measure: ``measure: skirt_length, to: 70`` (instead of ``by``)
grows on the drape the rows that bring the measure to that length
(:func:`ptailor.edits.asks.length_to`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ptailor.edits import tolerances as edit_tol
from ptailor.edits.achieved import row_offsets
from ptailor.edits.asks import length_to
from ptailor.edits.body import push_out
from ptailor.edits.checks import number
from ptailor.edits.extend.continuation import fold_check, fold_warning
from ptailor.edits.extend.drape import drape_rows, surface_directions
from ptailor.edits.extend.pattern import pattern_rows
from ptailor.edits.extend.rows import RowPlan, Rows, quad_rows, row_plan
from ptailor.edits.limits import check_by, check_new_triangles
from ptailor.edits.opening import OpeningEdges, find_opening, opening_edges, opening_spec
from ptailor.edits.registry import Step, checked, register
from ptailor.edits.shorten import MEASURE, TO, length_form, pattern_amounts, spread_stats
from ptailor.edits.state import EditOptions, EditState
from ptailor.method.geodesic import geodesic_distance
from ptailor.model.garment import Garment
from ptailor.model.structure import structure

__all__ = ["ExtendStep", "OpeningEdges", "extend", "opening_edges"]


@dataclass(frozen=True, kw_only=True)
class ExtendStep(Step):
    """An ``extend`` step (see :func:`extend`).

    Attributes
    ----------
    opening : str or dict
        An opening's name or ``{loop: k}``.
    by : float or None
        The length added, recipe units (None: found from ``measure`` and ``to``).
    clearance : float or None
        The distance new rows keep from a body (with ``options.body``); None:
        :data:`ptailor.edits.tolerances.EXTEND_CLEARANCE_EDGES` of the opening's mean edge
        length (:meth:`clearance_for`).
    measure : str
        Where ``by`` is measured (``drape``, ``pattern``), or a length measure's name
        (:data:`ptailor.measures.MEASURES`) brought ``to`` a length.
    to : float or None
        That measure's asked length, recipe units.
    """

    op = "extend"
    opening: str | dict[str, Any] = field(
        metadata=checked(opening_spec, "hem | neckline | ... | {loop: k}")
    )
    by: float | None = field(
        default=None,
        metadata=checked(
            number(gt=0.0), "length added, recipe units (see measure)", echo_none=False
        ),
    )
    clearance: float | None = field(
        default=None,
        metadata=checked(
            number(ge=0.0), "distance kept from the body (with a body); default half an edge"
        ),
    )
    measure: str = field(default="drape", metadata=MEASURE)
    to: float | None = field(default=None, metadata=TO)

    def clearance_for(self, mean_edge: float) -> float:
        """The clearance kept from a body: the step's, else half the opening's mean edge."""
        return (
            edit_tol.EXTEND_CLEARANCE_EDGES * mean_edge
            if self.clearance is None
            else float(self.clearance)
        )


def _grown_state(state: EditState, plan: RowPlan, built: Rows, new_e: np.ndarray) -> EditState:
    """``state`` with the new rows: the garment grown (its panels from
    :func:`ptailor.model.structure.structure`), the edited drape ``new_e`` appended, panels
    keeping their ``even`` flag, the new pattern vertices outline-free."""
    g = state.base
    Vb, V2, Ve = g.V3, g.V2, state.V3
    oe, rows, flab = plan.oe, plan.rows, plan.flab
    k, n2 = len(oe.a3), len(V2)
    new_b, new_2 = built.new_b, built.new_2
    F3_new = quad_rows(plan.A3, plan.B3, built.use_b)
    F2_new = quad_rows(plan.A2, plan.B2, built.use_b)
    lab_new = np.broadcast_to(flab[oe.face][None, :, None], (rows, k, 2)).reshape(-1)
    base = Garment(
        V3=np.concatenate([Vb, new_b]),
        F3=np.concatenate([g.F3, F3_new]),
        V2=np.concatenate([V2, new_2]),
        F2=np.concatenate([g.F2, F2_new]),
        face_group=np.concatenate([flab, lab_new]),
        group_names=tuple(p.name for p in state.panels),
        units=g.units,
        frame=g.frame,
    )
    new_panels = structure(base).panels
    old_even = {p.name: bool(state.even[p.index]) for p in state.panels}
    even = np.array([old_even.get(q.name, False) for q in new_panels], dtype=bool)
    free = np.ones(len(base.V2), dtype=bool)
    free[:n2] = False if state.outline_free is None else state.outline_free
    V3_new = np.concatenate([Ve, new_e])
    return replace(state, base=base, V3=V3_new, panels=new_panels, even=even, outline_free=free)


@register(ExtendStep, check=length_form)
def extend(state: EditState, step: ExtendStep, *, options: EditOptions) -> EditState:
    """Add rows of triangles beyond an opening, continuing the surface, ``by`` long.

    With a length measure and ``to`` instead of ``by``: the drape ``by`` that brings the
    measure to ``to`` (:func:`ptailor.edits.asks.length_to`); the record adds ``asked``,
    ``before``, ``target``, ``achieved`` (the measure's, cm) and ``tries``, and its
    ``achieved`` below is then ``edge_offset``.

    ``measure: drape`` (the paper's): each opening vertex grows a straight line of new
    vertices along the unit direction tangent to the surface and across the boundary,
    ``by`` long on the drape (:func:`drape_rows`); the pattern columns follow with the
    intrinsic scale of the triangles they grow from (``J+ dir``, the pseudo-inverse of
    their pattern-to-drape map on the original drape), the copies of a seam vertex in
    their seam's length ratio (:func:`match_seam_steps`). ``measure: pattern``: the new
    edge is laid out in each panel's pattern exactly ``by`` from the old one (the offset
    of the opening's pattern edges, seams continued straight where they meet it) and the
    drape rows are built to match through the pattern-to-drape maps of the triangles they
    grow from (:func:`pattern_rows`).

    There are ``rows`` rows, about the opening's mean edge length apart; where rows would
    cross (a concave opening) the directions there are smoothed, pass by pass, and after
    ``EXTEND_MAX_SMOOTHING`` passes the step fails naming where; an opening whose offset closes
    on itself is refused. The edited drape ``state.V3`` grows from its own opening; the
    original drape ``state.base.V3`` grows the same rows from its opening, so the new cloth
    follows earlier edits like the cloth it continues (after a first step both are the
    same). With a body (``options.body``, a ``trimesh.Trimesh``), new edited vertices
    inside it or within ``clearance`` of it are pushed out
    (:func:`ptailor.edits.body.push_out`). The new pattern vertices are the new
    triangles' original pattern (the final flattening glues them) and are outline-free;
    panels keep their ``even`` flag.

    New rows folded back against the row before them (the opening's triangles for the
    first), or growing against the surface's continuation, are a warning naming the
    opening, and the record's ``folds`` says where
    (:func:`ptailor.edits.extend.continuation.fold_check`).

    The log record's ``amount`` gives the length added both ways: ``pattern``, per panel
    the opening runs along, the ``min``, ``median`` and ``max`` distance of the new edge's
    pattern vertices from the old edge; ``drape``, the same of their surface distance from
    the old opening.
    """
    if step.to is not None:
        return length_to(state, step, extend, options=options)
    name, loop = find_opening(state, step.opening)
    by = float(step.by)
    measure = step.measure
    oe = opening_edges(state.base.F3, state.base.F2, loop)
    mean_edge, rows = _row_count(state, oe, by=by, measure=measure, name=name)
    plan = row_plan(state, oe, name=name, by=by, rows=rows)
    make = pattern_rows if measure == "pattern" else drape_rows
    built = make(state, plan)
    new_e = built.new_e
    if options.body is not None:
        new_e = push_out(new_e, options.body, clearance=step.clearance_for(mean_edge))

    grown = _grown_state(state, plan, built, new_e)
    rec = _extend_record(
        state, grown, plan, built, new_e, loop=loop, name=name, by=by, measure=measure
    )
    folds = fold_check(
        grown.V3,
        grown.base.F3[state.base.n_faces :],
        plan.n_src,
        plan.A3,
        surface_directions(state.V3, state.base.F3, oe),
    )
    if folds is not None:
        warn = fold_warning(name, by, folds, state.base.units)
        rec = {**rec, "folds": folds, "warnings": [*rec.get("warnings", ()), warn]}
    return replace(grown, log=(*state.log, rec))


def _row_count(
    state: EditState, oe: OpeningEdges, *, by: float, measure: str, name: str
) -> tuple[float, int]:
    """The opening's mean edge length (on the pattern for ``measure: pattern``, else on
    the edited drape) and the number of rows ``by`` asks for, about one edge apart
    (checked: ``by`` against the edge, the number of new triangles against the garment)."""
    g = state.base
    if measure == "pattern":
        Fo2 = g.F2[oe.face]
        V2 = g.V2
        mean_edge = float(np.linalg.norm(V2[Fo2] - V2[np.roll(Fo2, -1, axis=1)], axis=2).mean())
    else:
        Fo, Ve = g.F3[oe.face], state.V3
        mean_edge = float(np.linalg.norm(Ve[Fo] - Ve[np.roll(Fo, -1, axis=1)], axis=2).mean())
    check_by(by, mean_edge, what=f"extend {name}")
    rows_f = max(1.0, float(np.rint(by / mean_edge)))
    check_new_triangles(2.0 * rows_f * len(oe.a3), g.n_faces, what=f"extend {name} by {by:g}")
    return mean_edge, int(rows_f)


def _extend_record(
    state: EditState,
    grown: EditState,
    plan: RowPlan,
    built: Rows,
    new_e: np.ndarray,
    *,
    loop: np.ndarray,
    name: str,
    by: float,
    measure: str,
) -> dict:
    """The log record of an ``extend`` step (see :func:`extend`): the achieved lengths, the
    new edge's distance from the old opening in 3D and per panel."""
    oe, rows, nc, k = plan.oe, plan.rows, plan.nc, len(plan.oe.a3)
    V3_new, base = grown.V3, grown.base
    col_panel = plan.col_panel
    top2 = built.new_2[(rows - 1) * nc :]
    achieved = row_offsets(state, oe, new_e[(rows - 1) * k :], top2, col_panel)
    names = {p.index: p.name for p in state.panels}
    top_ids = len(state.base.V3) + (rows - 1) * k + np.arange(k)
    reach = edit_tol.EXTEND_MEASURE_REACH_BY * by
    surf = geodesic_distance(V3_new, base.F3, loop, limit=reach)[top_ids]
    if not np.all(surf < reach):  # pushed far out by the body: measure all the way
        surf = geodesic_distance(V3_new, base.F3, loop)[top_ids]
    return {
        "op": "extend",
        "opening": name,
        "by": by,
        "rows": rows,
        "new_triangles": 2 * rows * k,
        "smoothing": built.smoothing,
        "achieved": achieved,
        "measure": measure,
        "pattern_smoothing": built.pattern_smoothing,
        "amount": {
            "pattern": pattern_amounts(plan.field, top2, np.arange(nc), col_panel, names),
            "drape": spread_stats(surf[np.isfinite(surf)]),
        },
    }
