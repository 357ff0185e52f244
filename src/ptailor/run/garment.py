"""The run of one garment: files in, an output folder out (``adjust``, ``demo``, batch).

Read top to bottom: check the recipe and options, read the inputs, run the adjustment
(:func:`ptailor.pipeline.adjustment`), guard the result, carry the pieces, then write the
outputs and the report into a staging folder that replaces ``out`` whole.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from ptailor.errors import PtailorError
from ptailor.output import check_output_dir, staged_dir, write_json
from ptailor.pieces import carry_plan
from ptailor.pipeline import Adjustment, adjustment, solver_warnings
from ptailor.recipe import Recipe
from ptailor.report.build import build_report
from ptailor.run.checks import (
    check_finite_report,
    check_finite_result,
    check_seam_allowance,
    intrinsic_error_warnings,
    piece_warnings,
)
from ptailor.run.inputs import checked_recipe, edit_options, load_input, plan_pieces
from ptailor.run.options import RunOptions
from ptailor.run.outputs import OutputContext, write_outputs
from ptailor.run.sections import input_warnings, pattern_section, units_section


def run_garment(
    garment: str,
    recipe: Recipe | str,
    out: str | Path,
    *,
    options: RunOptions = RunOptions(),  # noqa: B008 - frozen
    drape: str | None = None,
    display_inputs: dict[str, str] | None = None,
    extra_files: dict[str, str] | None = None,
    check: Callable[[dict], None] | None = None,
) -> dict:
    """Load, adjust and write one garment; return the report.

    Parameters
    ----------
    garment : str
        OBJ with drape (v) and pattern (vt), or the pattern only with ``drape``; or a CAD
        pattern (DXF) with ``drape`` an OBJ whose ``vt`` triangulates its pieces.
    recipe : Recipe or str
        A validated recipe, or the path of one (``-`` for stdin).
    out : str or Path
        Output folder, written all or nothing.
    options : RunOptions
        How the garment is read, adjusted and written.
    drape : str, optional
        See :func:`ptailor.formats.garment.load_garment`; what the intake repaired goes
        into the report's ``intake``.
    display_inputs : dict, optional
        Role to the path the report shows (default: the path read).
    extra_files : dict, optional
        File name to text, written into the output folder too.
    check : callable, optional
        ``check(report)`` is called before the output folder is put in place; when it
        raises, nothing is written (quality gates).

    Returns
    -------
    dict
        The report.
    """
    recipe = checked_recipe(recipe, options)
    check_output_dir(out, [garment, drape, options.body])
    shown = (display_inputs or {}).get("garment", garment)
    edits = edit_options(recipe, options)
    t0 = time.perf_counter()
    loaded = load_input(garment, drape, recipe, options)
    plan = plan_pieces(loaded, edits, options)
    if options.seam_allowance:
        check_seam_allowance(loaded.garment, options.seam_allowance)
    t1 = time.perf_counter()
    adj = _adjusted(loaded.garment, recipe, options, edits, shown=shown)
    warnings = [*loaded.intake.get("warnings", []), *solver_warnings(adj), *input_warnings(loaded)]
    t2 = time.perf_counter()
    errors = _checked_errors(adj, shown=shown)
    warnings += intrinsic_error_warnings(adj, errors)
    carried: list = []
    if plan is not None:  # every adjusted panel gets a piece (a split panel one per part)
        plan, carried = carry_plan(adj, plan, up=edits.up)
    warnings += piece_warnings(plan, carried, options.seam_allowance)
    allowance = options.seam_allowance
    ctx = OutputContext(
        loaded=loaded,
        pieces=carried,
        plan=plan,
        errors=errors,
        seam_allowance=allowance,
        title=f"{Path(garment).name}: {Path(recipe.source).name}"
        + (f", seam allowance {allowance:g} {loaded.garment.units}" if allowance else ""),
    )
    sections = {
        "units_note": units_section(
            loaded, drape_units=options.drape_units, pattern_units=options.pattern_units
        ),
        "warnings": warnings,
        "extra": {
            "pattern": pattern_section(loaded, plan, carried, allowance),
            "intake": loaded.intake,
        },
    }
    with staged_dir(out) as tmp:
        written = write_outputs(tmp, adj, ctx, options.formats)
        for name, text in (extra_files or {}).items():
            (tmp / name).write_text(text)
        timing = {"load": t1 - t0, **adj.timing_s, "write": time.perf_counter() - t2}
        report = build_report(
            adj, inputs=_read(loaded, options), timing_s=timing, errors=errors, **sections
        )
        _show(report, {**_read(loaded, options), **(display_inputs or {})}, written)
        check_finite_report(report, path=shown)
        if check is not None:
            check(report)
        write_json(tmp / "report.json", report)
    return report


def _adjusted(garment, recipe: Recipe, options: RunOptions, edits, *, shown: str) -> Adjustment:
    """:func:`ptailor.pipeline.adjustment`, an error the garment decides naming it."""
    try:
        return adjustment(
            garment,
            recipe,
            method=options.method,
            intrinsic=options.intrinsic,
            baseline=options.baseline,
            options=edits,
        )
    except PtailorError as exc:
        if exc.path is not None:
            raise
        # the garment decides (an opening it lacks, an edit it cannot take): name it
        raise PtailorError(exc.message, path=shown) from None


def _checked_errors(adj: Adjustment, *, shown: str) -> np.ndarray:
    """The intrinsic-scale error per triangle, the result checked finite."""
    from ptailor.report.build import triangle_errors

    with np.errstate(all="ignore"):
        errors = triangle_errors(adj)
    check_finite_result(adj, errors, path=shown)
    return errors


def _read(loaded, options: RunOptions) -> dict[str, str]:
    """Role to the path read (the body too)."""
    return {**loaded.inputs, **({"body": options.body} if options.body else {})}


def _show(report: dict, shown: dict[str, str], written: list[str]) -> None:
    """Put the paths as shown and the files written into the report (in place)."""
    for role, path in shown.items():
        report["inputs"][role]["path"] = path
    report["outputs"] = sorted(["report.json", *written])
