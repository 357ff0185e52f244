"""The guards and warnings of one run: the engine, seam allowance, finite results, pieces.

(The options themselves are checked where they are made: :class:`~ptailor.run.options.RunOptions`.)

Every guard raises :class:`~ptailor.errors.PtailorError` before anything is written; every
warning is a line for the report's ``warnings``.
"""

from __future__ import annotations

import numpy as np

from ptailor import tolerances as tol
from ptailor.errors import NumericError, PtailorError
from ptailor.geometry.labels import used_indices
from ptailor.pipeline import Adjustment, solver_warnings
from ptailor.run.options import RunOptions


def check_engine() -> None:
    """Refuse a re-drape check when the cloth engine is not installed (before any file is
    read: :class:`~ptailor.verify.engine.EngineMissingError`, exit 2, the install hint)."""
    from ptailor.verify.engine import EngineMissingError, engine_available

    if not engine_available():
        raise EngineMissingError()


def check_seam_allowance(
    garment, allowance: float | None, named: tuple[tuple[str, float], ...] = (), *, path: str = ""
) -> None:
    """Refuse a ``--seam-allowance NAME=D`` naming no seam, seam line or opening of the
    garment, and an allowance above ``tol.SEAM_ALLOWANCE_MAX_REL`` of the largest piece
    (the garment's panels, found under its frame)."""
    from ptailor.model.structure import structure
    from ptailor.pieces import check_allowance_names

    check_allowance_names(garment, dict(named), path=path)
    values = [a for a in (allowance, *(d for _, d in named)) if a]
    if not values:
        return
    diag = 0.0
    for p in structure(garment).panels:  # a loop over panels (kept for the run's later use)
        P = garment.V2[p.vertices]
        diag = max(diag, float(np.linalg.norm(P.max(axis=0) - P.min(axis=0))))
    if not max(values) <= tol.SEAM_ALLOWANCE_MAX_REL * diag:
        raise PtailorError(
            f"--seam-allowance {max(values):g} {garment.units} is larger than "
            f"{tol.SEAM_ALLOWANCE_MAX_REL:g} of the largest piece's diagonal "
            f"({diag:.4g} {garment.units})"
        )


def check_finite_result(adj: Adjustment, errors: np.ndarray, *, path: str) -> None:
    """The final guard: refuse to write a drape, pattern or errors that are not finite.

    Parameters
    ----------
    adj : Adjustment
    errors : (m,) float array
        Intrinsic-scale error per adjusted triangle.
    path : str
        The garment the error names.

    Raises
    ------
    NumericError
        Naming the array and the solver step that produced it.
    """
    g = adj.garment
    used3 = used_indices(g.F3, len(g.V3))
    used2 = used_indices(g.F2, len(g.V2))
    checks = [
        ("the edited drape (the recipe's steps)", g.V3[used3]),
        ("the adjusted pattern (the flatten solver)", g.V2[used2]),
        ("the intrinsic-scale errors (the flatten solver)", errors),
    ]
    if adj.baseline is not None:
        checks.append(("the uniform baseline (flatten)", adj.baseline.V2[used2]))
    for what, arr in checks:  # a handful of arrays
        if not np.all(np.isfinite(arr)):
            raise NumericError(
                f"{what} has non-finite values: a numeric failure; nothing written", path=path
            )


def intrinsic_error_warnings(adj: Adjustment, errors: np.ndarray) -> list[str]:
    """A warning naming the panels whose intrinsic-scale error p95 exceeds the bound.

    Parameters
    ----------
    adj : Adjustment
        Its panels' ``faces`` index ``errors``.
    errors : (m,) float array
    """
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


def piece_warnings(plan, carried: list, seam_allowance: float | None) -> list[str]:
    """Warnings about the pieces: already cut with an allowance, marks dropped.

    Parameters
    ----------
    plan : PiecePlan or None
    carried : list of CarriedPiece or None
    seam_allowance : float, optional
    """
    warnings = []
    if seam_allowance and plan is not None:
        wide = [
            plan.pieces[m.piece].name
            for m, ff in zip(plan.matches, plan.from_file, strict=True)
            if ff and m.distance > tol.PIECE_OUTSIDE_ALLOWANCE_WARN * seam_allowance
        ]
        if wide:
            warnings.append(
                f"piece(s) {', '.join(wide)} already lie outside the drape's mesh (a cut line "
                "with its allowance?): --seam-allowance added another"
            )
    dropped = sum(cp.dropped for cp in carried if cp is not None)
    if dropped:
        warnings.append(
            f"{dropped} construction mark(s) dropped: on parts cut away, or notches the edit "
            "left inside a piece (see pattern.pieces)"
        )
    return warnings


