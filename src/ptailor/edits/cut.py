"""``cut``: cut the garment with a plane or a polyline sketched in a named view."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ptailor import tolerances as tol
from ptailor.edits import tolerances as edit_tol
from ptailor.edits.achieved import neck_drop, sketch_reach
from ptailor.edits.checks import VEC3, boolean, choice, is_number, vector3, with_schema
from ptailor.edits.corners import embed_polyline, mean_edge
from ptailor.edits.crumbs import drop_crumbs, drop_faces
from ptailor.edits.opening import find_opening, opening_spec
from ptailor.edits.pattern_distance import refine_crossings
from ptailor.edits.region import region_centroid, unit_vector
from ptailor.edits.registry import Step, checked, register
from ptailor.edits.sketch_lines import polyline_side, segments_meet_box
from ptailor.edits.state import EditOptions, EditState
from ptailor.edits.surgery import Crossing, SplitResult, panel_changes, split_keep
from ptailor.errors import PtailorError
from ptailor.geometry.labels import used_indices
from ptailor.model.frame import Frame
from ptailor.model.symmetry import SagittalPlane, mirror_points

VIEWS = ("front", "back", "left", "right", "top", "bottom")


@with_schema({"anyOf": [{"enum": list(VIEWS)}, VEC3]})
def view_spec(x: Any, where: str) -> list[str]:
    """A named view or a view direction ``[x, y, z]`` (from the viewer into the garment)."""
    if x in VIEWS:
        return []
    p = vector3(x, where)
    if p or all(v == 0 for v in x):
        return [f"{where}: expected one of {', '.join(VIEWS)} or [x, y, z], got {x!r}"]
    return []


@with_schema(
    {
        "type": "array",
        "minItems": 2,
        "items": {"type": "array", "items": {"type": "number"}, "minItems": 2, "maxItems": 2},
    }
)
def sketch_spec(x: Any, where: str) -> list[str]:
    """A polyline of at least two distinct 2D points."""
    ok = (
        isinstance(x, list)
        and len(x) >= 2
        and all(isinstance(q, list) and len(q) == 2 and all(is_number(v) for v in q) for q in x)
    )
    if not ok:
        return [f"{where}: expected a polyline [[u, v], [u, v], ...] of at least 2 points"]
    return []


@with_schema(
    {
        "type": "object",
        "properties": {"point": VEC3, "normal": VEC3},
        "required": ["point", "normal"],
        "additionalProperties": False,
    }
)
def plane_spec(x: Any, where: str) -> list[str]:
    """``{point: [x, y, z], normal: [x, y, z]}``."""
    if not isinstance(x, dict) or set(x) != {"point", "normal"}:
        return [f"{where}: expected {{point: [x, y, z], normal: [x, y, z]}}"]
    probs = vector3(x["point"], f"{where}.point") + vector3(x["normal"], f"{where}.normal")
    if not probs and all(v == 0 for v in x["normal"]):
        probs.append(f"{where}.normal: must not be zero")
    return probs


def sagittal_mirror_plane(V: np.ndarray, F: np.ndarray, *, frame: Frame) -> SagittalPlane:
    """The plane a cut mirrors across: it contains the up and front axes and passes through
    the drape's area-weighted centroid (a fitted plane comes with the symmetry step)."""
    return SagittalPlane(
        point=region_centroid(V, F, np.arange(len(F))),
        normal=np.asarray(frame.side),
        rms=0.0,
        max=0.0,
    )


def sagittal_mirror(V: np.ndarray, F: np.ndarray, *, frame: Frame) -> np.ndarray:
    """Mirror drape positions across :func:`sagittal_mirror_plane`."""
    return mirror_points(V, sagittal_mirror_plane(V, F, frame=frame))


