"""A cutting sheet's layout: every piece 1:1 on one sheet, cut into printable pages.

The sheet is in millimetres, ``y`` up as in the pattern (no piece is ever mirrored). Pieces
are laid out in shelves, the 10 cm test square first (top left, on page A1); the sheet is
then cut into tiles, one per page, neighbours sharing an ``overlap`` strip whose centre
line carries registration crosshairs: laid one over the other, crosshair on crosshair, two
pages join exactly. A roll (``roll:WIDTH``) is one page as long as the pattern (cut into
pages only past PDF's longest page); A0 is tiled like A4 when the pattern outgrows it.

The layout is data (:class:`CuttingLayout`): the PDF and SVG writers only draw it, and the
tests measure it.
"""

from __future__ import annotations

import math
import re
import textwrap
from dataclasses import dataclass

import numpy as np

from ptailor.errors import PtailorError
from ptailor.formats.cut_marks import CutStyle, Label, Stroke, piece_drawing
from ptailor.model.pieces import PatternFile, Piece
from ptailor.model.units import CM_PER

#: paper sizes (width, height) in mm, by the name ``--paper`` takes (ISO 216, ANSI)
PAPERS = {"A4": (210.0, 297.0), "Letter": (215.9, 279.4), "A3": (297.0, 420.0),
          "A0": (841.0, 1189.0)}  # fmt: skip

_ROLL = re.compile(r"^roll:(.+)$", re.IGNORECASE)
#: a roll's width: a number and a unit (mm when none)
_LENGTH = re.compile(r"^(\d+(?:\.\d*)?|\.\d+)\s*(mm|cm|m|in)?$", re.IGNORECASE)


@dataclass(frozen=True)
class Paper:
    """What the sheet is printed on.

    Attributes
    ----------
    name : str
        ``A4``, ``Letter``, ``A3``, ``A0`` or ``roll:WIDTH`` as given.
    width : float
        Millimetres.
    height : float or None
        Millimetres; None for a roll (as long as the pattern).
    """

    name: str
    width: float
    height: float | None


def parse_paper(text: str, *, style: CutStyle | None = None) -> Paper:
    """``--paper``'s value: a paper name (any case) or ``roll:WIDTH`` (``roll:914mm``,
    ``roll:36in``, a bare number in mm).

    Raises
    ------
    PtailorError
        An unknown name, or a roll too narrow for the test square (exit 2).
    """
    style = style or CutStyle()
    known = {k.lower(): k for k in PAPERS}
    if isinstance(text, str) and text.lower() in known:
        name = known[text.lower()]
        return Paper(name, *PAPERS[name])
    m = _ROLL.match(text) if isinstance(text, str) else None
    if m is None:
        raise PtailorError(
            f"--paper must be one of {', '.join(PAPERS)} or roll:WIDTH (roll:914mm), not {text!r}"
        )
    w = _LENGTH.match(m.group(1).strip())
    if w is None:
        raise PtailorError(
            f"--paper {text}: the roll's width is not a length (roll:914mm, roll:91.4cm, "
            "roll:36in; a bare number is mm)"
        )
    width = float(w.group(1)) * CM_PER[(w.group(2) or "mm").lower()] * 10.0
    least = style.square + 2 * (style.margin + style.overlap)
    if not least <= width <= style.max_page:
        raise PtailorError(
            f"--paper {text}: a roll must be {least:g} to {style.max_page:g} mm wide (the "
            f"{style.square / 10:g} cm test square, margins and a PDF page's limit), "
            f"not {width:g} mm"
        )
    return Paper(f"roll:{m.group(1)}", width, None)


@dataclass(frozen=True)
class Tile:
    """One page's share of the sheet: ``[x0, x0 + w] x [y0, y0 + h]`` in sheet mm."""

    row: int
    col: int
    x0: float
    y0: float

    @property
    def name(self) -> str:
        """``A1`` (rows are letters from the top, columns numbers from the left)."""
        return f"{_letters(self.row)}{self.col + 1}"


