"""The re-drape check through the command line: ``ptailor verify``, ``adjust --verify``,
``batch --verify`` with its gates and records.

The wiring is tested with a fake engine (``verify_patterns`` replaced by canned numbers), so
that these tests run without the cloth engine; one slow test runs the real one (skipped
when it is not installed).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from ptailor.batch import RECORD_KEYS, Gates, gate_failures, key_numbers
from ptailor.cli.main import cli
from ptailor.formats.obj import write_garment
from ptailor.samples import cylinder, lantern_sleeve
from tests.conftest import needs_matplotlib

HINT = "ptailor: error: the cloth engine is not installed: pip install 'ptailor[sim]'"
WIDER = "steps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.2}]\n"
VERIFY_FILES = {"verify_ours.obj", "verify_baseline.obj", "verify.png"}


def run(*args):
    return CliRunner().invoke(cli, [str(a) for a in args])


def small_sleeve(path: Path) -> Path:
    write_garment(path, lantern_sleeve(n_around=12, n_sleeve=3, n_cuff=2))
    return path


def panel_stats(stretch: float, displacement: float) -> dict:
    return {
        "stretch": {"p50": 1.0, "p95": stretch, "max": stretch + 0.01},
        "compression": {"p5": 0.98},
        "displacement": {"mean": displacement / 2, "p95": displacement, "max": 2 * displacement},
    }


@pytest.fixture
def fake_engine(monkeypatch):
    """The engine 'installed', and ``verify_patterns`` answering canned numbers: ours
    stretch p95 1.02 and displacement p95 0.4 per panel, the baseline 1.3 and 2.0; the
    settled drapes are the edited drape moved down 0.1 (ours), 0.2, 0.3. The picture is
    ptailor's own, drawn with matplotlib: a test that gets as far as drawing it also asks for
    ``picture`` (it skips, saying why, without matplotlib: the lean install)."""
    import ptailor.verify.check as check
    import ptailor.verify.engine as engine

    calls = []
    numbers = {"ours": (1.02, 0.4), "baseline": (1.3, 2.0), "original": (1.01, 0.3)}

    def verify_patterns(V3_edit, F3, F2, patterns, V2_orig, V3_orig, *, panel_names, **kw):
        calls.append({"patterns": patterns, "names": list(panel_names), "V3": V3_edit, **kw})
        np.testing.assert_allclose(kw["frame"].matrix()[1], [0, 1, 0], atol=1e-12)  # turned y-up
        assert set(patterns) == {"ours", "baseline", "original"}
        for V2 in patterns.values():
            assert V2.shape == V2_orig.shape and np.all(np.isfinite(V2))
        assert V3_edit.shape == V3_orig.shape and len(F3) == len(F2)
        section = {
            "engine": "fake 0.0",
            "device": "cpu",
            "steps": 30,
            "seconds": 0.5,
            "settled": True,
            "rest": kw["rest"],
        }
        drapes, stretch = {}, {}
        for i, kind in enumerate(patterns):
            s, d = numbers[kind]
            section[kind] = {
                "panels": {n: panel_stats(s, d) for n in panel_names},
                "settled": True,
                "steps": 10,
                "seconds": 0.1,
            }
            drapes[kind] = V3_edit - np.array([0.0, 0.1 * (i + 1), 0.0])
            stretch[kind] = np.full((len(F3), 2), s)
        return section, drapes, stretch

    monkeypatch.setattr(engine, "engine_available", lambda: True)
    monkeypatch.setattr(check, "verify_patterns", verify_patterns)
    return calls


@pytest.fixture
def picture():
    """``verify.png`` is drawn: matplotlib (the sim extra's) is needed, else the test skips."""
    needs_matplotlib()


@pytest.fixture
def no_engine(monkeypatch):
    import ptailor.verify.engine as engine

    monkeypatch.setattr(engine, "engine_available", lambda: False)


# --------------------------------------------------------------------------- no engine


def test_without_the_engine_every_command_says_how_to_install_it(tmp_path, no_engine):
    """Exit 2 with the install hint before any file is read (the garment does not even
    exist), nothing written."""
    rec = tmp_path / "r.yaml"
    rec.write_text(WIDER)
    out = tmp_path / "o"
    for args in (
        ["verify", tmp_path / "missing.obj", "-o", out],
        ["adjust", tmp_path / "missing.obj", rec, "-o", out, "--verify"],
        ["batch", rec, tmp_path / "missing.obj", "-o", out, "--verify"],
    ):
        r = run(*args)
        assert r.exit_code == 2, (args[0], r.output)
        assert r.output.strip() == HINT, args[0]
        assert not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.yaml"]


def test_without_verify_the_engine_is_not_needed(tmp_path, no_engine):
    g = small_sleeve(tmp_path / "s.obj")
    rec = tmp_path / "r.yaml"
    rec.write_text(WIDER)
    r = run("adjust", g, rec, "-o", tmp_path / "o", "--formats", "obj", "-q")
    assert r.exit_code == 0, r.output
    report = json.loads((tmp_path / "o" / "report.json").read_text())
    assert "verify" not in report


def test_the_command_line_does_not_import_the_engine():
    """``ptailor --help`` stays fast: neither the engine nor ptailor.verify is imported until
    a check runs."""
    import subprocess
    import sys

    code = (
        "import sys; from ptailor.cli.main import cli; "
        "bad = [m for m in ('warp', 'newton', 'ptailor.verify', 'ptailor.run') "
        "if m in sys.modules]; print(bad)"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "[]"


# --------------------------------------------------------------------------- ptailor verify


@pytest.mark.slow
def test_verify_writes_the_check_all_or_nothing(tmp_path, fake_engine, picture):
    orig = small_sleeve(tmp_path / "s.obj")
    rec = tmp_path / "r.yaml"
    rec.write_text(WIDER)
    r = run("adjust", orig, rec, "-o", tmp_path / "adj", "--formats", "obj", "-q")
    assert r.exit_code == 0, r.output
    garment = tmp_path / "adj" / "garment.obj"
    out = tmp_path / "check"
    r = run("verify", garment, "--original", orig, "-o", out, "--max-steps", 5, "--json")
    assert r.exit_code == 0, r.output
    doc = json.loads((out / "verify.json").read_text())
    assert json.loads(r.output) == doc
    assert {p.name for p in out.iterdir()} == {".ptailor", "verify.json", *VERIFY_FILES}
    assert doc["outputs"] == sorted(["verify.json", *VERIFY_FILES])
    assert doc["inputs"] == {"garment": str(garment), "original": str(orig)}
    assert doc["units"] == "cm"
    sec = doc["verify"]
    assert {"engine", "device", "steps", "seconds", "settled", "rest"} <= set(sec)
    assert {"ours", "baseline", "original"} <= set(sec)
    assert sec["ours"]["panels"]["cuff"]["stretch"]["p95"] == 1.02
    (call,) = fake_engine
    assert call["rest"] == "intrinsic" and call["settings"].max_steps == 5
    assert call["null_limits"] == (None, None)  # the defaults
    assert call["body"] is None and call["units_m"] == pytest.approx(0.01)
    assert sorted(call["names"]) == ["cuff", "sleeve"]
    # the settled drapes: v = the fake's drape (0.1 below the edited one), vt = the pattern
    from ptailor.formats.garment import load_garment

    edited = load_garment(garment, weld="off").garment
    ours = load_garment(out / "verify_ours.obj", weld="off").garment
    assert np.allclose(ours.V3, edited.V3 - [0, 0.1, 0], atol=1e-5)
    assert np.allclose(ours.V2, edited.V2, atol=1e-5)
    assert np.array_equal(ours.F3, edited.F3)
    base = load_garment(out / "verify_baseline.obj", weld="off").garment
    assert np.allclose(base.V3, edited.V3 - [0, 0.2, 0], atol=1e-5)
    # the summary lines
    r = run("verify", garment, "--original", orig, "-o", out, "--rest", "pattern",
            "--null-mean", "5mm", "--null-p95", "2")  # fmt: skip
    assert r.exit_code == 0, r.output
    assert "ours" in r.output and "stretch p95 1.020" in r.output
    assert fake_engine[-1]["rest"] == "pattern"
    assert fake_engine[-1]["null_limits"] == pytest.approx((0.5, 2.0))  # cm
    r = run("verify", garment, "-o", tmp_path / "bad", "--null-p95", "far")
    assert r.exit_code == 2 and "--null-p95: not a length" in r.output
    assert not (tmp_path / "bad").exists()


def test_verify_without_original_is_its_own_original(tmp_path, fake_engine, picture):
    g = small_sleeve(tmp_path / "s.obj")
    r = run("verify", g, "-o", tmp_path / "o", "-q")
    assert r.exit_code == 0, r.output
    assert r.output == ""
    (call,) = fake_engine
    assert np.array_equal(call["patterns"]["ours"], call["patterns"]["original"])


def test_verify_refuses_an_original_with_other_faces(tmp_path, fake_engine):
    g = small_sleeve(tmp_path / "s.obj")
    other = tmp_path / "c.obj"
    write_garment(other, cylinder())
    out = tmp_path / "o"
    r = run("verify", g, "--original", other, "-o", out)
    assert r.exit_code == 2, r.output
    line = r.output.strip()
    assert line.startswith("ptailor: error:") and "\n" not in line
    assert str(g) in line and str(other) in line and "same faces" in line
    assert not out.exists() and fake_engine == []


@pytest.mark.slow
def test_verify_with_a_body_and_bad_options(tmp_path, fake_engine, picture):
    import trimesh

    g = small_sleeve(tmp_path / "s.obj")
    body = tmp_path / "arm.obj"
    trimesh.creation.cylinder(radius=2.0, height=60.0).export(body)
    r = run("verify", g, "--body", body, "-o", tmp_path / "o", "-q")
    assert r.exit_code == 0, r.output
    V, F = fake_engine[-1]["body"]
    assert V.shape[1] == 3 and F.shape[1] == 3
    doc = json.loads((tmp_path / "o" / "verify.json").read_text())
    assert doc["inputs"]["body"] == str(body)
    r = run("verify", g, "-o", tmp_path / "o2", "--max-steps", 0)
    assert r.exit_code == 2 and not (tmp_path / "o2").exists()
    r = run("verify", g, "-o", tmp_path / "o2", "--rest", "nope")
    assert r.exit_code == 2 and not (tmp_path / "o2").exists()


@pytest.mark.parametrize(
    ("where", "message"),
    [("around", "% of the garment's drape lies inside the body"), ("away", "do not overlap")],
)
def test_a_body_that_is_not_worn_inside_the_garment_is_exit_2(tmp_path, fake_engine, where,
                                                              message):  # fmt: skip
    """A cube body around the whole garment (its units or frame wrong) or beside it: exit 2
    naming the body file, before any re-drape, nothing written; adjust the same."""
    import trimesh

    g = small_sleeve(tmp_path / "s.obj")
    cube = trimesh.creation.box(extents=[500.0, 500.0, 500.0])
    if where == "away":
        cube.apply_translation([2000.0, 0.0, 0.0])
    body = tmp_path / "cube.obj"
    cube.export(body)
    cm = ["--drape-units", "cm", "--pattern-units", "cm"]  # (no size check against the body)
    r = run("verify", g, "--body", body, *cm, "-o", tmp_path / "o")
    assert r.exit_code == 2, r.output
    assert message in r.output and "cube.obj" in r.output and "--body-units" in r.output
    assert not (tmp_path / "o").exists() and fake_engine == []
    rec = tmp_path / "r.yaml"
    rec.write_text(WIDER)
    r = run("adjust", g, rec, "--body", body, *cm, "-o", tmp_path / "a")
    assert r.exit_code == 2, r.output
    assert message in r.output and not (tmp_path / "a").exists()
    r = run("verify", g, "--body", body, "-o", tmp_path / "o")  # read in cm by default
    assert r.exit_code == 2 and "times its body's size" in r.output, r.output


@pytest.mark.slow
def test_write_body_writes_the_body_used(tmp_path, fake_engine, picture):
    """--write-body: OUT/body.obj is the body the re-drapes collided with, in the drape
    file's units (the garment's are cm here), listed in the outputs."""
    import trimesh

    g = small_sleeve(tmp_path / "s.obj")
    arm = trimesh.creation.cylinder(radius=2.0, height=60.0)
    body = tmp_path / "arm.obj"
    arm.export(body)
    r = run("verify", g, "--body", body, "--write-body", "-o", tmp_path / "o", "-q")
    assert r.exit_code == 0, r.output
    doc = json.loads((tmp_path / "o" / "verify.json").read_text())
    assert "body.obj" in doc["outputs"]
    back = trimesh.load(tmp_path / "o" / "body.obj", process=False)
    np.testing.assert_allclose(back.vertices, fake_engine[-1]["body"][0], atol=1e-6)
    np.testing.assert_allclose(back.bounds, arm.bounds, atol=1e-6)
    rec = tmp_path / "r.yaml"
    rec.write_text(WIDER)
    mm = tmp_path / "arm_mm.obj"
    arm.copy().apply_scale(10.0).export(mm)
    r = run("adjust", g, rec, "--body", mm, "--body-units", "mm", "--write-body", "-o",
            tmp_path / "a", "--formats", "obj", "-q")  # fmt: skip
    assert r.exit_code == 0, r.output
    back = trimesh.load(tmp_path / "a" / "body.obj", process=False)
    np.testing.assert_allclose(back.bounds, arm.bounds, atol=1e-6)  # read in mm, written in cm


def test_verify_turns_a_z_up_garment_y_up_for_the_engine(tmp_path, fake_engine, picture):
    """The engine's gravity is along -y: a z-up garment is turned for the simulation and
    its settled drapes turned back (the fake's drop along -y is a drop along -z)."""
    from dataclasses import replace

    from ptailor.formats.garment import load_garment

    g = lantern_sleeve(n_around=12, n_sleeve=3, n_cuff=2)
    R = np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]])  # y -> z, z -> -y
    path = tmp_path / "zup.obj"
    write_garment(path, replace(g, V3=g.V3 @ R.T))
    r = run("verify", path, "--up", "z", "--front", "-y", "-o", tmp_path / "o", "-q")
    assert r.exit_code == 0, r.output
    (call,) = fake_engine
    V3 = load_garment(path, weld="off").garment.V3
    assert np.allclose(np.sort(call["V3"][:, 1]), np.sort(V3[:, 2]), atol=1e-6)
    ours = load_garment(tmp_path / "o" / "verify_ours.obj", weld="off").garment
    assert np.allclose(ours.V3, V3 - [0, 0, 0.1], atol=1e-5)


