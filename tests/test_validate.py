"""``ptailor validate`` and the published recipe schema."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import pytest
import yaml
from click.testing import CliRunner

from ptailor.cli.main import cli
from ptailor.edits import OPERATIONS
from ptailor.recipe import FLATTEN_PARAMS, recipe_problems
from ptailor.recipe.schema import recipe_schema, schema_text

RECIPES = Path(__file__).resolve().parents[1] / "recipes"

BROKEN = """\
units: cm
steps:
  - op: scale
    region: all
    factor: -1.5
  - op: frobnicate
    by: 2
  - op: shorten
    by: 5
  - op: extend
    opening: hem
    by: lots
flatten:
  boundary: tight
"""


def run(*args, input=None):
    return CliRunner().invoke(cli, ["validate", *map(str, args)], input=input)


def test_the_published_schema_is_the_generated_one():
    assert (RECIPES / "schema.json").read_text() == schema_text()


def test_every_parameter_check_has_a_schema_fragment():
    for op in OPERATIONS.values():
        for key, prm in op.params.items():
            assert getattr(prm.check, "schema", None), f"{op.name}.{key}"
    for key, (check, _) in FLATTEN_PARAMS.items():
        assert getattr(check, "schema", None), f"flatten.{key}"


@pytest.mark.slow
@pytest.mark.parametrize("path", sorted(RECIPES.glob("*.yaml")), ids=lambda p: p.name)
def test_example_recipes_pass_the_schema_and_the_rules(path):
    data = yaml.safe_load(path.read_text())
    jsonschema.validate(data, recipe_schema())
    assert recipe_problems(path.read_text(), source=str(path)) == []


def test_every_problem_of_a_broken_recipe_is_reported_with_its_line(tmp_path):
    p = tmp_path / "broken.yaml"
    p.write_text(BROKEN)
    r = run(p)
    assert r.exit_code == 2
    lines = [ln for ln in r.stdout.splitlines() if ln]
    got = {(int(ln.split(":")[1]), ln.split(": ", 1)[1].split(":")[0]) for ln in lines}
    assert got == {
        (5, "steps[1].factor"),  # negative factor
        (6, "steps[2].op"),  # unknown op
        (8, "steps[3]"),  # missing key: shorten needs 'opening'
        (12, "steps[4].by"),  # wrong type
        (14, "flatten.boundary"),  # not one of the choices
    }
    assert all(ln.startswith(f"{p}:") for ln in lines)
    assert "5 problem(s) in 1 of 1" in r.stderr


def test_the_schema_alone_rejects_the_same_broken_steps():
    data = yaml.safe_load(BROKEN)
    errors = list(jsonschema.Draft202012Validator(recipe_schema()).iter_errors(data))
    paths = {tuple(e.absolute_path) for e in errors}
    assert ("steps", 0, "factor") in paths
    assert ("steps", 1, "op") in paths
    assert ("steps", 2) in paths  # 'opening' is required
    assert ("steps", 3, "by") in paths
    assert ("flatten", "boundary") in paths


def test_yaml_syntax_errors_give_their_line(tmp_path):
    p = tmp_path / "bad.yaml"
    p.write_text("units: cm\nsteps:\n  - op: scale\n   factor: [1.2\n")
    r = run(p)
    assert r.exit_code == 2 and r.stdout.startswith(f"{p}:4: YAML syntax error")


def test_unknown_keys_point_at_the_key(tmp_path):
    p = tmp_path / "k.yaml"
    p.write_text("steps:\n  - op: scale\n    region: all\n    factor: 1.1\n    colour: red\n")
    r = run(p)
    assert r.exit_code == 2 and r.stdout.startswith(f"{p}:5: steps[1]: unknown key 'colour'")


def test_several_files_stdin_and_json(tmp_path):
    good = RECIPES / "wider-around.yaml"
    bad = tmp_path / "b.yaml"
    bad.write_text("steps:\n  - op: shorten\n    opening: hem\n    by: -2\n")
    r = run(good, bad, tmp_path / "missing.yaml")
    assert r.exit_code == 2
    assert str(good) not in r.stdout
    assert f"{bad}:4: steps[1].by" in r.stdout and "missing.yaml: no such file" in r.stdout
    r = run("-", "--json", input="steps: [{op: scale, factor: 0}]\n")
    assert r.exit_code == 2
    recs = json.loads(r.stdout)
    assert recs == [
        {"file": "<stdin>", "line": 1, "message": "steps[1].factor: must be > 0.0, got 0"}
    ]
    r = run(good, "-", input="units: mm\nsteps: []\n")
    assert r.exit_code == 0 and r.stdout == "" and "2 recipe(s) valid" in r.stderr
