"""Recipes: YAML edit recipes (format 1), validated whole before any garment is read."""

from __future__ import annotations

import re
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from ptailor import tolerances as tol
from ptailor.edits import OPERATIONS
from ptailor.edits.checks import (
    boolean,
    choice,
    direction_problem,
    is_number,
    number,
    show,
    vector3,
)
from ptailor.errors import PtailorError, RecipeError
from ptailor.model.units import CM_PER, UNITS

FLATTEN_PARAMS = {
    "method": (choice("scale-preserving", "uniform"), "scale-preserving"),
    "intrinsic": (choice("polar", "paper"), "polar"),
    "boundary": (choice("auto", "similar", "free"), "auto"),
    "seams": (choice("ease", "free", "keep"), "ease"),
    "w_pin": (number(gt=0.0), tol.W_PIN),
    "w_asap": (number(gt=0.0), tol.W_ASAP),
    "max_iter": (number(ge=1, le=10000, integer=True), tol.ARAP_MAX_ITER),
}
TOP_KEYS = ("format", "units", "up", "front", "symmetric", "steps", "flatten")
#: A step key every operation accepts (see :mod:`ptailor.edits.mirror`).
STEP_KEYS = ("symmetric",)
AXIS_NAMES = ("x", "y", "z", "-x", "-y", "-z")
#: Step parameters that are lengths an edit adds or removes (bounded by
#: :data:`ptailor.tolerances.RECIPE_MAX_LENGTH_CM`).
LENGTH_PARAMS = {
    "extend": ("by", "clearance"),
    "shorten": ("by",),
    "loosen": ("by",),
    "tighten": ("by",),
}
#: Step parameters that are directions when given as ``[x, y, z]``: (op, path in the step).
DIRECTION_PARAMS = {
    "cut": (("plane", "normal"), ("view",)),
    "loosen": (("view",),),
    "tighten": (("view",),),
}
DEFAULT_UP, DEFAULT_FRONT = "y", "z"


def axes_problem(
    up: Any, front: Any, *, up_name: str = "up", front_name: str = "front"
) -> str | None:
    """Why ``up`` and ``front`` (axis names, or None for the default) cannot be a frame.

    The one rule of recipes (``up:``, ``front:``) and of the command line (``--up``,
    ``--front``): both must be axis names, and not parallel (``y`` and ``-y`` are).
    ``None`` stands for the default (y up, z front).
    """
    u = DEFAULT_UP if up is None else up
    f = DEFAULT_FRONT if front is None else front
    if u not in AXIS_NAMES or f not in AXIS_NAMES:
        return None  # reported by the choice check
    if u[-1] == f[-1]:
        uu = f"{up_name} {u}" + (" (the default)" if up is None else "")
        ff = f"{front_name} {f}" + (" (the default)" if front is None else "")
        return f"{ff} is parallel to {uu}: up and front must be different axes"
    return None


