"""Steps asked in points of measure (:mod:`ptailor.measures`): the parameter that gives an
asked value, and the record of what was asked and achieved.

Three operations take a value in a pattern maker's measure instead of their own parameter::

    - {op: loosen, region: {panels: [front, back]}, girth: 2}      # +2 cm of girth
    - {op: scale, region: {panels: [front, back]}, direction: around, measure: chest, to: 110}
    - {op: scale, region: all, direction: around, measure: hip, by: 5%}
    - {op: shorten, opening: hem, measure: body_length, to: 60}

Each applies itself to its input for a first guess of its parameter, measures the result on
the edited drape and corrects the parameter by secant steps (:func:`solve`) until the
measure is within :data:`~ptailor.edits.tolerances.ASK_TOL_CM` of the asked value, so the
answer includes everything the step does (an offset's falloff, the rest of the garment
following a scale). Measures are taken with :func:`ptailor.measures.garment_measures` on
the drape (the pattern is only known after the flattening: the report measures it).

The step's record states ``asked`` (as the recipe asked, lengths in cm) and ``achieved``
(``{"drape": cm}``: the measure on the step's output drape; a ``loosen``'s girth change).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ptailor.edits import tolerances as edit_tol
from ptailor.edits.checks import BIG, number_problem, show
from ptailor.edits.registry import Check
from ptailor.edits.state import EditState
from ptailor.errors import AbsentError, PtailorError
from ptailor.measures import MEASURES, garment_measures
from ptailor.model.garment import Garment
from ptailor.model.units import factor

#: ``"N%"``: a change relative to the measure's current value (what the schema publishes).
PERCENT = re.compile(r"^[-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)%$")


def measure_names(*kinds: str) -> list[str]:
    """The measure names of some kinds (all of them with no kind), in table order."""
    return [n for n, d in MEASURES.items() if not kinds or d.kind in kinds]


def measure_check(*kinds: str, also: tuple[str, ...] = ()) -> Check:
    """A point of measure's name (:data:`ptailor.measures.MEASURES`) of one of ``kinds``
    (any kind when none), or one of the words ``also``.

    Parameters
    ----------
    *kinds : str
        ``girth``, ``length``, ``depth``.
    also : tuple of str, keyword-only
        Other accepted values (``shorten``'s ``drape`` and ``pattern``).

    Returns
    -------
    Check
        Its message names an unknown measure and lists the known ones.
    """
    names = measure_names(*kinds)
    kind = " or ".join(kinds) if kinds else "point of"

    def check(x: Any, where: str) -> list[str]:
        if isinstance(x, str) and (x in also or x in names):
            return []
        words = "".join(f"{w}, " for w in also)
        if isinstance(x, str) and x in MEASURES:
            return [
                f"{where}: {x} is a {MEASURES[x].kind}; expected {words}a {kind} measure "
                f"({', '.join(names)})"
            ]
        return [
            f"{where}: unknown measure {show(x)} (expected {words}a {kind} measure: "
            f"{', '.join(names)})"
        ]

    check.schema = {"enum": [*also, *names]}  # type: ignore[attr-defined]
    return check


def amount(x: Any, where: str) -> list[str]:
    """A length (a number, recipe units) or a change in percent (``"N%"``, above -100 %)."""
    if isinstance(x, str):
        if not PERCENT.match(x):
            return [f"{where}: expected a number or a percentage such as '10%', got {show(x)}"]
        p = float(x[:-1])
        if not -100.0 < p <= BIG:
            return [f"{where}: {x} is out of range (above -100% and at most {BIG:g}%)"]
        return []
    bad = number_problem(x, where)
    return [bad] if bad else []


amount.schema = {  # type: ignore[attr-defined]
    "anyOf": [
        {"type": "number", "minimum": -BIG, "maximum": BIG},
        {"type": "string", "pattern": PERCENT.pattern},
    ]
}


def target_value(current: float, *, to: float | None, by: float | str | None) -> float:
    """The asked value of a measure now ``current``: ``to``, or ``current`` changed ``by`` a
    length or a percentage (``"10%"``)."""
    if to is not None:
        return float(to)
    if isinstance(by, str):
        return current * (1.0 + float(by[:-1]) / 100.0)
    return current + float(by or 0.0)


def drape_garment(state: EditState) -> Garment:
    """The garment as the steps so far left it: the edited drape with the input pattern."""
    return state.base.with_drape(state.V3)


def drape_measure(state: EditState, name: str) -> float:
    """The drape value of the measure ``name`` on the edited drape, in the garment's units.

    Raises
    ------
    PtailorError
        The garment has no such measure (it lacks the landmark), naming it and the
        measures it has.
    """
    found = {m.name: m for m in garment_measures(drape_garment(state))}
    if name not in found:
        have = ", ".join(found) or "none"
        raise AbsentError(f"the garment has no measure {name!r} (it has: {have})")
    return float(found[name].drape)


def measured(state: EditState, name: str) -> float | None:
    """:func:`drape_measure`, or None where the edited garment lacks the measure."""
    try:
        return drape_measure(state, name)
    except PtailorError:
        return None


def region_girths(state: EditState, faces: np.ndarray) -> list[str]:
    """The girths (points of measure of kind ``girth``) of the edited drape that lie in the
    region (at least half of each one's line on the region's triangles ``faces``): its
    sections (chest, hip, bicep: measured at a level) where it has some, else its openings
    (hem, neck, cuff)."""
    inside = np.zeros(len(state.base.F3), dtype=bool)
    inside[faces] = True
    found = [
        m
        for m in garment_measures(drape_garment(state))
        if m.kind == "girth" and len(m.line) and inside[m.line.face].mean() >= 0.5
    ]
    sections = [m.name for m in found if m.height is not None or m.point is not None]
    return sections or [m.name for m in found]


def cm(state: EditState) -> float:
    """Multiply a length in the garment's units by this for cm."""
    return factor(state.base.units, "cm")


def ask_tolerance(state: EditState) -> float:
    """:data:`~ptailor.edits.tolerances.ASK_TOL_CM` in the garment's units."""
    return edit_tol.ASK_TOL_CM / cm(state)


@dataclass(frozen=True)
class Solved:
    """The parameter found by :func:`solve`.

    Attributes
    ----------
    x : float
        The parameter.
    out : object
        What the step gave for it.
    value : float
        Its measure.
    tries : int
        Applications of the step.
    """

    x: float
    out: Any
    value: float
    tries: int


def solve(
    run: Callable[[float], tuple[Any, float]],
    *,
    anchor: tuple[float, float],
    first: float,
    target: float,
    tol: float,
    lower: float = -np.inf,
) -> Solved:
    """The parameter ``x`` whose step gives the measure ``target``, by secant steps.

    Parameters
    ----------
    run : callable
        ``run(x) -> (out, value)``: the step applied with parameter ``x`` and the measure
        of its result.
    anchor : (float, float), keyword-only
        A known ``(x, value)``: the parameter that changes nothing and the measure now (an
        offset of 0 adds no girth; a factor of 1 keeps the measure). The first correction is
        the secant through it.
    first : float, keyword-only
        The first guess.
    target : float, keyword-only
    tol : float, keyword-only
        Stop when ``|value - target| <= tol``.
    lower : float, keyword-only
        Parameters at or below this are not tried (a step would refuse them).

    Returns
    -------
    Solved
        The best of at most :data:`~ptailor.edits.tolerances.ASK_TRIES` tries.
    """
    xa, va = anchor
    x = float(first)
    out, v = run(x)
    best, n = Solved(x, out, v, 1), 1
    while abs(v - target) > tol and n < edit_tol.ASK_TRIES and v != va:
        nxt = x + (target - v) * (x - xa) / (v - va)
        if not np.isfinite(nxt) or nxt <= lower:
            break
        xa, va, x = x, v, float(nxt)
        out, v = run(x)
        n += 1
        if abs(v - target) < abs(best.value - target):
            best = Solved(x, out, v, n)
    return Solved(best.x, best.out, best.value, n)


def asked_of(state: EditState, **asked: Any) -> dict:
    """The record's ``asked``: the given keys, lengths converted to cm (a percentage kept
    as written, a name as it is)."""
    k = cm(state)
    return {
        key: (round(float(v) * k, 6) if isinstance(v, (int, float)) else v)
        for key, v in asked.items()
        if v is not None
    }


def measure_record(
    after: EditState,
    *,
    name: str,
    asked: dict,
    current: float,
    target: float,
    tries: int,
) -> dict:
    """The record keys of a step asked in the measure ``name``.

    Parameters
    ----------
    after : EditState
        The step's output.
    name : str
    asked : dict
        :func:`asked_of`.
    current, target : float
        The measure on the step's input and the asked value, the garment's units.
    tries : int

    Returns
    -------
    dict
        ``{"asked", "before": {"drape"}, "target": {"drape"}, "achieved": {"drape"},
        "tries"}``, lengths in cm; ``achieved`` empty where the edited garment lacks the
        measure.
    """
    k = cm(after)
    now = measured(after, name)
    return {
        "asked": {"measure": name, **asked},
        "before": {"drape": round(current * k, 4)},
        "target": {"drape": round(target * k, 4)},
        "achieved": {} if now is None else {"drape": round(now * k, 4)},
        "tries": tries,
    }


def with_ask(rec: dict, keys: dict, *, what: str, target: float) -> dict:
    """A step's record with the keys of its ask, and a warning where it missed.

    Parameters
    ----------
    rec : dict
        The step's record.
    keys : dict
        :func:`measure_record` (or a loosen's ``asked``, ``achieved``); a shorten's or an
        extend's own ``achieved`` (the new edge's offsets) moves to ``edge_offset``.
    what : str
        The asked quantity, for the warning (``chest``, ``girth``).
    target : float
        The asked value, cm.

    Returns
    -------
    dict
    """
    out = dict(rec)
    if "achieved" in out:
        out["edge_offset"] = out.pop("achieved")
    out.update(keys)
    got = keys.get("achieved", {}).get("drape")
    if got is None or abs(got - target) > edit_tol.ASK_WARN_CM:
        said = "is gone" if got is None else f"reached {got:.4g} cm"
        out["warnings"] = [
            *rec.get("warnings", []),
            f"{what}: asked {target:.4g} cm, the drape's {said} after {keys.get('tries')} tries"
            " (the step moves it little or not in proportion here)",
        ]
    return out


def length_to(state: EditState, step: Any, apply: Callable, *, options: Any) -> EditState:
    """``shorten`` or ``extend`` to a length: the ``by`` that brings ``step.measure`` to
    ``step.to`` on the drape (the cut and the new rows measured on the drape: what the step
    changes; the pattern follows through the flattening).

    The first ``by`` is the difference; secant steps on the measure of the step's output
    correct it (:func:`solve`).

    Parameters
    ----------
    state : EditState
    step : ShortenStep or ExtendStep
        With ``measure`` a length measure's name and ``to``.
    apply : callable
        The operation's apply function, called with ``by``.
    options : EditOptions, keyword-only

    Returns
    -------
    EditState
        Its last record with :func:`measure_record`'s keys (the step's own ``achieved``, the
        new edge's offsets, as ``edge_offset``).

    Raises
    ------
    PtailorError
        The garment lacks the measure, or it is already that short (``shorten``) or long.
    """
    name, to = str(step.measure), float(step.to)
    current = drape_measure(state, name)
    sign = 1.0 if step.op == "shorten" else -1.0
    first = sign * (current - to)
    if not first > 0.0:
        word = "short" if step.op == "shorten" else "long"
        raise PtailorError(
            f"{step.op} {name} to {to:g}: it is {current:.4g} {state.base.units}, already as "
            f"{word} as that"
        )

    def run(by: float) -> tuple[EditState, float]:
        out = apply(state, replace(step, by=by, to=None, measure="drape"), options=options)
        return out, drape_measure(out, name)

    got = solve(
        run, anchor=(0.0, current), first=first, target=to, tol=ask_tolerance(state), lower=0.0
    )
    k = cm(state)
    keys = measure_record(
        got.out,
        name=name,
        asked=asked_of(state, to=to),
        current=current,
        target=to,
        tries=got.tries,
    )
    rec = with_ask(got.out.log[-1], keys, what=name, target=to * k)
    return replace(got.out, log=(*got.out.log[:-1], rec))
