"""The command line: outputs, exit codes and one-line errors that name the file."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from ptailor.cli.main import cli
from ptailor.samples.obj_text import sample_obj_text

WIDER = "steps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.2}]\n"


@pytest.fixture
def runner():
    return CliRunner()


@pytest.fixture
def sleeve(tmp_path) -> Path:
    p = tmp_path / "sleeve.obj"
    p.write_text(sample_obj_text("lantern_sleeve"))
    return p


@pytest.fixture
def recipe(tmp_path) -> Path:
    p = tmp_path / "wider.yaml"
    p.write_text(WIDER)
    return p


def run(runner, *args, input=None):
    return runner.invoke(cli, [str(a) for a in args], input=input, catch_exceptions=False)


def test_help_lists_commands(runner):
    r = run(runner, "--help")
    assert r.exit_code == 0
    for cmd in ("adjust", "inspect", "demo"):
        assert cmd in r.output


@pytest.mark.slow
def test_adjust_writes_outputs_and_can_adjust_its_own_output(runner, sleeve, recipe, tmp_path):
    out = tmp_path / "out"
    r = run(runner, "adjust", sleeve, recipe, "-o", out)
    assert r.exit_code == 0, r.output
    assert sorted(p.name for p in out.iterdir()) == [
        ".ptailor",
        "garment.obj",
        "pattern.dxf",
        "pattern.svg",
        "preview.png",
        "report.json",
    ]
    rep = json.loads((out / "report.json").read_text())
    cuff = next(p for p in rep["panels"] if p["name"] == "cuff")
    assert cuff["size_after"] == pytest.approx([48.0, 8.0], rel=1e-6)
    assert cuff["baseline_size_after"][0] == pytest.approx(33.6, rel=1e-3)
    assert rep["inputs"]["garment"]["sha256"] and rep["method"] == "scale-preserving"
    assert set(rep["timing_s"]) == {"load", "edit", "flatten", "baseline", "measures", "write"}
    assert "cuff" in r.output and "sleeve" in r.output
    # the output is a garment again: an identity recipe returns it unchanged
    ident = tmp_path / "id.yaml"
    ident.write_text("steps: []\n")
    out2 = tmp_path / "out2"
    r2 = run(runner, "adjust", out / "garment.obj", ident, "-o", out2)
    assert r2.exit_code == 0, r2.output
    rep2 = json.loads((out2 / "report.json").read_text())
    for p in rep2["panels"]:
        assert p["size_after"] == pytest.approx(p["size_before"], rel=1e-7)
    assert [p["name"] for p in rep2["panels"]] == ["sleeve", "cuff"]


@pytest.mark.slow
def test_outputs_are_deterministic(runner, sleeve, recipe, tmp_path):
    for o in ("a", "b"):
        assert run(runner, "adjust", sleeve, recipe, "-o", tmp_path / o).exit_code == 0
    for name in ("garment.obj", "pattern.svg"):
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes()
    ra, rb = (json.loads((tmp_path / o / "report.json").read_text()) for o in "ab")
    ra.pop("timing_s"), rb.pop("timing_s")
    assert ra == rb


def test_report_has_no_negative_zero(runner, sleeve, recipe, tmp_path):
    """A number that rounds to zero is written 0.0, never -0.0 (the sleeve's seams meet
    their ratios to rounding, on both sides of zero)."""
    import math

    assert run(runner, "adjust", sleeve, recipe, "-o", tmp_path / "o").exit_code == 0
    text = (tmp_path / "o" / "report.json").read_text()
    zeros = []

    def walk(x):
        if isinstance(x, dict):
            for v in x.values():
                walk(v)
        elif isinstance(x, list):
            for v in x:
                walk(v)
        elif isinstance(x, float) and x == 0.0:
            zeros.append(math.copysign(1.0, x))

    walk(json.loads(text))
    assert zeros and min(zeros) > 0  # some zeros, none negative
    assert "-0.0" not in text


@pytest.mark.slow
def test_method_uniform_override_and_json(runner, sleeve, recipe, tmp_path):
    r = run(runner, "adjust", sleeve, recipe, "-o", tmp_path / "o", "--method", "uniform", "--json")
    assert r.exit_code == 0
    rep = json.loads(r.output)
    assert rep["method"] == "uniform"
    cuff = next(p for p in rep["panels"] if p["name"] == "cuff")
    assert cuff["size_after"][0] == pytest.approx(33.6, rel=1e-3)


@pytest.mark.slow
def test_recipe_from_stdin(runner, sleeve, tmp_path):
    r = run(runner, "adjust", sleeve, "-", "-o", tmp_path / "o", input=WIDER)
    assert r.exit_code == 0, r.output


@pytest.mark.slow
def test_drape_from_second_file(runner, tmp_path):
    from ptailor.samples import lantern_sleeve

    g = lantern_sleeve()
    pat = tmp_path / "pattern.obj"
    pat.write_text(
        "".join(f"v {x} {y} 0\n" for x, y in g.V2)
        + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in g.F2)
    )
    dr = tmp_path / "drape.obj"
    dr.write_text(
        "".join(f"v {x} {y} {z}\n" for x, y, z in g.V3)
        + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in g.F3)
    )
    rec = tmp_path / "r.yaml"
    rec.write_text(WIDER)
    r = run(runner, "adjust", pat, rec, "--drape", dr, "-o", tmp_path / "o", "--json")
    assert r.exit_code == 0, r.output
    widths = sorted(p["size_after"][0] for p in json.loads(r.output)["panels"])
    assert widths == pytest.approx([33.6, 48.0], rel=1e-6)


def test_inspect_lists_panels_seams_openings(runner, sleeve):
    r = run(runner, "inspect", sleeve)
    assert r.exit_code == 0
    assert "sleeve" in r.output and "cuff" in r.output and "openings:" in r.output
    info = json.loads(run(runner, "inspect", sleeve, "--json").output)
    assert len(info["panels"]) == 2 and len(info["seams"]) == 3
    ring = next(s for s in info["seams"] if set(s["panels"]) == {"sleeve", "cuff"})
    assert sorted(ring["lengths"]) == pytest.approx([28.0, 40.0])
    assert len(info["openings"]) == 2


@pytest.mark.slow
def test_demo(runner, tmp_path):
    out = tmp_path / "demo"
    r = run(runner, "demo", out)
    assert r.exit_code == 0, r.output
    assert (out / "sample.obj").is_file() and (out / "report.json").is_file()
    assert "uniform" in r.output
    assert run(runner, "demo", out).exit_code == 0  # re-running replaces its own output


# ---- bad input: exit 2, one line naming the file, no output folder ------------------------


def _named_samples() -> dict[str, str]:
    """Bundled recipe -> the sample its ``# sample: NAME`` line names (lantern_sleeve when none)."""
    from importlib import resources

    out = {}
    for p in (resources.files("ptailor") / "recipes").iterdir():
        if p.name.endswith(".yaml"):
            lines = [ln for ln in p.read_text().splitlines() if ln.startswith("# sample:")]
            out[p.name[:-5]] = lines[0].split(":", 1)[1].strip() if lines else "lantern_sleeve"
    return out


