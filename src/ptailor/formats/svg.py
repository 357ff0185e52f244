"""SVG of a pattern: the adjusted outline over the original one, printable at 1:1."""

from __future__ import annotations

import math
from xml.sax.saxutils import escape

import numpy as np

#: Units the SVG can print at 1:1: pattern unit -> (CSS unit of width/height, factor).
_CSS_UNITS = {
    "mm": ("mm", 1.0),
    "cm": ("cm", 1.0),
    "m": ("cm", 100.0),
    "in": ("in", 1.0),
    "pt": ("pt", 1.0),
    "px": ("px", 1.0),
}
#: Length of the scale bar per unit: 10 cm in every physical unit.
_BAR = {"mm": 100.0, "cm": 10.0, "m": 0.1, "in": 4.0}

_BEFORE = "#8a8a8a"
_AFTER = "#1f4e79"
_FILL = "#dce8f4"
_INK = "#222222"


def _num(x: float) -> str:
    """Fixed 3-decimal formatting without ``-0.000``."""
    return f"{round(float(x), 3) + 0.0:.3f}"


def _path(P: np.ndarray) -> str:
    """Closed SVG path data of an already transformed ``(k, 2)`` polyline."""
    R = np.round(P, 3) + 0.0  # + 0.0 turns -0.0 into 0.0
    pts = np.char.add(np.char.add(np.char.mod("%.3f", R[:, 0]), ","), np.char.mod("%.3f", R[:, 1]))
    return "M" + " L".join(pts.tolist()) + " Z"


def _nice(x: float) -> float:
    """The largest 1, 2 or 5 times a power of ten not above ``x`` (``x > 0``)."""
    e = math.floor(math.log10(x))
    for m in (5.0, 2.0, 1.0):
        if m * 10.0**e <= x:
            return m * 10.0**e
    return 10.0**e


def _check(loops, what: str, p: int) -> list[np.ndarray]:
    out = []
    for j, L in enumerate(loops):
        A = np.asarray(L, dtype=np.float64)
        if A.ndim != 2 or A.shape[1] != 2 or len(A) < 2:
            raise ValueError(f"{what}[{p}][{j}]: expected a (k, 2) array with k >= 2")
        if not np.all(np.isfinite(A)):
            raise ValueError(f"{what}[{p}][{j}]: non-finite coordinates")
        out.append(A)
    return out


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


def _layout(cell_w: np.ndarray, cell_h: np.ndarray, gap: float):
    """The row-wrapped grid that fits a landscape sheet (sqrt(2):1) best.

    Tries every row width at which some row breaks (the widths of the first ``k`` cells in a
    row) and keeps the one needing the smallest sheet; ties keep the narrower layout.
    Returns the cells' top-left corners, the total width and height.
    """
    if len(cell_w) == 0:
        return np.zeros((0, 2)), 0.0, 0.0
    starts = np.concatenate([[0.0], np.cumsum(cell_w + gap)])
    # candidate widths: every run of consecutive cells, as wide as the widest cell at least
    cand = (starts[None, 1:] - starts[:-1, None] - gap)[np.triu_indices(len(cell_w))]
    cand = np.unique(np.maximum(np.round(cand, 9), cell_w.max()))
    best = None
    for t in cand.tolist():
        origin, width, height = _shelves(cell_w, cell_h, gap, t + 1e-9)
        sheet = max(width / math.sqrt(2.0), height)
        if best is None or sheet < best[0] - 1e-9:
            best = (sheet, origin, width, height)
    return best[1], best[2], best[3]


