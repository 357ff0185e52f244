"""``pattern.pdf``: the cutting sheet as a vector PDF, 1:1, one page per tile.

Drawn with reportlab (imported here only) from :func:`ptailor.formats.cutting.cutting_layout`:
every coordinate is written in points (1/72 in) with no transformation of the page's
coordinates (``cm``) around the drawing, so a length in the file is the length printed;
the 10 cm test square is one ``re`` operator 283.46 points on a side. A page draws only the
strokes that reach its tile, clipped to it, then its frame and labels in the margin.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ptailor.formats.cut_marks import STROKES, CutStyle, Label, Stroke
from ptailor.formats.cutting import CuttingLayout, Tile, cutting_layout, page_labels
from ptailor.model.pieces import PatternFile

#: points per millimetre
PT = 72.0 / 25.4


def write_pdf(
    path: str | Path,
    pattern: PatternFile,
    *,
    paper: str = "A4",
    title: str = "",
    note: str = "",
) -> CuttingLayout:
    """Write a pattern's cutting sheet to ``path``.

    Parameters
    ----------
    path : str or Path
    pattern : PatternFile
        Pieces in ``pattern.units``: outlines are cut lines (``sew``: sew lines).
    paper : str
        ``A4`` (default), ``Letter``, ``A3``, ``A0`` or ``roll:WIDTH``.
    title, note : str
        Printed in the test square.

    Returns
    -------
    CuttingLayout
        What was drawn.
    """
    from reportlab.pdfgen.canvas import Canvas

    layout = cutting_layout(pattern, paper=paper, title=title, note=note)
    w, h = layout.page
    c = Canvas(str(path), pagesize=(w * PT, h * PT), invariant=1, pageCompression=1)
    c.setTitle(f"{title or pattern.style or 'pattern'}: cutting sheet")
    c.setCreator("ptailor")
    boxes = _boxes(layout.strokes)
    for tile in layout.tiles:  # a loop over pages
        _page(c, layout, tile, boxes)
        c.showPage()
    c.save()
    return layout


def _boxes(strokes: tuple[Stroke, ...]) -> np.ndarray:
    """Each stroke's bounding box ``(xmin, ymin, xmax, ymax)``, ``(n, 4)``."""
    return np.array(
        [[*s.points.min(axis=0), *s.points.max(axis=0)] for s in strokes]  # a loop over strokes
    ).reshape(-1, 4)


def _page(c, layout: CuttingLayout, tile: Tile, boxes: np.ndarray) -> None:
    """One page: the strokes and labels that reach its tile, clipped to it; its frame and
    its labels in the margin."""
    style = layout.style
    W, H = layout.tile
    m = style.margin
    shift = np.array([m - tile.x0, m - tile.y0])
    near = (
        (boxes[:, 2] >= tile.x0)
        & (boxes[:, 0] <= tile.x0 + W)
        & (boxes[:, 3] >= tile.y0)
        & (boxes[:, 1] <= tile.y0 + H)
    )
    c.saveState()
    clip = c.beginPath()
    clip.rect(m * PT, m * PT, W * PT, H * PT)
    c.clipPath(clip, stroke=0, fill=0)
    strokes = [s for s, k in zip(layout.strokes, near, strict=True) if k]
    for kind in STROKES:  # a loop over kinds of line
        _strokes(c, [s for s in strokes if s.kind == kind], kind, shift, style, layout)
    for lb in layout.labels:  # a loop over texts
        x, y = lb.x + shift[0], lb.y + shift[1]
        if -W < x - m < 2 * W and -H < y - m < 2 * H:
            _label(c, lb, x, y)
    c.restoreState()
    c.setLineWidth(style.mark_width * PT)
    c.setStrokeGray(0.5)
    c.rect(m * PT, m * PT, W * PT, H * PT, stroke=1, fill=0)
    c.setStrokeGray(0)
    for lb in page_labels(layout, tile):  # a page's labels
        _label(c, lb, lb.x, lb.y)


def _strokes(c, strokes, kind: str, shift, style: CutStyle, layout: CuttingLayout) -> None:
    """Strokes of one kind, in the kind's line style (the test square as one rectangle)."""
    if not strokes:
        return
    look = STROKES[kind]
    c.setLineWidth(getattr(style, look["width"]) * PT)
    c.setDash([d * PT for d in look["dash"]] if look["dash"] else [])
    if kind == "square":
        x, y, a = layout.square
        c.rect((x + shift[0]) * PT, (y + shift[1]) * PT, a * PT, a * PT, stroke=1, fill=0)
        return
    path = c.beginPath()
    for s in strokes:  # a loop over strokes
        P = (s.points + shift) * PT
        path.moveTo(*P[0])
        for x, y in P[1:]:  # a stroke's points (a piece's outline: hundreds)
            path.lineTo(x, y)
        if s.closed:
            path.close()
    c.drawPath(path, stroke=1, fill=0)


def _label(c, lb: Label, x: float, y: float) -> None:
    c.setFont("Helvetica-Bold" if lb.bold else "Helvetica", lb.size * PT)
    if lb.angle:
        c.saveState()
        c.translate(x * PT, y * PT)
        c.rotate(lb.angle)
        c.drawCentredString(0, 0, _latin1(lb.text))
        c.restoreState()
    else:
        c.drawCentredString(x * PT, y * PT, _latin1(lb.text))


def _latin1(text: str) -> str:
    """What the PDF's standard fonts can show: other characters become ``?``."""
    return text.encode("latin-1", "replace").decode("latin-1")
