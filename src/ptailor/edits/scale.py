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
    if step["axis"] == "auto":
        ax = region_axis(V3, g.F3, faces, body=options.body)
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
    return replace(state, V3=V_new, even=even, log=(*state.log, rec))
