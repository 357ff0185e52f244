"""``ptailor batch``: catalogues, isolation, records, skip-unchanged, gates, SIGINT, Dask."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from ptailor import batch as pb
from ptailor.cli.main import cli
from ptailor.formats.obj import write_garment
from ptailor.samples import cone_skirt, cylinder, lantern_sleeve, sample_for_triangles
from ptailor.samples.obj_text import sample_obj_text

WIDER = "steps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.2}]\n"
FAST = ("--formats", "obj", "--no-baseline")
ALL_OUTPUTS = {".ptailor", "batch.json", "garment.obj", "pattern.dxf", "pattern.svg", "preview.png"}


def run(*args, input=None):
    return CliRunner().invoke(cli, [str(a) for a in args], input=input, catch_exceptions=False)


def records(path: Path) -> list[dict]:
    return [json.loads(ln) for ln in path.read_text().splitlines()]


def visible(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


@pytest.fixture
def recipe(tmp_path) -> Path:
    p = tmp_path / "wider.yaml"
    p.write_text(WIDER)
    return p


@pytest.fixture
def catalogue(tmp_path) -> Path:
    """Four small generated garments of three kinds and one broken file."""
    cat = tmp_path / "cat"
    cat.mkdir()
    write_garment(cat / "a_sleeve.obj", lantern_sleeve(n_around=12, n_sleeve=6, n_cuff=2))
    write_garment(cat / "b_tube.obj", cylinder(circumference=40.0, n_around=16, n_along=6))
    (cat / "c_bad.obj").write_text("this is not a garment\n")
    write_garment(cat / "d_skirt.obj", cone_skirt(n_around=16, n_along=6))
    write_garment(cat / "e_sleeve.obj", lantern_sleeve(circumference=32.0, n_around=10))
    return cat


@pytest.mark.slow
def test_batch_isolates_a_broken_garment_and_records_in_input_order(tmp_path, recipe, catalogue):
    out, log = tmp_path / "out", tmp_path / "log.jsonl"
    r = run("batch", recipe, catalogue / "*.obj", "-o", out, "-j", "1", "--log", log)
    assert r.exit_code == 1, r.output
    assert visible(out) == ["a_sleeve", "b_tube", "d_skirt", "e_sleeve"]
    for name in ("a_sleeve", "d_skirt"):
        assert set(visible(out / name)) == ALL_OUTPUTS | {"report.json"}
    recs = records(log)
    assert [Path(x["garment"]).name for x in recs] == sorted(p.name for p in catalogue.iterdir())
    assert [x["status"] for x in recs] == ["ok", "ok", "failed", "ok", "ok"]
    bad = recs[2]
    assert bad["failure"] == "input" and "not an OBJ" in bad["reason"]
    assert bad["out"] == str(out / "c_bad") and bad["panels"] is None
    assert list(recs[0]) == list(pb.RECORD_KEYS)
    sleeve = recs[0]
    assert sleeve["panels"] == 2 and sleeve["max_area_change"] == pytest.approx(0.2, abs=1e-4)
    assert sleeve["flipped_triangles"] == 0 and sleeve["max_intrinsic_error_p95"] < 1e-6
    assert sleeve["max_boundary_deviation"] > 0 and sleeve["seconds"] > 0
    rep = json.loads((out / "a_sleeve" / "report.json").read_text())
    assert rep["inputs"]["garment"]["path"] == sleeve["garment"]
    # the summary names the failed garment and its reason
    assert "c_bad.obj" in r.stderr and "not an OBJ" in r.stderr and "garments/min" in r.stderr


def test_an_internal_error_is_one_garments_failure(tmp_path, recipe, catalogue, monkeypatch):
    import ptailor.run.garment

    real = ptailor.run.garment.staged_run

    def flaky(path, *args, **kw):
        if "b_tube" in path:
            raise ZeroDivisionError("boom")
        return real(path, *args, **kw)

    monkeypatch.setattr(ptailor.run.garment, "staged_run", flaky)
    out = tmp_path / "out"
    r = run("batch", recipe, catalogue / "[ab]_*.obj", "-o", out, "-j", "1", "--json", *FAST)
    assert r.exit_code == 1
    recs = [json.loads(ln) for ln in r.stdout.splitlines()]
    assert [x["status"] for x in recs] == ["ok", "failed"]
    assert recs[1]["failure"] == "internal"
    assert recs[1]["reason"].startswith("internal error: ZeroDivisionError: boom (a bug in")
    assert visible(out) == ["a_sleeve"]


@pytest.mark.slow
@pytest.mark.skipif(
    __import__("multiprocessing").get_start_method() != "fork",
    reason="the patched staged_run reaches the workers only when they are forked",
)
def test_a_garment_that_kills_its_worker_fails_alone(tmp_path, catalogue, monkeypatch):
    import ptailor.run.garment
    from ptailor.recipe import parse_recipe
    from ptailor.run import RunOptions

    (catalogue / "c_bad.obj").unlink()
    real = ptailor.run.garment.staged_run

    def deadly(path, *args, **kw):  # a crash in a native library, the OOM killer
        if "b_tube" in path:
            os.kill(os.getpid(), signal.SIGKILL)
        return real(path, *args, **kw)

    monkeypatch.setattr(ptailor.run.garment, "staged_run", deadly)
    out = tmp_path / "out"
    paths = sorted(str(p) for p in catalogue.glob("*.obj"))
    opts = RunOptions(formats=("obj",), baseline=False)
    jobs = pb.make_jobs(paths, out, parse_recipe(WIDER), options=opts)
    res = pb.run_batch(jobs, workers=2)
    assert [r["status"] for r in res.records] == ["ok", "failed", "ok", "ok"]
    assert "worker process died" in res.records[1]["reason"]
    assert res.exit_status == 1
    assert visible(out) == ["a_sleeve", "d_skirt", "e_sleeve"]


@pytest.mark.slow
def test_globs_folders_stdin_and_shared_stems(tmp_path, recipe):
    cat = tmp_path / "cat"
    (cat / "x" / "deep").mkdir(parents=True)
    (cat / "y").mkdir()
    text = sample_obj_text("cylinder")
    for rel in ("x/deep/tube.obj", "y/tube.obj", "tube.obj", "tube-2.obj", "y/other.obj"):
        (cat / rel).write_text(text)
    out = tmp_path / "out"
    # recursive glob, expanded sorted; the literal path given again is taken once
    r = run("batch", recipe, cat / "**" / "tube*.obj", cat / "tube.obj", "-o", out, "--json", *FAST)
    assert r.exit_code == 0, r.output
    recs = [json.loads(ln) for ln in r.stdout.splitlines()]
    expect = sorted(str(p) for p in cat.glob("**/tube*.obj"))
    assert [x["garment"] for x in recs] == expect
    # cat/tube-2.obj keeps its own name; the other 'tube's get tube-3, tube-4 in input order
    names = [Path(x["out"]).name for x in recs]
    assert names == ["tube-2", "tube", "tube-3", "tube-4"]
    assert [x["note"] is not None for x in recs] == [False, False, True, True]
    assert "shared with" in recs[2]["note"]
    assert visible(out) == sorted(names)
    # paths on stdin, blank lines ignored, in the order given
    out2 = tmp_path / "out2"
    listing = f"\n{cat / 'y' / 'other.obj'}\n\n{cat / 'tube.obj'}\n"
    r = run("batch", recipe, "-", "-o", out2, "--json", *FAST, input=listing)
    assert r.exit_code == 0, r.output
    assert [json.loads(ln)["out"] for ln in r.stdout.splitlines()] == [
        str(out2 / "other"),
        str(out2 / "tube"),
    ]
    # a folder means every *.obj below it; outputs under -o inside it are not garments
    out3 = cat / "out3"
    r = run("batch", recipe, cat, "-o", out3, "--json", *FAST)
    assert r.exit_code == 0, r.output
    assert len(r.stdout.splitlines()) == 5
    r = run("batch", recipe, cat, cat / "zz*.obj", "-o", out3, "--json", *FAST)
    assert [json.loads(ln)["status"] for ln in r.stdout.splitlines()] == ["skipped"] * 5
    assert "zz*.obj: no garments found" in r.stderr  # a glob that finds nothing is a warning


def test_bad_recipe_or_arguments_exit_2_and_write_nothing(tmp_path, recipe, catalogue):
    out = tmp_path / "out"
    bad = tmp_path / "bad.yaml"
    bad.write_text("steps: [{op: scale, factor: -1}, {op: nope}]\n")
    r = run("batch", bad, catalogue / "*.obj", "-o", out)
    assert r.exit_code == 2
    assert "steps[1].factor" in r.stderr and "steps[2].op" in r.stderr
    cases = [
        [catalogue / "nothing*.obj"],  # no garments matched
        [catalogue / "a_sleeve.obj", "-j", "0"],
        [catalogue / "a_sleeve.obj", "--formats", "obj,stl"],
        [catalogue / "a_sleeve.obj", "--formats", "pdf", "--paper", "B5"],
        [catalogue / "a_sleeve.obj", "--pattern-units", "furlong"],
        [catalogue / "a_sleeve.obj", "--seam-allowance", "-1cm"],
    ]
    for extra in cases:
        r = run("batch", recipe, *extra, "-o", out)
        assert r.exit_code == 2, (extra, r.output)
    r = run("batch", recipe, "-", "-o", out, input="\n\n")
    assert r.exit_code == 2 and "no garments" in r.stderr
    r = run("batch", "-", "-", "-o", out, input=WIDER)
    assert r.exit_code == 2
    assert not out.exists()


def _state(out: Path) -> dict:
    return {
        p.name: ((p / "report.json").stat().st_ino, (p / "report.json").stat().st_mtime_ns)
        for p in out.iterdir()
    }


@pytest.mark.slow
def test_rerun_skips_unchanged_and_redoes_changed(tmp_path, recipe, catalogue):
    (catalogue / "c_bad.obj").unlink()
    out, log = tmp_path / "out", tmp_path / "log.jsonl"
    args = ("batch", recipe, catalogue / "*.obj", "-o", out, "--log", log, *FAST)
    assert run(*args).exit_code == 0
    stamp = json.loads((out / "a_sleeve" / "batch.json").read_text())
    assert set(stamp) == {"key", "ptailor_version", "garment", "recipe", "options"}
    assert stamp["options"]["formats"] == ["obj"] and stamp["options"]["baseline"] is False
    first = _state(out)
    r = run(*args)
    assert r.exit_code == 0
    assert [x["status"] for x in records(log)] == ["skipped"] * 4
    assert records(log)[0]["max_area_change"] == pytest.approx(0.2, abs=1e-4)  # from the report
    assert _state(out) == first
    # the same recipe written differently (comments, defaults spelled out) is unchanged
    recipe.write_text(
        "# wider\nunits: cm\nsteps:\n"
        "  - {op: scale, factor: 1.2, region: all, axis: auto, direction: around}\n"
    )
    assert run(*args).exit_code == 0 and _state(out) == first
    # a changed garment is redone, the others are not
    p = catalogue / "b_tube.obj"
    p.write_text(p.read_text() + "# touched\n")
    assert run(*args).exit_code == 0
    assert [x["status"] for x in records(log)] == ["skipped", "ok", "skipped", "skipped"]
    second = _state(out)
    assert second["b_tube"] != first["b_tube"]
    assert {k: v for k, v in second.items() if k != "b_tube"} == {
        k: v for k, v in first.items() if k != "b_tube"
    }
    # a changed recipe redoes everything; so do --force and other options
    recipe.write_text(WIDER.replace("1.2", "1.25"))
    assert run(*args).exit_code == 0
    assert [x["status"] for x in records(log)] == ["ok"] * 4
    third = _state(out)
    assert all(third[k] != second[k] for k in third)
    assert run(*args, "--force").exit_code == 0
    assert [x["status"] for x in records(log)] == ["ok"] * 4
    assert run(*args, "--up", "y").exit_code == 0
    assert [x["status"] for x in records(log)] == ["ok"] * 4
    assert run(*args, "--up", "y").exit_code == 0
    assert [x["status"] for x in records(log)] == ["skipped"] * 4


@pytest.mark.slow
def test_quality_gates(tmp_path, recipe, catalogue):
    (catalogue / "c_bad.obj").unlink()
    out, log = tmp_path / "out", tmp_path / "log.jsonl"
    base = ("batch", recipe, catalogue / "[ab]_*.obj", "-o", out, "--log", log, *FAST)
    r = run(*base, "--max-area-change", "0.01")
    assert r.exit_code == 1
    recs = records(log)
    assert [x["status"] for x in recs] == ["failed", "failed"]
    assert all(x["failure"] == "gate" for x in recs)
    assert "cuff: area change 20 % > 1 %" in recs[0]["reason"]
    assert recs[0]["max_area_change"] == pytest.approx(0.2, abs=1e-4)
    assert "by quality gates" in r.stderr and "area change" in r.stderr
    assert not out.exists() or visible(out) == []  # no folder, no staging folder
    r = run(
        *base,
        "--max-area-change",
        "0.25",
        "--max-boundary-deviation",
        "100",
        "--max-intrinsic-error",
        "0.01",
        "--fail-on-flips",
    )
    assert r.exit_code == 0, r.output
    assert visible(out) == ["a_sleeve", "b_tube"]
    # gates are checked on unchanged folders too (the folder is kept)
    r = run(*base, "--max-boundary-deviation", "0.5")
    assert r.exit_code == 1
    assert all("boundary deviation" in x["reason"] for x in records(log))
    assert visible(out) == ["a_sleeve", "b_tube"]


def test_the_stamp_hashes_every_run_option(tmp_path):
    """The stamp is made from RunOptions' fields: any option that changes outputs changes it."""
    from dataclasses import fields, replace

    from ptailor.recipe import parse_recipe
    from ptailor.run import RunOptions

    g = tmp_path / "g.obj"
    g.write_text("v 0 0 0\n")
    spec = tmp_path / "g_specification.json"
    spec.write_text("{}")
    base = RunOptions()
    changed = {
        "pattern_units": "mm",
        "drape_units": "mm",
        "weld": "off",
        "method": "uniform",
        "intrinsic": "paper",
        "baseline": False,
        "formats": ("obj",),
        "up": "z",
        "front": "y",
        "body": "body.obj",
        "body_units": "mm",
        "write_body": True,
        "size": "M",
        "dxf_units": "mm",
        "seam_allowance": 1.0,
        "seam_allowances": (("hem", 3.0),),
        "verify": True,
        "verify_rest": "pattern",
        "verify_max_steps": 10,
        "verify_null_mean": 2.0,
        "verify_null_p95": 4.0,
        "spec": str(spec),
        "show_measures": True,
        "spec_units": "cm",
        "sizes": "all",
        "paper": "Letter",
        "edited_drape": str(g),
    }
    assert set(changed) == {f.name for f in fields(RunOptions)}

    def key(options):
        (job,) = pb.make_jobs([str(g)], tmp_path / "out", parse_recipe(WIDER), options=options)
        return pb.job_stamp(job)["key"]

    keys = {key(base)} | {key(replace(base, **{k: v})) for k, v in changed.items()}
    assert len(keys) == 1 + len(changed)
    stamp = pb.job_stamp(pb.make_jobs([str(g)], tmp_path / "o", parse_recipe(WIDER))[0])
    # an option added later is left out at its default: earlier runs' stamps stay valid
    assert list(stamp["options"]) == sorted(
        set(changed)
        - {"spec_units", "sizes", "paper", "edited_drape", "seam_allowances"}
        - {"verify_null_mean", "verify_null_p95"}
    )
    assert stamp["options"]["formats"] == sorted(base.formats)


