"""Points of measure as drawn: their colours, their lines in the pattern, where their labels go.

What the POM pictures (:mod:`ptailor.formats.pom_svg`) and the pattern previews with
``--show-measures`` (``pattern.svg``, ``preview.png``) share. A measure's line
(:class:`ptailor.measures.MaterialLine`) becomes segments in the pattern, each in the panel of
its triangle (:func:`pattern_lines`); each panel the line crosses gets its name once
(:func:`label_anchors`).

Examples
--------
>>> from ptailor.samples import cone_skirt
>>> from ptailor.measures import garment_measures
>>> from ptailor.model.structure import structure
>>> g = cone_skirt()
>>> lines = pattern_lines(garment_measures(g), g.V2, g.F2, structure(g).face_panel)
>>> [(m.name, sorted(set(m.panel.tolist()))) for m in lines]
[('waist', [0, 1]), ('hip', [0, 1]), ('hem', [0, 1]), ('skirt_length', [0])]
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ptailor import tolerances as tol
from ptailor.measures.lines import line_points
from ptailor.measures.measure import Measure

#: One colour per measure, left and right alike (sided names drop ``_left``/``_right``),
#: the same on every garment: dark enough on white and on the panels' light fill.
POM_COLOURS: dict[str, str] = {
    "neck": "#6a3d9a",
    "chest": "#e31a1c",
    "waist": "#33a02c",
    "hip": "#ff7f00",
    "hem": "#1f78b4",
    "body_length": "#b15928",
    "neck_drop": "#d4458f",
    "skirt_length": "#00a0a0",
    "sleeve_length": "#8c8c00",
    "bicep": "#9e5fd6",
    "cuff": "#0b3d91",
    "armhole": "#a6761d",
    "thigh": "#e7298a",
    "inseam": "#1b9e77",
    "leg_opening": "#7570b3",
}
#: A measure not in :data:`POM_COLOURS`.
POM_OTHER = "#444444"


def base_name(name: str) -> str:
    """A measure's name without its side: ``bicep_left`` -> ``bicep``."""
    for side in ("_left", "_right"):
        if name.endswith(side):
            return name[: -len(side)]
    return name


def pom_colour(name: str) -> str:
    """The colour a measure is drawn in (:data:`POM_COLOURS`)."""
    return POM_COLOURS.get(base_name(name), POM_OTHER)


@dataclass(frozen=True)
class MeasureLines:
    """One measure's segments in a pattern, each in one panel.

    Attributes
    ----------
    name, kind : str
        The measure's (:data:`ptailor.measures.MEASURES`).
    panel : (k,) int array
        The panel of each segment (an index into the panels drawn).
    A, B : (k, 2) float arrays
        Both ends of each segment in pattern coordinates.
    """

    name: str
    kind: str
    panel: np.ndarray
    A: np.ndarray
    B: np.ndarray

    @property
    def colour(self) -> str:
        return pom_colour(self.name)


def segments_path(A: np.ndarray, B: np.ndarray, *, decimals: int = 2) -> str:
    """SVG path data of segments, ``M a L b`` each (coordinates already in the document's).

    Parameters
    ----------
    A, B : (k, 2) float arrays
    decimals : int

    Returns
    -------
    str
        Empty for no segment.

    Examples
    --------
    >>> segments_path(np.array([[0.0, 1.0]]), np.array([[2.0, -0.0]]), decimals=1)
    'M0.0,1.0L2.0,0.0'
    """
    if len(A) == 0:
        return ""
    R = np.round(np.concatenate([A, B], axis=1), decimals) + 0.0  # + 0.0: no -0.0
    f = f"{{:.{decimals}f}}"
    fmt = f"M{f},{f}L{f},{f}".format
    return "".join(map(fmt, *R.T.tolist()))


