"""Errors by type (issue 40): a numeric failure of a solve is exit 2 naming the step, any
exception of no known kind is an internal error (exit 1, one line asking to report it, the
traceback only with ``--debug``), in ``adjust`` and in ``batch``'s records alike; nothing
is written in either case."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
from click.testing import CliRunner

from ptailor import __version__
from ptailor.cli.main import cli
from ptailor.edits import OPERATIONS
from ptailor.errors import NumericError, PtailorError
from ptailor.formats.obj import write_garment
from ptailor.samples import cylinder, lantern_sleeve

RECIPE = "steps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.2}]\n"
FAST = ("--formats", "obj", "--no-baseline")


@pytest.fixture
def garment(tmp_path) -> Path:
    p = tmp_path / "sleeve.obj"
    write_garment(p, lantern_sleeve(n_around=12, n_sleeve=6, n_cuff=2))
    return p


@pytest.fixture
def recipe(tmp_path) -> Path:
    p = tmp_path / "wider.yaml"
    p.write_text(RECIPE)
    return p


def adjust(garment: Path, recipe: Path, out: Path, *extra: str, debug: bool = False):
    head = ["--debug"] if debug else []
    args = [*head, "adjust", str(garment), str(recipe), "-o", str(out), *FAST, *extra]
    return CliRunner().invoke(cli, args, catch_exceptions=False)


def nothing_written(out: Path) -> None:
    assert not out.exists()
    assert not [p for p in out.parent.iterdir() if p.name.startswith(f".{out.name}.")]


def failing_step(monkeypatch, exc: BaseException) -> None:
    """The recipe's ``scale`` step raises ``exc``."""

    def boom(state, step, *, options):
        raise exc

    monkeypatch.setitem(OPERATIONS, "scale", replace(OPERATIONS["scale"], apply=boom))


def failing_flatten(monkeypatch, exc: BaseException) -> None:
    def boom(*a, **kw):
        raise exc

    monkeypatch.setattr("ptailor.pipeline.flatten", boom)


BUGS = [RuntimeError("boom"), NotImplementedError("not yet"), KeyError("panel"), ValueError("x")]


@pytest.mark.parametrize("exc", BUGS, ids=lambda e: type(e).__name__)
@pytest.mark.parametrize("where", ["edit", "flatten"])
def test_an_internal_error_is_exit_1_asking_to_report_it(
    garment, recipe, tmp_path, monkeypatch, exc, where
):
    """A RuntimeError (and its NotImplementedError) once was 'numeric failure', exit 2."""
    (failing_step if where == "edit" else failing_flatten)(monkeypatch, exc)
    out = tmp_path / "out"
    r = adjust(garment, recipe, out)
    assert r.exit_code == 1, r.output
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, lines
    line = lines[0]
    assert line.startswith(f"ptailor: internal error: {type(exc).__name__}: "), line
    assert f"a bug in ptailor {__version__}: please report it" in line
    assert "--debug" in line and "Traceback" not in r.output
    nothing_written(out)


@pytest.mark.parametrize("exc", BUGS[:3], ids=lambda e: type(e).__name__)
def test_debug_prints_the_traceback(garment, recipe, tmp_path, monkeypatch, exc):
    failing_step(monkeypatch, exc)
    out = tmp_path / "out"
    r = adjust(garment, recipe, out, debug=True)
    assert r.exit_code == 1, r.output
    assert r.stderr.startswith("Traceback (most recent call last):"), r.stderr
    assert "in boom" in r.stderr  # the frame that raised
    last = r.stderr.strip().splitlines()[-1]
    assert last.startswith("ptailor: internal error:") and "please report it" in last
    nothing_written(out)


def test_debug_from_the_environment(garment, recipe, tmp_path, monkeypatch):
    failing_step(monkeypatch, RuntimeError("boom"))
    monkeypatch.setenv("PTAILOR_DEBUG", "1")
    r = adjust(garment, recipe, tmp_path / "out")
    assert r.exit_code == 1 and "Traceback" in r.stderr


