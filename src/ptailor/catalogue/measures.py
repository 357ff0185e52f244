"""The catalogue's points of measure: on the index a column per measure the recipe's
``expect:`` asks about (achieved, red where missed), on a garment's page the table of every
measure before and after (the report's ``measures``) and what ``expect`` judged.
"""

from __future__ import annotations

from typing import Any

from ptailor.catalogue.rows import Row

#: a measure's sides, as the report names them
SIDES = ("drape", "pattern")


def _num(x: Any) -> float | None:
    return float(x) if isinstance(x, int | float) and not isinstance(x, bool) else None


def _text(x: Any) -> str:
    v = _num(x)
    return "-" if v is None else f"{v:.1f}"


def _expect_list(report: dict | None) -> list[dict]:
    recs = (report or {}).get("expect")
    return [r for r in recs if isinstance(r, dict)] if isinstance(recs, list) else []


def expected_names(rows: list[Row]) -> list[str]:
    """The measures some row's recipe expects, in the order they first appear."""
    names: dict[str, None] = {}
    for row in rows:  # a loop over garments
        for rec in _expect_list(row.report):
            names.setdefault(str(rec.get("name")), None)
    return list(names)


def _on(rec: dict) -> list[str]:
    return [s for s in SIDES if rec.get("on") in (s, "both")]


def expect_cell(rec: dict | None) -> dict:
    """One index cell: the achieved measure (drape / pattern, as ``on`` asks), its target
    and tolerance in the title, ``missed`` where it missed; ``data-sort`` the largest
    distance from the target (cm)."""
    if rec is None:
        return {"text": "-", "sort": "", "missed": False, "title": ""}
    if rec.get("skipped"):
        title = "optional: the garment has no such measure, skipped"
        return {"text": "skipped", "sort": "", "missed": False, "title": title}
    on = _on(rec)
    achieved, target = rec.get("achieved") or {}, rec.get("target") or {}
    misses = [
        abs(a - t)
        for s in on
        if (a := _num(achieved.get(s))) is not None and (t := _num(target.get(s))) is not None
    ]
    asked = "; ".join(f"{k} {v}" for k, v in (rec.get("asked") or {}).items())
    return {
        "text": " / ".join(_text(achieved.get(s)) for s in on),
        "sort": repr(max(misses)) if misses else "",
        "missed": not rec.get("ok"),
        "title": f"{' / '.join(on)}: asked {asked}, target "
        f"{' / '.join(_text(target.get(s)) for s in on)} cm, tol {rec.get('tol')}"
        + ("; missed" if not rec.get("ok") else ""),
    }


def expect_cells(row: Row, names: list[str]) -> list[dict]:
    """A row's cells for the measures ``names`` (:func:`expected_names`)."""
    by_name = {str(r.get("name")): r for r in _expect_list(row.report)}
    return [expect_cell(by_name.get(n)) for n in names]


def expect_columns(names: list[str]) -> list[dict]:
    """The index's headings for the measures ``names``."""
    return [
        {
            "key": f"expect:{n}",
            "label": f"{n} (cm)",
            "title": f"the recipe's expect: {n} achieved (drape / pattern), red where missed",
        }
        for n in names
    ]


def measures_view(report: dict) -> dict | None:
    """A garment page's measures: each measure before and after, in the drape and in the
    pattern (cm), the ones the recipe expects marked (``missed`` where they missed); None
    without the report's ``measures``."""
    sec = report.get("measures")
    if not isinstance(sec, dict):
        return None
    before = {str(d.get("name")): d for d in sec.get("before") or [] if isinstance(d, dict)}
    after = {str(d.get("name")): d for d in sec.get("after") or [] if isinstance(d, dict)}
    expect = {str(r.get("name")): r for r in _expect_list(report)}
    names = list(dict.fromkeys([*before, *after]))
    rows = []
    for n in names:  # a loop over measures
        b, a = before.get(n) or {}, after.get(n) or {}
        rec = expect.get(n)
        rows.append(
            {
                "name": n,
                "kind": str(b.get("kind") or a.get("kind") or ""),
                **{
                    s: f"{_text(b.get(s))} \u2192 {_text(a.get(s))}"
                    + _change(_num(b.get(s)), _num(a.get(s)))
                    for s in SIDES
                },
                "expected": rec is not None,
                "missed": rec is not None and not rec.get("ok"),
                "asked": expect_cell(rec)["title"] if rec is not None else "",
            }
        )
    return {"rows": rows}


def _change(b: float | None, a: float | None) -> str:
    if b is None or a is None:
        return ""
    return f" ({a - b:+.1f})"