def _letters(i: int) -> str:
    s = ""
    i += 1
    while i:  # base 26 digits: A..Z, AA..
        i, r = divmod(i - 1, 26)
        s = chr(ord("A") + r) + s
    return s


@dataclass(frozen=True)
class CuttingLayout:
    """A cutting sheet laid out and cut into pages.

    Attributes
    ----------
    paper : Paper
    page : (2,) tuple of float
        A page's width and height, mm (a fixed paper turned landscape when that takes
        fewer pages).
    tile : (2,) tuple of float
        The printed part of a page (the page less its margins), mm.
    rows, cols : int
        The grid of pages; ``tiles`` holds ``rows * cols`` of them, row by row from the top
        left (``A1``, the page with the test square).
    tiles : tuple of Tile
    strokes : tuple of Stroke
        Every line on the sheet (pieces, the test square, registration marks), sheet mm.
    labels : tuple of Label
        Every text on the sheet, sheet mm.
    pieces : tuple of Piece
        The pieces as placed (sheet mm): moved, or turned a quarter for a narrow roll.
    square : (3,) tuple of float
        The test square's bottom left corner and side, sheet mm.
    marks : (j, 2) float array
        The registration crosshairs' centres, sheet mm.
    style : CutStyle
    """

    paper: Paper
    page: tuple[float, float]
    tile: tuple[float, float]
    rows: int
    cols: int
    tiles: tuple[Tile, ...]
    strokes: tuple[Stroke, ...]
    labels: tuple[Label, ...]
    pieces: tuple[Piece, ...]
    square: tuple[float, float, float]
    marks: np.ndarray
    style: CutStyle

    @property
    def step(self) -> tuple[float, float]:
        """How far apart two neighbouring tiles start (the tile less the overlap), mm."""
        return self.tile[0] - self.style.overlap, self.tile[1] - self.style.overlap

    @property
    def extent(self) -> tuple[float, float]:
        """The sheet all tiles cover, from ``(0, 0)``, mm."""
        sx, sy = self.step
        o = self.style.overlap
        return self.cols * sx + o, self.rows * sy + o


def pieces_in_mm(pattern: PatternFile) -> list[Piece]:
    """The pattern's pieces in millimetres."""
    if pattern.units not in CM_PER:
        raise PtailorError(
            f"cannot draw a cutting sheet in unit {pattern.units!r} (known: {', '.join(CM_PER)})",
            path=pattern.path or None,
        )
    k = CM_PER[pattern.units] * 10.0
    return [p.map_points(lambda a: a * k) for p in pattern.pieces]


def _fit_roll(p: Piece, width: float) -> Piece:
    """A piece wider than a roll's printable width turned a quarter (counter-clockwise, not
    mirrored); still too wide: an error naming it."""
    w, h = p.extent
    if w <= width:
        return p
    if h <= width:
        return p.map_points(lambda a: np.stack([-a[:, 1], a[:, 0]], axis=1))
    raise PtailorError(
        f"--paper: piece {p.name!r} is {w:.0f} x {h:.0f} mm, wider than the roll's "
        f"{width:.0f} mm printable width either way"
    )


def _shelves(
    sizes: np.ndarray, width: float, gap: float, *, first: bool = True
) -> tuple[np.ndarray, float]:
    """Boxes laid in shelves left to right, top down, tallest first, each in the first shelf
    with room (first fit; only the last shelf grows taller); with ``first`` the first box
    (the test square) opens the first shelf. Their top left corners (``y`` down) and the
    height used."""
    tallest = sorted(range(len(sizes)), key=lambda i: (-sizes[i, 1], i))
    order = [0, *(i for i in tallest if i)] if first else tallest
    at = np.zeros((len(sizes), 2))
    shelves: list[list[float]] = []  # per shelf: its top, its height, its next free x
    for i in order:  # a loop over pieces
        w, h = sizes[i]
        room = [s for s in shelves if s[2] + w <= width and (h <= s[1] or s is shelves[-1])]
        if room:
            s = room[0]
        else:
            s = [shelves[-1][0] + shelves[-1][1] + gap if shelves else 0.0, 0.0, 0.0]
            shelves.append(s)
        at[i] = s[2], s[0]
        s[1], s[2] = max(s[1], h), s[2] + w + gap
    return at, shelves[-1][0] + shelves[-1][1]


