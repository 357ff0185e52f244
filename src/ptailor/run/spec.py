"""A run with a pattern specification (``--spec``): read, matched, adjusted, written, checked.

The specification is read before the garment (a bad one fails first, nothing read or
written); with ``--pattern-units auto`` its panel areas fix the pattern's scale (a [0, 1]
atlas has none); it is matched to the input garment's panels before the adjustment, so a
specification of another garment fails before any work; after the adjustment it is carried
through (:func:`ptailor.spec.adjust.adjusted_specification`), written as
``specification.json`` and checked against the adjusted mesh outline (report ``spec``).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from ptailor import tolerances as tol
from ptailor.errors import PtailorError
from ptailor.formats.garment import LoadedGarment
from ptailor.model.specification import Specification
from ptailor.model.structure import structure
from ptailor.model.units import CM_PER
from ptailor.spec.match import SpecMatching, match_specification

__all__ = [
    "SPEC_FILE",
    "matched_specification",
    "read_run_specification",
    "spec_input",
    "spec_outputs",
    "spec_unit",
    "spec_units",
]

#: the adjusted specification's file name in the output folder
SPEC_FILE = "specification.json"


def spec_input(garment: str, spec: str | None) -> str | None:
    """The specification a run reads: ``spec`` as given, the one beside ``garment`` for
    ``auto`` (:func:`ptailor.formats.spec_json.specification_beside`; None when there is
    none), or None."""
    if spec != "auto":
        return spec
    from ptailor.formats.spec_json import specification_beside

    return specification_beside(garment)


def read_run_specification(path: str, spec_units: str | None) -> Specification:
    """The specification at ``path``, in the unit ``spec_units`` when given (``--spec-units``:
    ``cm``, ``0.3333cm``)."""
    from ptailor.formats.garment import parse_units
    from ptailor.formats.spec_json import read_specification

    if spec_units is None:
        return read_specification(path)
    cm = parse_units(spec_units, what="--spec-units")
    return read_specification(path, units_in_meter=100.0 / cm)


def _panel_area(spec: Specification) -> float:
    """The specification's panels' total area, in its units squared."""
    from ptailor.model.polyline import signed_area

    return sum(abs(signed_area(p.outline(64)[0])) for p in spec.panels)


def spec_unit(loaded: LoadedGarment, spec: Specification) -> Specification:
    """A specification without ``units_in_meter`` in the unit that fits the garment:
    of :data:`ptailor.tolerances.SPEC_UNIT_GUESSES`, the one at which its panels' total
    area is the garment pattern's, within ``SPEC_AREA_REL`` (the nearest if several).
    A specification with its unit is returned as it is.

    Raises
    ------
    PtailorError
        No usual unit fits (it names the scale that would): give ``--spec-units``.
    """
    if spec.units_source != "absent":
        return spec
    from ptailor.geometry.triangles import signed_areas_2d

    g = loaded.garment
    a_mesh = float(np.abs(signed_areas_2d(g.V2, g.F2)).sum()) * CM_PER[g.units] ** 2
    a_spec = max(_panel_area(spec), tol.TINY)
    off = {um: abs(a_spec * (100.0 / um) ** 2 / max(a_mesh, tol.TINY) - 1.0)
           for um in tol.SPEC_UNIT_GUESSES}  # fmt: skip
    um = min(off, key=off.get)
    if off[um] > tol.SPEC_AREA_REL:
        would = 100.0 / float(np.sqrt(a_mesh / a_spec))
        raise PtailorError(
            f"no properties.units_in_meter, and at no usual unit ("
            f"{', '.join(f'{u:g}' for u in tol.SPEC_UNIT_GUESSES)} units per metre) have its "
            f"panels the garment's area (they would at {would:.4g} units per metre): give "
            "--spec-units",
            path=spec.path,
        )
    return replace(spec, units_in_meter=float(um), units_source="garment")


def spec_units(loaded: LoadedGarment, spec: Specification) -> LoadedGarment:
    """With ``--pattern-units auto``, the pattern scaled so its panels have the
    specification's total area (the atlas's scale, exactly; the drape's estimate is
    replaced). Otherwise ``loaded`` as it is."""
    if not loaded.pattern_units_estimated:
        return loaded
    from ptailor.geometry.triangles import signed_areas_2d

    g = loaded.garment
    k = spec.cm_per_unit / CM_PER[g.units]
    a_spec = _panel_area(spec) * k * k
    a_mesh = float(np.abs(signed_areas_2d(g.V2, g.F2)).sum())
    s = float(np.sqrt(a_spec / max(a_mesh, tol.TINY)))
    units = dict(loaded.intake.get("units", {}))
    scale = loaded.pattern_scale * s
    units.update(pattern=f"{scale:.9g}{g.units}", pattern_source="specification")
    return replace(
        loaded,
        garment=replace(g, V2=g.V2 * s),
        pattern_scale=scale,
        pattern_units_estimated=False,
        intake={**loaded.intake, "units": units},
    )


def matched_specification(loaded: LoadedGarment, spec: Specification) -> SpecMatching:
    """``spec`` matched to the input garment's panels and seams (under its frame)."""
    st = structure(loaded.garment)
    return match_specification(loaded.garment, spec, st.panels, seams=st.seams)