def segments(m: Measure, V: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The segments a measure is drawn as, in positions ``V`` (drape or pattern).

    A line's own segments; a depth (two points, the high one first) the segment joining its
    two points.

    Parameters
    ----------
    m : Measure
    V : (n, d) float array
    F : (m, 3) int array

    Returns
    -------
    ((k, d) float array, (k, d) float array)
    """
    A, B = line_points(m.line, V, F)
    if m.kind == "depth" and len(A) >= 2:
        return A[:1], A[1:2]
    return A, B


def pattern_lines(
    measures: Sequence[Measure], V2: np.ndarray, F2: np.ndarray, face_panel: np.ndarray
) -> list[MeasureLines]:
    """Each measure's segments in the pattern, by panel.

    Parameters
    ----------
    measures : sequence of Measure
        Of the garment whose pattern ``V2``, ``F2`` is (:func:`ptailor.measures.garment_measures`).
    V2 : (n, 2) float array
    F2 : (m, 3) int array
    face_panel : (m,) int array
        The panel index of each triangle (negative: a triangle in no panel drawn; its
        segments are left out).

    Returns
    -------
    list of MeasureLines
        In the order of ``measures``; a measure with no segment in a panel drawn is left out.
    """
    face_panel = np.asarray(face_panel)
    out = []
    for m in measures:  # a loop over measures
        A, B = segments(m, V2, F2)
        face = m.line.face[: len(A)]
        panel = face_panel[face]
        keep = panel >= 0
        if keep.any():
            out.append(MeasureLines(m.name, m.kind, panel[keep], A[keep], B[keep]))
    return out


def label_anchors(
    ml: MeasureLines, *, share: float = 0.15
) -> list[tuple[int, np.ndarray, np.ndarray]]:
    """Where a measure's name goes in the pattern: one place per panel it crosses.

    Parameters
    ----------
    ml : MeasureLines
    share : float
        A panel whose part of the line is shorter than this share of its longest part gets
        no label (a girth clipping a corner of a sleeve, say).

    Returns
    -------
    list of (int, (2,) float array, (2,) float array)
        ``(panel, point, tangent)``: the midpoint of the panel's segment nearest the middle
        of its segments and that segment's unit direction, panels in ascending order.
    """
    if len(ml.panel) == 0:
        return []
    mid = 0.5 * (ml.A + ml.B)
    d = ml.B - ml.A
    length = np.linalg.norm(d, axis=1)
    panels, inv = np.unique(ml.panel, return_inverse=True)
    total = np.bincount(inv, weights=length, minlength=len(panels))
    w = np.maximum(np.bincount(inv, minlength=len(panels)), 1)
    centre = np.stack(
        [np.bincount(inv, weights=mid[:, c], minlength=len(panels)) / w for c in (0, 1)], axis=1
    )
    dist = np.linalg.norm(mid - centre[inv], axis=1)
    order = np.lexsort((dist, inv))  # by panel, nearest first
    first = order[np.searchsorted(inv[order], np.arange(len(panels)))]
    keep = total >= share * total.max()
    tangent = d / np.maximum(length, tol.TINY)[:, None]
    tangent[length <= 0.0] = (1.0, 0.0)
    return [(int(p), mid[i], tangent[i]) for p, i, k in zip(panels, first, keep, strict=True) if k]


def label_offset(point: np.ndarray, tangent: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """The unit normal to a line at ``point`` that points towards ``centre`` (a piece's
    middle): the side a label goes, off the line and inside the piece (a hem's label clear
    of the piece's name under it and of the next piece).

    Examples
    --------
    >>> label_offset(np.array([0.0, 2.0]), np.array([1.0, 0.0]), np.zeros(2)).tolist()
    [0.0, -1.0]
    """
    n = np.array([-tangent[1], tangent[0]], dtype=np.float64) + 0.0  # + 0.0: no -0.0
    return n if float((centre - point) @ n) >= 0.0 else -n


def placed_labels(
    ml: MeasureLines, centres: np.ndarray, gap: float
) -> list[tuple[int, np.ndarray, float]]:
    """A measure's labels in the pattern, set off its line.

    Parameters
    ----------
    ml : MeasureLines
    centres : (n, 2) float array
        Each panel's middle (pattern coordinates): a label goes on the side of the line
        towards it.
    gap : float
        From the line to the label's middle (pattern units).

    Returns
    -------
    list of (int, (2,) float array, float, (2,) float array)
        ``(panel, middle, angle, normal)``: the label's middle in pattern coordinates, the
        angle of its baseline on the page (degrees clockwise, y down, in ``(-90, 90]``: along
        the line, never upside down) and the unit normal it was set off the line along.
    """
    out = []
    for p, xy, t in label_anchors(ml):  # a loop over the panels it crosses
        n = label_offset(xy, t, centres[p])
        angle = float(np.degrees(np.arctan2(-t[1], t[0])))
        angle = angle - 180.0 if angle > 90.0 else angle + 180.0 if angle <= -90.0 else angle
        out.append((p, xy + gap * n, angle, n))
    return out
