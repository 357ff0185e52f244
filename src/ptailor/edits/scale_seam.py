"""``scale_seam``: move a seam line, scaling the part on one side (the lantern sleeve)."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ptailor.edits import tolerances as edit_tol
from ptailor.edits.checks import choice, number, with_schema
from ptailor.edits.follow import rigid_apart
from ptailor.edits.opening import find_opening, opening_spec
from ptailor.edits.region import body_axis, unit_vector
from ptailor.edits.registry import Step, checked, register
from ptailor.edits.state import EditOptions, EditState
from ptailor.errors import AbsentError, PtailorError
from ptailor.geometry.labels import used_indices
from ptailor.geometry.segments import segment_moments
from ptailor.method.deform import arap_deform
from ptailor.method.gather import GatherBand
from ptailor.model.garment import panel_labels
from ptailor.model.seam_lines import seam_line as model_seam_line
from ptailor.model.seams import Seam, seams

PAIR_SCHEMA = {"type": "array", "items": {"type": "string"}, "minItems": 2, "maxItems": 2}


@with_schema(PAIR_SCHEMA)
def panel_pair(x: Any, where: str) -> list[str]:
    """Two panel names."""
    ok = isinstance(x, list) and len(x) == 2 and all(isinstance(n, str) for n in x)
    return [] if ok else [f"{where}: expected two panel names [a, b], got {x!r}"]


@with_schema({"type": "string", "minLength": 1})
def name(x: Any, where: str) -> list[str]:
    """A non-empty string."""
    return [] if isinstance(x, str) and x else [f"{where}: expected a name, got {x!r}"]


@with_schema({"type": "array", "items": {"anyOf": [PAIR_SCHEMA, {"$ref": "#/$defs/opening"}]}})
def fix_list(x: Any, where: str) -> list[str]:
    """Openings (names or ``{loop: k}``) and seams (``[a, b]``) that must not move."""
    if not isinstance(x, list):
        return [f"{where}: expected a list of openings and seams, got {x!r}"]
    probs: list[str] = []
    for i, f in enumerate(x):
        w = f"{where}[{i}]"
        probs += panel_pair(f, w) if isinstance(f, list) else opening_spec(f, w)
    return probs


@with_schema({"anyOf": [PAIR_SCHEMA, {"type": "string", "minLength": 1}]})
def seam_spec(x: Any, where: str) -> list[str]:
    """A seam: its two panels ``[a, b]``, or a seam's or seam line's name."""
    if (isinstance(x, str) and x) or not panel_pair(x, where):
        return []
    return [
        f"{where}: expected two panel names [a, b] or a seam's or seam line's name "
        f"(armhole_left), got {x!r}"
    ]


@dataclass(frozen=True, kw_only=True)
class ScaleSeamStep(Step):
    """A ``scale_seam`` step (see :func:`scale_seam`).

    Attributes
    ----------
    seam : str or list of str
        Its two panels ``[a, b]``, or a seam's or seam line's name.
    part : str
        The panel on the side that is scaled.
    direction : {"around", "along"}
    factor : float
    fix : list
        Openings (names or ``{loop: k}``) and seams (``[a, b]``) that must not move.
    """

    op = "scale_seam"
    seam: str | list[str] = field(
        metadata=checked(
            seam_spec,
            "the seam: its two panels [a, b], or a seam's or seam line's name "
            "(armhole_left_front, armhole_left)",
        )
    )
    part: str = field(metadata=checked(name, "the panel on the side that is scaled"))
    direction: str = field(default="around", metadata=checked(choice("around", "along")))
    factor: float = field(metadata=checked(number(gt=0.0, le=100.0)))
    fix: list[Any] = field(
        default_factory=list, metadata=checked(fix_list, "openings or seams that must not move")
    )


def part_in_seam(step: ScaleSeamStep, where: str) -> list[str]:
    """The scaled part is one of the seam's two panels (a named seam: checked on the
    garment)."""
    if isinstance(step.seam, list) and step.part not in step.seam:
        return [f"{where}.part: {step.part!r} is not one of the seam's panels {step.seam}"]
    return []


def state_seams(state: EditState) -> list[Seam]:
    """The seams of ``state.base`` between ``state.panels``.

    The garment's own (:func:`ptailor.model.structure.structure`, computed once) when the
    state's panels are the structure's.
    """
    st = state.structure
    if state.panels is st.panels:
        return st.seams
    return seams(state.base.F3, state.base.F2, panel_labels(state.panels, state.base.n_faces))


def seam_vertices(state: EditState, pair: list[str]) -> np.ndarray:
    """Drape vertices of the seam between two named panels.

    Raises
    ------
    PtailorError
        Unknown panel names, or panels that share no seam.
    """
    return np.unique(seam_edges(state, pair).ravel())


def seam_edges(state: EditState, pair: list[str]) -> np.ndarray:
    """Drape edges ``(e, 2)`` of the seam between two named panels.

    Raises
    ------
    PtailorError
        Unknown panel names, or panels that share no seam.
    """
    by_name = {p.name: p.index for p in state.panels}
    unknown = [n for n in pair if n not in by_name]
    if unknown:
        raise AbsentError(
            f"no panel named {', '.join(unknown)} (this garment has: {', '.join(by_name)})"
        )
    want = tuple(sorted((by_name[pair[0]], by_name[pair[1]])))
    found = [s for s in state_seams(state) if s.panels == want]
    if not found:
        raise AbsentError(f"panels {pair[0]} and {pair[1]} share no seam")
    return np.concatenate([s.edges3 for s in found])


def seam_line(state: EditState, part: str, other: str) -> list[str]:
    """The panels ``part`` meets across the seam line through its seam with ``other``, in
    order found (``other`` first): :func:`ptailor.model.seam_lines.seam_line` by name."""
    by_name = {p.name: p.index for p in state.panels}
    names = {p.index: p.name for p in state.panels}
    line = model_seam_line(state.V3, state_seams(state), by_name[part], by_name[other])
    return [names[i] for i in line]


def state_seam_names(state: EditState) -> list[str]:
    """The names of :func:`state_seams` (as ``inspect`` and the report give them).

    Raises
    ------
    PtailorError
        The state's panels are not the garment's own (after a cut or an extension: seams
        are named by their panels there).
    """
    st = state.structure
    if state.panels is not st.panels:
        raise PtailorError(
            "seams are named by name only on the garment as read; after a cut or an "
            "extension name a seam by its two panels, [a, b]"
        )
    return list(st.seam_names)


def resolve_seam(state: EditState, seam: Any, part: str) -> list[str]:
    """The two panels of a step's ``seam``: ``[a, b]`` as it is, or a name: a seam's
    (``armhole_left_front``) or a seam line's of ``part`` (``armhole_left``: the stem of
    its seams' names, :func:`ptailor.model.seam_lines.seam_lines`; else the stem of the
    name of a seam of ``part``, as ``armhole_left`` of a two-piece sleeve's front half),
    resolved to the first seam of ``part`` it names: the step then acts on the whole line
    through that seam (:func:`seam_line`).

    Raises
    ------
    PtailorError
        No seam or line of that name on ``part`` (the message lists those there are).
    """
    if isinstance(seam, list):
        return list(seam)
    from ptailor.model.seam_lines import seam_lines

    seam_list = state_seams(state)
    names = state_seam_names(state)
    pname = {p.index: p.name for p in state.panels}
    by_name = {p.name: p.index for p in state.panels}
    if part not in by_name:
        raise AbsentError(f"no panel named {part} (this garment has: {', '.join(by_name)})")
    ip = by_name[part]
    for s, nm in zip(seam_list, names, strict=True):
        if nm == seam:
            if ip not in s.panels:
                raise PtailorError(
                    f"seam {seam!r} joins {pname[s.panels[0]]} and {pname[s.panels[1]]}, not {part}"
                )
            return [pname[s.panels[0]], pname[s.panels[1]]]
    lines = [ln for ln in seam_lines(state.V3, seam_list, names) if ln.part == ip]
    for ln in lines:
        if ln.name == seam:
            return [part, pname[ln.panels[0]]]
    mine = [nm for s, nm in zip(seam_list, names, strict=True) if ip in s.panels]
    for s, nm in zip(seam_list, names, strict=True):  # a stem of one of part's seams' names
        if ip in s.panels and s.panels[0] != s.panels[1] and nm.startswith(seam + "_"):
            return [pname[s.panels[0]], pname[s.panels[1]]]  # (a two-piece sleeve's half)
    raise AbsentError(
        f"no seam or seam line named {seam!r} on {part} (its seams: {', '.join(mine) or 'none'}"
        f"; its seam lines: {', '.join(ln.name for ln in lines) or 'none'})"
    )


def _part_targets(
    V3: np.ndarray,
    part_v: np.ndarray,
    other_v: np.ndarray,
    fixed_v: np.ndarray,
    *,
    c: np.ndarray,
    ax: np.ndarray,
    f: float,
    direction: str,
) -> tuple[np.ndarray, np.ndarray]:
    """Handles and their targets for :func:`scale_seam`.

    Parameters
    ----------
    V3 : (n, 3) float array
        The drape.
    part_v, other_v, fixed_v : int arrays
        Vertices of the scaled part, of the other panel (off the seam), and fixed ones.
    c : (3,) float array, keyword-only
        The seam's centroid.
    ax : (3,) float array, keyword-only
        Unit axis.
    f : float, keyword-only
        The factor.
    direction : ``"around"`` or ``"along"``, keyword-only

    Returns
    -------
    handles : (h,) int array
    targets : (h, 3) float array
    """
    # the part scales from 1 at its fixed end (or far end) to the factor at the seam,
    # linearly along the axis: a straight tube becomes a frustum, exactly developable
    s_part = (V3[part_v] - c) @ ax
    own = fixed_v[np.isin(fixed_v, part_v)]  # the part's fixed end (not the other sleeve's)
    anchor = (
        float(((V3[own] - c) @ ax).mean()) if len(own) else float(s_part[np.argmax(np.abs(s_part))])
    )
    t = np.clip(1.0 - s_part / anchor, 0.0, 1.0) if anchor != 0 else np.ones(len(part_v))
    d = V3[part_v] - c
    axial = (d @ ax)[:, None] * ax
    if direction == "around":
        k = 1.0 + (f - 1.0) * t
        moved = c + axial + k[:, None] * (d - axial)
        handles, targets = part_v, moved
    else:
        # positions along the axis scale by f about the anchor; the other panel moves along
        shift = -(f - 1.0) * anchor * ax
        moved = V3[part_v] + ((f - 1.0) * (d @ ax - anchor))[:, None] * ax
        handles = np.concatenate([part_v, other_v])
        targets = np.concatenate([moved, V3[other_v] + shift])
    keep = ~np.isin(fixed_v, handles)
    handles = np.concatenate([handles, fixed_v[keep]])
    targets = np.concatenate([targets, V3[fixed_v[keep]]])
    return handles, targets


def _hold_fixed(
    V3: np.ndarray,
    handles: np.ndarray,
    targets: np.ndarray,
    fixed_v: np.ndarray,
    fix: list,
    part: str,
) -> np.ndarray:
    """``targets`` with every fixed vertex at its place: what ``fix`` names stays put
    exactly (the part's scaled field once moved a fixed cuff opening by 2 mm and a fixed
    seam of the part by 2.1 cm, as if unfixed). A fixed line the scaling moves by more
    than ``edit_tol.FIX_INSIDE_REL`` of the garment's size lies inside the scaled part, where
    it cannot stay put without tearing the part's scaling: an error naming it."""

    if not len(fixed_v):
        return targets
    row = np.full(len(V3), -1, dtype=np.int64)
    row[handles] = np.arange(len(handles))
    r = row[fixed_v]
    move = np.linalg.norm(targets[r] - V3[fixed_v], axis=1)
    size = float(np.linalg.norm(np.ptp(V3, axis=0))) or 1.0
    if move.max(initial=0.0) > edit_tol.FIX_INSIDE_REL * size:
        raise PtailorError(
            f"fix: {fix} lies inside the scaled part {part}, where this step moves it by up"
            f" to {move.max():.3g} (units of the drape): it cannot stay put; fix the part's"
            " far opening or a seam outside it"
        )
    out = targets.copy()
    out[r] = V3[fixed_v]
    return out


