"""``cut``: cut the garment with a plane or a polyline sketched in a named view."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ptailor import tolerances as tol
from ptailor.edits import tolerances as edit_tol
from ptailor.edits.checks import VEC3, boolean, choice, is_number, vector3, with_schema
from ptailor.edits.opening import find_opening, opening_spec
from ptailor.edits.region import region_centroid, unit_vector
from ptailor.edits.registry import Step, checked, register
from ptailor.edits.state import EditOptions, EditState
from ptailor.edits.surgery import panel_changes, split_keep
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


def sagittal_mirror(V: np.ndarray, F: np.ndarray, *, frame: Frame) -> np.ndarray:
    """Mirror drape positions across the sagittal plane.

    The plane contains the up and front axes and passes through the drape's area-weighted
    centroid (a fitted plane comes with the symmetry step).
    """
    plane = SagittalPlane(
        point=region_centroid(V, F, np.arange(len(F))),
        normal=np.asarray(frame.side),
        rms=0.0,
        max=0.0,
    )
    return mirror_points(V, plane)


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


def polyline_side(P: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """Signed distance of 2D points to a polyline extended straight beyond its ends.

    Positive on the left of the direction of travel. Uses the nearest segment (the end
    segments extended to infinity), so a polyline that crosses the garment splits it.

    Parameters
    ----------
    P : (n, 2) float array
    Q : (k, 2) float array
        Polyline, ``k >= 2``.

    Returns
    -------
    (n,) float array
    """
    A, B = Q[:-1], Q[1:]
    AB = B - A
    L2 = np.maximum((AB * AB).sum(1), tol.TINY)
    AP = P[:, None, :] - A[None]
    t = (AP * AB[None]).sum(2) / L2[None]
    lo = np.where(np.arange(len(A)) == 0, -np.inf, 0.0)
    hi = np.where(np.arange(len(A)) == len(A) - 1, np.inf, 1.0)
    t = np.clip(t, lo[None], hi[None])
    D = AP - t[..., None] * AB[None]
    dist = np.sqrt((D * D).sum(2))
    j = np.argmin(dist, axis=1)
    r = np.arange(len(P))
    side = AB[j, 0] * AP[r, j, 1] - AB[j, 1] * AP[r, j, 0]
    # nearest to an inner vertex: the side comes from the vertex's pseudo-normal (the sum of
    # its two segments' left normals), since either segment alone can give the wrong sign
    tj = t[r, j]
    vtx = np.where(tj >= 1.0, j + 1, np.where(tj <= 0.0, j, -1))
    inner = (vtx > 0) & (vtx < len(Q) - 1)
    nl = np.stack([-AB[:, 1], AB[:, 0]], 1) / np.sqrt(L2)[:, None]
    vi = vtx[inner]
    n_v = nl[vi - 1] + nl[vi]
    side[inner] = ((P[inner] - Q[vi]) * n_v).sum(1)
    return np.where(side >= 0, 1.0, -1.0) * dist[r, j]


def segments_meet_box(Q: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> bool:
    """Whether any segment of a 2D polyline meets an axis-aligned box (Liang-Barsky).

    Parameters
    ----------
    Q : (k, 2) float array
    lo, hi : (2,) float arrays
    """
    A, D = Q[:-1], Q[1:] - Q[:-1]
    t0 = np.zeros(len(A))
    t1 = np.ones(len(A))
    ok = np.ones(len(A), dtype=bool)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for c in range(2):  # the two coordinates
            flat = D[:, c] == 0
            ok &= ~(flat & ((A[:, c] < lo[c]) | (A[:, c] > hi[c])))
            ta = (lo[c] - A[:, c]) / D[:, c]
            tb = (hi[c] - A[:, c]) / D[:, c]
            t0 = np.where(flat, t0, np.maximum(t0, np.minimum(ta, tb)))
            t1 = np.where(flat, t1, np.minimum(t1, np.maximum(ta, tb)))
    return bool(np.any(ok & (t0 <= t1)))


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


def sketch_origin(state: EditState, step: CutStep, *, options: EditOptions) -> np.ndarray:
    """Where a sketch's ``[0, 0]`` lies in its view, ``(2,)``: the view's own origin, or
    with ``origin: OPENING`` that opening's centre across and its lowest point up (a
    neckline's front neck point in the front view), so one sketch fits garments of any
    height and placement. A list of openings takes the first the garment has."""
    spec = step.origin
    if spec is None:
        return np.zeros(2)
    frame = view_frame(step.view, frame=state.frame)
    if isinstance(spec, list):
        for i, o in enumerate(spec):
            try:
                _, loop = find_opening(state, o)
                break
            except PtailorError:
                if i == len(spec) - 1:
                    raise
    else:
        _, loop = find_opening(state, spec)
    X = state.V3[loop] @ frame[:2].T
    if step.layers == "near":  # the layer facing the viewer: its lowest point
        used = used_indices(state.base.F3, len(state.V3))
        mid = float(np.median(state.V3[used] @ frame[2]))
        near = state.V3[loop] @ frame[2] <= mid
        if near.any():
            return np.array([float(X[:, 0].mean()), float(X[near, 1].min())])
    return np.array([float(X[:, 0].mean()), float(X[:, 1].min())])


def sketch_field(
    V: np.ndarray, step: CutStep, *, frame: Frame, origin: np.ndarray | None = None
) -> np.ndarray:
    """Field whose negative side is what a sketch cut removes (the sketch's points offset
    by ``origin``, :func:`sketch_origin`), seen under the garment's ``frame``."""
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
        used = np.isfinite(X[:, 2])
        mid = float(np.median(X[used, 2]))
        phi = np.maximum(phi, X[:, 2] - mid)  # only the layer nearer than the middle goes
    return phi