def test_an_estimated_pattern_scale_is_the_originals(tmp_path, fake_engine, picture):
    """--pattern-units auto: the adjusted garment's pattern is read at the scale estimated
    for its original (it was written in the original's pattern units)."""
    from dataclasses import replace

    from ptailor.formats.garment import load_garment

    g = lantern_sleeve(n_around=12, n_sleeve=3, n_cuff=2)
    k = 1.0 / 60.0  # a [0, 1] atlas
    orig = tmp_path / "atlas.obj"
    write_garment(orig, replace(g, V2=g.V2 * k))
    rec = tmp_path / "r.yaml"
    rec.write_text(WIDER)
    auto = ["--pattern-units", "auto"]
    r = run("adjust", orig, rec, "-o", tmp_path / "adj", "--formats", "obj", "-q", *auto)
    assert r.exit_code == 0, r.output
    garment = tmp_path / "adj" / "garment.obj"
    r = run("verify", garment, "--original", orig, "-o", tmp_path / "o", "-q", *auto)
    assert r.exit_code == 0, r.output
    (call,) = fake_engine
    scale = load_garment(orig, pattern_units="auto").pattern_scale
    text = garment.read_text().splitlines()
    written = np.array([ln.split()[1:3] for ln in text if ln.startswith("vt ")], dtype=float)
    assert np.allclose(call["patterns"]["ours"], written * scale, rtol=1e-9)


