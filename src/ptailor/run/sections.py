"""The report sections a run adds to :func:`ptailor.report.build.build_report`'s: the units
each input came in, the pattern's pieces and what their marks did."""

from __future__ import annotations

import numpy as np

from ptailor.formats.garment import LoadedGarment
from ptailor.pieces import CarriedPiece, PiecePlan
from ptailor.run.outputs import OutputContext


def units_section(loaded: LoadedGarment) -> dict:
    """The report's ``units``: computation, drape and pattern units as read, where each came
    from (``command line``, ``default (size checked)``, ``estimate``, ``file``), and the
    estimate."""
    read = loaded.intake.get("units", {})
    note = {
        "computation": loaded.garment.units,
        "drape": read.get("drape", "cm"),
        "drape_source": read.get("drape_source"),
        "pattern": read.get("pattern", "cm") if loaded.pattern is None else loaded.pattern.units,
        "pattern_source": read.get("pattern_source"),
    }
    if loaded.pattern is not None:
        note["pattern_note"] = loaded.pattern.units_note
    if loaded.pattern_units_estimated:
        note["pattern_scale_estimate"] = round(loaded.pattern_scale, 6)
    return note


def _piece_record(pc, m, from_file: bool, cp: CarriedPiece | None, panel: str) -> dict:
    rec = {
        "name": pc.name,
        "panel": panel,
        "source": "file" if from_file else "mesh",
        "matched_by": m.how,
    }
    if from_file:
        rec["match_residual"] = round(m.residual, 6)
        rec["match_distance"] = round(m.distance, 6)
        rec["mirrored"] = bool(np.linalg.det(m.R) < 0)
        rec["unfolded"] = bool(m.fold)
    if cp is None:
        rec["removed"] = True
        return rec
    rec.update(
        {
            "outline": cp.outline_from,
            "notches": len(cp.piece.notches),
            "grain_line": cp.piece.grain is not None,
            "fold_line": cp.piece.mirror is not None,
            "internal_lines": len(cp.piece.internal),
            "drill_holes": len(cp.piece.drills),
            "marks_dropped": cp.dropped,
        }
    )
    return rec


def pieces_record(plan: PiecePlan, pieces: list[CarriedPiece | None]) -> list:
    """The report's ``pattern.pieces``: each piece's panel, how it matched, what its marks did."""
    names = [p.name for p in plan.panels]
    now = plan.panel_names or tuple(names[m.panel] for m in plan.matches)
    return [
        _piece_record(pc, m, ff, cp, pn)
        for pc, m, ff, cp, pn in zip(
            plan.pieces, plan.matches, plan.from_file, pieces, now, strict=True
        )
    ]


def pattern_section(
    loaded: LoadedGarment, ctx: OutputContext, named: tuple[tuple[str, float], ...] = ()
) -> dict:
    """The report's ``pattern``: pieces (with their seam allowances by seam and opening when
    one is asked), and the CAD file's size and style when read."""
    plan = ctx.plan
    rec: dict = {"pieces": pieces_record(plan, ctx.pieces) if plan else []}
    if loaded.pattern is not None:
        pf = loaded.pattern
        rec.update({"size": pf.size, "sizes": list(pf.sizes), "style": pf.style})
    if ctx.seam_allowance:
        rec["seam_allowance"] = ctx.seam_allowance
    if named:
        rec["seam_allowances"] = dict(named)
    for p, a in zip(rec["pieces"], ctx.allowances, strict=False):  # a loop over pieces
        if a is not None:
            p["allowances"] = a.runs
    return rec
