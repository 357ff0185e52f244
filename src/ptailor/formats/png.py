"""PNG preview of a pattern: the sheet of ``pattern.svg`` drawn with numpy and Pillow.

Everything is drawn :data:`SUPERSAMPLE` times larger, then averaged down (antialiased):
the fills as one label per pixel (:mod:`ptailor.formats.raster`, no Python loop over
triangles), then outlines, text, scale bar and legends with Pillow's ``ImageDraw`` in
DejaVu Sans (bundled, the glyphs matplotlib used to draw the preview with).
"""

from __future__ import annotations

import os

import numpy as np

from ptailor import tolerances as tol
from ptailor.formats.footer import text_width
from ptailor.formats.pom import POM_COLOURS, POM_OTHER, MeasureLines, placed_labels
from ptailor.formats.preview import (
    AFTER,
    BEFORE,
    ERROR_COLOURS,
    ERROR_TITLE,
    FILL,
    FRAME,
    INK,
    NAN_BIN,
    Pattern,
    bin_colour,
)
from ptailor.formats.raster import dashes, evenodd_mask, font, labels_inside, segments_mask
from ptailor.formats.sheet import Sheet, panel_boxes, preview_sheet

#: Drawn this many times larger, then averaged down: the antialiasing (2: five levels
#: along an edge; 3 looks the same at 1800 pixels and costs twice as much)
SUPERSAMPLE = 2
#: Lines turning by more than this get a round join (less leaves a notch under a pixel).
_JOIN_COS = float(np.cos(np.radians(12.0)))
#: Labels of the fill image: 0 white, ``1 + bin`` an error bin (NaN's included), then the
#: light fill of a panel drawn without triangles.
_FILL_LABEL = NAN_BIN + 2


def _rgb(colour: str) -> tuple[int, int, int]:
    c = colour.lstrip("#")
    return (int(c[0:2], 16), int(c[2:4], 16), int(c[4:6], 16))


#: The palette of the supersampled picture: the fill labels, then the line colours.
_COLOURS = (
    "#ffffff",
    *(bin_colour(b) for b in range(NAN_BIN + 1)),
    FILL,
    AFTER,
    BEFORE,
    INK,
    FRAME,
    *POM_COLOURS.values(),
    POM_OTHER,
)


def _palette() -> list[int]:
    return [v for c in _COLOURS for v in _rgb(c)]


def _index(colour: str) -> int:
    """The palette index of ``colour`` (a fill label for the bins' colours)."""
    return _COLOURS.index(colour)


def _has_triangles(pat: Pattern, p: int) -> bool:
    return pat.triangles is not None and len(pat.triangles[p][1]) > 0


def _panel_labels(pat: Pattern, p: int, k_of, box: tuple[int, int]) -> np.ndarray:
    """Fill labels of panel ``p`` over its bounding box ``box`` (rows, columns);
    ``k_of(P)`` maps the panel's pattern points to the box's pixels."""
    loops = [k_of(L) for L in pat.after[p]]
    if not _has_triangles(pat, p):
        return np.where(evenodd_mask(box, loops), _FILL_LABEL, 0).astype(np.uint8)
    V, F = pat.triangles[p]
    bins = pat.bins[p]
    # the most common bin fills the adjusted outline (the triangles' boundary, as the run
    # gives it), the other bins' triangles go over it: only their edges are rasterised
    dom = int(np.argmax(np.bincount(bins))) if loops else -1
    other = bins != dom
    inside, lab = labels_inside(box, loops, k_of(V)[F[other]], bins[other] + 1)
    # overlapping (flipped) triangles add their labels up: shown in the top bin
    lab = np.where(lab > NAN_BIN + 1, len(ERROR_COLOURS), lab).astype(np.uint8)
    return np.where(lab > 0, lab, inside * np.uint8(dom + 1)).astype(np.uint8)