def test_verify_names_a_missing_garment(tmp_path, fake_engine):
    r = run("verify", tmp_path / "missing.obj", "-o", tmp_path / "o")
    assert r.exit_code == 2 and "missing.obj" in r.output
    assert not (tmp_path / "o").exists()


# --------------------------------------------------------------------------- adjust --verify


@pytest.mark.slow
def test_adjust_verify_adds_the_section_and_the_files(tmp_path, fake_engine, picture):
    g = small_sleeve(tmp_path / "s.obj")
    rec = tmp_path / "r.yaml"
    rec.write_text(WIDER)
    out = tmp_path / "o"
    args = ["adjust", g, rec, "-o", out, "--formats", "obj", "--verify", "-q"]
    r = run(*args, "--verify-rest", "pattern", "--verify-max-steps", 7, "--verify-null-p95", "1in")
    assert r.exit_code == 0, r.output
    report = json.loads((out / "report.json").read_text())
    assert report["verify"]["rest"] == "pattern"
    assert report["verify"]["ours"]["panels"]["sleeve"]["displacement"]["p95"] == 0.4
    assert set(report["outputs"]) == {"report.json", "garment.obj", *VERIFY_FILES}
    assert {p.name for p in out.iterdir()} == {".ptailor", *report["outputs"]}
    assert "verify" in report["timing_s"]
    (call,) = fake_engine
    assert call["settings"].max_steps == 7 and call["null_limits"] == pytest.approx((None, 2.54))
    assert sorted(call["names"]) == sorted(p["name"] for p in report["panels"])
    # --no-baseline: the baseline is flattened for the check all the same
    r = run(*args[:-1], "--no-baseline")  # (not quiet: the summary names the check)
    assert r.exit_code == 0, r.output
    assert "re-drape: fake 0.0 on cpu" in r.output and "baseline  stretch p95 1.300" in r.output
    base = fake_engine[-1]["patterns"]["baseline"]
    assert np.all(np.isfinite(base))
    assert not np.allclose(base, fake_engine[-1]["patterns"]["ours"])


