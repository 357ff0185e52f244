"""Bad recipes (issue 12): every YAML and recipe signature refused in one line, quickly.

Each file of ``tests/corpus/yaml`` is a recipe that must fail ``ptailor validate`` and
``ptailor adjust`` alike (one validation path), with exit 2, one line per problem naming
the file and line, no traceback, nothing written, and in bounded time.
"""

from __future__ import annotations

import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from ptailor import tolerances as tol
from ptailor.cli.main import cli
from ptailor.errors import PtailorError, RecipeError
from ptailor.model.frame import Frame
from ptailor.recipe import (
    axes_problem,
    load_recipe,
    parse_recipe,
    recipe_problems,
    resolve_frame,
)

CORPUS = Path(__file__).resolve().parent / "corpus" / "yaml"

#: corpus file -> (line of the problem, what the message says)
EXPECTED = {
    "alias-bomb.yaml": (6, "aliases expanded"),
    "alias-bomb-steps.yaml": (6, "aliases expanded"),
    "alias-recursive.yaml": (1, "refers to a node that contains it"),
    "alias-many.yaml": (103, "more than 100 YAML aliases"),
    "nested-1000.yaml": (1, "nest"),  # libyaml: "maximum nesting depth"; else ours
    "nested-block-40.yaml": (33, "nested more than 32 deep"),
    "python-object.yaml": (1, "could not determine a constructor"),
    "opening-loop-true.yaml": (3, "steps[1].opening.loop: expected a loop number"),
    "up-front-parallel.yaml": (2, "front: -y is parallel to up y"),
    "up-z-default-front.yaml": (1, "front z (the default) is parallel to up z"),
    "axis-1e308.yaml": (4, "steps[1].axis: component 1: 1e+308 is out of range"),
    "axis-subnormal.yaml": (4, "steps[1].axis: [5e-324, 0, 0] is too short"),
    "factor-5e-324.yaml": (3, "steps[1].factor: must be >= 1e-06"),
    "extend-by-1e300.yaml": (4, "steps[1].by: 1e+300 is out of range"),
    "extend-by-99999.yaml": (4, "steps[1].by: 99999 is longer than 1000 cm"),
    "shorten-by-nan.yaml": (4, "steps[1].by: expected a finite number, got nan"),
    "shorten-by-inf.yaml": (4, "steps[1].by: expected a finite number, got inf"),
    "by-true.yaml": (4, "steps[1].by: expected a number, got True"),
    "huge-int.yaml": (4, "a number of 5000 characters"),
    "big-int.yaml": (4, "steps[1].by: 100000000000000000000 is out of range"),
    "weights-1e300.yaml": (4, "flatten.w_pin: 1e+300 is out of range"),
    "max-iter-float.yaml": (3, "flatten.max_iter: expected a whole number"),
    "bad-date.yaml": (2, "cannot read the value '2001-13-45'"),
    "sexagesimal.yaml": (2, "a number of 89 characters"),
    "duplicate-key.yaml": (4, "duplicate key 'factor' (first on line 3)"),
    "format-true.yaml": (1, "format: only format 1 is known, got True"),
    "plane-normal-tiny.yaml": (3, "steps[1].plane.normal: [0, 1e-300, 0] is too short"),
    "sketch-inf.yaml": (4, "steps[1].sketch: expected a polyline"),
    "box-1e300.yaml": (3, "steps[1].region.box.max: component 2: 1e+300 is out of range"),
    "long-key.yaml": (2, "YAML syntax error"),
    "unicode-key.yaml": (2, "unknown key 'ünits'"),
    "multi-doc.yaml": (2, "another document"),
    "tab-indent.yaml": (2, "YAML syntax error"),
}

#: seconds any one bad recipe may take to be refused (they take milliseconds)
TIME_LIMIT = 5.0


def invoke(*args, input=None):
    return CliRunner().invoke(cli, [str(a) for a in args], input=input)


def test_the_corpus_is_complete():
    assert sorted(p.name for p in CORPUS.glob("*.yaml")) == sorted(EXPECTED)


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_validate_refuses_in_one_line(name):
    path = CORPUS / name
    line, needle = EXPECTED[name]
    t0 = time.perf_counter()
    r = invoke("validate", path)
    assert time.perf_counter() - t0 < TIME_LIMIT
    assert r.exit_code == 2, r.output
    assert r.exception is None or isinstance(r.exception, SystemExit)
    assert "Traceback" not in r.output
    lines = r.stdout.splitlines()
    assert len(lines) == 1, lines  # each corpus file has exactly one problem
    assert lines[0].startswith(f"{path}:{line}: "), lines[0]
    assert needle in lines[0], lines[0]


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_adjust_refuses_the_same_way_before_reading_the_garment(name, tmp_path):
    path = CORPUS / name
    line, needle = EXPECTED[name]
    out = tmp_path / "out"
    t0 = time.perf_counter()
    # the garment does not exist: the recipe is refused first
    r = invoke("adjust", tmp_path / "no-garment.obj", path, "-o", out)
    assert time.perf_counter() - t0 < TIME_LIMIT
    assert r.exit_code == 2, r.output
    assert r.exception is None or isinstance(r.exception, SystemExit)
    err = r.stderr.strip().splitlines()
    assert len(err) == 1, err
    assert err[0].startswith(f"ptailor: error: {path}:{line}: "), err[0]
    assert needle in err[0]
    assert not out.exists()
    with pytest.raises(RecipeError) as exc:
        load_recipe(path)
    assert needle in str(exc.value)


