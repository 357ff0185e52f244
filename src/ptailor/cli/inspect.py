"""``ptailor inspect``."""

from __future__ import annotations

import click

from ptailor.cli.options import (
    GarmentPath,
    axes_options,
    dxf_options,
    garment_options,
    report_units_option,
    spec_option,
)


@click.command()
@click.argument("garment", type=GarmentPath())
@garment_options
@axes_options
@report_units_option(
    "Unit to report lengths in (garments; a DXF is shown in its own units and cm)."
)
@dxf_options
@spec_option(writes=False)
@click.option("--json", "as_json", is_flag=True, help="Print JSON instead of text.")
def inspect(
    garment,
    drape,
    pattern_units,
    drape_units,
    weld,
    up,
    front,
    units,
    size,
    dxf_units,
    spec,
    spec_units,
    as_json,
) -> None:
    """List GARMENT's panels, seams, openings and units.

    GARMENT may also be an AAMA/ASTM DXF pattern (PATTERN.dxf): its pieces, their sizes,
    quantities, notches and grain lines, the sizes the file grades to and its units; for a
    graded nest each size's grade from the size shown (--size, default the sample size):
    per piece its width, height and area difference and the largest point delta.

    With --spec SPEC.json (GarmentCode or Garment-Pattern-Generator), also each
    specification panel with the mesh panel it is matched to, and each stitch with its seam
    and the lengths of both edges in the specification and in the mesh.
    """
    import json

    from ptailor.errors import PtailorError
    from ptailor.formats import is_pattern_file
    from ptailor.formats.garment import parse_weld

    weld = parse_weld(weld, units=units)
    specification = None
    if spec is not None:  # read first: a bad specification fails before the garment is read
        from ptailor.run.spec import read_run_specification, spec_input

        found = spec_input(garment, spec)
        if found is None:
            raise PtailorError(
                "--spec auto: no specification beside the garment (looked for "
                "STEM_specification.json, its shorter prefixes, specification.json)",
                path=garment,
            )
        specification = read_run_specification(found, spec_units)
    if is_pattern_file(garment):
        if drape is not None:
            raise PtailorError(
                "inspect lists a DXF's pieces on their own: drop --drape", path=garment
            )
        if specification is not None:
            raise PtailorError(
                "--spec is matched to a garment's mesh (OBJ), not to a DXF pattern",
                path=garment,
            )
        _show_pattern(garment, size=size, dxf_units=dxf_units, as_json=as_json)
        return
    if size is not None or dxf_units is not None:
        raise PtailorError("--size and --dxf-units apply to DXF patterns only", path=garment)

    from ptailor.report.inspection import summary_text

    info = _garment_info(
        garment,
        drape=drape,
        units=units,
        pattern_units=pattern_units,
        drape_units=drape_units,
        weld=weld,
        axes=(up, front),
        spec=specification,
    )
    if as_json:
        click.echo(json.dumps(info, indent=2))
    else:
        click.echo(summary_text(info))


def _garment_info(garment, *, drape, units, pattern_units, drape_units, weld, axes, spec):
    """The summary of a garment (:func:`ptailor.report.inspection.garment_summary`), with its
    ``spec`` section when a specification is given and its points of measure (``measures``,
    in cm: :func:`ptailor.measures.measure_dicts`)."""
    from ptailor.formats.garment import load_garment
    from ptailor.measures import garment_measures, measure_dicts
    from ptailor.model.repair import topology
    from ptailor.recipe import resolve_frame
    from ptailor.report.inspection import garment_summary, spec_summary

    loaded = load_garment(
        garment,
        drape=drape,
        units=units,
        pattern_units=pattern_units,
        drape_units=drape_units,
        weld=weld,
        frame=resolve_frame(*axes, default=None),
    )
    matching = None
    if spec is not None:
        from ptailor.run.spec import matched_specification, spec_unit, spec_units

        spec = spec_unit(loaded, spec)
        loaded = spec_units(loaded, spec)
        matching = matched_specification(loaded, spec)
    info = garment_summary(loaded)
    info["intake"] = {
        **info.get("intake", {}),
        "topology": topology(loaded.garment.V3, loaded.garment.F3),
    }
    if matching is not None:
        info["spec"] = spec_summary(matching, info)
    # the points of measure, in cm (ptailor measure's)
    info["measures"] = measure_dicts(garment_measures(loaded.garment), loaded.garment.units)
    return info


def _show_pattern(garment, *, size, dxf_units, as_json: bool) -> None:
    """A DXF's pieces, sizes and units; for a graded nest each size's grade from the size
    shown (:func:`ptailor.report.inspection.grade_summary`)."""
    import json

    from ptailor.formats import pattern_reader_for, sizes_reader_for
    from ptailor.report.inspection import grade_summary, pattern_summary, pattern_summary_text

    pattern = pattern_reader_for(garment)(garment, size=size, units=dxf_units)
    info = pattern_summary(pattern)
    if len(pattern.sizes) > 1:  # a graded nest
        every = sizes_reader_for(garment)(garment, units=pattern.units)
        info["grades"] = grade_summary(every, pattern.size)
    click.echo(json.dumps(info, indent=2) if as_json else pattern_summary_text(info))
