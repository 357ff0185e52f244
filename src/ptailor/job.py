"""One ``adjust`` job from files to an output folder; shared by ``adjust``, ``demo`` and batch."""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ptailor import tolerances as tol
from ptailor.edits import EditOptions
from ptailor.errors import PtailorError
from ptailor.formats.garment import LoadedGarment, load_garment
from ptailor.model.boundary import boundary_loops
from ptailor.output import check_output_dir, staged_dir, write_json
from ptailor.pieces import CarriedPiece, PiecePlan
from ptailor.pipeline import Adjustment, adjustment, check_flatten_settings, solver_warnings
from ptailor.recipe import Recipe, load_recipe, resolve_axes
from ptailor.report.build import build_report


def panel_outlines(V2: np.ndarray, F2: np.ndarray, adj: Adjustment) -> list[list[np.ndarray]]:
    """Closed boundary loops of each panel (outer outline first), as ``(k, 2)`` arrays."""
    out = []
    for p in adj.state.panels:  # a loop over panels
        loops = boundary_loops(F2[p.faces])
        out.append([V2[lp] for lp in loops])
    return out


@dataclass(frozen=True)
class OutputContext:
    """What the output writers share besides the adjustment.

    Attributes
    ----------
    loaded : LoadedGarment
        The input, with its file units.
    pieces : list of CarriedPiece or None
        The adjusted pieces (computation units), ``None`` for panels removed whole.
    plan : PiecePlan or None
        None when no DXF is read or written.
    errors : (m,) float array
        Intrinsic-scale error per adjusted triangle.
    seam_allowance : float or None
        Computation units; the pattern's outline is then the sew line.
    title : str
        The previews' heading.
    sheet : dict or None
        What both previews draw (:func:`_sheet`), computed once when either is written.
    """

    loaded: LoadedGarment
    pieces: list[CarriedPiece | None]
    plan: PiecePlan | None
    errors: np.ndarray
    seam_allowance: float | None = None
    title: str = ""
    sheet: dict | None = None


def output_obj(tmp: Path, adj: Adjustment, ctx: OutputContext) -> str:
    """``garment.obj``: edited drape and adjusted pattern, in the input files' units."""
    from ptailor.formats.obj import write_obj
    from ptailor.method.flatten import panel_labels

    loaded = ctx.loaded
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


def _sheet(adj: Adjustment, ctx: OutputContext) -> dict:
    """The arguments both previews take: outlines before and after, triangles, errors."""
    g = adj.garment
    g0 = adj.original if adj.original is not None else adj.state.base
    orig = adj.original_panels()
    before = [
        [g0.V2[lp] for lp in boundary_loops(g0.F2[orig[p.name][0]])] if p.name in orig else []
        for p in adj.state.panels
    ]
    tris = []
    errs = []
    for p in adj.state.panels:  # a loop over panels
        vs, inv = np.unique(g.F2[p.faces], return_inverse=True)
        tris.append((g.V2[vs], inv.reshape(-1, 3)))
        errs.append(ctx.errors[p.faces])
    return {
        "outlines_before": before,
        "outlines_after": panel_outlines(g.V2, g.F2, adj),
        "names": [p.name for p in adj.state.panels],
        "units": g.units,
        "title": ctx.title,
        "triangles": tris,
        "errors": errs,
    }


def output_svg(tmp: Path, adj: Adjustment, ctx: OutputContext) -> str:
    """``pattern.svg``: adjusted outlines over the original ones (dashed), at 1:1."""
    from ptailor.formats.svg import pattern_svg

    (tmp / "pattern.svg").write_text(pattern_svg(**(ctx.sheet or _sheet(adj, ctx))))
    return "pattern.svg"


def output_png(tmp: Path, adj: Adjustment, ctx: OutputContext) -> str:
    """``preview.png``: the same sheet as the SVG, as a picture."""
    from ptailor.formats.png import pattern_png

    pattern_png(tmp / "preview.png", **(ctx.sheet or _sheet(adj, ctx)))
    return "preview.png"


