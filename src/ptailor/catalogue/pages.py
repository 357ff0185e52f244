"""The catalogue's pages, rendered with jinja2 (autoescaped: names, reasons and recipe text
from files show as text): ``OUT/index.html`` and each garment's ``OUT/NAME/index.html``.

The views here turn records and reports into what the templates show (display strings and
sort keys); the templates hold no logic beyond loops.
"""

from __future__ import annotations

import math
from collections import Counter
from pathlib import Path
from typing import Any
from urllib.parse import quote

from ptailor import tolerances as tol
from ptailor.batch.gates import (
    GATE_OPTIONS,
    area_change,
    p95,
    seam_mismatch,
    verify_number,
    verify_panels,
)
from ptailor.catalogue.measures import (
    expect_cells,
    expect_columns,
    expected_names,
    measures_view,
)
from ptailor.catalogue.rows import CATALOGUE_DIR, INDEX, ROW_STATUSES, Row, Summary
from ptailor.catalogue.thumbnails import PREVIEW, THUMBNAIL

#: the generator tag that marks an index.html as ptailor's (it may then be replaced)
GENERATOR = "ptailor catalogue"
#: the re-drape picture in a garment folder
VERIFY_PICTURE = "verify.png"

#: the index's number columns: (record key, heading, how it is shown, title)
COLUMNS = (
    ("panels", "panels", "int", "panels in the report"),
    ("max_area_change", "area change", "percent", "largest |area after / before - 1| of a panel"),
    ("max_intrinsic_error_p95", "scale error p95", "g3",
     "largest per-panel intrinsic-scale error, 95th percentile"),
    ("max_seam_mismatch", "seam mismatch", "g3",
     "largest |mismatch| of a seam (recipe units)"),
    ("flipped_triangles", "flips", "int", "flipped pattern triangles"),
    ("verify_stretch_p95", "re-drape stretch p95", "g4",
     "the re-drape check: worst panel's stretch p95 (1 = at rest)"),
    ("verify_displacement_p95", "re-drape displacement p95", "g3",
     "the re-drape check: worst panel's displacement p95 (recipe units)"),
    ("spec_fit_max", "spec fit", "g3", "the written specification's largest distance"),
    ("warnings", "warnings", "int", "warnings in the report"),
    ("seconds", "seconds", "g3", "the garment's time in its worker"),
)  # fmt: skip
#: the solver's fields a garment page shows
SOLVER_SHOWN = ("converged", "iterations", "newton_steps", "seam_violation", "residual")
#: columns shown only when some garment has a value
OPTIONAL_COLUMNS = frozenset({"verify_stretch_p95", "verify_displacement_p95", "spec_fit_max"})


def environment():
    """The jinja2 environment: the package's templates, autoescaped, strict."""
    import jinja2

    return jinja2.Environment(
        loader=jinja2.PackageLoader("ptailor.catalogue", "templates"),
        autoescape=True,
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
    )


# --------------------------------------------------------------------------- showing numbers


def shown_number(value: Any, how: str = "g4") -> str:
    """A number as a cell shows it (``-`` for none)."""
    if value is None or isinstance(value, bool) or not isinstance(value, int | float):
        return "-" if value is None else str(value)
    if not math.isfinite(value):
        return str(value)
    if how == "int":
        return f"{int(value)}"
    if how == "percent":
        return f"{100 * value:.3g} %"
    digits = int(how[1:]) if how[1:].isdigit() else 4
    return f"{value:.{digits}g}"


def shown(value: Any, *, limit: int = tol.CATALOGUE_SHOWN_MAX) -> str:
    """Any report value in a few words: numbers to 4 digits, lists in brackets, mappings as
    ``key: value``; cut at ``limit`` characters."""
    text = _shown(value)
    return text if len(text) <= limit else text[: limit - 1] + "\u2026"


def _shown(value: Any) -> str:
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, dict):
        return "; ".join(f"{k}: {_shown(v)}" for k, v in value.items())
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_shown(v) for v in value) + "]"
    if isinstance(value, float):
        return shown_number(value)
    return "-" if value is None else str(value)


def link(*parts: str) -> str:
    """A relative URL from path parts (each quoted: ``#``, ``?``, ``%`` and spaces too)."""
    return "/".join(quote(p, safe="") for p in parts)


