"""SVG of a pattern: the adjusted outline over the original one, printable at 1:1.

Optionally the adjusted pattern's triangles are coloured by their intrinsic-scale error (the
bins and colours of :mod:`ptailor.formats.preview`, shared with the PNG preview).
"""

from __future__ import annotations

import math

import numpy as np

from ptailor.formats.pom import MeasureLines, placed_labels, segments_path
from ptailor.formats.preview import (
    AFTER,
    BEFORE,
    ERROR_TITLE,
    FILL,
    FRAME,
    INK,
    Pattern,
    bin_colour,
)
from ptailor.formats.sheet import Sheet, panel_boxes, preview_sheet

#: Units the SVG can print at 1:1: pattern unit -> (CSS unit of width/height and of the
#: viewBox, its size in pattern units). Metres are drawn in cm: font sizes of a few hundredths
#: and 3 decimals (1 mm) are too coarse for renderers (librsvg draws no readable text then).
_CSS_UNITS = {
    "mm": ("mm", 1.0),
    "cm": ("cm", 1.0),
    "m": ("cm", 100.0),
    "in": ("in", 1.0),
    "pt": ("pt", 1.0),
    "px": ("px", 1.0),
}


#: The font of every text.
_FONT = 'font-family="Helvetica, Arial, sans-serif"'
#: A text centred on its position.
_MIDDLE = 'text-anchor="middle"'


def _user_units(units: str, u: float) -> tuple[str, float]:
    """The CSS unit of the document and user units per pattern unit.

    Unknown units (normalised UVs, say) are drawn at a power of ten that makes the largest
    panel 100 to 1000 user units (unitless: CSS pixels).
    """
    if units in _CSS_UNITS:
        return _CSS_UNITS[units]
    return "", 10.0 ** (2 - math.floor(math.log10(u)))


def escape(text: str) -> str:
    """``&``, ``<`` and ``>`` as XML entities (what ``xml.sax.saxutils.escape`` does, without
    its import of ``urllib.request``: 40 ms)."""
    return text.replace("&", "&amp;").replace(">", "&gt;").replace("<", "&lt;")


def _num(x: float) -> str:
    """Fixed 3-decimal formatting without ``-0.000``."""
    return f"{round(float(x), 3) + 0.0:.3f}"


def _xy(P: np.ndarray, decimals: int) -> np.ndarray:
    """``"x,y"`` strings (object array) of ``(k, 2)`` points with fixed decimals."""
    R = np.round(P, decimals) + 0.0  # + 0.0 turns -0.0 into 0.0
    fmt = f"{{:.{decimals}f}},{{:.{decimals}f}}".format  # as "%.{decimals}f" formats
    out = np.empty(len(R), dtype=object)
    out[:] = list(map(fmt, R[:, 0].tolist(), R[:, 1].tolist()))
    return out


def _path(P: np.ndarray) -> str:
    """Closed SVG path data of an already transformed ``(k, 2)`` polyline."""
    return "M" + " L".join(_xy(P, 3).tolist()) + " Z"


def _triangle_paths(T: np.ndarray, F: np.ndarray, bins: np.ndarray, decimals: int):
    """Path data of each bin's triangles, one ``M..L..L..Z`` subpath per triangle.

    Parameters
    ----------
    T : (n, 2) float array
        Vertices, already in sheet coordinates.
    F : (m, 3) int array
        Triangles (indices into ``T``), in the order they are written.
    bins : (m,) int array
        Each triangle's bin.
    decimals : int
        Decimals of the coordinates.

    Returns
    -------
    list of (int, str)
        ``(bin, d)`` for each bin that occurs, ascending.
    """
    # format each used vertex once (np.unique(F)'s order, without its sort)
    mask = np.zeros(len(T), dtype=bool)
    mask[F.ravel()] = True
    xy = _xy(T[mask], decimals)
    tri = xy[(np.cumsum(mask) - 1)[F]]
    out = []
    for b in np.unique(bins).tolist():
        sel = tri[bins == b]
        parts = np.empty((len(sel), 7), dtype=object)
        parts[:, 0] = "M"
        parts[:, 1] = sel[:, 0]
        parts[:, 2] = "L"
        parts[:, 3] = sel[:, 1]
        parts[:, 4] = "L"
        parts[:, 5] = sel[:, 2]
        parts[:, 6] = "Z"
        out.append((b, "".join(parts.ravel().tolist())))
    return out


