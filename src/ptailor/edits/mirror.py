"""Symmetric steps: a step and its mirror image across the sagittal plane.

A symmetric step is applied as usual, then once more to the garment's mirror image: the
drape (and the pattern) are reflected, the triangles' winding reversed so normals stay
outward, the step's panel references renamed to the mirror panels, the step applied, and
everything reflected back. Geometric references (boxes, planes, sketches, opening names
such as ``cuff_left``, which are found from the geometry) need no renaming: on the
mirrored garment they select the other side by themselves.

``symmetric`` is meant for one-sided steps. A step that is its own mirror image (named
references that map to themselves, such as ``region: all``, the front panel or the hem,
and no box, plane or sketch) is applied once and recorded ``"mirrored": "self"``. Otherwise
the report's step record says ``"mirrored": true`` and holds the mirror application's own
record under ``"mirror"`` (its ``centroid`` and ``axis`` reflected back into the garment's
coordinates).
An operation with its own ``symmetric`` parameter (``cut``) mirrors itself in one go, so a
centred cut does not fail for removing nothing the second time; its record says
``"mirror": "own"`` (``cut`` mirrors across the plane through the drape's area centroid
with normal ``up x front``, not the fitted plane).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from ptailor.edits import tolerances as edit_tol
from ptailor.edits.cut import CutStep
from ptailor.edits.extend import ExtendStep
from ptailor.edits.loosen import LoosenStep
from ptailor.edits.opening import drape_openings
from ptailor.edits.parts import mirror_part
from ptailor.edits.registry import OPERATIONS, Step
from ptailor.edits.scale import ScaleStep
from ptailor.edits.scale_seam import ScaleSeamStep, resolve_seam
from ptailor.edits.shorten import ShortenStep
from ptailor.edits.state import EditOptions, EditState
from ptailor.errors import PtailorError
from ptailor.model.symmetry import SagittalPlane, mirror_points, panel_mirror_map


def mirror_state(state: EditState, plane: SagittalPlane) -> EditState:
    """The garment's mirror image (an involution up to rounding).

    The drape (``state.V3`` and ``state.base.V3``) is reflected across the plane, the
    pattern across its vertical axis (``u -> -u``), and the winding of ``F3`` and ``F2``
    reversed, so drape normals stay outward and pattern triangles keep their orientation;
    panels, seams, the ``even`` and ``frozen`` panel sets are unchanged.
    """
    g = state.base
    base = replace(
        g,
        V3=mirror_points(g.V3, plane),
        F3=np.ascontiguousarray(g.F3[:, ::-1]),
        V2=g.V2 * np.array([-1.0, 1.0]),
        F2=np.ascontiguousarray(g.F2[:, ::-1]),
    )
    return replace(state, base=base, V3=mirror_points(state.V3, plane))


def mirror_options(options: EditOptions, plane: SagittalPlane) -> EditOptions:
    """The options with the body (if any) reflected too, its faces' winding reversed."""
    if options.body is None:
        return options
    import trimesh

    body = options.body
    mb = trimesh.Trimesh(
        vertices=mirror_points(np.asarray(body.vertices, dtype=np.float64), plane),
        faces=np.asarray(body.faces)[:, ::-1],
        process=False,
    )
    return replace(options, body=mb)


class _Renamer:
    """Renames a step's panel and ``{loop: k}`` references to their mirror images."""

    def __init__(
        self, before: EditState, mirrored: EditState, plane: SagittalPlane, options: EditOptions
    ) -> None:
        self.before, self.mirrored, self.plane, self.options = before, mirrored, plane, options
        self._names: dict[str, str | None] | None = None

    def panel(self, name: Any) -> Any:
        if not isinstance(name, str):
            return name
        if self._names is None:
            st = self.before
            mm = panel_mirror_map(st.base, self.plane, V3=st.V3, panel_list=st.panels)
            self._names = {
                p.name: (st.panels[int(mm[p.index])].name if mm[p.index] >= 0 else None)
                for p in st.panels
            }
        if name not in self._names:
            return name  # unknown: the step's own lookup reports it
        other = self._names[name]
        if other is None:
            raise PtailorError(
                f"panel {name!r} has no mirror image across the sagittal plane "
                "(no panel of matching area there): set symmetric: false on this step"
            )
        return other

    def loop(self, spec: dict) -> dict:
        k = spec["loop"]
        b = self.before
        ops0 = drape_openings(b)
        if k >= len(ops0):
            return spec  # the step's own lookup reports it
        m = self.mirrored
        ops1 = drape_openings(m)
        # on the mirrored garment, the mirror loop sits where loop k sat before the step
        cen = np.array([o.centroid for o in ops1]).reshape(-1, 3)
        d = np.linalg.norm(cen - ops0[k].centroid, axis=1)
        j = int(np.argmin(d)) if len(d) else -1
        if j < 0 or d[j] > edit_tol.MIRROR_LOOP_DIST * ops0[k].length:
            raise PtailorError(
                f"opening {{loop: {k}}} has no mirror image across the sagittal plane: "
                "set symmetric: false on this step"
            )
        return {"loop": j}

    def opening(self, spec: Any) -> Any:
        return self.loop(spec) if isinstance(spec, dict) and set(spec) == {"loop"} else spec


