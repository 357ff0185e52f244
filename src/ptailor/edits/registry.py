"""The registry of recipe operations: their typed steps and apply functions, by name.

Each operation is an :class:`Operation`: a :class:`Step` subclass, a frozen dataclass whose
fields are the operation's parameters (each field's recipe check and description in its
metadata, :func:`checked`; its default the parameter's, the one place a default is given),
built by the recipe rules once its values passed their checks (before any garment is
read), and a pure function applying the step::

    apply(state: EditState, step: Step, *, options: EditOptions) -> EditState

Operation modules register themselves with :func:`register` when imported
(:mod:`ptailor.edits` imports them all).
"""

from __future__ import annotations

import copy
from collections.abc import Callable
from dataclasses import MISSING, Field, dataclass, field, fields
from typing import Any, ClassVar

from ptailor.edits.state import EditState

#: validate(value, where) -> list of problems
Check = Callable[[Any, str], list[str]]

#: Step fields every operation has (not parameters of their own unless one declares it
#: :func:`checked`); a step's mapping lists them after its own parameters.
COMMON_FIELDS = ("symmetric", "optional")
#: What each of :data:`COMMON_FIELDS` does (the JSON Schema's description; both booleans).
COMMON_DOCS = {
    "symmetric": "also apply the mirror image of this step",
    "optional": "skip this step, with a warning, on a garment without the panel, part, "
    "opening, seam or measure it names (one recipe for garments with and without sleeves)",
}


@dataclass(frozen=True)
class Param:
    """One step parameter as the rules and the JSON Schema see it (read off a
    :class:`Step` field by :meth:`Step.params`): its check, whether it is required, its
    default, its description."""

    check: Check
    required: bool = False
    default: Any = None
    doc: str = ""


def checked(check: Check, doc: str = "", *, echo_none: bool = True) -> dict[str, Any]:
    """The metadata that makes a :class:`Step` field a recipe parameter::

        factor: float = field(metadata=checked(number(gt=0.0)))  # required
        direction: str = field(default="uniform", metadata=checked(choice("around", ...)))

    Parameters
    ----------
    check : Check
        The recipe check of its value (with a JSON Schema fragment, see
        :mod:`ptailor.edits.checks`).
    doc : str
        Its description (the JSON Schema's).
    echo_none : bool, keyword-only
        False: :meth:`Step.to_dict` leaves the parameter out while it is None (a later
        alternative form, such as ``girth``, so the mapping of a recipe that does not use it
        stays as it was: the catalogue's recipe text and a batch's stamp).

    Returns
    -------
    dict
        ``dataclasses.field``'s ``metadata``. The field's default is the parameter's
        (no default: required).
    """
    return {"check": check, "doc": doc, "echo_none": echo_none}


def _plain(x: Any) -> Any:
    """``x`` copied as :func:`dataclasses.asdict` copies a field's value (no object shared,
    so YAML writes no anchors)."""
    if isinstance(x, dict):
        return {_plain(k): _plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return type(x)(_plain(v) for v in x)
    return copy.deepcopy(x)


@dataclass(frozen=True, kw_only=True)
class Step:
    """A validated recipe step: one frozen subclass per operation, its parameters as fields.

    The recipe rules (:mod:`ptailor.recipe.rules`) build a step once its parameters passed
    their checks; edits read its attributes. Values are kept as the recipe wrote them
    (lists, mappings, ints), so :meth:`to_dict` gives back the validated mapping.

    Attributes
    ----------
    op : str
        The operation's name (a class attribute).
    symmetric : bool
        Also apply the step's mirror image (resolved: the step's own, else the recipe's).
    optional : bool
        Skip the step on a garment that lacks what it names (an
        :class:`~ptailor.errors.AbsentError`): :func:`ptailor.pipeline.apply_steps`.
    """

    op: ClassVar[str] = ""
    symmetric: bool = False
    optional: bool = field(default=False, metadata={"echo_default": False})

    @classmethod
    def recipe_fields(cls) -> list[Field]:
        """The fields in the recipe mapping's order: the operation's own, then
        :data:`COMMON_FIELDS`."""
        own = [f for f in fields(cls) if f.name not in COMMON_FIELDS]
        return own + [f for f in fields(cls) if f.name in COMMON_FIELDS]

    @classmethod
    def params(cls) -> dict[str, Param]:
        """The operation's parameters (the fields with :func:`checked` metadata), in order."""
        out = {}
        for f in cls.recipe_fields():
            if "check" not in f.metadata:
                continue
            required = f.default is MISSING and f.default_factory is MISSING
            default = f.default if f.default is not MISSING else None
            if f.default_factory is not MISSING:
                default = f.default_factory()
            out[f.name] = Param(
                f.metadata["check"], required=required, default=default, doc=f.metadata["doc"]
            )
        return out

    def to_dict(self) -> dict[str, Any]:
        """The step as the validated recipe mapping: ``op``, every parameter (defaults
        filled in; one :func:`checked` with ``echo_none=False`` only when given),
        ``symmetric``, ``optional`` only when true: what reports and the catalogue echo."""
        out: dict[str, Any] = {"op": self.op}
        for f in self.recipe_fields():
            value = getattr(self, f.name)
            if value is None and not f.metadata.get("echo_none", True):
                continue
            if not f.metadata.get("echo_default", True) and value == f.default:
                continue  # optional: false, as every recipe written before it was
            out[f.name] = _plain(value)
        return out


@dataclass(frozen=True)
class Operation:
    """A registered recipe operation: its step type, apply function and whole-step check."""

    name: str
    step: type[Step]
    apply: Callable[..., EditState]
    doc: str = ""
    check: Callable[[Any, str], list[str]] | None = None

    @property
    def params(self) -> dict[str, Param]:
        """``step.params()``: the parameters the rules check and the schema publishes."""
        return self.step.params()


OPERATIONS: dict[str, Operation] = {}


def register(
    step: type[Step],
    *,
    doc: str = "",
    check: Callable[[Any, str], list[str]] | None = None,
) -> Callable:
    """Decorator registering ``apply`` as the recipe operation ``step.op``.

    ``check(step, where)``, when given, validates the built step as a whole (rules that tie
    parameters together) after each parameter passed its own check.
    """

    def deco(fn: Callable[..., EditState]) -> Callable[..., EditState]:
        OPERATIONS[step.op] = Operation(
            name=step.op, step=step, apply=fn, doc=doc or fn.__doc__ or "", check=check
        )
        return fn

    return deco
