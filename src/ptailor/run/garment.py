"""The run of one garment: files in, an output folder out (``adjust``, ``demo``, batch).

Read top to bottom: check the recipe and options, read the inputs, run the adjustment
(:func:`ptailor.pipeline.adjustment`), guard the result, carry the pieces, then write the
outputs and the report into a staging folder that replaces ``out`` whole.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ptailor.edits import EditOptions
from ptailor.errors import NumericError, PtailorError
from ptailor.formats.garment import LoadedGarment
from ptailor.pieces import carry_plan
from ptailor.pieces.grade import grade_nest
from ptailor.pipeline import Adjustment, Progress, adjustment
from ptailor.recipe import Recipe
from ptailor.report.build import (
    build_report,
    error_reference,
    triangle_errors,
    without_negative_zeros,
)
from ptailor.report.expect import (
    expect_records,
    garment_measure_dicts,
    lost_measures,
    measures_section,
    steps_achieved,
)
from ptailor.report.metrics import ScaleReference
from ptailor.report.records import Report
from ptailor.run.checks import (
    check_finite_report,
    check_finite_result,
    run_warnings,
)
from ptailor.run.folder import check_output_dir, staged_dir, write_json
from ptailor.run.graded import check_sizes_input, grading_section
from ptailor.run.inputs import RunInputs, checked_recipe, read_inputs
from ptailor.run.library_warnings import capture_library_warnings
from ptailor.run.options import RunOptions
from ptailor.run.outputs import OutputContext, allowance_text, cut_allowances, write_outputs
from ptailor.run.sections import pattern_section, units_section
from ptailor.run.spec import spec_input, spec_outputs
from ptailor.run.verify import Redrapes


def run_garment(
    garment: str,
    recipe: Recipe | str,
    out: str | Path,
    *,
    options: RunOptions = RunOptions(),  # noqa: B008 - frozen
    drape: str | None = None,
    display_inputs: dict[str, str] | None = None,
    extra_files: dict[str, str] | None = None,
    progress: Progress | None = None,
) -> Report:
    """Load, adjust and write one garment; return the report (:func:`staged_run`'s
    parameters)."""
    with staged_run(
        garment,
        recipe,
        out,
        options=options,
        drape=drape,
        display_inputs=display_inputs,
        extra_files=extra_files,
        progress=progress,
    ) as report:
        pass
    return report


@contextmanager
def staged_run(
    garment: str,
    recipe: Recipe | str,
    out: str | Path,
    *,
    options: RunOptions = RunOptions(),  # noqa: B008 - frozen
    drape: str | None = None,
    display_inputs: dict[str, str] | None = None,
    extra_files: dict[str, str] | None = None,
    progress: Progress | None = None,
    divert: tuple[type[BaseException], str | Path] | None = None,
) -> Iterator[Report]:
    """Load, adjust and stage one garment; yield the report before ``out`` is put in place.

    An exception raised in the ``with`` block (a broken quality gate) leaves nothing
    written; when the block ends, the staged folder replaces ``out`` whole.

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
    progress : callable, optional
        ``progress(stage, iteration, residual)`` (:func:`ptailor.pipeline.adjustment`'s,
        and ``("read", 0, None)``, ``("write", 0, None)``): a progress line's feed.
    divert : (exception type, folder), optional
        An exception of that type raised in the ``with`` block puts the complete folder
        (its ``report.json`` too) at ``folder`` instead of ``out``
        (:func:`~ptailor.run.folder.staged_dir`): a batch's garments its gates rejected.

    Yields
    ------
    dict
        The report, as ``report.json`` will hold it.
    """
    recipe = checked_recipe(recipe, options)
    body_file = options.body if options.body != "auto" else None
    spec_file = spec_input(garment, options.spec)
    check_output_dir(out, [garment, drape, body_file, spec_file, options.edited_drape])
    shown = (display_inputs or {}).get("garment", garment)  # the garment errors name
    check_sizes_input(garment, options, shown=shown)
    # the library's warnings (numpy, ezdxf, ...) of this run, for the report's warnings
    with capture_library_warnings() as library:
        staged = _stage(
            garment, drape, recipe, options, spec_file=spec_file, shown=shown,
            progress=progress, library=library,
        )  # fmt: skip
        with staged_folder(
            out, staged, shown=shown, display=display_inputs or {}, extra_files=extra_files,
            divert=divert,
        ) as report:  # fmt: skip
            yield report


def _stage(
    garment: str,
    drape: str | None,
    recipe: Recipe,
    options: RunOptions,
    *,
    spec_file: str | None,
    shown: str,
    progress: Progress | None,
    library: list[str],
) -> Staged:
    """Read the inputs (:func:`~ptailor.run.inputs.read_inputs`), then :func:`stage` them."""
    t0 = time.perf_counter()
    if progress is not None:
        progress("read", 0, None)
    inputs = read_inputs(garment, drape, recipe, options, spec_file=spec_file, shown=shown)
    return stage(
        inputs, recipe, options, shown=shown, library=library, progress=progress,
        load_s=time.perf_counter() - t0,
    )  # fmt: skip


def stage(
    inputs: RunInputs,
    recipe: Recipe,
    options: RunOptions,
    *,
    shown: str,
    library: list[str],
    load_s: float = 0.0,
    progress: Progress | None = None,
) -> Staged:
    """Adjust what was read, re-drape (``--verify``): everything a folder is written from
    (:func:`staged_folder`); ``shown`` the garment errors name, ``library`` the run's library
    warnings (:func:`~ptailor.run.library_warnings.capture_library_warnings`'s list),
    ``load_s`` the seconds the reading took."""
    edits = inputs.edits
    adj = _adjustment(inputs, recipe, options, shown=shown, progress=progress)
    errors, reference = _checked_errors(adj, shown=shown)
    t2 = time.perf_counter()
    sections = _measure_sections(adj, recipe, inputs.measures_before)
    timing = {"load": load_s, **adj.timing_s, "measures": time.perf_counter() - t2}
    redrapes = _redrapes(adj, edits, options, timing=timing, progress=progress)
    t3 = time.perf_counter()
    if progress is not None:
        progress("write", 0, None)
    return Staged(
        adj,
        _output_context(adj, inputs, errors, garment=shown, recipe=recipe, options=options),
        options,
        timing=timing,
        start=t3,
        redrapes=redrapes,
        inputs=inputs,
        reference=reference,
        library_warnings=library,
        sections=sections,
    )


def _measure_sections(adj: Adjustment, recipe: Recipe, before: list[dict]) -> dict:
    """The report's ``measures`` (the garment as read, the adjusted garment), its ``steps``
    with the pattern's achieved values and, when the recipe has ``expect:``, ``expect``
    (:mod:`ptailor.report.expect`)."""
    after = garment_measure_dicts(adj.garment)
    out: dict = {
        "steps": steps_achieved(adj.state.log, before, after),
        "measures": measures_section(before, after),
    }
    if recipe.expect:
        out["expect"] = expect_records(recipe, before, after)
    return out


def _redrapes(
    adj: Adjustment, edits: EditOptions, options: RunOptions, *, timing: dict, progress=None
) -> Redrapes | None:
    """With ``--verify``, the re-drape check (the engine was checked before any file was
    read; its seconds go into ``timing``); else None."""
    if not options.verify:
        return None
    from ptailor.run.verify import adjustment_redrapes

    t = time.perf_counter()
    redrapes = adjustment_redrapes(adj, body=edits.body, options=options, progress=progress)
    timing["verify"] = time.perf_counter() - t
    return redrapes


def _output_context(
    adj: Adjustment,
    inputs: RunInputs,
    errors: np.ndarray,
    *,
    garment: str,
    recipe: Recipe,
    options: RunOptions,
) -> OutputContext:
    """What the writers need: the pieces carried through the adjustment (every adjusted
    panel gets one, a split panel one per part), the errors, the sheet's title."""
    plan, carried, nest = inputs.plan, [], None
    if plan is not None:
        plan, carried = carry_plan(adj, plan)
    if plan is not None and inputs.graded:
        nest = grade_nest(
            plan, carried, inputs.loaded.pattern, inputs.graded, units=adj.garment.units
        )
    allowance, named = options.seam_allowance, options.seam_allowances
    return OutputContext(
        loaded=inputs.loaded,
        pieces=carried,
        plan=plan,
        errors=errors,
        seam_allowance=allowance,
        allowances=cut_allowances(adj, plan, carried, allowance, named),
        show_measures=options.show_measures,
        nest=nest,
        paper=options.paper,
        title=f"{Path(garment).name}: {Path(options.edited_drape or recipe.source).name}"
        + allowance_text(allowance, named, inputs.loaded.garment.units),
    )


@dataclass(frozen=True)
class Staged:
    """What is written: the adjustment, the writers' context, the options, the timing so
    far and when the writing phase started (``perf_counter``); with ``--verify`` the
    re-drapes and the edits' options (their body and axes, for the picture); what the
    errors were measured against (the report measures the baseline against it too)."""

    adj: Adjustment
    ctx: OutputContext
    options: RunOptions
    timing: dict[str, float]
    start: float
    redrapes: Redrapes | None
    inputs: RunInputs  # (the edits' options, the body's fit, the specification matched)
    reference: ScaleReference | None
    #: the run's library warnings (:func:`~ptailor.run.library_warnings.capture_library_warnings`'s
    #: list, which the writing still adds to)
    library_warnings: list[str]
    #: the report's ``measures`` and ``expect`` (:func:`_measure_sections`)
    sections: dict


@contextmanager
def staged_folder(
    out: str | Path,
    staged: Staged,
    *,
    shown: str,
    display: dict[str, str],
    extra_files: dict[str, str] | None = None,
    divert: tuple[type[BaseException], str | Path] | None = None,
) -> Iterator[dict]:
    """Write the outputs and the extra files into a staging folder, yield the report, then
    write ``report.json`` and put the folder in place as ``out`` (``shown``: the garment an
    error names; ``display``: role to the path the report shows)."""
    adj, ctx, options = staged.adj, staged.ctx, staged.options
    with staged_dir(out, divert=divert) as tmp:
        written = write_outputs(tmp, adj, ctx, options.formats)
        if staged.redrapes is not None:
            written += _write_redrapes(tmp, staged)
        if options.write_body and staged.inputs.edits.body is not None:
            from ptailor.run.verify import write_body

            written += write_body(
                tmp,
                staged.inputs.edits.body,
                drape_scale=ctx.loaded.drape_scale,
                units=ctx.loaded.garment.units,
            )
        spec_section: dict | None = None
        spec_warnings: list[str] = list(staged.inputs.spec_note)
        if staged.inputs.spec_match is not None:
            files, spec_section, spec_warnings = spec_outputs(tmp, adj, staged.inputs.spec_match)
            written += files
        for name, text in (extra_files or {}).items():
            (tmp / name).write_text(text)
        timing = {**staged.timing, "write": time.perf_counter() - staged.start}
        report = _report(
            ctx.loaded,
            staged,
            timing,
            spec=(spec_section, spec_warnings),
            outputs=["report.json", *written],
            shown=display,
        )
        report = without_negative_zeros(report)
        check_finite_report(report, path=shown)
        diverted: tuple[type[BaseException], ...] = (divert[0],) if divert is not None else ()
        try:
            yield report
        except diverted:  # a diverted folder is complete: its report too
            write_json(tmp / "report.json", report)
            raise
        write_json(tmp / "report.json", report)


def _report(
    loaded: LoadedGarment,
    staged: Staged,
    timing: dict,
    *,
    spec: tuple,
    outputs: list[str],
    shown: dict[str, str],
) -> Report:
    """The report: :func:`ptailor.report.build.build_report` with the run's sections
    (``spec``: the ``--spec`` section and its warnings) and every warning, the library's
    captured during the run last."""
    adj, ctx, options = staged.adj, staged.ctx, staged.options
    spec_section, spec_warnings = spec
    warnings = run_warnings(loaded, adj, ctx.errors, ctx.plan, ctx.pieces, options)
    warnings += list(spec_warnings)
    warnings += list(ctx.nest.warnings) if ctx.nest is not None else []
    measures = staged.sections["measures"]
    warnings += lost_measures(measures["before"], measures["after"])
    warnings += [w for w in staged.library_warnings if w not in warnings]
    return build_report(
        adj,
        inputs=_read(loaded.inputs, options),
        shown=shown,
        outputs=outputs,
        units_note=units_section(loaded),
        warnings=warnings,
        timing_s=timing,
        errors=ctx.errors,
        reference=staged.reference,
        extra={
            "pattern": pattern_section(loaded, ctx, options.seam_allowances)
            | ({"grading": grading_section(ctx.nest, loaded.pattern, options)} if ctx.nest else {}),
            "intake": loaded.intake,
            **({"verify": staged.redrapes.section} if staged.redrapes is not None else {}),
            **({"body_fit": staged.inputs.body_fit} if staged.inputs.body_fit is not None else {}),
            **({"spec": spec_section} if spec_section is not None else {}),
            **staged.sections,
        },
    )


def _write_redrapes(tmp: Path, staged: Staged) -> list[str]:
    """The re-drape check's files (:func:`ptailor.run.verify.write_verify_files`)."""
    from ptailor.run.verify import write_verify_files

    edits = staged.inputs.edits
    return write_verify_files(
        tmp,
        staged.redrapes,
        loaded=staged.ctx.loaded,
        body=edits.body,
    )


def _adjustment(
    inputs: RunInputs, recipe: Recipe, options: RunOptions, *, shown: str, progress=None
) -> Adjustment:
    """:func:`ptailor.pipeline.adjustment` (of the recipe's steps, or of the edited drape),
    an error the garment decides naming it."""
    try:
        return adjustment(
            inputs.loaded.garment,
            recipe,
            method=options.method,
            intrinsic=options.intrinsic,
            baseline=options.baseline,
            options=inputs.edits,
            progress=progress,
            edited=inputs.edited,
        )
    except PtailorError as exc:
        if exc.path is not None:
            raise
        # the garment decides (an opening it lacks, an edit it cannot take): name it
        kind = NumericError if isinstance(exc, NumericError) else PtailorError
        raise kind(exc.message, path=shown) from None


def _checked_errors(adj: Adjustment, *, shown: str) -> tuple[np.ndarray, ScaleReference | None]:
    """The intrinsic-scale error per triangle, the result checked finite; and what the
    errors were measured against, when the report measures the uniform baseline too (else
    None)."""
    with np.errstate(all="ignore"):
        reference = error_reference(adj)
        errors = triangle_errors(adj, reference=reference)
    check_finite_result(adj, errors, path=shown)
    return errors, reference if adj.baseline is not None else None


def _read(inputs: dict[str, str], options: RunOptions) -> dict[str, str]:
    """Role to the path read: ``inputs``, the body (a fitted body, ``--body auto``, is no
    file read: the report's ``body_fit`` records it), the specification, the edited drape."""
    body = options.body if options.body not in (None, "auto") else None
    spec = inputs.get("garment") and spec_input(inputs["garment"], options.spec)
    extra = {"body": body, "spec": spec, "edited_drape": options.edited_drape}
    return {**inputs, **{role: path for role, path in extra.items() if path}}