# --------------------------------------------------------------------------- gates, records


def report_with(stretch: float | None, displacement: float | None, *, section: bool = True):
    rep = {"units": {"computation": "cm"}, "panels": [], "seams": []}
    if section:
        stats = panel_stats(stretch if stretch is not None else 1.0, displacement or 0.0)
        if stretch is None:
            del stats["stretch"]
        if displacement is None:
            del stats["displacement"]
        rep["verify"] = {"ours": {"panels": {"cuff": stats, "sleeve": panel_stats(1.0, 0.1)}}}
    return rep


def test_verify_gates_read_the_report_strictly():
    gates = Gates(max_verify_stretch=1.05, max_verify_displacement=1.0)
    assert gates.verify_gates and not Gates().verify_gates
    assert gate_failures(report_with(1.04, 0.9), gates) == []
    probs = gate_failures(report_with(1.2, 1.5), gates)
    assert probs == [
        "cuff: re-drape stretch p95 1.2 > 1.05",
        "cuff: re-drape displacement p95 1.5 > 1 cm",
    ]
    # strict: no section, or a number missing, fails
    probs = gate_failures(report_with(None, None, section=False), gates)
    assert len(probs) == 2 and all("verify.ours.panels" in p for p in probs)
    assert "--max-verify-stretch" in probs[0] and "--max-verify-displacement" in probs[1]
    probs = gate_failures(report_with(None, 0.2), Gates(max_verify_stretch=2.0))
    assert probs == ["cuff: re-drape stretch p95 missing from the report"]
    # without verify gates the section is not needed
    assert gate_failures(report_with(None, None, section=False), Gates()) == []


