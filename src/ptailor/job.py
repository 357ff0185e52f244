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
from ptailor.recipe import Recipe, axis_vector, load_recipe
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


def load_body(path: str, *, units: str, to: str):
    """Read a body mesh with trimesh, scaled from ``units`` to ``to``.

    Raises
    ------
    PtailorError
        A missing or unreadable file, or one with no triangles.
    """
    import trimesh

    from ptailor.formats.garment import parse_units
    from ptailor.model.units import CM_PER

    if not Path(path).is_file():
        raise PtailorError("no such file", path=path)
    try:
        mesh = trimesh.load(path, force="mesh", process=False)
    except Exception as exc:  # trimesh raises many kinds for bad files
        raise PtailorError(f"not a readable body mesh ({exc})", path=path) from None
    if not hasattr(mesh, "faces") or len(mesh.faces) == 0:
        raise PtailorError("body mesh has no triangles", path=path)
    scale = parse_units(units, what="--body-units") / CM_PER[to]
    return trimesh.Trimesh(vertices=mesh.vertices * scale, faces=mesh.faces, process=False)


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
    up: str | None = None,
    front: str | None = None,
    body: str | None = None,
    body_units: str = "cm",
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
    up, front : str, optional
        The garment's axes (``y``, ``-z``, ...); default the recipe's, else y up, z front.
    body : str, optional
        A watertight body mesh (any format trimesh reads) in ``body_units``: extended rows
        are pushed out of it.
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
    inputs = [garment_path] + ([drape] if drape else []) + ([body] if body else [])
    check_output_dir(out, inputs)
    options = EditOptions(
        up=axis_vector(up or recipe.up or "y"),
        front=axis_vector(front or recipe.front or "z"),
        body=load_body(body, units=body_units, to=recipe.units) if body else None,
    )
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
        read = {**loaded.inputs, **({"body": body} if body else {})}
        shown = {**read, **(display_inputs or {})}
        report = build_report(
            adj, inputs=read, units_note=units_note, warnings=warnings, timing_s=timing
        )
        for role, path in shown.items():
            report["inputs"][role]["path"] = path
        report["outputs"] = sorted(["report.json", *written])
        write_json(tmp / "report.json", report)
    return report