def test_one_executor_interface_picks_where_jobs_run(tmp_path):
    from ptailor.batch.executors import DaskCluster, InProcess, ProcessPool
    from ptailor.recipe import parse_recipe

    paths = [str(tmp_path / f"{k}.obj") for k in "abc"]
    jobs = pb.make_jobs(paths, tmp_path / "out", parse_recipe(WIDER))
    timed = pb.make_jobs(paths[:1], tmp_path / "out", parse_recipe(WIDER), timeout=5.0)
    assert isinstance(pb.executor_for(jobs, workers=1), InProcess)
    assert isinstance(pb.executor_for(jobs[:1], workers=4), InProcess)
    pool = pb.executor_for(jobs, workers=8)
    assert isinstance(pool, ProcessPool) and pool.n == 3 and pool.where == "3 worker processes"
    assert isinstance(pb.executor_for(timed, workers=1), ProcessPool)  # only a worker can stop
    dask = pb.executor_for(jobs, scheduler="tcp://h:8786")
    assert isinstance(dask, DaskCluster) and dask.where == "Dask scheduler tcp://h:8786"
    for ex in (InProcess(), pool, dask):
        assert isinstance(ex, pb.Executor)


def test_gates_read_the_report_strictly():
    """A renamed or missing field fails the gates that read it, never passes them silently."""
    panel = {"name": "p", "area_before": 1.0, "area_after": 1.0, "flipped_triangles": 0}
    report = {"units": "cm", "panels": [panel], "seams": []}
    gates = pb.Gates(max_area_change=0.5, max_boundary_deviation=1.0, fail_on_flips=True)
    assert pb.gate_failures(report, gates) == [
        "report: no panel has boundary_deviation (a gate cannot pass without it)"
    ]
    renamed = {**report, "panels": [{**panel, "flips": 0}]}
    del renamed["panels"][0]["flipped_triangles"]
    assert pb.gate_failures(renamed, pb.Gates(fail_on_flips=True)) == [
        "report: no panel has flipped_triangles (a gate cannot pass without it)"
    ]
    assert pb.gate_failures({"units": "cm", "seams": []}, pb.Gates(max_area_change=0.5)) == [
        "report: no panels list (a gate cannot pass without it)"
    ]
    assert pb.gate_failures({"panels": []}, pb.Gates(max_seam_mismatch=0.1)) == [
        "report: no seams list (a gate cannot pass without it)"
    ]
    assert pb.gate_failures({}, pb.Gates()) == []  # no gate set: nothing read