def mirror_step(
    step: Step,
    *,
    before: EditState,
    mirrored: EditState,
    plane: SagittalPlane,
    options: EditOptions,
) -> Step:
    """A step's references renamed for its application to the mirrored garment.

    Renamed: a ``region: {panels: [...]}`` (``scale``, ``loosen``, ``tighten``),
    ``scale_seam``'s ``seam`` and ``part`` and the seams ``[a, b]`` and ``{loop: k}``
    openings in its ``fix``, and an ``opening: {loop: k}`` (``shorten``, ``extend``).
    Panels map through :func:`ptailor.model.symmetry.panel_mirror_map` on the garment
    before the step; a ``{loop: k}`` to the loop of the mirrored garment nearest where
    loop ``k`` was.

    Parameters
    ----------
    step : Step
    before : EditState
        The garment before the step (the step's names refer to it).
    mirrored : EditState
        The mirror image of the garment after the step (what the renamed step acts on).
    plane : SagittalPlane
    options : EditOptions

    Returns
    -------
    Step
        Of the same type.

    Raises
    ------
    PtailorError
        A named panel or loop without a mirror image.
    """
    r = _Renamer(before, mirrored, plane, options)
    changes: dict[str, Any] = {}
    reg = _region(step)
    if isinstance(reg, dict) and "panels" in reg:
        from ptailor.edits.region import panels_named

        names = [p.name for p in panels_named(reg["panels"], before.panels)]  # families named
        changes["region"] = {**reg, "panels": [r.panel(n) for n in names]}
    if isinstance(reg, dict) and "part" in reg:  # sleeve_left <-> sleeve_right
        changes["region"] = {"part": mirror_part(reg["part"])}
    if isinstance(step, ScaleSeamStep):
        # a seam's name: its panels, then mirrored
        seam = step.seam
        if isinstance(seam, str):
            seam = resolve_seam(before, seam, step.part)
        changes["seam"] = [r.panel(n) for n in seam]
        changes["part"] = r.panel(step.part)
        changes["fix"] = [
            [r.panel(n) for n in f] if isinstance(f, list) else r.opening(f) for f in step.fix
        ]
    if isinstance(step, (ShortenStep, ExtendStep)):
        changes["opening"] = r.opening(step.opening)
    return replace(step, **changes)


def _region(step: Step) -> Any:
    """A step's ``region`` (``scale``, ``loosen``, ``tighten``), None for other steps."""
    return step.region if isinstance(step, (ScaleStep, LoosenStep)) else None


def _restore(after: EditState, pre: EditState, mirrored: EditState, plane) -> EditState:
    """Reflect the mirrored garment back; vertices the step left alone keep their bits."""
    back = mirror_state(after, plane)
    base = pre.base if after.base is mirrored.base else back.base
    V3 = back.V3
    if after.V3.shape == mirrored.V3.shape and base is pre.base:
        same = np.all(after.V3 == mirrored.V3, axis=1)
        V3 = np.where(same[:, None], pre.V3, V3)
    return replace(back, base=base, V3=V3)


def is_centred(step: Step, mstep: Step, *, panels: list | None = None) -> bool:
    """A step that is its own mirror image: renaming changed nothing, it names no side.

    A region's panels compare as sets of the panels they select (``[front, back_left,
    back_right]`` mirrors to ``[front, back_right, back_left]``: the same panels, so the
    step is applied once, not twice); ``panels`` (the garment's, before the step) expands
    families (``skirt`` selects every ``skirt_...``). Geometric references (a box, a plane,
    a sketch or silhouette) are never taken as centred: their mirror image is another
    place.
    """
    reg = _region(step)
    geometric = (
        (isinstance(reg, dict) and "box" in reg)
        or isinstance(step, CutStep)  # a plane or a sketch
        or (isinstance(step, LoosenStep) and step.silhouette is not None)
    )
    if isinstance(step, (ShortenStep, ExtendStep)):
        named = [step.opening]
    elif isinstance(step, ScaleSeamStep):
        named = list(step.fix)
    else:
        named = []
    sided = any(isinstance(v, str) and (v.endswith("_left") or v.endswith("_right")) for v in named)
    if geometric or sided:
        return False
    return _canonical(step, panels) == _canonical(mstep, panels)


