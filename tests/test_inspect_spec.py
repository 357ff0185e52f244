"""``ptailor inspect GARMENT --spec SPEC.json``: each specification panel with its mesh panel,
each stitch with its seam and both lengths (the shared garments; skipped when absent)."""

from __future__ import annotations

import json
import re
from collections import Counter
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from ptailor.cli.main import cli
from tests.conftest import GARMENTS

TEE6 = GARMENTS / "gpg_tee6" / "tee6_sim.obj"
TEE6_SPEC = GARMENTS / "gpg_tee6" / "tee6_specification.json"
TEE6_UNITS = ["--pattern-units", "0.3333cm", "--drape-units", "0.3333cm"]
SHIRT = GARMENTS / "garmentcode" / "shirt_mean_boxmesh.obj"
SHIRT_SPEC = GARMENTS / "garmentcode" / "shirt_mean_specification.json"
SHIRT_SEGMENTATION = GARMENTS / "garmentcode" / "shirt_mean_sim_segmentation.txt"

#: tee6: each specification panel and the mesh panel of that name (tests/test_names.py)
TEE6_PANELS = {
    "lfsleeve": "sleeve_left_front",
    "lbsleeve": "sleeve_left_back",
    "rfsleeve": "sleeve_right_front",
    "rbsleeve": "sleeve_right_back",
    "front": "front",
    "back": "back",
}


def shared(*paths: Path) -> None:
    """Skip when a shared file is absent."""
    for p in paths:
        if not p.is_file():
            pytest.skip(f"{p} not available (../shared is absent)")


def inspect(*args) -> tuple[int, str]:
    """``ptailor inspect ARGS``: exit code and output (stderr with it)."""
    r = CliRunner().invoke(cli, ["inspect", *(str(a) for a in args)])
    return r.exit_code, r.output


@pytest.fixture(scope="module")
def tee6_json() -> dict:
    shared(TEE6, TEE6_SPEC)
    code, out = inspect(TEE6, *TEE6_UNITS, "--spec", TEE6_SPEC, "--json")
    assert code == 0, out
    return json.loads(out)


@pytest.fixture(scope="module")
def shirt_json() -> dict:
    shared(SHIRT, SHIRT_SPEC)
    code, out = inspect(SHIRT, "--pattern-units", "auto", "--spec", SHIRT_SPEC, "--json")
    assert code == 0, out
    return json.loads(out)