def _fill_labels(pat: Pattern, s: Sheet, k: float, shape: tuple[int, int]) -> np.ndarray:
    """The fill label of each (supersampled) pixel: 0 white, ``1 + bin`` where a
    triangle of that error bin covers it, :data:`_FILL_LABEL` inside the adjusted outline
    of a panel without triangles."""
    H, W = shape
    out = np.zeros(shape, dtype=np.uint8)
    for p in range(len(pat.names)):  # a loop over panels
        pts = list(pat.after[p])
        if _has_triangles(pat, p):
            V, F = pat.triangles[p]
            pts = pts or [V[F].reshape(-1, 2)]
        if not pts:
            continue
        P = np.concatenate([s.to_sheet(L, p) * k for L in pts])
        lo = np.clip(np.floor(P.min(axis=0)).astype(int) - 1, 0, [W, H])
        hi = np.clip(np.ceil(P.max(axis=0)).astype(int) + 1, 0, [W, H])
        box = (int(hi[1] - lo[1]), int(hi[0] - lo[0]))
        if min(box) <= 0:
            continue
        lab = _panel_labels(pat, p, lambda Q, p=p, lo=lo: s.to_sheet(Q, p) * k - lo, box)
        region = out[lo[1] : hi[1], lo[0] : hi[0]]
        np.copyto(region, lab, where=lab > 0)
    return out


class _Pen:
    """Drawing in sheet coordinates, ``k`` pixels per sheet unit: shapes go onto the
    palette picture at once (:data:`_COLOURS` indices), texts are kept for the RGB one
    (:meth:`write`), where they are antialiased. Pillow's integer coordinates are pixel
    centres, hence the half-pixel shift."""

    def __init__(self, draw, k: float, s: Sheet, scale: float) -> None:
        self.draw, self.k = draw, k
        # outlines at least 1.5 / 2 pixels wide in the final image: the sheet's widths suit
        # print at 1:1, not a whole pattern on 1800 pixels
        sup = k / scale
        self.w_before = max(1, round(max(s.stroke_before * scale, 1.5) * sup))
        self.w_after = max(1, round(max(s.stroke_after * scale, 2.0) * sup))
        self.dash = (max(s.dash[0] * k, 1.0), max(s.dash[1] * k, 1.0))
        self.font = font(round(s.font * k))
        self.title_font = font(round(s.title_size * k), bold=True)
        self.texts: list[tuple] = []

    def line(self, P: np.ndarray, colour: str, width: int) -> None:
        """A polyline (closed when its ends coincide), round joins where it turns."""
        self._polyline(np.asarray(P, dtype=np.float64) * self.k - 0.5, _index(colour), width)

    def dashed(self, P: np.ndarray) -> None:
        for D in dashes(np.asarray(P, dtype=np.float64) * self.k, *self.dash):
            self._polyline(D - 0.5, _index(BEFORE), self.w_before)

    def _polyline(self, xy: np.ndarray, ink: int, width: int) -> None:
        # butt-joined segments in one call, and a round join (a disc) only where the line
        # turns by more than JOIN_DEG: Pillow's joint="curve" draws one at every vertex
        self.draw.line(xy.ravel().tolist(), fill=ink, width=width)
        if width < 3 or len(xy) < 3:
            return
        closed = bool(np.all(xy[0] == xy[-1]))
        Q = np.vstack([xy[-2:-1], xy]) if closed else xy
        a, b = Q[1:-1] - Q[:-2], Q[2:] - Q[1:-1]
        na, nb = np.hypot(*a.T), np.hypot(*b.T)
        cos = (a * b).sum(axis=1) / np.maximum(na * nb, tol.TINY)
        r = width / 2.0
        for x, y in Q[1:-1][cos < _JOIN_COS].tolist():  # the corners, a few per outline
            self.draw.ellipse((x - r, y - r, x + r, y + r), fill=ink)

    def box(self, x: float, y: float, w: float, h: float, colour: str) -> None:
        """A filled box with a :data:`FRAME` edge as wide as the original outline, centred
        on the box's border."""
        half = self.w_before / 2.0
        x0, y0 = x * self.k - 0.5 - half, y * self.k - 0.5 - half
        x1, y1 = (x + w) * self.k - 0.5 + half, (y + h) * self.k - 0.5 + half
        self.draw.rectangle(
            (x0, y0, x1, y1), fill=_index(colour), outline=_index(FRAME), width=self.w_before
        )

    def text(
        self, xy, text: str, anchor: str, *, title: bool = False, colour: str = INK, halo=None
    ) -> None:
        """A text kept for :meth:`write`; ``halo``: a white edge that many pixels wide."""
        x, y = xy
        f = self.title_font if title else self.font
        self.texts.append(((x * self.k, y * self.k), text, f, anchor, colour, halo))

    def write(self, draw) -> None:
        """Draw the kept texts with ``draw`` (on the RGB picture)."""
        for xy, text, f, anchor, colour, halo in self.texts:
            if halo:
                draw.text(
                    xy, text, fill=colour, font=f, anchor=anchor, stroke_width=halo,
                    stroke_fill="#ffffff",
                )  # fmt: skip
            else:
                draw.text(xy, text, fill=colour, font=f, anchor=anchor)


