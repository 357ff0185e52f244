"""The layout of a preview sheet (``pattern.svg``, ``preview.png``): where each panel, its
name, the title, the scale bar and the legends go (the footer's rows:
:mod:`ptailor.formats.footer`).

Everything here is in *sheet coordinates*: pattern units (times ``Sheet.zoom``, 1 unless the
SVG rescales), origin at the sheet's top-left corner, y down (as in SVG); a panel's pattern
coordinates ``P`` (y up) map to ``zoom * P * (1, -1) + sheet.offsets[p]``
(:meth:`Sheet.to_sheet`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ptailor import tolerances as tol
from ptailor.formats.footer import LineSample, Swatch, footer_layout, text_width
from ptailor.formats.preview import Pattern, check_inputs


def _shelves(cell_w: np.ndarray, cell_h: np.ndarray, gap: float, target: float):
    """Shelf packing in order: left to right, a new row when ``target`` width is exceeded."""
    origin = np.zeros((len(cell_w), 2))
    x = y = row_h = width = 0.0
    for p in range(len(cell_w)):
        if x > 0.0 and x + cell_w[p] > target:
            x, y, row_h = 0.0, y + row_h + gap, 0.0
        origin[p] = (x, y)
        width = max(width, x + cell_w[p])
        x += cell_w[p] + gap
        row_h = max(row_h, cell_h[p])
    return origin, width, y + row_h


def grid_layout(cell_w: np.ndarray, cell_h: np.ndarray, gap: float, sheet_size=None):
    """The row-wrapped grid that fits a landscape sheet (sqrt(2):1) best.

    Tries every row width at which some row breaks (the widths of runs of consecutive cells)
    and keeps the one needing the smallest sheet; ties keep the narrower layout.

    Parameters
    ----------
    cell_w, cell_h : (n,) float arrays
        The cells' sizes, in order.
    gap : float
        Space between cells.
    sheet_size : callable, optional
        ``(grid width, grid height) -> (sheet width, sheet height)``: what is around the
        grid (title, legends, margins); the grid alone by default.

    Returns
    -------
    origin : (n, 2) float array
        The cells' top-left corners.
    width, height : float
        The grid's size.
    """
    if len(cell_w) == 0:
        return np.zeros((0, 2)), 0.0, 0.0
    starts = np.concatenate([[0.0], np.cumsum(cell_w + gap)])
    cand = (starts[None, 1:] - starts[:-1, None] - gap)[np.triu_indices(len(cell_w))]
    cand = np.unique(np.maximum(np.round(cand, 9), cell_w.max()))
    best = None
    for t in cand.tolist():
        origin, width, height = _shelves(cell_w, cell_h, gap, t + tol.SHEET_LAYOUT_TIE)
        sw, sh = (width, height) if sheet_size is None else sheet_size(width, height)
        sheet = max(sw / math.sqrt(2.0), sh)
        if best is None or sheet < best[0] - tol.SHEET_LAYOUT_TIE:
            best = (sheet, origin, width, height)
    return best[1], best[2], best[3]


@dataclass(frozen=True)
class Sheet:
    """The layout of a preview sheet, in sheet coordinates (y down).

    Sheet coordinates are pattern units times ``zoom`` (1 from :func:`sheet_layout`; see
    :meth:`scaled`).

    Attributes
    ----------
    width, height : float
        The sheet's size.
    unit : float
        The largest panel dimension: what sizes and line widths scale with.
    font : float
        Font size of names, legends and scale bar (the title is ``title_size``).
    offsets : (n, 2) float array
        Panel ``p``'s pattern point ``P`` goes to ``zoom * P * (1, -1) + offsets[p]``.
    labels : (n, 2) float array
        Where each panel's name goes (centre of its baseline), under the panel.
    title, title_xy, title_size : str, (x, y), float
        The heading (left end of its baseline); ``title`` is empty when there is none.
    bar, bar_label, bar_xy, bar_tick, bar_label_xy : float, str, (x, y), float, (x, y)
        Scale bar of length ``bar`` from ``bar_xy`` to the right, ticks ``bar_tick`` long
        (half as long except every fifth) going down, its label's baseline start.
    lines : tuple of LineSample
        The "original" (dashed) and "adjusted" (solid) legend entries.
    error_title_xy : (x, y) or None
        Baseline start of :data:`ERROR_TITLE`; None without an error legend.
    swatches : tuple of Swatch
        The error legend's entries, one per bin in ascending order (touching boxes), the
        NaN one only when NaN occurs (set apart).
    stroke_before, stroke_after : float
        Outline widths; the dashes of the original are ``dash`` (on, off) long.
    tri_decimals : int
        Decimals enough for triangle corners (a resolution of ``unit / 2000`` or better:
        2 for panels of 20 cm to 2 m in cm).
    zoom : float
        Sheet units per pattern unit. The scale bar's ``bar_label`` stays in pattern units.
    """

    width: float
    height: float
    unit: float
    font: float
    offsets: np.ndarray
    labels: np.ndarray
    title: str
    title_xy: tuple[float, float]
    title_size: float
    bar: float
    bar_label: str
    bar_xy: tuple[float, float]
    bar_tick: float
    bar_label_xy: tuple[float, float]
    lines: tuple[LineSample, ...]
    error_title_xy: tuple[float, float] | None
    swatches: tuple[Swatch, ...]
    stroke_before: float
    stroke_after: float
    dash: tuple[float, float]
    tri_decimals: int
    zoom: float = 1.0

    def to_sheet(self, P: np.ndarray, p: int) -> np.ndarray:
        """Panel ``p``'s ``(k, 2)`` pattern points in sheet coordinates (a new array)."""
        return P * np.array([self.zoom, -self.zoom]) + self.offsets[p]

    def scaled(self, k: float) -> Sheet:
        """The same sheet in units ``k`` times smaller (``k = 100``: from m to cm).

        Every length and position is multiplied by ``k``, ``zoom`` too; texts stay.
        """

        def xy(t):
            return (k * t[0], k * t[1])

        return replace(
            self,
            width=k * self.width,
            height=k * self.height,
            unit=k * self.unit,
            font=k * self.font,
            offsets=k * self.offsets,
            labels=k * self.labels,
            title_xy=xy(self.title_xy),
            title_size=k * self.title_size,
            bar=k * self.bar,
            bar_xy=xy(self.bar_xy),
            bar_tick=k * self.bar_tick,
            bar_label_xy=xy(self.bar_label_xy),
            lines=tuple(
                replace(ls, x0=k * ls.x0, x1=k * ls.x1, y=k * ls.y, text_xy=xy(ls.text_xy))
                for ls in self.lines
            ),
            error_title_xy=None if self.error_title_xy is None else xy(self.error_title_xy),
            swatches=tuple(
                replace(sw, x=k * sw.x, y=k * sw.y, w=k * sw.w, h=k * sw.h, text_xy=xy(sw.text_xy))
                for sw in self.swatches
            ),
            stroke_before=k * self.stroke_before,
            stroke_after=k * self.stroke_after,
            dash=xy(self.dash),
            tri_decimals=max(0, self.tri_decimals - round(math.log10(k))),
            zoom=k * self.zoom,
        )


