"""Points of measure in a run's report: ``measures`` (before and after) and ``expect`` (the
recipe's expectations judged on the result).

A run measures the garment as read (:func:`measures_before`, which also refuses a recipe
that expects a measure the garment lacks) and the adjusted garment, the edited drape with
the adjusted pattern (:func:`measures_after`); :func:`expect_records` judges the recipe's
``expect:`` on them and :func:`missed_lines` says what missed, one line per measure (the
CLI's stderr, exit 3; a batch's ``expect`` gate).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from ptailor.errors import PtailorError
from ptailor.model.garment import Garment
from ptailor.model.units import CM_PER
from ptailor.recipe.expect import Expectation, percent
from ptailor.recipe.spec import Recipe

#: how the report's sides are named
SIDES = ("drape", "pattern")


def garment_measure_dicts(g: Garment) -> list[dict]:
    """The garment's points of measure as the report writes them (cm:
    :func:`ptailor.measures.measure_dicts`)."""
    from ptailor.measures import garment_measures, measure_dicts

    return measure_dicts(garment_measures(g), g.units)


def measures_before(g: Garment, recipe: Recipe, *, shown: str) -> list[dict]:
    """The measures of the garment as read, checked against the recipe's ``expect:``.

    Parameters
    ----------
    g : Garment
        The garment as read (before any step).
    recipe : Recipe
    shown : str
        The garment's path, as an error names it.

    Returns
    -------
    list of dict
        :func:`garment_measure_dicts` of ``g``.

    Raises
    ------
    PtailorError
        The recipe expects a measure the garment lacks and does not mark it ``optional``
        (exit 2, before any work), naming the recipe, the measures and what the garment
        has.
    """
    before = garment_measure_dicts(g)
    have = [d["name"] for d in before]
    lacking = [e.name for e in recipe.expect if e.name not in have and not e.optional]
    if lacking:
        raise PtailorError(
            f"expect: {shown} has no {', '.join(lacking)} "
            f"(its measures: {', '.join(have) or 'none'})",
            path=recipe.source,
        )
    return before


def measures_section(before: list[dict], after: list[dict]) -> dict:
    """The report's ``measures``: ``{"units": "cm", "before": [...], "after": [...]}``."""
    return {"units": "cm", "before": before, "after": after}


def _sides(d: dict | None) -> dict[str, float | None]:
    return {s: (d.get(s) if d is not None else None) for s in SIDES}


def _r(x: float | None) -> float | None:
    return None if x is None else round(float(x), 4)


def expect_record(e: Expectation, before: dict | None, after: dict | None, *, units: str) -> dict:
    """One expectation judged: the report's ``expect[i]``.

    Parameters
    ----------
    e : Expectation
    before, after : dict
        The measure's dict (cm) on the garment as read (None: the garment lacks it, only
        where ``e`` is optional: skipped), and on the adjusted garment (None: the adjusted
        garment lacks it, a miss).
    units : str
        The recipe's units (``e``'s lengths are in them).

    Returns
    -------
    dict
        ``name``, ``on``, ``asked`` (``{"by": cm}``, ``{"by": "N%"}`` or ``{"to": cm}``),
        ``tol`` (cm, or ``"N%"`` of the target), ``before``, ``target`` and ``achieved``
        (``{"drape", "pattern"}`` in cm; achieved None where the adjusted garment lacks the
        measure), ``ok`` and ``missed`` (the sides of ``on`` out of tolerance); an optional
        one also ``optional: true`` and ``skipped`` (true where the garment as read lacks
        the measure: ``before``, ``target`` and ``achieved`` null, ``ok``).
    """
    k = CM_PER[units]
    if e.to is not None:
        asked: dict[str, Any] = {"to": _r(e.to * k)}
    else:
        asked = {"by": e.by if percent(e.by) is not None else _r(float(e.by or 0.0) * k)}
    head = {
        "name": e.name,
        "on": e.on,
        "asked": asked,
        "tol": e.tol if percent(e.tol) is not None else _r(float(e.tol) * k),
    }
    if e.optional and before is None:
        none = dict.fromkeys(SIDES)
        return {**head, "before": none, "target": none, "achieved": none, "ok": True,
                "missed": [], "optional": True, "skipped": True}  # fmt: skip
    b, a = _sides(before), _sides(after)
    target = {s: e.target(float(b[s]), k) for s in SIDES}
    missed = [
        s
        for s in e.sides
        if a[s] is None or abs(float(a[s]) - target[s]) > e.tolerance(target[s], k)
    ]
    return {
        **head,
        "before": {s: _r(b[s]) for s in SIDES},
        "target": {s: _r(target[s]) for s in SIDES},
        "achieved": {s: _r(a[s]) for s in SIDES},
        "ok": not missed,
        "missed": missed,
    } | ({"optional": True, "skipped": False} if e.optional else {})