# --------------------------------------------------------------------------- the index


def _sort_key(value: Any) -> str:
    """A cell's ``data-sort``: the number as text, empty for none (sorted last)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return ""
    return repr(float(value)) if math.isfinite(value) else ""


def _row_view(row: Row, columns: list[tuple], expected: list[str]) -> dict:
    r = row.record
    has_page = row.folder is not None
    has_thumb = has_page and (row.folder / THUMBNAIL).is_file()
    gates = r.get("failed_gates") or []
    return {
        "index": r.get("index"),
        "garment": str(r.get("garment")),
        "name": row.name,
        "status": row.status,
        "rank": ROW_STATUSES.index(row.status) if row.status in ROW_STATUSES else 9,
        "failure": r.get("failure") or "",
        "reason": r.get("reason") or "",
        "note": r.get("note") or "",
        "earlier_folder": row.earlier_folder,
        "rejected": row.rejected,
        "page": link(*row.parts, INDEX) if has_page else None,
        "thumbnail": link(*row.parts, THUMBNAIL) if has_thumb else None,
        "gates": " ".join(str(g) for g in gates),
        "cells": [
            {
                "text": shown_number(r.get(key), how),
                "sort": _sort_key(r.get(key)),
                "missed": False,
                "title": "",
            }
            for key, _, how, _ in columns
        ]
        + expect_cells(row, expected),
    }


def index_view(rows: list[Row], summary: Summary, *, title: str, version: str) -> dict:
    """What ``index.html`` shows: the summary, the filters' choices, the columns, the rows."""
    records = [row.record for row in rows]
    columns = [
        c for c in COLUMNS
        if c[0] not in OPTIONAL_COLUMNS or any(r.get(c[0]) is not None for r in records)
    ]  # fmt: skip
    counts = Counter(row.status for row in rows)
    seen_gates = {g for r in records for g in (r.get("failed_gates") or [])}
    expected = expected_names(rows)  # the measures the recipe's expect: asks about
    rate = summary.rate
    return {
        "title": title,
        "generator": f"{GENERATOR} {version}",
        "assets": CATALOGUE_DIR,
        "total": len(rows),
        "counts": [(s, counts[s]) for s in ROW_STATUSES if counts[s]],
        "gated": sum(r.get("failure") == "gate" for r in records),
        "seconds": shown_number(summary.seconds, "g4") if summary.seconds else None,
        "rate": f"{rate:.1f}" if rate is not None else None,
        "ran": summary.ran,
        "where": summary.where,
        "source": summary.source,
        "recipe": summary.recipe,
        "recipe_text": summary.recipe_text,
        "statuses": [s for s in ROW_STATUSES if counts[s]],
        "gates": [g for g in GATE_OPTIONS.values() if g in seen_gates],
        "columns": [{"key": k, "label": lab, "title": t} for k, lab, _, t in columns]
        + expect_columns(expected),
        "rows": [_row_view(row, columns, expected) for row in rows],
    }


# --------------------------------------------------------------------------- a garment


def _panel_view(p: dict) -> dict:
    change = area_change(p)
    err = p.get("intrinsic_scale_error") if isinstance(p.get("intrinsic_scale_error"), dict) else {}
    base = p.get("baseline_intrinsic_scale_error")
    return {
        "name": str(p.get("name", "?")),
        "triangles": shown_number(p.get("triangles"), "int"),
        "area": f"{shown_number(p.get('area_before'))} \u2192 {shown_number(p.get('area_after'))}",
        "change": shown_number(change, "percent") if change is not None else "-",
        "size": f"{shown(p.get('size_before'))} \u2192 {shown(p.get('size_after'))}",
        "deviation": shown_number(p.get("boundary_deviation")),
        "error": " / ".join(shown_number(err.get(k), "g3") for k in ("mean", "p95", "max")),
        "p95": p95(p),
        "baseline": shown_number(base.get("p95"), "g3") if isinstance(base, dict) else "-",
        "flips": shown_number(p.get("flipped_triangles"), "int"),
        "mirrored": bool(p.get("mirrored")),
        "worst": False,
    }