def one_tool(step: CutStep, where: str) -> list[str]:
    """A cut has a plane or a sketch, not both."""
    if (step.plane is None) == (step.sketch is None):
        return [f"{where}: cut needs exactly one of 'plane' or 'sketch'"]
    return []


@register(CutStep, check=one_tool)
def cut(state: EditState, step: CutStep, *, options: EditOptions) -> EditState:
    """Cut with a plane, or with a sketched polyline extruded along the view direction.

    Triangles are split exactly on the cutting surface and the chosen side is removed;
    the pattern follows by barycentric transfer.
    """
    V = state.V3
    if step.plane is not None:
        p = np.asarray(step.plane["point"], float)
        nrm = unit_vector(step.plane["normal"], "plane normal")

        def field(X: np.ndarray) -> np.ndarray:
            return -(X - p) @ nrm

        what = "plane"
    else:
        o = sketch_origin(state, step, options=options)

        def field(X: np.ndarray) -> np.ndarray:
            return sketch_field(X, step, frame=state.frame, origin=o)

        what = "sketch"
        used = used_indices(state.base.F3, len(V))
        frame = view_frame(step.view, frame=state.frame)
        X2 = V[used] @ frame[:2].T
        lo, hi = X2.min(axis=0), X2.max(axis=0)
        pad = tol.ROUNDING_REL * max(float(np.max(hi - lo)), tol.TINY)
        if not segments_meet_box(np.asarray(step.sketch, float) + o, lo - pad, hi + pad):
            raise PtailorError(
                "the cut's sketch misses the garment: it does not overlap the garment in its "
                f"view (the garment spans "
                f"{lo[0]:.4g}..{hi[0]:.4g} across and {lo[1]:.4g}..{hi[1]:.4g} up): "
                "nothing to cut"
            )
    phi = field(V)
    if step.symmetric:
        # remove what the cut removes and what its mirror image removes
        phi = np.minimum(phi, field(sagittal_mirror(V, state.base.F3, frame=state.frame)))
    used = used_indices(state.base.F3, len(V))
    if np.all(phi[used] >= 0):
        raise PtailorError(f"the cut's {what} misses the garment: nothing to remove")
    res = split_keep(state, phi)
    panels, warnings = panel_changes(state, res)
    rec = {
        "op": "cut",
        "by": what,
        **(
            {"origin": [round(float(x), 6) for x in o]}
            if what == "sketch" and step.origin is not None
            else {}
        ),
        "removed_triangles": res.removed_triangles,
        "split_triangles": res.split_triangles,
        "new_edge_vertices": len(res.new_vertices3),
        "panels": panels,
    }
    if warnings:
        rec["warnings"] = warnings
    return replace(res.state, log=(*state.log, rec))
