"""``ptailor verify``."""

from __future__ import annotations

import click

from ptailor.cli.options import AXES, GarmentPath, body_options, units_options
from ptailor.cli.verify_options import max_steps_option, null_options, rest_option


@click.command()
@click.argument("garment", type=GarmentPath())
@click.option(
    "--original",
    type=click.Path(dir_okay=False),
    default=None,
    help="The garment before the edit (same faces as GARMENT): its pattern and drape give "
    "the intrinsic scale, and its pattern is the reference re-drape [default: GARMENT].",
)
@click.option("-o", "--out", required=True, type=click.Path(file_okay=False), help="Output folder.")
@units_options
@click.option("--up", default=None, type=click.Choice(AXES), help="Up axis [default: y].")
@click.option("--front", default=None, type=click.Choice(AXES), help="Front axis [default: z].")
@body_options
@rest_option()
@max_steps_option()
@null_options()
@click.option("--json", "as_json", is_flag=True, help="Print verify.json on stdout.")
@click.option("-q", "--quiet", is_flag=True, help="Print nothing on success.")
def verify(garment, original, out, as_json, quiet, **run) -> None:
    """Re-drape GARMENT's pattern with a cloth engine and write the check to OUT.

    GARMENT is an OBJ with v = drape and vt = pattern, typically an adjusted garment.obj
    with --original the garment it was made from. GARMENT's pattern (ours) and the uniform
    flattening of its drape (baseline) are sewn onto GARMENT's drape, ORIGINAL's pattern
    onto ORIGINAL's drape (the null test: it must land where it started), and settled
    under gravity, the top opening pinned. The verdict ranks ours against the baseline only
    when the null test holds. Writes OUT/verify.json (per panel: stretch, compression,
    displacement from the start drape; null, verdict), verify_ours.obj,
    verify_baseline.obj (the settled drapes) and verify.png. Lengths are in --drape-units
    (cm for a scaled unit). Needs pip install 'ptailor[sim]'.
    """
    import json

    from ptailor.cli.options import build_run_options, check_engine_first
    from ptailor.model.units import CM_PER
    from ptailor.run.verify import verify_garment

    check_engine_first(True)  # (before any file is read)
    units = run["drape_units"] if run["drape_units"] in CM_PER else "cm"
    options = build_run_options(run, units=units, verify=True)  # (--rest ...: verify_*)
    from ptailor.cli.progress import progress_line

    with progress_line(quiet=quiet) as progress:
        doc = verify_garment(
            garment, out, original=original, options=options, units=units, progress=progress
        )
    if as_json:
        click.echo(json.dumps(doc, indent=2))
    elif not quiet:
        from ptailor.verify.summary import summary_lines

        for line in summary_lines(doc):
            click.echo(line)
        click.echo(f"wrote {out}/ ({', '.join(doc['outputs'])})", err=True)
