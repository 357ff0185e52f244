"""``ptailor batch``: one recipe over a catalogue of garments."""

from __future__ import annotations

import functools

import click

from ptailor import tolerances as tol
from ptailor.cli.options import Finite, run_options


def _interrupt(signum, frame) -> None:
    raise KeyboardInterrupt


#: the limit gates: option, metavar, what a garment fails on (above the limit)
_LIMIT_GATES = (
    (
        "--max-area-change",
        "F",
        "a panel whose |area after / before - 1| exceeds F (a fraction: 0.05 = 5 %).",
    ),
    (
        "--max-boundary-deviation",
        "D",
        "a panel whose outline deviation (report's boundary_deviation, recipe units) exceeds D.",
    ),
    ("--max-intrinsic-error", "E", "a panel whose intrinsic-scale error p95 exceeds E."),
    (
        "--max-seam-mismatch",
        "D",
        "a seam whose two sides miss their target length ratio by more than D (report's "
        "seams[].mismatch, recipe units).",
    ),
    (
        "--max-verify-stretch",
        "S",
        "a panel whose re-drape stretch p95 (report's verify.ours) exceeds S (1.05 = 5 % "
        "stretched); needs --verify.",
    ),
    (
        "--max-verify-displacement",
        "D",
        "a panel whose re-drape displacement p95 (report's verify.ours, recipe units) exceeds "
        "D; needs --verify.",
    ),
    (
        "--max-spec-fit",
        "D",
        "a specification panel whose written curves lie farther than D from the adjusted "
        "mesh outline (report's spec.panels[].fit, recipe units); needs --spec.",
    ),
)


def gate_options(command):
    """The quality gates, ``--max-area-change`` ... ``--fail-on-flips``, handed to the
    command as one :class:`~ptailor.batch.gates.Gates` (its ``gates`` keyword)."""

    @functools.wraps(command)
    def with_gates(
        *args,
        max_area_change,
        max_boundary_deviation,
        max_intrinsic_error,
        max_seam_mismatch,
        max_verify_stretch,
        max_verify_displacement,
        max_spec_fit,
        fail_on_flips,
        **kwargs,
    ):
        from ptailor.batch import Gates

        gates = Gates(
            max_area_change=max_area_change,
            max_boundary_deviation=max_boundary_deviation,
            max_intrinsic_error=max_intrinsic_error,
            max_seam_mismatch=max_seam_mismatch,
            max_verify_stretch=max_verify_stretch,
            max_verify_displacement=max_verify_displacement,
            max_spec_fit=max_spec_fit,
            fail_on_flips=fail_on_flips,
        )
        return command(*args, gates=gates, **kwargs)

    fn = with_gates
    fn = click.option(
        "--fail-on-flips", is_flag=True, help="Gate: fail a garment with flipped triangles."
    )(fn)
    for name, metavar, fails in reversed(_LIMIT_GATES):
        fn = click.option(
            name,
            type=Finite(min=0),
            default=None,
            metavar=metavar,
            help=f"Gate: fail a garment with {fails}",
        )(fn)
    return fn


#: ``ptailor batch --help``
BATCH_HELP = """Apply RECIPE to every GARMENT (or every row of --manifest), one output folder each
under OUT.

GARMENT is an OBJ (v = drape, vt = pattern) or a DXF pattern paired with the OBJ drape
beside it (X.dxf with X.obj), a glob (quoted: '**/*.obj' is expanded here,
recursively), a folder (every *.obj and *.dxf below it; an OBJ that is a DXF's drape is
not a garment of its own) or '-' (paths on stdin, one per line). RECIPE is validated
first. Each garment is written all or nothing to OUT/NAME (NAME is the file's stem;
later garments with the same stem get NAME-2, NAME-3) with a
batch.json stamp: re-running skips garments whose file, recipe and options are
unchanged. A garment that fails, breaks a quality gate or runs past --timeout gets no
folder; the others go on. --manifest FILE gives each garment its own units, axes, DXF
size, drape and folder name; the whole manifest is checked before anything runs.

--verify re-drapes each garment with the cloth engine (pip install 'ptailor[sim]'; on
the GPU warp finds, else the CPU), one simulation at a time per worker.

Exit status: 0 every garment done or unchanged, 1 some failed, 2 bad recipe or
arguments, 130 interrupted by Ctrl-C or SIGTERM (complete folders are kept: run again
to finish).
"""