def panel_boxes(pattern: Pattern) -> tuple[np.ndarray, np.ndarray]:
    """Each panel's bounding box over both outlines and its triangles.

    Returns
    -------
    lo, hi : (n, 2) float arrays
        Zero for an empty panel.
    """
    n = len(pattern.names)
    lo = np.zeros((n, 2))
    hi = np.zeros((n, 2))
    for p in range(n):
        pts = pattern.before[p] + pattern.after[p]
        if pattern.triangles is not None:
            V, F = pattern.triangles[p]
            used = np.zeros(len(V), dtype=bool)  # the corners of the triangles, each once
            used[F.ravel()] = True
            pts = [*pts, V[used]]
        pts = [P for P in pts if len(P)]
        if pts:
            allp = np.concatenate(pts)
            lo[p], hi[p] = allp.min(axis=0), allp.max(axis=0)
    return lo, hi


def sheet_layout(pattern: Pattern, *, units: str, title: str = "") -> Sheet:
    """Lay out a preview sheet.

    Panels sit in a row-wrapped grid (chosen to fit a landscape sheet) in the given order,
    each centred in its own cell with its name under it; the title on top; under the grid
    the scale bar (10 cm or 4 in in physical units, else a round length) with the outline
    legend, then the error legend (when ``pattern`` has triangles) wrapped to the sheet's width.

    Parameters
    ----------
    pattern : Pattern
        From :func:`check_inputs`.
    units : str
        The pattern's length unit (scale bar).
    title : str
        Heading, or empty for none.

    Returns
    -------
    Sheet
    """
    n = len(pattern.names)
    lo, hi = panel_boxes(pattern)
    size = hi - lo
    u = float(size.max()) if n and size.max() > 0 else 1.0  # the largest panel dimension

    font = 0.04 * u
    gap = 0.1 * u
    label_h = 1.8 * font
    title_size = 1.4 * font

    # cells: the panel box plus its label, at least as wide as the label
    cell_w = np.maximum(size[:, 0], np.array([text_width(s, font) for s in pattern.names]))
    cell_h = size[:, 1] + label_h
    top = gap + (2.6 * font if title else 0.0)
    title_w = text_width(title, title_size)

    def footer(grid_w: float, y: float) -> tuple[dict, float, float]:
        """The footer under a grid ``grid_w`` wide, from height ``y`` down."""
        return footer_layout(
            pattern, units=units, grid_w=grid_w, y=y, u=u, font=font, gap=gap, title_w=title_w
        )

    def sheet_size(grid_w: float, grid_h: float) -> tuple[float, float]:
        _, foot_w, bottom = footer(grid_w, top + grid_h + gap)
        return max(grid_w, foot_w, title_w) + 2 * gap, bottom + gap

    origin, grid_w, grid_h = grid_layout(cell_w, cell_h, gap, sheet_size)
    offsets = np.zeros((n, 2))
    labels = np.zeros((n, 2))
    if n:
        offsets[:, 0] = gap + origin[:, 0] + 0.5 * (cell_w - size[:, 0]) - lo[:, 0]
        offsets[:, 1] = top + origin[:, 1] + hi[:, 1]
        labels[:, 0] = gap + origin[:, 0] + 0.5 * cell_w
        labels[:, 1] = top + origin[:, 1] + size[:, 1] + 1.25 * font
    foot, foot_w, bottom = footer(grid_w, top + grid_h + gap)
    W = max(grid_w, foot_w, title_w) + 2 * gap
    H = bottom + gap
    return Sheet(
        width=W,
        height=H,
        unit=u,
        font=font,
        offsets=offsets,
        labels=labels,
        title=title,
        title_xy=(gap, gap + 1.2 * font),
        title_size=title_size,
        bar_tick=0.5 * font,
        **foot,
        stroke_before=0.0018 * u,
        stroke_after=0.0025 * u,
        dash=(0.012 * u, 0.008 * u),
        tri_decimals=int(np.clip(math.ceil(-math.log10(u / 2000.0)), 0, 8)),
    )


