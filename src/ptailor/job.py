"""One ``adjust`` job from files to an output folder; shared by ``adjust``, ``demo`` and batch."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from ptailor.adjust import Adjustment, adjust
from ptailor.edits import EditOptions
from ptailor.errors import PtailorError
from ptailor.formats.garment import LoadedGarment, load_garment
from ptailor.model.boundary import boundary_loops
from ptailor.output import check_output_dir, staged_dir, write_json
from ptailor.recipe import Recipe, load_recipe
from ptailor.report.build import build_report


def panel_outlines(V2: np.ndarray, F2: np.ndarray, adj: Adjustment) -> list[list[np.ndarray]]:
    """Closed boundary loops of each panel (outer outline first), as ``(k, 2)`` arrays."""
    out = []
    for p in adj.state.panels:  # a loop over panels
        loops = boundary_loops(F2[p.faces])
        out.append([V2[lp] for lp in loops])
    return out


def output_obj(tmp: Path, adj: Adjustment, loaded: LoadedGarment) -> str:
    """``garment.obj``: edited drape and adjusted pattern, in the input files' units."""
    from ptailor.formats.obj import write_obj
    from ptailor.method.flatten import panel_labels

    g = adj.garment
    header = [
        "ptailor adjusted garment: v = edited drape, vt = adjusted pattern",
        f"v: {loaded.drape_scale:.9g} {g.units} per unit; "
        f"vt: {loaded.pattern_scale:.9g} {g.units} per unit"
        + (" (estimated)" if loaded.pattern_units_estimated else ""),
    ]
    write_obj(
        tmp / "garment.obj",
        V3=g.V3 / loaded.drape_scale,
        F3=g.F3,
        V2=g.V2 / loaded.pattern_scale,
        F2=g.F2,
        face_panel=panel_labels(adj.state.panels, g.n_faces),
        panel_names=[p.name for p in adj.state.panels],
        header=header,
    )
    return "garment.obj"


def output_svg(tmp: Path, adj: Adjustment, loaded: LoadedGarment) -> str:
    """``pattern.svg``: adjusted outlines over the original ones (dashed), at 1:1."""
    from ptailor.formats.svg import pattern_svg

    del loaded
    g = adj.garment
    g0 = adj.original if adj.original is not None else adj.state.base
    orig = adj.original_panels()
    before = [
        [g0.V2[lp] for lp in boundary_loops(g0.F2[orig[p.name][0]])] if p.name in orig else []
        for p in adj.state.panels
    ]
    after = panel_outlines(g.V2, g.F2, adj)
    names = [p.name for p in adj.state.panels]
    (tmp / "pattern.svg").write_text(pattern_svg(before, after, names, units=g.units))
    return "pattern.svg"


#: output format -> writer(folder, adjustment, loaded garment) returning the file name
OUTPUTS = {"obj": output_obj, "svg": output_svg}
FORMATS = tuple(OUTPUTS)


def write_outputs(
    tmp: Path, adj: Adjustment, loaded: LoadedGarment, formats: tuple[str, ...]
) -> list[str]:
    """Write the adjusted garment in the requested formats into ``tmp``; return file names."""
    return [OUTPUTS[f](tmp, adj, loaded) for f in FORMATS if f in formats]


def run_adjust(
    garment_path: str,
    recipe: Recipe | str,
    out: str | Path,
    *,
    drape: str | None = None,
    pattern_units: str = "cm",
    drape_units: str = "cm",
    method: str | None = None,
    intrinsic: str | None = None,
    baseline: bool = True,
    formats: tuple[str, ...] = FORMATS,
    options: EditOptions | None = None,
    display_inputs: dict[str, str] | None = None,
    extra_files: dict[str, str] | None = None,
) -> dict:
    """Load, adjust and write one garment; return the report.

    Parameters
    ----------
    garment_path : str
        OBJ with drape (v) and pattern (vt), or the pattern only with ``drape``.
    recipe : Recipe or str
        A validated recipe, or the path of one (``-`` for stdin).
    out : str or Path
        Output folder, written all or nothing.
    drape, pattern_units, drape_units
        See :func:`ptailor.formats.garment.load_garment`.
    method, intrinsic : str, optional
        Override the recipe's flatten settings.
    baseline : bool
        Compute uniform flattening for comparison.
    formats : tuple of str
        Outputs to write besides ``report.json``.
    options : EditOptions, optional
    display_inputs : dict, optional
        Role to the path the report shows (default: the path read).
    extra_files : dict, optional
        File name to text, written into the output folder too.

    Returns
    -------
    dict
        The report.
    """
    if not isinstance(recipe, Recipe):
        recipe = load_recipe(recipe)
    unknown = [f for f in formats if f not in FORMATS]
    if unknown:
        raise PtailorError(
            f"unknown output format(s) {', '.join(unknown)} (known: {', '.join(FORMATS)})"
        )
    inputs = [garment_path] + ([drape] if drape else [])
    check_output_dir(out, inputs)
    t0 = time.perf_counter()
    loaded = load_garment(
        garment_path,
        drape=drape,
        units=recipe.units,
        pattern_units=pattern_units,
        drape_units=drape_units,
    )
    t1 = time.perf_counter()
    adj = adjust(
        loaded.garment,
        recipe,
        method=method,
        intrinsic=intrinsic,
        baseline=baseline,
        options=options,
    )
    warnings: list[str] = []
    if not adj.result.info.converged:
        warnings.append(
            f"solver stopped after {adj.result.info.iterations} iterations without converging"
        )
    units_note = {
        "computation": loaded.garment.units,
        "drape": drape_units,
        "pattern": pattern_units,
    }
    if loaded.pattern_units_estimated:
        units_note["pattern_scale_estimate"] = round(loaded.pattern_scale, 6)
        warnings.append(
            f"pattern units estimated from the drape: {loaded.pattern_scale:.4g} "
            f"{loaded.garment.units} per pattern unit"
        )
    with staged_dir(out) as tmp:
        t2 = time.perf_counter()
        written = write_outputs(tmp, adj, loaded, formats)
        for name, text in (extra_files or {}).items():
            (tmp / name).write_text(text)
        t3 = time.perf_counter()
        timing = {"load": t1 - t0, **adj.timing_s, "write": t3 - t2}
        shown = dict(loaded.inputs)
        if display_inputs:
            shown.update(display_inputs)
        report = build_report(
            adj, inputs=loaded.inputs, units_note=units_note, warnings=warnings, timing_s=timing
        )
        for role, path in shown.items():
            report["inputs"][role]["path"] = path
        report["outputs"] = sorted(["report.json", *written])
        write_json(tmp / "report.json", report)
    return report
