"""Run options: the garment's axes from the recipe or the command line, and a body mesh."""

from __future__ import annotations

import json

import numpy as np
import pytest
from click.testing import CliRunner

from ptailor.cli.main import cli
from ptailor.formats.obj import write_garment
from ptailor.model.garment import Garment
from ptailor.samples import cone_skirt


def rotated_skirt(tmp_path):
    """The cone skirt stored z-up, facing -y."""
    g = cone_skirt()
    R = np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]])  # y -> z, z -> -y
    p = tmp_path / "zup.obj"
    write_garment(
        p,
        Garment(
            V3=g.V3 @ R.T,
            F3=g.F3,
            V2=g.V2,
            F2=g.F2,
            face_group=g.face_group,
            group_names=g.group_names,
        ),
    )
    return p


@pytest.mark.slow
@pytest.mark.parametrize("where", ["recipe", "cli"])
def test_axes_from_recipe_or_command_line(tmp_path, where):
    p = rotated_skirt(tmp_path)
    rec = tmp_path / "r.yaml"
    head = "up: z\nfront: -y\n" if where == "recipe" else ""
    rec.write_text(head + "steps: [{op: shorten, opening: hem, by: 5}]\n")
    args = ["adjust", str(p), str(rec), "-o", str(tmp_path / "o"), "--json"]
    if where == "cli":
        args += ["--up", "z", "--front", "-y"]
    r = CliRunner().invoke(cli, args)
    assert r.exit_code == 0, r.output
    step = json.loads(r.output)["steps"][0]
    assert step["opening"] == "hem"
    assert step["achieved"]["3d"]["mean"] == pytest.approx(5.0, rel=1e-6)


def test_recipe_axes_are_validated(tmp_path):
    rec = tmp_path / "r.yaml"
    rec.write_text("up: q\nfront: y\nsteps: []\n")
    r = CliRunner().invoke(cli, ["adjust", "nope.obj", str(rec), "-o", str(tmp_path / "o")])
    assert r.exit_code == 2 and "up: expected one of" in r.output


@pytest.mark.slow
def test_body_option(tmp_path):
    import trimesh

    from ptailor.samples.obj_text import sample_obj_text

    src = tmp_path / "s.obj"
    src.write_text(sample_obj_text("cone_skirt"))
    body = tmp_path / "body.obj"
    trimesh.creation.icosphere(subdivisions=3, radius=20.0).export(body)
    rec = tmp_path / "r.yaml"
    rec.write_text("steps: [{op: extend, opening: hem, by: 3}]\n")
    r = CliRunner().invoke(
        cli,
        ["adjust", str(src), str(rec), "--body", str(body), "-o", str(tmp_path / "o"), "--json"],
    )
    assert r.exit_code == 0, r.output
    assert "body" in json.loads(r.output)["inputs"]
    bad = tmp_path / "bad.obj"
    bad.write_text("nothing here\n")
    r = CliRunner().invoke(
        cli, ["adjust", str(src), str(rec), "--body", str(bad), "-o", str(tmp_path / "o2")]
    )
    assert r.exit_code == 2 and str(bad) in r.output
    assert not (tmp_path / "o2").exists()


_NUMERIC_BATCH_OPTIONS = (
    "--max-area-change",
    "--max-boundary-deviation",
    "--max-intrinsic-error",
    "--max-seam-mismatch",
    "--max-verify-stretch",
    "--max-verify-displacement",
    "--timeout",
)


@pytest.mark.parametrize("option", _NUMERIC_BATCH_OPTIONS)
@pytest.mark.parametrize("value", ["nan", "NaN", "inf", "-inf", "1e400"])
def test_numeric_options_that_are_not_finite_numbers_are_refused(tmp_path, option, value):
    """Issue 22: a gate of ``nan`` never fired (exit 0), ``--timeout nan`` failed every
    garment and ``--timeout inf`` was an internal error. Each is exit 2 naming the option,
    before any file is read."""
    g = tmp_path / "g.obj"
    write_garment(g, cone_skirt(n_around=8, n_along=3))
    rec = tmp_path / "r.yaml"
    rec.write_text("steps: [{op: scale, factor: 1.1}]\n")
    out = tmp_path / "out"
    args = ["batch", str(rec), str(g), "-o", str(out), option, value]
    r = CliRunner().invoke(cli, args)
    assert r.exit_code == 2, r.output
    assert option in r.output
    assert not out.exists()


def test_the_timeout_has_a_bound():
    from ptailor import tolerances as tol

    r = CliRunner().invoke(cli, ["batch", "r.yaml", "g.obj", "-o", "o", "--timeout", "1e12"])
    assert r.exit_code == 2 and "--timeout" in r.output
    assert tol.BATCH_TIMEOUT_MAX_S >= 86400  # a day at least


