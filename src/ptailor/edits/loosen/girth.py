"""``loosen girth:``: the girth an offset adds, measured on the drape it makes.

An offset ``by`` along the surface adds about ``2 pi by`` to a closed girth, less where the
region covers only part of it or where the offset falls off towards the region's border.
:func:`girth_levels` picks levels across the region and measures its sections there;
:func:`girth_change` measures the same levels on an offset drape: the mean change per
section piece is the girth the offset added, in the drape, and in the pattern as the
scale-preserving flatten will make it (each section carried by its triangles' stretch: a
knit worn stretched gains less pattern than drape).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor.edits import tolerances as edit_tol
from ptailor.errors import PtailorError
from ptailor.geometry.tube_axis import tube_axis
from ptailor.measures.lines import (
    MaterialLine,
    levels_across,
    line_length,
    line_pieces,
    line_points,
    plane_section,
)
from ptailor.model.frame import Frame


@dataclass(frozen=True)
class GirthLevels:
    """Where a region's girth is measured.

    Attributes
    ----------
    axis : (3,) float array
        Unit normal of the section planes.
    heights : (k,) float array
        The planes' positions along ``axis``.
    before : (k,) float array
        The length of the region's section at each level, on the drape they were found on.
    before_pattern : (k,) float array
        The same sections' lengths carried into the pattern (:func:`pattern_length`).
    pieces : (k,) int array
        Its connected pieces (the girths it holds: two for a pair of legs).
    closed : bool
        Whether every level's section is closed loops (a girth all round), else the region
        covers only part of it (the front alone).
    """

    axis: np.ndarray
    heights: np.ndarray
    before: np.ndarray
    before_pattern: np.ndarray
    pieces: np.ndarray
    closed: bool


@dataclass(frozen=True)
class Cloth:
    """The garment's cloth as read: its drape ``V0`` ``(n, 3)`` and pattern ``V2``, ``F2``,
    which give each triangle's stretch (drape length over pattern length, per direction)."""

    V0: np.ndarray
    V2: np.ndarray
    F2: np.ndarray


def pattern_length(line: MaterialLine, V: np.ndarray, F3: np.ndarray, cloth: Cloth) -> float:
    """A section of the drape ``V`` carried into the pattern by each triangle's stretch: each
    segment's length in ``V`` over its triangle's stretch along it (its length in the drape
    as read over its length in the pattern), summed. What the scale-preserving flatten makes of
    that section: a knit worn stretched gains less pattern than drape.

    Parameters
    ----------
    line : MaterialLine
        A section of ``V``'s triangles ``F3``.
    V : (n, 3) float array
    F3 : (m, 3) int array
    cloth : Cloth

    Returns
    -------
    float
    """
    if len(line) == 0:
        return 0.0
    A, B = line_points(line, V, F3)
    a0, b0 = line_points(line, cloth.V0, F3)
    a2, b2 = line_points(line, cloth.V2, cloth.F2)
    now = np.linalg.norm(B - A, axis=1)
    drape0 = np.linalg.norm(b0 - a0, axis=1)
    flat0 = np.linalg.norm(b2 - a2, axis=1)
    ratio = np.divide(flat0, drape0, out=np.ones_like(now), where=drape0 > 0.0)
    return float((now * ratio).sum())


def level_axis(V: np.ndarray, F3: np.ndarray, faces: np.ndarray, *, frame: Frame) -> np.ndarray:
    """The axis a region's girths are measured across: the garment's up, or the region's
    tube axis where that lies more than ``LOOSEN_GIRTH_TUBE_DEG`` from the up (a sleeve held
    out: its girths are across the arm).

    Parameters
    ----------
    V : (n, 3) float array
    F3 : (m, 3) int array
    faces : (k,) int array
        The region's triangles.
    frame : Frame, keyword-only

    Returns
    -------
    (3,) float array
        Unit vector.
    """
    up = frame.matrix()[1]
    ax = tube_axis(V, F3[faces])
    if ax is None:
        return up
    limit = np.cos(np.radians(edit_tol.LOOSEN_GIRTH_TUBE_DEG))
    return up if abs(float(ax @ up)) >= limit else np.asarray(ax, dtype=np.float64)


def girth_levels(
    V: np.ndarray, F3: np.ndarray, faces: np.ndarray, *, frame: Frame, cloth: Cloth
) -> GirthLevels:
    """Levels across a region where its girth is measured.

    ``LOOSEN_GIRTH_LEVELS`` planes across :func:`level_axis`, evenly spaced over the
    region's extent along it (none at its very ends); the region's section is taken at
    each. Where some levels' sections are closed loops (a torso below the armholes, a
    skirt), those are the levels; else (the region is part of a girth: a front panel) every
    level with a section.

    Parameters
    ----------
    V : (n, 3) float array
        The drape.
    F3 : (m, 3) int array
    faces : (k,) int array
        The region's triangles.
    frame : Frame, keyword-only
    cloth : Cloth, keyword-only
        The cloth as read (each triangle's stretch).

    Returns
    -------
    GirthLevels

    Raises
    ------
    PtailorError
        The region has no extent along the axis (no section to measure).
    """
    axis = level_axis(V, F3, faces, frame=frame)
    count = edit_tol.LOOSEN_GIRTH_LEVELS
    heights = levels_across(V, F3, faces, axis=axis, count=count)
    length = np.zeros(count)
    flat = np.zeros(count)
    pieces = np.zeros(count, dtype=np.int64)
    closed = np.zeros(count, dtype=bool)
    for i, t in enumerate(heights):  # a loop over two dozen levels
        line = plane_section(V, F3, point=t * axis, normal=axis, faces=faces)
        _, pieces[i], loops = line_pieces(line)
        length[i] = line_length(line, V, F3)
        flat[i] = pattern_length(line, V, F3, cloth)
        closed[i] = pieces[i] > 0 and bool(loops.all())
    keep = closed if closed.any() else pieces > 0
    if not keep.any():
        raise PtailorError("girth: the region has no section across its axis to measure")
    return GirthLevels(
        axis, heights[keep], length[keep], flat[keep], pieces[keep], bool(closed.any())
    )


def girth_change(
    levels: GirthLevels, V: np.ndarray, F3: np.ndarray, faces: np.ndarray, cloth: Cloth
) -> tuple[float, float]:
    """The girth an edit added: the mean over ``levels`` of the change of the region's
    section length per piece, on the edited drape ``V`` ``(n, 3)``, and the same carried into
    the pattern (:func:`pattern_length`: what the flatten will give, predicted).

    Parameters
    ----------
    levels : GirthLevels
        Found on the drape before the edit.
    V : (n, 3) float array
        The edited drape (same triangles).
    F3 : (m, 3) int array
    faces : (k,) int array
        The region's triangles.
    cloth : Cloth

    Returns
    -------
    (float, float)
        The drape's change and the pattern's; negative where the girth shrank.
    """
    ax = levels.axis
    lines = [  # a loop over two dozen levels
        plane_section(V, F3, point=t * ax, normal=ax, faces=faces) for t in levels.heights
    ]
    after = np.array([line_length(line, V, F3) for line in lines])
    flat = np.array([pattern_length(line, V, F3, cloth) for line in lines])
    per = np.maximum(levels.pieces, 1)
    return (
        float(np.mean((after - levels.before) / per)),
        float(np.mean((flat - levels.before_pattern) / per)),
    )
