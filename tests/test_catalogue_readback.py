"""What a batch and a catalogue read back (issue 43): every file type-checked in one reader
(``ptailor.batch.readback``), a bad file named in a warning (exit 2 for a ``--log``), never a
traceback; writes confined to OUT's own folders; the page never links a page that is not
there; the CLI's signals, closed pipes and stdin garments."""

from __future__ import annotations

import json
import os
import shutil
import signal
import struct
import subprocess
import sys
import zlib
from pathlib import Path

import pytest
from click.testing import CliRunner

from ptailor.batch.readback import (
    RECORD_FIELDS,
    REPORT_FIELDS,
    ReadBackError,
    checked,
    load_json,
    nesting_depth,
)
from ptailor.cli.main import cli
from ptailor.formats.obj import write_garment
from ptailor.run.folder import MARKER
from ptailor.samples import cone_skirt, cylinder
from tests.test_catalogue import assert_links_resolve

WIDER = "steps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.1}]\n"


def run(*args, input=None):
    return CliRunner().invoke(cli, [str(a) for a in args], input=input, catch_exceptions=False)


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> Path:
    """A batch --html output root of two garments (made once; tests copy it)."""
    root = tmp_path_factory.mktemp("built")
    (root / "g").mkdir()
    write_garment(root / "g" / "a_tube.obj", cylinder(circumference=40.0, n_around=12, n_along=4))
    write_garment(root / "g" / "b_skirt.obj", cone_skirt(n_around=12, n_along=4))
    (root / "wider.yaml").write_text(WIDER)
    res = run("batch", root / "wider.yaml", root / "g", "-o", root / "OUT", "--html", "-j", "1")
    assert res.exit_code == 0, res.output
    return root


@pytest.fixture
def site(built, tmp_path) -> Path:
    shutil.copytree(built, tmp_path / "s", symlinks=True)
    return tmp_path / "s"


def edit_json(path: Path, change) -> None:
    data = json.loads(path.read_text())
    change(data)
    path.write_text(json.dumps(data))


# --------------------------------------------------------------------------- the reader


def test_checked_drops_each_wrong_field_and_names_it():
    report = {
        "warnings": None,
        "panels": [{"flipped_triangles": "x", "area_before": 10**400, "name": "front"}, 3],
        "steps": "scale",
        "seams": [{"panels": 5, "mismatch": float("inf")}],
        "outputs": ["report.json"],
    }
    got, problems = checked(report, REPORT_FIELDS)
    assert got == {"panels": [{"name": "front"}], "seams": [{}], "outputs": ["report.json"]}
    assert "warnings is null, not a list" in problems
    assert "panels[0].flipped_triangles is a string 'x', not an integer" in problems
    assert "panels[0].area_before is a number out of range, not a number" in problems
    assert any(p.startswith("steps is a string") for p in problems)
    assert len(problems) == 7
    rec, problems = checked({"index": "2", "garment": "a.obj", "status": "ok"}, RECORD_FIELDS,
                            where="line 2:")  # fmt: skip
    assert rec == {"garment": "a.obj", "status": "ok"}
    assert problems == ["line 2: index is a string '2', not an integer"]
    assert checked([1], REPORT_FIELDS) == (None, ["the file is a list, not an object"])


def test_files_are_read_within_size_and_depth(tmp_path):
    assert nesting_depth('{"a": [[1], "[[[[["], "b": {}}') == 3
    deep = tmp_path / "deep.json"
    deep.write_text("[" * 100_000 + "]" * 100_000)
    with pytest.raises(ReadBackError, match="nested 100000 deep"):
        load_json(deep)
    digits = tmp_path / "digits.json"
    digits.write_text('{"a": ' + "9" * 5000 + "}")
    with pytest.raises(ReadBackError, match="not JSON"):
        load_json(digits)
    (tmp_path / "ok.json").write_text('{"a": [1, {"b": 2}]}')
    assert load_json(tmp_path / "ok.json") == {"a": [1, {"b": 2}]}


# --------------------------------------------------------------------------- tracebacks


@pytest.mark.slow
def test_an_earlier_folder_with_null_warnings_does_not_break_later_batches(site):
    """The issue's example: report.json with "warnings": null in one folder made every later
    batch into OUT exit 1 after the garments ran, its page without the garment written."""
    out = site / "OUT"
    edit_json(out / "b_skirt" / "report.json", lambda d: d.update(warnings=None, steps=3))
    (site / "g2").mkdir()
    write_garment(site / "g2" / "c_new.obj", cylinder(circumference=30.0, n_around=12, n_along=4))
    res = run("batch", site / "wider.yaml", site / "g2", "-o", out, "-j", "1")
    assert res.exit_code == 0, res.output
    assert "b_skirt/report.json: " in res.output and "warnings is null" in res.output
    page = assert_links_resolve(out / "index.html")
    assert "c_new/index.html" in page.refs and "b_skirt/index.html" in page.refs


