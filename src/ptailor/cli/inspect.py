"""``ptailor inspect``."""

from __future__ import annotations

import click

from ptailor.cli.options import axes_options, dxf_options, garment_options


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
    help="Unit to report lengths in (garments; a DXF is shown in its own units and cm).",
)
@dxf_options
@click.option("--json", "as_json", is_flag=True, help="Print JSON instead of text.")
def inspect(
    garment, drape, pattern_units, drape_units, weld, up, front, units, size, dxf_units, as_json
) -> None:
    """List GARMENT's panels, seams, openings and units.

    GARMENT may also be an AAMA/ASTM DXF pattern (PATTERN.dxf): its pieces, their sizes,
    quantities, notches and grain lines, the sizes the file grades to and its units.
    """
    import json

    from ptailor.cli.options import parse_weld_option
    from ptailor.errors import PtailorError
    from ptailor.formats import is_pattern_file, pattern_reader_for

    weld = parse_weld_option(weld, units=units)
    if is_pattern_file(garment):
        from ptailor.summary import pattern_summary, pattern_summary_text

        if drape is not None:
            raise PtailorError(
                "inspect lists a DXF's pieces on their own: drop --drape", path=garment
            )
        pattern = pattern_reader_for(garment)(garment, size=size, units=dxf_units)
        info = pattern_summary(pattern)
        click.echo(json.dumps(info, indent=2) if as_json else pattern_summary_text(info))
        return
    if size is not None or dxf_units is not None:
        raise PtailorError("--size and --dxf-units apply to DXF patterns only", path=garment)

    from ptailor.formats.garment import load_garment
    from ptailor.summary import garment_summary, summary_text

    loaded = load_garment(
        garment,
        drape=drape,
        units=units,
        pattern_units=pattern_units,
        drape_units=drape_units,
        weld=weld,
    )
    from ptailor.model.repair import topology
    from ptailor.recipe import resolve_axes

    up_v, front_v = resolve_axes(up, front)
    info = garment_summary(loaded, up=up_v, front=front_v)
    info["intake"] = {
        **info.get("intake", {}),
        "topology": topology(loaded.garment.V3, loaded.garment.F3),
    }
    if as_json:
        click.echo(json.dumps(info, indent=2))
    else:
        click.echo(summary_text(info))
