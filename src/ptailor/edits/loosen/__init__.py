"""``loosen`` / ``tighten``: ease a region along its normals, or over-sketch a silhouette.

Two forms of one step; both ops accept both, and in the silhouette form the op name is
only the user's intent (the sketch decides whether the outline moves in or out)::

    - {op: loosen, region: {panels: [front, back]}, by: 2}
    - {op: loosen, region: {panels: [front, back]}, girth: 2}
    - {op: tighten, view: front, silhouette: [[-22, 95], [-19, 80], [-21, 60]]}

*Offset* (``region`` + ``by``): the region moves along its outward normals, smoothed so
that wrinkles and folds ride along instead of folding over, by ``+by`` (loosen) or ``-by``
(tighten), falling off smoothly to zero at its border with the rest of the garment, which
stays where it is. With ``girth`` instead of ``by``, the offset is the one that adds (or,
tightening, removes) that much girth at every level of the region, measured on the drape
the offset makes (:mod:`~ptailor.edits.loosen.girth`).

*Silhouette* (``view`` + ``silhouette``): the garment's outline in the view is found row by
row (the left and right extremes of each horizontal band of the image, per connected piece
of the garment in the sketch's rows); outline points in the sketch's rows and near it move
horizontally onto it, and each one's horizontal ring follows, scaled about its centre so a
round cross-section stays round; the rest follows by as-rigid-as-possible deformation.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any, ClassVar

import numpy as np

from ptailor.edits import tolerances as edit_tol
from ptailor.edits.asks import ask_tolerance, asked_of, cm, region_girths, solve, with_ask
from ptailor.edits.checks import choice, number
from ptailor.edits.checks import region as region_spec
from ptailor.edits.coverage import girth_coverage, with_coverage
from ptailor.edits.cut import sketch_spec, view_frame, view_spec
from ptailor.edits.loosen.girth import Cloth, girth_change, girth_levels
from ptailor.edits.loosen.normals import (
    normal_smoother,
    outward_normals,
    panel_orientation,
    turned_faces,
)
from ptailor.edits.loosen.offset import falloff_weights, offset_region
from ptailor.edits.loosen.silhouette import row_crossings, silhouette_targets
from ptailor.edits.region import region_faces
from ptailor.edits.registry import Step, checked, register
from ptailor.edits.state import EditOptions, EditState
from ptailor.errors import LimitError, PtailorError
from ptailor.method.deform import arap_deform
from ptailor.model.garment import panel_labels
from ptailor.model.structure import structure

__all__ = [
    "LoosenStep",
    "TightenStep",
    "falloff_weights",
    "loosen",
    "normal_smoother",
    "outward_normals",
    "panel_orientation",
    "row_crossings",
    "turned_faces",
]


def view_name(view: Any) -> str:
    """A view as the user wrote it: ``front`` or ``[x, y, z]``."""
    return view if isinstance(view, str) else "[" + ", ".join(f"{float(x):g}" for x in view) + "]"


@dataclass(frozen=True, kw_only=True)
class LoosenStep(Step):
    """A ``loosen`` step (see :func:`loosen`): the offset form (``by`` or ``girth``, with
    ``region``) or the silhouette form (``silhouette``, with ``view``), exactly one.

    Attributes
    ----------
    region : str, dict or None
        The offset form's region; None: not given (:attr:`offset_region`).
    by : float or None
        The offset along the normals, recipe units.
    girth : float or None
        The girth added (``loosen``) or removed (``tighten``) at every level of the region,
        recipe units: the offset is the one that gives it.
    on : str or None
        With ``girth``: ``drape``, ``pattern`` or ``both`` (None: :attr:`girth_on`).
    view : str, list of float or None
        The silhouette form's view; None: not given (:attr:`sketch_view`).
    silhouette : list of [u, v] or None
        The over-sketched outline in the view's image plane.
    """

    op = "loosen"
    #: What the offset form edits without ``region``, and the silhouette form's view
    #: without ``view``.
    DEFAULT_REGION: ClassVar[str] = "all"
    DEFAULT_VIEW: ClassVar[str] = "front"
    region: str | dict[str, Any] | None = field(
        default=None,
        metadata=checked(
            region_spec,
            "all | {panels: [...]} | {part: torso, sleeves, ...} | {box: {min, max}} (with by or "
            "girth; default all)",
        ),
    )
    by: float | None = field(
        default=None,
        metadata=checked(number(gt=0.0), "offset along the surface normals, recipe units"),
    )
    girth: float | None = field(
        default=None,
        metadata=checked(
            number(gt=0.0),
            "girth added (loosen) or removed (tighten) at every level of the region, recipe "
            "units, instead of by: the offset that gives it is found",
            echo_none=False,
        ),
    )
    on: str | None = field(
        default=None,
        metadata=checked(
            choice("drape", "pattern", "both"),
            "with girth: where the girth is added: drape (as worn), pattern (the flatten's "
            "pattern, predicted from each triangle's stretch) or both (their mean is the "
            "girth asked; default: they differ only on cloth worn stretched)",
            echo_none=False,
        ),
    )
    view: str | list[float] | None = field(
        default=None,
        metadata=checked(
            view_spec, "front | back | left | right | top | bottom | [x, y, z] (default front)"
        ),
    )
    silhouette: list[list[float]] | None = field(
        default=None,
        metadata=checked(
            sketch_spec, "over-sketched outline [[u, v], ...] in the view's image plane"
        ),
    )

    @property
    def girth_on(self) -> str:
        """Where ``girth`` is added: the step's ``on``, else ``both``."""
        return "both" if self.on is None else self.on

    @property
    def offset_region(self) -> str | dict[str, Any]:
        """The offset form's region: the step's, else :attr:`DEFAULT_REGION`."""
        return self.DEFAULT_REGION if self.region is None else self.region

    @property
    def sketch_view(self) -> str | list[float]:
        """The silhouette form's view: the step's, else :attr:`DEFAULT_VIEW`."""
        return self.DEFAULT_VIEW if self.view is None else self.view


