"""A recipe's expectations (``expect:``): the points of measure a result must reach.

``expect:`` maps a measure name (:data:`ptailor.measures.MEASURES`) to ``{by, to, tol,
on, optional}``: exactly one of ``by`` (a length added, in the recipe's units, or ``"N%"``
of the measure before) and ``to`` (the length it must have); ``tol`` (a length, or ``"N%"``
of the target; default :data:`~ptailor.tolerances.EXPECT_TOL_CM` cm); ``on`` (``drape``,
``pattern`` or ``both``, the default); ``optional`` (default false: a garment without the
measure is refused; true: it is skipped there, as a step's ``optional``). Checked with the
whole recipe, before any garment is read; judged on the result by :mod:`ptailor.report.expect`.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

from ptailor import tolerances as tol
from ptailor.edits.checks import boolean, number_problem, show
from ptailor.measures.table import MEASURES
from ptailor.model.units import CM_PER

#: where an expectation is judged
ON = ("drape", "pattern", "both")
#: the keys of one expectation
EXPECT_KEYS = ("by", "to", "tol", "on", "optional")
_PERCENT = re.compile(r"^\s*([-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?)\s*%\s*$")


def percent(x: Any) -> float | None:
    """``"10%"`` as ``10.0``; None for anything else (a number, ``"10"``, ``"ten %"``).

    Examples
    --------
    >>> percent("10%"), percent(" -2.5 %"), percent(10), percent("10")
    (10.0, -2.5, None, None)
    """
    if not isinstance(x, str):
        return None
    m = _PERCENT.match(x)
    return float(m.group(1)) if m else None


@dataclass(frozen=True)
class Expectation:
    """One measure a recipe expects of its result.

    Attributes
    ----------
    name : str
        A measure's name (:data:`ptailor.measures.MEASURES`).
    by : float or str or None
        The change asked: a length in the recipe's units, or ``"N%"`` of the measure
        before.
    to : float or None
        The length asked, in the recipe's units (exactly one of ``by`` and ``to``).
    tol : float or str
        How far the result may be from the target: a length in the recipe's units, or
        ``"N%"`` of the target.
    on : str
        ``drape``, ``pattern`` or ``both``.
    optional : bool
        A garment without the measure skips it (recorded as skipped) instead of being
        refused.
    """

    name: str
    by: float | str | None = None
    to: float | None = None
    tol: float | str = tol.EXPECT_TOL_CM
    on: str = "both"
    optional: bool = False

    @property
    def sides(self) -> tuple[str, ...]:
        """Where it is judged: ``("drape",)``, ``("pattern",)`` or both."""
        return ("drape", "pattern") if self.on == "both" else (self.on,)

    def target(self, before: float, cm_per_unit: float) -> float:
        """The length asked, in cm, of a measure that was ``before`` cm."""
        if self.to is not None:
            return self.to * cm_per_unit
        p = percent(self.by)
        if p is not None:
            return before * (1.0 + p / 100.0)
        return before + float(self.by or 0.0) * cm_per_unit

    def tolerance(self, target: float, cm_per_unit: float) -> float:
        """How far from ``target`` (cm) the result may be, in cm."""
        p = percent(self.tol)
        return abs(target) * p / 100.0 if p is not None else float(self.tol) * cm_per_unit

    def to_dict(self) -> dict[str, Any]:
        """``{"by" or "to", "tol", "on"}`` as the recipe gives them (defaults filled in;
        ``optional`` only where true)."""
        asked = {"to": self.to} if self.to is not None else {"by": self.by}
        return {**asked, "tol": self.tol, "on": self.on} | (
            {"optional": True} if self.optional else {}
        )


def expect_problems(x: Any, *, units: Any) -> tuple[tuple[Expectation, ...], list[str]]:
    """A recipe's ``expect:`` as expectations, and its problems (``expect.hem.by: ...``).

    Parameters
    ----------
    x : object
        The document's ``expect`` value (None: none).
    units : object
        The recipe's ``units`` (lengths are in it; a bad unit is reported elsewhere).

    Returns
    -------
    expectations : tuple of Expectation
        Empty when there are problems.
    problems : list of str
    """
    if x is None:
        return (), []
    if not isinstance(x, dict):
        what = "a mapping of measure names to {by or to, tol, on, optional}"
        return (), [f"expect: expected {what}, got {show(x)}"]
    cm = CM_PER.get(units, 1.0) if isinstance(units, str) else 1.0
    out: list[Expectation] = []
    probs: list[str] = []
    for name, spec in x.items():  # a loop over the recipe's measures
        if not isinstance(name, str) or name not in MEASURES:
            probs.append(f"expect: unknown measure {show(name)} (known: {', '.join(MEASURES)})")
            continue
        e, bad = _expectation(name, spec, cm=cm)
        probs += bad
        if e is not None:
            out.append(e)
    return (tuple(out) if not probs else ()), probs


def _expectation(name: str, spec: Any, *, cm: float) -> tuple[Expectation | None, list[str]]:
    """One measure's expectation (lengths in the recipe's units: ``cm`` per unit), or its
    problems."""
    where = f"expect.{name}"
    if not isinstance(spec, dict):
        what = "a mapping with by or to (and tol, on, optional)"
        return None, [f"{where}: expected {what}, got {show(spec)}"]
    probs = [
        f"{where}: unknown key {show(k)} (known: {', '.join(EXPECT_KEYS)})"
        for k in spec
        if k not in EXPECT_KEYS
    ]
    if ("by" in spec) == ("to" in spec):
        probs.append(f"{where}: give exactly one of by and to")
    longest = tol.RECIPE_MAX_LENGTH_CM / cm
    if "by" in spec:
        probs += _length_or_percent(spec["by"], f"{where}.by", longest=longest, least=-100.0)
    if "to" in spec:
        probs += _length_or_percent(spec["to"], f"{where}.to", longest=longest, percent_ok=False)
    if "tol" in spec:
        probs += _length_or_percent(spec["tol"], f"{where}.tol", longest=longest, least=0.0)
    on = spec.get("on", "both")
    if not isinstance(on, str) or on not in ON:
        probs.append(f"{where}.on: expected one of {', '.join(ON)}, got {show(on)}")
    probs += boolean(spec.get("optional", False), f"{where}.optional")
    if probs:
        return None, probs
    return Expectation(
        name=name,
        by=spec.get("by"),
        to=spec.get("to"),
        tol=spec.get("tol", tol.EXPECT_TOL_CM / cm),
        on=on,
        optional=spec.get("optional", False),
    ), []


def _length_or_percent(
    x: Any, where: str, *, longest: float, least: float | None = None, percent_ok: bool = True
) -> list[str]:
    """A length within +-``longest`` (``to``: above 0; ``tol``: at least 0), or where
    ``percent_ok`` a ``"N%"`` with N above ``least`` (``by``: above -100; ``tol``: at
    least 0)."""
    p = percent(x) if percent_ok else None
    if p is not None:
        if not abs(p) <= tol.RECIPE_NUMBER_MAX:
            return [f"{where}: {show(x)} is out of range"]
        if least is not None and (p < least or (least < 0 and p == least)):
            return [f"{where}: {show(x)} must be {'above' if least < 0 else 'at least'} {least:g}%"]
        return []
    what = "a length or N%" if percent_ok else "a length"
    if isinstance(x, str):
        return [f"{where}: expected {what}, got {show(x)}"]
    bad = number_problem(x, where)
    if bad:
        return [bad.replace("a number", what)]
    if abs(x) > longest:
        limit = "ptailor.tolerances.RECIPE_MAX_LENGTH_CM"
        return [f"{where}: {x} is longer than {longest:g} ({limit})"]
    if not percent_ok and not x > 0:
        return [f"{where}: must be > 0, got {x}"]
    if least is not None and least >= 0 and x < least:
        return [f"{where}: must be >= {least:g}, got {x}"]
    return []