def output_dxf(tmp: Path, adj: Adjustment, ctx: OutputContext) -> str:
    """``pattern.dxf``: AAMA/ASTM pieces with their construction marks carried through."""
    from dataclasses import replace

    from ptailor.formats.dxf import write_dxf
    from ptailor.model.pieces import PatternFile
    from ptailor.model.units import CM_PER
    from ptailor.pieces import scale_piece, with_seam_allowance

    units = ctx.plan.units
    k = CM_PER[adj.garment.units] / CM_PER[units]
    pieces = []
    for cp in ctx.pieces:  # a loop over pieces
        if cp is None:
            continue
        pc = cp.piece
        if ctx.seam_allowance:
            pc = with_seam_allowance(pc, ctx.seam_allowance)
        pieces.append(scale_piece(pc, k))
    src = ctx.loaded.pattern
    pf = PatternFile(
        pieces=tuple(pieces),
        units=units,
        style=src.style if src is not None else Path(ctx.loaded.inputs.get("garment", "")).stem,
        sizes=(src.size,) if src is not None and src.size else (),
        size=src.size if src is not None else "",
        sample_size=src.sample_size if src is not None else "",
    )
    if src is not None:
        pf = replace(pf, units_text=src.units_text)
    write_dxf(tmp / "pattern.dxf", pf)
    return "pattern.dxf"


#: output format -> writer(folder, adjustment, context) returning the file name
OUTPUTS = {"obj": output_obj, "dxf": output_dxf, "svg": output_svg, "png": output_png}
FORMATS = tuple(OUTPUTS)


def write_outputs(
    tmp: Path, adj: Adjustment, ctx: OutputContext, formats: tuple[str, ...]
) -> list[str]:
    """Write the adjusted garment in the requested formats into ``tmp``; return file names."""
    from dataclasses import replace

    if ctx.sheet is None and {"svg", "png"} & set(formats):
        ctx = replace(ctx, sheet=_sheet(adj, ctx))
    return [OUTPUTS[f](tmp, adj, ctx) for f in FORMATS if f in formats]


def pieces_record(plan: PiecePlan, pieces: list[CarriedPiece | None]) -> list:
    """The report's ``pieces``: each piece's panel, how it matched, what its marks did."""
    names = [p.name for p in plan.panels]
    now = plan.panel_names or tuple(names[m.panel] for m in plan.matches)
    out = []
    for pc, m, ff, cp, pn in zip(
        plan.pieces, plan.matches, plan.from_file, pieces, now, strict=True
    ):
        rec = {
            "name": pc.name,
            "panel": pn,
            "source": "file" if ff else "mesh",
            "matched_by": m.how,
        }
        if ff:
            rec["match_residual"] = round(m.residual, 6)
            rec["match_distance"] = round(m.distance, 6)
            rec["mirrored"] = bool(np.linalg.det(m.R) < 0)
            rec["unfolded"] = bool(m.fold)
        if cp is None:
            rec["removed"] = True
        else:
            rec.update(
                {
                    "outline": cp.outline_from,
                    "notches": len(cp.piece.notches),
                    "grain_line": cp.piece.grain is not None,
                    "fold_line": cp.piece.mirror is not None,
                    "internal_lines": len(cp.piece.internal),
                    "drill_holes": len(cp.piece.drills),
                    "marks_dropped": cp.dropped,
                }
            )
        out.append(rec)
    return out


def load_body(path: str, *, units: str, to: str):
    """Read a ``--body`` mesh (:func:`ptailor.edits.body.read_body`)."""
    from ptailor.edits.body import read_body

    return read_body(path, units=units, to=to)


def check_seam_allowance(garment, allowance: float) -> None:
    """Refuse a seam allowance above ``tol.SEAM_ALLOWANCE_MAX_REL`` of the largest piece."""
    from ptailor.model.garment import panels

    diag = 0.0
    for p in panels(garment):  # a loop over panels
        P = garment.V2[p.vertices]
        diag = max(diag, float(np.linalg.norm(P.max(axis=0) - P.min(axis=0))))
    if not allowance <= tol.SEAM_ALLOWANCE_MAX_REL * diag:
        raise PtailorError(
            f"--seam-allowance {allowance:g} {garment.units} is larger than "
            f"{tol.SEAM_ALLOWANCE_MAX_REL:g} of the largest piece's diagonal "
            f"({diag:.4g} {garment.units})"
        )


def check_finite_result(adj: Adjustment, errors: np.ndarray, *, path: str) -> None:
    """The final guard: refuse to write a drape, pattern or errors that are not finite.

    Raises
    ------
    PtailorError
        Naming the array and the solver step that produced it.
    """
    g = adj.garment
    used3 = np.unique(g.F3)
    used2 = np.unique(g.F2)
    checks = [
        ("the edited drape (the recipe's steps)", g.V3[used3]),
        ("the adjusted pattern (the flatten solver)", g.V2[used2]),
        ("the intrinsic-scale errors (the flatten solver)", errors),
    ]
    if adj.baseline is not None:
        checks.append(("the uniform baseline (flatten)", adj.baseline.V2[used2]))
    for what, arr in checks:  # a handful of arrays
        if not np.all(np.isfinite(arr)):
            raise PtailorError(
                f"{what} has non-finite values: a numeric failure; nothing written", path=path
            )