def test_records_carry_the_verify_numbers():
    assert RECORD_KEYS.index("verify_stretch_p95") < RECORD_KEYS.index("warnings")
    nums = key_numbers(report_with(1.2, 1.5))
    assert nums["verify_stretch_p95"] == 1.2 and nums["verify_displacement_p95"] == 1.5
    nums = key_numbers(report_with(None, None, section=False))
    assert nums["verify_stretch_p95"] is None and nums["verify_displacement_p95"] is None


@pytest.mark.slow
def test_batch_verify_gates_and_records(tmp_path, fake_engine, picture):
    g = small_sleeve(tmp_path / "s.obj")
    rec = tmp_path / "r.yaml"
    rec.write_text(WIDER)
    log = tmp_path / "log.jsonl"
    base = ["batch", rec, g, "-j", 1, "--formats", "obj", "--no-baseline", "--log", log, "-q"]
    r = run(*base, "-o", tmp_path / "a", "--verify", "--max-verify-stretch", 1.01)
    assert r.exit_code == 1, r.output
    (record,) = [json.loads(x) for x in log.read_text().splitlines()]
    assert record["failure"] == "gate" and "re-drape stretch p95 1.02 > 1.01" in record["reason"]
    assert record["verify_stretch_p95"] == 1.02 and record["verify_displacement_p95"] == 0.4
    assert not (tmp_path / "a" / "s").exists()
    r = run(*base, "-o", tmp_path / "b", "--verify", "--max-verify-displacement", 0.5)
    assert r.exit_code == 0, r.output
    (record,) = [json.loads(x) for x in log.read_text().splitlines()]
    assert record["status"] == "ok" and record["verify_displacement_p95"] == 0.4
    assert {p.name for p in (tmp_path / "b" / "s").iterdir()} >= VERIFY_FILES
    # the stamp holds the verify options: without --verify the garment is redone
    r = run(*base, "-o", tmp_path / "b")
    assert r.exit_code == 0, r.output
    (record,) = [json.loads(x) for x in log.read_text().splitlines()]
    assert record["status"] == "ok" and record["verify_stretch_p95"] is None
    # a verify gate without --verify is a usage mistake
    r = run(*base, "-o", tmp_path / "c", "--max-verify-stretch", 1.1)
    assert r.exit_code == 2 and "need --verify" in r.output


# --------------------------------------------------------------------------- the real engine