def pattern_svg(
    outlines_before: list[list[np.ndarray]],
    outlines_after: list[list[np.ndarray]],
    names: list[str],
    *,
    units: str = "cm",
    title: str = "",
) -> str:
    """A standalone SVG document comparing a pattern before and after adjustment.

    Parameters
    ----------
    outlines_before, outlines_after : list (per panel) of list of (k, 2) float arrays
        Each panel's closed loops in pattern coordinates (y up), the outer outline first;
        a loop is closed implicitly (do not repeat the first point).
    names : list of str
        Panel names, one per panel.
    units : str
        The pattern's length unit. For ``mm``, ``cm``, ``m``, ``in``, ``pt`` and ``px`` the
        document's ``width``/``height`` are in real units (``m`` is written in ``cm``) with a
        ``viewBox`` in pattern units, so it prints at 1:1; any other unit (normalised UVs)
        gives a unitless size.
    title : str
        Written as the document's ``<title>`` and as a heading.

    Returns
    -------
    str
        The SVG document. Panels sit in a row-wrapped grid in the given order, each in its
        own cell (both outlines in the panel's own coordinates, translated, y flipped), the
        original dashed grey beneath the adjusted one solid, the name under it, and a scale
        bar (10 cm in physical units, else a round length) under the grid. Numbers have 3
        decimals: the output depends only on the inputs.

    Raises
    ------
    ValueError
        When the three lists differ in length or a loop is not a finite ``(k, 2)`` array.
    """
    n = len(names)
    if len(outlines_before) != n or len(outlines_after) != n:
        raise ValueError(
            f"pattern_svg: {len(outlines_before)} 'before' panels, {len(outlines_after)} "
            f"'after' panels and {n} names"
        )
    before = [_check(ls, "outlines_before", p) for p, ls in enumerate(outlines_before)]
    after = [_check(ls, "outlines_after", p) for p, ls in enumerate(outlines_after)]

    # panel boxes (union of before and after), in pattern units
    lo = np.zeros((n, 2))
    hi = np.zeros((n, 2))
    for p in range(n):
        pts = before[p] + after[p]
        if pts:
            allp = np.concatenate(pts)
            lo[p], hi[p] = allp.min(axis=0), allp.max(axis=0)
    size = hi - lo
    u = float(size.max()) if n and size.max() > 0 else 1.0  # the largest panel dimension

    font = 0.04 * u
    gap = 0.1 * u
    label_h = 1.8 * font
    stroke_after = 0.0025 * u
    stroke_before = 0.0018 * u
    dash = f"{_num(0.012 * u)},{_num(0.008 * u)}"

    # cells: the panel box plus its label, at least as wide as the label
    cell_w = np.maximum(size[:, 0], np.array([0.6 * font * len(s) for s in names]))
    cell_h = size[:, 1] + label_h
    origin, width, grid_h = _layout(cell_w, cell_h, gap)

    top = gap + (2.6 * font if title else 0.0)
    unit_bar = _BAR.get(units)
    bar = unit_bar if unit_bar is not None else _nice(0.25 * max(width, u))
    bar_h = 2.6 * font
    label = f"{_num(bar).rstrip('0').rstrip('.')} {units}".strip()
    seg = 2.5 * font  # legend line length
    legend_x = bar + 0.6 * font * (len(label) + 3)  # after the scale bar and its label
    legend_w = legend_x + 2 * (seg + 0.4 * font) + 0.6 * font * (len("original") + 2 + 8)
    W = max(width, legend_w, 0.65 * 1.4 * font * len(title)) + 2 * gap
    H = top + grid_h + gap + bar_h + gap

    css, factor = _CSS_UNITS.get(units, ("", 1.0))
    out = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" version="1.1" '
        f'width="{_num(W * factor)}{css}" height="{_num(H * factor)}{css}" '
        f'viewBox="0 0 {_num(W)} {_num(H)}">',
    ]
    if title:
        out.append(f"<title>{escape(title)}</title>")
    out.append(f'<rect x="0" y="0" width="{_num(W)}" height="{_num(H)}" fill="#ffffff"/>')
    text_attrs = f'font-family="Helvetica, Arial, sans-serif" fill="{_INK}"'
    if title:
        out.append(
            f'<text x="{_num(gap)}" y="{_num(gap + font * 1.2)}" font-size="{_num(1.4 * font)}" '
            f'font-weight="bold" {text_attrs}>{escape(title)}</text>'
        )

    for p in range(n):
        # pattern (x, y) -> svg (ox + x - lo_x + pad, oy + hi_y - y): centred in the cell
        ox = gap + origin[p, 0] + 0.5 * (cell_w[p] - size[p, 0]) - lo[p, 0]
        oy = top + origin[p, 1] + hi[p, 1]
        shift = np.array([ox, oy])
        flip = np.array([1.0, -1.0])
        out.append(f'<g id="panel-{p}" class="panel">')
        if after[p]:
            d = " ".join(_path(L * flip + shift) for L in after[p])
            out.append(
                f'<path class="fill" d="{d}" fill="{_FILL}" fill-rule="evenodd" stroke="none"/>'
            )
        out.extend(
            f'<path class="before" d="{_path(L * flip + shift)}" fill="none" '
            f'stroke="{_BEFORE}" stroke-width="{_num(stroke_before)}" '
            f'stroke-dasharray="{dash}" stroke-linejoin="round"/>'
            for L in before[p]
        )
        out.extend(
            f'<path class="after" d="{_path(L * flip + shift)}" fill="none" '
            f'stroke="{_AFTER}" stroke-width="{_num(stroke_after)}" stroke-linejoin="round"/>'
            for L in after[p]
        )
        tx = gap + origin[p, 0] + 0.5 * cell_w[p]
        ty = top + origin[p, 1] + size[p, 1] + 1.25 * font
        out.append(
            f'<text x="{_num(tx)}" y="{_num(ty)}" font-size="{_num(font)}" '
            f'text-anchor="middle" {text_attrs}>{escape(names[p])}</text>'
        )
        out.append("</g>")

    # scale bar: a bar with a tick every tenth, labelled
    bx, by = gap, top + grid_h + gap + 0.6 * font
    th = 0.5 * font
    ticks = bx + bar * np.arange(11) / 10.0
    tick_d = " ".join(
        f"M{_num(t)},{_num(by)} L{_num(t)},{_num(by + (th if k % 5 == 0 else 0.5 * th))}"
        for k, t in enumerate(ticks)
    )
    out.append('<g id="scale-bar">')
    out.append(
        f'<path d="M{_num(bx)},{_num(by)} L{_num(bx + bar)},{_num(by)} {tick_d}" fill="none" '
        f'stroke="{_INK}" stroke-width="{_num(stroke_after)}"/>'
    )
    out.append(
        f'<text x="{_num(bx + bar + 0.6 * font)}" y="{_num(by + 0.8 * font)}" '
        f'font-size="{_num(font)}" {text_attrs}>{escape(label)}</text>'
    )
    # legend: dashed = original, solid = adjusted
    lx = bx + legend_x
    ly = by + 0.45 * font
    out.append(
        f'<path d="M{_num(lx)},{_num(ly)} L{_num(lx + seg)},{_num(ly)}" fill="none" '
        f'stroke="{_BEFORE}" stroke-width="{_num(stroke_before)}" stroke-dasharray="{dash}"/>'
    )
    out.append(
        f'<text x="{_num(lx + seg + 0.4 * font)}" y="{_num(by + 0.8 * font)}" '
        f'font-size="{_num(font)}" {text_attrs}>original</text>'
    )
    lx2 = lx + seg + 0.4 * font + 0.6 * font * (len("original") + 2)
    out.append(
        f'<path d="M{_num(lx2)},{_num(ly)} L{_num(lx2 + seg)},{_num(ly)}" fill="none" '
        f'stroke="{_AFTER}" stroke-width="{_num(stroke_after)}"/>'
    )
    out.append(
        f'<text x="{_num(lx2 + seg + 0.4 * font)}" y="{_num(by + 0.8 * font)}" '
        f'font-size="{_num(font)}" {text_attrs}>adjusted</text>'
    )
    out.append("</g>")
    out.append("</svg>")
    return "\n".join(out) + "\n"