def view_frame(view: Any, *, frame: Frame) -> np.ndarray:
    """Rows ``(right, up, direction)`` of a view; ``direction`` points from the viewer.

    Named views use the garment's axes: ``front`` looks at the garment's front (the viewer
    stands in front, looking along ``-front``), ``left`` stands at the wearer's left, and so
    on; ``top`` looks down with the front at the bottom of the image.

    Parameters
    ----------
    view : str or (3,) sequence of float
        A named view or the direction the viewer looks along.
    frame : Frame
        The garment's frame.

    Returns
    -------
    (3, 3) float array
    """
    left, u, f = frame.matrix()
    dirs = {
        "front": (-f, u),
        "back": (f, u),
        "left": (-left, u),
        "right": (left, u),
        "top": (-u, f),
        "bottom": (u, -f),
    }
    if isinstance(view, str):
        d, img_up = dirs[view]
    else:
        d = unit_vector(view, "view")
        img_up = u - d * (u @ d)
        if np.linalg.norm(img_up) < edit_tol.CUT_VIEW_PARALLEL:
            img_up = f - d * (f @ d)
        img_up /= np.linalg.norm(img_up)
    right = np.cross(d, img_up)
    return np.stack([right, img_up, d])


@with_schema({"anyOf": [{"$ref": "#/$defs/opening"}, {"type": "array", "minItems": 1}]})
def origin_spec(x: Any, where: str) -> list[str]:
    """An opening, or a list of openings (the first the garment has)."""
    if isinstance(x, list):
        if not x:
            return [f"{where}: expected an opening or a list of openings, got []"]
        return [p for i, o in enumerate(x) for p in opening_spec(o, f"{where}[{i}]")]
    return opening_spec(x, where)


@dataclass(frozen=True, kw_only=True)
class CutStep(Step):
    """A ``cut`` step (see :func:`cut`): a plane, or a sketch in a view (exactly one).

    Attributes
    ----------
    plane : dict or None
        ``{point: [x, y, z], normal: [x, y, z]}``.
    view : str or list of float
        The sketch's view: a name or a view direction ``[x, y, z]``.
    sketch : list of [u, v] or None
        A polyline in the view's image plane.
    remove : {"above", "below", "left", "right"}
        The side of the sketch removed.
    layers : {"both", "near"}
    origin : str, dict, list or None
        An opening (or a list: the first the garment has) the sketch is measured from.
    symmetric : bool
        Also cut the mirror image (a parameter of its own: the cut mirrors itself).
    """

    op = "cut"
    plane: dict[str, list[float]] | None = field(
        default=None,
        metadata=checked(plane_spec, "{point, normal}: removes the side the normal points to"),
    )
    view: str | list[float] = field(
        default="front", metadata=checked(view_spec, "front | back | left | right | top | bottom")
    )
    sketch: list[list[float]] | None = field(
        default=None,
        metadata=checked(sketch_spec, "polyline [[u, v], ...] in the view's image plane"),
    )
    remove: str = field(
        default="above", metadata=checked(choice("above", "below", "left", "right"))
    )
    layers: str = field(default="both", metadata=checked(choice("both", "near")))
    origin: str | dict[str, int] | list[Any] | None = field(
        default=None,
        metadata=checked(
            origin_spec,
            "an opening (or a list: the first the garment has): the sketch is measured "
            "from its centre across and its lowest point up in the view (a neckline: the "
            "front neck point)",
        ),
    )
    symmetric: bool = field(default=False, metadata=checked(boolean, "also cut the mirror image"))


def origin_opening(state: EditState, spec: Any) -> tuple[str, np.ndarray]:
    """The opening a sketch's ``origin`` names (of a list, the first the garment has):
    its name and drape loop."""
    specs = spec if isinstance(spec, list) else [spec]
    for o in specs[:-1]:  # a loop over the few openings named
        try:
            return find_opening(state, o)
        except PtailorError:
            pass
    return find_opening(state, specs[-1])


