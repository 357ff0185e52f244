"""``--body auto`` poses the mean body's legs to the trouser legs (issue 46, ``verify/legs.py``)."""

from __future__ import annotations

import numpy as np
import pytest

from ptailor.geometry.tube_axis import tube_axis
from ptailor.samples import cone_skirt
from ptailor.samples.tee import flat_tee
from ptailor.verify import tolerances as verify_tol
from ptailor.verify.fit import fit_body, mean_body
from ptailor.verify.legs import crotch_height, leg_rigs, target_leg, trouser_axes
from ptailor.verify.pose import abduction, forward, pose_arms
from tests.test_body_pose import _closed_outward

#: a trouser leg's axis, found again after its leg was turned (degrees): the part below the
#: garment's crotch changes as the leg turns (its outer side rises above the crotch)
AXIS_TOL_DEG = 1.5
#: the posed body's thigh (its rigid part's tube axis) against the trouser leg's axis
#: (degrees): the skinning turns the rigid leg exactly, the tube axis of a posed mesh is
#: measured within this
POSED_TOL_DEG = 1.0


@pytest.fixture(scope="module")
def rigged():
    """The A-pose body, its crotch's height and its legs' rigs (computed once)."""
    import trimesh  # noqa: F401

    V, F = mean_body("a")
    return V, F, crotch_height(V, F), leg_rigs(V, F)


def _thigh_faces(V: np.ndarray, F: np.ndarray, y_c: float, rig) -> np.ndarray:
    """The rigid part (weight 1) of a rig's thigh, as triangles of the A-pose body."""
    h = float(np.ptp(V[:, 1]))
    m = (rig.weight > 0.999) & (V[:, 1] > y_c - verify_tol.FIT_THIGH * h) & (V[:, 1] < y_c)
    return F[m[F].all(axis=1)]


