"""Output folders that cannot eat user data (issue 12): the marker, inputs never replaced,
signals, symbolic links, file-system errors, one-line messages, library noise, batch
timeouts."""

from __future__ import annotations

import contextlib
import json
import logging
import os
import signal
import subprocess
import sys
import time
import warnings
from pathlib import Path

import pytest
from click.testing import CliRunner

from ptailor import batch as pb
from ptailor.cli.main import cli
from ptailor.formats.obj import write_garment
from ptailor.run.folder import MARKER, read_marker
from ptailor.run.staging import staging_stem
from ptailor.samples import lantern_sleeve, sample_for_triangles

WIDER = "steps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.2}]\n"
FAST = ("--formats", "obj", "--no-baseline")


@pytest.fixture
def garment(tmp_path) -> Path:
    p = tmp_path / "g.obj"
    write_garment(p, lantern_sleeve(n_around=10, n_sleeve=4, n_cuff=2))
    return p


@pytest.fixture
def recipe(tmp_path) -> Path:
    p = tmp_path / "r.yaml"
    p.write_text(WIDER)
    return p


def adjust(garment, recipe, out, *extra):
    args = ["adjust", str(garment), str(recipe), "-o", str(out), "-q", *FAST, *extra]
    return CliRunner().invoke(cli, args)


def error_line(r) -> str:
    """The exit-2 message: exactly one line on stderr."""
    assert r.exit_code == 2, (r.exit_code, r.output, r.exception)
    lines = r.stderr.splitlines()
    assert len(lines) == 1, lines
    assert ".tmp" not in lines[0]
    return lines[0]


def staging_left(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.endswith(".tmp"))


def tree(folder: Path) -> dict:
    return {str(p.relative_to(folder)): p.read_bytes() for p in folder.rglob("*") if p.is_file()}


# --------------------------------------------------------------------------- the marker


def test_another_tools_report_json_is_not_an_earlier_output(tmp_path, garment, recipe):
    out = tmp_path / "out"
    out.mkdir()
    (out / "report.json").write_text('{"tool": "someone else", "outputs": ["report.json"]}')
    (out / "notes.txt").write_text("mine")
    before = tree(out)
    line = error_line(adjust(garment, recipe, out))
    assert str(out) in line and "not an earlier ptailor output" in line and "notes.txt" in line
    assert tree(out) == before and staging_left(tmp_path) == []


def test_a_symlink_named_report_json_is_not_an_earlier_output(tmp_path, garment, recipe):
    done = tmp_path / "done"
    assert adjust(garment, recipe, done).exit_code == 0
    out = tmp_path / "out"
    out.mkdir()
    (out / "report.json").symlink_to(done / "report.json")  # a real ptailor report, linked
    (out / "garment.obj").symlink_to(done / "garment.obj")
    error_line(adjust(garment, recipe, out))
    assert (out / "report.json").is_symlink() and (done / "report.json").is_file()


def test_an_earlier_output_is_replaced_and_a_user_file_in_it_is_not(tmp_path, garment, recipe):
    out = tmp_path / "out"
    assert adjust(garment, recipe, out).exit_code == 0
    assert read_marker(out) == ["garment.obj", "report.json"]
    assert adjust(garment, recipe, out).exit_code == 0  # replaced: its marker lists it all
    (out / "notes.txt").write_text("mine")
    line = error_line(adjust(garment, recipe, out))
    assert "notes.txt" in line and "other than those its .ptailor marker lists" in line
    assert (out / "notes.txt").read_text() == "mine"
    (out / "notes.txt").unlink()
    (out / "sub").mkdir()  # a folder, even one named like nothing ptailor writes
    error_line(adjust(garment, recipe, out))
    assert (out / "sub").is_dir()


def test_a_marker_ptailor_did_not_write_is_refused(tmp_path, garment, recipe):
    out = tmp_path / "out"
    out.mkdir()
    (out / MARKER).write_text("not json")
    (out / "report.json").write_text("{}")
    line = error_line(adjust(garment, recipe, out))
    assert "report.json" in line and (out / MARKER).read_text() == "not json"