def test_a_recipe_over_the_size_limit_is_refused_before_parsing(tmp_path):
    p = tmp_path / "comments.yaml"
    line = "# " + "x" * 77 + "\n"
    p.write_text("steps: []\n" + line * (tol.RECIPE_MAX_BYTES // len(line) + 1))
    for args in (("validate", p), ("adjust", tmp_path / "g.obj", p, "-o", tmp_path / "o")):
        t0 = time.perf_counter()
        r = invoke(*args)
        assert time.perf_counter() - t0 < 2.0
        assert r.exit_code == 2
        msg = (r.stdout + r.stderr).splitlines()[0]
        assert str(p) in msg and f"larger than {tol.RECIPE_MAX_BYTES} bytes" in msg
    r = invoke("validate", "-", input="#" * (tol.RECIPE_MAX_BYTES + 1))
    assert r.exit_code == 2 and r.stdout.startswith("<stdin>: recipe larger than")
    with pytest.raises(RecipeError, match="larger than"):
        parse_recipe("#" * (tol.RECIPE_MAX_BYTES + 1))


def test_a_recipe_just_under_the_limit_is_read_quickly():
    text = "steps: []\n" + ("# " + "x" * 77 + "\n") * (tol.RECIPE_MAX_BYTES // 80 - 1)
    t0 = time.perf_counter()
    assert recipe_problems(text) == []
    assert time.perf_counter() - t0 < 2.0


def test_a_few_anchors_are_fine():
    """Anchors and aliases are allowed (a region reused), within the limits."""
    r = parse_recipe(
        "steps:\n"
        "  - {op: scale, region: &s {panels: [sleeve]}, factor: 1.1}\n"
        "  - {op: scale, region: *s, direction: around, factor: 1.2}\n"
    )
    assert r.steps[1].region == {"panels": ["sleeve"]}


def test_numbers_in_exponent_form_are_numbers():
    """YAML 1.2 (and the schema's editors) read 1e-1 as a number; so do recipes."""
    r = parse_recipe("steps: [{op: scale, factor: 11e-1}]")
    assert r.steps[0].factor == pytest.approx(1.1)


def test_many_problems_stay_linear():
    text = "steps:\n" + "  - {op: scale, factor: -1}\n" * tol.RECIPE_MAX_STEPS
    t0 = time.perf_counter()
    probs = recipe_problems(text)
    assert time.perf_counter() - t0 < TIME_LIMIT
    assert len(probs) == tol.RECIPE_MAX_STEPS
    assert [p.line for p in probs] == list(range(2, tol.RECIPE_MAX_STEPS + 2))
    probs = recipe_problems("steps:\n" + "  - {op: scale, factor: 2}\n" * 201)
    assert len(probs) == 1 and "more than 200" in probs[0].message


def test_messages_are_one_short_line():
    probs = recipe_problems(
        "steps:\n  - op: extend\n    opening: hem\n    by: '" + "a\\u2028b" * 2000 + "'\n"
    )
    assert len(probs) == 1
    s = str(probs[0])
    assert "\n" not in s and "\u2028" not in s and len(s) < 500


# ---------------------------------------------------------------------------------------
# up and front: one rule for recipes and the command line
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "up, front, bad",
    [
        ("y", "-y", True),
        ("y", "y", True),
        ("z", None, True),  # front defaults to z
        (None, "-y", True),  # up defaults to y
        ("y", "z", False),
        ("-z", "x", False),
        (None, None, False),
    ],
)
def test_axes_rule(up, front, bad):
    assert (axes_problem(up, front) is not None) == bad
    text = "".join(f"{k}: {v}\n" for k, v in (("up", up), ("front", front)) if v) + "steps: []"
    assert bool(recipe_problems(text)) == bad
    if bad:
        with pytest.raises(PtailorError, match="parallel"):
            resolve_frame(up, front)
    else:
        resolve_frame(up, front)


def test_command_line_axes_and_recipe_axes_combine():
    rec = parse_recipe("up: z\nfront: y\nsteps: []")
    assert resolve_frame(None, None, rec) == Frame((0.0, 0.0, 1.0), (0.0, 1.0, 0.0))
    with pytest.raises(PtailorError, match="--front z is parallel to up z"):
        resolve_frame(None, "z", parse_recipe("up: z\nfront: x\nsteps: []"))
    with pytest.raises(PtailorError, match="front y is parallel to --up -y"):
        resolve_frame("-y", None, rec)
    assert resolve_frame("x", None, rec) == Frame((1.0, 0.0, 0.0), (0.0, 1.0, 0.0))


def test_parallel_axes_on_the_command_line_exit_2(tmp_path):
    from ptailor.samples.obj_text import sample_obj_text

    g = tmp_path / "sleeve.obj"
    g.write_text(sample_obj_text("lantern_sleeve"))
    rec = tmp_path / "r.yaml"
    rec.write_text("steps: []\n")
    r = invoke("adjust", g, rec, "-o", tmp_path / "o", "--up", "y", "--front", "-y")
    assert r.exit_code == 2 and "parallel" in r.stderr
    assert not (tmp_path / "o").exists()