def _axis(X: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """A tube's axis, pointing down."""
    a = tube_axis(X, faces)
    return a if a[1] < 0 else -a


def test_the_legs_part_below_the_crotch_and_the_torso_stays(rigged):
    V, _, y_c, rigs = rigged
    assert 0.64 <= y_c <= 0.74  # m: the mean body's crotch (1.72 m tall)
    s = {"left": 1.0, "right": -1.0}
    for r in rigs:
        assert 0.07 <= s[r.side] * r.joint[0] <= 0.11  # the hip joint, 9 cm off the centre
        assert y_c < r.joint[1] < y_c + 0.1
        assert abduction(r.bone, r.side) == pytest.approx(2.5, abs=2.0)  # a standing leg
        foot = V[:, 1] < 0.1
        assert (r.weight[foot & (s[r.side] * V[:, 0] > 0)] == 1).all()
        assert (r.weight[s[r.side] * V[:, 0] <= 0] == 0).all()  # the other leg, the centre
        assert (r.weight[V[:, 1] > r.joint[1] + 0.1] == 0).all()  # the torso, the hands
        assert ((r.weight > 0) & (r.weight < 1)).sum() > 100  # a blended hip


@pytest.mark.parametrize("angle", [10.0, 30.0])
def test_the_legs_turn_to_the_angle_asked_and_the_body_stays_closed(angle, tmp_path, rigged):
    V, F, y_c, rigs = rigged
    s = {"left": 1.0, "right": -1.0}
    a = np.radians(angle)
    bones = {
        r.side: target_leg(r, np.array([s[r.side] * np.sin(a), -np.cos(a), 0.0])) for r in rigs
    }
    P = pose_arms(V, rigs, bones)
    for r in rigs:
        faces = _thigh_faces(V, F, y_c, r)
        before, after = _axis(V, faces), _axis(P, faces)
        assert abduction(after, r.side) == pytest.approx(angle, abs=POSED_TOL_DEG)
        assert forward(after) == pytest.approx(0.0, abs=POSED_TOL_DEG)
        assert abduction(before, r.side) == pytest.approx(abduction(r.bone, r.side), abs=0.5)
    _closed_outward(tmp_path, P * 100.0, F)


def test_the_abduction_is_kept_within_its_range(rigged):
    rig = rigged[3][0]
    lo, hi = verify_tol.FIT_LEG_ABDUCTION
    crossed = np.array([-np.sin(0.3), -np.cos(0.3), 0.0])  # 17 degrees inward
    assert abduction(target_leg(rig, crossed), "left") == pytest.approx(lo)
    split = np.array([1.0, -0.2, 0.0]) / np.hypot(1.0, 0.2)  # 79 degrees out
    assert abduction(target_leg(rig, split), "left") == pytest.approx(hi)


def test_a_skirt_and_a_tee_have_no_trouser_legs():
    assert trouser_axes(cone_skirt()) == {}
    assert trouser_axes(flat_tee()) == {}


def _shared(key: str):
    """A shared GarmentCode garment (``shorts``, ``jumpsuit``), skipped when absent."""
    from tests.names.cases import CASES, garment_of, shared_file

    case = next(c for c in CASES if c.key == f"shared-{key}")
    if not shared_file(case).is_file():
        pytest.skip(f"{shared_file(case)} absent (no ../shared)")
    return garment_of(case)


def _turned(g, angle: float):
    """The garment with each trouser leg (its part below the crotch) turned in the frontal
    plane about the top of its axis to ``angle`` degrees from straight down."""
    V = np.array(g.V3, dtype=np.float64)
    for side, ax in trouser_axes(g).items():  # the two legs
        s = 1.0 if side == "left" else -1.0
        top = V[ax.vertices, 1].max()
        pivot = ax.point + ax.direction * ((top - ax.point[1]) / ax.direction[1])
        a = np.radians(s * (angle - abduction(ax.direction, side)))
        c, si = np.cos(a), np.sin(a)
        turn = np.array([[c, si, 0.0], [-si, c, 0.0], [0.0, 0.0, 1.0]])
        V[ax.vertices] = pivot + (V[ax.vertices] - pivot) @ turn
    return g.with_drape(V)


@pytest.fixture(scope="module")
def shorts():
    return _shared("shorts")


@pytest.mark.slow  # the shared shorts' structure: about 1 s
@pytest.mark.parametrize("angle", [10.0, 20.0, 30.0])
def test_the_trouser_legs_axes_give_their_angle(angle, shorts):
    axes = trouser_axes(_turned(shorts, angle))
    assert set(axes) == {"left", "right"}
    for side, ax in axes.items():
        assert abduction(ax.direction, side) == pytest.approx(angle, abs=AXIS_TOL_DEG)
        assert ax.direction[1] < 0  # down, to the leg opening


def _check_legs(g, body_V, rec: dict, rigged) -> None:
    """Each posed leg's thigh (measured on the fitted body) along its trouser leg's axis,
    and its hip moved onto that axis (within the cap)."""
    V, F, y_c, rigs = rigged
    axes = trouser_axes(g)
    assert set(rec["legs"]) == set(axes) == {"left", "right"}
    for r in rigs:
        ax, leg = axes[r.side], rec["legs"][r.side]
        posed = _axis(body_V, _thigh_faces(V, F, y_c, r))
        assert abduction(posed, r.side) == pytest.approx(
            abduction(ax.direction, r.side), abs=POSED_TOL_DEG
        )
        assert forward(posed) == pytest.approx(forward(ax.direction), abs=POSED_TOL_DEG)
        assert leg["leg_abduction_deg"] == pytest.approx(leg["trouser_abduction_deg"], abs=0.1)
        assert 0.0 <= leg["hip_shift"] <= verify_tol.FIT_HIP_SHIFT_CM + 1e-9


@pytest.mark.slow  # a fit tries some 600 placements of the body: 5-10 s
def test_body_auto_poses_the_legs_to_trousers_at_20_degrees(tmp_path, shorts, rigged):
    from ptailor.model.structure import structure

    g = _turned(shorts, 20.0)
    fit = fit_body(
        g.V3, g.F3, openings=structure(g).openings, frame=g.frame, trousers=trouser_axes(g)
    )
    rec = fit.record()
    assert "arms" not in rec and rec["pose"] == "a-pose"
    for leg in rec["legs"].values():
        assert leg["leg_abduction_deg"] == pytest.approx(20.0, abs=AXIS_TOL_DEG)
    _check_legs(g, fit.V, rec, rigged)
    assert rec["drape_inside_fraction"] <= 0.05
    _closed_outward(tmp_path, fit.V, fit.F)


@pytest.mark.slow  # a fit of a shared garment: 5-10 s each
@pytest.mark.parametrize("key", ["shorts", "jumpsuit"])
def test_the_shared_trousers_hold_the_fitted_body_and_its_legs(key, rigged):
    """At most 5 % of the drape inside the fitted body, each leg along its trouser leg, and
    the jumpsuit's arms posed to its sleeves as well."""
    from ptailor.run.inputs import fitted_body
    from ptailor.verify.pose import sleeve_axes

    g = _shared(key)
    body, rec = fitted_body(g)
    assert rec["drape_inside_fraction"] <= 0.05
    legs = np.concatenate([ax.vertices for ax in trouser_axes(g).values()])
    assert body.contains(g.V3[legs]).mean() <= 0.05  # the legs, by the ray test on them all
    _check_legs(g, np.asarray(body.vertices), rec, rigged)
    sleeves = {"left", "right"} if key == "jumpsuit" else set()
    assert set(rec.get("arms", {})) == set(sleeve_axes(g)) == sleeves