@pytest.mark.slow
def test_real_engine_adjust_and_verify(tmp_path):
    """A small lantern sleeve widened 1.2, re-drapes capped at a few steps: the commands
    run end to end on the installed engine."""
    pytest.importorskip("newton")
    g = small_sleeve(tmp_path / "s.obj")
    rec = tmp_path / "r.yaml"
    rec.write_text(WIDER)
    out = tmp_path / "o"
    r = run("adjust", g, rec, "-o", out, "--formats", "obj", "--verify", "--verify-max-steps", 20)
    assert r.exit_code == 0, r.output
    report = json.loads((out / "report.json").read_text())
    sec = report["verify"]
    assert sec["device"] in ("cpu", "cuda:0") and "newton" in sec["engine"]
    for kind in ("ours", "baseline", "original"):
        assert sec[kind]["steps"] <= 20
        assert set(sec[kind]["panels"]) == {"sleeve", "cuff"}
    assert set(report["outputs"]) >= VERIFY_FILES
    r = run("verify", out / "garment.obj", "--original", g, "-o", tmp_path / "v", "--max-steps", 20)
    assert r.exit_code == 0, r.output
    doc = json.loads((tmp_path / "v" / "verify.json").read_text())
    assert set(doc["verify"]["ours"]["panels"]) == {"sleeve", "cuff"}


@pytest.mark.slow
def test_tee6_on_its_own_body_settles_within_minutes(tmp_path):
    """The issue's acceptance: tee6 with one sleeve 1.1 around; ``--body auto --write-body``
    writes the fitted body (GarmentCode's mean body decimated to 7,002 vertices, scaled and
    placed) in the garment's own frame and units (1/300 m); ``verify`` with that body as a
    user's file (``--body body.obj --body-units 0.3333cm``) runs its three re-drapes well
    within 5 minutes (it once ran 14 minutes without a result), the body shown and recorded;
    with the null test and the verdict."""
    import time

    pytest.importorskip("newton")
    from tests.conftest import real_path

    tee = real_path("tee6")
    units = ["--pattern-units", "0.3333cm", "--drape-units", "0.3333cm"]
    rec = tmp_path / "r.yaml"
    rec.write_text(
        "units: cm\nsteps: [{op: scale, region: {panels: [sleeve_left]}, direction: around, "
        "axis: auto, factor: 1.1}]\n"
    )
    out = tmp_path / "a"
    r = run("adjust", tee, rec, *units, "--body", "auto", "--write-body", "--formats", "obj",
            "--verify", "--verify-max-steps", 1, "-o", out, "-q")  # fmt: skip
    assert r.exit_code == 0, r.output
    report = json.loads((out / "report.json").read_text())
    fit = report["body_fit"]
    assert fit["pose"] == "a-pose" and fit["anchor"] == "neckline"  # posed to the sleeves
    assert all(a["arm_abduction_deg"] > 80.0 for a in fit["arms"].values())  # a T-pose tee
    body = out / "body.obj"
    assert sum(1 for ln in body.read_text().splitlines() if ln.startswith("v ")) == 7002
    t0 = time.perf_counter()
    r = run("verify", out / "garment.obj", "--original", tee, *units, "--body", body,
            "--body-units", "0.3333cm", "-o", tmp_path / "v", "-q")  # fmt: skip
    wall = time.perf_counter() - t0
    assert r.exit_code == 0, r.output
    sec = json.loads((tmp_path / "v" / "verify.json").read_text())["verify"]
    # settled is speed and displacement over a window (issue 46): the null re-drape settles;
    # ours and the baseline stop at the cap creeping about 1 mm per second (1.1 and 1.4 mm
    # in the last 100 steps against 1 mm; the sleeves on a body that is not posed), and say so
    assert sec["original"]["settled"], sec["original"]["settle"]
    for kind in ("ours", "baseline"):
        R = sec[kind]
        assert R["settle"]["why"].startswith("settled" if R["settled"] else "not settled")
        assert R["settle"]["move_p95"] < 2 * R["settle"]["move_limit"], R["settle"]
    # (this body, scaled and placed, fails the null test: 2.74 cm mean, 4.97 p95)
    assert (sec["verdict"]["result"] == "inconclusive") == (not sec["null"]["holds"])
    assert wall < 300.0
    ours = max(p["stretch"]["p95"] for p in sec["ours"]["panels"].values())
    base = max(p["stretch"]["p95"] for p in sec["baseline"]["panels"].values())
    assert ours < base  # the baseline's neckline is stretched over the body (1.043 vs 1.057)