def sketch_origin(state: EditState, step: CutStep, *, options: EditOptions) -> np.ndarray:
    """Where a sketch's ``[0, 0]`` lies in its view, ``(2,)``: the view's own origin, or
    with ``origin: OPENING`` that opening's centre across and its lowest point up (a
    neckline's front neck point in the front view), so one sketch fits garments of any
    height and placement. A list of openings takes the first the garment has."""
    if step.origin is None:
        return np.zeros(2)
    frame = view_frame(step.view, frame=state.frame)
    _, loop = origin_opening(state, step.origin)
    X = state.V3[loop] @ frame[:2].T
    if step.layers == "near":  # the layer facing the viewer: its lowest point
        used = used_indices(state.base.F3, len(state.V3))
        mid = float(np.median(state.V3[used] @ frame[2]))
        near = state.V3[loop] @ frame[2] <= mid
        if near.any():
            return np.array([float(X[:, 0].mean()), float(X[near, 1].min())])
    return np.array([float(X[:, 0].mean()), float(X[:, 1].min())])


def sketch_field(
    V: np.ndarray,
    step: CutStep,
    *,
    frame: Frame,
    origin: np.ndarray | None = None,
    mid: float | None = None,
) -> np.ndarray:
    """Field whose negative side is what a sketch cut removes (the sketch's points offset
    by ``origin``, :func:`sketch_origin`), seen under the garment's ``frame``; with
    ``layers: near``, only in front of the depth ``mid`` (default: the median depth of
    ``V``)."""
    X = V @ view_frame(step.view, frame=frame).T  # (right, up, depth)
    Q = np.asarray(step.sketch, float) + (0.0 if origin is None else origin)
    side = polyline_side(X[:, :2], Q)
    # which way is "above" / "left" for this polyline's direction of travel
    travel = Q[-1] - Q[0]
    left_normal = np.array([-travel[1], travel[0]])
    want = {"above": [0, 1], "below": [0, -1], "left": [-1, 0], "right": [1, 0]}[step.remove]
    sign = 1.0 if left_normal @ np.asarray(want, float) > 0 else -1.0
    phi = -sign * side  # removed where phi < 0
    if step.layers == "near":
        if mid is None:
            mid = float(np.median(X[np.isfinite(X[:, 2]), 2]))
        phi = np.maximum(phi, X[:, 2] - mid)  # only the layer nearer than the middle goes
    return phi


@dataclass(frozen=True)
class CutField:
    """A cut's field as a function of drape points, its constants fixed on one state (the
    layers' middle depth, the mirror plane), so points added later are cut alike.

    Attributes
    ----------
    step : CutStep
    frame : Frame
    origin : (2,) float array or None
        The sketch's origin in its view (a sketch), None for a plane.
    mids : tuple of float or None
        The middle depth of the drape and of its mirror image (``layers: near``).
    plane : SagittalPlane or None
        The mirror plane (``symmetric``).
    """

    step: CutStep
    frame: Frame
    origin: np.ndarray | None
    mids: tuple[float | None, float | None]
    plane: SagittalPlane | None

    def one(self, X: np.ndarray, mid: float | None) -> np.ndarray:
        """The field of the step itself (not mirrored), ``(n,)``."""
        if self.step.plane is not None:
            p = np.asarray(self.step.plane["point"], float)
            return -(X - p) @ unit_vector(self.step.plane["normal"], "plane normal")
        return sketch_field(X, self.step, frame=self.frame, origin=self.origin, mid=mid)

    def __call__(self, X: np.ndarray) -> np.ndarray:
        """The field, ``(n,)``: removed where negative (the cut's and its mirror image's)."""
        phi = self.one(X, self.mids[0])
        if self.plane is not None:
            phi = np.minimum(phi, self.one(mirror_points(X, self.plane), self.mids[1]))
        return phi

    def near(self, X: np.ndarray) -> np.ndarray:
        """Which drape points ``(n, 3)`` lie in front of the layers' middle (or its mirror
        image's), ``(n,)`` bool: where the sketch cuts; all for ``layers: both``."""
        if self.mids[0] is None:
            return np.ones(len(X), bool)
        d = view_frame(self.step.view, frame=self.frame)[2]
        out = X @ d < self.mids[0]
        if self.plane is not None:
            out |= self.mirror(X) @ d < self.mids[1]
        return out

    def mirror(self, X: np.ndarray) -> np.ndarray:
        """Drape points mirrored across the cut's plane (``symmetric``), ``(n, 3)``."""
        return mirror_points(X, self.plane)