def test_demo_offers_every_sample_and_every_sample_a_recipe_names():
    from ptailor.cli.demo import DEFAULT_RECIPES, SAMPLE_NAMES
    from ptailor.recipe.bundled import bundled_recipe
    from ptailor.samples import SAMPLES

    assert set(SAMPLE_NAMES) == set(SAMPLES)
    assert set(_named_samples().values()) <= set(SAMPLE_NAMES)
    for sample, name in DEFAULT_RECIPES.items():  # each default is bundled and meant for it
        assert bundled_recipe(name)
        assert _named_samples()[name] in (sample, "lantern_sleeve")


def test_demo_runs_a_bundled_recipe_on_the_sample_it_names(runner, tmp_path):
    out = tmp_path / "cylinder"  # the smallest sample (the bodice's run is a golden one)
    r = run(runner, "demo", out, "--sample", "cylinder")
    assert r.exit_code == 0, r.output
    assert "sample: cylinder, recipe: recipes/wider-around.yaml" in r.output
    assert (out / "report.json").is_file()


def obj_with(tmp_path, text, name="bad.obj"):
    p = tmp_path / name
    p.write_text(text)
    return p


SQUARE = "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (None, "no such file"),
        ("hello, world\n", "not an OBJ"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "no texture coordinates"),
        ("v 0 0 nan\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n", "NaN"),
        ("v 0 0 0\nv 1 0 0\nv 2 0 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n", "zero-area"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 2 0\nf 1/1 2/2 3/3\n", "zero-area"),
        (SQUARE + "f 1/1 2/2 3/3\nf 1/1 2/2 9/3\n", "out of range"),
        (SQUARE + "v 0 1 0\nf 1/1 2/2 3/3\nf 1/1 3/2 4/3\n", "different faces"),
    ],
)
def test_bad_garment(runner, tmp_path, recipe, content, message):
    path = tmp_path / "missing.obj" if content is None else obj_with(tmp_path, content)
    out = tmp_path / "out"
    r = runner.invoke(cli, ["adjust", str(path), str(recipe), "-o", str(out)])
    assert r.exit_code == 2
    err = r.stderr if hasattr(r, "stderr") else r.output
    assert message in err and str(path) in err
    assert len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_drape_with_different_faces(runner, tmp_path, recipe):
    pat = obj_with(tmp_path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "p.obj")
    dr = obj_with(tmp_path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 1\nf 1 2 3\nf 2 4 3\n", "d.obj")
    r = runner.invoke(
        cli, ["adjust", str(pat), str(recipe), "--drape", str(dr), "-o", str(tmp_path / "o")]
    )
    assert r.exit_code == 2 and "different faces" in r.output and str(dr) in r.output
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize(
    ("text", "messages"),
    [
        ("steps: [{op: twirl}]", ["steps[1].op: unknown op 'twirl'"]),
        (
            "steps: [{op: scale, factor: -1, direction: sideways, colour: red}]",
            ["steps[1].factor", "steps[1].direction", "unknown key 'colour'"],
        ),
        (
            "steps: [{op: scale}]\nflatten: {method: magic}\nextra: 1",
            ["needs exactly one of 'factor' or 'measure'", "flatten.method", "'extra'"],
        ),
        ("steps: [{op: scale, factor: 2\n", ["YAML syntax error"]),
    ],
)
def test_bad_recipe_reports_everything_before_reading_garment(runner, tmp_path, text, messages):
    rec = tmp_path / "r.yaml"
    rec.write_text(text)
    out = tmp_path / "out"
    # the garment does not exist: the recipe must fail first
    r = runner.invoke(cli, ["adjust", str(tmp_path / "nope.obj"), str(rec), "-o", str(out)])
    assert r.exit_code == 2
    for m in messages:
        assert m in r.output
    assert str(rec) in r.output and "nope.obj" not in r.output
    assert not out.exists()


def test_unknown_panel_lists_names(runner, sleeve, tmp_path):
    rec = tmp_path / "r.yaml"
    rec.write_text("steps: [{op: scale, region: {panels: [collar]}, factor: 1.1}]")
    r = runner.invoke(cli, ["adjust", str(sleeve), str(rec), "-o", str(tmp_path / "o")])
    assert r.exit_code == 2 and "collar" in r.output and "sleeve, cuff" in r.output
    assert not (tmp_path / "o").exists()


def test_refuses_output_over_input_or_foreign_folder(runner, sleeve, recipe, tmp_path):
    r = runner.invoke(cli, ["adjust", str(sleeve), str(recipe), "-o", str(tmp_path)])
    assert r.exit_code == 2 and "input" in r.output
    foreign = tmp_path / "foreign"
    foreign.mkdir()
    (foreign / "keep.txt").write_text("mine")
    r = runner.invoke(cli, ["adjust", str(sleeve), str(recipe), "-o", str(foreign)])
    assert r.exit_code == 2 and (foreign / "keep.txt").read_text() == "mine"


def test_failure_midway_leaves_no_partial_output(runner, sleeve, recipe, tmp_path, monkeypatch):
    import ptailor.run.garment

    def boom(*a, **k):
        raise RuntimeError("disk full")

    monkeypatch.setattr(ptailor.run.garment, "write_outputs", boom)
    r = runner.invoke(
        cli, ["adjust", str(sleeve), str(recipe), "-o", str(tmp_path / "o")], catch_exceptions=False
    )
    assert r.exit_code == 1  # an internal error (issue 40: not the garment's)
    assert "internal error: RuntimeError: disk full" in r.stderr and "Traceback" not in r.stderr
    assert not (tmp_path / "o").exists()
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".o.")]