def intrinsic_error_warnings(adj: Adjustment, errors: np.ndarray) -> list[str]:
    """A warning naming the panels whose intrinsic-scale error p95 exceeds the bound."""
    bad = []
    for p in adj.state.panels:  # a loop over panels
        e = errors[p.faces]
        if len(e) and np.percentile(e, 95) > tol.INTRINSIC_ERROR_WARN:
            bad.append(f"{p.name} ({np.percentile(e, 95):.3g})")
    if not bad:
        return []
    return [
        f"intrinsic-scale error p95 above {tol.INTRINSIC_ERROR_WARN:g} on panel(s) "
        f"{', '.join(bad[:5])}{' and more' if len(bad) > 5 else ''}: the edit distorts the "
        "pattern far beyond what it can absorb; check the recipe"
    ]


def non_finite_numbers(obj, where: str = "report") -> list[str]:
    """Paths of the NaN or infinite numbers in a JSON-like object (report guard)."""
    out: list[str] = []
    if isinstance(obj, dict):
        for k, v in obj.items():
            out += non_finite_numbers(v, f"{where}.{k}")
    elif isinstance(obj, (list, tuple)):
        for i, v in enumerate(obj):
            out += non_finite_numbers(v, f"{where}[{i}]")
    elif isinstance(obj, (float, np.floating, np.ndarray)):
        arr = np.asarray(obj)
        if arr.dtype.kind == "f" and not np.all(np.isfinite(arr)):
            out.append(where)
    return out