@pytest.mark.slow
def test_report_on_wrong_typed_catalogue_and_reports_warns_and_writes(site):
    out = site / "OUT"

    def spoil(d):
        d["summary"]["seconds"] = "slow"
        d["records"][0]["failed_gates"] = 3
        d["records"][1]["index"] = [1]

    edit_json(out / "_catalogue" / "catalogue.json", spoil)
    spoilt = {"panels": {"x": 1}, "warnings": [None, 2], "steps": [1, {"op": 2}]}
    edit_json(out / "a_tube" / "report.json", lambda d: d.update(spoilt))
    res = run("report", out)
    assert res.exit_code == 0, res.output
    assert "catalogue.json: summary.seconds is a string 'slow', not a number" in res.output
    assert "records[0].failed_gates is a number" in res.output
    assert "a_tube/report.json: " in res.output
    assert "panels is an object, not a list" in res.output
    page = assert_links_resolve(out / "index.html")
    assert len(page.rows) == 2


@pytest.mark.slow
def test_a_deep_or_huge_catalogue_json_is_a_warning_not_a_recursion(site):
    out = site / "OUT"
    (out / "_catalogue" / "catalogue.json").write_text("[" * 200_000 + "]" * 200_000)
    res = run("report", out)
    assert res.exit_code == 0, res.output
    assert "catalogue.json: nested 200000 deep" in res.output
    assert len(assert_links_resolve(out / "index.html").rows) == 2  # from the folders


def test_a_log_mixing_string_and_number_index_is_exit_2(tmp_path):
    site = tmp_path
    (site / "OUT").mkdir()
    log = site / "batch.jsonl"
    lines = [
        {"index": 1, "garment": "a.obj", "status": "ok"},
        {"index": "2", "garment": "b.obj", "status": "ok"},
    ]
    log.write_text("".join(json.dumps(r) + "\n" for r in lines))
    res = run("report", site / "OUT", "--log", log)
    assert res.exit_code == 2
    assert "line 2: index is a string '2', not an integer" in res.output
    assert list((site / "OUT").iterdir()) == []


def _huge_png(path: Path, w: int, h: int) -> None:
    """A PNG whose header says w x h (its data is one row: Pillow refuses it before)."""

    def chunk(kind: bytes, data: bytes) -> bytes:
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    ihdr = struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)
    idat = zlib.compress(b"\0" + b"\0" * 3 * 8)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", idat)
                     + chunk(b"IEND", b""))  # fmt: skip


@pytest.mark.slow
def test_a_decompression_bomb_preview_gets_no_thumbnail(site):
    folder = site / "OUT" / "a_tube"
    (folder / "thumbnail.png").unlink()
    _huge_png(folder / "preview.png", 30000, 30000)
    res = run("report", site / "OUT")
    assert res.exit_code == 0, res.output
    assert "a_tube/preview.png: no thumbnail" in res.output
    assert "30000 x 30000" in res.output or "decompression" in res.output.lower()
    assert not (folder / "thumbnail.png").exists()
    assert_links_resolve(site / "OUT" / "index.html")


# --------------------------------------------------------------------------- outside writes


@pytest.mark.slow
def test_a_garment_folder_that_is_a_link_is_never_written_through(site, tmp_path):
    out = site / "OUT"
    outside = tmp_path / "outside"
    shutil.move(out / "b_skirt", outside)
    (out / "b_skirt").symlink_to(outside, target_is_directory=True)
    for name in ("index.html", "thumbnail.png"):
        (outside / name).unlink()
    marker = (outside / MARKER).read_bytes()
    res = run("report", out)
    assert res.exit_code == 0, res.output
    assert "b_skirt: a symbolic link" in res.output
    assert sorted(p.name for p in outside.iterdir() if p.name.endswith((".html", ".png"))) == [
        "preview.png"
    ]
    assert (outside / MARKER).read_bytes() == marker
    page = assert_links_resolve(out / "index.html")
    assert not any(r.startswith("b_skirt") for r in page.refs)


# --------------------------------------------------------------------------- crash consistency


@pytest.mark.slow
def test_a_killed_rerun_leaves_no_link_to_a_missing_page(site, monkeypatch):
    """A batch --html re-run killed after replacing folders (their pages not yet written):
    the page links none of them."""
    import ptailor.cli.batch as batch_cli

    out = site / "OUT"

    def killed(todo, **kwargs):
        for job in todo:  # each folder replaced as a garment's run commits it: no page yet
            folder = Path(job.out_abs)
            for name in ("index.html", "thumbnail.png"):
                (folder / name).unlink(missing_ok=True)
        raise SystemExit(137)

    monkeypatch.setattr(batch_cli, "_run", killed)
    args = ["batch", site / "wider.yaml", site / "g" / "a_tube.obj", "-o", out, "--force"]
    res = CliRunner().invoke(cli, [str(a) for a in args])
    assert res.exit_code == 137
    page = assert_links_resolve(out / "index.html")
    assert "b_skirt/index.html" in page.refs  # (not re-run: still linked)
    assert not any(r.startswith("a_tube/") for r in page.refs)
    assert {r["data-status"] for r in page.rows} == {"interrupted", "ok"}


