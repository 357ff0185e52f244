"""``scale``: scale a region around, along or uniformly about its axis."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ptailor.edits.checks import axis, choice, number, region
from ptailor.edits.region import region_axis, region_centroid, region_faces, unit_vector
from ptailor.edits.registry import Param, register
from ptailor.edits.state import EditOptions, EditState
from ptailor.method.deform import arap_deform


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


@register(
    "scale",
    {
        "region": Param(region, default="all", doc="all | {panels: [...]} | {box: {min, max}}"),
        "direction": Param(choice("around", "along", "uniform"), default="uniform"),
        "axis": Param(axis, default="auto", doc="auto (the region's principal axis) | [x, y, z]"),
        "factor": Param(number(gt=0.0, le=100.0), required=True),
    },
)
def scale(state: EditState, step: dict, *, options: EditOptions) -> EditState:
    """Scale a region of the drape; the rest follows by as-rigid-as-possible deformation.

    The region's triangles are mapped by ``c + A (p - c)`` with ``c`` the region's centroid
    and ``A`` from :func:`scale_matrix`. Panels wholly inside the region move evenly;
    panels partly inside, or moved only by the follow-up deformation, do not.
    """
    g, V3 = state.base, state.V3
    faces = region_faces(step["region"], g, V3, state.panels)
    warnings: list[str] = []
    if step["axis"] == "auto":
        ax = region_axis(V3, g.F3, faces, body=options.body)
        warnings += auto_axis_warnings(V3, g.F3, faces, ax, options)
    else:
        ax = unit_vector(step["axis"], "axis")
    c = region_centroid(V3, g.F3, faces)
    A = scale_matrix(step["direction"], ax, float(step["factor"]))
    in_region = np.zeros(len(V3), dtype=bool)
    in_region[g.F3[faces]] = True
    handles = np.flatnonzero(in_region)  # sorted, as np.unique (a mask is cheaper)
    moved = c + (V3[handles] - c) @ A.T
    used = np.zeros(len(V3), dtype=bool)
    used[g.F3] = True
    if np.all(in_region[used]):
        V_new = V3.copy()
        V_new[handles] = moved
    else:
        V_new = arap_deform(V3, g.F3, handles, moved)
    face_in = np.zeros(g.n_faces, dtype=bool)
    face_in[faces] = True
    changed = np.any(V_new != V3, axis=1)
    even = state.even.copy()
    for p in state.panels:  # a loop over panels, not triangles
        inside = bool(face_in[p.faces].all())
        still = not bool(changed[g.F3[p.faces]].any())
        even[p.index] &= inside or still
    rec = {
        "op": "scale",
        "direction": step["direction"],
        "factor": float(step["factor"]),
        "axis": [round(float(x), 6) for x in ax],
        "centroid": [round(float(x), 6) for x in c],
        "triangles": int(faces.size),
    }
    if warnings:
        rec["warnings"] = warnings
    return replace(state, V3=V_new, even=even, log=(*state.log, rec))


def auto_axis_warnings(
    V3: np.ndarray, F3: np.ndarray, faces: np.ndarray, ax: np.ndarray, options: EditOptions
) -> list[str]:
    """A warning where ``axis: auto`` had no tube to go by (the region's normals avoid no
    one direction: a whole T-shirt, torso and sleeves) and its fallback, the direction of
    largest extent, lies more than ``tol.AUTO_AXIS_UP_DEG`` from the garment's up: the
    shared tshirt's came out 55 degrees from vertical, and a symmetric ``along`` x1.1 grew
    one sleeve 10.8 % and the other 2.8 %. A tube's axis (a sleeve's: horizontal in a
    T-pose) and a body's are what they are."""
    from ptailor import tolerances as tol
    from ptailor.geometry.tube_axis import tube_axis

    if options.body is not None or tube_axis(V3, F3[faces]) is not None:
        return []
    up = unit_vector(options.up, "up")
    angle = float(np.degrees(np.arccos(min(1.0, abs(float(ax @ up))))))
    if angle <= tol.AUTO_AXIS_UP_DEG:
        return []
    return [
        f"axis: auto found no tube in the region and took its longest extent, {angle:.0f}"
        f" degrees from the garment's up {list(options.up)}: give the axis (axis: [x, y, z])"
        " or a smaller region (one sleeve, the torso)"
    ]
