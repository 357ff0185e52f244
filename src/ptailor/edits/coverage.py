"""How much of a girth a region covers: a girth edit on part of a girth says so.

``loosen``, ``tighten`` and ``scale direction: around`` grow a girth where their region
is; a region that holds only part of it (a poncho's centre strips without its side panels,
a tee's front alone) grows the girth only there. :func:`girth_coverage` measures, at a few
levels across the region, the fraction of the garment's closed section there (over the
panels that go around the same part of the body: the trunk's, or one arm's) that lies on the
region; :func:`coverage_warnings` words it when it is below
:data:`~ptailor.edits.tolerances.GIRTH_COVERAGE_MIN`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor.edits import tolerances as edit_tol
from ptailor.edits.parts import LIMB_ROLES, PARTS
from ptailor.geometry.tube_axis import tube_axis
from ptailor.measures.lines import levels_across, line_pieces, line_points, plane_section
from ptailor.model.garment import Garment
from ptailor.model.structure import structure


@dataclass(frozen=True)
class Coverage:
    """The share of one body part's girth a region holds.

    Attributes
    ----------
    part : str
        The part whose girth it is (:func:`panel_parts`): ``torso``, ``sleeve_left``,
        ``sleeve_right`` (``sleeves`` for a lone sleeve), ``collar``, ``waistband``.
    fraction : float
        The mean over the levels of the region's share of the closed section there
        (unitless, 0 to 1).
    lowest : float
        The least of them.
    levels : int
        Levels where the region lies on a closed section (those measured).
    """

    part: str
    fraction: float
    lowest: float
    levels: int


def panel_parts(garment: Garment) -> np.ndarray:
    """Which body part's girth each panel is of (layout order): ``torso`` (the body
    panels), a limb's ``sleeve_left``, ``sleeve_right`` or ``sleeves`` (sleeves and cuffs),
    else the panel's role (``collar``, ``waistband``, ``strap``: each its own girth).

    Returns
    -------
    (n_p,) object array of str
    """
    lay = structure(garment).layout
    out = np.array(lay.role, dtype=object)  # a collar's, a waistband's, a strap's own
    for p, (role, side) in enumerate(zip(lay.role, lay.side, strict=True)):  # over panels
        if role == "body":
            out[p] = "torso"
        elif role in LIMB_ROLES:
            out[p] = f"sleeve_{side}" if side in ("left", "right") else "sleeves"
    return out


def level_fractions(
    V: np.ndarray, F3: np.ndarray, faces: np.ndarray, around: np.ndarray, axis: np.ndarray
) -> np.ndarray:
    """The region's share of the closed sections at levels across it.

    Parameters
    ----------
    V : (n, 3) float array
        The drape.
    F3 : (m, 3) int array
    faces : (k,) int array
        The region's triangles (a subset of ``around``).
    around : (a,) int array
        The triangles of every panel around the same part of the body.
    axis : (3,) float array
        Unit normal of the section planes.

    Returns
    -------
    (l,) float array
        Per level where the region lies on a closed piece of the section of ``around``:
        the length on the region over the length of those closed pieces; ``l`` at most
        ``GIRTH_COVERAGE_LEVELS``.
    """
    levels = levels_across(V, F3, faces, axis=axis, count=edit_tol.GIRTH_COVERAGE_LEVELS)
    inside = np.zeros(len(F3), dtype=bool)
    inside[faces] = True
    out = []
    for t in levels:  # a loop over a few levels
        line = plane_section(V, F3, point=t * axis, normal=axis, faces=around)
        if not len(line):
            continue
        label, _, closed = line_pieces(line)
        A, B = line_points(line, V, F3)
        seg = np.linalg.norm(B - A, axis=1)
        on = inside[line.face]
        held = np.unique(label[on])
        held = held[closed[held]]
        keep = np.isin(label, held)
        total = float(seg[keep].sum())
        if held.size and total > 0.0:
            out.append(float(seg[keep & on].sum()) / total)
    return np.asarray(out, dtype=np.float64)


def part_axis(
    V: np.ndarray, F3: np.ndarray, around: np.ndarray, *, up: np.ndarray, limb: bool
) -> np.ndarray:
    """The axis a part's girths are measured across: a limb's tube axis (an arm held out or
    hanging at 45 degrees: its girths are across it); else ``up``, or the part's tube axis
    where that lies more than ``LOOSEN_GIRTH_TUBE_DEG`` from it (as ``loosen girth:``'s
    levels); ``up`` where the part is no tube.

    Parameters
    ----------
    V : (n, 3) float array
    F3 : (m, 3) int array
    around : (a,) int array
        The part's triangles.
    up : (3,) float array, keyword-only
        The garment's up.
    limb : bool, keyword-only
        The part is a limb's (a sleeve's).

    Returns
    -------
    (3,) float array
        Unit vector.
    """
    ax = tube_axis(V, F3[around])
    limit = np.cos(np.radians(edit_tol.LOOSEN_GIRTH_TUBE_DEG))
    if ax is None or (not limb and abs(float(ax @ up)) >= limit):
        return np.asarray(up, dtype=np.float64)
    return np.asarray(ax, dtype=np.float64)


def girth_coverage(
    V: np.ndarray,
    F3: np.ndarray,
    faces: np.ndarray,
    *,
    garment: Garment,
    axis: np.ndarray | None = None,
) -> list[Coverage]:
    """The share of each body part's girth a region holds (:func:`level_fractions`), per
    part the region touches (:func:`panel_parts`).

    Parameters
    ----------
    V : (n, 3) float array
        The drape (before the edit).
    F3 : (m, 3) int array
        ``garment.F3``.
    faces : (k,) int array
        The region's triangles.
    garment : Garment, keyword-only
        Its structure gives the panels' roles and sides.
    axis : (3,) float array, optional
        The girths' axis (a scale's); else each part's
        (:func:`part_axis`: the garment's up, or the part's tube axis where that is far from
        it: an arm held out).

    Returns
    -------
    list of Coverage
        One per part with a level where the region lies on a closed section (none for a
        region on no closed girth: an open poncho's front).
    """
    lab, _ = structure(garment).panel_components
    face_part = panel_parts(garment)[lab]
    out = []
    for part in sorted(set(face_part[faces].tolist())):  # a loop over a few parts
        around = np.flatnonzero(face_part == part)
        mine = faces[face_part[faces] == part]
        up = garment.frame.matrix()[1]
        limb = part.startswith("sleeve")
        ax = axis if axis is not None else part_axis(V, F3, around, up=up, limb=limb)
        fr = level_fractions(V, F3, mine, around, np.asarray(ax, dtype=np.float64))
        if fr.size:
            out.append(Coverage(part, float(fr.mean()), float(fr.min()), int(fr.size)))
    return out


def coverage_warnings(found: list[Coverage]) -> list[str]:
    """A warning per part whose girth the region covers less than ``GIRTH_COVERAGE_MIN`` of.

    Returns
    -------
    list of str
    """
    out = []
    for c in found:  # a loop over a few parts
        if c.fraction >= edit_tol.GIRTH_COVERAGE_MIN:
            continue
        what = {"torso": "the torso", "collar": "the neck", "waistband": "the waist"}
        hint = (
            f" (region: {{part: {c.part}}} takes every panel around {what.get(c.part, 'that arm')})"
            if c.part in PARTS
            else ""
        )
        out.append(
            f"the region covers {100 * c.fraction:.0f} % of the {c.part} girth at its levels"
            f" ({c.levels} levels, {100 * c.lowest:.0f} % at the least; warned below"
            f" {100 * edit_tol.GIRTH_COVERAGE_MIN:.0f} %): the girth grows only there{hint}"
        )
    return out


def with_coverage(rec: dict, found: list[Coverage]) -> dict:
    """A step's record with ``girth_coverage`` (``{part: fraction}``) and its
    :func:`coverage_warnings` added where there are some; else as it was."""
    warns = coverage_warnings(found)
    if not warns:
        return rec
    return {
        **rec,
        "girth_coverage": {c.part: round(c.fraction, 4) for c in found},
        "warnings": [*rec.get("warnings", ()), *warns],
    }