def _region_panels(step: Step, panels: list | None) -> frozenset[str] | None:
    """The names of the panels a step's ``region: {panels: [...]}`` selects, None without."""
    reg = _region(step)
    if not (isinstance(reg, dict) and "panels" in reg):
        return None
    if panels is None:
        return frozenset(reg["panels"])
    from ptailor.edits.region import panels_named

    return frozenset(p.name for p in panels_named(reg["panels"], panels))


def _canonical(step: Step, panels: list | None) -> Step:
    """A step with its region's panels as the set they select."""
    sel = _region_panels(step, panels)
    if sel is None:
        return step
    return replace(step, region={**_region(step), "panels": sel})


def overlap_error(step: Step, mstep: Step, *, panels: list) -> PtailorError | None:
    """A symmetric step whose region and mirror region share panels but differ (``[front,
    sleeve_left]`` mirrors to ``[front, sleeve_right]``): applied twice, the shared panels
    would get the edit twice. None where they are disjoint or the same."""
    a, b = _region_panels(step, panels), _region_panels(mstep, panels)
    if a is None or b is None or a == b or not (a & b):
        return None
    both = ", ".join(sorted(a & b))
    return PtailorError(
        f"step '{step.op}' with symmetric: its region's panels {both} are their own mirror"
        f" images, so the mirrored application would edit them a second time; split the step:"
        f" one step for {both} (not symmetric), one symmetric step for"
        f" {', '.join(sorted(a - b))}"
    )


def apply_mirrored(
    state: EditState, step: Step, *, options: EditOptions, plane: SagittalPlane
) -> EditState:
    """Apply a step and its mirror image across the sagittal plane.

    Parameters
    ----------
    state : EditState
    step : Step
        A validated step.
    options : EditOptions
    plane : SagittalPlane

    Returns
    -------
    EditState
        With one log record for the step: the step's own, with ``"mirrored": true`` and the
        mirror application's record under ``"mirror"`` (``"mirrored": "self"`` when the step
        is its own mirror image, see :func:`is_centred`, and was applied once).

    Raises
    ------
    PtailorError
        A panel or loop the step names that has no mirror image.
    """
    op = OPERATIONS[step.op]
    n_log = len(state.log)
    if "symmetric" in op.params:  # the operation mirrors itself
        out = op.apply(state, replace(step, symmetric=True), options=options)
        recs = out.log[n_log:]
        rec = {**(recs[-1] if recs else {"op": op.name}), "mirrored": True, "mirror": "own"}
        return replace(out, log=(*state.log, rec))
    from ptailor.method.solver import SymbolicCache

    # the two applications factor matrices of one pattern (a loosen's diffusion matrix over
    # the same triangles): one symbolic analysis serves both
    options = replace(options, symbolic=SymbolicCache())
    once = op.apply(state, step, options=options)
    m = mirror_state(once, plane)
    mstep = mirror_step(step, before=state, mirrored=m, plane=plane, options=options)
    if is_centred(step, mstep, panels=state.panels):
        # its own mirror image (region all, a front panel, the hem): applied once
        rec1 = once.log[n_log:]
        rec = {**(rec1[-1] if rec1 else {"op": op.name}), "mirrored": "self"}
        return replace(once, log=(*state.log, rec))
    overlap = overlap_error(step, mstep, panels=state.panels)
    if overlap is not None:
        raise overlap
    m_after = op.apply(m, mstep, options=mirror_options(options, plane))
    out = _restore(m_after, once, m, plane)
    rec1 = once.log[n_log:]
    rec2 = m_after.log[len(once.log) :]
    rec = {**(rec1[-1] if rec1 else {"op": op.name}), "mirrored": True}
    rec["mirror"] = _record_back(rec2[-1], plane) if rec2 else {}
    return replace(out, log=(*state.log, rec))


def _record_back(rec: dict, plane: SagittalPlane) -> dict:
    """A mirror application's log record in the garment's coordinates.

    Its ``centroid`` (a point) and ``axis`` (a direction, largest component kept positive)
    are reflected back; everything else is copied.
    """
    out = dict(rec)
    if _is3(rec.get("centroid")):
        c = mirror_points(np.asarray(rec["centroid"], dtype=np.float64), plane)
        out["centroid"] = [round(float(x), 6) for x in c]
    if _is3(rec.get("axis")):
        a = np.asarray(rec["axis"], dtype=np.float64)
        n = np.asarray(plane.normal, dtype=np.float64)
        a = a - 2.0 * (a @ n) * n
        a = a * np.sign(a[np.argmax(np.abs(a))])
        out["axis"] = [round(float(x), 6) for x in a]
    return out


def _is3(x: Any) -> bool:
    return isinstance(x, list) and len(x) == 3