def _closed(L: np.ndarray) -> np.ndarray:
    return np.vstack([L, L[:1]])


def _draw_panels(pen: _Pen, pat: Pattern, s: Sheet) -> None:
    """Original outlines dashed, then adjusted ones solid, then the names."""
    n = len(pat.names)
    for p in range(n):
        for L in pat.before[p]:
            pen.dashed(_closed(s.to_sheet(L, p)))
    for p in range(n):
        for L in pat.after[p]:
            pen.line(_closed(s.to_sheet(L, p)), AFTER, pen.w_after)
    for p in range(n):
        pen.text(s.labels[p], pat.names[p], "ms")
    if s.title:
        pen.text(s.title_xy, s.title, "ls", title=True)


def _draw_measures(img, pen: _Pen, pat: Pattern, s: Sheet, measures: list[MeasureLines]):
    """The points of measure over the panels: each measure's segments in its colour on the
    palette picture ``img`` (returned anew), its name on each panel it crosses (horizontal,
    a white halo under the letters)."""
    from PIL import Image

    k = pen.k
    width = 2.0 * pen.w_after
    ink = np.asarray(img).copy()
    for ml in measures:  # a loop over measures
        A, B = s.to_sheet(ml.A, ml.panel) * k, s.to_sheet(ml.B, ml.panel) * k
        ink[segments_mask(ink.shape, A, B, width)] = _index(ml.colour)
    out = Image.fromarray(ink)
    out.putpalette(_palette())  # "L" -> "P"
    lo, hi = panel_boxes(pat)
    centres = 0.5 * (lo + hi)
    gap = 0.8 * s.font / s.zoom  # (pattern units)
    for ml in measures:  # a loop over measures
        # horizontal labels: set off a steep line by half their width more
        half = 0.5 * text_width(ml.name, s.font) / s.zoom
        for p, xy, _, n in placed_labels(ml, centres, gap):
            at = s.to_sheet(xy + half * abs(n[0]) * n, p)
            pen.text(at, ml.name, "mm", colour=ml.colour, halo=max(1, pen.w_after))
    return out


def _draw_footer(pen: _Pen, s: Sheet) -> None:
    """Scale bar (ticks every tenth, longer every fifth), outline legend, error legend."""
    bx, by = s.bar_xy
    pen.line(np.array([[bx, by], [bx + s.bar, by]]), INK, pen.w_after)
    ticks = bx + s.bar * np.arange(11) / 10.0
    tick_len = np.where(np.arange(11) % 5 == 0, 1.0, 0.5) * s.bar_tick
    for t, h in zip(ticks.tolist(), tick_len.tolist(), strict=True):
        pen.line(np.array([[t, by], [t, by + h]]), INK, pen.w_after)
    pen.text(s.bar_label_xy, s.bar_label, "ls")
    for ls in s.lines:
        seg = np.array([[ls.x0, ls.y], [ls.x1, ls.y]])
        if ls.kind == "before":
            pen.dashed(seg)
        else:
            pen.line(seg, AFTER, pen.w_after)
        pen.text(ls.text_xy, ls.label, "ls")
    if s.error_title_xy is not None:
        pen.text(s.error_title_xy, ERROR_TITLE, "ls")
    for sw in s.swatches:
        pen.box(sw.x, sw.y, sw.w, sw.h, sw.colour)
        pen.text(sw.text_xy, sw.label, "ms")


def _check_size(size: int, dpi: float) -> None:
    """Refuse a picture smaller than ``tol.PREVIEW_MIN_PIXELS`` or a resolution <= 0."""
    if int(size) < tol.PREVIEW_MIN_PIXELS:
        raise ValueError(
            f"pattern_png: size must be at least {tol.PREVIEW_MIN_PIXELS} pixels, got {size}"
        )
    if not dpi > 0:
        raise ValueError(f"pattern_png: dpi must be positive, got {dpi}")