def test_pattern_units_auto_estimates_and_warns(runner, tmp_path, recipe):
    from ptailor.samples import cylinder

    g = cylinder()
    s = 1.0 / np.ptp(g.V2, axis=0).max()
    p = tmp_path / "atlas.obj"
    p.write_text(
        "".join(f"v {x} {y} {z}\n" for x, y, z in g.V3)
        + "".join(f"vt {x * s} {y * s}\n" for x, y in g.V2)
        + "".join(
            f"f {a + 1}/{d + 1} {b + 1}/{e + 1} {c + 1}/{f + 1}\n"
            for (a, b, c), (d, e, f) in zip(g.F3, g.F2, strict=True)
        )
    )
    r = run(runner, "adjust", p, recipe, "-o", tmp_path / "o", "--pattern-units", "auto", "--json")
    rep = json.loads(r.output)
    assert rep["units"]["pattern_scale_estimate"] == pytest.approx(1 / s, rel=1e-6)
    assert any("estimated" in w for w in rep["warnings"])


def test_one_blas_thread_unless_the_user_chose(monkeypatch):
    import os
    import sys

    from ptailor.cli.main import BLAS_THREAD_VARIABLES, one_blas_thread

    for var in BLAS_THREAD_VARIABLES:
        monkeypatch.delenv(var, raising=False)
    monkeypatch.delitem(sys.modules, "numpy")
    one_blas_thread()
    assert [os.environ[v] for v in BLAS_THREAD_VARIABLES] == ["1", "1", "1"]
    for var in BLAS_THREAD_VARIABLES:
        monkeypatch.delenv(var)
    monkeypatch.setenv("OMP_NUM_THREADS", "4")
    one_blas_thread()  # the user's choice stands, and nothing else is set
    assert [os.environ.get(v) for v in BLAS_THREAD_VARIABLES] == [None, "4", None]