def spec_outputs(tmp: Path, adj, matching: SpecMatching) -> tuple[list[str], dict, list[str]]:
    """Write ``specification.json`` into ``tmp``; return the files written, the report's
    ``spec`` section and its warnings."""
    from ptailor.formats.spec_json import write_specification
    from ptailor.pieces.plan import source_panels
    from ptailor.spec.adjust import adjusted_specification
    from ptailor.spec.check import spec_fit

    g0 = adj.original if adj.original is not None else adj.state.base
    orig = structure(g0).panels
    adjusted = adjusted_specification(adj, matching, orig, source_panels(adj, tuple(orig)))
    write_specification(
        tmp / SPEC_FILE,
        adjusted.spec,
        edge_sources={c.name: list(c.edge_sources) for c in adjusted.changes},
    )
    units = g0.units
    cm = CM_PER[units]
    fits = spec_fit(adjusted, adj.result.V2, adj.state.base.F2, list(adj.state.panels))
    panels, warnings = _panel_records(adj, matching, adjusted, fits, units=units)
    stitches = _stitch_records(matching, adjusted)
    for si in adjusted.dropped_stitches:  # a loop over stitches
        (pa, ea), (pb, eb) = matching.spec.stitches[si].sides
        warnings.append(
            f"spec: stitch {si} ({pa}.{ea} to {pb}.{eb}) dropped: its edge left the pattern"
        )
    for name in adjusted.removed_panels:  # a loop over panels
        warnings.append(f"spec: panel {name!r} removed: the adjustment removed its triangles")
    section = {
        "input": matching.spec.path,
        "format": matching.spec.flavour,
        "units_in_meter": matching.spec.units_in_meter,
        "units_source": matching.spec.units_source,
        "file": SPEC_FILE,
        "fit_max": round(max((float(d.max(initial=0.0)) for d in fits), default=0.0), 6),
        "fit_warn": round(tol.SPEC_FIT_WARN_CM / cm, 6),
        "panels": panels,
        "stitches": stitches,
        "dropped_stitches": list(adjusted.dropped_stitches),
        "removed_panels": list(adjusted.removed_panels),
    }
    return [SPEC_FILE], section, warnings


def _panel_records(
    adj, matching: SpecMatching, adjusted, fits: list[np.ndarray], *, units: str
) -> tuple[list[dict], list[str]]:
    """The ``spec`` section's ``panels`` (each written panel: where it came from, how it was
    made, its fit to the adjusted outline, the map to the pattern) and their warnings."""
    k = matching.scale
    cm = CM_PER[units]
    warnings, panels = [], []
    for sp, ch, d in zip(adjusted.spec.panels, adjusted.changes, fits, strict=True):  # panels
        m = next(pm for pm in matching.panels if matching.spec.panels[pm.spec].name == ch.source)
        worst = float(d.max(initial=0.0))
        rec = {
            "name": sp.name,
            "panel": adj.state.panels[ch.panel].name,
            "how": ch.how,
            "mirrored": bool(np.linalg.det(m.R) < 0),
            "input_fit": round(m.distance, 6),
            "fit": round(worst, 6),
            "edges": len(sp.edges),
            "edge_sources": list(ch.edge_sources),
            "bent": [{"edge": i, "deviation": round(dev * k, 6)} for i, dev in ch.bent],
            "refit_max": round(max(ch.refit, default=0.0) * k, 6),
            "to_pattern": {  # spec panel point x -> adjusted pattern point A x + b
                "matrix": [[round(float(v), 12) for v in row] for row in ch.to_pattern[0]],
                "offset": [round(float(v), 9) for v in ch.to_pattern[1]],
            },
        }
        if ch.removed:
            rec["removed_edges"] = list(ch.removed)
        panels.append(rec)
        if worst * cm > tol.SPEC_FIT_WARN_CM:
            e = int(np.argmax(d))
            warnings.append(
                f"spec: panel {sp.name!r} edge {e} lies {worst:.3g} {units} from the adjusted "
                f"mesh outline (more than {tol.SPEC_FIT_WARN_CM * 10:g} mm)"
            )
        for i, dev in ch.bent:
            warnings.append(
                f"spec: panel {sp.name!r} edge {i} was straight and is now curved (its "
                f"points leave the chord by {dev * k:.3g} {units})"
            )
    return panels, warnings


def _stitch_records(matching: SpecMatching, adjusted) -> list[dict]:
    """The ``spec`` section's ``stitches``: each written stitch's sides and their curve
    lengths before and after (in the pattern's units)."""
    from ptailor.spec.check import edge_lengths

    k = matching.scale
    before = edge_lengths(matching.spec)
    after = edge_lengths(adjusted.spec)
    stitches = []
    for st, si in zip(adjusted.spec.stitches, adjusted.stitch_sources, strict=True):
        (pa, ea), (pb, eb) = st.sides
        (qa, fa), (qb, fb) = matching.spec.stitches[si].sides
        stitches.append(
            {
                "stitch": si,
                "sides": [f"{pa}.{ea}", f"{pb}.{eb}"],
                "before": [round(before[qa, fa] * k, 6), round(before[qb, fb] * k, 6)],
                "after": [round(after[pa, ea] * k, 6), round(after[pb, eb] * k, 6)],
            }
        )
    return stitches