def _seam_view(s: dict) -> dict:
    return {
        "name": str(s.get("name", "?")),
        "panels": " / ".join(str(x) for x in s.get("panels", [])),
        "edges": shown_number(s.get("edges"), "int"),
        "before": shown(s.get("length_before")),
        "after": shown(s.get("length_after")),
        "ratio": shown_number(s.get("ratio_after")),
        "target": shown_number(s.get("ratio_target")),
        "mismatch": shown_number(s.get("mismatch"), "g3"),
        "size": seam_mismatch(s),
        "worst": False,
    }


def _mark_worst(items: list[dict], key: str) -> list[dict]:
    """Mark the item with the largest ``key`` (above 0) as the worst: where the
    intrinsic-scale error or the seam mismatch sits."""
    values = [(v, k) for k, it in enumerate(items) if (v := it[key]) is not None and v > 0]
    if values:
        items[max(values)[1]]["worst"] = True
    return items


def _step_view(step: dict) -> dict:
    fields = [(str(k), shown(v)) for k, v in step.items() if k not in ("op", "achieved")]
    achieved = step.get("achieved")
    return {
        "op": str(step.get("op", "?")),
        "fields": fields,
        "achieved": shown(achieved) if achieved is not None else None,
    }


def _verify_view(report: dict, folder: Path) -> dict | None:
    sec = report.get("verify")
    if not isinstance(sec, dict):
        return None
    ours, base = verify_panels(report) or {}, verify_panels(report, "baseline") or {}

    def p95_of(panels: dict, name: str, measure: str) -> str:
        return shown_number(verify_number(panels.get(name), measure), "g4")

    return {
        "picture": link(VERIFY_PICTURE) if (folder / VERIFY_PICTURE).is_file() else None,
        "summary": shown(
            {k: sec.get(k) for k in ("engine", "device", "settled", "rest", "seconds")}
        ),
        "panels": [
            {
                "name": str(name),
                "stretch": p95_of(ours, name, "stretch"),
                "baseline_stretch": p95_of(base, name, "stretch"),
                "displacement": p95_of(ours, name, "displacement"),
                "baseline_displacement": p95_of(base, name, "displacement"),
            }
            for name in ours
        ],
    }


def _files(folder: Path, report: dict) -> list[str]:
    """The garment folder's files a person may open, sorted."""
    names = set(report.get("outputs") or []) | {"batch.json", "verify.json", THUMBNAIL}
    return sorted(n for n in names if isinstance(n, str) and (folder / n).is_file())


def garment_view(row: Row, *, title: str, version: str) -> dict:
    """What ``OUT/NAME/index.html`` shows: the pattern, its tables, steps and warnings."""
    report, folder, r = row.report or {}, row.folder, row.record
    units = report.get("units")
    solver = report.get("solver") if isinstance(report.get("solver"), dict) else {}
    return {
        "title": title,
        "generator": f"{GENERATOR} {version}",
        "assets": "../" * len(row.parts) + CATALOGUE_DIR,
        "name": row.name,
        "garment": str(r.get("garment")),
        "status": row.status,
        "reason": r.get("reason") or "",
        "note": r.get("note") or "",
        "earlier_folder": row.earlier_folder,
        "rejected": row.rejected,
        "home": "../" * len(row.parts) + INDEX,
        "units": units.get("computation", "") if isinstance(units, dict) else str(units or ""),
        "svg": link("pattern.svg") if (folder / "pattern.svg").is_file() else None,
        "preview": link(PREVIEW) if (folder / PREVIEW).is_file() else None,
        "method": shown({k: report.get(k) for k in ("method", "intrinsic", "boundary")}),
        "solver": shown({k: solver.get(k) for k in SOLVER_SHOWN}),
        "panels": _mark_worst(
            [_panel_view(p) for p in report.get("panels", []) if isinstance(p, dict)], "p95"
        ),
        "seams": _mark_worst(
            [_seam_view(s) for s in report.get("seams", []) if isinstance(s, dict)], "size"
        ),
        "measures": measures_view(report),
        "steps": [_step_view(s) for s in report.get("steps", []) if isinstance(s, dict)],
        "warnings": [str(w) for w in report.get("warnings", [])],
        "verify": _verify_view(report, folder),
        "files": [{"name": n, "href": link(n)} for n in _files(folder, report)],
    }  # fmt: skip
