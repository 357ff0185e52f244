"""The registry of recipe operations: their parameter specs and apply functions, by name.

Each operation is an :class:`Operation`: a parameter spec, checked when the recipe is
validated (before any garment is read), and a pure function applying the step::

    apply(state: EditState, step: dict, *, options: EditOptions) -> EditState

Operation modules register themselves with :func:`register` when imported
(:mod:`ptailor.edits` imports them all).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ptailor.edits.state import EditState

#: validate(value, where) -> list of problems
Check = Callable[[Any, str], list[str]]


@dataclass(frozen=True)
class Param:
    """One step parameter: its check, whether it is required, its default."""

    check: Check
    required: bool = False
    default: Any = None
    doc: str = ""


@dataclass(frozen=True)
class Operation:
    """A registered recipe operation."""

    name: str
    params: dict[str, Param]
    apply: Callable[..., EditState]
    doc: str = ""
    check: Callable[[dict, str], list[str]] | None = None


OPERATIONS: dict[str, Operation] = {}


def register(
    name: str,
    params: dict[str, Param],
    doc: str = "",
    *,
    check: Callable[[dict, str], list[str]] | None = None,
) -> Callable:
    """Decorator registering ``apply`` as the recipe operation ``name``.

    ``check(step, where)``, when given, validates the step as a whole (rules that tie
    parameters together) after each parameter passed its own check.
    """

    def deco(fn: Callable[..., EditState]) -> Callable[..., EditState]:
        OPERATIONS[name] = Operation(
            name=name, params=params, apply=fn, doc=doc or fn.__doc__ or "", check=check
        )
        return fn

    return deco
