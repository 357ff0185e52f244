"""The re-drape check: sew each pattern on its drape, simulate, measure, judge.

Three re-drapes on the same body: ours (the adjusted pattern) and the uniform baseline
start from the edited drape; the original pattern starts from the original drape (the
**null test**: it must land where it started, else the body does not fit the garment and
the check ranks nothing). Each pattern's triangles rest as
:func:`ptailor.verify.rest.rest_shapes` says; the top opening is pinned; the cloth engine
(:mod:`ptailor.verify.engine`) settles it; :mod:`ptailor.verify.measure` gives per-panel
stretch and displacement (from the drape it started from); :mod:`ptailor.verify.verdict`
the null test and the verdict.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ptailor.method.flatten import flatten
from ptailor.model.frame import Frame
from ptailor.model.garment import Garment
from ptailor.model.structure import structure
from ptailor.verify.engine import Settings, redrape
from ptailor.verify.measure import (
    panel_stats,
    pattern_vertex_values,
    principal_stretches,
    top_opening,
)
from ptailor.verify.proxy import simulation_mesh
from ptailor.verify.rest import rest_shapes
from ptailor.verify.verdict import null_test, verdict

__all__ = ["KINDS", "uniform_pattern", "verify_patterns", "verify_section"]

#: The three re-drapes, in report order.
KINDS: tuple[str, ...] = ("ours", "baseline", "original")
#: The re-drape that starts from the original drape: the null test.
NULL = "original"


def uniform_pattern(
    V3_edit: np.ndarray, F3: np.ndarray, V2: np.ndarray, F2: np.ndarray
) -> np.ndarray:
    """The uniform-flattening baseline of an edited drape, for a garment without an Adjustment.

    Parameters
    ----------
    V3_edit : (n3, 3) float array
        The edited drape.
    F3 : (m, 3) int array
    V2 : (n2, 2) float array
        A pattern on the same triangles (its panels, orientation and mirrors are kept).
    F2 : (m, 3) int array

    Returns
    -------
    (n2, 2) float array
        :func:`ptailor.method.flatten.flatten` with ``method="uniform"``, ``seams="free"``
        (the paper's baseline: the drape alone decides).
    """
    g = Garment(V3=np.asarray(V3_edit, dtype=float), F3=F3, V2=np.asarray(V2, dtype=float), F2=F2)
    return flatten(g, g.V3, method="uniform", seams="free").V2


def _one(
    V2, start, *, common: dict, run: dict, measure: dict, init: np.ndarray | None = None
) -> tuple[dict, np.ndarray, np.ndarray]:
    """One re-drape of the drape ``start`` (n3, 3), simulated from ``init`` (n3, 3; default
    ``start``): rest shapes, the engine, the measures (report ``R``, drape, stretch);
    displacements are from ``start``."""
    rest = rest_shapes(
        V2, common["F2"], common["V2_orig"], common["V3_orig"], common["F3"], mode=common["rest"]
    )
    sim = common["sim"]
    init = start if init is None else init
    if sim is None:
        drape = redrape(init, common["F3"], rest, **run)  # run: its progress too
        V = np.asarray(drape.V, dtype=float)
        speed = drape.speed
    else:  # on the simulation mesh, carried back
        k3, k2 = sim.keep3, sim.keep2
        rest_sim = rest_shapes(
            V2[k2], sim.F2, common["V2_orig"][k2], common["V3_orig"][k3], sim.F3,
            mode=common["rest"],
        )  # fmt: skip
        drape = redrape(init[k3], sim.F3, rest_sim, **run)
        V = sim.carry(drape.V)
        speed = None if drape.speed is None else sim.carry(drape.speed)
    stretch = principal_stretches(V, common["F3"], rest)
    d3 = np.linalg.norm(V - start, axis=1) * measure["to_units"]
    d2 = pattern_vertex_values(d3, common["F3"], common["F2"], len(common["V2_orig"]))
    panels = panel_stats(
        stretch, d2, measure["face_panel"], measure["vertex_panel"], measure["names"]
    )
    R = {
        "panels": panels,
        "displacement": _whole(d3[np.unique(common["F3"])]),
        "settled": bool(drape.settled),
        "steps": int(drape.steps),
        "seconds": float(drape.seconds),
    }
    if drape.cpu_seconds is not None:
        R["cpu_seconds"] = round(float(drape.cpu_seconds), 3)
    if speed is not None:
        R.update(_still_moving(speed, common["F3"], measure))
    if drape.settle is not None:
        R["settle"] = _settle_record(drape.settle, measure["to_units"])
    return {"R": R, "drape": drape}, V, stretch


def _whole(d: np.ndarray) -> dict:
    """``{mean, p95, max}`` of the drape vertices' displacements (nan for none)."""
    d = d[np.isfinite(d)]
    if len(d) == 0:
        return {"mean": float("nan"), "p95": float("nan"), "max": float("nan")}
    return {"mean": float(d.mean()), "p95": float(np.percentile(d, 95)), "max": float(d.max())}


def _settle_record(settle: dict, to_units: float) -> dict:
    """The engine's settle record in report units (the speed is ``R["speed_p95"]``)."""
    out = {"why": settle["why"], "speed_limit": round(settle["speed_limit"] * to_units, 6)}
    if "window_steps" in settle:
        move = settle["move_p95"]
        out["window_steps"] = int(settle["window_steps"])
        out["move_p95"] = None if move is None else round(move * to_units, 6)
        out["move_limit"] = round(settle["move_limit"] * to_units, 6)
    return out


def _still_moving(speed: np.ndarray, F3: np.ndarray, measure: dict) -> dict:
    """How fast a re-drape still moved when it stopped, and where: the free vertices' 95th
    percentile speed (garment units per second) and the (up to three) panels whose
    triangles moved fastest (each triangle at its corners' mean speed, a panel at its
    triangles' 95th percentile), fastest first."""
    v = np.asarray(speed, dtype=float) * measure["to_units"]
    free = v[np.unique(F3)]
    free = free[free > 0]
    tri = v[np.asarray(F3)].mean(axis=1)
    fp = np.asarray(measure["face_panel"])
    out = []
    for k, name in enumerate(measure["names"]):  # a loop over panels
        t = tri[fp == k]
        if len(t):
            out.append((float(np.percentile(t, 95)), name))
    out.sort(key=lambda x: -x[0])
    return {
        "speed_p95": round(float(np.percentile(free, 95)) if len(free) else 0.0, 4),
        "moving": [{"panel": n, "speed_p95": round(x, 4)} for x, n in out[:3]],
    }


def _feed(progress, kind: str, settings) -> Callable[[int, float], None]:
    """A re-drape's ``(steps, speed_p95)`` as a progress line's ``(stage, 0, None)``."""
    cap, dt, thr = settings.max_steps, settings.dt, settings.settle_speed

    def feed(steps: int, speed: float) -> None:
        progress(
            f"re-drape {kind}: step {steps}/{cap}, {steps * dt:.2f} s simulated, speed p95"
            f" {1000 * speed:.3g} mm/s (settled below {1000 * thr:g} mm/s)",
            0,
            None,
        )

    return feed


def verify_patterns(
    V3_edit: np.ndarray,
    F3: np.ndarray,
    F2: np.ndarray,
    patterns: dict[str, np.ndarray],
    V2_orig: np.ndarray,
    V3_orig: np.ndarray,
    *,
    panel_names: list[str],
    face_panel: np.ndarray,
    vertex_panel: np.ndarray,
    body: tuple[np.ndarray, np.ndarray] | None = None,
    rest: str = "intrinsic",
    frame: Frame,
    units_m: float,
    to_units: float,
    settings: Settings | None = None,
    device: str | None = None,
    null_limits: tuple[float | None, float | None] = (None, None),
    progress=None,
) -> tuple[dict, dict[str, np.ndarray], dict[str, np.ndarray]]:
    """Re-drape several patterns, measure them, and judge them (the null test and the
    verdict, with ``ours``, ``baseline`` and ``original``).

    Parameters
    ----------
    V3_edit : (n3, 3) float array
        The edited drape: every re-drape but ``original`` starts there (displacements are
        from the start).
    F3, F2 : (m, 3) int arrays
        Drape and pattern triangles (shared by every pattern).
    patterns : dict of str to (n2, 2) float array
        ``{"ours": V2, "baseline": V2, "original": V2_orig}`` (any names, in report order);
        ``original`` (:data:`NULL`) starts from the original drape: the null test.
    V2_orig : (n2, 2) float array
    V3_orig : (n3, 3) float array
        The original pattern and drape (its intrinsic scale makes the rest shapes; the null
        re-drape starts there).
    panel_names : list of str
    face_panel : (m,) int array
    vertex_panel : (n2,) int array
        Panel index per pattern vertex (``structure(garment).vertex_panel``).
    body : (V (nb, 3), F (mb, 3)), optional
        A static collider in the garment's frame and units.
    rest : {"intrinsic", "pattern"}
    frame : Frame
        The drapes' axes, up +y (the engine's gravity is -y: ``ptailor.run.verify`` turns a
        garment); the top opening (highest boundary loop) is pinned.
    units_m : float
        Metres per garment unit.
    to_units : float
        Report units per garment unit (displacements are multiplied by it).
    settings : Settings, optional
    device : str, optional
    null_limits : (float or None, float or None)
        The null test's mean and p95 limits, cm (None: the defaults).

    Returns
    -------
    section : dict
        :func:`_section`'s; with ``ours``, ``baseline`` and ``original`` also ``null``
        (:func:`ptailor.verify.verdict.null_test`) and ``verdict``
        (:func:`ptailor.verify.verdict.verdict`).
    drapes : dict of str to (n3, 3) float array
        The settled drapes, in the garment's units.
    stretches : dict of str to (m, 2) float array
        Their principal stretches.
    """
    _check_up(frame)
    s = settings if settings is not None else Settings()
    common = _common_inputs(V3_edit, F3, F2, V2_orig, V3_orig, rest=rest, sim_faces=s.sim_faces)
    run = _engine_options(
        common, frame=frame, units_m=units_m, body=body, settings=s, device=device
    )
    measure = _measure_options(to_units, face_panel, vertex_panel, panel_names)
    reports, drapes, stretches = _redrapes(patterns, common, run, measure, progress)
    section = _section(reports, common, rest)
    if set(KINDS) <= set(section):
        _judge(section, cm_per_unit=units_m * 100.0 / float(to_units), limits=null_limits)
    return section, drapes, stretches


def _judge(section: dict, *, cm_per_unit: float, limits) -> None:
    """Add the null test and the verdict to ``section``."""
    null = null_test(section[NULL], cm_per_unit=cm_per_unit, mean_cm=limits[0], p95_cm=limits[1])
    section["null"] = null
    section["verdict"] = verdict(section, null, cm_per_unit=cm_per_unit)


def _check_up(frame: Frame) -> None:
    """Refuse a frame whose up is not +y: the engine's gravity is along -y."""
    u = frame.matrix()[1]
    if not np.allclose(u, [0.0, 1.0, 0.0]):
        raise ValueError(f"up must be +y (the engine's gravity is along -y), not {frame.up}")


def _common_inputs(V3_edit, F3, F2, V2_orig, V3_orig, *, rest: str, sim_faces) -> dict:
    """What every re-drape shares: the edited drape, the triangles, the original pattern and
    drape (the rest shapes), the rest mode and the simulation mesh (``sim``, None when the
    garment is simulated as it is)."""
    V3_edit = np.asarray(V3_edit, dtype=float)
    common = {
        "V3_edit": V3_edit,
        "F3": np.asarray(F3),
        "F2": np.asarray(F2),
        "rest": rest,
        "V2_orig": np.asarray(V2_orig, dtype=float),
        "V3_orig": np.asarray(V3_orig, dtype=float),
    }
    common["sim"] = simulation_mesh(
        V3_edit, common["F3"], common["V2_orig"], common["F2"], max_faces=sim_faces
    )
    return common


def _engine_options(
    common: dict, *, frame: Frame, units_m: float, body, settings: Settings, device
) -> dict:
    """:func:`ptailor.verify.engine.redrape`'s options: the top opening pinned (on the
    simulation mesh's vertices when there is one)."""
    sim = common["sim"]
    pinned = top_opening(common["V3_edit"], common["F3"], frame=frame)
    if sim is not None:  # (every pattern boundary vertex is a simulation vertex)
        pinned = np.searchsorted(sim.keep3, pinned)
    return {
        "units_m": float(units_m),
        "pinned": pinned,
        "body": body,
        "settings": settings,
        "device": device,
    }


def _measure_options(to_units: float, face_panel, vertex_panel, panel_names) -> dict:
    """What :func:`_one` measures with: the report units and the panels."""
    return {
        "to_units": float(to_units),
        "face_panel": np.asarray(face_panel),
        "vertex_panel": np.asarray(vertex_panel),
        "names": list(panel_names),
    }


def _redrapes(
    patterns: dict[str, np.ndarray], common: dict, run: dict, measure: dict, progress
) -> tuple[dict, dict[str, np.ndarray], dict[str, np.ndarray]]:
    """Each pattern re-draped and measured (:func:`_one`), of the edited drape (:data:`NULL`
    of the original drape): reports, drapes and stretches by name, each with its own
    progress feed. The null re-drape runs first; when it settled, the others are simulated
    from it moved by the edit (:func:`_warm_start`), and measured from the edited drape. A
    pattern and start that an earlier one had (an identity edit's ours and null) is not
    simulated again: its report is that one's, with ``same_as``."""
    reports, drapes, stretches = {}, {}, {}
    done: list[tuple[str, np.ndarray, np.ndarray]] = []
    for kind in sorted(patterns, key=lambda k: k != NULL):  # the null first
        V2 = patterns[kind]
        feed = None if progress is None else _feed(progress, kind, run["settings"])
        start = common["V3_orig"] if kind == NULL else common["V3_edit"]
        same = next(
            (k for k, P, S in done if np.array_equal(P, V2) and np.array_equal(S, start)), None
        )
        done.append((kind, V2, start))
        if same is not None:  # deterministic: the same run
            R = {**reports[same]["R"], "same_as": same}
            reports[kind] = {"R": R, "drape": reports[same]["drape"]}
            drapes[kind], stretches[kind] = drapes[same], stretches[same]
            continue
        init = None if kind == NULL else _warm_start(reports, drapes, common)
        reports[kind], drapes[kind], stretches[kind] = _one(
            V2,
            start,
            common=common,
            run={**run, **({"progress": feed} if feed else {})},
            measure=measure,
            init=init,
        )
        if init is not None:
            reports[kind]["R"]["start"] = "null+edit"
    order = list(patterns)
    return ({k: reports[k] for k in order}, {k: drapes[k] for k in order},
            {k: stretches[k] for k in order})  # fmt: skip


def _warm_start(reports: dict, drapes: dict, common: dict) -> np.ndarray | None:
    """Where a re-drape of the edited drape is simulated from: the settled null re-drape
    moved by the edit (``null + V3_edit - V3_orig``, so the pinned top opening is exactly
    the edited drape's), or None (from the edited drape itself) when there is no settled
    null re-drape. The body and cloth's own sag, which the null re-drape has already
    settled, is then not settled again from the start: tee6's three edits' re-drapes of the
    edited drape took 440-1000 steps from it (see docs/verify.md)."""
    if NULL not in reports or not reports[NULL]["R"]["settled"]:
        return None
    return drapes[NULL] + (common["V3_edit"] - common["V3_orig"])


def _section(reports: dict, common: dict, rest: str) -> dict:
    """The report section of the re-drapes (:func:`verify_patterns`).

    Returns
    -------
    dict
        ``{"engine", "device", "steps", "seconds", "cpu_seconds", "settled", "rest",
        "triangles", NAME: R...}`` with ``R = {"panels": panel_stats(...),
        "displacement": {"mean", "p95", "max"}, "settled", "steps", "seconds",
        "cpu_seconds", "speed_p95", "moving", "settle"}``: the displacements over the
        drape's vertices from the drape it started from (report units), how fast the free
        vertices still moved when it stopped (report units per second), the three fastest
        panels, why it settled or not; the top-level ``steps``, ``seconds`` and
        ``cpu_seconds`` are totals (of the re-drapes simulated: one with ``same_as`` was
        not), ``settled`` whether all settled.
    """
    sim = common["sim"]
    first = next(iter(reports.values()))["drape"] if reports else None
    ran = [r["R"] for r in reports.values() if "same_as" not in r["R"]]
    return {
        "engine": first.engine if first is not None else "",
        "device": first.device if first is not None else "",
        "steps": int(sum(R["steps"] for R in ran)),
        "seconds": float(sum(R["seconds"] for R in ran)),
        "cpu_seconds": round(sum(R.get("cpu_seconds", 0.0) for R in ran), 3),
        "settled": all(r["R"]["settled"] for r in reports.values()),
        "rest": rest,
        "triangles": {
            "garment": len(common["F3"]),
            "simulated": sim.n_faces if sim else len(common["F3"]),
        },
        **{k: r["R"] for k, r in reports.items()},
    }


def verify_section(
    adj,
    *,
    body: tuple[np.ndarray, np.ndarray] | None = None,
    rest: str = "intrinsic",
    units_m: float,
    to_units: float,
    settings: Settings | None = None,
    device: str | None = None,
    null_limits: tuple[float | None, float | None] = (None, None),
) -> tuple[dict, dict[str, np.ndarray]]:
    """The re-drape check of an :class:`ptailor.pipeline.Adjustment`.

    Parameters
    ----------
    adj : Adjustment
        ``adj.state.base`` the original garment on the current triangles, ``adj.state.V3``
        the edited drape, ``adj.result.V2`` ours, ``adj.baseline.V2`` the uniform baseline
        (computed with :func:`uniform_pattern` when ``adj.baseline`` is None).
    body, rest, units_m, to_units, settings, device, null_limits
        As in :func:`verify_patterns` (the frame is the garment's: its up must be +y).

    Returns
    -------
    section : dict
        :func:`verify_patterns`'s, with ``"ours"``, ``"baseline"`` and ``"original"``.
    drapes : dict of str to (n3, 3) float array
        The three settled drapes.
    """
    section, drapes, _ = verify_adjustment(
        adj,
        body=body,
        rest=rest,
        units_m=units_m,
        to_units=to_units,
        settings=settings,
        device=device,
        null_limits=null_limits,
    )
    return section, drapes


def verify_adjustment(adj, **kw) -> tuple[dict, dict, dict]:
    """:func:`verify_section` with the stretches too (for ``picture.verify_png``).

    Returns
    -------
    (section, drapes, stretches)
        As :func:`verify_patterns`.
    """
    base = adj.state.base
    s = structure(base)
    baseline = (
        adj.baseline.V2
        if adj.baseline is not None
        else uniform_pattern(adj.state.V3, base.F3, base.V2, base.F2)
    )
    patterns = {"ours": adj.result.V2, "baseline": baseline, "original": base.V2}
    return verify_patterns(
        adj.state.V3,
        base.F3,
        base.F2,
        patterns,
        base.V2,
        base.V3,
        panel_names=[p.name for p in s.panels],
        face_panel=s.face_panel,
        vertex_panel=s.vertex_panel,
        frame=base.frame,
        **kw,
    )
