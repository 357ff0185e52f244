"""A drape edited elsewhere (``adjust --edited-drape``, ``edited_drape`` in a manifest,
``adjustment(edited=...)``): the pattern follows it as it follows a recipe's steps."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from ptailor.batch.manifest import read_manifest
from ptailor.cli.main import cli
from ptailor.edits.drape import similar_panels
from ptailor.errors import PtailorError
from ptailor.formats import reader_for
from ptailor.formats.obj import write_garment
from ptailor.model.structure import structure
from ptailor.pipeline import adjustment
from ptailor.recipe import Recipe, parse_recipe
from ptailor.samples import bodice, flat_tee

#: a deformation-only edit (no triangle added or removed): the tee 15 % wider around
AROUND = (
    "units: cm\nsteps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.15}]\n"
)
#: the sleeves 10 % larger, uniformly: their panels move by a similarity
SLEEVES = (
    "units: cm\nsteps: [{op: scale, region: {part: sleeves}, direction: uniform, factor: 1.1}]\n"
)
#: the pattern of the edited drape agrees with the recipe's run within this (mm)
AGREE_MM = 0.01


def run(*args) -> tuple[int, str]:
    r = CliRunner().invoke(cli, [str(a) for a in args])
    return r.exit_code, r.stderr if hasattr(r, "stderr") else r.output


def pattern_mm(folder: Path) -> np.ndarray:
    """The written garment's pattern (``vt``), in mm (the tee's file unit is cm)."""
    return 10.0 * reader_for(folder / "garment.obj")(folder / "garment.obj").vt


@pytest.fixture(scope="module")
def tee() -> object:
    return flat_tee()


@pytest.fixture
def tee_obj(tmp_path, tee) -> Path:
    p = tmp_path / "tee.obj"
    write_garment(p, tee)
    return p


@pytest.mark.slow
@pytest.mark.parametrize("text", [AROUND, SLEEVES], ids=["around", "sleeves"])
def test_edited_drape_in_memory_is_the_recipes_pattern(tee, text):
    recipe = parse_recipe(text)
    a = adjustment(tee, recipe, baseline=False)
    b = adjustment(tee, Recipe(flatten=recipe.flatten), baseline=False, edited=a.garment.V3)
    assert np.array_equal(a.state.even, b.state.even)
    assert np.abs(b.result.V2 - a.result.V2).max() * 10 < AGREE_MM
    (rec,) = b.state.log
    assert rec["op"] == "edited_drape" and rec["moved_max"] > 1.0


@pytest.mark.slow
def test_cli_round_trip_gives_the_runs_pattern(tmp_path, tee_obj):
    recipe = tmp_path / "around.yaml"
    recipe.write_text(AROUND)
    assert run("adjust", tee_obj, recipe, "-o", tmp_path / "a", "-q")[0] == 0
    code, err = run(
        "adjust", tee_obj, "--edited-drape", tmp_path / "a" / "garment.obj", "-o", tmp_path / "b"
    )
    assert code == 0, err
    diff = np.abs(pattern_mm(tmp_path / "b") - pattern_mm(tmp_path / "a")).max()
    assert diff < AGREE_MM
    assert diff < np.abs(pattern_mm(tmp_path / "a") - 10 * tee_obj_vt(tee_obj)).max() / 100
    report = json.loads((tmp_path / "b" / "report.json").read_text())
    assert report["inputs"]["edited_drape"]["path"].endswith("garment.obj")
    assert report["steps"][0]["op"] == "edited_drape"
    assert "baseline" in json.dumps(report)  # the uniform baseline, as for a recipe


def tee_obj_vt(path: Path) -> np.ndarray:
    return reader_for(path)(path).vt


def split(g):
    """``g`` with its drape unwelded: one drape vertex per pattern vertex (per-piece CAD
    exports come so), coincident along the seams."""
    to3 = np.empty(len(g.V2), dtype=np.int64)
    to3[g.F2.ravel()] = g.F3.ravel()
    return replace(g, V3=g.V3[to3], F3=g.F2.copy())


@pytest.mark.slow
def test_edited_drape_in_the_files_numbering_is_welded_as_the_garment(tmp_path, tee):
    g = split(tee)
    write_garment(tmp_path / "split.obj", g)
    write_garment(tmp_path / "edited.obj", replace(g, V3=1.1 * g.V3))  # 10 % larger
    recipe = tmp_path / "larger.yaml"
    recipe.write_text("units: cm\nsteps: [{op: scale, region: all, factor: 1.1}]\n")
    assert run("adjust", tmp_path / "split.obj", recipe, "-o", tmp_path / "a", "-q")[0] == 0
    code, err = run(
        "adjust", tmp_path / "split.obj", "--edited-drape", tmp_path / "edited.obj",
        "-o", tmp_path / "b", "-q",
    )  # fmt: skip
    assert code == 0, err
    report = json.loads((tmp_path / "b" / "report.json").read_text())
    assert report["intake"]["welded_vertices"] > 0  # (the weld did join the panels)
    (rec,) = report["steps"]
    assert rec["vertices"] == len(tee.V3) and len(rec["similar_panels"]) == 6
    diff = np.abs(pattern_mm(tmp_path / "b") - pattern_mm(tmp_path / "a")).max()
    assert diff < AGREE_MM


def test_mismatched_counts_exit_2_naming_both_files_and_counts(tmp_path, tee_obj, tee):
    other = tmp_path / "other.obj"
    g = bodice()
    write_garment(other, g)
    out = tmp_path / "out"
    code, err = run("adjust", tee_obj, "--edited-drape", other, "-o", out)
    assert code == 2
    assert len(err.strip().splitlines()) == 1
    for text in (str(other), str(tee_obj), f"{len(g.V3)} vertices", f"{len(g.F3)} faces"):
        assert text in err
    assert f"{len(tee.V3)} vertices and {len(tee.F3)} faces" in err
    assert not out.exists()


def test_other_faces_exit_2(tmp_path, tee_obj, tee):
    other = tmp_path / "other.obj"
    F = tee.F3.copy()
    F[[0, 1]] = F[[1, 0]]  # the same triangles in another order
    write_garment(other, replace(tee, F3=F, F2=tee.F2[[1, 0, *range(2, len(F))]]))
    code, err = run("adjust", tee_obj, "--edited-drape", other, "-o", tmp_path / "out")
    assert code == 2 and "face 1 joins other vertices" in err and str(tee_obj) in err
    assert not (tmp_path / "out").exists()


def test_a_recipe_with_steps_is_refused_before_reading(tmp_path, tee_obj):
    recipe = tmp_path / "around.yaml"
    recipe.write_text(AROUND)
    missing = tmp_path / "missing.obj"  # (not read: the recipe is refused first)
    code, err = run("adjust", tee_obj, recipe, "--edited-drape", missing, "-o", tmp_path / "o")
    assert code == 2 and "has 1 step" in err and "around.yaml" in err


def test_recipe_or_edited_drape_is_required(tmp_path, tee_obj):
    code, err = run("adjust", tee_obj, "-o", tmp_path / "o")
    assert code == 2 and "RECIPE" in err


def test_collapsing_edit_is_refused(tee):
    V = tee.V3.copy()
    V[tee.F3[0]] = V[tee.F3[0, 0]]  # one triangle's corners at one point
    with pytest.raises(PtailorError, match="collapses"):
        adjustment(tee, Recipe(), baseline=False, edited=V)


def test_similar_panels(tee):
    plist = structure(tee).panels
    c, theta = tee.V3.mean(0), 0.3
    R = np.array([[np.cos(theta), 0, np.sin(theta)], [0, 1, 0], [-np.sin(theta), 0, np.cos(theta)]])
    moved = (tee.V3 - c) @ R.T * 1.7 + [1.0, 2.0, 3.0]
    assert similar_panels(tee.V3, moved, tee.F3, plist).all()
    along = tee.V3 * [1.0, 1.05, 1.0]  # an affine map, no similarity
    assert not similar_panels(tee.V3, along, tee.F3, plist).any()


def test_manifest_edited_drape_column(tmp_path, tee_obj):
    (tmp_path / "e.obj").write_text("")
    m = tmp_path / "m.csv"
    m.write_text("garment,edited_drape\ntee.obj,e.obj\ntee.obj,nope.obj\n")
    with pytest.raises(PtailorError, match=r"row 3: edited_drape .*nope.obj: no such file"):
        read_manifest(m, check=lambda column, text: text)
    m.write_text("garment,edited_drape,name\ntee.obj,e.obj,a\n")
    (row,) = read_manifest(m, check=lambda column, text: text)
    assert row.options["edited_drape"] == str(tmp_path / "e.obj")
