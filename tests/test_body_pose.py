"""``--body auto`` poses the mean body's arms to the sleeves (issue 46, ``verify/pose.py``)."""

from __future__ import annotations

import numpy as np
import pytest

from ptailor.samples.tee import flat_tee
from ptailor.verify import tolerances as verify_tol
from ptailor.verify.fit import fit_body, mean_body
from ptailor.verify.pose import abduction, arm_rigs, pose_arms, sleeve_axes, target_bone
from tests.conftest import REAL, real_path


def _tee_at(angle: float):
    """The sample tee (T-pose, sleeves from |x| = 24 cm out) with each sleeve turned down
    about its underarm to ``angle`` degrees from straight down."""
    g = flat_tee()
    V = np.array(g.V3, dtype=np.float64)
    turn = np.radians(90.0 - angle)
    for s in (1.0, -1.0):  # the two sleeves
        m = s * V[:, 0] > 24.0 - 1e-9  # the armhole seam too: the sleeve turns rigidly
        pivot = np.array([s * 24.0, 48.0])  # the underarm
        d = V[m, :2] - pivot
        c, si = np.cos(turn), -s * np.sin(turn)
        V[m, :2] = pivot + d @ np.array([[c, si], [-si, c]])
    return g.with_drape(V)


def _closed_outward(tmp_path, V, F):
    """The posed body, written and read back through ``--body``'s checks (closed, one
    outward piece: :func:`ptailor.edits.body.read_body`)."""
    from ptailor.edits.body import read_body

    p = tmp_path / "posed.obj"
    lines = [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in V]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in F]
    p.write_text("\n".join(lines) + "\n")
    body = read_body(str(p), units="cm", to="cm")
    assert body.is_watertight and body.volume > 0
    return body


@pytest.mark.parametrize("angle", [45.0, 60.0, 75.0])
def test_the_sleeves_axes_give_their_angle(angle):
    axes = sleeve_axes(_tee_at(angle))
    assert set(axes) == {"left", "right"}
    for side, ax in axes.items():
        assert abduction(ax.direction, side) == pytest.approx(angle, abs=3.0)
        assert ax.direction @ np.array([1.0 if side == "left" else -1.0, 0, 0]) > 0  # outward


def test_the_untouched_tee_has_horizontal_sleeves():
    axes = sleeve_axes(flat_tee())
    assert [round(abduction(a.direction, s)) for s, a in sorted(axes.items())] == [90, 90]
    assert sleeve_axes(flat_tee(sleeves="none")) == {}  # no sleeve panel: nothing to pose


@pytest.fixture(scope="module")
def rigged():
    """The A-pose body and its arms' rigs (computed once; trimesh's import paid here)."""
    import trimesh  # noqa: F401

    import ptailor.edits.body
    import ptailor.formats.obj  # noqa: F401

    V, F = mean_body("a")
    return V, F, arm_rigs(V, F)


@pytest.mark.parametrize("angle", [30.0, 70.0, 90.0])
def test_the_arms_turn_to_the_angle_asked_and_the_body_stays_closed(angle, tmp_path, rigged):
    V, F, rigs = rigged
    s = {"left": 1.0, "right": -1.0}
    a = np.radians(angle)
    bones = {
        r.side: target_bone(r, np.array([s[r.side] * np.sin(a), -np.cos(a), 0.0])) for r in rigs
    }
    P = pose_arms(V, rigs, bones)

    def axis(X, r):  # the rigid arm's principal axis, to the hand
        c = X[r.weight > 0.999] - X[r.weight > 0.999].mean(axis=0)
        d = np.linalg.eigh(c.T @ c)[1][:, -1]
        return d if d[1] < 0 or s[r.side] * d[0] > 0.9 else -d

    for r in rigs:
        # the whole arm (its forearm bends from the bone) turns as far as its bone is asked to
        turned = abduction(axis(P, r), r.side) - abduction(axis(V, r), r.side)
        assert turned == pytest.approx(angle - abduction(r.bone, r.side), abs=2.0)
        assert (r.weight > 0.999).sum() > 500 and (r.weight[V[:, 0] * s[r.side] < 0] == 0).all()
    _closed_outward(tmp_path, P * 100.0, F)


@pytest.mark.slow  # a fit tries some 600 placements of the body: 1-3 s
def test_body_auto_poses_the_arms_to_sleeves_at_75_degrees(tmp_path):
    from ptailor.model.structure import structure

    g = _tee_at(75.0)
    fit = fit_body(
        g.V3, g.F3, openings=structure(g).openings, frame=g.frame, sleeves=sleeve_axes(g)
    )
    rec = fit.record()
    assert set(rec["arms"]) == {"left", "right"}
    for arm in rec["arms"].values():
        assert arm["arm_abduction_deg"] == pytest.approx(75.0, abs=3.0)
        assert abs(arm["shoulder_shift"]) <= verify_tol.FIT_SHOULDER_SHIFT_CM + 1e-9
    assert rec["drape_inside_fraction"] <= 0.05
    _closed_outward(tmp_path, fit.V, fit.F)


@pytest.mark.slow  # a fit of a shared garment: 5-13 s each
@pytest.mark.parametrize("key", sorted(REAL))
def test_the_shared_garments_hold_the_fitted_body_and_its_arms(key):
    """At most 5 % of the drape inside the fitted body, and each sleeve's axis, from its
    middle to its cuff, inside the body's arm."""
    import trimesh

    from ptailor.formats.garment import load_garment
    from ptailor.model.structure import structure
    from ptailor.run.inputs import fitted_body

    units = {"tee6": ("0.3333cm", "0.3333cm")}.get(key, (REAL[key][1], "cm"))
    g = load_garment(real_path(key), pattern_units=units[0], drape_units=units[1]).garment
    body, rec = fitted_body(g)
    used = np.unique(g.F3)
    assert body.contains(g.V3[used]).mean() <= 0.05
    axes = sleeve_axes(g)
    assert set(rec.get("arms", {})) == set(axes)
    ops = {o.name: o for o in structure(g).openings}
    for side, ax in axes.items():
        arm = rec["arms"][side]
        assert arm["arm_abduction_deg"] == pytest.approx(abduction(ax.direction, side), abs=0.5)
        cuff = ops[f"cuff_{side}"].centroid
        along = ax.point + np.linspace(0.0, 1.0, 5)[:, None] * (cuff - ax.point)
        assert trimesh.Trimesh(body.vertices, body.faces).contains(along).all(), side
