"""The garment carries its frame: a garment turned to z up (and mirrored, and turned about
up) and read with the matching axes gets the same names, the same report (less its
coordinates) and a file that reads back with the same names."""

from __future__ import annotations

import json
import pickle
import re
from dataclasses import replace

import numpy as np
import pytest
from click.testing import CliRunner

from ptailor.cli.main import cli
from ptailor.formats.garment import load_garment
from ptailor.formats.obj import write_garment, write_obj
from ptailor.model.frame import DEFAULT_FRAME, Frame, axis_vector
from ptailor.model.names import seam_names
from ptailor.model.structure import structure
from ptailor.samples import flat_tee, halved_bodice, unnamed_skirt

from .conftest import REAL, real_path

#: y up, z front -> z up, -y front (a right-handed turn about x)
Z_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
Z_FRAME = Frame((0.0, 0.0, 1.0), (0.0, -1.0, 0.0))


def about_z(deg: float) -> np.ndarray:
    a = np.radians(deg)
    return np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0], [0, 0, 1.0]])


def bare(g):
    """The garment without group names: every panel named from the drape."""
    return replace(g, face_group=np.full(g.n_faces, -1), group_names=())


def mirrored(g):
    """The garment's mirror image across its sagittal plane (x -> -x), a true garment: the
    pattern mirrored too and every triangle's winding reversed."""
    flip = np.array([-1.0, 1.0, 1.0])
    return replace(
        g, V3=g.V3 * flip, V2=g.V2 * flip[:2], F3=g.F3[:, ::-1].copy(), F2=g.F2[:, ::-1].copy()
    )


def swap_sides(name: str) -> str:
    return re.sub(r"left|right", lambda m: "right" if m.group(0) == "left" else "left", name)


def turned(g, R: np.ndarray, frame: Frame):
    """``g`` with its drape turned by ``R`` (and moved), worn in ``frame``."""
    return replace(g, V3=g.V3 @ R.T + np.array([3.0, -40.0, 12.0]), frame=frame)


def names(g) -> dict[str, list[str]]:
    """Every name a garment's structure gives: panels, seams and openings."""
    st = structure(g)
    panels = [p.name for p in st.panels]
    return {
        "panels": panels,
        "seams": seam_names(g.V3, st.seams, st.layout, panels),
        "openings": sorted(o.name for o in st.openings),
    }


GARMENTS = {
    "tee": lambda: bare(flat_tee()),
    "tee_one_piece_sleeves": lambda: bare(flat_tee(sleeves="one")),
    "skirt": unnamed_skirt,
    "halved_bodice": halved_bodice,
}


# ---------------------------------------------------------------- the frame itself


def test_frame_rows_and_names():
    assert Frame.from_names("z", "-y") == Z_FRAME
    assert axis_vector("-x") == (-1.0, 0.0, 0.0)
    np.testing.assert_allclose(DEFAULT_FRAME.matrix(), np.eye(3))
    np.testing.assert_allclose(Z_FRAME.matrix() @ Z_UP, np.eye(3), atol=1e-15)
    assert Frame().side == (1.0, 0.0, 0.0)  # y up, z front: the wearer's left is +x
    with pytest.raises(ValueError, match="parallel"):
        Frame((0, 0, 1), (0, 0, -2))
    with pytest.raises(ValueError, match="finite non-zero"):
        Frame((0, 0, 0), (0, 0, 1))
    with pytest.raises(ValueError):
        axis_vector("w")


def test_a_garment_keeps_its_frame_through_copies_and_pickles():
    g = flat_tee().with_frame(Z_FRAME)
    assert g.with_drape(g.V3 * 2).frame == Z_FRAME
    assert g.with_pattern(g.V2 * 2).frame == Z_FRAME
    assert pickle.loads(pickle.dumps(g)).frame == Z_FRAME
    with pytest.raises(TypeError, match="Frame"):
        replace(g, frame=((0, 0, 1), (0, -1, 0)))