@pytest.mark.slow
def test_a_stored_report_with_a_wrong_field_is_rerun_not_trusted(site):
    out = site / "OUT"
    edit_json(out / "a_tube" / "report.json", lambda d: d.update(warnings=None))
    res = run("batch", site / "wider.yaml", site / "g", "-o", out, "-j", "1", "--json")
    recs = {json.loads(ln)["garment"].rsplit("/", 1)[-1]: json.loads(ln)
            for ln in res.stdout.splitlines() if ln.startswith("{")}  # fmt: skip
    assert recs["a_tube.obj"]["status"] == "ok" and recs["b_skirt.obj"]["status"] == "skipped"
    assert json.loads((out / "a_tube" / "report.json").read_text())["warnings"] is not None


# --------------------------------------------------------------------------- the CLI


def test_a_garment_from_stdin_is_one_clear_line(tmp_path):
    (tmp_path / "r.yaml").write_text(WIDER)
    for cmd in (["adjust", "-", tmp_path / "r.yaml", "-o", tmp_path / "o"], ["inspect", "-"]):
        res = run(*cmd, input="v 0 0 0\n")
        assert res.exit_code == 2
        assert "a garment cannot be read from stdin ('-')" in res.output
        assert "'.' files" not in res.output
    assert not (tmp_path / "o").exists()


def test_a_signal_as_out_is_put_in_place_says_out_is_complete(tmp_path, monkeypatch):
    import ptailor.run.folder as folder_mod

    write_garment(tmp_path / "t.obj", cylinder(circumference=40.0, n_around=12, n_along=4))
    (tmp_path / "r.yaml").write_text(WIDER)
    out = tmp_path / "o"
    assert run("adjust", tmp_path / "t.obj", tmp_path / "r.yaml", "-o", out, "-q").exit_code == 0
    real_rmtree = shutil.rmtree

    def signalled(path, *a, **k):  # SIGINT while the old folder goes (OUT already in place)
        signal.raise_signal(signal.SIGINT)
        return real_rmtree(path, *a, **k)

    monkeypatch.setattr(folder_mod.shutil, "rmtree", signalled)
    res = CliRunner().invoke(cli, ["adjust", str(tmp_path / "t.obj"), str(tmp_path / "r.yaml"),
                                   "-o", str(out), "-q"])  # fmt: skip
    assert res.exit_code == 130
    assert f"after {out} was written: it is complete" in res.output
    assert "no partial output" not in res.output
    assert (out / "report.json").is_file()


@pytest.mark.slow
def test_a_closed_stdout_ends_quietly(built, tmp_path):
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parents[1] / "src"))
    cmd = [sys.executable, "-m", "ptailor", "batch", str(built / "wider.yaml"),
           str(built / "g"), "-o", str(tmp_path / "o"), "-j", "1", "--json", "--force"]  # fmt: skip
    p = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    p.stdout.close()  # as `| head` does once it has its lines
    err = p.stderr.read().decode()
    assert p.wait(timeout=120) == 141, err
    assert "Broken pipe" not in err and "error" not in err


@pytest.mark.slow
def test_names_no_file_system_takes_are_warnings_not_errors(site):
    """A report listing an output of 400 characters, a record whose folder name has 400:
    found by the campaign (``File name too long``, exit 2, the pages half written)."""
    out = site / "OUT"
    edit_json(out / "a_tube" / "report.json", lambda d: d["outputs"].append("9" * 400))
    edit_json(out / "_catalogue" / "catalogue.json",
              lambda d: d["records"][1].update(out="x" * 400, garment="\ud800.obj"))  # fmt: skip
    res = run("report", out)
    assert res.exit_code == 0, res.output
    assert "outputs[" in res.output and "not a plain file name" in res.output
    page = assert_links_resolve(out / "index.html")
    assert len(page.rows) == 3  # the renamed record, and b_skirt's folder as earlier


def test_a_manifest_naming_a_file_no_system_takes_is_exit_2(tmp_path):
    (tmp_path / "r.yaml").write_text(WIDER)
    m = tmp_path / "m.jsonl"
    m.write_text(json.dumps({"garment": "9" * 400 + ".obj"}) + "\n")
    res = run("batch", tmp_path / "r.yaml", "--manifest", m, "-o", tmp_path / "o")
    assert res.exit_code == 2
    assert str(m) in res.output and "not a file name (File name too long)" in res.output
    assert not (tmp_path / "o").exists()