@dataclass(frozen=True, kw_only=True)
class TightenStep(LoosenStep):
    """A ``tighten`` step: :class:`LoosenStep`'s forms, the offset inward."""

    op = "tighten"


def one_form(step: LoosenStep, where: str) -> list[str]:
    """Exactly one of ``by`` or ``girth`` (with ``region``) or ``silhouette`` (with
    ``view``)."""
    forms = {"by": step.by, "girth": step.girth, "silhouette": step.silhouette}
    given = [k for k, v in forms.items() if v is not None]
    if len(given) != 1:
        return [
            f"{where}: {step.op} needs exactly one of 'by' or 'girth' (with 'region') or "
            "'silhouette' (with 'view')" + (f", got {' and '.join(given)}" if given else "")
        ]
    if given[0] != "silhouette" and step.view is not None:
        return [f"{where}: 'view' goes with 'silhouette', not with '{given[0]}'"]
    if given[0] != "girth" and step.on is not None:
        return [f"{where}: 'on' goes with 'girth', not with '{given[0]}'"]
    if given[0] == "silhouette" and step.region is not None:
        return [f"{where}: 'region' goes with 'by' or 'girth', not with 'silhouette'"]
    return []


def moved_panels_uneven(state: EditState, V_new: np.ndarray) -> np.ndarray:
    """``state.even`` with every panel whose drape vertices moved set to False."""
    changed = np.any(V_new != state.V3, axis=1)
    moved = np.zeros(len(state.panels), dtype=bool)
    fp = panel_labels(state.panels, len(state.base.F3))
    hit = changed[state.base.F3].any(axis=1)
    moved[np.unique(fp[hit & (fp >= 0)])] = True
    return state.even & ~moved


def loosen(state: EditState, step: LoosenStep, *, options: EditOptions) -> EditState:
    """Loosen or tighten: offset a region along its normals, or over-sketch a silhouette.

    Offset form: see :func:`offset_region` (``+by`` for loosen, ``-by`` for tighten; with
    ``girth``, the offset found by :func:`girth_offset`). Silhouette form: see
    :func:`silhouette_targets`; the rest of the drape follows by
    :func:`ptailor.method.deform.arap_deform` with the moved rings as handles. Every panel
    whose drape moved loses ``even`` (its outline is free when flattened).
    """
    if step.silhouette is None:
        V_new, rec = offset_step(state, step, options=options)
    else:
        V_new, rec = silhouette_step(state, step, options=options)
    even = moved_panels_uneven(state, V_new)
    return replace(state, V3=V_new, even=even, log=(*state.log, rec))


def offset_step(
    state: EditState, step: LoosenStep, *, options: EditOptions
) -> tuple[np.ndarray, dict]:
    """The offset form: the edited drape ``(n, 3)`` and the step's record."""
    g, V3 = state.base, state.V3
    faces = region_faces(step.offset_region, g, V3, state.panels)
    sign = 1.0 if step.op == "loosen" else -1.0
    # the seam pairs the flatten after the edit takes from the same structure
    pairs = structure(g).seam_halfedges

    def offset(by: float) -> tuple[np.ndarray, float]:
        return offset_region(
            V3,
            g.F3,
            g.F2,
            state.panels,
            faces,
            by=sign * by,
            frame=g.frame,
            pairs=pairs,
            symbolic=options.symbolic,
        )

    if step.girth is None:
        by, asked = float(step.by), {}
        try:
            V_new, sigma = offset(by)
        except LimitError as err:
            raise refusal(err, by, offset) from None
    else:
        by, (V_new, sigma), asked = girth_offset(state, step, faces, offset)
    rec = {"op": step.op, "by": by, "triangles": int(faces.size), "smoothing": round(sigma, 6)}
    if asked:
        rec = with_ask(rec, asked, what="girth", target=asked["asked"]["girth"])
    if step.offset_region != "all":  # part of a girth: the share it holds, where short
        rec = with_coverage(rec, girth_coverage(V3, g.F3, faces, garment=g))
    return V_new, rec