@pytest.mark.slow  # a fresh interpreter importing the command and numpy: 0.9 s
def test_the_command_sets_one_blas_thread_before_numpy_loads(tmp_path):
    import os
    import subprocess
    import sys

    env = {k: v for k, v in os.environ.items() if not k.endswith("_NUM_THREADS")}
    code = (
        "import sys; from ptailor.cli.main import cli\n"
        "sys.argv = ['ptailor', 'validate', sys.argv[1]]\n"
        "try:\n    cli()\nexcept SystemExit:\n    pass\n"
        "import os; print(os.environ.get('OPENBLAS_NUM_THREADS'))"
    )
    recipe = tmp_path / "r.yaml"
    recipe.write_text("steps: []\n")
    out = subprocess.run([sys.executable, "-c", code, str(recipe)], env=env,
                         capture_output=True, text=True, check=True)  # fmt: skip
    assert out.stdout.strip().splitlines()[-1] == "1"


#: adjust's options that batch does not take, and batch's own: docs/batch.md ("Options")
#: says why. An option added to one command and not the other fails the test below until
#: it is listed here and there.
ADJUST_ONLY = {"--drape", "--edited-drape"}
BATCH_ONLY = {
    "--manifest",
    "-j",
    "--jobs",
    "--scheduler",
    "--timeout",
    "--force",
    "--log",
    "--html",
    "--max-area-change",
    "--max-boundary-deviation",
    "--max-intrinsic-error",
    "--max-seam-mismatch",
    "--max-verify-stretch",
    "--max-verify-displacement",
    "--max-spec-fit",
    "--fail-on-flips",
}


def _options(command) -> dict:
    """A command's options by each of their names (``-j`` and ``--jobs``)."""
    import click

    return {o: p for p in command.params if isinstance(p, click.Option) for o in p.opts}


def test_adjust_and_batch_differ_only_by_the_documented_options():
    """Issue 40: batch silently lacked ``--method`` and ``--intrinsic``. Batch takes every
    option of adjust but the documented few, each run option declared once for both."""
    import click

    from ptailor.cli.adjust import adjust
    from ptailor.cli.batch import batch
    from ptailor.cli.options import run_options

    a, b = _options(adjust), _options(batch)
    assert set(a) - set(b) == ADJUST_ONLY
    assert set(b) - set(a) == BATCH_ONLY
    docs = (Path(__file__).resolve().parents[1] / "docs" / "batch.md").read_text()
    section = docs.split("\n## Options\n")[1].split("\n## ")[0]
    for name in sorted(ADJUST_ONLY):
        assert f"`{name}`" in section, name
    for name in sorted(BATCH_ONLY):
        assert f"`{name}" in docs, name  # (`--max-area-change F` in the gates table)
    # the run's options are one declaration (run_options), the same in both commands
    probe = click.command()(run_options(lambda **run: None))
    names = {o for p in probe.params for o in p.opts}
    assert names <= set(a) & set(b)
    for name in names:
        assert a[name].to_info_dict() == b[name].to_info_dict(), name
