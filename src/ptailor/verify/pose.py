"""Posing the mean body's arms to a garment's sleeves: a linear-blend skinning of each arm.

The shipped bodies are plain meshes, with no skeleton: each arm's rig is derived from the
A-pose body's geometry (:func:`arm_rigs`):

1. *The arm*: rows of the body (``FIT_ARM_ROW`` of its height apart), followed up from the
   hand (the farthest vertex on that side): a row that has a gap wider than
   ``FIT_ARM_GAP_EDGES`` median edges between the torso and what lies beyond holds the arm
   beyond it (the widest gap in the hand's row, then in each row up the gap nearest the
   row's below). The highest row with a gap is the armpit.
2. *The bone*: the principal axis of the arm's vertices from the armpit down to
   ``FIT_UPPER_ARM`` of the height (the upper arm), pointing to the hand. The shoulder joint
   lies one arm radius (the median distance of those vertices to the bone) outside the
   armpit, midway in height between the armpit and the top of the shoulder there (its
   highest vertex), at the bone's depth.
3. *The weights*: 1 on the arm beyond ``FIT_ARM_BAND`` of the height from the joint along
   the bone, 0 on the torso (inside the armpit, and below it outside the arm), harmonic in
   between (the mesh's graph Laplacian, a sparse solve): the shoulder bends smoothly and the
   mesh stays closed and outward (only vertices move).

The sleeves' axes come from the garment (:func:`sleeve_axes`: the sleeve and cuff panels of
each side, :func:`ptailor.geometry.tube_axis.tube_axis`); each arm is rotated about its joint
by the least rotation taking its bone to its sleeve's axis (abduction and the forward swing,
abduction kept within ``FIT_ARM_ABDUCTION``), and its shoulder moved onto the sleeve's axis
(:func:`shoulder_shift`, at most ``FIT_SHOULDER_SHIFT_CM``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor import tolerances as tol
from ptailor.geometry.tube_axis import extent_axis, tube_axis
from ptailor.verify import tolerances as verify_tol

__all__ = [
    "ArmRig",
    "LimbAxis",
    "LimbRig",
    "SleeveAxis",
    "abduction",
    "arm_rigs",
    "body_rows",
    "clamped_bone",
    "component",
    "forward",
    "harmonic_weights",
    "limb_axis",
    "pose_arms",
    "rotation",
    "shoulder_shift",
    "sleeve_axes",
]

#: the sides, as the sign of the body's ``x`` (its left)
SIDES = {"left": 1.0, "right": -1.0}


@dataclass(frozen=True)
class LimbRig:
    """One limb of a body (an arm, or a leg: :mod:`ptailor.verify.legs`): its joint, its
    bone and its skinning weights.

    Attributes
    ----------
    side : str
        ``left`` (+x) or ``right``.
    joint : (3,) float array
        The shoulder (hip) joint (the body's axes and units).
    bone : (3,) float array
        Unit direction from the joint to the hand (foot).
    radius : float
        The upper arm's (thigh's) median radius.
    weight : (nb,) float array
        Per body vertex, in [0, 1]: how much it follows the limb.
    centre : (3,) float array
        The upper arm's (thigh's) centroid: the limb's axis is the line through it along
        the bone.
    """

    side: str
    joint: np.ndarray
    bone: np.ndarray
    radius: float
    weight: np.ndarray
    centre: np.ndarray

    def turned(self, bone: np.ndarray, X: np.ndarray) -> np.ndarray:
        """Points ``(k, 3)`` turned about the joint by the least rotation from this arm's
        bone to ``bone`` (unit)."""
        return (X - self.joint) @ rotation(self.bone, bone).T + self.joint


#: an arm's rig (the name it had before the legs were rigged too)
ArmRig = LimbRig


@dataclass(frozen=True)
class LimbAxis:
    """A sleeve's (a trouser leg's) axis, in the garment's frame axes (left, up, front) and
    units.

    Attributes
    ----------
    side : str
    point : (3,) float array
        The sleeve's (leg's) area-weighted centroid (on the axis of a tube).
    direction : (3,) float array
        Unit, from the shoulder to the cuff (the hip to the leg opening).
    vertices : (k,) int array
        The sleeve's (leg's) drape vertices (into ``V3``).
    """

    side: str
    point: np.ndarray
    direction: np.ndarray
    vertices: np.ndarray


#: a sleeve's axis (the name it had before the trouser legs' axes)
SleeveAxis = LimbAxis


def abduction(direction: np.ndarray, side: str) -> float:
    """Degrees from straight down of a direction ``(3,)`` in the frontal plane, positive
    away from the body (90: horizontal)."""
    return float(np.degrees(np.arctan2(SIDES[side] * direction[0], -direction[1])))


def forward(direction: np.ndarray) -> float:
    """Degrees a direction ``(3,)`` swings forward (+z) out of the frontal plane."""
    return float(np.degrees(np.arcsin(np.clip(direction[2], -1.0, 1.0))))


def arm_rigs(V: np.ndarray, F: np.ndarray) -> tuple[LimbRig, ...]:
    """Both arms' rigs (left, right) of a body ``V`` ``(nb, 3)``, ``F`` ``(f, 3)`` in the
    A-pose (y up, its left +x; see the module docstring)."""
    return tuple(_arm_rig(V, F, side) for side in SIDES)


def body_rows(V: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, float, float]:
    """The body's rows, as the arm and leg rigs read them.

    Returns
    -------
    row : (nb,) int array
        Each vertex's row, from the feet up, ``FIT_ARM_ROW`` of the height apart.
    h : float
        The body's height.
    gap : float
        The gap that parts a row: ``FIT_ARM_GAP_EDGES`` median edges.
    """
    from ptailor.geometry.triangles import edge_lengths

    h = float(np.ptp(V[:, 1]))
    gap = verify_tol.FIT_ARM_GAP_EDGES * float(np.median(edge_lengths(V, F)))
    row = np.floor((V[:, 1] - V[:, 1].min()) / (verify_tol.FIT_ARM_ROW * h)).astype(np.int64)
    return row, h, gap


def _arm_rows(V: np.ndarray, F: np.ndarray, s: float) -> tuple[np.ndarray, float, float]:
    """The arm's vertices ``(nb,)`` bool on the side of sign ``s``, the armpit's height
    and its distance from the centre line (see the module docstring, step 1)."""
    row, h, gap = body_rows(V, F)
    xs = s * V[:, 0]
    arm = np.zeros(len(V), dtype=bool)
    top, x_a = None, 0.0
    for r in range(int(row[np.argmax(xs)]), int(row.max()) + 1):  # a loop over rows, upward
        sel = np.flatnonzero((row == r) & (xs > 0.0))
        x = np.sort(xs[sel])
        g = np.diff(x)
        wide = np.flatnonzero(g > gap)
        if wide.size == 0:
            break
        # the gap followed up from the hand's row, where the widest is the torso's edge
        k = wide[np.argmin(np.abs(x[wide] - x_a))] if top is not None else int(np.argmax(g))
        if top is not None and abs(x[k] - x_a) > gap:
            break  # the armpit closed: a gap farther out lies between the arm's vertices
        cut = x[k]
        arm[sel[xs[sel] > cut]] = True
        top, x_a = r, float(cut)
    if top is None:
        raise ValueError("the body has no arm apart from its torso")
    return arm, float(V[:, 1].min() + (top + 1) * verify_tol.FIT_ARM_ROW * h), x_a


def _arm_rig(V: np.ndarray, F: np.ndarray, side: str) -> LimbRig:
    """One arm's rig (see the module docstring)."""
    s = SIDES[side]
    h = float(np.ptp(V[:, 1]))
    arm, y_a, x_a = _arm_rows(V, F, s)
    upper = arm & (V[:, 1] > y_a - verify_tol.FIT_UPPER_ARM * h)
    c = V[upper].mean(axis=0)
    bone = extent_axis(V[upper])
    bone = bone if bone[1] < 0.0 else -bone  # to the hand: down
    off = V[upper] - c
    radius = float(np.median(np.linalg.norm(off - np.outer(off @ bone, bone), axis=1)))
    column = np.abs(s * V[:, 0] - x_a - radius) < 0.5 * radius  # over the shoulder
    y_j = 0.5 * (y_a + float(V[column, 1].max()))  # midway from the armpit to the shoulder's top
    on_bone = c + bone * ((y_j - c[1]) / bone[1])
    joint = np.array([s * (x_a + radius), y_j, on_bone[2]])
    far = (V - joint) @ bone > verify_tol.FIT_ARM_BAND * h
    one = component(F, far, int(np.argmax(s * V[:, 0])))
    inner = s * V[:, 0] < x_a - 0.5 * verify_tol.FIT_ARM_BAND * h
    zero = inner | (far & ~one) | ((V[:, 1] < y_a) & ~arm & ~one)  # the torso, its side too
    return LimbRig(side, joint, bone, radius, harmonic_weights(V, F, one, zero & ~one), c)