def refusal(err: LimitError, by: float, offset) -> LimitError:
    """``err`` (an offset of ``by`` refused) with the largest of a few smaller offsets that
    passes, ``by`` times ``LOOSEN_PROBE_FRACTIONS``, named; or that none of them does.

    A refusal need not be monotone in ``by``: the falloff's band and the normals' smoothing
    both widen with ``by``, so near the region's border (where the falloff ramps up) a
    larger offset moves a tight fold less, and along normals smoothed wider, than a smaller
    one. Only smaller values are probed: they are what a user who asked ``by`` can take.
    """
    for frac in edit_tol.LOOSEN_PROBE_FRACTIONS:  # a loop over a few trial offsets
        try:
            offset(by * frac)
        except LimitError:
            continue
        return LimitError(f"{err.message} (by: {by * frac:.3g} passes)", path=err.path)
    tried = ", ".join(f"{by * f:.3g}" for f in edit_tol.LOOSEN_PROBE_FRACTIONS)
    return LimitError(f"{err.message} (nor do by: {tried})", path=err.path)


def girth_offset(state: EditState, step: LoosenStep, faces: np.ndarray, offset) -> tuple:
    """The offset that adds (loosen) or removes (tighten) ``step.girth`` at every level of
    the region, measured on the drape each trial offset makes (so the falloff counts).

    The first trial is ``girth / (2 pi)`` (a closed girth grows ``2 pi by``); secant steps
    on the measured change (:func:`ptailor.edits.asks.solve`, from no offset: no change)
    correct it. Returns ``(by, offset(by), record keys)``: ``asked``, ``achieved`` (the
    mean girth change over the levels, cm), ``levels`` and ``tries``.
    """
    g = state.base
    cloth = Cloth(g.V3, g.V2, g.F2)
    levels = girth_levels(state.V3, g.F3, faces, frame=g.frame, cloth=cloth)
    sign = 1.0 if step.op == "loosen" else -1.0
    want = float(step.girth)
    weight = {"drape": 1.0, "pattern": 0.0, "both": 0.5}[step.girth_on]

    def run(by: float) -> tuple[tuple[tuple[np.ndarray, float], tuple], float]:
        try:
            out = offset(by)
        except PtailorError as exc:
            raise PtailorError(
                f"girth {want:g} (an offset of {by:.3g}): "
                + str(exc).replace("a smaller 'by'", "a smaller 'girth'")
            ) from None
        d, p = (sign * x for x in girth_change(levels, out[0], g.F3, faces, cloth))
        return (out, (d, p)), weight * d + (1.0 - weight) * p

    got = solve(
        run,
        anchor=(0.0, 0.0),
        first=want / (2.0 * np.pi),
        target=want,
        tol=ask_tolerance(state),
        lower=0.0,
    )
    out, (d, p) = got.out
    k = cm(state)
    keys = {
        "asked": asked_of(state, girth=want) | {"on": step.girth_on},
        "achieved": {"drape": round(d * k, 4), "pattern_predicted": round(p * k, 4)},
        "levels": int(levels.heights.size),
        "tries": got.tries,
        "measures": region_girths(state, faces),
    }
    return got.x, out, keys


def silhouette_step(
    state: EditState, step: LoosenStep, *, options: EditOptions
) -> tuple[np.ndarray, dict]:
    """The silhouette form: the edited drape ``(n, 3)`` and the step's record."""
    g, V3 = state.base, state.V3
    view = step.sketch_view
    frame = view_frame(view, frame=g.frame)
    X = V3 @ frame.T
    T = g.F3
    h = float(np.linalg.norm(V3[T] - V3[np.roll(T, -1, axis=1)], axis=2).mean())
    handles, targets, change = silhouette_targets(
        X,
        T,
        np.asarray(step.silhouette, float),
        row=edit_tol.SILHOUETTE_ROW_EDGES * h,
        view_name=view_name(view),
    )
    moved = targets @ frame
    seen = np.zeros(len(V3), dtype=bool)
    seen[T] = True
    used = np.flatnonzero(seen)  # as np.unique(T), cheaper
    if handles.size == used.size and np.array_equal(handles, used):
        V_new = V3.copy()
        V_new[handles] = moved
    else:
        V_new = arap_deform(V3, T, handles, moved, symbolic=options.symbolic)
    rec = {
        "op": step.op,
        "view": view,
        "outline_points": int(change.size),
        "handles": int(handles.size),
        "change_mean": round(float(change.mean()), 6),
        "change_max": round(float(change[np.argmax(np.abs(change))]), 6),
    }
    return V_new, rec


register(LoosenStep, check=one_form)(loosen)
register(TightenStep, check=one_form)(loosen)
