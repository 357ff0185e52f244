"""The adjustment pipeline: recipe steps on the drape, then scale-preserving flattening."""

from __future__ import annotations

import time
import warnings as _warnings
from collections.abc import Callable
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from ptailor.edits import OPERATIONS, EditOptions, EditState, Step
from ptailor.edits.drape import check_drape, edited_state
from ptailor.edits.mirror import apply_mirrored
from ptailor.edits.scale_seam import gather_bands
from ptailor.errors import AbsentError, NumericError, PtailorError, RecipeError
from ptailor.method import tolerances as method_tol
from ptailor.method.flatten import FlattenResult, flatten
from ptailor.method.solver import SymbolicCache, counted_so_far, counting, reusing
from ptailor.model.frame import Frame
from ptailor.model.garment import Garment, vertex_labels, with_panel_names
from ptailor.model.structure import structure
from ptailor.model.symmetry import sagittal_plane
from ptailor.recipe import Recipe


@dataclass(frozen=True)
class Adjustment:
    """Everything an ``adjust`` run produced.

    Attributes
    ----------
    state : EditState
        ``state.base`` the original garment, ``state.V3`` the edited drape.
    result : FlattenResult
        The adjusted pattern (``result.V2``).
    baseline : FlattenResult or None
        Uniform flattening of the edited drape, for comparison.
    settings : dict
        The flatten settings used (after command-line overrides).
    timing_s : dict
        Seconds per stage.
    factorizations : dict
        Sparse factorisations by stage (``edit``, ``flatten``, ``baseline``); ``repeated``.
    original : Garment or None
        The input garment, before any step (surgery changes ``state.base``'s triangles).
    notes : tuple of str
        Library warnings (numpy, scipy) caught during the run, for the report.
    """

    state: EditState
    result: FlattenResult
    baseline: FlattenResult | None
    settings: dict
    timing_s: dict = field(default_factory=dict)
    factorizations: dict = field(default_factory=dict)
    original: Garment | None = None
    notes: tuple[str, ...] = ()

    def original_panels(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """Panel name to ``(faces, vertices)`` in the input garment."""
        g = self.original if self.original is not None else self.state.base
        return {p.name: (p.faces, p.vertices) for p in structure(g).panels}

    @property
    def frame(self) -> Frame:
        """The garment's frame (the run's axes, carried by the garment)."""
        return self.state.base.frame

    @cached_property
    def garment(self) -> Garment:
        """The adjusted garment: edited drape and adjusted pattern (made once: its structure,
        which the report's measures and the outputs read, is computed once). It carries the
        input's panels and openings under their names (``Garment.with_drape``)."""
        return self.state.base.with_drape(self.state.V3).with_pattern(self.result.V2)


def apply_steps(garment: Garment, recipe: Recipe, *, options: EditOptions) -> EditState:
    """Apply a recipe's steps to the drape, in order.

    A step with ``optional: true`` on a garment that lacks what it names (an
    :class:`~ptailor.errors.AbsentError`: a panel, part, opening, seam or measure) is skipped:
    its record is :func:`skipped_record`. Every other error fails the run, naming the step.

    A step with ``symmetric: true`` is applied with its mirror image across the sagittal
    plane (:func:`ptailor.edits.mirror.apply_mirrored`). The plane is fitted once, to the
    input drape (or to ``options.body``), before the first step, and recorded as the
    first log record ``{"op": "symmetry", "plane": ..., "rms": ..., "max": ...}``.

    Parameters
    ----------
    garment : Garment
    recipe : Recipe
    options : EditOptions

    Returns
    -------
    EditState
    """
    plist = structure(garment).panels
    state = EditState(
        base=garment,
        V3=garment.V3.copy(),
        panels=plist,
        even=np.ones(len(plist), dtype=bool),
    )
    plane = None
    if any(step.symmetric for step in recipe.steps):
        plane = sagittal_plane(garment.V3, garment.F3, frame=garment.frame, body=options.body)
        rec = plane.record()
        state = replace(
            state,
            log=(
                {
                    "op": "symmetry",
                    "fitted_to": "body" if options.body is not None else "drape",
                    "plane": {"point": rec["point"], "normal": rec["normal"]},
                    "rms": rec["rms"],
                    "max": rec["max"],
                },
            ),
        )
    for i, step in enumerate(recipe.steps, start=1):
        where = f"steps[{i}] ({step.op})"
        try:
            with numeric_failures(where):
                if step.symmetric and plane is not None:
                    state = apply_mirrored(state, step, options=options, plane=plane)
                else:
                    state = OPERATIONS[step.op].apply(state, step, options=options)
        except AbsentError as exc:  # the garment lacks what the step names
            if step.optional:
                state = replace(state, log=(*state.log, skipped_record(step, where, exc)))
                continue
            raise at_step(exc, where) from None
        except PtailorError as exc:
            raise at_step(exc, where) from None
        check_drape(state, where)
    return state


def at_step(exc: PtailorError, where: str) -> PtailorError:
    """``exc`` prefixed with the step ``where`` it came from, of the same kind (a recipe's
    own problems become a plain input error); unchanged when it names a file or a step."""
    if exc.path is not None or str(exc).startswith("steps["):
        return exc
    kind = PtailorError if isinstance(exc, RecipeError) else type(exc)
    return kind(f"{where}: {exc}")


def skipped_record(step: Step, where: str, exc: AbsentError) -> dict:
    """The record of an ``optional`` step skipped on a garment without what it names:
    ``{"op", "skipped": why, "warnings": [...]}`` (the report's warnings say so)."""
    why = str(exc)
    return {
        "op": step.op,
        "skipped": why,
        "warnings": [f"{where} skipped (optional: true): {why}"],
    }


@contextmanager
def numeric_failures(where: str):
    """Name the step ``where`` in a numeric failure of its solves, by the exception's type.

    A :class:`~ptailor.errors.NumericError` (raised where the solve is: a singular
    factorisation, non-finite values) gets the step's name; numpy's ``LinAlgError``,
    ``FloatingPointError`` and ``OverflowError`` become one; ``MemoryError`` is the step's
    "out of memory". Every other exception passes as it is: an internal error (a bug),
    not the garment's.
    """
    try:
        yield
    except NumericError as exc:
        raise exc.at(where) from None
    except PtailorError:
        raise
    except (np.linalg.LinAlgError, FloatingPointError, OverflowError) as exc:
        raise NumericError(
            f"{where}: numeric failure ({type(exc).__name__}: {exc}); the edit or the "
            "flatten settings leave a degenerate problem"
        ) from None
    except MemoryError:
        raise PtailorError(f"{where}: out of memory (the edit is too large)") from None


@contextmanager
def caught_warnings(notes: list[str]):
    """Silence numpy's floating-point warnings and collect library warnings into ``notes``."""
    with np.errstate(all="ignore"), _warnings.catch_warnings(record=True) as caught:
        _warnings.simplefilter("always")
        try:
            yield
        finally:
            seen: dict[str, int] = {}
            for w in caught:
                if not (
                    issubclass(w.category, RuntimeWarning)
                    or w.category.__module__.split(".")[0] in ("numpy", "scipy")
                ):
                    _warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
                    continue
                key = f"{w.category.__name__}: {str(w.message).splitlines()[0][:160]}"
                seen[key] = seen.get(key, 0) + 1
            notes.extend(
                f"library warning during the method ({k})" + (f" x{c}" if c > 1 else "")
                for k, c in seen.items()
            )


def asap_mask(state: EditState, boundary: str) -> np.ndarray:
    """Panels that keep their outline shape, per ``flatten.boundary``."""
    n = len(state.panels)
    if boundary == "similar":
        return np.ones(n, dtype=bool)
    if boundary == "free":
        return np.zeros(n, dtype=bool)
    return state.even.copy()


def seam_mode(name: str) -> str:
    """``flatten.seams`` to the solver's mode (``keep``, an older name, is ``ease``)."""
    return "free" if name == "free" else "ease"


def seam_factors(state: EditState) -> dict[tuple[int, int], float]:
    """The steps' gathers as ``{(part index, other index): factor}`` (products if repeated)."""
    idx = {p.name: p.index for p in state.panels}
    out: dict[tuple[int, int], float] = {}
    for part, other, f in state.gathers:  # a loop over steps
        if part not in idx or other not in idx:
            continue  # a later step (a cut) removed one of the seam's panels: no seam left
        key = (idx[part], idx[other])
        out[key] = out.get(key, 1.0) * f
    return out


#: ``progress(stage, iteration, residual)``: the run's stages and stitching iterations
Progress = Callable[[str, int, "float | None"], None]


def _stage(progress: Progress | None, stage: str) -> Callable[[int, float], None] | None:
    """The stitching's ``progress(iteration, residual)`` as ``stage``'s."""
    if progress is None:
        return None
    return lambda it, res: progress(stage, it, res)


def adjustment(
    garment: Garment,
    recipe: Recipe,
    *,
    method: str | None = None,
    intrinsic: str | None = None,
    baseline: bool = True,
    options: EditOptions | None = None,
    progress: Progress | None = None,
    edited: np.ndarray | None = None,
) -> Adjustment:
    """Run a recipe on a garment and adjust its pattern.

    Parameters
    ----------
    garment : Garment
        Worn in ``garment.frame``: its names from geometry, openings, views and mirror
        plane follow that frame. A recipe's ``up:``/``front:`` take part where the garment
        is read (``load_garment(frame=resolve_frame(up, front, recipe))``, as the command
        line does), not here.
    recipe : Recipe
    method, intrinsic : str, optional
        Override ``recipe.flatten``'s.
    baseline : bool
        Also compute uniform flattening for the report.
    options : EditOptions, optional
    progress : callable, optional
        ``progress(stage, iteration, residual)``: called with ``("edit", 0, None)`` before
        the steps and once per stitching iteration of ``"flatten"`` and ``"baseline"``
        (a progress line's feed; the result does not depend on it).
    edited : (n3, 3) float array, optional
        The drape edited elsewhere, in place of the recipe's steps (which must then be
        none): :func:`ptailor.edits.drape.edited_state`; the recipe gives the settings.

    Returns
    -------
    Adjustment
    """
    settings = dict(recipe.flatten)
    if method is not None:
        settings["method"] = method
    if intrinsic is not None:
        settings["intrinsic"] = intrinsic
    if settings["method"] == "uniform":
        settings["seams"] = "free"  # the paper's baseline: the drape alone decides
    notes: list[str] = []
    with caught_warnings(notes), counting() as count:
        adj = _adjust(garment, recipe, settings, baseline, options, progress, edited)
    adj.factorizations["repeated"] = count.repeated  # its own dict, made by _adjust
    return replace(adj, notes=tuple(notes))


def _adjust(
    garment: Garment,
    recipe: Recipe,
    settings: dict,
    baseline: bool,
    options: EditOptions | None,
    progress: Progress | None = None,
    edited: np.ndarray | None = None,
) -> Adjustment:
    """:func:`adjust` once its settings are resolved."""
    marks: list[int] = []  # the factorisations so far at each stage's start and the end
    t0 = _clock(marks)
    if progress is not None:
        progress("edit", 0, None)
    options = options or EditOptions()
    # panel names (from the file, else from the drape in the garment's frame) fixed once
    garment = with_panel_names(garment, plist=structure(garment).panels)
    state = _edit_state(garment, recipe, options, edited)
    t1 = _clock(marks)
    asap = asap_mask(state, settings["boundary"])
    kw = {
        "asap_panels": asap,
        "outline_free": state.outline_free,
        "frozen_panels": np.array([p.name in state.frozen for p in state.panels], dtype=bool),
        "w_pin": float(settings["w_pin"]),
        "w_asap": float(settings["w_asap"]),
        "max_iter": int(settings["max_iter"]),
        "panel_list": state.panels,
    }
    seams = seam_mode(settings["seams"])
    # the seams the run's structure already found (the input garment's, when no step
    # changed the cloth): not again inside the flatten
    pairs = structure(state.base).seam_halfedges if seams == "ease" else None
    # the baseline's matrix has the pattern of ours: one analysis for both; without a
    # baseline none is kept for later (the factor alone serves ours: 19 MB less at 300k)
    symbolic = SymbolicCache() if baseline else None
    with numeric_failures("flatten"):
        result = flatten(
            state.base,
            state.V3,
            method=settings["method"],
            intrinsic=settings["intrinsic"],
            seams=seams,
            seam_factors=seam_factors(state),
            gathers=gather_bands(state),
            seam_pairs=pairs,
            progress=_stage(progress, "flatten"),
            symbolic=symbolic,
            **kw,
        )
    t2 = _clock(marks)
    base = None
    if baseline:
        with numeric_failures("flatten (the uniform baseline)"):
            base = (
                result
                if settings["method"] == "uniform"
                else flatten(
                    state.base,
                    state.V3,
                    method="uniform",
                    seams="free",
                    progress=_stage(progress, "baseline"),
                    symbolic=symbolic,
                    **kw,
                )
            )
    t3 = _clock(marks)
    timing = {"edit": t1 - t0, "flatten": t2 - t1, "baseline": t3 - t2}
    return Adjustment(
        factorizations=dict(zip(timing, np.diff(marks).tolist(), strict=True)),  # by stage
        state=state,
        result=result,
        baseline=base,
        settings=settings,
        timing_s=timing,
        original=garment,
    )


def _edit_state(garment, recipe: Recipe, options: EditOptions, edited) -> EditState:
    """The recipe's steps applied, or the drape edited elsewhere (``edited``)."""
    if edited is None:
        with reusing():  # a matrix the steps factor again (same handles) takes its factor
            return apply_steps(garment, recipe, options=options)
    if recipe.steps:
        raise PtailorError("a drape edited elsewhere takes a recipe without steps")
    return edited_state(garment, edited)


def _clock(marks: list[int]) -> float:
    """The time now (``time.perf_counter``), noting the factorisations so far in ``marks``."""
    marks.append(counted_so_far())
    return time.perf_counter()


def solver_warnings(adj: Adjustment) -> list[str]:
    """Warnings about the stitching solve: panels it left unconverged, seams left open.

    Returns
    -------
    list of str
        One line naming the unconverged panels (worst first) with their last relative step
        (the baseline's too), and one when a seam is met worse than ``SEAM_WARN_REL``.
    """
    info = adj.result.info
    out = _unconverged(info, adj.state.panels)
    if adj.baseline is not None and adj.baseline is not adj.result:
        out += [f"baseline: uniform {w}" for w in _unconverged(adj.baseline.info, adj.state.panels)]
    if info.seam_violation > method_tol.SEAM_WARN_REL:
        out.append(
            f"seam ease met only to {100 * info.seam_violation:.2g} % (relative length"
            " mismatch of the worst seam edge)"
        )
    out.extend(_zigzag_warnings(adj))
    out.extend(
        f"{rec.get('op')} step: {w}" for rec in adj.state.log for w in rec.get("warnings", ())
    )
    out.extend(adj.notes)
    return out


def _unconverged(info, panels) -> list[str]:
    """The line naming a solve's unconverged panels (worst first, with their last relative
    step), or saying its seams were met only to some precision; none for a converged one."""
    res = np.asarray(info.panel_residual)
    bad = np.argsort(-res)[: int(np.sum(res > method_tol.ARAP_STEP_TOL))]
    if info.converged or not len(res):
        return []
    if not len(bad):
        return [
            f"solver stopped with every panel's step below {method_tol.ARAP_STEP_TOL:g} but its"
            f" seam constraints met only to {info.seam_violation:.2g} (relative; converged needs"
            f" {method_tol.SEAM_EXACT_REL:g}): its seam rows are likely dependent (a flat or"
            " self-touching drape whose weld joined what is not sewn?)"
        ]
    names = ", ".join(f"{panels[i].name} ({res[i]:.2g})" for i in bad[:5])
    more = f" and {len(bad) - 5} more" if len(bad) > 5 else ""
    why = f"at the {info.iterations}-iteration cap (flatten.max_iter)"
    if getattr(info, "stalled", False):
        why = f"after {info.iterations} iterations without progress"
    return [
        f"solver stopped {why} before converging: panel {names}{more} still moving"
        " (last step / panel size)"
    ]


def _zigzag_warnings(adj: Adjustment) -> list[str]:
    """One line per panel whose seam side the stitching zigzagged
    (:func:`ptailor.method.ease.side_zigzag` above ``method_tol.SEAM_ZIGZAG_RAD``)."""
    if adj.settings.get("seams") != "ease":
        return []
    from ptailor.geometry.topology import half_edges
    from ptailor.method.ease import side_zigzag

    g = adj.state.base
    pairs = structure(g).seam_halfedges
    if not len(pairs):
        return []
    z = side_zigzag(g.V2, adj.result.V2, half_edges(g.F2)[np.asarray(pairs).ravel()])
    bad = z > method_tol.SEAM_ZIGZAG_RAD
    if not bad.any():
        return []
    lab = vertex_labels(adj.state.panels, len(g.V2))
    out = []
    for p in np.unique(lab[bad & (lab >= 0)]):  # a loop over the panels that zigzag
        on = bad & (lab == p)
        out.append(
            f"seam side on panel {adj.state.panels[p].name} zigzags: its outline's turning"
            f" alternates by up to {np.degrees(z[on].max()):.0f} degrees at {int(on.sum())}"
            " vertices (a side the seam stretches gains length by a sawtooth on a fine mesh;"
            " docs/method.md)"
        )
    return out
