"""``loosen girth:``: the girth an offset adds, measured on the drape it makes.

An offset ``by`` along the surface adds about ``2 pi by`` to a closed girth, less where the
region covers only part of it or where the offset falls off towards the region's border.
:func:`girth_levels` picks levels across the region and measures its sections there;
:func:`girth_change` measures the same levels on an offset drape: the mean change per
section piece is the girth the offset added.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor.edits import tolerances as edit_tol
from ptailor.errors import PtailorError
from ptailor.geometry.tube_axis import tube_axis
from ptailor.measures.lines import line_length, line_pieces, plane_section
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
    pieces : (k,) int array
        Its connected pieces (the girths it holds: two for a pair of legs).
    closed : bool
        Whether every level's section is closed loops (a girth all round), else the region
        covers only part of it (the front alone).
    """

    axis: np.ndarray
    heights: np.ndarray
    before: np.ndarray
    pieces: np.ndarray
    closed: bool


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


def girth_levels(V: np.ndarray, F3: np.ndarray, faces: np.ndarray, *, frame: Frame) -> GirthLevels:
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

    Returns
    -------
    GirthLevels

    Raises
    ------
    PtailorError
        The region has no extent along the axis (no section to measure).
    """
    axis = level_axis(V, F3, faces, frame=frame)
    h = V[np.unique(F3[faces])] @ axis
    lo, hi = float(h.min()), float(h.max())
    count = edit_tol.LOOSEN_GIRTH_LEVELS
    heights = lo + (np.arange(count) + 0.5) / count * (hi - lo)
    length = np.zeros(count)
    pieces = np.zeros(count, dtype=np.int64)
    closed = np.zeros(count, dtype=bool)
    for i, t in enumerate(heights):  # a loop over two dozen levels
        line = plane_section(V, F3, point=t * axis, normal=axis, faces=faces)
        _, pieces[i], loops = line_pieces(line)
        length[i] = line_length(line, V, F3)
        closed[i] = pieces[i] > 0 and bool(loops.all())
    keep = closed if closed.any() else pieces > 0
    if not keep.any():
        raise PtailorError("girth: the region has no section across its axis to measure")
    return GirthLevels(axis, heights[keep], length[keep], pieces[keep], bool(closed.any()))


def girth_change(levels: GirthLevels, V: np.ndarray, F3: np.ndarray, faces: np.ndarray) -> float:
    """The girth an edit added: the mean over ``levels`` of the change of the region's
    section length per piece, on the edited drape ``V`` ``(n, 3)``.

    Parameters
    ----------
    levels : GirthLevels
        Found on the drape before the edit.
    V : (n, 3) float array
        The edited drape (same triangles).
    F3 : (m, 3) int array
    faces : (k,) int array
        The region's triangles.

    Returns
    -------
    float
        Negative where the girth shrank.
    """
    ax = levels.axis
    after = np.array(
        [  # a loop over two dozen levels
            line_length(plane_section(V, F3, point=t * ax, normal=ax, faces=faces), V, F3)
            for t in levels.heights
        ]
    )
    return float(np.mean((after - levels.before) / np.maximum(levels.pieces, 1)))