def pattern_svg(
    outlines_before: list[list[np.ndarray]],
    outlines_after: list[list[np.ndarray]],
    names: list[str],
    *,
    units: str = "cm",
    title: str = "",
    triangles: list[tuple[np.ndarray, np.ndarray]] | None = None,
    errors: list[np.ndarray] | None = None,
    layout: tuple[Pattern, Sheet] | None = None,
    measures: list[MeasureLines] | None = None,
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
        document's ``width``/``height`` are in real units with a ``viewBox`` in the same
        units (pattern units, but ``cm`` for ``m``), so it prints at 1:1; any other unit
        (normalised UVs) gives a unitless size, the pattern scaled by a power of ten that
        makes the largest panel 100 to 1000 user units. The scale bar's label is in
        ``units``.
    title : str
        Written as the document's ``<title>`` and as a heading.
    triangles : list (per panel) of (V, F), optional
        The adjusted pattern's vertices ``V`` (n, 2) float, in the coordinates of
        ``outlines_after``, and triangles ``F`` (m, 3) int. ``V`` may hold more vertices than
        ``F`` uses (the whole pattern's, say).
    errors : list (per panel) of (m,) float arrays, optional
        Relative intrinsic-scale error of each triangle (``0.01`` = 1 %, sign ignored, NaN
        for unknown); required with ``triangles``.
    layout : (Pattern, Sheet), optional
        :func:`ptailor.formats.sheet.preview_sheet` of these very inputs, when the caller
        has it already (the PNG draws the same sheet): the inputs are then not read again.
    measures : list of MeasureLines, optional
        Points of measure (:func:`ptailor.formats.pom.pattern_lines`) drawn over the panels,
        named along their lines (``<g id="measures">``); None: none, the document unchanged.

    Returns
    -------
    str
        The SVG document. Panels sit in a row-wrapped grid in the given order, each in its
        own cell (everything in the panel's own coordinates, translated, y flipped), the
        original outline dashed grey beneath the adjusted one solid, the name under it; a
        scale bar (10 cm or 4 in in physical units, else a round length) and the outline
        legend under the grid. With ``triangles``, each panel's triangles are drawn beneath
        the outlines, one ``<path class="error" data-bin="k">`` per bin that occurs holding
        that bin's triangles as ``M..L..L..Z`` subpaths, with an error legend (one swatch per
        bin, and one for NaN if it occurs) under the scale bar; without, the adjusted panel
        gets a light fill. Outline numbers have 3 decimals, triangle corners
        ``Sheet.tri_decimals`` (2 for cm-sized panels): the output depends only on the inputs.

    Raises
    ------
    ValueError
        When the lists differ in length, ``triangles`` comes without ``errors`` (or the
        reverse), a loop is not a finite ``(k, 2)`` array, a mesh is malformed or an error
        array does not match its triangles.
    """
    pat, s = preview_sheet(
        outlines_before, outlines_after, names, triangles, errors,
        units=units, title=title, caller="pattern_svg", layout=layout,
    )  # fmt: skip
    css, zoom = _user_units(units, s.unit)
    if zoom != 1.0:
        s = s.scaled(zoom)
    out = _head(s, title=title, css=css)
    for p in range(len(pat.names)):
        out.extend(_panel(pat, s, p))
    out.extend(_measures(pat, s, measures) if measures else [])
    out.extend(_scale_bar(s) + _legend(s))
    out.extend(_error_legend(s) if s.error_title_xy is not None else [])
    out.append("</svg>")
    return "\n".join(out) + "\n"


def _text(xy, size: float, text: str, *, attrs: str = "", fill: str = INK) -> str:
    """A ``<text>`` element of ``text`` (escaped) at ``xy``, the start of its baseline
    (the middle with ``attrs=_MIDDLE``), ``size`` its font size, ``fill`` its colour;
    ``attrs`` go before the font and colour."""
    lead = f"{attrs} " if attrs else ""
    return (
        f'<text x="{_num(xy[0])}" y="{_num(xy[1])}" font-size="{_num(size)}" '
        f'{lead}{_FONT} fill="{fill}">{escape(text)}</text>'
    )


def _dasharray(s: Sheet) -> str:
    """The original outline's ``stroke-dasharray``."""
    return f"{_num(s.dash[0])},{_num(s.dash[1])}"


def _head(s: Sheet, *, title: str, css: str) -> list[str]:
    """The document's opening lines: the ``<svg>`` element (``css`` the unit of its size),
    the title, the white background and the heading."""
    W, H = s.width, s.height
    out = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" version="1.1" '
        f'width="{_num(W)}{css}" height="{_num(H)}{css}" '
        f'viewBox="0 0 {_num(W)} {_num(H)}">',
    ]
    if title:
        out.append(f"<title>{escape(title)}</title>")
    out.append(f'<rect x="0" y="0" width="{_num(W)}" height="{_num(H)}" fill="#ffffff"/>')
    if title:
        out.append(_text(s.title_xy, s.title_size, title, attrs='font-weight="bold"'))
    return out


def _panel(pat: Pattern, s: Sheet, p: int) -> list[str]:
    """Panel ``p``'s ``<g>``: its triangles by error bin (or the light fill), the original
    outline dashed, the adjusted one solid, its name."""
    out = [f'<g id="panel-{p}" class="panel">']
    has_tris = pat.triangles is not None and len(pat.triangles[p][1]) > 0
    if has_tris:
        V, F = pat.triangles[p]
        for b, d in _triangle_paths(s.to_sheet(V, p), F, pat.bins[p], s.tri_decimals):
            out.append(
                f'<path class="error" data-bin="{b}" d="{d}" fill="{bin_colour(b)}" stroke="none"/>'
            )
    elif pat.after[p]:
        d = " ".join(_path(s.to_sheet(L, p)) for L in pat.after[p])
        out.append(f'<path class="fill" d="{d}" fill="{FILL}" fill-rule="evenodd" stroke="none"/>')
    dash = _dasharray(s)
    out.extend(
        f'<path class="before" d="{_path(s.to_sheet(L, p))}" fill="none" '
        f'stroke="{BEFORE}" stroke-width="{_num(s.stroke_before)}" '
        f'stroke-dasharray="{dash}" stroke-linejoin="round"/>'
        for L in pat.before[p]
    )
    out.extend(
        f'<path class="after" d="{_path(s.to_sheet(L, p))}" fill="none" '
        f'stroke="{AFTER}" stroke-width="{_num(s.stroke_after)}" stroke-linejoin="round"/>'
        for L in pat.after[p]
    )
    out.append(_text(s.labels[p], s.font, pat.names[p], attrs=_MIDDLE))
    out.append("</g>")
    return out


def _measures(pat: Pattern, s: Sheet, measures: list[MeasureLines]) -> list[str]:
    """The points of measure's ``<g>``: each measure's segments (``<path class="pom">``) and
    its labels (``<text class="pom-label">``, a white halo under the letters)."""
    lo, hi = panel_boxes(pat)
    centres = 0.5 * (lo + hi)
    font = 0.8 * s.font
    gap = font / s.zoom  # (pattern units)
    out = ['<g id="measures">']
    for ml in measures:  # a loop over measures
        d = segments_path(s.to_sheet(ml.A, ml.panel), s.to_sheet(ml.B, ml.panel), decimals=3)
        out.append(
            f'<path class="pom" data-name="{escape(ml.name)}" d="{d}" fill="none" '
            f'stroke="{ml.colour}" stroke-width="{_num(2.0 * s.stroke_after)}" '
            'stroke-linecap="round"/>'
        )
    for ml in measures:  # labels over every line
        for p, xy, angle, _ in placed_labels(ml, centres, gap):
            x, y = s.to_sheet(xy, p)
            attrs = (
                f'class="pom-label" data-name="{escape(ml.name)}" text-anchor="middle" '
                f'dominant-baseline="central" transform="rotate({angle:.1f} {_num(x)} {_num(y)})" '
                f'stroke="#ffffff" stroke-width="{_num(0.25 * font)}" stroke-linejoin="round" '
                f'paint-order="stroke"'
            )
            out.append(_text((x, y), font, ml.name, attrs=attrs, fill=ml.colour))
    out.append("</g>")
    return out


def _scale_bar(s: Sheet) -> list[str]:
    """The scale bar's ``<g>``: a bar with a tick every tenth (longer every fifth),
    labelled."""
    bx, by = s.bar_xy
    ticks = bx + s.bar * np.arange(11) / 10.0
    tick_d = " ".join(
        f"M{_num(t)},{_num(by)} L{_num(t)},{_num(by + s.bar_tick * (1.0 if k % 5 == 0 else 0.5))}"
        for k, t in enumerate(ticks)
    )
    return [
        '<g id="scale-bar">',
        f'<path d="M{_num(bx)},{_num(by)} L{_num(bx + s.bar)},{_num(by)} {tick_d}" fill="none" '
        f'stroke="{INK}" stroke-width="{_num(s.stroke_after)}"/>',
        _text(s.bar_label_xy, s.font, s.bar_label),
        "</g>",
    ]


def _legend(s: Sheet) -> list[str]:
    """The outline legend's ``<g>``: dashed = original, solid = adjusted."""
    dash = _dasharray(s)
    out = ['<g id="legend">']
    for ls in s.lines:
        style = (
            f'stroke="{BEFORE}" stroke-width="{_num(s.stroke_before)}" stroke-dasharray="{dash}"'
            if ls.kind == "before"
            else f'stroke="{AFTER}" stroke-width="{_num(s.stroke_after)}"'
        )
        out.append(
            f'<path class="{ls.kind}" d="M{_num(ls.x0)},{_num(ls.y)} L{_num(ls.x1)},{_num(ls.y)}" '
            f'fill="none" {style}/>'
        )
        out.append(_text(ls.text_xy, s.font, ls.label))
    out.append("</g>")
    return out


def _error_legend(s: Sheet) -> list[str]:
    """The error legend's ``<g>``: its title and one labelled swatch per bin."""
    out = [
        '<g id="error-legend">',
        _text(s.error_title_xy, s.font, ERROR_TITLE),
    ]
    for sw in s.swatches:
        out.append(
            f'<rect class="swatch" data-bin="{sw.bin}" x="{_num(sw.x)}" y="{_num(sw.y)}" '
            f'width="{_num(sw.w)}" height="{_num(sw.h)}" fill="{sw.colour}" '
            f'stroke="{FRAME}" stroke-width="{_num(s.stroke_before)}"/>'
        )
        out.append(_text(sw.text_xy, s.font, sw.label, attrs=_MIDDLE))
    out.append("</g>")
    return out