def test_gate_failures_reads_the_report_fields():
    report = {
        "units": "cm",
        "panels": [
            {
                "name": "p",
                "area_before": 100.0,
                "area_after": 103.0,
                "boundary_deviation": 0.2,
                "intrinsic_scale_error": {"mean": 0.01, "p95": 0.02, "max": 0.5},
                "flipped_triangles": 2,
            },
            {"name": "q", "area_before": 10.0, "area_after": 10.0, "flipped_triangles": 0},
        ],
        "seams": [
            {"panels": ["p", "q"], "mismatch": -0.25},
            {"panels": ["q", "q"], "mismatch": 0.001},
        ],
    }
    assert pb.gate_failures(report, pb.Gates()) == []
    gates = pb.Gates(
        max_area_change=0.02,
        max_boundary_deviation=0.1,
        max_intrinsic_error=0.01,
        max_seam_mismatch=0.1,
        fail_on_flips=True,
    )
    assert pb.gate_failures(report, gates) == [
        "p: area change 3 % > 2 %",
        "p: boundary deviation 0.2 > 0.1 cm",
        "p: intrinsic-scale error p95 0.02 > 0.01",
        "p: 2 flipped triangles",
        "seam p / q: mismatch 0.25 > 0.1 cm",
    ]
    loose = pb.Gates(
        max_area_change=0.05,
        max_boundary_deviation=0.3,
        max_intrinsic_error=0.1,
        max_seam_mismatch=0.3,
    )
    assert pb.gate_failures(report, loose) == []
    # a report without the field fails the gate instead of passing it silently
    old = {**report, "seams": [{"panels": ["p", "q"], "length_after": [1.0, 1.0]}]}
    assert pb.gate_failures(old, loose) == ["seam p / q: mismatch missing"]
    assert pb.key_numbers(report) == {
        "panels": 2,
        "max_area_change": 0.03,
        "max_boundary_deviation": 0.2,
        "max_intrinsic_error_p95": 0.02,
        "max_seam_mismatch": 0.25,
        "flipped_triangles": 2,
        "verify_stretch_p95": None,
        "verify_displacement_p95": None,
        "spec_fit_max": None,
        "warnings": 0,
    }


