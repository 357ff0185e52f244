"""``scale``: scale a region around, along or uniformly about its axis.

By a ``factor``, or to a point of measure's asked value (``measure`` with ``to`` or ``by``):
the factor is then found from the measure on the step's input drape, target / current (a
girth under an ``around`` scale of its region, a length under an ``along`` one), and
corrected on the scaled drape (:mod:`ptailor.edits.asks`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ptailor.edits import tolerances as edit_tol
from ptailor.edits.asks import (
    amount,
    ask_tolerance,
    asked_of,
    drape_measure,
    measure_check,
    measure_record,
    solve,
    target_value,
    with_ask,
)
from ptailor.edits.checks import axis as axis_spec
from ptailor.edits.checks import choice, number
from ptailor.edits.checks import region as region_spec
from ptailor.edits.coverage import girth_coverage, with_coverage
from ptailor.edits.follow import rigid_apart
from ptailor.edits.limbs import Piece, limb_pieces
from ptailor.edits.region import region_axis, region_centroid, region_faces, unit_vector
from ptailor.edits.registry import Step, checked, register
from ptailor.edits.state import EditOptions, EditState
from ptailor.errors import PtailorError
from ptailor.measures import MEASURES
from ptailor.method.deform import arap_deform
from ptailor.model.frame import Frame


def scale_matrix(direction: str, ax: np.ndarray, factor: float) -> np.ndarray:
    """The 3x3 linear map of a scale step.

    Parameters
    ----------
    direction : {"around", "along", "uniform"}
        ``around`` scales distances from the axis, ``along`` positions along it.
    ax : (3,) float array
        Unit axis.
    factor : float

    Returns
    -------
    (3, 3) float array
    """
    P = np.outer(ax, ax)
    if direction == "along":
        return np.eye(3) + (factor - 1.0) * P
    if direction == "around":
        return factor * np.eye(3) + (1.0 - factor) * P
    return factor * np.eye(3)


@dataclass(frozen=True, kw_only=True)
class ScaleStep(Step):
    """A ``scale`` step (see :func:`scale`).

    Attributes
    ----------
    region : str or dict
        ``all``, ``{panels: [...]}``, ``{part: ...}`` or ``{box: {min, max}}``.
    direction : {"uniform", "around", "along"}
    axis : str or list of float
        ``auto`` or ``[x, y, z]``.
    factor : float or None
        The scale factor; None: found from ``measure``.
    measure : str or None
        A point of measure (:data:`ptailor.measures.MEASURES`) the factor brings to ``to``
        or changes ``by``.
    to : float or None
        Its asked value, recipe units.
    by : float, str or None
        Its asked change: a length (recipe units) or ``"N%"``.
    """

    op = "scale"
    region: str | dict[str, Any] = field(
        default="all",
        metadata=checked(
            region_spec, "all | {panels: [...]} | {part: torso, sleeves, ...} | {box: {min, max}}"
        ),
    )
    direction: str = field(
        default="uniform", metadata=checked(choice("around", "along", "uniform"))
    )
    axis: str | list[float] = field(
        default="auto",
        metadata=checked(axis_spec, "auto (the region's principal axis) | [x, y, z]"),
    )
    factor: float | None = field(
        default=None,
        metadata=checked(
            number(gt=0.0, le=100.0), "the scale factor (or measure with to or by)", echo_none=False
        ),
    )
    measure: str | None = field(
        default=None,
        metadata=checked(
            measure_check(),
            "a point of measure (chest, hip, body_length, ...) brought to `to` or changed "
            "`by`, instead of factor: the factor is found",
            echo_none=False,
        ),
    )
    to: float | None = field(
        default=None,
        metadata=checked(
            number(gt=0.0), "the measure's asked value, recipe units", echo_none=False
        ),
    )
    by: float | str | None = field(
        default=None,
        metadata=checked(
            amount, "the measure's asked change: recipe units, or 'N%'", echo_none=False
        ),
    )


#: The directions that scale a measure of each kind in proportion (a girth grows with an
#: ``around`` scale of its region, a length with an ``along`` one).
LINEAR = {
    "girth": ("around", "uniform"),
    "length": ("along", "uniform"),
    "depth": ("along", "uniform"),
}


def scale_form(step: ScaleStep, where: str) -> list[str]:
    """Exactly one of ``factor`` or ``measure`` (with exactly one of ``to`` or ``by``); the
    measure one the direction scales in proportion."""
    if (step.factor is None) == (step.measure is None):
        return [f"{where}: scale needs exactly one of 'factor' or 'measure' (with 'to' or 'by')"]
    if step.measure is None:
        extra = [k for k, v in (("to", step.to), ("by", step.by)) if v is not None]
        return [f"{where}: '{k}' goes with 'measure', not with 'factor'" for k in extra]
    if (step.to is None) == (step.by is None):
        return [f"{where}: measure {step.measure} needs exactly one of 'to' or 'by'"]
    kind = MEASURES[step.measure].kind
    if step.direction not in LINEAR[kind]:
        article = "an" if step.direction == "along" else "a"
        return [
            f"{where}: {article} {step.direction} scale does not scale the {kind} "
            f"{step.measure} in proportion: use direction {' or '.join(LINEAR[kind])}"
        ]
    return []


@register(ScaleStep, check=scale_form)
def scale(state: EditState, step: ScaleStep, *, options: EditOptions) -> EditState:
    """Scale a region of the drape; the rest follows by as-rigid-as-possible deformation.

    By ``factor`` (:func:`scale_by`), or by the factor that brings ``measure`` to its
    asked value (:func:`scale_to_measure`). An ``around`` scale whose region holds only part
    of a girth warns with the share it holds (:mod:`ptailor.edits.coverage`).
    """
    if step.measure is None:
        out = scale_by(state, step, float(step.factor), options=options)
    else:
        out = scale_to_measure(state, step, options=options)
    if step.direction != "around" or step.region == "all":
        return out
    g = state.base
    faces = region_faces(step.region, g, state.V3, state.panels)
    ax = None if step.axis == "auto" else unit_vector(step.axis, "axis")
    found = girth_coverage(state.V3, g.F3, faces, garment=g, axis=ax)
    return replace(out, log=(*out.log[:-1], with_coverage(out.log[-1], found)))


def scale_to_measure(state: EditState, step: ScaleStep, *, options: EditOptions) -> EditState:
    """Scale by the factor that brings ``step.measure`` to ``to`` (or changes it ``by``).

    The first factor is target / current, the measure on the step's input drape; secant
    steps on the measure of the scaled drape correct it where the region holds only part of
    the measure's line or the rest of the garment pulls (:func:`ptailor.edits.asks.solve`).
    The record adds ``asked``, ``before``, ``target``, ``achieved`` (cm, the drape) and
    ``tries``.

    Raises
    ------
    PtailorError
        The garment lacks the measure, or the asked value is not a length (a change below
        minus the measure).
    """
    name = str(step.measure)
    current = drape_measure(state, name)
    target = target_value(current, to=step.to, by=step.by)
    if not target > 0.0:
        raise PtailorError(
            f"scale {name} by {step.by}: {name} is {current:.4g}, so that is no length"
        )

    def run(f: float) -> tuple[EditState, float]:
        out = scale_by(state, step, f, options=options)
        try:
            return out, drape_measure(out, name)
        except PtailorError as exc:
            raise PtailorError(f"scaled by {f:.4g}, {exc}") from None

    got = solve(
        run,
        anchor=(1.0, current),
        first=target / current,
        target=target,
        tol=ask_tolerance(state),
        lower=0.0,
    )
    keys = measure_record(
        got.out,
        name=name,
        asked=asked_of(state, to=step.to, by=step.by),
        current=current,
        target=target,
        tries=got.tries,
    )
    rec = with_ask(got.out.log[-1], keys, what=name, target=keys["target"]["drape"])
    return replace(got.out, log=(*got.out.log[:-1], rec))


def scale_by(
    state: EditState, step: ScaleStep, factor: float, *, options: EditOptions
) -> EditState:
    """Scale a region of the drape by ``factor``; the rest follows by as-rigid-as-possible
    deformation.

    The region's triangles are mapped by ``c + A (p - c)`` with ``c`` the region's centroid
    and ``A`` from :func:`scale_matrix`. Panels wholly inside a ``uniform`` scale move evenly
    (a similarity: their outline keeps its shape); an ``around`` or ``along`` scale is no
    similarity of a panel's pattern (a cone's gore widens at the hem by its radius, a sleeve's
    rectangle widens but keeps its length), nor is a panel partly inside or moved only by the
    follow-up deformation: their outlines are free, so the pattern takes the widths asked.
    """
    g, V3 = state.base, state.V3
    faces = region_faces(step.region, g, V3, state.panels)
    warnings: list[str] = []
    # with axis: auto, each connected part of the region about its own axis and centroid
    # (both sleeves of a shirt: each around its own arm, not around one axis through both)
    parts = region_parts(g.F3, faces, len(V3)) if step.axis == "auto" else [faces]
    in_region = np.zeros(len(V3), dtype=bool)
    in_region[g.F3[faces]] = True
    handles = np.flatnonzero(in_region)  # sorted, as np.unique (a mask is cheaper)
    moved = V3[handles].copy()
    row = np.full(len(V3), -1, dtype=np.int64)
    row[handles] = np.arange(len(handles))
    records = []
    for part in parts:  # a loop over the region's connected parts (a few)
        if step.axis != "auto":
            ax = unit_vector(step.axis, "axis")
            c = region_centroid(V3, g.F3, part)
            A = scale_matrix(step.direction, ax, factor)
            r = row[np.unique(g.F3[part])]
            moved[r] = c + (V3[handles[r]] - c) @ A.T
            records.append((ax, c, int(part.size)))
            continue
        pieces = limb_pieces(g, part) if options.body is None else [Piece(part, True, None)]
        for verts, target, rec in piece_moves(V3, g.F3, pieces, step, factor, options):
            moved[row[verts]] = target
            records.append(rec)
        warnings += auto_axis_warnings(
            V3, g.F3, pieces[0].faces, records[-len(pieces)][0], options, frame=g.frame
        )
    ax, c = records[0][0], records[0][1]
    used = np.zeros(len(V3), dtype=bool)
    used[g.F3] = True
    if np.all(in_region[used]):
        V_new = V3.copy()
        V_new[handles] = moved
    else:
        V_new = arap_deform(V3, g.F3, handles, moved)
        V_new = rigid_apart(g, V_new, state.panels, in_region, handles, moved, V3=V3)
    face_in = np.zeros(g.n_faces, dtype=bool)
    face_in[faces] = True
    changed = np.any(V_new != V3, axis=1)
    even = state.even.copy()
    similar = step.direction == "uniform"
    for p in state.panels:  # a loop over panels, not triangles
        inside = bool(face_in[p.faces].all())
        still = not bool(changed[g.F3[p.faces]].any())
        even[p.index] &= (inside and similar) or still
    rec = {
        "op": "scale",
        "direction": step.direction,
        "factor": factor,
        "axis": [round(float(x), 6) for x in ax],
        "centroid": [round(float(x), 6) for x in c],
        "triangles": int(faces.size),
    }
    if len(records) > 1:
        rec["parts"] = [
            {
                "axis": [round(float(x), 6) for x in a],
                "centroid": [round(float(x), 6) for x in cc],
                "triangles": t,
            }
            for a, cc, t in records
        ]
    if warnings:
        rec["warnings"] = warnings
    return replace(state, V3=V_new, even=even, log=(*state.log, rec))


def piece_moves(
    V3: np.ndarray, F3: np.ndarray, pieces: list, step: ScaleStep, factor: float, options
) -> list[tuple[np.ndarray, np.ndarray, tuple]]:
    """Where ``axis: auto`` moves a part's trunk and limbs (:func:`ptailor.edits.limbs.
    limb_pieces`), each about its own axis: the trunk about its centroid, a limb about its
    joint carried where the trunk's map takes the joint, the joint keeping the trunk's map.

    Returns
    -------
    list of (verts, target, record)
        ``verts`` ``(j,)`` drape vertices, ``target`` ``(j, 3)`` their new places, and
        ``(axis, centre, triangles)`` for the step's record; the trunk first.
    """
    out = []
    c_t, A_t = np.zeros(3), np.eye(3)
    for pc in pieces:  # a loop over the part's trunk and limbs (three at most)
        ax = region_axis(V3, F3, pc.faces, body=options.body)
        A = scale_matrix(step.direction, ax, factor)
        verts = np.unique(F3[pc.faces])
        if pc.trunk:
            c = c_t = region_centroid(V3, F3, pc.faces)
            A_t, shift = A, np.zeros(3)
        else:
            c = V3[pc.joint].mean(axis=0)
            shift = (c - c_t) @ A_t.T + c_t - c
            verts = np.setdiff1d(verts, pc.joint, assume_unique=True)
        out.append((verts, c + shift + (V3[verts] - c) @ A.T, (ax, c, int(pc.faces.size))))
    return out


def region_parts(F3: np.ndarray, faces: np.ndarray, n: int) -> list[np.ndarray]:
    """The region's triangles ``faces`` split into its connected parts on the drape
    (triangles sharing a vertex), largest first; the whole region as one part where a
    part holds less than ``edit_tol.REGION_PART_MIN`` of its triangles.

    Parameters
    ----------
    F3 : (m, 3) int array
    faces : (k,) int array
    n : int
        Drape vertices.

    Returns
    -------
    list of (k_i,) int arrays
    """
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components

    T = F3[faces]
    adj = sp.csr_matrix(
        (np.ones(3 * len(T)), (T.ravel(), np.roll(T, -1, axis=1).ravel())), shape=(n, n)
    )
    lab = connected_components(adj, directed=False)[1][T[:, 0]]
    _, inv, cnt = np.unique(lab, return_inverse=True, return_counts=True)
    if len(cnt) == 1 or cnt.min() < edit_tol.REGION_PART_MIN * len(faces):
        return [faces]  # one part, or crumbs (a box through a fold): the region as one
    order = np.argsort(-cnt, kind="stable")
    return [faces[inv == k] for k in order]


def auto_axis_warnings(
    V3: np.ndarray,
    F3: np.ndarray,
    faces: np.ndarray,
    ax: np.ndarray,
    options: EditOptions,
    *,
    frame: Frame,
) -> list[str]:
    """A warning where ``axis: auto`` had no tube to go by (the region's normals avoid no
    one direction: a whole T-shirt, torso and sleeves) and its fallback, the direction of
    largest extent, lies more than ``edit_tol.AUTO_AXIS_UP_DEG`` from the garment's up: the
    shared tshirt's came out 55 degrees from vertical, and a symmetric ``along`` x1.1 grew
    one sleeve 10.8 % and the other 2.8 %. A tube's axis (a sleeve's: horizontal in a
    T-pose) and a body's are what they are."""
    from ptailor.geometry.tube_axis import tube_axis

    if options.body is not None or tube_axis(V3, F3[faces]) is not None:
        return []
    up = frame.matrix()[1]
    angle = float(np.degrees(np.arccos(min(1.0, abs(float(ax @ up))))))
    if angle <= edit_tol.AUTO_AXIS_UP_DEG:
        return []
    return [
        f"axis: auto found no tube in the region and took its longest extent, {angle:.0f}"
        f" degrees from the garment's up {list(frame.up)}: give the axis (axis: [x, y, z])"
        " or a smaller region (one sleeve, the torso)"
    ]