def read_obj(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """An OBJ's ``v`` positions and its faces' ``v`` indices (0-based), read here."""
    V, F = [], []
    with open(path) as fh:
        for line in fh:  # a loop over the file's lines
            if line.startswith("v "):
                V.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                F.append([int(t.split("/")[0]) - 1 for t in line.split()[1:]])
    return np.array(V), np.array(F)


@pytest.mark.slow
def test_tee6_spec_panels_are_the_mesh_panels_named_like_them(tee6_json):
    sec = tee6_json["spec"]
    assert sec["input"] == str(TEE6_SPEC)
    assert sec["format"] == "gpg"
    assert sec["units_in_meter"] > 0
    got = {p["name"]: p["panel"] for p in sec["panels"]}
    assert got == TEE6_PANELS
    for p in sec["panels"]:
        assert 0 <= p["fit"] < 0.1  # cm: the outlines lie on each other
        assert p["residual"] >= 0
        assert isinstance(p["mirrored"], bool)


@pytest.mark.slow
def test_tee6_every_stitch_has_a_seam_and_its_lengths(tee6_json):
    sec = tee6_json["spec"]
    seams = {s["name"]: s for s in tee6_json["seams"]}
    panel_of = {p["name"]: p["panel"] for p in sec["panels"]}
    assert [s["stitch"] for s in sec["stitches"]] == list(range(12))
    for s in sec["stitches"]:
        assert s["seam"] in seams, s
        sides = [side.rsplit(".", 1)[0] for side in s["sides"]]
        # the seam joins the mesh panels the two stitched panels are
        assert sorted(seams[s["seam"]]["panels"]) == sorted(panel_of[n] for n in sides)
        for a, b in zip(s["spec_lengths"], s["mesh_lengths"], strict=True):
            assert a > 0
            assert abs(a - b) < 0.1, s  # cm
    # every seam of tee6 is one stitch
    assert sorted(s["seam"] for s in sec["stitches"]) == sorted(seams)


@pytest.mark.slow
def test_tee6_text_lists_the_panels_and_stitches():
    shared(TEE6, TEE6_SPEC)
    code, out = inspect(TEE6, *TEE6_UNITS, "--spec", TEE6_SPEC)
    assert code == 0, out
    lines = out.splitlines()
    head = lines.index(f"specification (gpg, {TEE6_SPEC}):")
    block = lines[head + 1 :]
    for name, panel in TEE6_PANELS.items():
        assert any(
            re.fullmatch(rf"  {name} -> {panel}  fit \d+\.\d{{3}} cm(  mirrored)?", ln)
            for ln in block
        ), (name, block)
    stitch = re.compile(
        r"  stitch (\d+)  \S+\.\d+ / \S+\.\d+  -> \w+"
        r"  spec \d+\.\d\d / \d+\.\d\d, mesh \d+\.\d\d / \d+\.\d\d"
    )
    got = [int(m.group(1)) for ln in block if (m := stitch.fullmatch(ln))]
    assert got == list(range(12))


@pytest.mark.slow
def test_shirt_panels_and_stitches(shirt_json):
    sec = shirt_json["spec"]
    assert sec["format"] == "garmentcode"
    assert len(sec["panels"]) == 8
    assert len({p["panel"] for p in sec["panels"]}) == 8
    assert len(sec["stitches"]) == 18
    names = {s["name"] for s in shirt_json["seams"]}
    for s in sec["stitches"]:
        assert s["seam"] in names
        for a, b in zip(s["spec_lengths"], s["mesh_lengths"], strict=True):
            assert abs(a - b) < 0.1, s
    # the pattern's scale came from the specification, not from the drape's estimate
    units = shirt_json["units"]
    assert units["pattern_source"] == "specification"
    assert "pattern_scale_estimate" not in units


def _shirt_structure():
    from ptailor.formats.garment import load_garment
    from ptailor.model.structure import structure

    g = load_garment(SHIRT, pattern_units="auto").garment
    return g, structure(g)  # inspect's default axes: y up, z front


@pytest.mark.slow
def test_shirt_panel_matching_agrees_with_garmentcodes_segmentation(shirt_json):
    """GarmentCode's own per-vertex labels: the mesh panel a spec panel is matched to is
    made of the vertices GarmentCode labelled with that spec panel's name."""
    shared(SHIRT_SEGMENTATION)
    V, F = read_obj(SHIRT)
    labels = SHIRT_SEGMENTATION.read_text().split()
    assert len(labels) == len(V)  # one line per OBJ v line
    g, st = _shirt_structure()
    assert g.F3.shape == F.shape and (g.F3 == F).all()  # the faces are the OBJ's, in order
    spec_names = {p["name"] for p in shirt_json["spec"]["panels"]}
    majority = {}
    for p in st.panels:  # a loop over the mesh panels
        used = np.unique(F[p.faces])
        votes = Counter(labels[v] for v in used if labels[v] in spec_names)
        (label, n), *_ = votes.most_common()
        assert n > 0.95 * sum(votes.values()), (p.name, votes)
        majority[p.name] = label
    got = {p["panel"]: p["name"] for p in shirt_json["spec"]["panels"]}
    assert got == majority


@pytest.mark.slow
def test_shirt_stitches_lie_on_their_seams_in_garmentcodes_segmentation(shirt_json):
    """Every vertex GarmentCode labelled ``stitch_N`` lies on the seam stitch N is matched
    to."""
    shared(SHIRT_SEGMENTATION)
    labels = SHIRT_SEGMENTATION.read_text().split()
    _, st = _shirt_structure()
    seam_index = {s["name"]: i for i, s in enumerate(shirt_json["seams"])}
    for s in shirt_json["spec"]["stitches"]:  # a loop over stitches
        tag = f"stitch_{s['stitch']}"
        on = {v for v, lab in enumerate(labels) if tag in lab.split(",")}
        assert on, tag
        seam_vertices = set(st.seams[seam_index[s["seam"]]].edges3.ravel().tolist())
        assert on <= seam_vertices, (tag, s["seam"], sorted(on - seam_vertices))


@pytest.mark.slow
def test_json_has_the_spec_section(tee6_json):
    assert set(tee6_json["spec"]) == {
        "input",
        "format",
        "units_in_meter",
        "panels",
        "stitches",
    }
    assert set(tee6_json["spec"]["panels"][0]) == {"name", "panel", "mirrored", "fit", "residual"}
    assert set(tee6_json["spec"]["stitches"][0]) == {
        "stitch",
        "sides",
        "seam",
        "spec_lengths",
        "mesh_lengths",
    }


@pytest.mark.slow
def test_units_convert_the_lengths():
    """--units mm: fits and lengths in mm, ten times the cm ones."""
    shared(TEE6, TEE6_SPEC)
    args = [TEE6, *TEE6_UNITS, "--spec", TEE6_SPEC, "--json"]
    code, out = inspect(*args, "--units", "mm")
    assert code == 0, out
    code_cm, out_cm = inspect(*args)
    assert code_cm == 0, out_cm
    mm, cm = json.loads(out)["spec"], json.loads(out_cm)["spec"]
    for a, b in zip(mm["stitches"], cm["stitches"], strict=True):
        assert np.allclose(a["spec_lengths"], np.multiply(b["spec_lengths"], 10), atol=0.01)
        assert np.allclose(a["mesh_lengths"], np.multiply(b["mesh_lengths"], 10), atol=0.01)


@pytest.mark.slow
def test_a_spec_of_another_garment_exits_2_naming_the_file():
    """tee6's specification (6 panels) on the shirt (8)."""
    shared(SHIRT, TEE6_SPEC)
    code, out = inspect(SHIRT, "--pattern-units", "auto", "--spec", TEE6_SPEC)
    assert code == 2
    assert str(TEE6_SPEC) in out
    assert "panels" in out
    assert "Traceback" not in out


@pytest.mark.slow
def test_a_panel_of_another_shape_exits_2_naming_the_file_and_the_panel(tmp_path):
    """The shirt's specification with one panel stretched (same area, other shape)."""
    shared(SHIRT, SHIRT_SPEC)
    raw = json.loads(SHIRT_SPEC.read_text())
    panel = raw["pattern"]["panels"]["left_btorso"]
    panel["vertices"] = [[1.5 * x, y / 1.5] for x, y in panel["vertices"]]
    bad = tmp_path / "other_spec.json"
    bad.write_text(json.dumps(raw))
    code, out = inspect(SHIRT, "--pattern-units", "auto", "--spec", bad)
    assert code == 2
    assert str(bad) in out
    assert "'left_btorso'" in out
    assert "Traceback" not in out


def test_a_bad_spec_fails_before_the_garment_is_read(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{"x": 1}')
    code, out = inspect(tmp_path / "missing.obj", "--spec", bad)
    assert code == 2
    assert str(bad) in out
    assert "missing.obj" not in out
