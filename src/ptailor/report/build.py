"""The report: ``report.json`` content and the terminal summary."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ptailor import __version__
from ptailor import tolerances as tol
from ptailor.digest import file_sha256
from ptailor.geometry.labels import scatter_labels
from ptailor.method import tolerances as method_tol
from ptailor.model.structure import structure
from ptailor.pipeline import Adjustment, seam_mode
from ptailor.report.metrics import (
    ScaleReference,
    boundary_deviation,
    flipped,
    intrinsic_scale_error,
    panel_areas,
    panel_sizes,
    scale_reference,
    summary_stats,
)
from ptailor.report.records import BaselineRecord, PanelRecord, Report, SolverRecord
from ptailor.report.seams import seam_records, seam_warnings


def _r(x: float, nd: int = 6) -> float:
    return round(float(x), nd)


def without_negative_zeros(obj: Any) -> Any:
    """``obj`` with every float ``-0.0`` written as ``0.0`` (a new object; dicts, lists and
    tuples walked): a number that rounds to zero reads the same on either side of it.

    Examples
    --------
    >>> without_negative_zeros({"a": [-0.0, 1.5, "x"], "b": round(-1e-9, 6)})
    {'a': [0.0, 1.5, 'x'], 'b': 0.0}
    """
    if isinstance(obj, float):
        return obj + 0.0
    if isinstance(obj, dict):
        return {k: without_negative_zeros(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [without_negative_zeros(v) for v in obj]
    return obj


def _error_frame(adj: Adjustment) -> tuple[np.ndarray, np.ndarray | None]:
    """Per-vertex x sign that unmirrors mirrored panels, and the targets errors refer to."""
    st = adj.state
    g = st.base
    sign_v = np.where(np.isin(np.arange(len(g.V2)), _mirrored_vertices(st)), -1.0, 1.0)
    flipv = np.stack([sign_v, np.ones(len(g.V2))], 1)
    polar = adj.settings["method"] != "uniform" and adj.settings["intrinsic"] == "polar"
    return flipv, adj.result.targets if polar else None


def error_reference(adj: Adjustment) -> ScaleReference:
    """What :func:`triangle_errors` measures against (computed once when the uniform
    baseline is measured too: :func:`build_report`'s ``reference``)."""
    st = adj.state
    g = st.base
    flipv, target = _error_frame(adj)
    return scale_reference(g.V2 * flipv, g.F2, g.V3, st.V3, g.F3, target=target)


def triangle_errors(adj: Adjustment, *, reference: ScaleReference | None = None) -> np.ndarray:
    """Each adjusted triangle's relative intrinsic-scale error, ``(m,)``.

    See :func:`ptailor.report.metrics.intrinsic_scale_error`; ``reference``:
    :func:`error_reference` of ``adj``, when the caller has it.
    """
    return _scale_errors(adj, adj.result.V2, reference)


def _scale_errors(adj: Adjustment, V2: np.ndarray, reference: ScaleReference | None):
    """Each triangle's relative intrinsic-scale error in the pattern ``V2`` (ours or the
    baseline's), ``(m,)``."""
    st = adj.state
    g = st.base
    flipv, target = _error_frame(adj)
    return intrinsic_scale_error(
        g.V2 * flipv, V2 * flipv, g.F2, g.V3, st.V3, g.F3, target=target, reference=reference
    )


def _split_parts_before(st, g0, orig: dict, area0: np.ndarray) -> np.ndarray:
    """``area_before`` of the panels a cut split: each part's share of its original's area
    (the step record's ``panels``), not the whole original for the part that kept its name
    and 0 for the others (a V-neck through a collar read -96 % and 0 where 57 % was cut)."""
    from ptailor.geometry.triangles import signed_areas_2d

    index = {p.name: p.index for p in st.panels}
    out = area0.copy()
    for rec in st.log:
        for name, info in (rec.get("panels") or {}).items():
            parts = info.get("parts", {}) if isinstance(info, dict) else {}
            if len(parts) < 2 or name not in orig:
                continue
            whole = float(np.abs(signed_areas_2d(g0.V2, g0.F2[orig[name][0]])).sum())
            for q, share in parts.items():
                if q in index:
                    out[index[q]] = share * whole
    return out


def build_report(
    adj: Adjustment,
    *,
    inputs: dict[str, str],
    units_note: dict,
    warnings: list[str],
    timing_s: dict[str, float],
    outputs: Sequence[str] = (),
    shown: dict[str, str] | None = None,
    errors: np.ndarray | None = None,
    extra: dict | None = None,
    reference: ScaleReference | None = None,
) -> Report:
    """Assemble the report, every section in its place (nothing is patched in afterwards).

    Parameters
    ----------
    adj : Adjustment
    inputs : dict
        Role to the path read; each file is hashed.
    units_note : dict
        ``units`` block: computation unit and each file's unit (and whether estimated).
    warnings : list of str
        Every warning of the run, in order (library warnings included); the seams that
        miss their ratio follow (:func:`ptailor.report.seams.seam_warnings`).
    timing_s : dict
        Seconds per stage (load, edit, flatten, baseline, write).
    outputs : sequence of str
        The files of the output folder (``report.json`` among them); none for a report
        that is not written.
    shown : dict, optional
        Role to the path the report shows instead of the one read (``ptailor demo``).
    errors : (m,) float array, optional
        :func:`triangle_errors`, when already computed.
    extra : dict, optional
        More top-level sections (``pattern``, ``intake``, ...), inserted before ``timing_s``.
    reference : ScaleReference, optional
        :func:`error_reference` of ``adj``, when already computed (the baseline's errors
        are measured against it).

    Returns
    -------
    Report
        JSON-serialisable, deterministic apart from ``timing_s``.
    """
    gs = structure(adj.state.base)
    err = triangle_errors(adj) if errors is None else errors
    shown = shown or {}
    seams = seam_records(adj, gs)
    return {
        "ptailor_version": __version__,
        "method": adj.settings["method"],
        "intrinsic": adj.settings["intrinsic"] if adj.settings["method"] != "uniform" else None,
        "boundary": adj.settings["boundary"],
        "units": units_note,
        "inputs": {
            k: {"path": shown.get(k, v), "sha256": file_sha256(v)} for k, v in inputs.items()
        },
        "steps": list(adj.state.log),
        "solver": solver_record(adj),
        **({"baseline": baseline_record(adj)} if adj.baseline is not None else {}),
        "panels": panel_records(adj, gs, err, reference=reference),
        "seams": seams,
        **(extra or {}),  # type: ignore[typeddict-item]
        "timing_s": {k: round(v, 4) for k, v in timing_s.items()},
        "warnings": [*warnings, *seam_warnings(adj, seams)],
        "outputs": sorted(outputs),
    }


def solver_record(adj: Adjustment) -> SolverRecord:
    """The report's ``solver``: how the stitching solver ran and what converged means."""
    info = adj.result.info
    return {
        "iterations": info.iterations,
        "newton_steps": info.newton_steps,
        "converged": info.converged,
        "energy": float(f"{info.energy:.6g}"),
        "w_pin": adj.settings["w_pin"],
        "w_asap": adj.settings["w_asap"],
        "seams": seam_mode(adj.settings["seams"]),
        "seam_violation": float(f"{info.seam_violation:.3g}"),
        "residual": float(f"{max(info.panel_residual, default=0.0):.3g}"),
        # the run's sparse factorisations by stage, and how many factored a matrix again
        "factorizations": {k: int(v) for k, v in adj.factorizations.items()},
        # what "converged" means: every panel's last step (its largest vertex move,
        # rigid motion removed) at most `step` of the panel's size, and every seam edge
        # within `seam_violation` (relative) of its ratio; a run that took Newton steps
        # (where local/global steps crawl) ends with one that moves no more than `step`
        "converged_when": {
            "step": method_tol.ARAP_STEP_TOL,
            "seam_violation": method_tol.SEAM_EXACT_REL,
            "newton_step": method_tol.ARAP_STEP_TOL,
        },
    }


def baseline_record(adj: Adjustment) -> BaselineRecord:
    """The report's ``baseline``: how the uniform baseline's stitching ran (the same
    solver, stopping rule and iteration cap as ours; its seconds are ``timing_s.baseline``)."""
    info = adj.baseline.info  # type: ignore[union-attr] - called only with a baseline
    return {
        "solver": {
            "iterations": info.iterations,
            "newton_steps": info.newton_steps,
            "converged": info.converged,
            "energy": float(f"{info.energy:.6g}"),
            "residual": float(f"{max(info.panel_residual, default=0.0):.3g}"),
            "factorizations": int(adj.factorizations.get("baseline", 0)),
        }
    }


def _panel_areas_before(adj: Adjustment, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Area and size of each panel before: the input garment's panel of the same name
    (surgery changes triangles; a split panel's parts share what it was)."""
    st = adj.state
    g0 = adj.original if adj.original is not None else st.base
    orig = adj.original_panels()
    kept = [p for p in st.panels if p.name in orig]
    ids = [p.index for p in kept]
    flab0 = scatter_labels([orig[p.name][0] for p in kept], g0.n_faces, labels=ids)
    vlab0 = scatter_labels([orig[p.name][1] for p in kept], len(g0.V2), labels=ids)
    keep0 = flab0 >= 0
    area0 = panel_areas(g0.V2, g0.F2[keep0], flab0[keep0], n)
    return _split_parts_before(st, g0, orig, area0), panel_sizes(g0.V2, vlab0, n)


def panel_records(
    adj: Adjustment, gs, errors: np.ndarray, *, reference: ScaleReference | None = None
) -> list[PanelRecord]:
    """The report's ``panels``: one record per adjusted panel (``gs``: the garment's
    :func:`~ptailor.model.structure.structure`; ``errors``: :func:`triangle_errors`)."""
    st = adj.state
    g = st.base
    n = len(st.panels)
    flab, vlab = gs.face_panel, gs.vertex_panel
    orient = np.array([-1.0 if p.mirrored else 1.0 for p in st.panels])[flab]
    V2a = adj.result.V2
    es = summary_stats(errors, flab, n)
    flips = np.bincount(flab, flipped(V2a, g.F2, orient), minlength=n)
    area0, size0 = _panel_areas_before(adj, n)
    area1 = panel_areas(V2a, g.F2, flab, n)
    size1 = panel_sizes(V2a, vlab, n)
    dev = boundary_deviation(g.V2, V2a, g.F2, vlab, n)
    if adj.baseline is not None:
        Vb = adj.baseline.V2
        areab = panel_areas(Vb, g.F2, flab, n)
        sizeb = panel_sizes(Vb, vlab, n)
        errb = summary_stats(_scale_errors(adj, Vb, reference), flab, n)
    kept = adj.result.asap_panels
    out: list[PanelRecord] = []
    for p in st.panels:  # one record per panel
        i = p.index
        rec: PanelRecord = {
            "name": p.name,
            "triangles": int(p.faces.size),
            "mirrored": p.mirrored,
            "outline_kept": bool(kept[i]) if kept is not None else False,
            "area_before": _r(area0[i]),
            "area_after": _r(area1[i]),
            "size_before": [_r(size0[i, 0]), _r(size0[i, 1])],
            "size_after": [_r(size1[i, 0]), _r(size1[i, 1])],
            "boundary_deviation": _r(dev[i]),
            "intrinsic_scale_error": {k: _r(v[i], 8) for k, v in es.items()},  # type: ignore[typeddict-item]
            "flipped_triangles": int(flips[i]),
        }
        if adj.baseline is not None:
            rec["baseline_area_after"] = _r(areab[i])
            rec["baseline_size_after"] = [_r(sizeb[i, 0]), _r(sizeb[i, 1])]
            rec["baseline_intrinsic_scale_error"] = {k: _r(v[i], 8) for k, v in errb.items()}  # type: ignore[typeddict-item]
        out.append(rec)
    return out


def _mirrored_vertices(st) -> np.ndarray:
    parts = [p.vertices for p in st.panels if p.mirrored]
    return np.concatenate(parts) if parts else np.zeros(0, dtype=np.int64)


def _wh(s: list[float]) -> str:
    return f"{s[0]:7.2f} x {s[1]:7.2f}"


def _panel_lines(report: dict) -> list[str]:
    """The method line, the table head and one line per panel."""
    u = report["units"]["computation"]
    has_base = bool(report["panels"]) and "baseline_size_after" in report["panels"][0]
    head = f"{'panel':<14} {'size before':>17} {'after (ours)':>17}"
    if has_base:
        head += f" {'uniform':>17}"
    head += f" {'outline dev':>11} {'scale err p95':>13} {'flips':>5}"
    lines = [
        f"method: {report['method']}"
        + (f" ({report['intrinsic']})" if report["intrinsic"] else "")
        + f", units: {u}",
        head,
    ]
    for p in report["panels"]:
        ln = f"{p['name'][:14]:<14} {_wh(p['size_before']):>17} {_wh(p['size_after']):>17}"
        if has_base:
            ln += f" {_wh(p['baseline_size_after']):>17}"
        ln += (
            f" {p['boundary_deviation']:11.4f} {p['intrinsic_scale_error']['p95']:13.2e}"
            f" {p['flipped_triangles']:5d}"
        )
        lines.append(ln)
    return lines


def _seam_line(seams: list[dict], u: str) -> str:
    """One line on the seams: how many, how many gathered, the worst mismatch."""
    changed = [
        s
        for s in seams
        if abs(s["ratio_target"] - s["ratio_before"])
        > tol.SUMMARY_RATIO_CHANGED_REL * s["ratio_before"]
    ]
    line = f"seams: {len(seams)}"
    if changed:
        line += f", {len(changed)} with a new ratio (gathered)"
    if seams:
        worst = max(seams, key=lambda s: abs(s["mismatch"]))
        if abs(worst["mismatch"]) < tol.SUMMARY_MISMATCH_ZERO:
            line += f", every one at its target length ratio (mismatch below 0.001 {u})"
        else:
            line += (
                f", worst {' / '.join(worst['panels'])}: mismatch"
                f" {abs(worst['mismatch']):.3g} {u} (ratio {worst['ratio_after']:.4f},"
                f" target {worst['ratio_target']:.4f})"
            )
    return line


def _step_lines(steps: list[dict], u: str) -> list[str]:
    """Lines for the steps that measured what they achieved, and the symmetry plane."""
    lines = []
    for st in steps:
        amount = st.get("amount")
        if isinstance(amount, dict) and isinstance(amount.get("pattern"), dict):
            lo = [v["min"] for v in amount["pattern"].values()]
            hi = [v["max"] for v in amount["pattern"].values()]
            drape = amount.get("drape") or {}
            lines.append(
                f"{st['op']} {st.get('opening', '')} by {st.get('by', 0):g}"
                f" (measured on the {st.get('measure', 'drape')}):"
                + (f" pattern {min(lo):.3f}-{max(hi):.3f}" if lo else "")
                + (
                    f", drape {drape['min']:.3f}-{drape['max']:.3f} {u}"
                    if "min" in drape
                    else f" {u}"
                )
            )
        if st.get("op") == "symmetry":
            n = ", ".join(f"{x:.3f}" for x in st["plane"]["normal"])
            lines.append(
                f"symmetry plane: normal ({n}), garment vs mirror rms {st['rms']:.3g},"
                f" max {st['max']:.3g}"
            )
    return lines


def _pieces_line(pat: dict) -> str:
    """One line on the pattern pieces written."""
    pcs = pat["pieces"]
    from_file = sum(p["source"] == "file" for p in pcs)
    moved = sum(p.get("matched_by") == "shape" for p in pcs)
    notches = sum(p.get("notches", 0) for p in pcs)
    src = (
        f"{from_file} from the pattern file, {len(pcs) - from_file} drawn from the mesh"
        if from_file
        else "drawn from the mesh"
    )
    return (
        f"pieces: {len(pcs)} ({src}"
        + (f", {moved} matched by shape" if moved else "")
        + f"), {notches} notches"
        + (f", size {pat['size']}" if pat.get("size") else "")
        + _allowance_words(pat)
    )


def _allowance_words(pat: dict) -> str:
    """``, seam allowance 1 (hem 3)``: the default and the named allowances asked."""
    named = pat.get("seam_allowances", {})
    if not (pat.get("seam_allowance") or named):
        return ""
    words = ", ".join(f"{n} {d:g}" for n, d in named.items())
    default = f"{pat['seam_allowance']:g}" if pat.get("seam_allowance") else "none"
    return f", seam allowance {default}" + (f" ({words})" if words else "")


def summary_lines(report: Report) -> list[str]:
    """A short human summary of a report, one panel per line."""
    u = report["units"]["computation"]
    lines = _panel_lines(report)
    lines.append(_seam_line(report["seams"], u))
    sol = report.get("solver", {})
    if sol:
        lines.append(
            f"solver: {sol['iterations']} iterations, seams {sol['seams']}"
            + ("" if sol["converged"] else f", NOT converged (residual {sol['residual']:.3g})")
        )
    lines.extend(_step_lines(report.get("steps", []), u))
    pat = report.get("pattern")
    if pat and pat.get("pieces"):
        lines.append(_pieces_line(pat))
    lines.extend(f"warning: {w}" for w in report["warnings"])
    return lines