def test_output_names_and_staging_clean_up(tmp_path):
    names = pb.output_names(["a/x.obj", "b/x.obj", "x-2.obj", "c/x.obj", "y.obj"])
    assert [n for n, _ in names] == ["x", "x-3", "x-2", "x-4", "y"]
    assert names[1][1] == "stem 'x' is shared with a/x.obj: folder x-3" and names[0][1] is None
    out = tmp_path / "g"
    (tmp_path / ".g.abcd_123.tmp").mkdir()  # being written when killed
    (tmp_path / ".g.old-.g.zzzzzzzz.tmp").mkdir()  # the previous output, moved aside
    (tmp_path / ".g.old-.g.zzzzzzzz.tmp" / "report.json").write_text("{}")
    (tmp_path / ".gg.abcdefgh.tmp").mkdir()  # another garment's: untouched
    assert len(pb.remove_staging(out)) == 2
    assert visible(tmp_path) == [".gg.abcdefgh.tmp", "g"]
    assert (out / "report.json").is_file()


def test_given_names_are_kept_and_stems_avoid_them():
    names = pb.output_names(["a/x.obj", "b/y.obj", "c/x.obj"], ["y", None, None])
    assert [n for n, _ in names] == ["y", "y-2", "x"]
    assert names[1][1] == "stem 'y' is another garment's given name: folder y-2"
    assert names[0][1] is None and names[2][1] is None