def test_out_of_memory_is_not_a_bug(garment, recipe, tmp_path, monkeypatch):
    """MemoryError: exit 2 and one line, as before, never 'please report'."""
    monkeypatch.setattr(
        "ptailor.run.garment.write_outputs", lambda *a, **k: (_ for _ in ()).throw(MemoryError)
    )
    out = tmp_path / "out"
    r = adjust(garment, recipe, out)
    assert r.exit_code == 2, r.output
    assert r.stderr.strip() == "ptailor: error: out of memory: the garment or its edit needs " \
        "more memory than there is; nothing written"  # fmt: skip
    nothing_written(out)
    failing_step(monkeypatch, MemoryError())  # in a step: the step named, as before
    r = adjust(garment, recipe, out)
    assert r.exit_code == 2 and "steps[1] (scale): out of memory" in r.stderr, r.output
    nothing_written(out)


# --------------------------------------------------------------------------- numeric


def test_a_singular_system_is_a_numeric_error_naming_what_failed():
    from ptailor.method.solver.linear import factor

    singular = r"cannot be factored \(SuperLU: Factor is exactly singular\)"
    with pytest.raises(NumericError, match=singular):
        factor(sp.csc_matrix(np.zeros((3, 3))))
    with pytest.raises(NumericError, match="non-finite entries"):
        factor(sp.csc_matrix(np.diag([1.0, np.nan, 1.0])))


def test_superlu_errors_other_than_singular_are_internal(monkeypatch):
    """Only SuperLU's 'singular' RuntimeError is the matrix's: another abort is a bug."""
    import scipy.sparse.linalg

    from ptailor.method.solver.cholesky import superlu_solver

    def abort(*a, **k):
        raise RuntimeError("SuperLU: some internal abort")

    monkeypatch.setattr(scipy.sparse.linalg, "splu", abort)
    with pytest.raises(RuntimeError, match="internal abort"):
        superlu_solver(sp.identity(3, format="csc"))


def test_a_singular_stitching_system_is_exit_2_naming_the_step(
    garment, recipe, tmp_path, monkeypatch
):
    """CHOLMOD finds it not positive definite (its ArithmeticError), SuperLU singular (its
    RuntimeError): the solver's wrapper names it, the pipeline the step."""
    import scipy.sparse.linalg
    from cvxopt import cholmod

    def not_positive_definite(*a, **k):
        raise ArithmeticError(7)  # cvxopt.cholmod.numeric's, with the failing column

    def singular(*a, **k):
        raise RuntimeError("Factor is exactly singular")  # scipy's splu's

    monkeypatch.setattr(cholmod, "numeric", not_positive_definite)
    monkeypatch.setattr(scipy.sparse.linalg, "splu", singular)
    out = tmp_path / "out"
    r = adjust(garment, recipe, out)
    assert r.exit_code == 2, r.output
    (line,) = r.stderr.strip().splitlines()
    assert line.startswith(f"ptailor: error: {garment}: flatten: the sparse system cannot be")
    assert "exactly singular" in line and "bug" not in line
    nothing_written(out)


def nan_solves(monkeypatch) -> None:
    """CHOLMOD's solves return NaN (as a factor of a nearly singular matrix may)."""
    from cvxopt import cholmod

    real = cholmod.solve

    def solve(F, B, *a, **k):
        real(F, B, *a, **k)
        B[:] = float("nan")

    monkeypatch.setattr(cholmod, "solve", solve)


def test_a_non_finite_solve_is_exit_2_naming_the_step(garment, recipe, tmp_path, monkeypatch):
    nan_solves(monkeypatch)
    out = tmp_path / "out"
    r = adjust(garment, recipe, out)
    assert r.exit_code == 2, r.output
    (line,) = r.stderr.strip().splitlines()
    assert f"{garment}: flatten: the stitching solver diverged (non-finite" in line, line
    nothing_written(out)


