"""The re-drape check of a run: the adjusted pattern and the uniform baseline sewn on the
edited drape, the original pattern on the original drape (the null test), settled with the
cloth engine (:mod:`ptailor.verify`), and its files.

``adjust --verify`` calls :func:`adjustment_redrapes` and :func:`write_verify_files`;
``ptailor verify`` calls :func:`verify_garment`, the same check for any garment (an
adjusted one with its original, or a garment alone). The engine is imported only when a
check runs (:func:`ptailor.run.checks.check_engine` refuses it before any file is read).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ptailor.errors import PtailorError
from ptailor.formats import writer_for
from ptailor.formats.garment import LoadedGarment
from ptailor.model.frame import Frame
from ptailor.model.garment import Garment
from ptailor.model.units import CM_PER
from ptailor.pipeline import Adjustment
from ptailor.run.checks import (
    check_body_placement,
    check_engine,
    check_finite_report,
    check_size_against_body,
)
from ptailor.run.folder import check_output_dir, staged_dir, write_json
from ptailor.run.options import RunOptions
from ptailor.verify import tolerances as verify_tol

#: the re-drapes whose settled drapes are written, and their files
DRAPE_FILES = {"ours": "verify_ours.obj", "baseline": "verify_baseline.obj"}
#: the picture of the three settled drapes
PICTURE = "verify.png"
#: every file a re-drape check writes besides its report
VERIFY_FILES = (*DRAPE_FILES.values(), PICTURE)
#: the body, with ``--write-body``
BODY_FILE = "body.obj"


def write_body(tmp: Path, body, *, drape_scale: float, units: str) -> list[str]:
    """``body.obj``: the body (a trimesh in the computation units) in the drape file's units
    (``drape_scale`` computation units per file unit; trimesh's OBJ writer); returns the
    file names."""
    import trimesh

    mesh = trimesh.Trimesh(np.asarray(body.vertices, dtype=float) / drape_scale,
                           np.asarray(body.faces), process=False)  # fmt: skip
    text = mesh.export(file_type="obj", include_normals=False, include_texture=False)
    head = f"# ptailor body: {drape_scale:.9g} {units} per unit, in the garment's frame\n"
    (tmp / BODY_FILE).write_text(head + text)
    return [BODY_FILE]


@dataclass(frozen=True)
class Redrape:
    """What is re-draped: the edited drape and the patterns that are sewn onto it.

    Attributes
    ----------
    V3_edit : (n3, 3) float array
        The edited drape: every re-drape starts from it.
    F3, F2 : (m, 3) int arrays
        The drape's and the patterns' triangles (the same faces).
    patterns : dict of str to (n2, 2) float array
        ``ours`` (the adjusted pattern), ``baseline`` (uniform flattening) and
        ``original`` (the input pattern).
    V3_orig : (n3, 3) float array
        The original drape (with ``patterns["original"]``: the intrinsic scale).
    panel_names : list of str
    face_panel : (m,) int array
    vertex_panel : (n2,) int array
        The panel of each pattern vertex.
    frame : Frame
        The garment's frame: the drapes are turned so that its up is +y.
    """

    V3_edit: np.ndarray
    F3: np.ndarray
    F2: np.ndarray
    patterns: dict
    V3_orig: np.ndarray
    panel_names: list
    face_panel: np.ndarray
    vertex_panel: np.ndarray
    frame: Frame


@dataclass(frozen=True)
class Redrapes:
    """The check's outcome: what was re-draped, the report section, the settled drapes
    (``ours``, ``baseline``, ``original``; computation units) and each face's principal
    stretches."""

    inp: Redrape
    section: dict
    drapes: dict
    stretch: dict


def vertex_panels(face_panel: np.ndarray, F2: np.ndarray, n2: int) -> np.ndarray:
    """The panel of each pattern vertex (a pattern vertex lies in one panel)."""
    out = np.full(n2, -1, dtype=np.int64)
    out[np.asarray(F2).reshape(-1)] = np.repeat(np.asarray(face_panel), 3)
    return out


def units_m(units: str) -> float:
    """Metres per computation unit."""
    return CM_PER[units] / 100.0


def body_arrays(body) -> tuple[np.ndarray, np.ndarray] | None:
    """A ``--body`` mesh (a trimesh) as the engine's ``(V, F)`` arrays, or None."""
    if body is None:
        return None
    return np.asarray(body.vertices, dtype=float), np.asarray(body.faces, dtype=np.int64)


def engine_settings(max_steps: int | None):
    """The engine's settings with the step cap, or None for its defaults."""
    if max_steps is None:
        return None
    from ptailor.verify.engine import Settings

    return Settings(max_steps=int(max_steps))


def to_y_up(frame: Frame) -> np.ndarray:
    """The rotation (3x3, det 1) taking the frame's up to +y: the engine's gravity pulls
    along -y, so a garment with another up axis is turned for the simulation."""
    u = frame.matrix()[1]
    y = np.array([0.0, 1.0, 0.0])
    c = float(u @ y)
    if c < -1.0 + verify_tol.UPSIDE_DOWN:  # upside down: half a turn about x
        return np.diag([1.0, -1.0, -1.0])
    from ptailor.verify.pose import rotation

    return rotation(u, y)


def redrape_check(
    inp: Redrape,
    *,
    body,
    rest: str,
    units: str,
    max_steps: int | None,
    null_limits: tuple[float | None, float | None] = (None, None),
    progress=None,
) -> Redrapes:
    """Run the three re-drapes (:func:`ptailor.verify.check.verify_patterns`), the garment
    turned so that its frame's up is +y (the engine's gravity is along -y) and the settled
    drapes turned back.

    Parameters
    ----------
    inp : Redrape
    body : trimesh.Trimesh or None
        In the computation units.
    rest : {"intrinsic", "pattern"}
    units : str
        The computation unit (the report's).
    max_steps : int, optional
    null_limits : (float or None, float or None)
        The null test's mean and p95 limits, cm (None: the defaults).
    progress : callable, optional
        ``progress(stage, iteration, residual)``: one line per re-drape's settle checks.
    """
    from ptailor.verify.check import verify_patterns

    R = to_y_up(inp.frame)
    arrays = body_arrays(body)
    section, drapes, stretch = verify_patterns(
        inp.V3_edit @ R.T,
        inp.F3,
        inp.F2,
        inp.patterns,
        inp.patterns["original"],
        inp.V3_orig @ R.T,
        panel_names=list(inp.panel_names),
        face_panel=inp.face_panel,
        vertex_panel=inp.vertex_panel,
        body=None if arrays is None else (arrays[0] @ R.T, arrays[1]),
        rest=rest,
        frame=Frame(R @ inp.frame.up, R @ inp.frame.front),
        units_m=units_m(units),
        to_units=1.0,
        settings=engine_settings(max_steps),
        null_limits=null_limits,
        progress=progress,
    )
    drapes = {k: np.asarray(V) @ R for k, V in drapes.items()}
    return Redrapes(inp=inp, section=section, drapes=drapes, stretch=stretch)


def adjustment_redrapes(adj: Adjustment, *, body, options: RunOptions, progress=None) -> Redrapes:
    """The re-drape check of an adjustment (``adjust --verify``): its pattern and its
    baseline (flattened uniform here when the run skipped it) sewn onto the edited drape,
    the original pattern onto the original drape (the null test)."""
    from ptailor.model.garment import panel_labels

    base = adj.state.base
    V3 = adj.state.V3
    face_panel = panel_labels(adj.state.panels, base.n_faces)
    inp = Redrape(
        V3_edit=V3,
        F3=base.F3,
        F2=base.F2,
        patterns={
            "ours": adj.result.V2,
            "baseline": _baseline(adj),
            "original": base.V2,
        },
        V3_orig=base.V3,
        panel_names=[p.name for p in adj.state.panels],
        face_panel=face_panel,
        vertex_panel=vertex_panels(face_panel, base.F2, len(base.V2)),
        frame=base.frame,
    )
    return redrape_check(
        inp,
        body=body,
        rest=options.verify_rest,
        units=base.units,
        max_steps=options.verify_max_steps,
        null_limits=null_limits(options),
        progress=progress,
    )


def null_limits(options: RunOptions) -> tuple[float | None, float | None]:
    """The null test's limits (cm) from ``--null-mean`` / ``--null-p95`` (None: default)."""
    return options.verify_null_mean, options.verify_null_p95


def _baseline(adj: Adjustment) -> np.ndarray:
    if adj.baseline is not None:
        return adj.baseline.V2
    from ptailor.verify.check import uniform_pattern

    base = adj.state.base
    return uniform_pattern(adj.state.V3, base.F3, adj.result.V2, base.F2)


def write_verify_files(
    tmp: Path,
    res: Redrapes,
    *,
    loaded: LoadedGarment,
    body,
) -> list[str]:
    """``verify_ours.obj``, ``verify_baseline.obj`` (v = the settled drape, vt = the pattern
    sewn, in the input files' units) and ``verify.png``; returns the file names."""
    from ptailor.verify.picture import verify_png

    inp, units = res.inp, loaded.garment.units
    for key, name in DRAPE_FILES.items():  # two files
        writer_for(name)(
            tmp / name,
            V3=res.drapes[key] / loaded.drape_scale,
            F3=inp.F3,
            V2=inp.patterns[key] / loaded.pattern_scale,
            F2=inp.F2,
            face_panel=inp.face_panel,
            panel_names=list(inp.panel_names),
            header=[
                f"ptailor re-drape check ({key}): v = settled drape, vt = the pattern sewn",
                f"v: {loaded.drape_scale:.9g} {units} per unit; "
                f"vt: {loaded.pattern_scale:.9g} {units} per unit",
                *filter(None, [inp.frame.header()]),
            ],
        )
    verify_png(
        tmp / PICTURE,
        res.drapes,
        inp.F3,
        res.stretch,
        body=body_arrays(body),
        frame=inp.frame,
        captions=worst_panel_captions(res.section, units),
    )
    return list(VERIFY_FILES)


def worst_panel_captions(section: dict, units: str) -> dict[str, str]:
    """One line per re-drape: its worst panel's stretch p95 and mean displacement."""
    out = {}
    for key in ("ours", "baseline", "original"):
        panels = list(section[key]["panels"].values())
        stretch = np.array([p["stretch"]["p95"] for p in panels], dtype=float)
        moved = np.array([p["displacement"]["mean"] for p in panels], dtype=float)
        s = np.nanmax(stretch) if np.isfinite(stretch).any() else float("nan")
        d = np.nanmax(moved) if np.isfinite(moved).any() else float("nan")
        out[key] = f"worst panel:\nstretch p95 {s:.3f}\nmoved {d:.2f} {units}"
    return out


# --------------------------------------------------------------------------- ptailor verify


def verify_garment(
    garment: str,
    out: str | Path,
    *,
    original: str | None = None,
    options: RunOptions = RunOptions(verify=True),  # noqa: B008 - frozen
    units: str = "cm",
    progress=None,
) -> dict:
    """Re-drape a garment's pattern, its uniform baseline and its original's pattern, and
    write ``verify.json`` with the check's files to ``out`` (all or nothing).

    Parameters
    ----------
    garment : str
        An OBJ: v = the (edited) drape, vt = its pattern (an adjusted ``garment.obj``).
    out : str or Path
    original : str, optional
        The garment before the edit, with the same faces (default: ``garment`` itself).
    options : RunOptions
        How the files are read (units, weld, axes, body) and ``verify_rest``,
        ``verify_max_steps``.
    units : str
        The computation unit: the report's lengths are in it.
    progress : callable, optional
        ``progress(stage, iteration, residual)``: a progress line's feed (each re-drape's
        steps and speed).

    Returns
    -------
    dict
        What ``verify.json`` holds.
    """
    from ptailor.recipe import resolve_frame
    from ptailor.run.inputs import fitted_body, load_body

    check_engine()
    auto = options.body == "auto"
    check_output_dir(out, [garment, original, None if auto else options.body])
    frame = resolve_frame(options.up, options.front, default=None)
    orig = None if original is None else _load(original, options, units, frame)
    edited = _load(garment, _same_pattern_scale(options, orig, units), units, frame)
    orig = orig or edited
    same_faces(edited.garment, orig.garment, garment=garment, original=original or garment)
    fit = None
    if auto:  # fitted to the original drape, the one the garment was simulated on
        body, fit = fitted_body(orig.garment, path=original or garment)
    else:
        body = load_body(options.body, units=options.body_units, to=units) if options.body else None
        if body is not None:
            if options.drape_units is None:
                check_size_against_body(orig.garment, body, path=original or garment)
            check_body_placement(orig.garment, body, path=options.body)
    inp = garment_redrape(edited.garment, orig.garment)
    t0 = time.perf_counter()
    res = redrape_check(
        inp,
        body=body,
        rest=options.verify_rest,
        units=units,
        max_steps=options.verify_max_steps,
        null_limits=null_limits(options),
        progress=progress,
    )
    inputs = {"garment": garment, "original": original or garment}
    if options.body and not auto:
        inputs["body"] = options.body
    doc = {"inputs": inputs, "units": units, "verify": res.section}
    if fit is not None:
        doc["body_fit"] = fit
    with staged_dir(out) as tmp:
        written = write_verify_files(tmp, res, loaded=edited, body=body)
        if options.write_body and body is not None:
            written += write_body(tmp, body, drape_scale=edited.drape_scale, units=units)
        doc["outputs"] = sorted(["verify.json", *written])
        doc["timing_s"] = {"verify": round(time.perf_counter() - t0, 3)}
        check_finite_report(doc, path=garment)
        write_json(tmp / "verify.json", doc)
    return doc


def _load(path: str, options: RunOptions, units: str, frame: Frame) -> LoadedGarment:
    from ptailor.formats.garment import load_garment

    return load_garment(
        path,
        units=units,
        pattern_units=options.pattern_units,
        drape_units=options.drape_units,
        weld=options.weld,
        frame=frame,
    )


def _same_pattern_scale(options: RunOptions, orig: LoadedGarment | None, units: str):
    """With ``--pattern-units auto`` the garment's pattern is read at the scale estimated for
    its original (an adjusted ``garment.obj`` is written in its input's pattern units; an
    estimate from the edited drape would differ)."""
    if orig is None or options.pattern_units != "auto":
        return options
    from dataclasses import replace

    cm = orig.pattern_scale * CM_PER[units]
    return replace(options, pattern_units=f"{cm:.12g}cm")


def same_faces(edited: Garment, orig: Garment, *, garment: str, original: str) -> None:
    """Refuse an original whose faces are not the garment's (exit 2, naming both)."""
    same = (
        edited.F3.shape == orig.F3.shape
        and edited.F2.shape == orig.F2.shape
        and len(edited.V3) == len(orig.V3)
        and len(edited.V2) == len(orig.V2)
        and np.array_equal(edited.F3, orig.F3)
        and np.array_equal(edited.F2, orig.F2)
    )
    if not same:
        raise PtailorError(
            f"{garment} and {original} do not have the same faces ({len(edited.F3)} and "
            f"{len(orig.F3)} triangles, {len(edited.V3)} and {len(orig.V3)} drape vertices): "
            "--original must be the garment the adjusted one was made from"
        )


def garment_redrape(edited: Garment, orig: Garment) -> Redrape:
    """What ``ptailor verify`` re-drapes: ``edited``'s pattern (ours) and its uniform
    flattening (baseline) on ``edited``'s drape, ``orig``'s pattern on ``orig``'s drape (the
    null test; panels named under ``orig``'s frame)."""
    from ptailor.model.structure import structure
    from ptailor.verify.check import uniform_pattern

    st = structure(orig)
    return Redrape(
        V3_edit=edited.V3,
        F3=edited.F3,
        F2=edited.F2,
        patterns={
            "ours": edited.V2,
            "baseline": uniform_pattern(edited.V3, edited.F3, edited.V2, edited.F2),
            "original": orig.V2,
        },
        V3_orig=orig.V3,
        panel_names=[p.name for p in st.panels],
        face_panel=np.asarray(st.face_panel),
        vertex_panel=np.asarray(st.vertex_panel),
        frame=orig.frame,
    )
