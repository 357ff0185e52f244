"""``ptailor measure``."""

from __future__ import annotations

import click

from ptailor.cli.options import GarmentPath, axes_options, garment_options, report_units_option


@click.command()
@click.argument("garment", type=GarmentPath())
@garment_options
@axes_options
@report_units_option()
@click.option("--json", "as_json", is_flag=True, help="Print JSON instead of a table.")
def measure(garment, drape, pattern_units, drape_units, weld, up, front, units, as_json) -> None:
    """List GARMENT's points of measure, in the drape and in the pattern.

    Each measure is named from the garment's structure (its openings, panels, the body's
    axis and limbs): chest, waist, hip, hem, neck, body_length, sleeve_length_left, bicep_left,
    cuff_left, skirt_length, thigh_left, inseam_left, ...; a measure the garment lacks is
    absent. A girth's drape value is the cross-section's perimeter, its pattern value the
    same line of cloth measured on the flat pieces it crosses (docs/measures.md).
    """
    import json

    from ptailor.formats.garment import load_garment
    from ptailor.measures import garment_measures, measure_dicts
    from ptailor.recipe import resolve_frame

    loaded = load_garment(
        garment,
        drape=drape,
        units=units,
        pattern_units=pattern_units,
        drape_units=drape_units,
        weld=weld,
        frame=resolve_frame(up, front, default=None),
    )
    g = loaded.garment
    dicts = in_units(measure_dicts(garment_measures(g), g.units), units)
    if as_json:
        click.echo(json.dumps({"units": units, "measures": dicts}, indent=2))
        return
    for line in table_lines(dicts, units=units, garment=garment):
        click.echo(line)


def in_units(dicts: list[dict], units: str) -> list[dict]:
    """Measure dicts (cm: :func:`ptailor.measures.measure_dicts`) with their lengths in
    ``units`` (``axis`` is a direction: unchanged)."""
    from ptailor.model.units import factor

    k = factor("cm", units)
    if k == 1.0:
        return dicts
    out = []
    for d in dicts:  # a loop over measures
        e = {**d, "drape": round(d["drape"] * k, 4), "pattern": round(d["pattern"] * k, 4)}
        if "height" in d:
            e["height"] = round(d["height"] * k, 4)
        if "point" in d:
            e["point"] = [round(x * k, 4) for x in d["point"]]
        out.append(e)
    return out


def table_lines(dicts: list[dict], *, units: str, garment: str) -> list[str]:
    """The measures as a table: name, kind, drape, pattern, pattern - drape."""
    if not dicts:
        return [f"{garment}: no points of measure (no opening or panel names a measure)"]
    w = max(len("measure"), *(len(d["name"]) for d in dicts))
    head = (
        f"{'measure':<{w}}  {'kind':<6}  {'drape ' + units:>10}  {'pattern ' + units:>10}"
        f"  {'pattern-drape':>13}"
    )
    lines = [head, "-" * len(head)]
    for d in dicts:  # a loop over measures
        diff = d["pattern"] - d["drape"]
        lines.append(
            f"{d['name']:<{w}}  {d['kind']:<6}  {d['drape']:>10.2f}  {d['pattern']:>10.2f}"
            f"  {diff:>+13.2f}"
        )
    return lines