def _seam_frame(
    V3: np.ndarray, line_edges: np.ndarray, ring: np.ndarray, *, body=None
) -> tuple[np.ndarray, np.ndarray]:
    """The centre and unit axis of a seam line.

    Parameters
    ----------
    V3 : (n, 3) float array
        The edited drape.
    line_edges : (e, 2) int array
        The seam line's drape edges, and ``ring`` ``(r,)`` their vertices.
    body : trimesh.Trimesh, optional, keyword-only
        With a body, the axis is the body's local axis at the line
        (:func:`ptailor.edits.region.body_axis`).

    Returns
    -------
    c : (3,) float array
        The line's centroid by arc length.
    ax : (3,) float array
        The normal of its best-fit plane by arc length, or the body's axis.
    """
    # the seam line's centroid and plane by arc length: the same however finely it is
    # meshed (its vertices' mean moves toward its finely meshed parts)
    c, S = segment_moments(V3, line_edges)
    if body is not None:
        ax = body_axis(V3[ring], np.asarray(body.vertices, dtype=float))
    else:
        ax = np.linalg.eigh(S)[1][:, 0]  # the seam plane's normal
    return c, unit_vector(ax, "the seam's axis")


def _fixed_vertices(
    state: EditState, fix: list, ring: np.ndarray, *, seam: list[str], options: EditOptions
) -> np.ndarray:
    """The drape vertices ``fix`` names (seams and openings), less the moved seam line's
    ``ring``, ascending; a ``fix`` entry lying wholly on the seam line is refused."""
    fixed: list[np.ndarray] = []
    for spec in fix:
        if isinstance(spec, list):
            fixed.append(seam_vertices(state, spec))
        else:
            fixed.append(find_opening(state, spec)[1])
        if not len(np.setdiff1d(fixed[-1], ring)):  # once silently ignored (0 fixed vertices)
            a, b = seam
            raise PtailorError(
                f"fix: {spec} lies on the seam [{a}, {b}] this step moves: it cannot stay put;"
                " fix an opening or another seam"
            )
    return np.setdiff1d(np.unique(np.concatenate(fixed)), ring) if fixed else np.zeros(0, int)