def cut_field(state: EditState, step: CutStep, *, origin: np.ndarray | None) -> CutField:
    """The :class:`CutField` of a step on ``state``."""
    V, frame = state.V3, state.frame
    plane = None
    if step.symmetric:
        plane = sagittal_mirror_plane(V, state.base.F3, frame=frame)
    mids: tuple[float | None, float | None] = (None, None)
    if step.sketch is not None and step.layers == "near":
        d = view_frame(step.view, frame=frame)[2]
        mids = (
            float(np.median(V @ d)),
            float(np.median(mirror_points(V, plane) @ d)) if plane is not None else None,
        )
    return CutField(step=step, frame=frame, origin=origin, mids=mids, plane=plane)


def one_tool(step: CutStep, where: str) -> list[str]:
    """A cut has a plane or a sketch, not both."""
    if (step.plane is None) == (step.sketch is None):
        return [f"{where}: cut needs exactly one of 'plane' or 'sketch'"]
    return []


def check_sketch_meets(state: EditState, step: CutStep, *, origin: np.ndarray) -> None:
    """Raise when a sketch (offset by ``origin``) does not overlap the garment in its view."""
    used = used_indices(state.base.F3, len(state.V3))
    frame = view_frame(step.view, frame=state.frame)
    X2 = state.V3[used] @ frame[:2].T
    lo, hi = X2.min(axis=0), X2.max(axis=0)
    pad = tol.ROUNDING_REL * max(float(np.max(hi - lo)), tol.TINY)
    if not segments_meet_box(np.asarray(step.sketch, float) + origin, lo - pad, hi + pad):
        raise PtailorError(
            "the cut's sketch misses the garment: it does not overlap the garment in its "
            f"view (the garment spans "
            f"{lo[0]:.4g}..{hi[0]:.4g} across and {lo[1]:.4g}..{hi[1]:.4g} up): "
            "nothing to cut"
        )


def sketch_corners(state: EditState, fld: CutField) -> tuple[EditState, int]:
    """The sketch embedded in the garment where the cut passes (its corners made
    vertices, and its crossings with edges it crosses twice), and its mirror image for a
    symmetric cut (:func:`ptailor.edits.corners.embed_polyline`); the state and how many
    vertices."""
    Q = np.asarray(fld.step.sketch, float) + fld.origin
    rows = view_frame(fld.step.view, frame=fld.frame)[:2].T
    state, n = embed_polyline(state, lambda X: X @ rows, Q, field=fld)
    if fld.plane is not None:
        state, m = embed_polyline(state, lambda X: fld.mirror(X) @ rows, Q, field=fld)
        n += m
    return state, n


@dataclass(frozen=True)
class DrapeLevel:
    """A cut's field read where :func:`ptailor.edits.pattern_distance.refine_crossings`
    reads a pattern distance (``at(points, panel)``): the same root finding on the drape."""

    fld: CutField

    def at(self, X: np.ndarray, panel: np.ndarray) -> np.ndarray:
        """The field at drape points ``(r, 3)``, ``(r,)`` (``panel`` unused)."""
        return self.fld(X)


def exact_crossings(state: EditState, fld: CutField) -> Crossing:
    """Where the split cuts each crossed edge: the root of the cut's field along it in the
    edited drape (:func:`ptailor.edits.surgery.split_keep`'s ``crossing``). The linear
    estimate is exact for a plane, not for a distance to a polyline next to a corner: there
    the new edge bowed off the V's arms (0.47 cm on the shared tshirt, 0.31 on a 4 cm tee)."""
    g = state.base

    def crossing(a2: np.ndarray, b2: np.ndarray, t: np.ndarray, face: np.ndarray) -> np.ndarray:
        a3 = g.F3[face, np.argmax(g.F2[face] == a2[:, None], axis=1)]
        b3 = g.F3[face, np.argmax(g.F2[face] == b2[:, None], axis=1)]
        return refine_crossings(DrapeLevel(fld), state.V3, a3, b3, t, face, 0.0)

    return crossing