def test_any_number_given_to_a_gate_is_refused_unless_finite_and_in_range(tmp_path):
    """Issue 22, as a property: a gate takes exactly the finite numbers >= 0."""
    hypothesis = pytest.importorskip("hypothesis")
    from hypothesis import given
    from hypothesis import strategies as st

    rec = tmp_path / "r.yaml"
    rec.write_text("steps: [{op: scale, factor: 1.1}]\n")
    missing = tmp_path / "none" / "g.obj"  # exit 2 later, for a different reason

    @given(
        st.sampled_from(_NUMERIC_BATCH_OPTIONS[:-1]),
        st.floats(allow_nan=True, allow_infinity=True),
    )
    @hypothesis.settings(max_examples=60, deadline=None)
    def check(option, x):
        args = ["batch", str(rec), str(missing), "-o", str(tmp_path / "o"), option, repr(x)]
        r = CliRunner().invoke(cli, args)
        bad = not (np.isfinite(x) and x >= 0)
        assert (option in r.output and "Invalid value" in r.output) == bad, (x, r.output)

    check()


@pytest.mark.parametrize(
    "field, value, option",
    [
        ("formats", ("obj", "stl"), "--formats"),
        ("formats", "obj", "--formats"),
        ("seam_allowance", -1.0, "--seam-allowance"),
        ("seam_allowance", float("nan"), "--seam-allowance"),
        ("pattern_units", "furlong", "--pattern-units"),
        ("drape_units", "0cm", "--drape-units"),
        ("body_units", "parsec", "--body-units"),
        ("weld", "sometimes", "--weld"),
        ("method", "magic", "--method"),
        ("intrinsic", "guess", "--intrinsic"),
        ("up", "w", "--up"),
        ("dxf_units", "ft", "--dxf-units"),
        ("verify_rest", "sleep", "--rest"),
        ("verify_max_steps", 0, "--max-steps"),
        ("verify_max_steps", True, "--max-steps"),
        ("verify_null_mean", 0.0, "--null-mean"),
        ("verify_null_p95", float("inf"), "--null-p95"),
        ("verify_null_p95", "2cm", "--null-p95"),
    ],
)
def test_run_options_are_checked_where_they_are_made(field, value, option):
    """One place checks the options (the record's constructor), for every command and for a
    manifest row's overrides (``replace`` constructs again)."""
    from dataclasses import replace

    from ptailor.errors import PtailorError
    from ptailor.run.options import RunOptions

    with pytest.raises(PtailorError, match=option):
        RunOptions(**{field: value})
    with pytest.raises(PtailorError, match=option):
        replace(RunOptions(), **{field: value})


#: one value per RunOptions field, as the command line gives it, different from the default
_RUN_ARGS = {
    "pattern_units": ("--pattern-units", "mm"),
    "drape_units": ("--drape-units", "mm"),
    "weld": ("--weld", "off"),
    "method": ("--method", "uniform"),
    "intrinsic": ("--intrinsic", "paper"),
    "baseline": ("--no-baseline",),
    "formats": ("--formats", "obj,svg"),
    "up": ("--up", "z"),
    "front": ("--front", "y"),
    "body": ("--body", "body.obj"),
    "body_units": ("--body-units", "mm"),
    "write_body": ("--write-body",),
    "size": ("--size", "M"),
    "dxf_units": ("--dxf-units", "mm"),
    "seam_allowance": ("--seam-allowance", "1cm"),
    "seam_allowances": ("--seam-allowance", "hem=3cm"),
    "verify": ("--verify",),
    "verify_rest": ("--verify-rest", "pattern"),
    "verify_max_steps": ("--verify-max-steps", "10"),
    "verify_null_mean": ("--verify-null-mean", "2cm"),
    "verify_null_p95": ("--verify-null-p95", "5"),
    "spec": ("--spec", "auto"),
    "spec_units": ("--spec-units", "0.3333cm"),
    "show_measures": ("--show-measures",),
    "sizes": ("--sizes", "all"),
    "paper": ("--paper", "Letter"),
}


#: RunOptions fields that name one garment's own file: an option of ``adjust`` only, a
#: manifest's column for ``batch`` (as ``--drape`` is), built with the command's ``fixed``
_GARMENT_FILES = {"edited_drape": "--edited-drape"}


def test_garment_files_are_adjusts_options_and_manifest_columns():
    from ptailor.batch.manifest import MANIFEST_COLUMNS
    from ptailor.cli.adjust import adjust
    from ptailor.cli.options import build_run_options

    opts = {o for p in adjust.params for o in getattr(p, "opts", ())}
    for field, option in _GARMENT_FILES.items():
        assert option in opts and field in MANIFEST_COLUMNS
        assert getattr(build_run_options({}, **{field: "x.obj"}), field) == "x.obj"


def _run_probe():
    import click

    from ptailor.cli.options import run_options

    return click.command()(run_options(lambda **run: None))