@click.command(help=BATCH_HELP)
@click.argument("recipe", type=click.Path(dir_okay=False, allow_dash=True))
@click.argument("garments", metavar="[GARMENT...]", nargs=-1)
@click.option(
    "--manifest",
    type=click.Path(dir_okay=False),
    default=None,
    metavar="FILE",
    help="The garments, one a row, instead of GARMENT arguments: CSV with a header row or "
    "JSON Lines, columns garment (required; relative to the manifest's folder), drape, name "
    "(the output folder) and pattern_units, drape_units, dxf_units, size, up, front, which "
    "override the options for that garment (an empty cell: the option's value).",
)
@click.option(
    "-o",
    "--out",
    required=True,
    type=click.Path(file_okay=False),
    help="Output root: one folder per garment, named after its file.",
)
@run_options
@click.option(
    "-j",
    "--jobs",
    type=click.IntRange(min=1),
    default=None,
    help="Worker processes [default: the number of cores]; 1 runs in this process.",
)
@click.option(
    "--scheduler",
    metavar="ADDRESS",
    default=None,
    help="Run on a Dask distributed cluster (tcp://host:8786); its workers must see the "
    "same files. Needs pip install 'ptailor[dask]'.",
)
@click.option(
    "--timeout",
    type=Finite(min=0, max=tol.BATCH_TIMEOUT_MAX_S, min_open=True),
    default=None,
    metavar="SECONDS",
    help="Per garment: one still running after SECONDS is stopped and failed (failure: "
    "timeout), its staging folder removed. Garments then always run in worker processes "
    "(with -j 1 too).",
)
@click.option("--force", is_flag=True, help="Redo every garment, even unchanged ones.")
@click.option(
    "--log",
    type=click.Path(dir_okay=False),
    default=None,
    help="Write one JSON record per garment to this file (JSON lines, input order). An "
    "existing file is replaced only when it is such a log (an input of the run, or any "
    "other file, is exit 2).",
)
@click.option("--json", "as_json", is_flag=True, help="Print the JSON records on stdout.")
@click.option("-q", "--quiet", is_flag=True, help="No progress bar and no summary (failures only).")
@click.option(
    "--html",
    is_flag=True,
    help="Write OUT/index.html after the run: the catalogue, a row per garment (status, "
    "reason, thumbnail, numbers; sortable, filterable) and a page per garment "
    "(OUT/NAME/index.html; what a gate rejected is kept in OUT/_rejected/NAME). Once OUT "
    "has one, every batch into OUT rewrites it; so does 'ptailor report OUT'.",
)
@gate_options
@click.pass_context
def batch(
    ctx,
    recipe,
    garments,
    manifest,
    out,
    jobs,
    scheduler,
    timeout,
    force,
    log,
    as_json,
    quiet,
    html,
    gates,
    **run,
) -> None:
    """``ptailor batch``: its help is :data:`BATCH_HELP`; ``run``: the run's options
    (:func:`~ptailor.cli.options.run_options`), each garment's unless its manifest row
    overrides one."""
    import os
    import sys

    from ptailor.batch import make_jobs
    from ptailor.cli.options import build_run_options, check_engine_first
    from ptailor.recipe import load_recipe

    html = html or _has_catalogue(out)  # a catalogue once made is kept current
    _check_arguments(
        recipe, garments, manifest, timeout=timeout, scheduler=scheduler, gates=gates,
        verify=run["verify"], spec=run["spec"], html_out=out if html else None,
    )  # fmt: skip
    check_engine_first(run["verify"])  # (before any file is read)
    rec = load_recipe(recipe)
    options = build_run_options(run, units=rec.units)
    paths = _garment_paths(ctx, garments, manifest, out)
    if any(getattr(row, "options", {}).get("edited_drape") for row in paths):
        from ptailor.run.edited import check_edited_recipe

        check_edited_recipe(rec)  # (edited drapes take a recipe without steps)
    if log:
        _check_log(log, paths, recipe, manifest)
    todo = make_jobs(paths, out, rec, options=options, gates=gates, force=force,
                     timeout=timeout, keep_rejected=html,
                     debug=bool(ctx.find_root().params.get("debug")))  # fmt: skip
    if html:  # the page never links a garment page the run has not written yet
        _unlink_rerun(out, todo)
    bar = not quiet and sys.stderr.isatty()
    workers = jobs or os.cpu_count() or 1
    result = _run(todo, workers=workers, scheduler=scheduler, log=log, as_json=as_json, bar=bar)
    _summary(result, len(todo), quiet=quiet)
    if html:
        _catalogue(out, result, rec, quiet=quiet)
    ctx.exit(result.exit_status)