def on_level_faces(before: EditState, res: SplitResult, fld: CutField) -> np.ndarray:
    """Triangles of a split's result whose three corners lie on the cut (within the
    split's snap) and whose centroid the cut removes, ``(m,)`` bool: the split keeps a
    triangle with no corner on the removed side, but the tip of a V embedded in the mesh
    can leave one wholly inside the V."""
    g = res.state.base
    h = mean_edge(before.V3, before.base.F3)
    zero = np.abs(fld(res.state.V3)) <= edit_tol.SPLIT_SNAP_REL * h
    inside = zero[g.F3].all(axis=1)
    if inside.any():
        mid = res.state.V3[g.F3[inside]].mean(axis=1)
        inside[inside] = fld(mid) < -tol.ROUNDING_REL * h  # not a sliver along the cut
    return inside


def cut_reach(before: EditState, res: SplitResult, fld: CutField) -> dict:
    """How far a sketch cut reaches from its origin, asked and achieved, and with the
    neckline as its origin the garment's ``neck_drop`` before and after (drape, the
    garment's units), for the step record (:func:`ptailor.edits.achieved.sketch_reach`)."""
    step = fld.step
    rows = view_frame(step.view, frame=fld.frame)
    out = {
        "depth": sketch_reach(
            res, rows=rows, sketch=np.asarray(step.sketch, float), origin=fld.origin,
            remove=step.remove, near=fld.near,
        )
    }  # fmt: skip
    if step.origin is not None and origin_opening(before, step.origin)[0] == "neckline":
        after = neck_drop(res.state.base, res.state.V3)
        if after is not None:  # a cut through the straps leaves no neckline
            out["neck_drop"] = {"before": neck_drop(before.base, before.V3), "after": after}
    return out


@register(CutStep, check=one_tool)
def cut(state: EditState, step: CutStep, *, options: EditOptions) -> EditState:
    """Cut with a plane, or with a sketched polyline extruded along the view direction.

    A sketch's corners inside the garment are first made vertices
    (:func:`ptailor.edits.corners.embed_polyline`), so the new edge passes exactly through
    them; then triangles are split exactly on the cutting surface and the chosen side is
    removed, the pattern following by barycentric transfer; a piece the cut leaves smaller
    than a few triangles goes with it (:func:`ptailor.edits.crumbs.drop_crumbs`, warned).
    """
    o = None
    if step.sketch is not None:
        o = sketch_origin(state, step, options=options)
        check_sketch_meets(state, step, origin=o)
    fld = cut_field(state, step, origin=o)
    inserted = 0
    if step.sketch is not None:
        state, inserted = sketch_corners(state, fld)
    phi = fld(state.V3)
    used = used_indices(state.base.F3, len(state.V3))
    if np.all(phi[used] >= 0):
        raise PtailorError(f"the cut's {'plane' if o is None else 'sketch'} misses the garment: "
                           "nothing to remove")  # fmt: skip
    res = split_keep(state, phi, crossing=exact_crossings(state, fld) if o is not None else None)
    inside = on_level_faces(state, res, fld)
    if inside.any():
        res = drop_faces(state, res, ~inside)
    res, dropped = drop_crumbs(state, res)
    panels, warnings = panel_changes(state, res)
    rec = {
        "op": "cut",
        "by": "plane" if o is None else "sketch",
        **({"origin": [round(float(x), 6) for x in o]} if step.origin is not None else {}),
        "removed_triangles": res.removed_triangles,
        "split_triangles": res.split_triangles,
        "new_edge_vertices": len(res.new_vertices3),
        **({"corner_vertices": inserted} if o is not None else {}),
        **(cut_reach(state, res, fld) if o is not None else {}),
        **({"dropped": dropped["pieces"]} if dropped["pieces"] else {}),
        "panels": panels,
    }
    warnings = dropped["warnings"] + warnings
    if warnings:
        rec["warnings"] = warnings
    return replace(res.state, log=(*state.log, rec))
