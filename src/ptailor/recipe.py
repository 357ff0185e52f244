"""Recipes: YAML edit recipes (format 1), validated whole before any garment is read."""

from __future__ import annotations

import re
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from ptailor import tolerances as tol
from ptailor.edits import OPERATIONS
from ptailor.edits.checks import boolean, choice, number
from ptailor.errors import PtailorError, RecipeError
from ptailor.model.units import UNITS

FLATTEN_PARAMS = {
    "method": (choice("scale-preserving", "uniform"), "scale-preserving"),
    "intrinsic": (choice("polar", "paper"), "polar"),
    "boundary": (choice("auto", "similar", "free"), "auto"),
    "seams": (choice("ease", "free", "keep"), "ease"),
    "w_pin": (number(gt=0.0), tol.W_PIN),
    "w_asap": (number(gt=0.0), tol.W_ASAP),
    "max_iter": (number(ge=1, le=10000), tol.ARAP_MAX_ITER),
}
TOP_KEYS = ("format", "units", "up", "front", "symmetric", "steps", "flatten")
#: A step key every operation accepts (see :mod:`ptailor.edits.mirror`).
STEP_KEYS = ("symmetric",)
AXIS_NAMES = ("x", "y", "z", "-x", "-y", "-z")


def axis_vector(name: str) -> tuple[float, float, float]:
    """``"-y"`` -> ``(0, -1, 0)``."""
    sign = -1.0 if name.startswith("-") else 1.0
    v = [0.0, 0.0, 0.0]
    v["xyz".index(name[-1])] = sign
    return (v[0], v[1], v[2])


@dataclass(frozen=True)
class Recipe:
    """A validated recipe with every default filled in.

    Attributes
    ----------
    units : str
    steps : list of dict
        Each with ``op``, all of its parameters and ``symmetric`` (resolved: the step's
        own, else the recipe's).
    flatten : dict
        ``method``, ``intrinsic``, ``boundary``, ``w_pin``, ``w_asap``, ``max_iter``.
    source : str
        Where it came from (a path, ``<stdin>`` or ``<string>``).
    up, front : str or None
        The garment's axes (``y``, ``-z``, ...) when the recipe sets them.
    symmetric : bool
        The recipe-level default of every step's ``symmetric`` (each step in ``steps``
        carries its own, resolved value).
    """

    units: str = "cm"
    steps: list[dict] = field(default_factory=list)
    flatten: dict = field(default_factory=lambda: {k: d for k, (_, d) in FLATTEN_PARAMS.items()})
    source: str = "<string>"
    up: str | None = None
    front: str | None = None
    symmetric: bool = False


def validate(data: Any) -> tuple[Recipe | None, list[str]]:
    """Check a parsed recipe; collect every problem.

    Parameters
    ----------
    data : object
        The YAML document.

    Returns
    -------
    recipe : Recipe or None
        None when there are problems.
    problems : list of str
    """
    probs: list[str] = []
    if data is None:
        data = {}
    if not isinstance(data, dict):
        return None, ["the recipe must be a mapping with 'steps' (and optionally units, flatten)"]
    for k in data:
        if k not in TOP_KEYS:
            probs.append(f"unknown key {k!r} (known: {', '.join(TOP_KEYS)})")
    if data.get("format", 1) != 1:
        probs.append(f"format: only format 1 is known, got {data['format']!r}")
    units = data.get("units", "cm")
    probs += choice(*UNITS)(units, "units")
    for k in ("up", "front"):
        if k in data:
            probs += choice(*AXIS_NAMES)(data[k], k)
    if "up" in data and "front" in data and str(data["up"])[-1:] == str(data["front"])[-1:]:
        probs.append("up and front must be different axes")
    symmetric = data.get("symmetric", False)
    probs += boolean(symmetric, "symmetric")
    steps_in = data.get("steps", [])
    if steps_in is None:
        steps_in = []
    steps: list[dict] = []
    if not isinstance(steps_in, list):
        probs.append("steps: expected a list of steps")
        steps_in = []
    for i, st in enumerate(steps_in, start=1):
        where = f"steps[{i}]"
        if not isinstance(st, dict) or "op" not in st:
            probs.append(f"{where}: expected a mapping with 'op'")
            continue
        op = OPERATIONS.get(st["op"]) if isinstance(st["op"], str) else None
        if op is None:
            probs.append(f"{where}.op: unknown op {st['op']!r} (known: {', '.join(OPERATIONS)})")
            continue
        full = {"op": op.name}
        known = [*op.params, *(k for k in STEP_KEYS if k not in op.params)]
        for k in st:
            if k != "op" and k not in known:
                probs.append(
                    f"{where}: unknown key {k!r} for {op.name} (known: {', '.join(known)})"
                )
        for k, prm in op.params.items():
            if k in st:
                probs += prm.check(st[k], f"{where}.{k}")
                full[k] = st[k]
            elif prm.required:
                probs.append(f"{where}: {op.name} needs {k!r}")
            else:
                full[k] = prm.default
        # symmetric: every op's, defaulting to the recipe's (an op's own symmetric param, such
        # as cut's, takes the same resolved value and mirrors itself)
        if "symmetric" in st and "symmetric" not in op.params:
            probs += boolean(st["symmetric"], f"{where}.symmetric")
        full["symmetric"] = st.get("symmetric", symmetric is True)
        if op.check is not None and not any(pr.startswith(where) for pr in probs):
            probs += op.check(full, where)
        steps.append(full)
    fl_in = data.get("flatten", {}) or {}
    flatten: dict = {}
    if not isinstance(fl_in, dict):
        probs.append("flatten: expected a mapping")
        fl_in = {}
    for k in fl_in:
        if k not in FLATTEN_PARAMS:
            probs.append(f"flatten: unknown key {k!r} (known: {', '.join(FLATTEN_PARAMS)})")
    for k, (check, default) in FLATTEN_PARAMS.items():
        if k in fl_in:
            probs += check(fl_in[k], f"flatten.{k}")
        flatten[k] = fl_in.get(k, default)
    if probs:
        return None, probs
    return Recipe(
        units=units,
        steps=steps,
        flatten=flatten,
        up=data.get("up"),
        front=data.get("front"),
        symmetric=symmetric,
    ), []