def pattern_png(
    path: str | os.PathLike,
    outlines_before: list[list[np.ndarray]],
    outlines_after: list[list[np.ndarray]],
    names: list[str],
    *,
    triangles: list[tuple[np.ndarray, np.ndarray]] | None = None,
    errors: list[np.ndarray] | None = None,
    units: str = "cm",
    title: str = "",
    size: int = 1800,
    dpi: int = 150,
    layout: tuple[Pattern, Sheet] | None = None,
    measures: list[MeasureLines] | None = None,
) -> tuple[int, int]:
    """Write a PNG comparing a pattern before and after adjustment.

    The same sheet as :func:`ptailor.formats.svg.pattern_svg` (layout, colours, error bins
    and legends from :mod:`ptailor.formats.preview`): panels in a row-wrapped grid, each
    adjusted panel's triangles coloured by error bin (or a light fill without ``triangles``),
    the original outline dashed grey, the adjusted one solid dark blue, names under the
    panels, the title on top, scale bar and legends at the bottom, on white.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write.
    outlines_before, outlines_after : list (per panel) of list of (k, 2) float arrays
        Each panel's closed loops in pattern coordinates (y up), the outer outline first.
    names : list of str
        Panel names, one per panel.
    triangles : list (per panel) of (V (n, 2) float, F (m, 3) int), optional
        The adjusted pattern's triangles, in the coordinates of ``outlines_after``.
    errors : list (per panel) of (m,) float arrays, optional
        Relative intrinsic-scale error per triangle (sign ignored, NaN for unknown);
        required with ``triangles``.
    units : str
        The pattern's length unit (scale bar: 10 cm or 4 in in physical units).
    title : str
        Heading, none when empty.
    size : int
        Length of the image's long side in pixels, whatever the units; the short side
        follows with equal aspect.
    dpi : int
        Resolution written in the file; does not change the pixel size.
    layout : (Pattern, Sheet), optional
        :func:`ptailor.formats.sheet.preview_sheet` of these very inputs, when the caller
        has it already (the SVG drew the same sheet): the inputs are then not read again.
    measures : list of MeasureLines, optional
        Points of measure drawn over the adjusted panels, as ``pattern_svg`` draws them
        (labels horizontal). None: the picture is as it is without them.

    Returns
    -------
    (int, int)
        The image's width and height in pixels.

    Raises
    ------
    ValueError
        As :func:`ptailor.formats.preview.check_inputs`, or when ``size`` is below
        ``tol.PREVIEW_MIN_PIXELS`` or ``dpi`` <= 0.

    Notes
    -----
    Drawn :data:`SUPERSAMPLE` times larger and averaged down. Each pixel of a panel takes
    the colour of the triangle under its centre (:func:`ptailor.formats.raster.triangle_labels`):
    no Python loop over triangles, no hairline seams between triangles. Identical inputs give
    identical bytes (Pillow writes no software/time metadata; the bundled font).
    """
    _check_size(size, dpi)
    pat, s = preview_sheet(
        outlines_before, outlines_after, names, triangles, errors,
        units=units, title=title, caller="pattern_png", layout=layout,
    )  # fmt: skip
    img = _picture(pat, s, size=int(size), measures=measures)
    # Pillow's encoder at zlib level 1: the flat fills compress as well as at the default
    # level, in a third of the time; Pillow writes no time or software chunk
    img.save(os.fspath(path), format="PNG", compress_level=1, dpi=(dpi, dpi))
    return img.size


def _picture(pat: Pattern, s: Sheet, *, size: int, measures: list[MeasureLines] | None = None):
    """The sheet drawn ``size`` pixels on its long side (a Pillow RGB image): the fills,
    outlines and footer on the :data:`SUPERSAMPLE` times larger palette picture, the texts
    on its RGB copy, averaged down."""
    from PIL import Image, ImageDraw

    scale = size / max(s.width, s.height)  # pixels per sheet unit
    pw = max(1, round(s.width * scale))
    ph = max(1, round(s.height * scale))
    k = scale * SUPERSAMPLE
    shape = (ph * SUPERSAMPLE, pw * SUPERSAMPLE)
    img = Image.fromarray(_fill_labels(pat, s, k, shape))
    img.putpalette(_palette())  # "L" -> "P"
    draw = ImageDraw.Draw(img)
    draw.fontmode = "1"
    pen = _Pen(draw, k, s, scale)
    _draw_panels(pen, pat, s)
    if measures:
        img = _draw_measures(img, pen, pat, s, measures)
        draw = ImageDraw.Draw(img)
        draw.fontmode = "1"
        pen.draw = draw
    _draw_footer(pen, s)
    img = img.convert("RGB")
    pen.write(ImageDraw.Draw(img))
    return img.reduce(SUPERSAMPLE)
