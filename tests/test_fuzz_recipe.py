"""Property-based fuzzing of the recipe reader and validator (issue 12).

Random YAML documents (nested mappings and lists, anchors and aliases, tags, odd scalars)
and mutations of the real recipes in ``recipes/*.yaml`` go through ``ptailor validate``.
The contract: exit 0 or 2, never a traceback; with 2, exactly one line per problem, each
naming the file; within a time bound; and when validate says 0, the recipe reads with
finite numbers only, and ``parse_recipe`` (the path ``adjust`` takes) agrees.

Seeded and short by default (the ``ci`` profile of ``conftest.py``); longer with
``PTAILOR_FUZZ=long``. ``bench/fuzz_recipe.py`` runs a campaign outside pytest.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import given  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

RECIPES = Path(__file__).resolve().parents[1] / "recipes"
#: seconds one case may take (they take milliseconds)
CASE_LIMIT = 5.0

ODD_SCALARS = [
    ".nan",
    ".NaN",
    ".inf",
    "-.inf",
    "+.inf",
    "1e400",
    "-1e400",
    "1e308",
    "5e-324",
    "1.0e+300",
    "0x7fffffffffffffffffff",
    "0o777",
    "0b1011",
    "1_000_000",
    "190:20:30",
    "99999999999999999999999999",
    "9" * 60,
    "-0.0",
    "~",
    "null",
    "Null",
    "yes",
    "no",
    "on",
    "off",
    "y",
    "n",
    "true",
    "false",
    "True",
    "2001-12-14",
    "2001-13-45",
    "2001-12-14t21:59:43.10-05:00",
    "''",
    '""',
    "'a''b'",
    '"\\u2028"',
    '"\\x00"',
    "<<",
    "=",
    "-",
    "?",
    "hem",
    "neckline",
    "{loop: 0}",
    "{loop: true}",
    "{loop: -1}",
    "scale",
    "extend",
    "cut",
    "shorten",
    "loosen",
    "tighten",
    "scale_seam",
    "all",
    "auto",
    "front",
    "y",
    "-y",
    "z",
    "cm",
    "mm",
    "in",
    "m",
    "around",
    "along",
    "uniform",
    "!!python/object:os.system x",
    "!!python/name:os.system",
    "!!binary aGVsbG8=",
    "!!binary ???",
    "!!int abc",
    "!!float x",
    "!!str 1",
    "!!set {a, b}",
    "!!omap [a]",
    "!foo bar",
    "'\u00fcnits'",
    '"\U0001f600"',
    "x" * 300,
]
KEYS = [
    "format",
    "units",
    "up",
    "front",
    "symmetric",
    "steps",
    "flatten",
    "op",
    "region",
    "factor",
    "by",
    "opening",
    "axis",
    "direction",
    "plane",
    "point",
    "normal",
    "view",
    "sketch",
    "remove",
    "layers",
    "measure",
    "clearance",
    "silhouette",
    "seam",
    "part",
    "fix",
    "panels",
    "box",
    "min",
    "max",
    "loop",
    "method",
    "intrinsic",
    "boundary",
    "seams",
    "w_pin",
    "w_asap",
    "max_iter",
    "<<",
    "'?'",
    "1",
    "~",
    "\u00fcnits",
]


def scalar_text() -> st.SearchStrategy[str]:
    return st.one_of(
        st.sampled_from(ODD_SCALARS),
        st.integers(min_value=-(10**30), max_value=10**30).map(str),
        st.floats(allow_nan=True, allow_infinity=True).map(repr),
        st.text(alphabet=st.characters(blacklist_categories=("Cs",)), min_size=0, max_size=20).map(
            lambda s: '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'
        ),
    )


@st.composite
def yaml_doc(draw) -> str:
    """Flow-style YAML text with anchors, aliases and tags, possibly invalid."""
    anchors: list[str] = []

    def node(depth: int) -> str:
        kind = draw(st.integers(0, 9 if depth < 5 else 3))
        if kind <= 3:
            text = draw(scalar_text())
        elif kind == 4 and anchors:
            return "*" + draw(st.sampled_from([*anchors, "nowhere"]))
        elif kind <= 6:
            n = draw(st.integers(0, 4))
            text = "[" + ", ".join(node(depth + 1) for _ in range(n)) + "]"
        else:
            n = draw(st.integers(0, 4))
            items = [f"{draw(st.sampled_from(KEYS))}: {node(depth + 1)}" for _ in range(n)]
            text = "{" + ", ".join(items) + "}"
        if draw(st.integers(0, 7)) == 0:
            name = f"a{len(anchors)}"
            anchors.append(name)
            text = f"&{name} {text}"
        return text

    top = draw(st.integers(0, 5))
    lines = [f"{draw(st.sampled_from(KEYS))}: {node(1)}" for _ in range(top)]
    if draw(st.booleans()):
        lines.append("steps: " + node(1))
    return "\n".join(lines) + "\n"


def real_recipes() -> list[str]:
    return sorted(p.read_text() for p in RECIPES.glob("*.yaml"))


EXTREMES = [
    1e308,
    -1e308,
    float("nan"),
    float("inf"),
    -float("inf"),
    10**30,
    -(10**30),
    5e-324,
    1e-300,
    -0.0,
    0,
    -1,
    1e6,
    1e6 + 1,
    1000.0,
    1001.0,
    True,
    False,
    None,
    "",
    "x" * 500,
    [],
    {},
    [1, 2],
    [1e308, 1e308, 1e308],
    [0, 0, 0],
    [5e-324, 0, 0],
    {"loop": True},
    {"loop": 0},
    {"loop": 10**20},
    "hem",
    "all",
    "auto",
    [[0, 0]],
    [[0, 0], [1e300, 1]],
]


def paths_of(data, prefix=()):
    """Every path (tuple of keys and indices) into a parsed recipe."""
    out = [prefix]
    if isinstance(data, dict):
        for k, v in data.items():
            out += paths_of(v, (*prefix, k))
    elif isinstance(data, list):
        for i, v in enumerate(data):
            out += paths_of(v, (*prefix, i))
    return out


@st.composite
def mutated_recipe(draw) -> str:
    """A real recipe with one to three values replaced, keys dropped or duplicated."""
    import copy

    import yaml

    text = draw(st.sampled_from(real_recipes()))
    data = yaml.safe_load(text)
    for _ in range(draw(st.integers(1, 3))):
        paths = [p for p in paths_of(data) if p]
        if not paths:
            break
        path = draw(st.sampled_from(paths))
        parent = data
        for k in path[:-1]:
            parent = parent[k]
        how = draw(st.integers(0, 3))
        if how == 0 and isinstance(parent, dict):
            del parent[path[-1]]
        elif how == 1 and isinstance(parent, list):
            parent.append(copy.deepcopy(parent[path[-1]]))
        else:
            parent[path[-1]] = copy.deepcopy(draw(st.sampled_from(EXTREMES)))
    out = yaml.safe_dump(data, sort_keys=False)
    if draw(st.integers(0, 4)) == 0:  # a key written twice
        lines = out.splitlines()
        keyed = [i for i, ln in enumerate(lines) if ":" in ln and not ln.rstrip().endswith(":")]
        if keyed:
            i = draw(st.sampled_from(keyed))
            lines.insert(i + 1, lines[i])
            out = "\n".join(lines) + "\n"
    return out


def all_finite(x) -> bool:
    if isinstance(x, bool) or x is None or isinstance(x, str):
        return True
    if isinstance(x, (int, float)):
        return math.isfinite(x) and abs(x) <= 1e6
    if isinstance(x, dict):
        return all(all_finite(v) for v in x.values())
    if isinstance(x, (list, tuple)):
        return all(all_finite(v) for v in x)
    return False  # nothing else (dates, bytes, sets) may reach a valid recipe


def check_contract(text: str, path: Path) -> dict:
    """Run ``ptailor validate`` on ``text``; assert the contract; return a summary."""
    from click.testing import CliRunner

    from ptailor.cli.main import cli
    from ptailor.errors import RecipeError
    from ptailor.recipe import parse_recipe, recipe_problems

    path.write_text(text, encoding="utf-8")
    t0 = time.perf_counter()
    r = CliRunner().invoke(cli, ["validate", str(path)])
    took = time.perf_counter() - t0
    assert took < CASE_LIMIT, f"validate took {took:.1f} s"
    assert r.exception is None or isinstance(r.exception, SystemExit), repr(r.exception)
    assert r.exit_code in (0, 2), r.output
    assert "Traceback" not in r.output
    lines = r.stdout.splitlines()
    problems = recipe_problems(text, source=str(path))
    if r.exit_code == 0:
        assert lines == [] and problems == []
        rec = parse_recipe(text)  # the path adjust takes agrees
        assert all_finite(rec.to_dict())
    else:
        assert len(lines) == len(problems) >= 1  # exactly one line per problem
        assert all(ln.startswith(f"{path}:") for ln in lines), lines
        assert all(len(ln) < 600 for ln in lines)
        assert f"{len(lines)} problem(s)" in r.stderr
        with pytest.raises(RecipeError):
            parse_recipe(text)
    return {"exit": r.exit_code, "seconds": took}


@pytest.mark.slow
@given(yaml_doc())
def test_random_yaml_documents_keep_the_contract(tmp_path_factory, text):
    check_contract(text, tmp_path_factory.mktemp("fz") / "recipe.yaml")


@pytest.mark.slow
@given(mutated_recipe())
def test_mutated_recipes_keep_the_contract(tmp_path_factory, text):
    check_contract(text, tmp_path_factory.mktemp("fz") / "recipe.yaml")


@pytest.mark.parametrize("path", sorted(RECIPES.glob("*.yaml")), ids=lambda p: p.name)
def test_the_real_recipes_pass(path, tmp_path):
    assert check_contract(path.read_text(), tmp_path / path.name)["exit"] == 0


def _schema_refuses(data) -> bool:
    import jsonschema

    from ptailor.recipe.schema import recipe_schema

    global _SCHEMA_VALIDATOR
    if _SCHEMA_VALIDATOR is None:
        _SCHEMA_VALIDATOR = jsonschema.Draft202012Validator(recipe_schema())
    return next(iter(_SCHEMA_VALIDATOR.iter_errors(data)), None) is not None


_SCHEMA_VALIDATOR = None


@given(mutated_recipe())
def test_the_schema_never_refuses_what_the_rules_accept(text):
    """The rules are the one authority at run time (``recipe_problems``); the published
    schema, generated from the same checks, must never show an editor's user an error on a
    recipe that runs. (The rules may refuse more: parallel axes, lengths in the recipe's
    units, steps that only make sense together.)"""
    import yaml

    from ptailor.recipe import recipe_problems

    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError:
        return
    if recipe_problems(text) == []:
        assert not _schema_refuses(data), text


@pytest.mark.parametrize("path", sorted(RECIPES.glob("*.yaml")), ids=lambda p: p.name)
def test_the_rules_refuse_what_the_schema_refuses_in_real_recipes_mutated(path):
    """Each real recipe with one value made wrong the schema's way (a string where a number
    goes, an unknown key, an unknown op): the schema and the rules both refuse it."""
    import yaml

    from ptailor.recipe import recipe_problems

    data = yaml.safe_load(path.read_text())
    if not data.get("steps"):
        pytest.skip("no steps to break")
    for broken in (
        {**data, "colour": "red"},
        {**data, "steps": [{**data["steps"][0], "op": "frobnicate"}]},
        {**data, "steps": [{**data["steps"][0], "colour": 1}]},
        {**data, "flatten": {"boundary": "tight"}},
        {**data, "units": "furlongs"},
    ):
        assert _schema_refuses(broken)
        assert recipe_problems(yaml.safe_dump(broken)) != [], broken