def parse_recipe(text: str, *, source: str = "<string>") -> Recipe:
    """Parse and validate recipe text.

    Raises
    ------
    RecipeError
        Listing every problem, or the YAML syntax error with its line.
    """
    import yaml

    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"line {mark.line + 1}: " if mark is not None else ""
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise RecipeError([f"{where}YAML syntax error: {problem}"], path=source) from None
    recipe, probs = validate(data)
    if probs:
        raise RecipeError(probs, path=source)
    assert recipe is not None
    return replace(recipe, source=source)


def load_recipe(path: str | Path) -> Recipe:
    """Read and validate a recipe file (``-`` reads standard input)."""
    import sys

    if str(path) == "-":
        return parse_recipe(sys.stdin.read(), source="<stdin>")
    try:
        text = Path(path).read_text()
    except FileNotFoundError:
        raise PtailorError("no such file", path=str(path)) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise PtailorError(f"cannot read recipe ({exc})", path=str(path)) from None
    return parse_recipe(text, source=str(path))


@dataclass(frozen=True)
class Problem:
    """One problem in a recipe file.

    Attributes
    ----------
    source : str
        The recipe's path (``<stdin>`` for standard input).
    line : int or None
        1-based line of the offending key or value; None when the problem is the whole
        document.
    message : str
        What is wrong, starting with where (``steps[2].factor: must be > 0, got -1``).
    """

    source: str
    line: int | None
    message: str

    def __str__(self) -> str:
        return (
            f"{self.source}:{self.line}: {self.message}"
            if self.line
            else (f"{self.source}: {self.message}")
        )


_WHERE = re.compile(r"^((?:[A-Za-z_]\w*)(?:\.[A-Za-z_]\w*|\[\d+\])*)(?=: )")
_TOKEN = re.compile(r"\.?([A-Za-z_]\w*)|\[(\d+)\]")
_UNKNOWN = re.compile(r"unknown key '([^']+)'")


def _path_of(message: str) -> tuple[list, str | None]:
    """``steps[2].factor: ...`` -> ``(["steps", 1, "factor"], None)``; unknown keys' names."""
    path: list = []
    m = _WHERE.match(message)
    if m:
        for name, idx in _TOKEN.findall(m.group(1)):
            path.append(name if name else int(idx) - (1 if path == ["steps"] else 0))
    unknown = _UNKNOWN.search(message)
    return path, unknown.group(1) if unknown else None


def _line_of(node: Any, path: list, key: str | None) -> int | None:
    """Line of the YAML node at ``path`` (or of ``key`` under it), as deep as it exists."""
    import yaml

    if node is None:
        return None
    line = node.start_mark.line + 1
    for step in [*path, *([key] if key is not None else [])]:
        if isinstance(node, yaml.MappingNode):
            hit = [(k, v) for k, v in node.value if getattr(k, "value", None) == step]
            if not hit:
                break
            k, node = hit[0]
            line = (k if step == key else node).start_mark.line + 1
        elif isinstance(node, yaml.SequenceNode) and isinstance(step, int):
            if not 0 <= step < len(node.value):
                break
            node = node.value[step]
            line = node.start_mark.line + 1
        else:
            break
    return line


def _schema_problems(data: Any) -> list[tuple[list, str]]:
    """``(path, message)`` for each place the document breaks ``recipes/schema.json``."""
    import jsonschema

    from ptailor.schema import recipe_schema

    validator = jsonschema.Draft202012Validator(recipe_schema())
    out = []
    for err in sorted(validator.iter_errors(data), key=lambda e: list(map(str, e.path))):
        path = list(err.absolute_path)
        where = "".join(
            f"[{p + 1 if path[:1] == ['steps'] and i == 1 else p}]"
            if isinstance(p, int)
            else (f".{p}" if i else p)
            for i, p in enumerate(path)
        )
        out.append((path, f"{where or 'recipe'}: {err.message} (schema)"))
    return out


def recipe_problems(text: str, *, source: str = "<string>") -> list[Problem]:
    """Every problem of a recipe's text, each with its line: the schema's and the rules'.

    The operations' own rules (:func:`validate`) are the authority; a schema complaint about
    a place the rules already reported is not repeated.

    Parameters
    ----------
    text : str
    source : str
        Shown with each problem.

    Returns
    -------
    list of Problem
        Sorted by line; empty for a valid recipe.
    """
    import yaml

    try:
        root = yaml.compose(text, Loader=yaml.SafeLoader)
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        return [Problem(source, mark.line + 1 if mark else None, f"YAML syntax error: {problem}")]
    _, rule_msgs = validate(data)
    found = []
    seen_paths = []
    for msg in rule_msgs:
        path, key = _path_of(msg)
        seen_paths.append(path)
        found.append(Problem(source, _line_of(root, path, key), msg))
    if isinstance(data, dict) or data is None:
        for path, msg in _schema_problems(data if data is not None else {}):
            covered = any(path[: len(p)] == p or p[: len(path)] == path for p in seen_paths if p)
            if not covered:
                found.append(Problem(source, _line_of(root, path, None), msg))
    return sorted(found, key=lambda p: p.line or 0)