def _summary_of(statuses: list[str], ran: int | None, seconds: float = 30.0) -> str:
    blank = dict.fromkeys(pb.RECORD_KEYS)
    recs = [{**blank, "garment": f"g{k}.obj", "status": s} for k, s in enumerate(statuses)]
    result = pb.BatchResult(records=recs, seconds=seconds, where="in-process", ran=ran)
    return next(ln for ln in pb.summary_lines(result) if ln.startswith("time"))


def test_the_summary_rates_only_the_garments_run():
    """Issue 24: a rerun where every garment was unchanged printed '48466 garments/min'."""
    line = _summary_of(["skipped"] * 4, ran=0, seconds=0.005)
    assert "0 done, 4 skipped, 0 failed; none run" in line and "garments/min" not in line
    # a gate failing on an unchanged folder is no garment run
    line = _summary_of(["skipped", "failed"], ran=0)
    assert "0 done, 1 skipped, 1 failed; none run" in line
    line = _summary_of(["ok", "skipped", "skipped", "failed"], ran=2)
    assert "1 done, 2 skipped, 1 failed; 4.0 garments/min over the 2 run (in-process)" in line


def test_a_batch_of_unchanged_garments_says_so(tmp_path, recipe, catalogue):
    args = ("batch", recipe, catalogue / "[ab]_*.obj", "-o", tmp_path / "out", "-j", "1", *FAST)
    r = run(*args)
    assert r.exit_code == 0 and "2 done, 0 skipped, 0 failed;" in r.stderr
    assert "garments/min over the 2 run" in r.stderr
    r = run(*args)
    assert r.exit_code == 0
    last = r.stderr.splitlines()[-1]
    assert last.startswith("time") and "0 done, 2 skipped, 0 failed; none run" in last
    assert "garments/min" not in r.stderr


