"""Small reusable parameter checks for recipe validation (each returns a list of problems)."""

from __future__ import annotations

from typing import Any

from ptailor.edits import Check


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

    return check


def choice(*options: str) -> Check:
    """One of a fixed set of strings."""

    def check(x: Any, where: str) -> list[str]:
        if x not in options:
            return [f"{where}: expected one of {', '.join(options)}, got {x!r}"]
        return []

    return check


def vector3(x: Any, where: str) -> list[str]:
    """A list of three numbers."""
    if not (isinstance(x, (list, tuple)) and len(x) == 3 and all(is_number(v) for v in x)):
        return [f"{where}: expected [x, y, z], got {x!r}"]
    return []


def axis(x: Any, where: str) -> list[str]:
    """``auto`` or a non-zero 3-vector."""
    if x == "auto":
        return []
    p = vector3(x, where)
    if not p and all(v == 0 for v in x):
        return [f"{where}: axis must not be zero"]
    return p and [f"{where}: expected auto or [x, y, z], got {x!r}"]


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