def _has_catalogue(out: str) -> bool:
    """Whether OUT holds a catalogue page ptailor wrote (then every batch rewrites it)."""
    from pathlib import Path

    from ptailor.catalogue.write import is_catalogue_page

    return is_catalogue_page(Path(out) / "index.html")


def _unlink_rerun(out: str, todo) -> None:
    """OUT's catalogue page without links to the folders the run may replace
    (:func:`~ptailor.catalogue.write.unlink_rerun`; its warnings come with the page the
    run writes at its end)."""
    from pathlib import Path

    from ptailor.catalogue.write import unlink_rerun

    unlink_rerun(out, {Path(job.out_abs).name for job in todo}, warn=lambda msg: None)


def _catalogue(out: str, result, recipe, *, quiet: bool) -> None:
    """The catalogue page of the run (``--html``), its path on stderr."""
    from pathlib import Path

    from ptailor.catalogue import Summary, write_catalogue
    from ptailor.catalogue.rows import recipe_text

    def warn(msg: str) -> None:
        if not quiet:
            click.echo(f"ptailor: warning: {msg}", err=True)

    Path(out).mkdir(parents=True, exist_ok=True)  # (every garment may have failed)
    summary = Summary(
        seconds=result.seconds,
        ran=result.runs,
        where=result.where,
        recipe=recipe.source,
        recipe_text=recipe_text(recipe),
    )
    page = write_catalogue(out, result.records, summary, warn=warn)
    if not quiet:
        click.echo(f"catalogue: {page}", err=True)


def _check_arguments(
    recipe: str,
    garments,
    manifest,
    *,
    timeout,
    scheduler,
    gates,
    verify: bool,
    spec,
    html_out: str | None = None,
) -> None:
    """Refuse arguments that do not go together (exit 2, before any garment is read), and
    with ``--html`` (``html_out``: OUT) a catalogue page in OUT that is not ptailor's."""
    import os

    from ptailor.errors import PtailorError

    if timeout is not None and scheduler is not None:
        raise PtailorError("--timeout cannot be used with --scheduler (Dask cannot stop a task)")
    if manifest is not None and garments:
        raise PtailorError("give the garments as GARMENT arguments or with --manifest, not both")
    if manifest is None and not garments:
        raise PtailorError("no garments: give GARMENT arguments or --manifest FILE")
    if recipe == "-" and "-" in garments:
        raise PtailorError("the recipe and the garment list cannot both come from stdin")
    if gates.verify_gates and not verify:
        raise PtailorError(
            "--max-verify-stretch and --max-verify-displacement need --verify "
            "(they judge the re-drape check)"
        )
    if gates.max_spec_fit is not None and spec is None and manifest is None:
        raise PtailorError("--max-spec-fit needs --spec (it judges the written specification)")
    if spec not in (None, "auto") and not os.path.isfile(spec):  # one for every garment
        raise PtailorError("no such file (--spec; auto takes each garment's own)", path=spec)
    if html_out is not None:
        from ptailor.catalogue import check_catalogue_target

        check_catalogue_target(html_out)


def _garment_paths(ctx: click.Context, garments, manifest, out) -> list:
    """The garments to run: the manifest's rows (each cell checked), else the GARMENT
    arguments expanded (folders, globs, ``-`` for a list on stdin)."""
    import sys

    from ptailor.batch import expand_garments
    from ptailor.batch.manifest import read_manifest
    from ptailor.errors import PtailorError

    if manifest is not None:
        return read_manifest(manifest, check=_cell_check(ctx))
    paths = expand_garments(
        garments,
        stdin=sys.stdin,
        exclude_under=out,
        warn=lambda msg: click.echo(f"ptailor: warning: {msg}", err=True),
    )
    if not paths:
        raise PtailorError(f"no garments: {' '.join(garments)} matched no files")
    return paths


