"""``--body auto``: GarmentCode's mean body fitted to a garment (issue 25, ``verify/fit.py``)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from click.testing import CliRunner

from ptailor.cli.main import cli
from ptailor.errors import PtailorError
from ptailor.model.frame import Frame
from ptailor.model.openings import openings
from ptailor.samples import cone_skirt
from ptailor.verify.fit import fit_body, mean_body
from tests.conftest import REAL, real_path
from tests.test_names import flat_square


def test_the_shipped_bodies_are_closed_1_72_m_tall_and_front_is_z():
    import trimesh

    for pose in ("a", "t"):
        V, F = mean_body(pose)
        assert len(V) == 7002
        m = trimesh.Trimesh(V, F, process=False)
        assert m.is_watertight and m.volume > 0.05  # outward, about 73 litres
        assert np.ptp(V[:, 1]) == pytest.approx(1.72, abs=0.01)
        feet = V[V[:, 1] < 0.05]
        assert feet[:, 2].max() > -feet[:, 2].min()  # the toes point to +z
    assert np.ptp(mean_body("t")[0][:, 0]) > np.ptp(mean_body("a")[0][:, 0]) + 0.2


@pytest.mark.slow  # a fit tries some 600 placements of the body: 3-5 s
def test_a_skirt_hangs_from_its_waist_with_the_body_inside():
    g = cone_skirt()
    fit = fit_body(g.V3, g.F3, openings=openings(g.V3, g.F3, F2=g.F2, frame=Frame()), frame=Frame())
    assert fit.anchor == "waist" and fit.pose == "a"
    assert fit.inside <= 0.005
    assert 0.5 <= fit.scale <= 1.5
    rec = fit.record()
    assert rec["pose"] == "a-pose" and rec["inside_fraction"] <= 0.005


def test_a_drape_with_nothing_to_hang_on_is_refused():
    g = flat_square()
    with pytest.raises(PtailorError, match="neither a neckline nor a waist"):
        ops = openings(g.V3, g.F3, F2=g.F2, frame=Frame())
        fit_body(g.V3, g.F3, openings=ops, path="square.obj", frame=Frame())


@pytest.mark.slow  # a fit tries some 600 placements of the body: 3-5 s
@pytest.mark.parametrize(("key", "pose"), [("tee6", "t"), ("tshirt", "a"), ("longsleeve", "a")])
def test_the_shared_tops_are_fitted_in_their_pose(key, pose):
    from ptailor.formats.garment import load_garment

    units = {"tee6": ("0.3333cm", "0.3333cm")}.get(key, (REAL[key][1], "cm"))
    g = load_garment(real_path(key), pattern_units=units[0], drape_units=units[1]).garment
    fit = fit_body(g.V3, g.F3, openings=openings(g.V3, g.F3, F2=g.F2, frame=Frame()), frame=Frame())
    assert fit.pose == pose and fit.anchor == "neckline"
    assert fit.inside <= 0.005
    assert 0.6 <= fit.scale <= 1.2  # a body of 1.0-2.1 m
    assert 1.0 <= fit.gap_median <= 6.0  # cm: a tee hangs a few cm off the body


@pytest.mark.slow  # a fit tries some 600 placements of the body: 3-5 s
def test_adjust_with_body_auto_records_the_fit(tmp_path):
    from ptailor.formats.obj import write_garment

    write_garment(tmp_path / "skirt.obj", cone_skirt())
    (tmp_path / "r.yaml").write_text("units: cm\nsteps: [{op: extend, opening: hem, by: 2}]\n")
    r = CliRunner().invoke(
        cli,
        ["adjust", str(tmp_path / "skirt.obj"), str(tmp_path / "r.yaml"), "-o",
         str(tmp_path / "o"), "--body", "auto", "--formats", "obj", "--no-baseline"],
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    report = json.loads((tmp_path / "o" / "report.json").read_text())
    assert report["body_fit"]["anchor"] == "waist"
    assert report["body_fit"]["pose"] == "a-pose"


def test_body_auto_on_a_drape_it_cannot_fit_is_exit_2(tmp_path):
    from ptailor.formats.obj import write_garment

    write_garment(tmp_path / "square.obj", flat_square())
    (tmp_path / "r.yaml").write_text("steps: []\n")
    r = CliRunner().invoke(
        cli,
        ["adjust", str(tmp_path / "square.obj"), str(tmp_path / "r.yaml"), "-o",
         str(tmp_path / "o"), "--body", "auto"],
    )  # fmt: skip
    assert r.exit_code == 2, r.output
    assert "--body auto" in r.output and "square.obj" in r.output
    assert not (tmp_path / "o").exists()