def test_an_output_from_before_the_marker(tmp_path, garment, recipe):
    """Decision: a folder without the marker is accepted only when every file in it is one
    that ptailor writes and its report.json (a ptailor report: inputs, panels, solver)
    lists; anything else is refused, with a message to empty it or choose another."""
    out = tmp_path / "out"
    assert adjust(garment, recipe, out, "--formats", "obj,svg").exit_code == 0
    (out / MARKER).unlink()  # as a ptailor before the marker wrote it
    assert adjust(garment, recipe, out).exit_code == 0
    assert read_marker(out) is not None
    (out / MARKER).unlink()
    (out / "recipe.yaml").write_text("user's")  # a name the demo writes, not in outputs
    line = error_line(adjust(garment, recipe, out))
    assert "recipe.yaml" in line and (out / "recipe.yaml").read_text() == "user's"


# --------------------------------------------------------------------------- inputs


@pytest.mark.parametrize("role", ["recipe", "garment", "drape", "body"])
def test_inputs_are_never_inside_what_gets_replaced(tmp_path, garment, recipe, role):
    out = tmp_path / "out"
    assert adjust(garment, recipe, out).exit_code == 0
    inside = out / f"in-{role}"
    inside.write_bytes((recipe if role == "recipe" else garment).read_bytes())
    args = {"garment": garment, "recipe": recipe}
    extra = []
    if role in ("recipe", "garment"):
        args[role] = inside
    else:
        extra = [f"--{role}", str(inside)]
    before = tree(out)
    line = error_line(adjust(args["garment"], args["recipe"], out, *extra))
    assert str(inside) in line and str(out) in line
    assert tree(out) == before


def test_an_input_reached_through_a_link_or_a_relative_path(tmp_path, garment, recipe):
    out = tmp_path / "out"
    assert adjust(garment, recipe, out).exit_code == 0
    (out / "r.yaml").write_text(WIDER)
    link = tmp_path / "link.yaml"
    link.symlink_to(out / "r.yaml")
    error_line(adjust(garment, link, out))
    old = os.getcwd()
    try:
        os.chdir(out)
        error_line(adjust(garment, "r.yaml", "."))  # -o . with the recipe in it
        error_line(adjust(garment, "../r.yaml", ".."))  # the output holds every input
    finally:
        os.chdir(old)
    assert (out / "r.yaml").read_text() == WIDER and garment.is_file()


def test_batch_never_replaces_the_recipe(tmp_path, garment):
    out = tmp_path / "out"
    r = CliRunner().invoke(cli, ["batch", str(tmp_path / "r0.yaml"), str(garment), "-o", out])
    assert r.exit_code == 2  # (no recipe yet)
    rec = out / "g" / "r.yaml"
    rec.parent.mkdir(parents=True)
    rec.write_text(WIDER)
    args = ["batch", str(rec), str(garment), "-o", str(out), "-j", "1", "--json", *FAST]
    r = CliRunner().invoke(cli, args)
    assert r.exit_code == 1
    record = json.loads(r.stdout.splitlines()[0])
    assert record["failure"] == "input" and "r.yaml" in record["reason"]
    assert rec.read_text() == WIDER


# --------------------------------------------------------------------------- links, names


def test_a_symlinked_output_is_followed_and_kept(tmp_path, garment, recipe):
    """Decision: a link to a folder is followed (the folder it points to is replaced under
    the same rules, the link is kept: CAD users link an output into a shared drive); a
    link to nothing is refused, nothing is created."""
    target = tmp_path / "real"
    target.mkdir()
    link = tmp_path / "out"
    link.symlink_to(target)
    assert adjust(garment, recipe, link).exit_code == 0
    assert link.is_symlink() and os.readlink(link) == str(target)
    assert (target / "report.json").is_file() and read_marker(target) is not None
    assert adjust(garment, recipe, link).exit_code == 0  # again: an earlier output
    assert link.is_symlink() and staging_left(tmp_path) == []
    (target / "notes.txt").write_text("mine")
    error_line(adjust(garment, recipe, link))
    assert (target / "notes.txt").read_text() == "mine" and link.is_symlink()


