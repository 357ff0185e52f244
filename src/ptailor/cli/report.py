"""``ptailor report``: the catalogue page of an existing batch output root."""

from __future__ import annotations

import click

#: ``ptailor report --help``
REPORT_HELP = """Write OUT/index.html, the catalogue of a batch output root: one row per
garment (status, failure reason, thumbnail, the record's numbers), sortable and
filterable, and a page per garment (OUT/NAME/index.html: the pattern SVG, the panel and
seam tables, the steps, the warnings, the re-drape picture, every output file).

The rows are the batch's records: --log FILE (a ptailor batch --log), else those the last
ptailor batch --html saved in OUT/_catalogue, else the garment folders alone (failed
garments have no folder, so they are then not shown). Garment folders no record names are
added (status earlier). Static and offline: open it from disk or a CI artifact.

Prints the page's path on stdout. Exit status 2: OUT is not a batch output root (no
garment folder and no records), its index.html is not ptailor's, or the log is not a log.
"""


@click.command(help=REPORT_HELP)
@click.argument("out", type=click.Path(file_okay=False, exists=True))
@click.option(
    "--log",
    type=click.Path(dir_okay=False, exists=True),
    default=None,
    help="The batch's records (ptailor batch --log FILE), for the rows of failed garments.",
)
@click.option("--title", default=None, help="The page's title [default: ptailor catalogue: OUT].")
@click.option("-q", "--quiet", is_flag=True, help="No warnings on stderr.")
def report(out, log, title, quiet) -> None:
    """``ptailor report``: its help is :data:`REPORT_HELP`."""
    from pathlib import Path

    from ptailor.catalogue import Summary, read_log, saved_records, write_catalogue
    from ptailor.catalogue.rows import garment_folders
    from ptailor.errors import PtailorError

    def warn(msg: str) -> None:
        if not quiet:
            click.echo(f"ptailor: warning: {msg}", err=True)

    saved = saved_records(Path(out), warn=warn)
    if log is not None:  # (the recipe the last catalogue saved, if any)
        last = saved[1] if saved else Summary()
        records = read_log(log)
        summary = Summary(source=f"the log {log}", recipe=last.recipe, recipe_text=last.recipe_text)
    else:
        records, summary = saved or ([], Summary(source="the garment folders"))
    if not records and not garment_folders(Path(out)):
        raise PtailorError(
            "not a batch output root: no garment folder (with report.json) and no records",
            path=out,
        )

    page = write_catalogue(out, records, summary, title=title, warn=warn)
    click.echo(str(page))