def _garments(folder: Path, sizes: list[int]) -> None:
    """Lantern sleeves g00.obj, g01.obj, ... of about these many triangles."""
    folder.mkdir(parents=True, exist_ok=True)
    for k, n in enumerate(sizes):
        write_garment(folder / f"g{k:02d}.obj", sample_for_triangles(n))


def _cmd(*args) -> list[str]:
    return [sys.executable, "-m", "ptailor", "batch", *[str(a) for a in args]]


def _complete(folder: Path) -> bool:
    try:
        rep = json.loads((folder / "report.json").read_text())
    except (OSError, ValueError):
        return False
    return set(rep["outputs"]) | {"batch.json"} <= set(visible(folder))


@pytest.mark.slow
def test_sigint_leaves_complete_folders_and_a_rerun_finishes(tmp_path, recipe):
    cat = tmp_path / "cat"
    _garments(cat, [12_000 + 500 * k for k in range(10)])
    out, log = tmp_path / "out", tmp_path / "log.jsonl"
    cmd = _cmd(recipe, cat / "*.obj", "-o", out, "-j", "2", "--log", log)
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 240
    while time.monotonic() < deadline and proc.poll() is None:
        if out.is_dir() and any(not p.name.startswith(".") for p in out.iterdir()):
            break
        time.sleep(0.01)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "interrupted" in err and "run the same command again" in err
    done = visible(out)
    assert 1 <= len(done) < 10, done  # only complete folders, no staging folders
    assert all(_complete(out / name) for name in done)
    recs = records(log)
    assert [Path(x["garment"]).stem for x in recs] == [f"g{k:02d}" for k in range(10)]
    assert {x["status"] for x in recs} <= {"ok", "interrupted"}
    assert sorted(Path(x["out"]).name for x in recs if x["status"] == "ok") == done
    # the re-run skips what was done and finishes the rest
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    recs = records(log)
    assert sorted(Path(x["out"]).name for x in recs if x["status"] == "skipped") == done
    assert sum(x["status"] == "ok" for x in recs) == 10 - len(done)
    assert len(visible(out)) == 10 and all(_complete(p) for p in out.iterdir())


def _outputs(out: Path) -> dict:
    """Every output file's bytes, report.json without timing_s."""
    files = {}
    for folder in sorted(out.iterdir()):
        for f in sorted(folder.iterdir()):
            data = f.read_bytes()
            if f.name == "report.json":
                rep = json.loads(data)
                rep.pop("timing_s")
                data = json.dumps(rep, sort_keys=True).encode()
            files[f"{folder.name}/{f.name}"] = data
    return files


