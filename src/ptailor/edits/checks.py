"""Small reusable parameter checks for recipe validation (each returns a list of problems).

Each check carries ``schema``: the JSON Schema fragment of what it accepts, from which
``recipes/schema.json`` is generated (:mod:`ptailor.schema`). The checks stay the
authority (they also check what a schema cannot say: a zero axis, min above max).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ptailor.edits import Check

#: ``[x, y, z]``
VEC3 = {"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3}


def with_schema(fragment: dict) -> Callable[[Check], Check]:
    """Decorator: attach a JSON Schema fragment to a check as ``check.schema``."""

    def attach(fn: Check) -> Check:
        fn.schema = fragment  # type: ignore[attr-defined]
        return fn

    return attach


def is_number(x: Any) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and x == x  # NaN != NaN


def number(*, gt: float | None = None, ge: float | None = None, le: float | None = None) -> Check:
    """A finite number within bounds."""

    def check(x: Any, where: str) -> list[str]:
        if not is_number(x) or x in (float("inf"), float("-inf")):
            return [f"{where}: expected a number, got {x!r}"]
        if gt is not None and not x > gt:
            return [f"{where}: must be > {gt}, got {x}"]
        if ge is not None and not x >= ge:
            return [f"{where}: must be >= {ge}, got {x}"]
        if le is not None and not x <= le:
            return [f"{where}: must be <= {le}, got {x}"]
        return []

    bounds = {"exclusiveMinimum": gt, "minimum": ge, "maximum": le}
    check.schema = {"type": "number", **{k: v for k, v in bounds.items() if v is not None}}
    return check


def choice(*options: str) -> Check:
    """One of a fixed set of strings."""

    def check(x: Any, where: str) -> list[str]:
        if x not in options:
            return [f"{where}: expected one of {', '.join(options)}, got {x!r}"]
        return []

    check.schema = {"enum": list(options)}
    return check


@with_schema({"type": "boolean"})
def boolean(x: Any, where: str) -> list[str]:
    """true or false."""
    return [] if isinstance(x, bool) else [f"{where}: expected true or false, got {x!r}"]


@with_schema(VEC3)
def vector3(x: Any, where: str) -> list[str]:
    """A list of three numbers."""
    if not (isinstance(x, (list, tuple)) and len(x) == 3 and all(is_number(v) for v in x)):
        return [f"{where}: expected [x, y, z], got {x!r}"]
    return []


@with_schema({"anyOf": [{"const": "auto"}, VEC3]})
def axis(x: Any, where: str) -> list[str]:
    """``auto`` or a non-zero 3-vector."""
    if x == "auto":
        return []
    p = vector3(x, where)
    if not p and all(v == 0 for v in x):
        return [f"{where}: axis must not be zero"]
    return p and [f"{where}: expected auto or [x, y, z], got {x!r}"]


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
    """``all`` | ``{panels: [names]}`` | ``{box: {min: [x,y,z], max: [x,y,z]}}``."""
    if x == "all":
        return []
    if not isinstance(x, dict) or len(x) != 1 or next(iter(x)) not in ("panels", "box"):
        return [f"{where}: expected all, {{panels: [...]}} or {{box: {{min: ..., max: ...}}}}"]
    if "panels" in x:
        names = x["panels"]
        ok = isinstance(names, list) and names and all(isinstance(n, str) for n in names)
        return [] if ok else [f"{where}.panels: expected a non-empty list of panel names"]
    box = x["box"]
    if not isinstance(box, dict) or set(box) != {"min", "max"}:
        return [f"{where}.box: expected {{min: [x, y, z], max: [x, y, z]}}"]
    probs = vector3(box["min"], f"{where}.box.min") + vector3(box["max"], f"{where}.box.max")
    if not probs and any(a > b for a, b in zip(box["min"], box["max"], strict=True)):
        probs.append(f"{where}.box: min must not exceed max")
    return probs
