"""Small reusable parameter checks for recipe validation (each returns a list of problems).

Each check carries ``schema``: the JSON Schema fragment of what it accepts, from which
``recipes/schema.json`` is generated (:mod:`ptailor.recipe.schema`). The checks stay the
authority (they also check what a schema cannot say: a zero axis, min above max).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ptailor import tolerances as tol
from ptailor.edits.parts import PARTS
from ptailor.edits.registry import Check

#: Every recipe number lies within +-this (:data:`ptailor.tolerances.RECIPE_NUMBER_MAX`).
BIG = tol.RECIPE_NUMBER_MAX
#: ``[x, y, z]``
VEC3 = {
    "type": "array",
    "items": {"type": "number", "minimum": -BIG, "maximum": BIG},
    "minItems": 3,
    "maxItems": 3,
}


def show(x: Any) -> str:
    """``repr(x)`` cut to a readable length (a message stays one short line)."""
    try:
        r = repr(x)
    except (RecursionError, ValueError):  # pragma: no cover - bounded documents
        r = f"<{type(x).__name__}>"
    n = tol.RECIPE_SHOW_CHARS
    return r if len(r) <= n else r[: n - 3] + "..."


def with_schema(fragment: dict) -> Callable[[Check], Check]:
    """Decorator: attach a JSON Schema fragment to a check as ``check.schema``."""

    def attach(fn: Check) -> Check:
        fn.schema = fragment  # type: ignore[attr-defined]
        return fn

    return attach


def is_number(x: Any) -> bool:
    """A finite int or float (not a bool) within +-:data:`BIG`."""
    if isinstance(x, bool) or not isinstance(x, (int, float)):
        return False
    return -BIG <= x <= BIG  # False for NaN and the infinities


def number_problem(x: Any, where: str, *, big: float = BIG) -> str | None:
    """Why ``x`` is not a recipe number within +-``big`` (None when it is one)."""
    if isinstance(x, bool) or not isinstance(x, (int, float)):
        return f"{where}: expected a number, got {show(x)}"
    if x != x or x in (float("inf"), float("-inf")):
        return f"{where}: expected a finite number, got {x}"
    if not -big <= x <= big:
        return f"{where}: {show(x)} is out of range (recipe numbers lie within +-{big:g})"
    return None


def number(
    *,
    gt: float | None = None,
    ge: float | None = None,
    le: float | None = None,
    integer: bool = False,
) -> Check:
    """A finite number within bounds (and within +-:data:`BIG` unless ``le`` is above it:
    flatten weights go to 1e9).

    ``gt=0`` (a positive size or factor) also refuses values below
    :data:`ptailor.tolerances.RECIPE_POSITIVE_MIN`: a factor of 5e-324 is not a scale.
    ``integer`` asks for an int.
    """
    if gt == 0 and ge is None:
        ge = tol.RECIPE_POSITIVE_MIN
    if le is None:
        le = BIG

    def check(x: Any, where: str) -> list[str]:
        bad = number_problem(x, where, big=max(BIG, le))
        if bad:
            return [bad]
        if integer and not isinstance(x, int):
            return [f"{where}: expected a whole number, got {x}"]
        if gt is not None and not x > gt:
            return [f"{where}: must be > {gt}, got {x}"]
        if ge is not None and not x >= ge:
            return [f"{where}: must be >= {ge:g}, got {x}"]
        if not x <= le:
            return [f"{where}: must be <= {le:g}, got {x}"]
        return []

    bounds = {"exclusiveMinimum": gt, "minimum": ge, "maximum": le}
    check.schema = {
        "type": "integer" if integer else "number",
        **{k: v for k, v in bounds.items() if v is not None},
    }
    if "minimum" not in check.schema and "exclusiveMinimum" not in check.schema:
        check.schema["minimum"] = -BIG
    return check


def choice(*options: str) -> Check:
    """One of a fixed set of strings."""

    def check(x: Any, where: str) -> list[str]:
        if not isinstance(x, str) or x not in options:
            return [f"{where}: expected one of {', '.join(options)}, got {show(x)}"]
        return []

    check.schema = {"enum": list(options)}
    return check


@with_schema({"type": "boolean"})
def boolean(x: Any, where: str) -> list[str]:
    """true or false."""
    return [] if isinstance(x, bool) else [f"{where}: expected true or false, got {show(x)}"]


@with_schema(VEC3)
def vector3(x: Any, where: str) -> list[str]:
    """A list of three finite numbers within +-:data:`BIG`."""
    if not (isinstance(x, (list, tuple)) and len(x) == 3):
        return [f"{where}: expected [x, y, z], got {show(x)}"]
    for i, v in enumerate(x):
        bad = number_problem(v, where)
        if bad:
            return [bad.replace(f"{where}: ", f"{where}: component {i + 1}: ", 1)]
    return []


def direction_problem(x: Any, where: str) -> str | None:
    """Why a valid ``[x, y, z]`` is no usable direction (zero, or too short to normalise)."""
    m = max(abs(v) for v in x)
    if m == 0:
        return f"{where}: axis must not be zero"
    if m < tol.RECIPE_DIRECTION_MIN:
        return (
            f"{where}: {show(list(x))} is too short to be a direction (the largest component "
            f"must be at least {tol.RECIPE_DIRECTION_MIN:g}; scale it, e.g. [0, 1, 0])"
        )
    return None


@with_schema({"anyOf": [{"const": "auto"}, VEC3]})
def axis(x: Any, where: str) -> list[str]:
    """``auto`` or a non-zero 3-vector."""
    if x == "auto":
        return []
    if not (isinstance(x, (list, tuple)) and len(x) == 3):
        return [f"{where}: expected auto or [x, y, z], got {show(x)}"]
    p = vector3(x, where)
    if p:
        return p
    d = direction_problem(x, where)
    return [d] if d else []


@with_schema(
    {
        "anyOf": [
            {"const": "all"},
            {
                "type": "object",
                "properties": {
                    "panels": {"type": "array", "items": {"type": "string"}, "minItems": 1}
                },
                "required": ["panels"],
                "additionalProperties": False,
            },
            {
                "type": "object",
                "properties": {"part": {"enum": list(PARTS)}},
                "required": ["part"],
                "additionalProperties": False,
            },
            {
                "type": "object",
                "properties": {
                    "box": {
                        "type": "object",
                        "properties": {"min": VEC3, "max": VEC3},
                        "required": ["min", "max"],
                        "additionalProperties": False,
                    }
                },
                "required": ["box"],
                "additionalProperties": False,
            },
        ]
    }
)
def region(x: Any, where: str) -> list[str]:
    """``all`` | ``{panels: [names]}`` | ``{part: torso}`` | ``{box: {min: [x,y,z], max:
    [x,y,z]}}`` (the parts: :data:`ptailor.edits.parts.PARTS`)."""
    if x == "all":
        return []
    if not isinstance(x, dict) or len(x) != 1 or next(iter(x)) not in ("panels", "part", "box"):
        return [
            f"{where}: expected all, {{panels: [...]}}, {{part: torso}} or "
            "{box: {min: ..., max: ...}}"
        ]
    if "part" in x:
        if isinstance(x["part"], str) and x["part"] in PARTS:
            return []
        return [f"{where}.part: expected one of {', '.join(PARTS)}, got {show(x['part'])}"]
    if "panels" in x:
        names = x["panels"]
        ok = isinstance(names, list) and names and all(isinstance(n, str) and n for n in names)
        return [] if ok else [f"{where}.panels: expected a non-empty list of panel names"]
    box = x["box"]
    if not isinstance(box, dict) or set(box) != {"min", "max"}:
        return [f"{where}.box: expected {{min: [x, y, z], max: [x, y, z]}}"]
    probs = vector3(box["min"], f"{where}.box.min") + vector3(box["max"], f"{where}.box.max")
    if not probs and any(a > b for a, b in zip(box["min"], box["max"], strict=True)):
        probs.append(f"{where}.box: min must not exceed max")
    return probs