def expect_records(recipe: Recipe, before: Sequence[dict], after: Sequence[dict]) -> list[dict]:
    """The report's ``expect``: each of the recipe's expectations judged
    (:func:`expect_record`; an optional one the garment as read lacks, skipped), in the
    recipe's order."""
    b = {d["name"]: d for d in before}
    a = {d["name"]: d for d in after}
    return [
        expect_record(
            e, b.get(e.name) if e.optional else b[e.name], a.get(e.name), units=recipe.units
        )
        for e in recipe.expect
    ]


def steps_achieved(log: Sequence[dict], before: Sequence[dict], after: Sequence[dict]) -> list:
    """The report's ``steps``: each step's record, where it asked a measure (``asked`` with a
    ``measure``) or a girth over named girths (``measures``), with the pattern's value after
    the flatten added to its ``achieved`` (cm; after every step: a later step acting on the
    same measure moves it too).

    - A step asked in a measure: ``achieved.pattern`` is that measure's pattern value.
    - A girth (``loosen``/``tighten`` ``girth:``): ``achieved.measures`` is the change
      ``{drape, pattern}`` (before to after) of each named girth in its region (its sections,
      such as the chest, else its openings), and ``achieved.pattern`` their mean pattern
      change.

    Parameters
    ----------
    log : sequence of dict
        The steps' records (not changed: changed copies are returned).
    before, after : sequence of dict
        The garment's measures as read and adjusted (:func:`garment_measure_dicts`).

    Returns
    -------
    list of dict
    """
    b = {d["name"]: d for d in before}
    a = {d["name"]: d for d in after}
    out = []
    for rec in log:  # a loop over a recipe's steps
        asked = rec.get("asked")
        if not isinstance(asked, dict) or not isinstance(rec.get("achieved"), dict):
            out.append(rec)
            continue
        got = dict(rec["achieved"])
        name = asked.get("measure")
        if name in a:
            got["pattern"] = a[name]["pattern"]
        names = [n for n in rec.get("measures", ()) if n in a and n in b]
        if "girth" in asked and names:
            change = {n: {s: _r(a[n][s] - b[n][s]) for s in ("drape", "pattern")} for n in names}
            got["pattern"] = _r(sum(c["pattern"] for c in change.values()) / len(change))
            got["measures"] = change
        out.append({**rec, "achieved": got})
    return out


def lost_measures(before: Sequence[dict], after: Sequence[dict]) -> list[str]:
    """A warning when points of measure the garment had are absent after the adjustment (its
    openings or panels are no longer found as they were: a waist named hem, a sleeve lost),
    and which; none when every one is still there.

    Examples
    --------
    >>> lost_measures([{"name": "waist"}, {"name": "hem"}], [{"name": "hem"}])[0][:47]
    'points of measure lost in the adjustment: waist'
    >>> lost_measures([{"name": "hem"}], [{"name": "hem"}])
    []
    """
    have = {d["name"] for d in after}
    gone = [d["name"] for d in before if d["name"] not in have]
    if not gone:
        return []
    return [
        f"points of measure lost in the adjustment: {', '.join(gone)} (the adjusted "
        "garment's openings or panels are not found as they were: check the drape)"
    ]


def _asked_text(rec: dict) -> str:
    asked = rec.get("asked") or {}
    if "to" in asked:
        return f"{asked['to']:g} cm"
    by = asked.get("by")
    p = percent(by)
    if p is not None:
        return f"{p:+g}%"
    return f"{by:+g} cm" if isinstance(by, int | float) else str(by)


def missed_line(rec: dict) -> str:
    """One missed expectation in words: ``hem: asked +10% (pattern 207.3 cm), achieved drape
    207.1, pattern 201.0 (tol 0.5 cm)``."""
    missed = rec.get("missed") or []
    target, achieved = rec.get("target") or {}, rec.get("achieved") or {}
    on = [s for s in SIDES if rec.get("on") in (s, "both")]
    targets = ", ".join(f"{s} {target.get(s, 0.0):.1f} cm" for s in missed)
    if all(achieved.get(s) is None for s in on):
        got = f"the adjusted garment has no {rec.get('name')}"
    else:
        got = "achieved " + ", ".join(
            f"{s} {achieved[s]:.1f}" if achieved.get(s) is not None else f"{s} none" for s in on
        )
    tol = rec.get("tol")
    tol_text = tol if isinstance(tol, str) else f"{tol:g} cm"
    return f"{rec.get('name')}: asked {_asked_text(rec)} ({targets}), {got} (tol {tol_text})"


def missed_lines(report: dict) -> list[str]:
    """One line per expectation the report's result missed (:func:`missed_line`), in the
    recipe's order; none without ``expect``."""
    recs = report.get("expect")
    if not isinstance(recs, list):
        return []
    return [missed_line(r) for r in recs if isinstance(r, dict) and not r.get("ok")]
