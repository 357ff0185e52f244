"""A body for every garment: GarmentCode's mean body, posed and fitted to a drape.

``--body auto`` places a body inside a garment so that the re-drape check has something to
hang the cloth on. ptailor ships GarmentCode's MIT mean body (``verify/bodies``: A-pose and
T-pose, decimated by pymeshlab to 7,002 vertices, in metres, y up, z front, feet at 0;
``bench/make_bodies.py`` makes them from ``../shared/bodies``). The fit is a similarity:

1. *Pose*: a garment with sleeves or trouser legs takes the A-pose body, its arms posed to
   the sleeves (:mod:`ptailor.verify.pose`) and its legs to the trouser legs
   (:mod:`ptailor.verify.legs`); otherwise a top whose cuffs lie more than ``FIT_T_POSE_DEG``
   from straight down, seen from the neckline, takes the T-pose body, every other garment
   the A-pose one.
2. *Anchor*: where the garment hangs. A top's neckline centroid goes to the body's neck
   base (``FIT_NECK_HEIGHT`` of its height, on the torso's mid-depth), a skirt's or trousers'
   waist centroid to its waist (``FIT_WAIST_HEIGHT``). A drape with neither is refused.
3. *Scale*: the largest body scale (about the anchor, in ``FIT_SCALE_RANGE``) at which at most
   ``FIT_INSIDE_MAX`` of the torso's vertices (those no farther out than the hem reaches: a
   sleeve at another angle than the body's arm does not decide) lie inside the body (moved up to
   ``FIT_OFFSET_CM`` up, down, forward or back from the anchor, the best kept), by bisection; each
   vertex is inside when it lies behind the nearest body vertex's normal (a KD-tree query:
   the body's vertices are about 1.5 cm apart, the test is that exact).

No rotation is fitted: the garment's ``up``/``front`` axes say how it is worn.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from importlib import resources

import numpy as np

from ptailor.errors import PtailorError
from ptailor.model.frame import Frame
from ptailor.model.openings import Opening
from ptailor.verify import tolerances as verify_tol

__all__ = ["BodyFit", "fit_body", "mean_body"]


@dataclass(frozen=True)
class BodyFit:
    """A body fitted to a garment.

    Attributes
    ----------
    V : (k, 3) float array
        The body's vertices in the garment's coordinates and units.
    F : (f, 3) int array
        Outward triangles.
    pose : str
        ``a`` or ``t``.
    scale : float
        Against the mean body (1.72 m tall).
    anchor : str
        ``neckline`` or ``waist``.
    inside : float
        Fraction of the torso's garment vertices inside the body (those the scale is fitted
        to).
    drape_inside : float or None
        Fraction of all the drape's vertices (at most ``FIT_INSIDE_POINTS`` of them) inside the
        body (trimesh's ray test), sleeves and legs included; None where no limb was posed.
    arms : dict
        Per posed arm (``left``, ``right``): the sleeve's abduction and forward swing and the
        arm's (degrees), the shoulder's move onto the sleeve's axis (garment units).
    legs : dict
        Per posed leg (``left``, ``right``): the trouser leg's abduction and forward swing
        and the leg's (degrees), the hip's move onto the trouser leg's axis (garment units).
    gap_rms, gap_median : float
        The garment's vertices' distances to the nearest body vertex (garment units).
    """

    V: np.ndarray
    F: np.ndarray
    pose: str
    scale: float
    anchor: str
    inside: float
    gap_rms: float
    gap_median: float
    drape_inside: float | None = None
    arms: dict = field(default_factory=dict)
    legs: dict = field(default_factory=dict)

    def record(self) -> dict:
        """The fit as ``verify.json`` and the report hold it."""
        return {
            "body": "GarmentCode mean body (MIT)",
            "pose": f"{self.pose}-pose",
            "scale": round(self.scale, 4),
            "anchor": self.anchor,
            "inside_fraction": round(self.inside, 5),
            "gap_rms": round(self.gap_rms, 4),
            "gap_median": round(self.gap_median, 4),
            **(
                {}
                if self.drape_inside is None
                else {"drape_inside_fraction": round(self.drape_inside, 5)}
            ),
            **({"arms": self.arms} if self.arms else {}),
            **({"legs": self.legs} if self.legs else {}),
        }


def mean_body(pose: str) -> tuple[np.ndarray, np.ndarray]:
    """The shipped mean body, ``(V, F)`` in metres (y up, z front, feet at 0).

    Parameters
    ----------
    pose : str
        ``a`` or ``t``.
    """
    ref = resources.files("ptailor.verify") / "bodies" / f"body_{pose}pose.npz"
    with resources.as_file(ref) as path, np.load(path) as data:
        return data["V"].astype(np.float64), data["F"].astype(np.int64)


@lru_cache(maxsize=2)
def _rigs(kind: str) -> tuple:
    """The A-pose body's arm (``kind`` ``arm``) or leg rigs
    (:func:`ptailor.verify.pose.arm_rigs`, :func:`ptailor.verify.legs.leg_rigs`), computed
    once."""
    from ptailor.verify.legs import leg_rigs
    from ptailor.verify.pose import arm_rigs

    return (arm_rigs if kind == "arm" else leg_rigs)(*mean_body("a"))


def _inside(P: np.ndarray, V: np.ndarray, N: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per point: inside (behind its nearest body vertex's normal) and that distance."""
    from scipy.spatial import cKDTree

    d, i = cKDTree(V).query(P)
    return np.einsum("ij,ij->i", P - V[i], N[i]) < 0.0, d


def _pose(ops: dict[str, Opening], frame: np.ndarray) -> str:
    """``t`` when a top's cuffs lie more than ``FIT_T_POSE_DEG`` from straight down."""
    if not {"neckline", "cuff_left", "cuff_right"} <= ops.keys():
        return "a"
    neck = ops["neckline"].centroid @ frame.T
    angles = []
    for side in ("cuff_left", "cuff_right"):
        d = ops[side].centroid @ frame.T - neck
        angles.append(np.degrees(np.arccos(np.clip(-d[1] / np.linalg.norm(d), -1.0, 1.0))))
    return "t" if float(np.mean(angles)) > verify_tol.FIT_T_POSE_DEG else "a"


def fit_body(
    V3: np.ndarray,
    F3: np.ndarray,
    *,
    openings: list[Opening],
    frame: Frame,
    cm_per_unit: float = 1.0,
    path: str | None = None,
    sleeves: dict | None = None,
    trousers: dict | None = None,
) -> BodyFit:
    """Fit the mean body to a garment's drape (see the module docstring).

    Parameters
    ----------
    V3 : (n, 3) float array
    F3 : (m, 3) int array
    openings : list of Opening
        The drape's named openings (:func:`ptailor.model.openings.openings`).
    frame : Frame
        How the garment is worn (``Garment.frame``).
    cm_per_unit : float, keyword-only
        The drape's unit.
    path : str, optional
        The file named in errors.
    sleeves, trousers : dict of str to LimbAxis, optional
        The garment's sleeves' and trouser legs' axes (:func:`ptailor.verify.pose.
        sleeve_axes`, :func:`ptailor.verify.legs.trouser_axes`): the A-pose body's arms and
        legs are posed to them before the fit, its shoulders and hips moved onto them after.

    Returns
    -------
    BodyFit

    Raises
    ------
    PtailorError
        A drape with no neckline and no waist (nothing to hang it on), or one the body
        fits inside at no scale in ``FIT_SCALE_RANGE``.
    """
    R = frame.matrix()  # rows: left, up, front (the body's x, y, z)
    ops = {o.name: o for o in openings}
    anchor = "neckline" if "neckline" in ops else "waist" if "waist" in ops else None
    if anchor is None:
        raise PtailorError(
            "--body auto: the drape has neither a neckline nor a waist to hang it on a body "
            f"(its openings: {', '.join(sorted(ops)) or 'none'}); give a body with --body FILE",
            path=path,
        )
    to_m = cm_per_unit / 100.0
    arms = _Limbs.of("arm", sleeves or {}, to_m)
    legs = _Limbs.of("leg", trousers or {}, to_m)
    pose = "a" if (posed := bool(arms.bones or legs.bones)) else _pose(ops, R)
    BV, BF = mean_body(pose)
    BV = legs.posed(arms.posed(BV))
    import trimesh

    BN = np.asarray(trimesh.Trimesh(BV, BF, process=False).vertex_normals)  # outward, unit
    P, a_g = _garment_points(V3, F3, ops, anchor, R, to_m, [a.vertices for a in arms.axes.values()])
    fit = _Placement(P, BV, BN, _body_anchor(BV, anchor), a_g, _offsets(), (arms, legs))
    s = _largest_scale(fit, path=path)
    V_b = fit.placed(s, fit.best[s])
    for limbs in (arms, legs):
        limbs.fill_record(fit, s)
    inside, dist = _inside(P, V_b, BN)
    drape_inside = _drape_inside(V3, F3, R, to_m, V_b, BF) if posed else None
    return BodyFit(
        V=(V_b / to_m) @ R,  # back to the garment's axes and units
        F=BF,
        pose=pose,
        scale=s,
        anchor=anchor,
        inside=float(inside.mean()),
        gap_rms=float(np.sqrt(np.mean(dist**2)) / to_m),
        gap_median=float(np.median(dist) / to_m),
        drape_inside=drape_inside,
        arms=arms.record,
        legs=legs.record,
    )


def _drape_inside(
    V3: np.ndarray, F3: np.ndarray, frame: np.ndarray, to_m: float, V_b: np.ndarray, BF: np.ndarray
) -> float:
    """The fraction of the drape's used vertices (at most ``FIT_INSIDE_POINTS``, evenly
    subsampled) inside the placed body ``V_b`` ``(nb, 3)``, ``BF`` ``(f, 3)`` (the body's
    axes, metres), by trimesh's ray test (:func:`ptailor.edits.body.inside_body`).

    The ray test (seconds for some thousand points) is asked only of the points inside by
    the nearest vertex's normal (:func:`_inside`) or within ``FIT_NEAR_EDGES`` median body
    edges of the body: one farther out, in front of that normal, is outside.
    """
    import trimesh

    from ptailor.edits.body import inside_body
    from ptailor.geometry.triangles import edge_lengths

    used = np.unique(np.asarray(F3))
    Q = (np.asarray(V3, dtype=np.float64)[used] @ frame.T) * to_m
    Q = Q[:: -(-len(Q) // verify_tol.FIT_INSIDE_POINTS)] if len(Q) else Q
    body = trimesh.Trimesh(V_b, BF, process=False)
    behind, d = _inside(Q, V_b, np.asarray(body.vertex_normals))
    ask = behind | (d < verify_tol.FIT_NEAR_EDGES * float(np.median(edge_lengths(V_b, BF))))
    inside = np.zeros(len(Q), dtype=bool)
    inside[ask] = inside_body(Q[ask], body)
    return float(inside.mean())


@dataclass
class _Limbs:
    """The arms posed to the sleeves (:mod:`ptailor.verify.pose`), or the legs to the
    trouser legs (:mod:`ptailor.verify.legs`), in the body's axes and metres: the rigs, each
    posed limb's new bone, the garment's axes, and the record.

    Attributes
    ----------
    kind : str
        ``arm`` or ``leg``.
    """

    kind: str
    rigs: tuple
    bones: dict
    axes: dict
    to_m: float
    record: dict = field(default_factory=dict)

    @classmethod
    def of(cls, kind: str, axes: dict, to_m: float) -> _Limbs:
        """The limbs to pose for the axes given (none: no rig is built)."""
        if not axes:
            return cls(kind, (), {}, {}, to_m)
        from ptailor.verify.legs import target_leg
        from ptailor.verify.pose import target_bone

        rigs = _rigs(kind)
        target = target_bone if kind == "arm" else target_leg
        bones = {r.side: target(r, axes[r.side].direction) for r in rigs if r.side in axes}
        return cls(kind, rigs, bones, axes, to_m)

    def posed(self, BV: np.ndarray) -> np.ndarray:
        """The body's vertices ``(nb, 3)`` with the limbs turned to their new bones."""
        if not self.bones:
            return BV
        from ptailor.verify.pose import pose_arms

        return pose_arms(BV, self.rigs, self.bones)

    def shifts(self, joint_at) -> list:
        """Per posed limb, its rig and the move ``(3,)`` of its joint onto its axis
        (:func:`ptailor.verify.pose.shoulder_shift`, at most ``FIT_SHOULDER_SHIFT_CM`` for
        an arm, ``FIT_HIP_SHIFT_CM`` for a leg), the body placed by ``joint_at`` (a function
        of ``(1, 3)`` body points)."""
        from ptailor.verify.pose import shoulder_shift

        out = []
        cm = verify_tol.FIT_SHOULDER_SHIFT_CM if self.kind == "arm" else verify_tol.FIT_HIP_SHIFT_CM
        for rig in self.rigs:  # a loop over the two limbs
            if rig.side in self.bones:
                ax, bone = self.axes[rig.side], self.bones[rig.side]
                centre = joint_at(rig.turned(bone, rig.centre[None]))[0]
                t = shoulder_shift(centre, ax.point * self.to_m, bone, cap=cm / 100.0)
                out.append((rig, t))
        return out

    def fill_record(self, fit: _Placement, s: float) -> None:
        """Fill :attr:`record` for the body placed at scale ``s``."""
        from ptailor.verify.pose import abduction, forward

        part, joint = ("sleeve", "shoulder") if self.kind == "arm" else ("trouser", "hip")
        off = fit.best[s]
        for rig, t in self.shifts(lambda X: fit.placed(s, off, X, shift=False)):
            ax, bone = self.axes[rig.side], self.bones[rig.side]
            self.record[rig.side] = {
                f"{part}_abduction_deg": round(abduction(ax.direction, rig.side), 1),
                f"{part}_forward_deg": round(forward(ax.direction), 1),
                f"{self.kind}_abduction_deg": round(abduction(bone, rig.side), 1),
                f"{self.kind}_forward_deg": round(forward(bone), 1),
                f"{joint}_up": round(float(t[1]) / self.to_m, 3),
                f"{joint}_shift": round(float(np.linalg.norm(t)) / self.to_m, 3),
            }


def _garment_points(
    V3: np.ndarray,
    F3: np.ndarray,
    ops: dict[str, Opening],
    anchor: str,
    frame: np.ndarray,
    to_m: float,
    sleeves: list | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """The garment's vertices the fit looks at, in the body's axes and metres, and its
    anchor opening's centroid there.

    ``sleeves`` (a list of ``(k,)`` int arrays: the sleeves' vertices) are left out.

    Returns
    -------
    P : (k, 3) float array
        The torso's used vertices (evenly subsampled to about ``FIT_POINTS``).
    a_g : (3,) float array
    """
    used = np.unique(np.asarray(F3))
    if sleeves:  # the sleeves (their arms are posed to them) do not decide the torso's fit
        used = np.setdiff1d(used, np.concatenate(sleeves))
    P = (np.asarray(V3, dtype=np.float64)[used] @ frame.T) * to_m  # body axes, metres
    a_g = (ops[anchor].centroid @ frame.T) * to_m
    # the torso decides: the vertices no farther out than the hem (or the waist) reaches,
    # so a sleeve at another angle than the body's arm does not shrink the body
    bottom = ops.get("hem") or ops.get("waist")
    if bottom is not None:
        reach = float(np.abs((V3[bottom.loop] @ frame[0]) * to_m - a_g[0]).max())
        torso = np.abs(P[:, 0] - a_g[0]) <= reach
        if torso.sum() >= verify_tol.FIT_TORSO_MIN_POINTS:
            P = P[torso]
    return P[:: max(1, len(P) // verify_tol.FIT_POINTS)], a_g


def _body_anchor(BV: np.ndarray, anchor: str) -> np.ndarray:
    """The body's anchor ``(3,)``: its neck base or waist height, on the torso's mid-depth
    there, on the centre line."""
    h = float(BV[:, 1].max() - BV[:, 1].min())
    y_a = h * (verify_tol.FIT_NECK_HEIGHT if anchor == "neckline" else verify_tol.FIT_WAIST_HEIGHT)
    band = BV[np.abs(BV[:, 1] - y_a) < verify_tol.FIT_ANCHOR_BAND * h]
    return np.array([0.0, y_a, 0.5 * float(band[:, 2].min() + band[:, 2].max())])


def _offsets() -> np.ndarray:
    """The body's offsets ``(q, 2)`` from the anchor tried (up, front; metres), nearest first.

    The anchor is where the garment hangs, not a landmark it hits exactly: offsets of the
    body up/down and front/back (cm) are tried at each scale, the least inside kept.
    """
    reach, step = verify_tol.FIT_OFFSET_CM, verify_tol.FIT_OFFSET_STEP_CM
    steps = np.arange(-reach, reach + 1e-9, step) / 100.0
    offsets = np.stack(np.meshgrid(steps, steps, indexing="ij"), -1).reshape(-1, 2)
    return offsets[np.argsort(np.abs(offsets).sum(axis=1), kind="stable")]  # nearest first


@dataclass
class _Placement:
    """The body placed about the garment's anchor: the points it must hold, and the best
    offset found at each scale tried (``best``).

    Attributes
    ----------
    P : (k, 3) float array
        Garment points (:func:`_garment_points`).
    BV, BN : (nb, 3) float arrays
        The body's vertices and unit normals.
    a_b, a_g : (3,) float arrays
        The body's anchor and the garment's.
    offsets : (q, 2) float array
        :func:`_offsets`.
    limbs : tuple of _Limbs
        The posed arms and legs, whose shoulders and hips move onto the sleeves' and
        trouser legs' axes wherever the body is placed.
    best : dict of float to (2,) float array
        The offset with the least inside, per scale tried.
    """

    P: np.ndarray
    BV: np.ndarray
    BN: np.ndarray
    a_b: np.ndarray
    a_g: np.ndarray
    offsets: np.ndarray
    limbs: tuple = ()
    best: dict = field(default_factory=dict)

    def placed(
        self, s: float, off=(0.0, 0.0), X: np.ndarray | None = None, *, shift: bool = True
    ) -> np.ndarray:
        """The body's vertices (or points ``X`` ``(k, 3)`` of it) scaled by ``s`` about its
        anchor, moved by ``off``; with ``shift``, the body's posed shoulders and hips then
        moved onto their sleeves' and trouser legs' axes (:meth:`_Limbs.shifts`)."""
        V = (self.BV if X is None else X) - self.a_b
        V = V * s + self.a_g + np.array([0.0, off[0], off[1]])
        if X is None and shift:
            for limbs in self.limbs:  # the arms, the legs
                for rig, t in limbs.shifts(lambda J: self.placed(s, off, J, shift=False)):
                    V = V + rig.weight[:, None] * t
        return V

    def inside_fraction(self, s: float) -> float:
        """The least fraction of the points inside the body at scale ``s``, over the offsets
        (the offset kept in :attr:`best`)."""
        fr = np.array(
            [_inside(self.P, self.placed(s, o), self.BN)[0].mean() for o in self.offsets]
        )  # a loop over offsets
        k = int(np.argmin(fr))
        self.best[s] = self.offsets[k]
        return float(fr[k])


def _largest_scale(fit: _Placement, *, path: str | None) -> float:
    """The largest scale in ``FIT_SCALE_RANGE`` with at most ``FIT_INSIDE_MAX`` of the
    points inside, by bisection (``fit.best`` then holds its offset)."""
    lo, hi = verify_tol.FIT_SCALE_RANGE
    if fit.inside_fraction(lo) > verify_tol.FIT_INSIDE_MAX:
        raise PtailorError(
            f"--body auto: the body does not fit inside the drape at any scale from {lo:g} to"
            f" {hi:g} (at {lo:g}, {100 * fit.inside_fraction(lo):.1f} % of the garment is inside"
            " it); check --up, --front and the units, or give a body with --body FILE",
            path=path,
        )
    if fit.inside_fraction(hi) <= verify_tol.FIT_INSIDE_MAX:
        lo = hi
    for _ in range(verify_tol.FIT_SCALE_STEPS):  # bisection on the scale
        if lo == hi:
            break
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if fit.inside_fraction(mid) <= verify_tol.FIT_INSIDE_MAX else (lo, mid)
    s = lo
    if s not in fit.best:
        fit.inside_fraction(s)
    return s