@pytest.mark.slow
def test_same_bytes_from_one_two_workers_and_dask(tmp_path, recipe, monkeypatch):
    distributed = pytest.importorskip("dask.distributed")
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1700000000")
    cat = tmp_path / "cat"
    # big first: with two workers the records complete out of order
    _garments(cat, [12_000, 3000, 3000])
    write_garment(cat / "skirt.obj", cone_skirt(n_around=20, n_along=8))
    (cat / "sleeve.obj").write_text(sample_obj_text("lantern_sleeve"))
    outs = {}
    for name, extra in (("j1", ["-j", "1"]), ("j2", ["-j", "2"])):
        outs[name] = tmp_path / name
        r = subprocess.run(
            _cmd(recipe, "*/*.obj", "-o", name, "--json", *extra),
            capture_output=True,
            text=True,
            timeout=300,
            cwd=tmp_path,
        )
        assert r.returncode == 0, r.stderr
        assert [json.loads(ln)["out"] for ln in r.stdout.splitlines()] == [
            f"{name}/{g}" for g in ("g00", "g01", "g02", "skirt", "sleeve")
        ]
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        outs["dask"] = tmp_path / "dask"
        r = subprocess.run(
            _cmd(recipe, "*/*.obj", "-o", "dask", "--scheduler", cluster.scheduler_address),
            capture_output=True,
            text=True,
            timeout=300,
            cwd=tmp_path,
        )
        assert r.returncode == 0, r.stderr
        assert "Dask scheduler" in r.stderr
    ref = _outputs(outs["j1"])
    assert len(ref) == 5 * 7
    assert {k.split("/")[1] for k in ref} == ALL_OUTPUTS | {"report.json"}
    for name in ("j2", "dask"):
        got = _outputs(outs[name])
        assert sorted(got) == sorted(ref)
        assert [k for k in ref if got[k] != ref[k]] == [], name


def test_scheduler_without_dask_is_a_clear_error(tmp_path, recipe, monkeypatch):
    monkeypatch.setitem(sys.modules, "dask.distributed", None)
    p = tmp_path / "sleeve.obj"
    p.write_text(sample_obj_text("lantern_sleeve"))
    r = run("batch", recipe, p, "-o", tmp_path / "out", "--scheduler", "tcp://127.0.0.1:1")
    assert r.exit_code == 2
    assert "pip install 'ptailor[dask]'" in r.stderr


@pytest.mark.slow
def test_worker_pool_isolates_failures_quietly(tmp_path, recipe, catalogue):
    out = tmp_path / "out"
    r = subprocess.run(
        _cmd(recipe, catalogue / "*.obj", "-o", out, "-j", "2", "--json", "-q", *FAST),
        capture_output=True,
        text=True,
        timeout=300,
        env={**os.environ, "PYTHONWARNINGS": "ignore"},
    )
    assert r.returncode == 1
    recs = [json.loads(ln) for ln in r.stdout.splitlines()]
    assert [x["status"] for x in recs] == ["ok", "ok", "failed", "ok", "ok"]
    # -q: no summary table, only the failure
    assert [ln.strip() for ln in r.stderr.splitlines() if ln.strip()] == [recs[2]["reason"]]
    assert "2 worker processes" not in r.stderr


@pytest.mark.slow
def test_dxf_patterns_with_their_drapes_in_a_folder(tmp_path):
    """A folder of CAD exports (X.dxf + X.obj): each pair is one garment; a DXF without its
    drape fails naming the missing file; the drape is stamped with the pattern."""
    from tests.test_pattern_io import _setup

    cat = tmp_path / "cat"
    cat.mkdir()
    for sample in ("lantern_sleeve", "cone_skirt"):
        _setup(cat, sample)  # cat/SAMPLE.dxf (mm) + cat/SAMPLE.obj (vt in mm)
    lone = cat / "lone.dxf"
    lone.write_bytes((cat / "cone_skirt.dxf").read_bytes())
    recipe = tmp_path / "r.yaml"
    recipe.write_text("steps: [{op: scale, region: all, direction: uniform, factor: 1.1}]\n")
    out = tmp_path / "out"
    r = run("batch", recipe, cat, "-o", out, "-j", "1", "--json", "-q", "--formats", "dxf")
    assert r.exit_code == 1
    recs = {Path(x["garment"]).name: x for x in map(json.loads, r.stdout.splitlines())}
    assert sorted(recs) == ["cone_skirt.dxf", "lantern_sleeve.dxf", "lone.dxf"]
    assert recs["lone.dxf"]["status"] == "failed" and "lone.obj" in recs["lone.dxf"]["reason"]
    assert sorted(p.name for p in out.iterdir()) == ["cone_skirt", "lantern_sleeve"]
    for name in ("cone_skirt", "lantern_sleeve"):
        rep = json.loads((out / name / "report.json").read_text())
        assert set(rep["inputs"]) == {"pattern", "drape"}
        assert all(p["source"] == "file" for p in rep["pattern"]["pieces"])
    # unchanged -> skipped; a changed drape redoes its garment only
    r = run("batch", recipe, cat, "-o", out, "-j", "1", "--json", "-q", "--formats", "dxf")
    recs = {Path(x["garment"]).name: x["status"] for x in map(json.loads, r.stdout.splitlines())}
    assert recs["cone_skirt.dxf"] == "skipped" and recs["lantern_sleeve.dxf"] == "skipped"
    drape = cat / "cone_skirt.obj"
    drape.write_text(drape.read_text() + "# touched\n")
    r = run("batch", recipe, cat, "-o", out, "-j", "1", "--json", "-q", "--formats", "dxf")
    recs = {Path(x["garment"]).name: x["status"] for x in map(json.loads, r.stdout.splitlines())}
    assert recs["cone_skirt.dxf"] == "ok" and recs["lantern_sleeve.dxf"] == "skipped"


