"""``ptailor inspect``."""

from __future__ import annotations

import click

from ptailor.cli.options import axes_options, axis_vector, garment_options


@click.command()
@click.argument("garment", type=click.Path(dir_okay=False))
@garment_options
@axes_options
@click.option(
    "--units",
    "units",
    default="cm",
    show_default=True,
    type=click.Choice(["mm", "cm", "m", "in"]),
    help="Unit to report lengths in.",
)
@click.option("--json", "as_json", is_flag=True, help="Print JSON instead of text.")
def inspect(garment, drape, pattern_units, drape_units, up, front, units, as_json) -> None:
    """List GARMENT's panels, seams, openings and units."""
    import json

    from ptailor.formats.garment import load_garment
    from ptailor.summary import garment_summary, summary_text

    loaded = load_garment(
        garment, drape=drape, units=units, pattern_units=pattern_units, drape_units=drape_units
    )
    info = garment_summary(loaded, up=axis_vector(up, "y"), front=axis_vector(front, "z"))
    info["units"].update({"pattern": pattern_units, "drape": drape_units})
    if as_json:
        click.echo(json.dumps(info, indent=2))
    else:
        click.echo(summary_text(info))