def test_a_dangling_symlink_output_is_refused(tmp_path, garment, recipe):
    link = tmp_path / "out"
    link.symlink_to(tmp_path / "nowhere")
    line = error_line(adjust(garment, recipe, link))
    assert str(link) in line and "does not exist" in line
    assert link.is_symlink() and not (tmp_path / "nowhere").exists()
    assert staging_left(tmp_path) == []


def test_a_name_too_long_is_one_line(tmp_path, garment, recipe):
    out = tmp_path / ("x" * 300)
    line = error_line(adjust(garment, recipe, out))
    assert "too long" in line and staging_left(tmp_path) == []


def test_a_long_name_that_fits_is_written_and_replaced(tmp_path, garment, recipe):
    out = tmp_path / ("y" * 250)  # its staging folders' names are cut to fit
    assert adjust(garment, recipe, out).exit_code == 0
    assert adjust(garment, recipe, out).exit_code == 0
    assert len(staging_stem(out.name)) < 100 and staging_left(tmp_path) == []
    assert (out / "report.json").is_file()


def test_an_unwritable_parent_is_one_line(tmp_path, garment, recipe, monkeypatch):
    import ptailor.run.staging

    def denied(*a, **k):
        raise PermissionError(13, "Permission denied", str(tmp_path / "ro"))

    monkeypatch.setattr(ptailor.run.staging.tempfile, "mkdtemp", denied)
    line = error_line(adjust(garment, recipe, tmp_path / "ro" / "out"))
    assert str(tmp_path / "ro" / "out") in line and "Permission denied" in line


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_a_read_only_parent_is_one_line(tmp_path, garment, recipe):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        line = error_line(adjust(garment, recipe, ro / "out"))
        assert "Permission denied" in line
    finally:
        ro.chmod(0o755)


def test_an_os_error_while_writing_names_the_output_not_the_staging(
    tmp_path, garment, recipe, monkeypatch
):
    import ptailor.run.garment

    def full(tmp, *a, **k):
        (tmp / "garment.obj").write_text("partial")
        raise OSError(28, "No space left on device", str(tmp / "garment.obj"))

    monkeypatch.setattr(ptailor.run.garment, "write_outputs", full)
    out = tmp_path / "out"
    line = error_line(adjust(garment, recipe, out))
    assert str(out) in line and "No space left on device" in line
    assert not out.exists() and staging_left(tmp_path) == []


def test_the_output_folder_keeps_its_permissions(tmp_path, garment, recipe):
    out = tmp_path / "out"
    assert adjust(garment, recipe, out).exit_code == 0
    assert out.stat().st_mode & 0o777 == 0o777 & ~_umask()  # not mkdtemp's 0700
    out.chmod(0o750)
    assert adjust(garment, recipe, out).exit_code == 0
    assert out.stat().st_mode & 0o777 == 0o750


def _umask() -> int:
    m = os.umask(0)
    os.umask(m)
    return m


# --------------------------------------------------------------------------- library noise


def test_library_warnings_go_to_the_report_not_the_terminal(tmp_path, garment, recipe, monkeypatch):
    import ptailor.run.garment

    real = ptailor.run.garment.write_outputs

    def noisy(*a, **k):
        warnings.warn("invalid value encountered in divide", RuntimeWarning, stacklevel=1)
        logging.getLogger("ezdxf").warning("recover mode: fixed 3 entities")
        return real(*a, **k)

    monkeypatch.setattr(ptailor.run.garment, "write_outputs", noisy)
    out = tmp_path / "out"
    r = adjust(garment, recipe, out)
    assert r.exit_code == 0 and r.stderr == ""
    w = json.loads((out / "report.json").read_text())["warnings"]
    assert "library warning: RuntimeWarning: invalid value encountered in divide" in w
    assert "library warning: ezdxf: recover mode: fixed 3 entities" in w