def test_one_builder_makes_every_run_option_from_the_command_line():
    """Every RunOptions field is an option of adjust and batch (both take ``run_options``),
    and the builder turns the options' defaults into RunOptions' defaults."""
    from dataclasses import fields

    from ptailor.cli.options import build_run_options
    from ptailor.run.options import RunOptions

    assert set(_RUN_ARGS) | set(_GARMENT_FILES) == {f.name for f in fields(RunOptions)}
    probe = _run_probe()
    default = RunOptions()
    assert build_run_options(probe.make_context("probe", []).params) == default
    for field, args in _RUN_ARGS.items():
        built = build_run_options(probe.make_context("probe", list(args)).params, units="mm")
        changed = [
            f.name for f in fields(default) if getattr(built, f.name) != getattr(default, f.name)
        ]
        assert changed == [field]
    seam = probe.make_context("probe", ["--seam-allowance", "1cm"]).params
    assert build_run_options(seam, units="mm").seam_allowance == pytest.approx(10.0)
    args = ["--seam-allowance", "hem=3cm", "--seam-allowance", "1cm", "--seam-allowance", "a=2"]
    both = build_run_options(probe.make_context("probe", args).params, units="mm")
    assert (both.seam_allowance, both.seam_allowances) == (10.0, (("hem", 30.0), ("a", 2.0)))
    assert build_run_options({"formats": "obj,svg"}).formats == ("obj", "svg")
    null = probe.make_context("probe", ["--verify-null-mean", "5mm", "--verify-null-p95", "3"])
    built = build_run_options(null.params, units="mm")  # lengths in cm, a bare one in mm
    assert (built.verify_null_mean, built.verify_null_p95) == pytest.approx((0.5, 0.3))


def test_the_builder_takes_verifys_names_and_refuses_any_other():
    from ptailor.cli.options import build_run_options
    from ptailor.errors import PtailorError

    built = build_run_options({"rest": "pattern", "max_steps": 5, "null_mean": "2",
                               "null_p95": "1in"}, verify=True)  # fmt: skip
    assert (built.verify, built.verify_rest, built.verify_max_steps) == (True, "pattern", 5)
    assert (built.verify_null_mean, built.verify_null_p95) == pytest.approx((2.0, 2.54))
    with pytest.raises(PtailorError, match="--null-mean: not a length"):
        build_run_options({"null_mean": "wide"})
    with pytest.raises(TypeError):
        build_run_options({"out": "o"})  # a command's own parameter
    with pytest.raises(PtailorError, match="--seam-allowance"):
        build_run_options({"seam_allowance": "wide"})
    for bad, said in [
        (("1cm", "2cm"), "a bare length given twice"),
        (("hem=1cm", "hem=2cm"), "hem given twice"),
        (("=1cm",), "needs a name"),
        (("hem=wide",), "--seam-allowance hem: not a length"),
        (("hem=-1",), "--seam-allowance hem: must be a length >= 0"),
    ]:
        with pytest.raises(PtailorError, match=said):
            build_run_options({"seam_allowance": bad})


def test_the_command_line_choices_are_run_options_own():
    import click

    from ptailor.run import options as run

    choices = {
        p.name: tuple(p.type.choices)
        for p in _run_probe().params
        if isinstance(p.type, click.Choice)
    }
    assert choices == {
        "up": run.AXES,
        "front": run.AXES,
        "method": run.METHODS,
        "intrinsic": run.INTRINSICS,
        "verify_rest": run.REST_MODES,
        "dxf_units": run.DXF_UNITS,
    }


@pytest.mark.slow
@pytest.mark.parametrize(
    "option, field, value",
    [("--method", "method", "uniform"), ("--intrinsic", "intrinsic", "paper")],
)
def test_batch_takes_the_method_options_as_adjust_does(tmp_path, option, field, value):
    """Issue 40: batch lacked ``--method`` and ``--intrinsic``. With either, a garment's
    report is adjust's with the same option (to its timing), and the option is stamped: a
    rerun without it redoes the garment."""
    from ptailor.samples import lantern_sleeve

    def run(*args):
        return CliRunner().invoke(cli, [str(a) for a in args], catch_exceptions=False)

    def read(path):
        return json.loads(path.read_text())

    g, recipe = tmp_path / "sleeve.obj", tmp_path / "wider.yaml"
    write_garment(g, lantern_sleeve(n_around=12, n_sleeve=6, n_cuff=2))
    recipe.write_text("steps: [{op: scale, region: all, direction: around, factor: 1.2}]\n")
    fast = ("--formats", "obj", "--no-baseline")
    alone, out, log = tmp_path / "alone", tmp_path / "out", tmp_path / "log.jsonl"
    assert run("adjust", g, recipe, "-o", alone, *fast, option, value).exit_code == 0
    args = ("batch", recipe, g, "-o", out, "-j", 1, "--log", log, *fast)
    assert run(*args, option, value).exit_code == 0
    want, got = read(alone / "report.json"), read(out / "sleeve" / "report.json")
    assert want[field] == value  # (the option took effect)
    want.pop("timing_s"), got.pop("timing_s")
    assert got == want
    assert read(out / "sleeve" / "batch.json")["options"][field] == value
    assert run(*args, option, value).exit_code == 0
    assert read(log)["status"] == "skipped"
    assert run(*args).exit_code == 0
    assert read(log)["status"] == "ok"
    assert read(out / "sleeve" / "report.json")[field] != value