def preview_sheet(
    outlines_before: list[list[np.ndarray]],
    outlines_after: list[list[np.ndarray]],
    names: list[str],
    triangles: list[tuple[np.ndarray, np.ndarray]] | None,
    errors: list[np.ndarray] | None,
    *,
    units: str,
    title: str,
    caller: str,
    layout: tuple[Pattern, Sheet] | None = None,
) -> tuple[Pattern, Sheet]:
    """The checked inputs of a preview and its sheet: :func:`check_inputs` then
    :func:`sheet_layout`, what ``pattern_svg`` and ``pattern_png`` both start with.

    Parameters
    ----------
    outlines_before, outlines_after : list (per panel) of list of (k, 2) float arrays
    names : list of str
    triangles : list (per panel) of (V (n, 2) float, F (m, 3) int), or None
    errors : list (per panel) of (m,) float arrays, or None
        As :func:`ptailor.formats.svg.pattern_svg` takes them.
    units, title : str
        The pattern's unit and the sheet's heading.
    caller : str
        The writer's name, starting each error message.
    layout : (Pattern, Sheet), optional
        This very function's result for these inputs, when the caller has it already:
        returned as it is (the inputs are not read again).

    Returns
    -------
    Pattern
        The checked inputs.
    Sheet
        Their layout.

    Raises
    ------
    ValueError
        As :func:`ptailor.formats.preview.check_inputs` (``caller`` starts the message).
    """
    if layout is not None:
        return layout
    pat = check_inputs(outlines_before, outlines_after, names, triangles, errors, caller=caller)
    return pat, sheet_layout(pat, units=units, title=title)