def run_adjust(
    garment_path: str,
    recipe: Recipe | str,
    out: str | Path,
    *,
    drape: str | None = None,
    pattern_units: str = "cm",
    drape_units: str = "cm",
    weld: str | float = "auto",
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
    size: str | None = None,
    dxf_units: str | None = None,
    seam_allowance: float | None = None,
    check=None,
) -> dict:
    """Load, adjust and write one garment; return the report.

    Parameters
    ----------
    garment_path : str
        OBJ with drape (v) and pattern (vt), or the pattern only with ``drape``; or a DXF
        pattern with ``drape`` an OBJ whose ``vt`` triangulates its pieces.
    recipe : Recipe or str
        A validated recipe, or the path of one (``-`` for stdin).
    out : str or Path
        Output folder, written all or nothing.
    drape, pattern_units, drape_units, weld
        See :func:`ptailor.formats.garment.load_garment`; what the intake repaired goes
        into the report's ``intake``.
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
    size, dxf_units : str, optional
        For a DXF pattern: the size to read, and its unit (default: from the file).
    seam_allowance : float, optional
        In the recipe's units: the DXF's cut line is the adjusted outline offset by this
        (mitred corners), and the outline itself becomes the sew line (layer 14).
    check : callable, optional
        ``check(report)`` is called before the output folder is put in place; when it
        raises, nothing is written (quality gates).

    Returns
    -------
    dict
        The report.
    """
    from ptailor.model.garment import panels
    from ptailor.pieces import carry_plan, piece_plan
    from ptailor.report.build import triangle_errors

    if not isinstance(recipe, Recipe):
        recipe = load_recipe(recipe)
    if seam_allowance is not None and not (np.isfinite(seam_allowance) and seam_allowance >= 0):
        raise PtailorError(f"--seam-allowance must be a length >= 0, not {seam_allowance}")
    unknown = [f for f in formats if f not in FORMATS]
    if unknown:
        raise PtailorError(
            f"unknown output format(s) {', '.join(unknown)} (known: {', '.join(FORMATS)})"
        )
    try:
        check_flatten_settings({**recipe.flatten})
    except PtailorError as exc:
        raise PtailorError(exc.message, path=recipe.source) from None
    inputs = [garment_path] + ([drape] if drape else []) + ([body] if body else [])
    check_output_dir(out, inputs)
    shown_garment = (display_inputs or {}).get("garment", garment_path)
    up_v, front_v = resolve_axes(up, front, recipe)
    options = EditOptions(
        up=up_v,
        front=front_v,
        body=load_body(body, units=body_units, to=recipe.units) if body else None,
    )
    t0 = time.perf_counter()
    loaded = load_garment(
        garment_path,
        drape=drape,
        units=recipe.units,
        pattern_units=pattern_units,
        drape_units=drape_units,
        weld=weld,
        size=size,
        dxf_units=dxf_units,
    )
    # pieces are matched (a DXF's, failing early) or drawn when a DXF is read or written
    plan = (
        piece_plan(
            loaded.garment,
            panels(loaded.garment, up=options.up, front=options.front),
            pattern=loaded.pattern,
            up=options.up,
        )
        if "dxf" in formats or loaded.pattern is not None
        else None
    )
    if seam_allowance:
        check_seam_allowance(loaded.garment, seam_allowance)
    t1 = time.perf_counter()
    try:
        adj = adjustment(
            loaded.garment,
            recipe,
            method=method,
            intrinsic=intrinsic,
            baseline=baseline,
            options=options,
        )
    except PtailorError as exc:
        if exc.path is not None:
            raise
        # the garment decides (an opening it lacks, an edit it cannot take): name it
        raise PtailorError(exc.message, path=shown_garment) from None
    warnings: list[str] = [*loaded.intake.get("warnings", []), *solver_warnings(adj)]
    units_note = {
        "computation": loaded.garment.units,
        "drape": drape_units,
        "pattern": pattern_units if loaded.pattern is None else loaded.pattern.units,
    }
    if loaded.pattern is not None:
        units_note["pattern_note"] = loaded.pattern.units_note
        warnings += list(loaded.pattern.warnings)
    if loaded.pattern_units_estimated:
        units_note["pattern_scale_estimate"] = round(loaded.pattern_scale, 6)
        warnings.append(
            f"pattern units estimated from the drape: {loaded.pattern_scale:.4g} "
            f"{loaded.garment.units} per pattern unit"
        )
    t2 = time.perf_counter()
    with np.errstate(all="ignore"):
        errors = triangle_errors(adj)
    check_finite_result(adj, errors, path=shown_garment)
    warnings += intrinsic_error_warnings(adj, errors)
    carried: list = []
    if plan is not None:  # every adjusted panel gets a piece (a split panel one per part)
        plan, carried = carry_plan(adj, plan, up=options.up)
    ctx = OutputContext(
        loaded=loaded,
        pieces=carried,
        plan=plan,
        errors=errors,
        seam_allowance=seam_allowance,
        title=f"{Path(garment_path).name}: {Path(recipe.source).name}"
        + (f", seam allowance {seam_allowance:g} {loaded.garment.units}" if seam_allowance else ""),
    )
    dropped = sum(cp.dropped for cp in carried if cp is not None)
    if seam_allowance and plan is not None:
        wide = [
            plan.pieces[m.piece].name
            for m, ff in zip(plan.matches, plan.from_file, strict=True)
            if ff and m.distance > 0.25 * seam_allowance
        ]
        if wide:
            warnings.append(
                f"piece(s) {', '.join(wide)} already lie outside the drape's mesh (a cut line "
                "with its allowance?): --seam-allowance added another"
            )
    if dropped:
        warnings.append(
            f"{dropped} construction mark(s) dropped: on parts cut away, or notches the edit "
            "left inside a piece (see pattern.pieces)"
        )
    with staged_dir(out) as tmp:
        written = write_outputs(tmp, adj, ctx, formats)
        for name, text in (extra_files or {}).items():
            (tmp / name).write_text(text)
        t3 = time.perf_counter()
        timing = {"load": t1 - t0, **adj.timing_s, "write": t3 - t2}
        read = {**loaded.inputs, **({"body": body} if body else {})}
        shown = {**read, **(display_inputs or {})}
        pattern_rec = {"pieces": pieces_record(plan, carried) if plan else []}
        if loaded.pattern is not None:
            pf = loaded.pattern
            pattern_rec.update({"size": pf.size, "sizes": list(pf.sizes), "style": pf.style})
        if seam_allowance:
            pattern_rec["seam_allowance"] = seam_allowance
        report = build_report(
            adj,
            inputs=read,
            units_note=units_note,
            warnings=warnings,
            timing_s=timing,
            errors=errors,
            extra={"pattern": pattern_rec, "intake": loaded.intake},
        )
        for role, path in shown.items():
            report["inputs"][role]["path"] = path
        report["outputs"] = sorted(["report.json", *written])
        bad = non_finite_numbers(report)
        if bad:
            raise PtailorError(
                f"the report would hold non-finite numbers (at {', '.join(bad[:3])}): "
                "a numeric failure in the method; nothing written",
                path=shown_garment,
            )
        if check is not None:
            check(report)
        write_json(tmp / "report.json", report)
    return report