def _cell_check(ctx: click.Context):
    """A manifest's option cells checked as the command line checks its options: by the
    option's own click type (``up``'s choices, ...), units by the parser that reads them."""
    from ptailor.batch.manifest import UNIT_OPTIONS, check_units
    from ptailor.errors import PtailorError

    params = {p.name: p for p in ctx.command.params}

    def check(column: str, text: str):
        param = params[column]
        try:
            value = param.type.convert(text, param, ctx)
        except click.BadParameter as exc:
            raise PtailorError(f"{column}: {exc.message}") from None
        return check_units(column, value) if column in UNIT_OPTIONS else value

    return check


def _check_log(log: str, paths: list, recipe: str, manifest: str | None = None) -> None:
    """Exit 2 before anything runs where the log would overwrite an input of the run or a
    file that is not a ptailor log (:func:`ptailor.batch.records.log_problem`); ``paths``
    are garment paths or a manifest's rows."""
    from pathlib import Path

    from ptailor.batch.manifest import as_rows
    from ptailor.batch.records import log_problem
    from ptailor.errors import PtailorError

    rows = as_rows(paths)
    inputs = [Path(r.garment) for r in rows] + [Path(r.drape) for r in rows if r.drape]
    inputs += [p.with_suffix(ext) for p in inputs if p.suffix.lower() == ".dxf"
               for ext in (".obj", ".OBJ")]  # fmt: skip
    inputs += [Path(f) for f in (recipe, manifest) if f is not None and f != "-"]
    problem = log_problem(log, inputs)
    if problem:
        raise PtailorError(f"--log {problem}", path=log)


def _run(todo, *, workers: int, scheduler, log, as_json: bool, bar: bool):
    """Run the jobs: records to the log and stdout, a progress bar, SIGTERM as Ctrl-C.

    The log gets each record when it is known (completion order, each with its input
    ``index``: a run killed with SIGKILL keeps every garment it finished), and at the end
    is rewritten in input order; stdout (``--json``) gets them in input order."""
    import contextlib
    import os
    import signal
    import sys

    from ptailor.batch import record_line, run_batch
    from ptailor.errors import PtailorError

    old_term = None
    try:
        logf = open(log, "w") if log else None  # noqa: SIM115 - closed below
    except OSError as exc:
        raise PtailorError(f"cannot write the log ({exc.strerror or exc})", path=log) from None
    result = None
    try:

        def on_record(r: dict) -> None:
            if as_json:
                click.echo(record_line(r))

        def on_done(r: dict, progress=None) -> None:
            if logf is not None:
                logf.write(record_line(r) + "\n")
                logf.flush()
            if progress is not None:
                progress.update(1)

        with contextlib.suppress(ValueError):  # (only the main thread can)
            old_term = signal.signal(signal.SIGTERM, _interrupt)  # SIGTERM is Ctrl-C too
        if not bar:
            result = run_batch(
                todo, workers=workers, scheduler=scheduler, on_record=on_record, on_done=on_done
            )
            return result
        with click.progressbar(
            length=len(todo), label="adjusting", file=sys.stderr, show_pos=True
        ) as progress:
            result = run_batch(
                todo,
                workers=workers,
                scheduler=scheduler,
                on_record=on_record,
                on_done=lambda r: on_done(r, progress),
            )
            return result
    finally:
        if old_term is not None:
            signal.signal(signal.SIGTERM, old_term)
        if logf is not None:
            logf.close()
            if result is not None:  # the whole run's records, in input order
                tmp = f"{log}.{os.getpid()}.tmp"
                with contextlib.suppress(OSError):
                    with open(tmp, "w") as fh:
                        fh.writelines(record_line(r) + "\n" for r in result.records)
                    os.replace(tmp, log)
                with contextlib.suppress(OSError):
                    os.unlink(tmp)


def _summary(result, n: int, *, quiet: bool) -> None:
    """The end-of-batch table on stderr (the failures only with ``quiet``)."""
    from ptailor.batch import summary_lines

    lines = summary_lines(result)
    if quiet:
        lines = [ln for ln in lines if ln.startswith("  ")]
    for line in lines:
        click.echo(line, err=True)
    if result.interrupted:
        done = n - result.count("interrupted")
        click.echo(
            f"ptailor: interrupted: {done} of {n} garments done, their folders complete;"
            " run the same command again to finish the rest",
            err=True,
        )