def test_library_warnings_never_come_before_the_error_line(tmp_path, garment, recipe, monkeypatch):
    import ptailor.run.garment
    from ptailor.errors import PtailorError

    def fails(*a, **k):
        warnings.warn("overflow encountered in multiply", RuntimeWarning, stacklevel=1)
        logging.getLogger("ezdxf").error("DXF structure error")
        raise PtailorError("bad\npiece", path=str(garment))

    monkeypatch.setattr(ptailor.run.garment, "write_outputs", fails)
    line = error_line(adjust(garment, recipe, tmp_path / "out"))
    assert line == f"ptailor: error: {garment}: bad piece"


# --------------------------------------------------------------------------- signals


def _cmd(*args) -> list[str]:
    return [sys.executable, "-m", "ptailor", *[str(a) for a in args]]


def _signal_when_staging(proc, parent: Path, sig: int, name: str, limit: float = 120) -> bool:
    """Send ``sig`` once a staging folder for ``name`` appears (or at once when the run
    ended); True when the signal landed while the staging folder existed."""
    deadline = time.monotonic() + limit
    while time.monotonic() < deadline and proc.poll() is None:
        if any(p.name.startswith(f".{name}.") for p in parent.iterdir()):
            proc.send_signal(sig)
            return True
        time.sleep(0.005)
    return False


@pytest.fixture(scope="module")
def big(tmp_path_factory) -> Path:
    p = tmp_path_factory.mktemp("big") / "big.obj"
    write_garment(p, sample_for_triangles(30_000))
    return p


@pytest.mark.slow
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_a_signal_while_writing_leaves_no_staging_and_the_old_output(tmp_path, big, recipe, sig):
    out = tmp_path / "out"
    out.mkdir()
    (out / MARKER).write_text(json.dumps({"written_by": "ptailor", "files": ["report.json"]}))
    (out / "report.json").write_text("{}")  # an earlier output, kept when interrupted
    before = tree(out)
    proc = subprocess.Popen(
        _cmd("adjust", big, recipe, "-o", out, "-q"), stderr=subprocess.PIPE, text=True
    )
    landed = _signal_when_staging(proc, tmp_path, sig, "out")
    _, err = proc.communicate(timeout=120)
    if not landed:  # (the run ended first: a slow machine did not show the folder)
        pytest.skip("the run ended before its staging folder was seen")
    assert proc.returncode == 128 + sig, err
    assert err.splitlines() == [
        f"ptailor: interrupted ({signal.Signals(sig).name}): no partial output left"
    ]
    assert staging_left(tmp_path) == []
    # the earlier output as it was, or (the signal held back while the folder was swapped)
    # the new one complete
    after = tree(out)
    assert after == before or set(read_marker(out)) <= set(after)


@pytest.mark.slow
def test_sigterm_at_random_times_never_leaves_staging(tmp_path, recipe):
    g = tmp_path / "m.obj"
    write_garment(g, sample_for_triangles(6000))
    for k, delay in enumerate([0.05, 0.3, 0.6, 0.9, 1.2, 1.6]):
        out = tmp_path / f"o{k}"
        proc = subprocess.Popen(_cmd("adjust", g, recipe, "-o", out, "-q"), stderr=subprocess.PIPE)
        time.sleep(delay)
        proc.send_signal(signal.SIGTERM)
        proc.communicate(timeout=120)
        assert proc.returncode in (0, 128 + signal.SIGTERM, -signal.SIGTERM)
        assert staging_left(tmp_path) == []
        if proc.returncode != 0:
            assert not out.exists() or read_marker(out) is not None
        else:
            assert read_marker(out) is not None


# --------------------------------------------------------------------------- batch timeout


@pytest.mark.slow
@pytest.mark.parametrize("jobs", ["1", "2"])
def test_batch_timeout_fails_the_garment_and_writes_nothing(tmp_path, garment, recipe, jobs):
    out = tmp_path / "out"
    args = ["batch", str(recipe), str(garment), "-o", str(out), "--json", "-j", jobs]
    r = CliRunner().invoke(cli, [*args, "--timeout", "0.001", *FAST])
    assert r.exit_code == 1, r.output
    rec = json.loads(r.stdout.splitlines()[0])
    assert rec["status"] == "failed" and rec["failure"] == "timeout"
    assert "timeout" in rec["reason"]
    assert not (out / "g").exists() and (not out.exists() or staging_left(out) == [])
    r = CliRunner().invoke(cli, [*args, "--timeout", "300", *FAST])
    assert r.exit_code == 0 and json.loads(r.stdout.splitlines()[0])["status"] == "ok"