def test_the_structure_follows_the_garments_frame():
    g = bare(flat_tee())
    h = g.with_frame(Z_FRAME)  # the same drape worn lying down: other names
    assert structure(h) is not structure(g)
    assert names(h)["panels"] != names(g)["panels"]


# ---------------------------------------------------------------- names under any frame


@pytest.mark.parametrize("key", sorted(GARMENTS))
@pytest.mark.parametrize("how", ["z_up", "z_up_turned_30", "z_up_mirrored"])
def test_names_follow_the_frame(key, how):
    g = GARMENTS[key]()
    want = names(g)
    if how == "z_up":
        h = turned(g, Z_UP, Z_FRAME)
    elif how == "z_up_turned_30":  # the wearer faces 30 degrees off -y, and the frame says so
        R = about_z(30.0)
        h = turned(g, R @ Z_UP, Frame((0, 0, 1), R @ [0.0, -1.0, 0.0]))
    else:
        h = turned(mirrored(g), Z_UP, Z_FRAME)
        want = {k: [swap_sides(n) for n in v] for k, v in want.items()}
        want["openings"] = sorted(want["openings"])
    assert names(h) == want


@pytest.mark.parametrize("key", sorted(GARMENTS))
def test_a_written_garment_reads_back_with_its_names(key, tmp_path):
    """``write_garment`` names panels under the garment's own frame (it once named a z-up
    garment's panels under y up and wrote those names into the file)."""
    g = GARMENTS[key]()
    h = turned(g, Z_UP, Z_FRAME)
    path = tmp_path / "g.obj"
    write_garment(path, h)
    back = load_garment(path, frame=Z_FRAME).garment
    assert back.frame == Z_FRAME
    assert [p.name for p in structure(back).panels] == names(g)["panels"]
    # the names are in the file: read under any frame they stay
    assert [p.name for p in structure(load_garment(path).garment).panels] == names(g)["panels"]


@pytest.mark.slow
@pytest.mark.parametrize("key", ["tee6", "dress"])
def test_shared_garments_name_alike_under_any_frame(key):
    loaded = load_garment(real_path(key), pattern_units=REAL[key][1])
    g = bare(loaded.garment)
    want = names(g)
    assert names(turned(g, Z_UP, Z_FRAME)) == want
    R = about_z(30.0)
    assert names(turned(g, R @ Z_UP, Frame((0, 0, 1), R @ [0.0, -1.0, 0.0]))) == want


# ---------------------------------------------------------------- the command line


def _write_bare(path, g, V3):
    """An OBJ of ``g`` with drape ``V3`` and one group over the whole mesh (no panel names:
    every name comes from the drape under the run's axes)."""
    write_obj(path, V3=V3, F3=g.F3, V2=g.V2, F2=g.F2,
              face_panel=np.zeros(g.n_faces, dtype=int), panel_names=["garment"])  # fmt: skip


#: report fields that are coordinates in the drape's frame (they turn with it)
COORDINATES = {"plane", "point", "normal", "centroid", "axis", "timing_s", "inputs", "outputs"}


def _without_coordinates(x):
    if isinstance(x, dict):
        return {k: _without_coordinates(v) for k, v in x.items() if k not in COORDINATES}
    if isinstance(x, list):
        return [_without_coordinates(v) for v in x]
    if isinstance(x, float):
        return round(x, 4)
    return x


