"""Units that cannot be silently wrong (issue 24): a garment read in a unit nobody gave must
be of human size (``model/size.py``), and a DXF that says only METRIC is in the unit under
which its pieces are of a garment's size."""

from __future__ import annotations

import dataclasses
import json

import ezdxf
import numpy as np
import pytest
from click.testing import CliRunner
from ezdxf.math import Matrix44

from ptailor.cli.main import cli
from ptailor.formats.garment import load_garment
from ptailor.formats.obj import write_garment
from ptailor.model.repair import UnitMismatchError
from ptailor.model.size import (
    GarmentSize,
    garment_size,
    piece_extents,
    plausible_units,
    size_problem,
)
from ptailor.samples import bodice, lantern_sleeve
from tests.conftest import SHARED, real_path

RECIPE = (
    "units: cm\n"
    "steps: [{op: scale, region: all, direction: around, axis: [0, 1, 0], factor: 1.1}]\n"
)


def run(*args):
    return CliRunner().invoke(cli, [str(a) for a in args])


def test_piece_extents_measure_a_rotated_piece_as_laid_straight():
    t = np.radians(30.0)
    R = np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]])
    sq = np.array([[0.0, 0.0], [40.0, 0.0], [40.0, 10.0], [0.0, 10.0]])
    V = np.concatenate([sq @ R.T, sq + np.array([100.0, 0.0])])
    F = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]])
    np.testing.assert_allclose(piece_extents(V, F), [[40.0, 10.0], [40.0, 10.0]], atol=1e-9)


@pytest.mark.parametrize(
    ("size", "needle"),
    [
        (GarmentSize(extent=300.0, pieces=np.zeros((0, 2))), "across"),
        (GarmentSize(extent=10.0, pieces=np.zeros((0, 2))), "across"),
        (GarmentSize(extent=60.0, pieces=np.zeros((0, 2)), thickness=93.0), "thick"),
        (GarmentSize(extent=float("nan"), pieces=np.array([[7.3, 2.0]])), "largest piece"),
        (GarmentSize(extent=float("nan"), pieces=np.array([[300.0, 20.0]])), "longer"),
        (GarmentSize(extent=float("nan"), pieces=np.array([[200.0, 170.0]])), "wider"),
    ],
)
def test_what_is_not_of_human_size(size, needle):
    assert needle in size_problem(size)


def test_the_samples_are_of_human_size_in_cm_only():
    for g in (bodice(), lantern_sleeve()):
        s = garment_size(g.V3, g.F3, g.V2, g.F2)
        assert size_problem(s) is None
        assert size_problem(s.scaled(10.0)) is not None  # read as cm from mm
        assert "cm" in [name for name, _ in plausible_units(s)]


@pytest.fixture
def bodice_in_mm(tmp_path):
    g = bodice()
    mm = dataclasses.replace(g, V3=g.V3 * 10.0, V2=g.V2 * 10.0)
    path = tmp_path / "bodice_mm.obj"
    write_garment(path, mm)
    return path


def test_a_garment_in_mm_read_with_the_default_is_exit_2_naming_the_options(bodice_in_mm, tmp_path):
    rec = tmp_path / "r.yaml"
    rec.write_text(RECIPE)
    out = tmp_path / "out"
    res = run("adjust", bodice_in_mm, rec, "-o", out)
    assert res.exit_code == 2, res.output
    assert "--drape-units" in res.output and "--pattern-units" in res.output
    assert "read in mm" in res.output  # the unit under which it is of human size
    assert not out.exists()
    # given in mm, it runs; given explicitly in cm (consistent), it is the user's word
    assert run("adjust", bodice_in_mm, rec, "-o", out, "--drape-units", "mm",
               "--pattern-units", "mm", "-q").exit_code == 0  # fmt: skip
    loaded = load_garment(bodice_in_mm, pattern_units="cm", drape_units="cm")
    assert loaded.intake["units"]["drape_source"] == "command line"


def test_not_given_units_are_recorded_as_default_and_checked(tmp_path):
    path = tmp_path / "b.obj"
    write_garment(path, bodice())
    loaded = load_garment(path, pattern_units=None, drape_units=None)
    assert loaded.intake["units"]["drape_source"] == "default, size checked"
    assert loaded.intake["units"]["pattern_source"] == "default, size checked"
    g = bodice()
    tiny = tmp_path / "tiny.obj"  # written in dm, read as cm: 10 times too small
    write_garment(tiny, dataclasses.replace(g, V3=g.V3 / 10.0, V2=g.V2 / 10.0))
    with pytest.raises(UnitMismatchError, match="--drape-units and --pattern-units"):
        load_garment(tiny, pattern_units=None, drape_units=None, units="mm")
    # the computation unit does not change the file's: the same garment read for mm
    assert (
        load_garment(path, pattern_units=None, drape_units=None, units="mm").garment.units == "mm"
    )