def test_batch_timeout_with_a_scheduler_is_refused(tmp_path, garment, recipe):
    r = CliRunner().invoke(
        cli,
        [
            "batch",
            str(recipe),
            str(garment),
            "-o",
            str(tmp_path / "o"),
            "--timeout",
            "1",
            "--scheduler",
            "tcp://127.0.0.1:1",
        ],
    )
    assert r.exit_code == 2 and "--timeout" in r.stderr


@pytest.mark.slow
@pytest.mark.skipif(
    __import__("multiprocessing").get_start_method() != "fork",
    reason="the patched staged_run reaches the workers only when they are forked",
)
def test_a_garment_stuck_past_its_timeout_has_its_worker_killed(tmp_path, monkeypatch):
    import ptailor.run.garment
    from ptailor.recipe import parse_recipe
    from ptailor.run import RunOptions

    for name in ("a", "b", "c"):
        write_garment(tmp_path / f"{name}.obj", lantern_sleeve(n_around=8, n_sleeve=3))
    real = ptailor.run.garment.staged_run

    def stuck(path, *args, **kw):  # deaf to signals, as native code can be
        if path.endswith("b.obj"):
            t = time.monotonic()
            while time.monotonic() - t < 60:
                with contextlib.suppress(BaseException):  # the timeout too
                    time.sleep(0.05)
        return real(path, *args, **kw)

    monkeypatch.setattr(ptailor.run.garment, "staged_run", stuck)
    monkeypatch.setattr(pb.jobs, "TIMEOUT_GRACE_S", 0.5)
    out = tmp_path / "out"
    paths = [str(tmp_path / f"{n}.obj") for n in "abc"]
    opts = RunOptions(formats=("obj",), baseline=False)
    jobs = pb.make_jobs(paths, out, parse_recipe(WIDER), options=opts, timeout=1.0)
    t0 = time.monotonic()
    res = pb.run_batch(jobs, workers=2)
    assert time.monotonic() - t0 < 50
    assert [r["status"] for r in res.records] == ["ok", "failed", "ok"]
    assert res.records[1]["failure"] == "timeout"
    assert sorted(p.name for p in out.iterdir()) == ["a", "c"]


def test_a_batch_folder_from_before_the_marker_is_redone(tmp_path, garment, recipe):
    out = tmp_path / "out"
    args = ["batch", str(recipe), str(garment), "-o", str(out), "-j", "1", "-q", *FAST]
    assert CliRunner().invoke(cli, args).exit_code == 0
    (out / "g" / MARKER).unlink()  # as a ptailor before the marker wrote it (batch.json too)
    r = CliRunner().invoke(cli, [*args, "--force"])
    assert r.exit_code == 0, r.stderr
    assert set(read_marker(out / "g")) == {"batch.json", "garment.obj", "report.json"}


