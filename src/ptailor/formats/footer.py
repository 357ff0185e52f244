"""The footer of a preview sheet: the scale bar, the outline legend and the error legend
under the grid of panels, in sheet coordinates (:mod:`ptailor.formats.sheet`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ptailor.formats.preview import (
    ERROR_COLOURS,
    ERROR_TITLE,
    NAN_BIN,
    Pattern,
    bin_colour,
    bin_label,
)

#: Length of the scale bar per unit: 10 cm in every physical unit (4 in for inches).
_BAR = {"mm": 100.0, "cm": 10.0, "m": 0.1, "in": 4.0}
#: Estimated advance of one character, in font sizes (a little wide, to be safe).
_CHAR = 0.62


def nice(x: float) -> float:
    """The largest 1, 2 or 5 times a power of ten not above ``x`` (``x > 0``)."""
    e = math.floor(math.log10(x))
    for m in (5.0, 2.0, 1.0):
        if m * 10.0**e <= x:
            return m * 10.0**e
    return 10.0**e


def text_width(s: str, size: float) -> float:
    """Estimated advance width of ``s`` at font size ``size`` (generous)."""
    return _CHAR * size * len(s)


@dataclass(frozen=True)
class Swatch:
    """One entry of the error legend: a ``w`` x ``h`` box at ``(x, y)`` (top-left) and its
    label, centred on ``text_xy`` (the middle of its baseline), under the box."""

    bin: int
    colour: str
    label: str
    x: float
    y: float
    w: float
    h: float
    text_xy: tuple[float, float]  # middle of the baseline


@dataclass(frozen=True)
class LineSample:
    """One entry of the outline legend: a line ``x0 .. x1`` at height ``y`` and text."""

    kind: str  # "before" or "after"
    label: str
    x0: float
    x1: float
    y: float
    text_xy: tuple[float, float]


def footer_layout(
    pattern: Pattern,
    *,
    units: str,
    grid_w: float,
    y: float,
    u: float,
    font: float,
    gap: float,
    title_w: float,
) -> tuple[dict, float, float]:
    """The footer under a grid ``grid_w`` wide, from height ``y`` down: the scale bar and
    the outline legend (:func:`_bar_row`), then the error legend when ``pattern`` has
    triangles (:func:`_error_row`).

    Parameters
    ----------
    pattern : Pattern
    units : str
        The pattern's length unit (scale bar).
    grid_w, y : float
        The grid's width and the footer's top.
    u, font, gap, title_w : float
        The largest panel dimension, the font size, the margin, the title's width.

    Returns
    -------
    dict
        The :class:`ptailor.formats.sheet.Sheet` fields of the footer (``bar`` ... ``swatches``).
    foot_w : float
        The footer's width.
    bottom : float
        Where it ends.
    """
    bar_row, foot_w = _bar_row(units, grid_w=grid_w, y=y, u=u, font=font, gap=gap)
    y += 2.6 * font
    error_title_xy = None
    swatches: tuple[Swatch, ...] = ()
    if pattern.triangles is not None:
        avail = max(grid_w, foot_w, title_w)
        error_title_xy, swatches, legend_w, y = _error_row(
            pattern, avail=avail, y=y, font=font, gap=gap
        )
        foot_w = max(foot_w, legend_w)
    return {**bar_row, "error_title_xy": error_title_xy, "swatches": swatches}, foot_w, y


def _bar_row(
    units: str, *, grid_w: float, y: float, u: float, font: float, gap: float
) -> tuple[dict, float]:
    """The footer's first row, at height ``y``: the scale bar (10 cm or 4 in in physical
    units, else a round length) with its label, then the outline legend.

    Returns
    -------
    dict
        The :class:`Sheet`'s fields ``bar``, ``bar_label``, ``bar_xy``, ``bar_label_xy``,
        ``lines``.
    float
        The row's width.
    """
    # first row: scale bar with its label, then the outline legend
    unit_bar = _BAR.get(units)
    bar = unit_bar if unit_bar is not None else nice(0.25 * max(grid_w, u))
    bar_label = f"{f'{bar:.3f}'.rstrip('0').rstrip('.')} {units}".strip()
    bx, by = gap, y + 0.6 * font
    seg = 2.5 * font
    x = bx + bar + 0.6 * font
    bar_label_xy = (x, by + 0.8 * font)
    x += text_width(bar_label, font) + 1.5 * font
    lines = []
    for kind, text in (("before", "original"), ("after", "adjusted")):
        ty = by + 0.8 * font
        lines.append(
            LineSample(kind, text, x, x + seg, by + 0.45 * font, (x + seg + 0.4 * font, ty))
        )
        x += seg + 0.4 * font + text_width(text, font) + 1.5 * font
    row = {
        "bar": bar,
        "bar_label": bar_label,
        "bar_xy": (bx, by),
        "bar_label_xy": bar_label_xy,
        "lines": tuple(lines),
    }
    return row, x - 1.5 * font - gap


def _error_row(
    pattern: Pattern, *, avail: float, y: float, font: float, gap: float
) -> tuple[tuple[float, float], tuple[Swatch, ...], float, float]:
    """The error legend from height ``y`` down, ``avail`` the width of what is above.

    Returns
    -------
    error_title_xy : (x, y)
    swatches : tuple of Swatch
    width, bottom : float
    """
    # the error legend: its title, then the bins as a row of touching boxes (an ordered
    # scale) with each range centred under its box; the title goes on a row of its own
    # when both do not fit the width of what is above
    bins = list(range(len(ERROR_COLOURS)))
    if NAN_BIN in pattern.used_bins:
        bins.append(NAN_BIN)
    bw = max(text_width(bin_label(b), font) for b in bins) + 0.6 * font
    bh = 1.0 * font
    scale_w = bw * len(bins) + (0.8 * font if NAN_BIN in bins else 0.0)
    head_w = text_width(ERROR_TITLE, font) + 0.8 * font
    error_title_xy = (gap, y + 0.85 * font)
    if head_w + scale_w <= avail:
        x = head_w
    else:
        x, y = 0.0, y + 1.6 * font
    swatches: list[Swatch] = []
    for b in bins:
        if b == NAN_BIN:
            x += 0.8 * font  # set apart: not part of the scale
        swatches.append(
            Swatch(
                b, bin_colour(b), bin_label(b), gap + x, y, bw, bh,
                (gap + x + 0.5 * bw, y + bh + 1.05 * font),
            )
        )  # fmt: skip
        x += bw
    return error_title_xy, tuple(swatches), max(x, head_w), y + bh + 1.6 * font
