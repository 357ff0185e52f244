"""Posing the mean body's legs to a garment's trouser legs: a linear-blend skinning of each
leg, as :mod:`ptailor.verify.pose` does the arms.

Each leg's rig is derived from the A-pose body's geometry (:func:`leg_rigs`):

1. *The crotch*: rows of the body (``FIT_ARM_ROW`` of its height apart), from the feet up:
   the legs stand apart while the row's nearest vertices either side of the centre line
   (``x = 0``) leave a gap wider than ``FIT_ARM_GAP_EDGES`` median edges; the first row
   without that gap is the crotch. The side's leg is its half of the body below it.
2. *The bone*: the axis of the thigh (the leg from the crotch down ``FIT_THIGH`` of the
   height): :func:`ptailor.geometry.tube_axis.tube_axis` of its triangles (the direction
   its normals avoid; the thigh is about as wide as it is long, so its vertices' own
   principal axis is ill-posed), pointing to the foot. The hip joint lies on the bone's
   line through the thigh's centroid, ``FIT_HIP_ABOVE_CROTCH`` of the height above the
   crotch.
3. *The weights*: 1 on the leg beyond ``FIT_LEG_BAND`` of the height from the joint along
   the bone (the part joined to the foot), 0 on the other half of the body, on the torso
   more than ``FIT_LEG_BAND`` above the joint and on what else lies beyond the band,
   harmonic in between (:func:`ptailor.verify.pose.harmonic_weights`).

The trouser legs' axes come from the garment (:func:`trouser_axes`: each side's leg panels
below the garment's crotch); each leg is turned about its hip by the least rotation taking
its bone to its trouser leg's axis (:func:`target_leg`: abduction within
``FIT_LEG_ABDUCTION``, the forward swing within ``FIT_LEG_FORWARD``), and its hip moved onto
that axis by at most ``FIT_HIP_SHIFT_CM`` (:func:`ptailor.verify.pose.shoulder_shift`).
"""

from __future__ import annotations

import numpy as np

from ptailor.geometry.tube_axis import tube_axis
from ptailor.verify import tolerances as verify_tol
from ptailor.verify.pose import (
    SIDES,
    LimbAxis,
    LimbRig,
    body_rows,
    clamped_bone,
    component,
    harmonic_weights,
    limb_axis,
)

__all__ = ["crotch_height", "leg_rigs", "target_leg", "trouser_axes"]


def crotch_height(V: np.ndarray, F: np.ndarray) -> float:
    """The height of the A-pose body's crotch (``V`` ``(nb, 3)``, ``F`` ``(f, 3)``, y up,
    its left +x): the bottom of the lowest row of the body not parted by the centre line
    (see the module docstring, step 1).

    Raises
    ------
    ValueError
        A body whose lowest row is not parted (no legs apart).
    """
    row, h, gap = body_rows(V, F)
    n = int(row.max()) + 1
    left, right = np.full(n, np.inf), np.full(n, -np.inf)
    pos = V[:, 0] > 0.0
    np.minimum.at(left, row[pos], V[pos, 0])  # per row, the nearest vertex left of the centre
    np.maximum.at(right, row[~pos], V[~pos, 0])  # ... and right of it
    closed = np.flatnonzero(left - right <= gap)
    if closed.size == 0 or closed[0] == 0:
        raise ValueError("the body has no legs apart below its torso")
    return float(V[:, 1].min() + closed[0] * verify_tol.FIT_ARM_ROW * h)


def leg_rigs(V: np.ndarray, F: np.ndarray) -> tuple[LimbRig, ...]:
    """Both legs' rigs (left, right) of a body ``V`` ``(nb, 3)``, ``F`` ``(f, 3)`` in the
    A-pose (y up, its left +x; see the module docstring)."""
    y_c = crotch_height(V, F)
    return tuple(_leg_rig(V, F, side, y_c) for side in SIDES)


def _leg_rig(V: np.ndarray, F: np.ndarray, side: str, y_c: float) -> LimbRig:
    """One leg's rig below the crotch at height ``y_c`` (see the module docstring)."""
    s = SIDES[side]
    h = float(np.ptp(V[:, 1]))
    half = s * V[:, 0] > 0.0
    thigh = half & (V[:, 1] < y_c) & (V[:, 1] > y_c - verify_tol.FIT_THIGH * h)
    bone = tube_axis(V, F[thigh[F].all(axis=1)])
    if bone is None:
        raise ValueError(f"the body's {side} thigh is no tube")
    bone = bone if bone[1] < 0.0 else -bone  # to the foot: down
    c = V[thigh].mean(axis=0)
    off = V[thigh] - c
    radius = float(np.median(np.linalg.norm(off - np.outer(off @ bone, bone), axis=1)))
    y_j = y_c + verify_tol.FIT_HIP_ABOVE_CROTCH * h
    joint = c + bone * ((y_j - c[1]) / bone[1])
    band = verify_tol.FIT_LEG_BAND * h
    far = half & ((V - joint) @ bone > band)
    foot = int(np.flatnonzero(half)[np.argmin(V[half, 1])])
    one = component(F, far, foot)
    zero = ~half | (V[:, 1] > y_j + band) | (far & ~one)
    return LimbRig(side, joint, bone, radius, harmonic_weights(V, F, one, zero & ~one), c)


def target_leg(rig: LimbRig, leg: np.ndarray) -> np.ndarray:
    """The leg's new bone ``(3,)``: the trouser leg's direction ``(3,)``, its abduction kept
    within ``FIT_LEG_ABDUCTION`` and its forward swing within ``FIT_LEG_FORWARD``
    (degrees)."""
    return clamped_bone(
        leg,
        rig.side,
        abduction_range=verify_tol.FIT_LEG_ABDUCTION,
        forward_max=verify_tol.FIT_LEG_FORWARD,
    )


def trouser_axes(garment) -> dict[str, LimbAxis]:
    """Each side's trouser leg axis (:class:`ptailor.verify.pose.LimbAxis`), in the
    garment's frame axes and units.

    The side's leg panels (``structure(garment).layout``: body panels of the ``leg`` tier,
    those that reach a leg opening) below the garment's crotch (the lowest vertex the two
    sides' leg panels share; all of them where they share none) make the tube
    (:func:`ptailor.verify.pose.limb_axis`), its direction oriented towards the side's leg
    opening (``leg_left``, ``leg_right``). A garment without both leg openings has none.
    """
    from ptailor.model.structure import structure

    st = structure(garment)
    lay = st.layout
    ops = {o.name: o for o in st.openings}
    if not {"leg_left", "leg_right"} <= ops.keys():
        return {}
    R = garment.frame.matrix()
    P = np.asarray(garment.V3, dtype=np.float64) @ R.T
    F = np.asarray(garment.F3)
    faces = {}
    for side in SIDES:  # a loop over the two sides
        panels = [
            k
            for k, (r, sd, t) in enumerate(zip(lay.role, lay.side, lay.tier, strict=True))
            if r == "body" and t == "leg" and sd == side
        ]
        faces[side] = F[np.isin(st.face_panel, panels)]
    both = np.intersect1d(*(np.unique(f) for f in faces.values()))
    down = np.array([0.0, -1.0, 0.0])
    out = {}
    for side, f in faces.items():  # a loop over the two sides
        if both.size:
            f = f[(P[f, 1] < P[both, 1].min()).all(axis=1)]  # below the crotch
        axis = limb_axis(side, P, f, ops[f"leg_{side}"].centroid @ R.T, down)
        if axis is not None:
            out[side] = axis
    return out