def test_usage_errors_are_one_line(tmp_path, garment, recipe):
    (tmp_path / "f").write_text("a file")
    r = CliRunner().invoke(cli, ["adjust", str(garment), str(recipe), "-o", str(tmp_path / "f")])
    assert r.exit_code == 2 and len(r.stderr.splitlines()) == 1
    assert str(tmp_path / "f") in r.stderr
    r = CliRunner().invoke(cli, ["adjust", str(garment)])
    assert r.exit_code == 2 and r.stderr.splitlines() == [
        "ptailor adjust: error: Missing option '-o' / '--out'. (ptailor adjust --help)"
    ]
    r = CliRunner().invoke(cli, ["adjust", str(garment), "-o", str(tmp_path / "o")])
    assert r.exit_code == 2 and r.stderr.splitlines() == [
        "ptailor adjust: error: Missing argument 'RECIPE' (or give --edited-drape). "
        "(ptailor adjust --help)"
    ]
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("when", ["mkdtemp", "writing", "swap"])
def test_a_signal_at_each_step_of_staging_leaves_no_staging(tmp_path, monkeypatch, when):
    """Deterministic: SIGINT as the staging folder is created, while it is written, and
    while the folders are swapped (held back until the swap is done)."""
    import tempfile

    import ptailor.run.folder as po

    out = tmp_path / "out"
    real_mkdtemp = tempfile.mkdtemp

    def mkdtemp(*a, **k):
        path = real_mkdtemp(*a, **k)
        if when == "mkdtemp":
            signal.raise_signal(signal.SIGINT)
        return path

    monkeypatch.setattr(tempfile, "mkdtemp", mkdtemp)  # (as ptailor.run.staging calls it)
    if when == "swap":
        real_check = po.check_replaceable

        def check(folder, shown):
            signal.raise_signal(signal.SIGINT)  # in the middle of the swap
            real_check(folder, shown)

        monkeypatch.setattr(po, "check_replaceable", check)
        out.mkdir()
    with pytest.raises(KeyboardInterrupt), po.staged_dir(out) as tmp:
        (tmp / "report.json").write_text("{}")
        if when == "writing":
            signal.raise_signal(signal.SIGINT)
    assert staging_left(tmp_path) == []
    if when == "swap":  # the swap was finished first
        assert read_marker(out) == ["report.json"]
    else:
        assert not out.exists()


def test_a_full_disk_leaves_no_parent_folder_it_made(tmp_path, garment, recipe, monkeypatch):
    """Issue 22: ``-o mnt/new/sub/out`` on a full disk left ``new/sub`` behind."""
    import ptailor.run.garment

    def full(tmp, *a, **k):
        raise OSError(28, "No space left on device", str(tmp / "garment.obj"))

    monkeypatch.setattr(ptailor.run.garment, "write_outputs", full)
    (tmp_path / "mnt").mkdir()
    out = tmp_path / "mnt" / "new" / "sub" / "out"
    line = error_line(adjust(garment, recipe, out))
    assert "No space left on device" in line
    assert sorted(p.name for p in (tmp_path / "mnt").iterdir()) == []


def test_a_staging_folder_no_live_process_holds_is_removed_by_the_next_run(
    tmp_path, garment, recipe
):
    """Issue 22: ``kill -9`` during ``adjust`` left ``.OUT.XXXXXXXX.tmp`` and later runs
    never removed it. The next run on that output removes the staging folders of its own
    kind that no live process holds (a writer holds a lock on its folder), and leaves a
    held one alone."""
    import fcntl

    out = tmp_path / "out"
    assert adjust(garment, recipe, out).exit_code == 0  # an earlier output: kept as it is
    stale = tmp_path / f".{staging_stem('out')}.abcd1234.tmp"
    held = tmp_path / f".{staging_stem('out')}.held5678.tmp"
    old = tmp_path / f".{staging_stem('out')}.old-{stale.name}"
    for d in (stale, held, old):
        d.mkdir()
        (d / "garment.obj").write_text("partial")
    other = tmp_path / ".notes.abcd1234.tmp"  # another output's: not ours to touch
    other.mkdir()
    fd = os.open(held, os.O_RDONLY)
    fcntl.flock(fd, fcntl.LOCK_EX)
    try:
        r = adjust(garment, recipe, out)
        assert r.exit_code == 0, r.output
        assert not stale.exists() and not old.exists()
        assert held.exists() and other.exists()
    finally:
        os.close(fd)


def _children(pid: int) -> list[int]:
    out = subprocess.run(["pgrep", "-P", str(pid)], capture_output=True, text=True)
    return [int(x) for x in out.stdout.split()]


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().split(")")[-1].split()[0] != "Z"
    except OSError:
        return False