def _grid(paper: Paper, sizes: np.ndarray, style: CutStyle):
    """The page, the tile, the grid and the shelves: for a fixed paper the orientation and
    number of columns that need fewest pages (then portrait, then fewest columns); a roll
    one column. The shelves
    start inside the top and left outer overlap strips and may reach into the bottom and
    right ones (all inside the tiles)."""
    m, o, g = style.margin, style.overlap, style.gap
    if paper.height is None:
        W = paper.width - 2 * m
        at, used = min(
            (_shelves(sizes, W - 2 * o, g, first=f) for f in (True, False)),
            key=lambda r: r[1] if r[1] + 2 * (m + o) <= style.max_page else math.inf,
        )
        H = float(min(used + 2 * o, style.max_page - 2 * m))
        rows = max(1, math.ceil(used / (H - o)))
        return (paper.width, H + 2 * m), (W, H), rows, 1, at
    best = None
    for turn, (pw, ph) in enumerate([(paper.width, paper.height), (paper.height, paper.width)]):
        W, H = pw - 2 * m, ph - 2 * m
        sx, sy = W - o, H - o
        least = max(1, math.ceil(float(sizes[:, 0].max()) / sx))
        for cols in range(least, least + 1 + math.ceil(float(sizes[:, 0].sum()) / sx)):
            for f in (True, False):  # the square first, or anywhere on a one-page sheet
                at, used = _shelves(sizes, cols * sx, g, first=f)
                rows = max(1, math.ceil(used / sy))
                key = (rows * cols, turn, cols, not f)
                if (f or rows * cols == 1) and (best is None or key < best[0]):
                    best = (key, (pw, ph), (W, H), rows, cols, at)
    return best[1:]


def cutting_layout(
    pattern: PatternFile, *, paper: str | Paper = "A4", title: str = "", note: str = "",
    style: CutStyle | None = None,
) -> CuttingLayout:  # fmt: skip
    """Lay a pattern's pieces out 1:1 and cut the sheet into pages.

    Parameters
    ----------
    pattern : PatternFile
        Pieces in ``pattern.units``: each outline is its cut line (``sew``: its sew line).
    paper : str or Paper
        ``--paper``'s value.
    title, note : str
        Printed in the test square (the garment and recipe; the seam allowance).
    style : CutStyle, optional

    Returns
    -------
    CuttingLayout

    Raises
    ------
    PtailorError
        A bad paper, a unit without a length, a piece wider than a roll.
    """
    style = style or CutStyle()
    paper = paper if isinstance(paper, Paper) else parse_paper(paper, style=style)
    o = style.overlap
    pieces = pieces_in_mm(pattern)
    if paper.height is None:
        room = paper.width - 2 * (style.margin + o)
        pieces = [_fit_roll(p, room) for p in pieces]
    lows = [np.asarray(p.outline, dtype=float).min(axis=0) for p in pieces]
    sizes = np.array([[style.square, style.square], *[p.extent for p in pieces]])
    page, tile, rows, cols, at = _grid(paper, sizes, style)
    top = rows * (tile[1] - o) + o
    # shelves' top left corners (y down from the sheet's top, inside the outer strips)
    corner = np.stack([o + at[:, 0], top - o - at[:, 1] - sizes[:, 1]], axis=1)
    placed = [
        p.map_points(lambda a, d=corner[i + 1] - lows[i]: a + d) for i, p in enumerate(pieces)
    ]
    strokes, labels = [], []
    for p in placed:  # a loop over pieces
        s, lb = piece_drawing(p, style=style)
        strokes += s
        labels += lb
    sq = (float(corner[0, 0]), float(corner[0, 1]), style.square)
    s, lb = _square(sq, paper, rows, cols, title=title, note=note, style=style)
    marks = _marks(rows, cols, tile, o)
    return CuttingLayout(
        paper=paper,
        page=page,
        tile=tile,
        rows=rows,
        cols=cols,
        tiles=tuple(
            Tile(r, c, c * (tile[0] - o), top - r * (tile[1] - o) - tile[1])
            for r in range(rows)
            for c in range(cols)
        ),
        strokes=(*s, *strokes, *_crosshairs(marks, style.cross)),
        labels=(*lb, *labels),
        pieces=tuple(placed),
        square=sq,
        marks=marks,
        style=style,
    )