def resolve_axes(
    up: str | None, front: str | None, recipe: Recipe | None = None
) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """The run's ``(up, front)`` vectors: the command line's, else the recipe's, else y, z.

    Raises
    ------
    PtailorError
        When they are parallel (the same rule as a recipe's ``up``/``front``).
    """
    u = up or (recipe.up if recipe else None)
    f = front or (recipe.front if recipe else None)
    bad = axes_problem(
        u,
        f,
        up_name="--up" if up else "up",
        front_name="--front" if front else "front",
    )
    if bad:
        raise PtailorError(bad)
    return axis_vector(u or DEFAULT_UP), axis_vector(f or DEFAULT_FRONT)


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
            probs.append(f"unknown key {show(k)} (known: {', '.join(TOP_KEYS)})")
    fmt = data.get("format", 1)
    if isinstance(fmt, bool) or fmt != 1:
        probs.append(f"format: only format 1 is known, got {show(fmt)}")
    units = data.get("units", "cm")
    probs += choice(*UNITS)(units, "units")
    for k in ("up", "front"):
        if k in data:
            probs += choice(*AXIS_NAMES)(data[k], k)
    bad_axes = axes_problem(data.get("up"), data.get("front"))
    if bad_axes:
        # on the key the recipe set (front when it set both, or only front)
        key = "front" if "front" in data else "up"
        probs.append(f"{key}: " + bad_axes.removeprefix(f"{key} "))
    symmetric = data.get("symmetric", False)
    probs += boolean(symmetric, "symmetric")
    steps_in = data.get("steps", [])
    if steps_in is None:
        steps_in = []
    steps: list[dict] = []
    if not isinstance(steps_in, list):
        probs.append("steps: expected a list of steps")
        steps_in = []
    if len(steps_in) > tol.RECIPE_MAX_STEPS:
        probs.append(
            f"steps: {len(steps_in)} steps, more than {tol.RECIPE_MAX_STEPS} "
            "(ptailor.tolerances.RECIPE_MAX_STEPS)"
        )
        steps_in = []
    for i, st in enumerate(steps_in, start=1):
        where = f"steps[{i}]"
        start = len(probs)
        if not isinstance(st, dict) or "op" not in st:
            probs.append(f"{where}: expected a mapping with 'op'")
            continue
        op = OPERATIONS.get(st["op"]) if isinstance(st["op"], str) else None
        if op is None:
            probs.append(
                f"{where}.op: unknown op {show(st['op'])} (known: {', '.join(OPERATIONS)})"
            )
            continue
        full = {"op": op.name}
        known = [*op.params, *(k for k in STEP_KEYS if k not in op.params)]
        for k in st:
            if k != "op" and k not in known:
                probs.append(
                    f"{where}: unknown key {show(k)} for {op.name} (known: {', '.join(known)})"
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
        if len(probs) == start:  # only this step's problems were added since its start
            probs += _sizes(full, where, units)
        if op.check is not None and len(probs) == start:
            probs += op.check(full, where)
        steps.append(full)
    fl_in = data.get("flatten")
    if fl_in is None:  # absent or null; 0, false, '' and [] are not mappings
        fl_in = {}
    flatten: dict = {}
    if not isinstance(fl_in, dict):
        probs.append("flatten: expected a mapping")
        fl_in = {}
    for k in fl_in:
        if k not in FLATTEN_PARAMS:
            probs.append(f"flatten: unknown key {show(k)} (known: {', '.join(FLATTEN_PARAMS)})")
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


def _sizes(step: dict, where: str, units: Any) -> list[str]:
    """Lengths within :data:`~ptailor.tolerances.RECIPE_MAX_LENGTH_CM`; directions usable."""
    probs = []
    cm = CM_PER.get(units, 1.0) if isinstance(units, str) else 1.0
    limit = tol.RECIPE_MAX_LENGTH_CM / cm
    for k in LENGTH_PARAMS.get(step["op"], ()):
        x = step.get(k)
        if is_number(x) and abs(x) > limit:
            probs.append(
                f"{where}.{k}: {x} is longer than {limit:g} {units} "
                f"({tol.RECIPE_MAX_LENGTH_CM:g} cm; ptailor.tolerances.RECIPE_MAX_LENGTH_CM)"
            )
    for path in DIRECTION_PARAMS.get(step["op"], ()):
        x: Any = step
        for k in path:
            x = x.get(k) if isinstance(x, dict) else None
        if isinstance(x, list) and not vector3(x, where):
            bad = direction_problem(x, f"{where}." + ".".join(path))
            if bad:
                probs.append(bad)
    return probs


def one_line(message: str, limit: int = 400) -> str:
    """``message`` on one printable line of at most ``limit`` characters."""
    out = "".join(
        c if c.isprintable() else c.encode("unicode_escape").decode("ascii") for c in message
    )
    return out if len(out) <= limit else out[: limit - 3] + "..."


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

    def __post_init__(self) -> None:
        object.__setattr__(self, "message", one_line(self.message))

    def __str__(self) -> str:
        return (
            f"{self.source}:{self.line}: {self.message}"
            if self.line
            else (f"{self.source}: {self.message}")
        )


class RecipeProblemsError(RecipeError):
    """A recipe's problems, each shown as ``FILE:LINE: WHERE: PROBLEM`` on one line.

    ``problems`` holds the messages (``steps[2].by: ...``), ``located`` the
    :class:`Problem` records with their lines.
    """

    def __init__(self, located: list[Problem], *, path: str | None = None) -> None:
        super().__init__([p.message for p in located], path=path)
        self.located = list(located)

    def __str__(self) -> str:
        return "; ".join(str(p) for p in self.located)


def parse_recipe(text: str, *, source: str = "<string>") -> Recipe:
    """Parse and validate recipe text: the same checks as ``ptailor validate``.

    Raises
    ------
    RecipeError
        Listing every problem (:func:`recipe_problems`: the YAML reader's limits, the
        schema, the operations' rules), each with its line.
    """
    probs, data = _problems_and_data(text, source=source)
    if probs:
        raise RecipeProblemsError(probs, path=source)
    recipe, rule_msgs = validate(data)
    if rule_msgs or recipe is None:  # pragma: no cover - recipe_problems saw them
        raise RecipeError(rule_msgs, path=source)
    return replace(recipe, source=source)


def read_recipe_text(path: str | Path) -> str:
    """A recipe file's text (``-``: standard input), refusing one over the size limit.

    The size is checked before anything is parsed: at most
    :data:`ptailor.tolerances.RECIPE_MAX_BYTES` plus one bytes are read.

    Raises
    ------
    PtailorError
        A missing, unreadable, too large or non-UTF-8 file.
    """
    import sys

    limit = tol.RECIPE_MAX_BYTES
    name = "<stdin>" if str(path) == "-" else str(path)
    try:
        if str(path) == "-":
            stream = getattr(sys.stdin, "buffer", None)
            raw = stream.read(limit + 1) if stream is not None else None
            if raw is None:
                txt = sys.stdin.read(limit + 1)
                raw = txt.encode("utf-8", "surrogatepass")
        else:
            with open(path, "rb") as fh:
                raw = fh.read(limit + 1)
    except FileNotFoundError:
        raise PtailorError("no such file", path=name) from None
    except OSError as exc:
        raise PtailorError(f"cannot read recipe ({exc.strerror or exc})", path=name) from None
    if len(raw) > limit:
        raise PtailorError(
            f"recipe larger than {limit} bytes (ptailor.tolerances.RECIPE_MAX_BYTES); "
            "recipes are short YAML files",
            path=name,
        )
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise PtailorError(f"not UTF-8 text (byte {exc.start}: {exc.reason})", path=name) from None
    return text.removeprefix("\ufeff")


def load_recipe(path: str | Path) -> Recipe:
    """Read and validate a recipe file (``-`` reads standard input)."""
    name = "<stdin>" if str(path) == "-" else str(path)
    return parse_recipe(read_recipe_text(path), source=name)


# --- reading YAML with bounded work -------------------------------------------------------


class _YamlLimitError(Exception):
    """A recipe's YAML over one of the reader's limits (a problem with its line)."""

    def __init__(self, line: int | None, message: str) -> None:
        super().__init__(message)
        self.line = line
        self.message = message


def _loader_class():
    """The recipe loader: libyaml's safe loader when available (linear, fast), with the
    constructors that can raise or run away (long ints, bad dates, explicit tags on the
    wrong scalars) turned into YAML errors with their line. Only safe tags are known:
    ``!!python/object`` and every other unknown tag stays an error."""
    import yaml

    base = getattr(yaml, "CSafeLoader", None) or yaml.SafeLoader

    class RecipeLoader(base):  # type: ignore[misc, valid-type]
        def construct_object(self, node, deep=False):
            try:
                return super().construct_object(node, deep=deep)
            except yaml.YAMLError:
                raise
            except (ValueError, TypeError, OverflowError, ArithmeticError) as exc:
                raise yaml.constructor.ConstructorError(
                    None,
                    None,
                    f"cannot read the value {show(node.value)} ({exc})",
                    node.start_mark,
                ) from None

        def construct_yaml_int(self, node):
            value = str(node.value)
            if len(value) > tol.RECIPE_MAX_NUMBER_CHARS:
                raise yaml.constructor.ConstructorError(
                    None,
                    None,
                    f"a number of {len(value)} characters (at most "
                    f"{tol.RECIPE_MAX_NUMBER_CHARS}: ptailor.tolerances.RECIPE_MAX_NUMBER_CHARS)",
                    node.start_mark,
                )
            return super().construct_yaml_int(node)

        def construct_yaml_float(self, node):
            value = str(node.value)
            if ":" in value and len(value) > tol.RECIPE_MAX_NUMBER_CHARS:
                raise yaml.constructor.ConstructorError(
                    None, None, f"a number of {len(value)} characters", node.start_mark
                )
            return super().construct_yaml_float(node)

    # YAML 1.2 (and JSON, and the schema's editors) read 1e5 as a number; YAML 1.1 as a
    # string: a recipe's 1e-3 or 1e300 is a number here, and checked as one.
    RecipeLoader.add_implicit_resolver(
        "tag:yaml.org,2002:float",
        re.compile(r"^[-+]?(?:[0-9][0-9_]*)(?:\.[0-9_]*)?[eE][-+]?[0-9]+$"),
        list("-+0123456789"),
    )
    RecipeLoader.add_constructor("tag:yaml.org,2002:int", RecipeLoader.construct_yaml_int)
    RecipeLoader.add_constructor("tag:yaml.org,2002:float", RecipeLoader.construct_yaml_float)
    return RecipeLoader


_LOADER = None


def recipe_loader():
    """The YAML loader class recipes are read with (built once)."""
    global _LOADER
    if _LOADER is None:
        _LOADER = _loader_class()
    return _LOADER


def _check_events(text: str) -> None:
    """One linear pass over the YAML events, before anything is composed: nesting depth,
    the number of aliases, and the document's size with every alias expanded.

    Raises
    ------
    _YamlLimitError
        Over :data:`~ptailor.tolerances.RECIPE_MAX_DEPTH`,
        :data:`~ptailor.tolerances.RECIPE_MAX_ALIASES` or
        :data:`~ptailor.tolerances.RECIPE_MAX_NODES`.
    yaml.YAMLError
        A syntax error.
    """
    import yaml

    ev = yaml.events
    stack: list[list] = []  # [expanded size, anchor] of each open collection
    sizes: dict[str, int] = {}  # anchor -> expanded size of its (closed) node
    aliases = 0
    total = 0

    def line(e) -> int | None:
        return e.start_mark.line + 1 if e.start_mark is not None else None

    def bump(n: int, e) -> None:
        nonlocal total
        if stack:
            stack[-1][0] += n
        total += n
        if total > tol.RECIPE_MAX_NODES:
            raise _YamlLimitError(
                line(e),
                f"the document holds more than {tol.RECIPE_MAX_NODES} values with its "
                "aliases expanded (ptailor.tolerances.RECIPE_MAX_NODES)",
            )

    loader = recipe_loader()(text)
    try:
        while loader.check_event():
            e = loader.get_event()
            if isinstance(e, ev.AliasEvent):
                aliases += 1
                if aliases > tol.RECIPE_MAX_ALIASES:
                    raise _YamlLimitError(
                        line(e),
                        f"more than {tol.RECIPE_MAX_ALIASES} YAML aliases "
                        "(ptailor.tolerances.RECIPE_MAX_ALIASES)",
                    )
                if e.anchor not in sizes:
                    if any(a == e.anchor for _, a in stack):
                        raise _YamlLimitError(
                            line(e), f"the alias *{e.anchor} refers to a node that contains it"
                        )
                    raise _YamlLimitError(line(e), f"the alias *{e.anchor} has no anchor before it")
                bump(sizes[e.anchor], e)  # the expanded copy counts in full
            elif isinstance(e, ev.ScalarEvent):
                if e.anchor is not None:
                    sizes[e.anchor] = 1
                bump(1, e)
            elif isinstance(e, (ev.SequenceStartEvent, ev.MappingStartEvent)):
                if len(stack) >= tol.RECIPE_MAX_DEPTH:
                    raise _YamlLimitError(
                        line(e),
                        f"nested more than {tol.RECIPE_MAX_DEPTH} deep "
                        "(ptailor.tolerances.RECIPE_MAX_DEPTH)",
                    )
                bump(1, e)  # the collection itself, counted in its parent
                stack.append([1, e.anchor])
            elif isinstance(e, (ev.SequenceEndEvent, ev.MappingEndEvent)):
                n, anchor = stack.pop()
                if anchor is not None:
                    sizes[anchor] = n
                if stack:
                    stack[-1][0] += n - 1  # its contents (itself was counted at its start)
    finally:
        loader.dispose()


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


def _line_of(node: Any, path: list, key: str | None, index: dict | None = None) -> int | None:
    """Line of the YAML node at ``path`` (or of ``key`` under it), as deep as it exists.

    ``index`` caches each mapping's keys (so many problems cost linear time).
    """
    import yaml

    if node is None:
        return None
    if index is None:
        index = {}
    line = node.start_mark.line + 1
    for step in [*path, *([key] if key is not None else [])]:
        if isinstance(node, yaml.MappingNode):
            keys = index.get(id(node))
            if keys is None:
                keys = {}
                for k, v in node.value:
                    keys.setdefault(str(getattr(k, "value", None)), (k, v))
                index[id(node)] = keys
            hit = keys.get(str(step))
            if hit is None:
                break
            k, node = hit
            line = (k if step == key else node).start_mark.line + 1
        elif isinstance(node, yaml.SequenceNode) and isinstance(step, int):
            if not 0 <= step < len(node.value):
                break
            node = node.value[step]
            line = node.start_mark.line + 1
        else:
            break
    return line


_VALIDATOR = None


def _schema_problems(data: Any) -> list[tuple[list, str]]:
    """``(path, message)`` for each place the document breaks ``recipes/schema.json``."""
    import jsonschema

    from ptailor.schema import recipe_schema

    global _VALIDATOR
    if _VALIDATOR is None:
        _VALIDATOR = jsonschema.Draft202012Validator(recipe_schema())
    validator = _VALIDATOR
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


def _duplicate_keys(root: Any) -> list[tuple[int, str]]:
    """``(line, message)`` for each key written twice in one mapping (YAML keeps the last
    silently; a recipe with ``by`` twice is ambiguous). Each node is visited once."""
    import yaml

    out = []
    seen: set[int] = set()
    todo = [root]
    while todo:
        node = todo.pop()
        if node is None or id(node) in seen:
            continue
        seen.add(id(node))
        if isinstance(node, yaml.MappingNode):
            first: dict[tuple, int] = {}
            for k, v in node.value:
                if isinstance(k, yaml.ScalarNode) and k.value != "<<":
                    ln = k.start_mark.line + 1
                    key = (k.tag, k.value)
                    if key in first:
                        out.append(
                            (ln, f"duplicate key {show(k.value)} (first on line {first[key]})")
                        )
                    else:
                        first[key] = ln
                todo += [k, v]
        elif isinstance(node, yaml.SequenceNode):
            todo += node.value
    return out


def _problems_and_data(text: str, *, source: str) -> tuple[list[Problem], Any]:
    """Every problem of a recipe's text (each with its line) and the document read."""
    import yaml

    try:
        n = len(text.encode("utf-8"))
    except UnicodeEncodeError:
        return [Problem(source, None, "not valid text (unpaired surrogates)")], None
    if n > tol.RECIPE_MAX_BYTES:
        return [
            Problem(
                source,
                None,
                f"recipe larger than {tol.RECIPE_MAX_BYTES} bytes "
                "(ptailor.tolerances.RECIPE_MAX_BYTES); recipes are short YAML files",
            )
        ], None
    text = text.removeprefix("\ufeff")
    try:
        _check_events(text)
        loader = recipe_loader()(text)
        try:
            root = loader.get_single_node()
            dups = _duplicate_keys(root)
            if dups:
                return [Problem(source, ln, msg) for ln, msg in dups], None
            data = loader.construct_document(root) if root is not None else None
        finally:
            loader.dispose()
    except _YamlLimitError as exc:
        return [Problem(source, exc.line, f"YAML: {exc.message}")], None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        return [
            Problem(source, mark.line + 1 if mark else None, f"YAML syntax error: {problem}")
        ], None
    _, rule_msgs = validate(data)
    found = []
    unknown_at: set[tuple] = set()  # mappings where the rules found unknown keys
    seen: set[tuple] = set()  # the places the rules reported
    above: set[tuple] = set()  # ... and every place above them
    index: dict = {}
    for msg in rule_msgs:
        path, key = _path_of(msg)
        if "unknown key" in msg:  # the schema's "Additional properties" there says the same
            unknown_at.add(tuple(path))
        if path:
            seen.add(tuple(path))
            above.update(tuple(path[:i]) for i in range(1, len(path) + 1))
        found.append(Problem(source, _line_of(root, path, key, index), msg))
    if isinstance(data, dict) or data is None:
        doc = data if data is not None else {}
        if isinstance(doc.get("steps"), list) and len(doc["steps"]) > tol.RECIPE_MAX_STEPS:
            doc = {k: v for k, v in doc.items() if k != "steps"}  # reported by the rules
        for path, msg in _schema_problems(doc):
            covered = (
                (tuple(path) in unknown_at and "Additional properties" in msg)
                or tuple(path) in above
                or any(tuple(path[:i]) in seen for i in range(1, len(path) + 1))
            )
            if not covered:
                found.append(Problem(source, _line_of(root, path, None, index), msg))
    return sorted(found, key=lambda p: p.line or 0), data


def recipe_problems(text: str, *, source: str = "<string>") -> list[Problem]:
    """Every problem of a recipe's text, each with its line: the reader's, the schema's and
    the rules'. ``ptailor validate`` and every command reading a recipe use this one path.

    The YAML is read with bounded work (:data:`~ptailor.tolerances.RECIPE_MAX_BYTES`,
    ``RECIPE_MAX_DEPTH``, ``RECIPE_MAX_ALIASES``, ``RECIPE_MAX_NODES``), by the safe
    loader only. The operations' own rules (:func:`validate`) are the authority; a schema
    complaint about a place the rules already reported is not repeated.

    Parameters
    ----------
    text : str
    source : str
        Shown with each problem.

    Returns
    -------
    list of Problem
        Sorted by line; empty for a valid recipe. Each message is one line.
    """
    return _problems_and_data(text, source=source)[0]
