"""``ptailor batch --manifest``: per-garment units, axes, drapes and names (issue 24)."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from ptailor.formats.obj import write_garment
from ptailor.samples import cone_skirt, cylinder, lantern_sleeve
from tests.conftest import real_path
from tests.test_batch import FAST, WIDER, _outputs, records, run

IN_CM = 2.54


def folder(path: Path) -> dict:
    """A garment's output folder: every file's bytes, report.json without its timings."""
    prefix = path.name + "/"
    return {k[len(prefix) :]: v for k, v in _outputs(path.parent).items() if k.startswith(prefix)}


@pytest.fixture
def recipe(tmp_path) -> Path:
    (tmp_path / "wider.yaml").write_text(WIDER)
    return tmp_path / "wider.yaml"


@pytest.fixture
def cat(tmp_path) -> Path:
    """Small generated garments whose files are in different units.

    a.obj: cm; b_mm.obj: mm (pattern and drape); c_in.obj: pattern in inches, drape in cm;
    sub/d.obj: cm; e_mixed.obj: pattern in inches, drape in mm.
    """
    root = tmp_path / "cat"
    (root / "sub").mkdir(parents=True)
    sleeve = lantern_sleeve(n_around=12, n_sleeve=6, n_cuff=2)
    tube = cylinder(circumference=40.0, n_around=16, n_along=6)
    skirt = cone_skirt(n_around=16, n_along=6)
    write_garment(root / "a.obj", sleeve)
    write_garment(root / "b_mm.obj", tube.with_drape(tube.V3 * 10.0).with_pattern(tube.V2 * 10.0))
    write_garment(root / "c_in.obj", skirt.with_pattern(skirt.V2 / IN_CM))
    write_garment(root / "sub" / "d.obj", lantern_sleeve(circumference=32.0, n_around=10))
    mixed = sleeve.with_drape(sleeve.V3 * 10.0).with_pattern(sleeve.V2 / IN_CM)
    write_garment(root / "e_mixed.obj", mixed)
    return root


#: the manifest rows of the first test: (garment, its options as command-line arguments)
ROWS = [
    ("a.obj", {}),
    ("b_mm.obj", {"pattern_units": "mm", "drape_units": "mm"}),
    ("c_in.obj", {"pattern_units": "in"}),
    ("sub/d.obj", {"up": "-y", "front": "x", "name": "dee"}),
]


def write_csv(path: Path, rows: list[tuple[str, dict]], columns: list[str]) -> Path:
    lines = [",".join(["garment", *columns])]
    lines += [",".join([g, *(opts.get(c, "") for c in columns)]) for g, opts in rows]
    path.write_text("\n".join(lines) + "\n")
    return path


def write_jsonl(path: Path, rows: list[tuple[str, dict]]) -> Path:
    path.write_text("".join(json.dumps({"garment": g, **opts}) + "\n" for g, opts in rows))
    return path


def option_args(opts: dict) -> list[str]:
    return [a for k, v in opts.items() if k != "name" for a in (f"--{k.replace('_', '-')}", v)]


@pytest.mark.slow
def test_csv_and_json_lines_manifests_give_what_separate_runs_give(tmp_path, recipe, cat):
    columns = ["pattern_units", "drape_units", "up", "front", "name"]
    csv_manifest = write_csv(cat / "units.csv", ROWS, columns)
    out, log = tmp_path / "out", tmp_path / "log.jsonl"
    r = run("batch", recipe, "--manifest", csv_manifest, "-o", out, "--log", log, *FAST)
    assert r.exit_code == 0, r.output
    recs = records(log)
    assert [x["garment"] for x in recs] == [str(cat / g) for g, _ in ROWS]  # beside the manifest
    assert [Path(x["out"]).name for x in recs] == ["a", "b_mm", "c_in", "dee"]
    assert [x["status"] for x in recs] == ["ok"] * 4
    # each garment as a batch of its own with the row's options on the command line
    for (g, opts), rec in zip(ROWS, recs, strict=True):
        alone = tmp_path / f"alone-{Path(g).stem}"
        r = run("batch", recipe, cat / g, "-o", alone, *option_args(opts), *FAST)
        assert r.exit_code == 0, (g, r.output)
        assert folder(Path(rec["out"])) == folder(alone / Path(g).stem), g
    stamp = json.loads((out / "b_mm" / "batch.json").read_text())
    assert stamp["options"]["pattern_units"] == "mm" and stamp["options"]["drape_units"] == "mm"
    d = json.loads((out / "dee" / "batch.json").read_text())["options"]
    assert (d["up"], d["front"]) == ("-y", "x")
    # the units are the rows': the 40 x 20 cm tube (in mm), not 400 x 200
    b = json.loads((out / "b_mm" / "report.json").read_text())
    assert sum(p["area_before"] for p in b["panels"]) == pytest.approx(40.0 * 20.0, rel=1e-6)
    # the same rows as JSON Lines: the same folders, byte for byte, and the same stamps
    jsonl = write_jsonl(cat / "units.jsonl", ROWS)
    out2 = tmp_path / "out2"
    r = run("batch", recipe, "--manifest", jsonl, "-o", out2, *FAST)
    assert r.exit_code == 0, r.output
    assert {p.name: folder(p) for p in out2.iterdir()} == {p.name: folder(p) for p in out.iterdir()}
    r = run("batch", recipe, "--manifest", jsonl, "-o", out, "--log", log, *FAST)
    assert r.exit_code == 0 and [x["status"] for x in records(log)] == ["skipped"] * 4


@pytest.mark.slow
def test_a_missing_column_or_empty_cell_takes_the_command_line(tmp_path, recipe, cat):
    # no unit column at all: the command line's units for every row
    only = write_csv(cat / "only.csv", [("b_mm.obj", {})], [])
    out = tmp_path / "out"
    mm = ("--pattern-units", "mm", "--drape-units", "mm")
    r = run("batch", recipe, "--manifest", only, "-o", out, *mm, *FAST)
    assert r.exit_code == 0, r.output
    r = run("batch", recipe, cat / "b_mm.obj", "-o", tmp_path / "alone", *mm, *FAST)
    assert r.exit_code == 0, r.output
    assert folder(out / "b_mm") == folder(tmp_path / "alone" / "b_mm")
    # a column with an empty cell: that row takes the command line's value
    rows = [("b_mm.obj", {}), ("e_mixed.obj", {"pattern_units": "in"})]
    some = write_csv(cat / "some.csv", rows, ["pattern_units"])
    out2 = tmp_path / "out2"
    r = run("batch", recipe, "--manifest", some, "-o", out2, *mm, *FAST)
    assert r.exit_code == 0, r.output
    assert folder(out2 / "b_mm") == folder(out / "b_mm")
    e = json.loads((out2 / "e_mixed" / "batch.json").read_text())["options"]
    assert (e["pattern_units"], e["drape_units"]) == ("in", "mm")
    units = ("--pattern-units", "in", "--drape-units", "mm")
    r = run("batch", recipe, cat / "e_mixed.obj", "-o", tmp_path / "e", *units, *FAST)
    assert r.exit_code == 0, r.output
    assert folder(out2 / "e_mixed") == folder(tmp_path / "e" / "e_mixed")


def _mtimes(out: Path) -> dict[str, int]:
    return {p.name: (p / "report.json").stat().st_mtime_ns for p in out.iterdir()}


@pytest.mark.slow
def test_rerun_skips_every_row_and_a_changed_unit_redoes_that_garment_only(tmp_path, recipe, cat):
    rows = ROWS[:3]
    columns = ["pattern_units", "drape_units"]
    manifest = write_csv(cat / "units.csv", rows, columns)
    out, log = tmp_path / "out", tmp_path / "log.jsonl"
    args = ("batch", recipe, "--manifest", manifest, "-o", out, "--log", log, *FAST)
    assert run(*args).exit_code == 0
    first = _mtimes(out)
    r = run(*args)
    assert r.exit_code == 0
    assert [x["status"] for x in records(log)] == ["skipped"] * 3
    assert _mtimes(out) == first
    # the summary's last line counts; no rate when nothing ran
    last = r.stderr.splitlines()[-1]
    assert "0 done, 3 skipped, 0 failed" in last and "garments/min" not in last, r.stderr
    # b's unit written another way (the same scale): b is redone, the others are not
    changed = [rows[0], ("b_mm.obj", {"pattern_units": "0.1cm", "drape_units": "mm"}), rows[2]]
    write_csv(manifest, changed, columns)
    r = run(*args)
    assert r.exit_code == 0
    assert [x["status"] for x in records(log)] == ["skipped", "ok", "skipped"]
    second = _mtimes(out)
    assert second["b_mm"] != first["b_mm"]
    assert {k: v for k, v in second.items() if k != "b_mm"} == {
        k: v for k, v in first.items() if k != "b_mm"
    }
    stamp = json.loads((out / "b_mm" / "batch.json").read_text())
    assert stamp["options"]["pattern_units"] == "0.1cm"
    assert "1 done, 2 skipped, 0 failed" in r.stderr and "over the 1 run" in r.stderr


@pytest.mark.slow
def test_a_dxf_row_with_its_own_drape_size_and_unit(tmp_path):
    from tests.test_pattern_io import _setup

    cat = tmp_path / "cat"
    cat.mkdir()
    obj, dxf, _ = _setup(cat)  # cat/lantern_sleeve.dxf (mm) + its drape beside it
    elsewhere = cat / "meshes"
    elsewhere.mkdir()
    drape = elsewhere / "sleeve_drape.obj"
    shutil.copy(obj, drape)
    recipe = tmp_path / "r.yaml"
    recipe.write_text("steps: [{op: scale, region: all, direction: uniform, factor: 1.1}]\n")
    # the batch of the pair as exported (X.dxf + X.obj) with the options on the command line
    opts = ("--dxf-units", "mm", "--size", "M", "--formats", "obj", "--no-baseline")
    r = run("batch", recipe, dxf, "-o", tmp_path / "pair", *opts)
    assert r.exit_code == 0, r.output
    obj.unlink()  # now the drape is only where the manifest says
    manifest = cat / "m.csv"
    manifest.write_text(
        "garment,drape,dxf_units,size\nlantern_sleeve.dxf,meshes/sleeve_drape.obj,mm,M\n"
    )
    out = tmp_path / "out"
    r = run("batch", recipe, "--manifest", manifest, "-o", out, "--json", *opts[4:])
    assert r.exit_code == 0, r.output
    (rec,) = map(json.loads, r.stdout.splitlines())
    assert rec["status"] == "ok"
    rep = json.loads((out / "lantern_sleeve" / "report.json").read_text())
    assert rep["inputs"]["drape"]["path"] == str(drape)
    pair = tmp_path / "pair" / "lantern_sleeve"
    assert (out / "lantern_sleeve" / "garment.obj").read_bytes() == (
        pair / "garment.obj"
    ).read_bytes()
    stamp = json.loads((out / "lantern_sleeve" / "batch.json").read_text())
    assert stamp["key"] == json.loads((pair / "batch.json").read_text())["key"]


BAD_CSV = {
    # name: (manifest text, the row named, a part of the message)
    "unknown column": ("garment,colour\na.obj,red\n", 1, "unknown column 'colour'"),
    "no garment column": ("pattern_units\nmm\n", 1, "no garment column"),
    "empty garment": ("garment,pattern_units\na.obj,\n,mm\n", 3, "no garment"),
    "bad unit": ("garment,pattern_units\na.obj,\nb_mm.obj,furlong\n", 3, "unknown unit 'furlong'"),
    "absurd unit": ("garment,drape_units\na.obj,1e9km\n", 2, "drape_units"),
    "bad axis": ("garment,up\na.obj,q\n", 2, "up:"),
    "bad dxf unit": ("garment,dxf_units\na.obj,yd\n", 2, "dxf_units:"),
    "missing garment": ("garment\na.obj\n\nnope.obj\n", 4, "nope.obj: no such file"),
    "missing drape": ("garment,drape\na.obj,nope.obj\n", 2, "drape"),
    "dxf without drape": ("garment\nlone.dxf\n", 2, "lone.obj"),
    "duplicate name": ("garment,name\na.obj,x\nb_mm.obj,\nc_in.obj,x\n", 4, "'x' is row 2's"),
    "a path as name": ("garment,name\na.obj,../x\n", 2, "not a plain folder name"),
    "too many cells": ("garment\na.obj,mm\n", 2, "2 cells"),
    "repeated column": ("garment,up,up\na.obj,y,y\n", 1, "'up' given twice"),
}
BAD_JSONL = {
    "not an object": ('{"garment": "a.obj"}\n[1, 2]\n', 2, "not a JSON object"),
    "not JSON": ('{"garment": "a.obj"}\n{garment: a.obj}\n', 2, "not a JSON object"),
    "a list value": ('{"garment": "a.obj", "up": ["y"]}\n', 1, "up: must be a string"),
    "repeated key": ('{"garment": "a.obj", "garment": "b_mm.obj"}\n', 1, "given twice"),
    "unknown key": ('{"garment": "a.obj"}\n{"garment": "a.obj", "unit": "mm"}\n', 2, "'unit'"),
    "bad unit": ('{"garment": "a.obj", "pattern_units": "furlong"}\n', 1, "furlong"),
}


@pytest.mark.parametrize(
    "kind, case", [("csv", k) for k in BAD_CSV] + [("jsonl", k) for k in BAD_JSONL]
)
def test_a_bad_manifest_is_exit_2_naming_file_and_row_and_writes_nothing(
    tmp_path, recipe, cat, kind, case
):
    text, row, problem = (BAD_CSV if kind == "csv" else BAD_JSONL)[case]
    (cat / "lone.dxf").write_text("0\nEOF\n")
    manifest = cat / f"m.{kind}"
    manifest.write_text(text)
    out, log = tmp_path / "out", tmp_path / "log.jsonl"
    r = run("batch", recipe, "--manifest", manifest, "-o", out, "--log", log, *FAST)
    assert r.exit_code == 2, r.output
    assert r.stderr.startswith(f"ptailor: error: {manifest}: "), r.stderr
    assert f"row {row}: " in r.stderr and problem in r.stderr, r.stderr
    assert len(r.stderr.splitlines()) == 1
    assert not out.exists() and not log.exists()


def test_every_problem_of_a_manifest_at_once(tmp_path, recipe, cat):
    manifest = cat / "m.csv"
    manifest.write_text("garment,up\nnope.obj,y\na.obj,sideways\n")
    r = run("batch", recipe, "--manifest", manifest, "-o", tmp_path / "out")
    assert r.exit_code == 2
    assert "2 problems: row 2: garment" in r.stderr and "; row 3: up:" in r.stderr


def test_manifest_or_garments_not_both_nor_neither(tmp_path, recipe, cat):
    manifest = write_csv(cat / "m.csv", ROWS[:1], [])
    out = tmp_path / "out"
    r = run("batch", recipe, cat / "a.obj", "--manifest", manifest, "-o", out)
    assert r.exit_code == 2 and "not both" in r.stderr
    r = run("batch", recipe, "-o", out)
    assert r.exit_code == 2 and "--manifest" in r.stderr
    r = run("batch", recipe, "--manifest", tmp_path / "nope.csv", "-o", out)
    assert r.exit_code == 2 and "nope.csv: no such file" in r.stderr
    empty = cat / "empty.csv"
    empty.write_text("garment,pattern_units\n\n")
    r = run("batch", recipe, "--manifest", empty, "-o", out)
    assert r.exit_code == 2 and "empty.csv: no garments" in r.stderr
    # the log is never the manifest
    r = run("batch", recipe, "--manifest", manifest, "-o", out, "--log", manifest)
    assert r.exit_code == 2 and "input of this run" in r.stderr
    assert not out.exists()


@pytest.mark.slow
def test_real_garments_with_their_own_units_in_one_manifest(tmp_path, recipe):
    """gpg's tee6 is in 1/300 m in both its pattern and its drape; diffavatar's tshirt has
    a [0, 1] atlas and a drape in cm: one manifest runs both."""
    tee6, tshirt = real_path("tee6"), real_path("tshirt")
    manifest = tmp_path / "real.jsonl"
    rows = [
        {"garment": str(tee6), "pattern_units": "0.3333cm", "drape_units": "0.3333cm"},
        {"garment": str(tshirt), "pattern_units": "auto", "drape_units": "cm"},
    ]
    manifest.write_text("".join(json.dumps(r) + "\n" for r in rows))
    out, log = tmp_path / "out", tmp_path / "log.jsonl"
    args = ("batch", recipe, "--manifest", manifest, "-o", out, "--log", log, "-j", "1", *FAST)
    r = run(*args)
    assert r.exit_code == 0, r.output
    assert [x["status"] for x in records(log)] == ["ok", "ok"]
    for name, units in (("tee6_sim", ("0.3333cm", "0.3333cm")), ("tshirt", ("auto", "cm"))):
        stamp = json.loads((out / name / "batch.json").read_text())["options"]
        assert (stamp["pattern_units"], stamp["drape_units"]) == units
        rep = json.loads((out / name / "report.json").read_text())
        assert rep["panels"] and all(p["area_after"] > p["area_before"] for p in rep["panels"])
    r = run(*args)
    assert r.exit_code == 0 and [x["status"] for x in records(log)] == ["skipped", "skipped"]