@register(ScaleSeamStep, check=part_in_seam)
def scale_seam(state: EditState, step: ScaleSeamStep, *, options: EditOptions) -> EditState:
    """Move a seam line and scale the part on one side; what ``fix`` names stays put.

    The axis is the normal of the seam line's best-fit plane (or the body's local axis with
    a body). ``around`` with a fixed end on the part scales the part about the axis by a
    factor growing linearly along it from 1 at that end to ``factor`` at the seam, so a
    straight sleeve becomes a frustum (the lantern); with none it is a gather: the drape is
    kept and the part's pattern takes the extra length in a band along the seam
    (``GATHER_BAND_REL`` times the seam line's mean radius, :mod:`ptailor.method.gather`),
    the rest of the part keeping its shape; ``along`` scales the part's positions along
    the axis about that end, moving the seam and carrying the other panel with it. The
    rest of the garment follows by as-rigid-as-possible deformation; what ``fix`` names
    stays put. The other
    panel's pattern is kept (``frozen``): its drape's change goes into its intrinsic scale,
    as a gathered cuff takes up a wider sleeve. ``around`` changes the seam's length ratio
    by ``factor`` on purpose (the part's side grows, the other's is kept): the flattening
    keeps the seam at that new ratio (``gathers``).
    """
    g, V3 = state.base, state.V3
    part = step.part
    a, b = resolve_seam(state, step.seam, part)
    if a == b:
        raise PtailorError(
            f"seam [{a}, {b}]: a panel's seam with itself (a tube's closing seam) cannot be "
            "scaled on one side; name two different panels"
        )
    other = b if part == a else a
    named = seam_edges(state, [a, b])  # (names and the seam checked first)
    others = seam_line(state, part, other)  # the whole line: both halves of an armhole
    line_edges = np.concatenate([named, *(seam_edges(state, [part, x]) for x in others[1:])])
    ring = np.unique(line_edges.ravel())
    c, ax = _seam_frame(V3, line_edges, ring, body=options.body)
    f = float(step.factor)
    by_name = {p.name: p for p in state.panels}
    part_v = used_indices(g.F3[by_name[part].faces], len(g.V3))
    across = np.concatenate([by_name[x].faces for x in others])
    other_v = np.setdiff1d(used_indices(g.F3[across], len(g.V3)), ring)
    fixed_v = _fixed_vertices(state, step.fix, ring, seam=[a, b], options=options)
    band = 0.0
    if step.direction == "around" and not np.isin(fixed_v, part_v).any():
        # a gather: the drape kept, the pattern's extra length in a band along the seam
        band = edit_tol.GATHER_BAND_REL * float(np.linalg.norm(V3[ring] - c, axis=1).mean())
        V_new = V3.copy()
    else:  # the part tapers from its fixed end (the lantern sleeve), or moves along
        V_new = _deformed(state, part_v, other_v, fixed_v, step, c=c, ax=ax)
    changed = np.any(np.abs(V_new - V3) > 0, axis=1)
    even = state.even.copy()
    for p in state.panels:  # a loop over panels
        if p.name == part or changed[g.F3[p.faces]].any():
            even[p.index] = False  # the part's outline changes shape (wider at the seam)
    rec = {
        "op": "scale_seam",
        "seam": [a, b],
        "part": part,
        "direction": step.direction,
        "factor": f,
        "axis": [round(float(x), 6) for x in ax],
        "seam_vertices": len(ring),
        "fixed_vertices": len(fixed_v),
        "pattern_kept": other,
        "seam_line": others,
        "seam_ratio_factor": f if step.direction == "around" else 1.0,
        "spread": "band" if band else ("taper" if step.direction == "around" else "along"),
        "band": round(band, 6),
    }
    gather = tuple((part, x, f) for x in others) if step.direction == "around" else ()
    bands = ((part, tuple(others), f, band),) if band else ()
    return replace(
        state,
        V3=V_new,
        even=even,
        frozen=state.frozen | set(others),
        gathers=(*state.gathers, *gather),
        gather_bands=(*state.gather_bands, *bands),
        log=(*state.log, rec),
    )