def test_the_baseline_step_is_named(garment, recipe, tmp_path, monkeypatch):
    import ptailor.pipeline

    real = ptailor.pipeline.flatten

    def uniform_fails(*a, method, **kw):
        if method == "uniform":
            raise NumericError("the sparse system cannot be factored (test)")
        return real(*a, method=method, **kw)

    monkeypatch.setattr(ptailor.pipeline, "flatten", uniform_fails)
    out = tmp_path / "out"
    r = CliRunner().invoke(
        cli, ["adjust", str(garment), str(recipe), "-o", str(out), "--formats", "obj"]
    )
    assert r.exit_code == 2, r.output
    assert "flatten (the uniform baseline): the sparse system cannot be factored" in r.stderr
    nothing_written(out)


@pytest.mark.parametrize(
    "exc, kind",
    [
        (NumericError("the sparse system cannot be factored"), NumericError),
        (np.linalg.LinAlgError("Singular matrix"), NumericError),
        (FloatingPointError("overflow"), NumericError),
        (PtailorError("no such opening"), PtailorError),
        (RuntimeError("boom"), RuntimeError),
        (ValueError("array must not contain infs or NaNs"), ValueError),  # no message decides
    ],
)
def test_a_step_names_itself_in_numeric_failures_only(garment, monkeypatch, exc, kind):
    from ptailor.formats.garment import load_garment
    from ptailor.pipeline import adjustment
    from ptailor.recipe import parse_recipe

    failing_step(monkeypatch, exc)
    g = load_garment(str(garment)).garment
    with pytest.raises(Exception) as ei:
        adjustment(g, parse_recipe(RECIPE), baseline=False)
    assert type(ei.value) is kind
    if issubclass(kind, PtailorError):
        assert str(ei.value).startswith("steps[1] (scale): "), str(ei.value)
    else:
        assert ei.value is exc


# --------------------------------------------------------------------------- batch


def test_batch_records_internal_and_numeric_failures_apart(tmp_path, recipe, monkeypatch):
    import ptailor.run.garment

    cat = tmp_path / "cat"
    cat.mkdir()
    write_garment(cat / "a_bug.obj", lantern_sleeve(n_around=12, n_sleeve=6, n_cuff=2))
    write_garment(cat / "b_nan.obj", cylinder(circumference=40.0, n_around=16, n_along=6))
    real_run = ptailor.run.garment.staged_run

    def buggy(path, *a, **k):
        if "a_bug" in path:
            raise KeyError("lost")
        return real_run(path, *a, **k)

    monkeypatch.setattr(ptailor.run.garment, "staged_run", buggy)
    nan_solves(monkeypatch)
    out = tmp_path / "out"
    args = ["batch", str(recipe), str(cat), "-o", str(out), "-j", "1", "--json", "--html", *FAST]
    r = CliRunner().invoke(cli, args, catch_exceptions=False)
    assert r.exit_code == 1, r.output
    bug, nan = (json.loads(ln) for ln in r.stdout.splitlines())
    assert bug["status"] == nan["status"] == "failed"
    assert bug["failure"] == "internal"
    assert bug["reason"] == (
        f"internal error: KeyError: 'lost' (a bug in ptailor {__version__}: please report it)"
    )
    assert nan["failure"] == "input"
    assert "flatten: the stitching solver diverged" in nan["reason"]
    assert "Traceback" not in r.stderr
    # no folder for either; the catalogue shows both kinds
    assert sorted(p.name for p in out.iterdir()) == ["_catalogue", "index.html"]
    page = (out / "index.html").read_text()
    assert "internal" in page and "a bug in ptailor" in page and "diverged" in page

    r = CliRunner().invoke(cli, ["--debug", *args, "--force"], catch_exceptions=False)
    assert r.exit_code == 1
    assert "ptailor: " + str(cat / "a_bug.obj") + ": internal error:\nTraceback" in r.stderr
    assert "KeyError: 'lost'" in r.stderr and r.stderr.count("Traceback") == 1