def test_tee6_read_without_unit_options_is_exit_2_and_with_them_runs(tmp_path):
    tee = real_path("tee6")
    rec = tmp_path / "r.yaml"
    rec.write_text(RECIPE)
    out = tmp_path / "out"
    res = run("adjust", tee, rec, "-o", out, "--no-baseline", "--formats", "obj")
    assert res.exit_code == 2, res.output
    assert "--drape-units and --pattern-units" in res.output and "0.3333cm" in res.output
    assert not out.exists()
    ok = run("adjust", tee, rec, "-o", out, "--no-baseline", "--formats", "obj", "-q",
             "--pattern-units", "0.3333cm", "--drape-units", "0.3333cm")  # fmt: skip
    assert ok.exit_code == 0, ok.output
    report = json.loads((out / "report.json").read_text())
    assert report["units"]["drape"] == "0.3333cm"
    assert report["units"]["drape_source"] == "command line"


@pytest.mark.parametrize("key", ["tshirt", "longsleeve", "dress"])
def test_the_shared_garments_in_cm_pass_the_size_check(key):
    loaded = load_garment(real_path(key), pattern_units="auto", drape_units=None)
    assert loaded.intake["units"]["drape_source"] == "default, size checked"


def scaled_dxf(src, dst, s: float) -> None:
    """A copy of an AAMA/ASTM DXF with every coordinate times ``s`` (the pieces' blocks and
    the inserts' positions), its 'Units:' text kept."""
    doc = ezdxf.readfile(src)
    m = Matrix44.scale(s)
    for blk in doc.blocks:
        if not blk.name.startswith("*"):
            for e in blk:
                e.transform(m)
    for e in doc.modelspace():
        if e.dxftype() == "INSERT":
            e.dxf.insert = e.dxf.insert * s
        else:
            e.transform(m)
    doc.saveas(dst)


@pytest.mark.slow  # a real CAD pattern read twice: 1 s
def test_a_metric_dxf_in_cm_reads_as_the_same_pieces_as_the_mm_one(tmp_path):
    src = SHARED / "dxf" / "clo-pattern.dxf"
    if not src.is_file():
        pytest.skip(f"{src} not available (../shared is absent)")
    dst = tmp_path / "clo_cm.dxf"
    scaled_dxf(src, dst, 0.1)
    mm = json.loads(run("inspect", src, "--json").output)
    cm = json.loads(run("inspect", dst, "--json").output)
    assert mm["units"]["file"] == "mm" and cm["units"]["file"] == "cm"
    assert "garment size only in cm" in cm["units"]["note"]
    for a, b in zip(mm["pieces"], cm["pieces"], strict=True):
        np.testing.assert_allclose(a["size_cm"], b["size_cm"], rtol=1e-6)
    text = run("inspect", dst).output
    assert text.count("size (cm)") == 1  # one size column for a file in cm


def test_a_garment_beside_a_body_of_another_size_is_exit_2_unless_its_units_are_given(tmp_path):
    """A body written in metres read as cm (1.7 'cm' tall) beside a 30 cm bodice (worn on
    it: a 20 cm wide box through the bodice's 30 cm tube)."""
    import trimesh

    body = tmp_path / "body.obj"
    trimesh.creation.box(extents=(0.2, 1.7, 0.2)).export(body)
    garment = tmp_path / "b.obj"
    write_garment(garment, bodice())
    rec = tmp_path / "r.yaml"
    rec.write_text("units: cm\nsteps: []\n")
    out = tmp_path / "out"
    res = run("adjust", garment, rec, "-o", out, "--body", body, "--no-baseline")
    assert res.exit_code == 2, res.output
    assert "--body-units" in res.output and "--drape-units" in res.output
    assert not out.exists()
    ok = run("adjust", garment, rec, "-o", out, "--body", body, "--body-units", "m",
             "--no-baseline", "-q")  # fmt: skip
    assert ok.exit_code == 0, ok.output


# ------------------------------------------- units given are checked too (issue 42, item 8)


@pytest.mark.parametrize(
    ("units", "warned"),
    [(("cm", "cm"), False), (("mm", "mm"), True), (("m", "m"), True), (("cm", None), False)],
)
def test_units_given_that_make_no_garment_are_a_warning_not_a_refusal(tmp_path, units, warned):
    from ptailor.formats.garment import load_garment
    from ptailor.formats.obj import write_garment
    from ptailor.samples import flat_tee

    p = tmp_path / "tee.obj"
    write_garment(p, flat_tee())
    loaded = load_garment(p, drape_units=units[0], pattern_units=units[1])
    found = [w for w in loaded.intake["warnings"] if "not a garment's size" in w]
    assert bool(found) == warned
    if warned:
        assert found[0].startswith(f"read with --drape-units {units[0]}")
        assert "check the units" in found[0]