def _deformed(
    state: EditState,
    part_v: np.ndarray,
    other_v: np.ndarray,
    fixed_v: np.ndarray,
    step: ScaleSeamStep,
    *,
    c: np.ndarray,
    ax: np.ndarray,
) -> np.ndarray:
    """The drape ``(n3, 3)`` with the part tapered (``around``) or moved (``along``) by
    :func:`_part_targets`, what ``fix`` names held, the rest following
    (as-rigid-as-possible, panels apart from the edit rigidly)."""
    g, V3 = state.base, state.V3
    f = float(step.factor)
    handles, targets = _part_targets(
        V3, part_v, other_v, fixed_v, c=c, ax=ax, f=f, direction=step.direction
    )
    targets = _hold_fixed(V3, handles, targets, fixed_v, step.fix, step.part)
    V_new = arap_deform(V3, g.F3, handles, targets)
    held = np.zeros(len(V3), dtype=bool)
    held[handles] = True
    return rigid_apart(g, V_new, state.panels, held, handles, targets, V3=V3)


def gather_bands(state: EditState) -> tuple[GatherBand, ...]:
    """The state's gathers spread in a band (:attr:`EditState.gather_bands`) on its
    current panels: each part's triangles and its pattern vertices on its seams with the
    panels across its seam line (a gather whose panels a later step removed is dropped)."""
    by_name = {p.name: p for p in state.panels}
    out = []
    for part, others, f, band in state.gather_bands:  # a loop over the recipe's gathers
        if part not in by_name:
            continue
        ip = by_name[part].index
        pairs = {tuple(sorted((ip, by_name[x].index))) for x in others if x in by_name}
        found = [s for s in state_seams(state) if s.panels in pairs]
        if not found:
            continue
        sides = [s.edges_a if s.panels[0] == ip else s.edges_b for s in found]
        seam_e = np.concatenate(sides)
        out.append(GatherBand(by_name[part].faces, np.unique(seam_e), seam_e, f, band))
    return tuple(out)