@pytest.mark.parametrize("target", ["garment", "recipe", "notes", "report", "binary"])
def test_the_log_never_overwrites_an_input_or_a_file_that_is_not_a_log(
    tmp_path, recipe, catalogue, target
):
    """Issue 22: ``--log garment.obj`` destroyed the garment, ``--log recipe.yaml`` replaced
    the recipe with JSON lines (exit 0). An input of the run or a file that is not a
    ptailor log is exit 2 before anything runs, the file untouched, no output."""
    out = tmp_path / "out"
    (tmp_path / "notes.txt").write_text("my notes\n")
    (tmp_path / "report.json").write_text('{"panels": []}\n')
    (tmp_path / "blob.bin").write_bytes(b"\xff\xfe\x00garbage")
    log = {
        "garment": catalogue / "a_sleeve.obj",
        "recipe": recipe,
        "notes": tmp_path / "notes.txt",
        "report": tmp_path / "report.json",
        "binary": tmp_path / "blob.bin",
    }[target]
    before = log.read_bytes()
    r = run("batch", recipe, catalogue / "a_*.obj", "-o", out, "--log", log, *FAST)
    assert r.exit_code == 2
    assert str(log) in r.stderr and "--log" in r.stderr
    assert log.read_bytes() == before
    assert not out.exists()


def test_the_log_replaces_its_own_kind_and_an_empty_file(tmp_path, recipe, catalogue):
    out, log = tmp_path / "out", tmp_path / "log.jsonl"
    log.write_text("")
    args = ("batch", recipe, catalogue / "a_*.obj", "-o", out, "--log", log, *FAST)
    assert run(*args).exit_code == 0
    assert [x["status"] for x in records(log)] == ["ok"]
    assert run(*args).exit_code == 0  # an earlier run's log: replaced by this run's records
    assert [x["status"] for x in records(log)] == ["skipped"]
    log.write_text(log.read_text() + "not a record\n")
    assert run(*args).exit_code == 2


def test_the_log_is_not_the_drape_beside_a_dxf_garment(tmp_path, recipe, catalogue):
    from ptailor.batch.records import log_problem

    dxf = catalogue / "a_sleeve.dxf"
    dxf.write_text("0\nEOF\n")
    drape = catalogue / "a_sleeve.obj"
    assert log_problem(drape, [dxf, drape]) is not None
    r = run("batch", recipe, dxf, "-o", tmp_path / "out", "--log", drape, *FAST)
    assert r.exit_code == 2 and "input of this run" in r.stderr


def test_a_folder_completed_as_the_interrupt_came_is_recorded_ok(tmp_path):
    """The race behind a flaky interrupt test: a worker swaps its folder in, then the
    Ctrl-C reaches it before its result does. The folder is complete and stamped by this
    run, so its record is ``ok`` (from the folder's report), not ``interrupted``; a job
    without its folder stays interrupted."""
    from ptailor.batch.executors import _final_records
    from ptailor.recipe import parse_recipe
    from ptailor.run import RunOptions

    cat = tmp_path / "cat"
    _garments(cat, [2_000, 2_000])
    opts = RunOptions(formats=("obj",), baseline=False)
    jobs = pb.make_jobs(sorted(str(p) for p in cat.glob("*.obj")), tmp_path / "out",
                        parse_recipe(WIDER), options=opts)  # fmt: skip
    ran = pb.run_batch(jobs[:1], workers=1)
    assert [r["status"] for r in ran.records] == ["ok"]
    final = _final_records(jobs, [None, None], cleanup=True)
    assert [r["status"] for r in final] == ["ok", "interrupted"]
    assert final[0]["reason"] == "finished as the batch was interrupted"
    assert final[0]["max_area_change"] == ran.records[0]["max_area_change"]
