"""``ptailor adjust``."""

from __future__ import annotations

import click

from ptailor.cli.options import GarmentPath, drape_option, run_options


@click.command()
@click.argument("garment", type=GarmentPath())
@click.argument("recipe", type=click.Path(dir_okay=False, allow_dash=True), required=False)
@click.option("-o", "--out", required=True, type=click.Path(file_okay=False), help="Output folder.")
@drape_option
@click.option(
    "--edited-drape",
    type=click.Path(dir_okay=False),
    default=None,
    help="OBJ of GARMENT's drape edited in another tool (same vertices and faces; vt "
    "ignored): the edit, in place of RECIPE's steps (RECIPE then optional: settings, expect).",
)
@run_options
@click.option("--json", "as_json", is_flag=True, help="Print the report as JSON on stdout.")
@click.option("-q", "--quiet", is_flag=True, help="Print nothing on success.")
def adjust(garment, recipe, out, drape, edited_drape, as_json, quiet, **run) -> None:
    """Apply RECIPE's 3D edits to GARMENT and write the adjusted pattern to OUT.

    GARMENT is an OBJ with v = drape and vt = pattern (faces f v/vt), or an AAMA/ASTM DXF
    pattern with --drape an OBJ whose vt triangulates its pieces (same layout and units).
    RECIPE is a YAML edit recipe ('-' reads it from stdin); it is validated whole before
    GARMENT is read. --verify re-drapes the result with the cloth engine (the body, when
    given, holds the re-drapes too; the top opening is pinned).

    With --edited-drape EDITED.obj (GARMENT's drape edited in Blender, Maya, CLO, ...: the
    same vertices and faces, moved), the pattern follows that drape instead of RECIPE's
    steps; RECIPE is then optional and may give units, axes, flatten settings and expect:.

    When the result misses a measure the recipe's expect: asks for, the outputs are
    written, stderr has one line per missed measure and the exit status is 3.
    """
    from ptailor.cli.options import build_run_options, check_engine_first
    from ptailor.cli.progress import progress_line
    from ptailor.recipe import load_recipe
    from ptailor.run.folder import check_output_dir
    from ptailor.run.garment import run_garment

    check_engine_first(run["verify"])  # (before any file is read)
    # every input (the recipe too) is checked against the output folder before any is read
    check_output_dir(out, [garment, recipe, drape, run["body"], run["spec"], edited_drape])
    if recipe is None and edited_drape is None:
        raise click.UsageError("Missing argument 'RECIPE' (or give --edited-drape).")
    from ptailor.run.edited import NO_RECIPE

    rec = NO_RECIPE if recipe is None else load_recipe(recipe)
    options = build_run_options(run, units=rec.units, edited_drape=edited_drape)
    with progress_line(quiet=quiet) as progress:
        report = run_garment(garment, rec, out, options=options, drape=drape, progress=progress)
    _show(report, out, as_json=as_json, quiet=quiet)
    _expectations(report)


def _expectations(report) -> None:
    """Exit 3, one line per missed measure on stderr, when the result misses the recipe's
    ``expect:`` (the outputs are written)."""
    from ptailor.report.expect import missed_lines

    missed = missed_lines(report)
    for line in missed:
        click.echo(f"ptailor: expect: {line}", err=True)
    if missed:
        raise click.exceptions.Exit(3)


def _show(report, out, *, as_json: bool, quiet: bool) -> None:
    """The report on stdout: JSON, or the summary (and the re-drape's) and what was written."""
    import json
    from pathlib import Path

    from ptailor.report.build import summary_lines

    if as_json:
        click.echo(json.dumps(report, indent=2))
    elif not quiet:
        for line in summary_lines(report):
            click.echo(line)
        if "verify" in report:
            from ptailor.verify.summary import summary_lines as verify_lines

            for line in verify_lines(report):
                click.echo(line)
        click.echo(f"wrote {Path(out)}/ ({', '.join(report['outputs'])})", err=True)