@pytest.mark.slow  # two adjust runs each: 0.3-0.8 s
@pytest.mark.parametrize(
    ("recipe", "sample"),
    [
        ("units: cm\nsymmetric: true\nsteps:\n  - op: scale\n    region: {panels: [sleeve_left]}"
         "\n    direction: around\n    axis: auto\n    factor: 1.1\n", "tee"),
        ("units: cm\nsteps:\n  - op: shorten\n    opening: hem\n    by: 3\n", "skirt"),
    ],
    ids=["tee_wider_sleeves", "skirt_shorter"],
)  # fmt: skip
def test_adjust_under_z_up_gives_the_same_report_and_names(recipe, sample, tmp_path):
    g = GARMENTS[sample]()
    (tmp_path / "r.yaml").write_text(recipe)
    _write_bare(tmp_path / "y.obj", g, g.V3)
    _write_bare(tmp_path / "z.obj", g, g.V3 @ Z_UP.T)
    runner = CliRunner()
    common = [str(tmp_path / "r.yaml"), "--formats", "obj"]
    out_y = ["-o", str(tmp_path / "oy")]
    ry = runner.invoke(cli, ["adjust", str(tmp_path / "y.obj"), *common, *out_y])
    rz = runner.invoke(
        cli,
        ["adjust", str(tmp_path / "z.obj"), *common, "-o", str(tmp_path / "oz"),
         "--up", "z", "--front", "-y"],
    )  # fmt: skip
    assert ry.exit_code == 0, ry.output
    assert rz.exit_code == 0, rz.output
    rep_y = json.loads((tmp_path / "oy" / "report.json").read_text())
    rep_z = json.loads((tmp_path / "oz" / "report.json").read_text())
    assert _without_coordinates(rep_z) == _without_coordinates(rep_y)
    # the written garment reads back with the same names under the same axes
    back_y = load_garment(tmp_path / "oy" / "garment.obj").garment
    back_z = load_garment(tmp_path / "oz" / "garment.obj", frame=Z_FRAME).garment
    assert [p.name for p in structure(back_z).panels] == [p.name for p in structure(back_y).panels]
    np.testing.assert_allclose(back_z.V3, back_y.V3 @ Z_UP.T, atol=1e-6)


def test_a_file_ptailor_wrote_carries_its_frame(tmp_path):
    """A garment written in a frame other than the default says so in a comment, and a
    reader given no axes takes it: an adjusted z-up garment reads back z up."""
    g = turned(GARMENTS["skirt"](), Z_UP, Z_FRAME)
    write_garment(tmp_path / "z.obj", g)
    assert "# ptailor frame: up z, front -y\n" in (tmp_path / "z.obj").read_text()
    assert load_garment(tmp_path / "z.obj").garment.frame == Z_FRAME
    # the command line's axes win over the file's
    assert load_garment(tmp_path / "z.obj", frame=DEFAULT_FRAME).garment.frame == DEFAULT_FRAME
    # a default-frame garment's file says nothing (and reads back y up)
    write_garment(tmp_path / "y.obj", GARMENTS["skirt"]())
    assert "ptailor frame" not in (tmp_path / "y.obj").read_text()
    assert load_garment(tmp_path / "y.obj").garment.frame == DEFAULT_FRAME
    # a frame off the axes has no names to write: the file says nothing
    assert Frame((0, 1, 0), (1, 0, 1)).header() is None


def test_a_bad_frame_comment_is_exit_2_naming_the_file(tmp_path):
    bad = tmp_path / "bad.obj"
    write_garment(bad, GARMENTS["skirt"](), header=["ptailor frame: up z, front z"])
    r = CliRunner().invoke(cli, ["inspect", str(bad)])
    assert r.exit_code == 2
    assert "bad.obj" in r.output and "parallel" in r.output


def test_adjust_then_inspect_keeps_the_frame(tmp_path):
    """``adjust --up z --front -y`` writes a garment that ``inspect`` (no axes) names the
    same way: its openings are found under the frame the file states."""
    g = GARMENTS["skirt"]()
    _write_bare(tmp_path / "z.obj", g, g.V3 @ Z_UP.T)
    (tmp_path / "r.yaml").write_text("units: cm\nsteps: []\n")
    r = CliRunner().invoke(cli, ["adjust", str(tmp_path / "z.obj"), str(tmp_path / "r.yaml"),
                                 "-o", str(tmp_path / "o"), "--formats", "obj",
                                 "--up", "z", "--front", "-y"])  # fmt: skip
    assert r.exit_code == 0, r.output
    info = CliRunner().invoke(cli, ["inspect", str(tmp_path / "o" / "garment.obj"), "--json"])
    assert info.exit_code == 0, info.output
    names = sorted(o["name"] for o in json.loads(info.output)["openings"])
    assert names == names_of_openings(g)


def names_of_openings(g) -> list[str]:
    return sorted(o.name for o in structure(g).openings)