def check_size_against_body(garment, body, *, path: str) -> None:
    """A garment read in the default unit (``--drape-units`` not given) beside a ``--body``
    must be of the body's size: its drape's largest extent between ``tol.BODY_SIZE_RATIO``
    times the body's; else :class:`~ptailor.model.repair.UnitMismatchError` (exit 2).

    Parameters
    ----------
    garment : Garment
    body : trimesh.Trimesh
        In the garment's computation unit.
    path : str
        The garment file, named in the message.
    """
    from ptailor.model.repair import UnitMismatchError

    used = np.unique(garment.F3)
    g_ext = float(np.ptp(garment.V3[used], axis=0).max())
    b_ext = float(np.max(body.extents))
    lo, hi = tol.BODY_SIZE_RATIO
    if b_ext > 0 and not lo <= g_ext / b_ext <= hi:
        u = garment.units
        raise UnitMismatchError(
            f"read in cm (--drape-units not given) the garment is {g_ext:.4g} {u} across and"
            f" the body (--body, in --body-units) {b_ext:.4g} {u}: a garment is {lo:g}-{hi:g}"
            f" times its body's size; give the garment's units with --drape-units and"
            f" --pattern-units (or check --body-units)",
            path=path,
        )


def _span(lo, hi) -> str:
    """A bounding box as ``x0..x1 x y0..y1 x z0..z1``."""
    return " x ".join(f"{a:.4g}..{b:.4g}" for a, b in zip(lo, hi, strict=True))


def check_body_placement(garment, body, *, path: str) -> None:
    """A ``--body`` FILE must be where the garment is worn: its bounding box overlaps the
    drape's and at most ``tol.BODY_INSIDE_MAX`` of the drape's vertices lie inside it
    (winding numbers on up to ``tol.BODY_CHECK_POINTS`` of them); else exit 2 naming the
    body file (a body in another frame or unit, or a box around the whole garment, would
    collide with everything or nothing).

    Parameters
    ----------
    garment : Garment
    body : trimesh.Trimesh
        In the garment's computation unit and frame.
    path : str
        The body file, named in the message.
    """
    from ptailor.edits.body import winding_numbers

    used = np.unique(garment.F3)
    V = garment.V3[used]
    blo, bhi = np.asarray(body.bounds[0]), np.asarray(body.bounds[1])
    glo, ghi = V.min(axis=0), V.max(axis=0)
    u = garment.units
    if (bhi < glo).any() or (blo > ghi).any():
        raise PtailorError(
            f"the body and the garment's drape do not overlap (body {_span(blo, bhi)} {u}, "
            f"drape {_span(glo, ghi)} {u}): give the body in the garment's frame, or its "
            "unit with --body-units, or use --body auto",
            path=path,
        )
    step = max(1, -(-len(V) // tol.BODY_CHECK_POINTS))
    inside = winding_numbers(V[::step], np.asarray(body.vertices), np.asarray(body.faces)) > 0.5
    if inside.mean() > tol.BODY_INSIDE_MAX:
        raise PtailorError(
            f"{100 * inside.mean():.0f} % of the garment's drape lies inside the body (at most "
            f"{100 * tol.BODY_INSIDE_MAX:g} %: a body is worn inside its garment; body "
            f"{_span(blo, bhi)} {u}, drape {_span(glo, ghi)} {u}): give the body in the "
            "garment's frame, or its unit with --body-units, or use --body auto",
            path=path,
        )


def input_warnings(loaded) -> list[str]:
    """What reading the pattern said, and the pattern scale when it was estimated
    (``loaded``: a :class:`~ptailor.formats.garment.LoadedGarment`)."""
    warnings = []
    if loaded.pattern is not None:
        warnings += list(loaded.pattern.warnings)
    if loaded.pattern_units_estimated:
        warnings.append(
            f"pattern units estimated from the drape: {loaded.pattern_scale:.4g} "
            f"{loaded.garment.units} per pattern unit"
        )
    return warnings


def naming_warnings(adj: Adjustment) -> list[str]:
    """A warning when the run's panels could not be named from the geometry (no rule
    recognised the garment: :func:`ptailor.model.names.layout.recognised`): ``panel_k``."""
    import re

    from ptailor.model.names.layout import UNRECOGNISED

    plain = [p.name for p in adj.state.panels if re.fullmatch(r"panel_\d+", p.name)]
    return [f"panels {', '.join(plain)}: {UNRECOGNISED}"] if plain else []


def run_warnings(
    loaded, adj: Adjustment, errors: np.ndarray, plan, carried: list, options: RunOptions
) -> list[str]:
    """Every warning of a run, in order: the intake's, the solver's, the pattern file's,
    the intrinsic-scale error's, the pieces'.

    Parameters
    ----------
    loaded : LoadedGarment
    adj : Adjustment
    errors : (m,) float array
        Intrinsic-scale error per adjusted triangle.
    plan : PiecePlan or None
    carried : list of CarriedPiece or None
    options : RunOptions
    """
    return [
        *loaded.intake.get("warnings", []),
        *solver_warnings(adj),
        *input_warnings(loaded),
        *naming_warnings(adj),
        *intrinsic_error_warnings(adj, errors),
        *piece_warnings(plan, carried, options.seam_allowance),
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


def check_finite_report(report: dict, *, path: str) -> None:
    """Refuse a report holding NaN or infinite numbers (naming where)."""
    bad = non_finite_numbers(report)
    if bad:
        raise NumericError(
            f"the report would hold non-finite numbers (at {', '.join(bad[:3])}): "
            "a numeric failure in the method; nothing written",
            path=path,
        )