def _marks(rows: int, cols: int, tile: tuple[float, float], o: float) -> np.ndarray:
    """Registration crosshairs on the overlap strips' centre lines, at every crossing."""
    xs = np.arange(cols + 1) * (tile[0] - o) + o / 2
    ys = np.arange(rows + 1) * (tile[1] - o) + o / 2
    X, Y = np.meshgrid(xs, ys)
    return np.stack([X.ravel(), Y.ravel()], axis=1)


def _crosshairs(marks: np.ndarray, r: float) -> list[Stroke]:
    out = []
    arms = r * np.array([[[-1.0, 0.0], [1.0, 0.0]], [[0.0, -1.0], [0.0, 1.0]]])
    for c in marks:  # a loop over pages' corners
        out += [Stroke("mark", c + a) for a in arms]
    return out


def _square(
    sq: tuple[float, float, float], paper: Paper, rows: int, cols: int, *, title: str,
    note: str, style: CutStyle,
) -> tuple[list[Stroke], list[Label]]:  # fmt: skip
    """The test square and what it says: its size, how to print and join the pages, the
    pattern's title and the seam allowance."""
    x, y, a = sq
    box = np.array([[x, y], [x + a, y], [x + a, y + a], [x, y + a]])
    pages = f"{rows} x {cols} pages" if rows * cols > 1 else "1 page"
    text = [
        "Print at 100 % (actual size, no fit to page): check this square measures "
        f"10 x 10 cm. {paper.name}, {pages}."
    ]
    if rows * cols > 1:
        text.append(
            "Trim each page at its frame's left and top; lay it over its neighbours, "
            "crosshair on crosshair; tape."
        )
    lines = [("10 cm test square", style.name_size, True)]
    for t, h in [*((t, style.text_size) for t in text), (note, style.page_text),
                 (title, style.page_text)]:  # fmt: skip
        # Helvetica's mean advance is about half its height
        lines += [(w, h, False) for w in textwrap.wrap(t, width=int(0.8 * a / (0.5 * h)))]
    labels, yy = [], y + a - style.name_size - 2
    for t, h, bold in lines:  # a loop over lines of text
        if yy < y + 2:
            break
        labels.append(Label(x + a / 2, yy, t, h, bold))
        yy -= 1.35 * h
    return [Stroke("square", box, True)], labels


def page_labels(layout: CuttingLayout, tile: Tile) -> list[Label]:
    """A page's own texts, in page mm (its bottom left corner at 0): its name and number at
    the top, and its neighbours' names at the edges they join."""
    (pw, ph), m = layout.page, layout.style.margin
    h = layout.style.page_text
    n = layout.rows * layout.cols
    k = tile.row * layout.cols + tile.col + 1
    out = [Label(pw / 2, ph - m + 2, f"page {tile.name}  ({k} of {n})", h, bold=True)]
    near = [
        (tile.row, tile.col + 1, pw - m / 2 + h / 3, ph / 2, "v {} v", 90.0),
        (tile.row, tile.col - 1, m / 2 + h / 3, ph / 2, "^ {} ^", 90.0),
        (tile.row - 1, tile.col, m + 3 * h, ph - m + 2, "^ {}", 0.0),
        (tile.row + 1, tile.col, pw / 2, m - 2 - h, "v {}", 0.0),
    ]
    for r, c, x, y, text, angle in near:  # a page's four neighbours
        if 0 <= r < layout.rows and 0 <= c < layout.cols:
            out.append(Label(x, y, text.format(Tile(r, c, 0, 0).name), h, angle=angle))
    return out