def component(F: np.ndarray, keep: np.ndarray, seed: int) -> np.ndarray:
    """The vertices ``(nb,)`` bool of ``keep`` joined to ``seed`` through edges among them."""
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components

    E = F[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    E = E[keep[E[:, 0]] & keep[E[:, 1]]]
    n = len(keep)
    A = sp.coo_matrix((np.ones(len(E)), (E[:, 0], E[:, 1])), shape=(n, n))
    _, label = connected_components(A, directed=False)
    return keep & (label == label[seed])


def harmonic_weights(V: np.ndarray, F: np.ndarray, one: np.ndarray, zero: np.ndarray) -> np.ndarray:
    """Weights ``(nb,)``: 1 on ``one``, 0 on ``zero``, harmonic (the graph Laplacian's
    solution) on the rest."""
    import scipy.sparse as sp
    from scipy.sparse.linalg import spsolve

    n = len(V)
    E = F[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    A = sp.coo_matrix((np.ones(len(E)), (E[:, 0], E[:, 1])), shape=(n, n)).tocsr()
    A = ((A + A.T) > 0).astype(np.float64)
    L = sp.diags(np.asarray(A.sum(axis=1)).ravel()) - A
    w = one.astype(np.float64)
    free = ~(one | zero)
    if free.any():
        rhs = -L[free][:, ~free] @ w[~free]
        w[free] = spsolve(L[free][:, free].tocsc(), rhs)
    return np.clip(w, 0.0, 1.0)


def rotation(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The least rotation ``(3, 3)`` taking unit ``a`` to unit ``b`` (Rodrigues)."""
    v = np.cross(a, b)
    c = float(a @ b)
    K = np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])
    return np.eye(3) + K + K @ K / max(1.0 + c, tol.TINY)


def clamped_bone(
    direction: np.ndarray, side: str, *, abduction_range: tuple, forward_max: float
) -> np.ndarray:
    """A limb's new bone ``(3,)``: the unit ``direction`` ``(3,)`` with its abduction
    (:func:`abduction`) clipped to ``abduction_range`` and its forward swing
    (:func:`forward`) to ``forward_max`` either way (degrees)."""
    s = SIDES[side]
    lo, hi = abduction_range
    ab = np.radians(np.clip(abduction(direction, side), lo, hi))
    fw = np.radians(np.clip(forward(direction), -forward_max, forward_max))
    return np.array([s * np.sin(ab) * np.cos(fw), -np.cos(ab) * np.cos(fw), np.sin(fw)])


def target_bone(rig: LimbRig, sleeve: np.ndarray) -> np.ndarray:
    """The arm's new bone ``(3,)``: the sleeve's direction, its abduction kept within
    ``FIT_ARM_ABDUCTION`` and its forward swing within ``FIT_ARM_FORWARD`` (degrees)."""
    return clamped_bone(
        sleeve,
        rig.side,
        abduction_range=verify_tol.FIT_ARM_ABDUCTION,
        forward_max=verify_tol.FIT_ARM_FORWARD,
    )


def pose_arms(V: np.ndarray, rigs: tuple[LimbRig, ...], bones: dict[str, np.ndarray]) -> np.ndarray:
    """The body's vertices ``(nb, 3)`` with each limb (arm or leg) named by its side in
    ``bones`` turned about its joint from its bone to the bone given (unit, the body's
    axes), blended by its weights."""
    out = np.array(V, dtype=np.float64)
    for rig in rigs:  # a loop over the two limbs
        if rig.side not in bones:
            continue
        out += rig.weight[:, None] * (rig.turned(bones[rig.side], V) - V)
    return out


def shoulder_shift(
    centre: np.ndarray, sleeve_point: np.ndarray, direction: np.ndarray, *, cap: float
) -> np.ndarray:
    """The move ``(3,)`` that puts the posed arm's axis (through ``centre``, along the
    sleeve's ``direction``) on the sleeve's axis line (the part across the axis), no longer
    than ``cap``."""
    d = sleeve_point - centre
    t = d - direction * float(d @ direction)
    n = float(np.linalg.norm(t))
    return t if n <= cap else t * (cap / n)


def sleeve_axes(garment) -> dict[str, LimbAxis]:
    """Each side's sleeve axis (:class:`LimbAxis`), in the garment's frame axes and units.

    The side's sleeve and cuff panels (``structure(garment).layout``) make the tube; its
    direction is oriented towards the side's cuff opening where there is one, else away
    from the centre line. A side with no sleeve panel, or whose panels are no tube
    (:func:`ptailor.geometry.tube_axis.tube_axis` returns None), is left out.
    """
    from ptailor.model.structure import structure

    st = structure(garment)
    lay = st.layout
    R = garment.frame.matrix()
    P = np.asarray(garment.V3, dtype=np.float64) @ R.T
    F = np.asarray(garment.F3)
    ops = {o.name: o for o in st.openings}
    out = {}
    for side, s in SIDES.items():  # a loop over the two sides
        panels = [
            k
            for k, (r, sd) in enumerate(zip(lay.role, lay.side, strict=True))
            if r in ("sleeve", "cuff") and sd == side
        ]
        cuff = ops.get(f"cuff_{side}")
        end = None if cuff is None else cuff.centroid @ R.T
        axis = limb_axis(side, P, F[np.isin(st.face_panel, panels)], end, np.array([s, 0, 0.0]))
        if axis is not None:
            out[side] = axis
    return out


def limb_axis(
    side: str, P: np.ndarray, faces: np.ndarray, end: np.ndarray | None, away: np.ndarray
) -> LimbAxis | None:
    """The axis of a limb's tube: the triangles ``faces`` ``(k, 3)`` of the drape ``P``
    ``(n, 3)`` (the garment's frame axes), its direction oriented towards its opening's
    centroid ``end`` ``(3,)`` where there is one, else along ``away`` ``(3,)``.

    Flat panels (a box mesh, not draped) are no tube
    (:func:`ptailor.geometry.tube_axis.tube_axis` returns None): the centroid to ``end``
    then gives the direction; without ``end`` either, None.
    """
    if len(faces) == 0:
        return None
    T = P[faces]
    area = np.linalg.norm(np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0]), axis=1)
    point = (T.mean(axis=1) * area[:, None]).sum(axis=0) / max(float(area.sum()), tol.TINY)
    out_dir = away if end is None else end - point
    axis = tube_axis(P, faces)
    if axis is None and end is None:
        return None
    axis = out_dir if axis is None else axis
    axis = axis if axis @ out_dir >= 0.0 else -axis
    return LimbAxis(side, point, axis / np.linalg.norm(axis), np.unique(faces))