@pytest.mark.slow
@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc and pgrep")
def test_kill_9_of_a_batch_ends_its_workers_and_keeps_the_records_it_had(tmp_path, recipe):
    """Issue 22: ``kill -9`` of ``ptailor batch`` left its workers alive and idle, holding
    its stdout (``ptailor batch ... | tee`` never ended), and its log empty with 8 of 9
    folders complete (records waited for input order). Workers now end within a second of
    their batch, and the log holds each record as it became known (with its index)."""
    cat = tmp_path / "cat"
    cat.mkdir()
    for i in range(8):
        write_garment(cat / f"g{i}.obj", sample_for_triangles(3000 + 400 * i))
    out, log = tmp_path / "out", tmp_path / "log.jsonl"
    cmd = [sys.executable, "-m", "ptailor", "batch", str(recipe), str(cat / "*.obj"),
           "-o", str(out), "-j", "2", "--log", str(log), "-q", *FAST]  # fmt: skip
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and not (
            log.exists() and log.read_text().count("\n") >= 2
        ):
            time.sleep(0.05)
        workers = _children(p.pid)
        assert workers, "no worker processes"
        p.kill()
        p.wait()
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and any(_alive(w) for w in workers):
            time.sleep(0.05)
        assert not any(_alive(w) for w in workers)
        p.stdout.read()  # every writer of the pipe is gone: no hang
    finally:
        with contextlib.suppress(ProcessLookupError):
            p.kill()
    recs = [json.loads(ln) for ln in log.read_text().splitlines()]
    assert len(recs) >= 2 and all(r["status"] == "ok" for r in recs)
    assert len({r["index"] for r in recs}) == len(recs)
    for r in recs:
        assert (Path(r["out"]) / "garment.obj").is_file() or (out / Path(r["out"]).name).is_dir()


@pytest.mark.parametrize(("finished", "says"), [(True, "its output is complete"),
                                                 (False, "nothing written")])  # fmt: skip
def test_a_signal_outside_the_command_ends_with_its_one_line(finished, says):
    """Issue 22: a signal in the last milliseconds, after the output was in place, ended
    the process without its one-line message."""
    code = (
        "import ptailor.cli.main as m, signal; "
        f"m._FINISHED = {finished}; m._die(signal.SIGTERM, None)"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 128 + signal.SIGTERM
    when = "after the command finished" if finished else "before the command started"
    assert r.stderr.strip() == f"ptailor: interrupted (SIGTERM) {when}: {says}"


class _RejectedError(Exception):
    pass


def test_a_diverted_folder_goes_elsewhere_whole_and_out_stays(tmp_path):
    """``staged_dir(divert=...)``: the exception named puts the staged folder at the other
    place (its marker written), ``out`` untouched; another exception removes it; a foreign
    folder in the way is never replaced (the staged one is removed)."""
    from ptailor.run.folder import add_files, staged_dir

    out, elsewhere = tmp_path / "out", tmp_path / "_rejected" / "out"
    with staged_dir(out) as tmp:
        (tmp / "a.txt").write_text("first\n")
    with pytest.raises(_RejectedError), staged_dir(out, divert=(_RejectedError, elsewhere)) as tmp:
        (tmp / "a.txt").write_text("rejected\n")
        raise _RejectedError
    assert (out / "a.txt").read_text() == "first\n"
    assert (elsewhere / "a.txt").read_text() == "rejected\n"
    assert read_marker(elsewhere) == ["a.txt"]
    with pytest.raises(ValueError), staged_dir(out, divert=(_RejectedError, elsewhere)) as tmp:
        (tmp / "a.txt").write_text("broken\n")
        raise ValueError
    assert (elsewhere / "a.txt").read_text() == "rejected\n"  # not diverted: removed
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("mine\n")
    with pytest.raises(_RejectedError), staged_dir(out, divert=(_RejectedError, mine)) as tmp:
        (tmp / "a.txt").write_text("rejected\n")
        raise _RejectedError
    assert sorted(p.name for p in mine.iterdir()) == ["notes.txt"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["_rejected", "mine", "out"]
    # files added to an output folder are its marker's: it stays replaceable
    add_files(out, {"page.html": b"<p>\n"})
    assert read_marker(out) == ["a.txt", "page.html"]
    with staged_dir(out) as tmp:
        (tmp / "b.txt").write_text("second\n")
    assert sorted(p.name for p in out.iterdir()) == [MARKER, "b.txt"]
    with pytest.raises(Exception, match=r"no \.ptailor marker"):
        add_files(mine, {"page.html": b"<p>\n"})
