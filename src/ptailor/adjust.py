"""The adjustment pipeline: recipe steps on the drape, then scale-preserving flattening."""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace

import numpy as np

from ptailor import tolerances as tol
from ptailor.edits import OPERATIONS, EditOptions, EditState
from ptailor.edits.mirror import apply_mirrored
from ptailor.method.flatten import FlattenResult, flatten, panel_labels, vertex_labels
from ptailor.model.garment import Garment, panels, with_panel_names
from ptailor.model.seams import seams
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
    original : Garment or None
        The input garment, before any step (surgery changes ``state.base``'s triangles).
    axes : tuple of two 3-tuples
        The run's ``(up, front)`` axes (for names from geometry).
    """

    state: EditState
    result: FlattenResult
    baseline: FlattenResult | None
    settings: dict
    timing_s: dict = field(default_factory=dict)
    original: Garment | None = None
    axes: tuple = ((0.0, 1.0, 0.0), (0.0, 0.0, 1.0))

    def original_panels(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """Panel name to ``(faces, vertices)`` in the input garment."""
        g = self.original if self.original is not None else self.state.base
        return {p.name: (p.faces, p.vertices) for p in panels(g)}

    @property
    def garment(self) -> Garment:
        """The adjusted garment: edited drape and adjusted pattern."""
        return Garment(
            V3=self.state.V3,
            F3=self.state.base.F3,
            V2=self.result.V2,
            F2=self.state.base.F2,
            face_group=self.state.base.face_group,
            group_names=self.state.base.group_names,
            units=self.state.base.units,
        )


def apply_steps(garment: Garment, recipe: Recipe, *, options: EditOptions) -> EditState:
    """Apply a recipe's steps to the drape, in order.

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
    plist = panels(garment)
    state = EditState(
        base=garment, V3=garment.V3.copy(), panels=plist, even=np.ones(len(plist), dtype=bool)
    )
    plane = None
    if any(step.get("symmetric") for step in recipe.steps):
        plane = sagittal_plane(
            garment.V3, garment.F3, up=options.up, front=options.front, body=options.body
        )
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
    for step in recipe.steps:
        if step.get("symmetric") and plane is not None:
            state = apply_mirrored(state, step, options=options, plane=plane)
        else:
            state = OPERATIONS[step["op"]].apply(state, step, options=options)
    return state


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
        key = (idx[part], idx[other])
        out[key] = out.get(key, 1.0) * f
    return out


def adjust(
    garment: Garment,
    recipe: Recipe,
    *,
    method: str | None = None,
    intrinsic: str | None = None,
    baseline: bool = True,
    options: EditOptions | None = None,
) -> Adjustment:
    """Run a recipe on a garment and adjust its pattern.

    Parameters
    ----------
    garment : Garment
    recipe : Recipe
    method, intrinsic : str, optional
        Override ``recipe.flatten``'s.
    baseline : bool
        Also compute uniform flattening for the report.
    options : EditOptions, optional

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
    t0 = time.perf_counter()
    options = options or EditOptions()
    # panel names (from the file, else from the drape in the run's axes) fixed once
    garment = with_panel_names(garment, up=options.up, front=options.front)
    state = apply_steps(garment, recipe, options=options)
    t1 = time.perf_counter()
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
    result = flatten(
        state.base,
        state.V3,
        method=settings["method"],
        intrinsic=settings["intrinsic"],
        seams=seam_mode(settings["seams"]),
        seam_factors=seam_factors(state),
        **kw,
    )
    t2 = time.perf_counter()
    base = None
    if baseline:
        base = (
            result
            if settings["method"] == "uniform"
            else flatten(state.base, state.V3, method="uniform", seams="free", **kw)
        )
    t3 = time.perf_counter()
    timing = {"edit": t1 - t0, "flatten": t2 - t1, "baseline": t3 - t2}
    return Adjustment(
        state=state,
        result=result,
        baseline=base,
        settings=settings,
        timing_s=timing,
        original=garment,
        axes=(tuple(options.up), tuple(options.front)),
    )


def solver_warnings(adj: Adjustment) -> list[str]:
    """Warnings about the stitching solve: panels it left unconverged, seams left open.

    Returns
    -------
    list of str
        One line naming the unconverged panels (worst first) with their last relative
        step, and one when a seam constraint is met less well than ``tol.SEAM_WARN_REL``.
    """
    info = adj.result.info
    out = []
    res = np.asarray(info.panel_residual)
    if not info.converged and len(res):
        bad = np.argsort(-res)[: int(np.sum(res > tol.ARAP_STEP_TOL))]
        names = ", ".join(f"{adj.state.panels[i].name} ({res[i]:.2g})" for i in bad[:5])
        more = f" and {len(bad) - 5} more" if len(bad) > 5 else ""
        out.append(
            f"solver stopped at the {info.iterations}-iteration cap (flatten.max_iter) before"
            f" converging: panel {names}{more} still moving (last step / panel size)"
        )
    if info.seam_violation > tol.SEAM_WARN_REL:
        out.append(
            f"seam ease met only to {100 * info.seam_violation:.2g} % (relative length"
            " mismatch of the worst seam edge)"
        )
    return out


def garment_structure(state: EditState) -> tuple[np.ndarray, np.ndarray, list]:
    """Face and vertex panel labels and the seams of the (original) garment."""
    g = state.base
    flab = panel_labels(state.panels, g.n_faces)
    vlab = vertex_labels(state.panels, len(g.V2))
    return flab, vlab, seams(g.F3, g.F2, flab)
