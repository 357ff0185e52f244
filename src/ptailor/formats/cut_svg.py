"""``pattern_cut.svg``: the cutting sheet as one SVG sheet, 1:1 in millimetres.

The same content as ``pattern.pdf`` (:func:`ptailor.formats.cutting.cutting_layout`: cut
and sew lines, notches, grain lines, names, sizes, quantities, the 10 cm test square) laid
out on one 914 mm (36 in) roll (``CutStyle.roll``), or wider for a wider piece, with no
pages nor registration marks: for a plotter or a cutter that reads SVG, or to look at.
``width`` and ``height`` are in ``mm`` and the ``viewBox`` in millimetres, so every length
is the length cut.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ptailor.formats.cut_marks import STROKES, CutStyle
from ptailor.formats.cutting import CuttingLayout, Paper, cutting_layout
from ptailor.formats.svg import escape
from ptailor.model.pieces import PatternFile
from ptailor.model.units import CM_PER


def cut_svg(pattern: PatternFile, *, title: str = "", note: str = "") -> tuple[str, CuttingLayout]:
    """The SVG document of a pattern's cutting sheet, and its layout.

    Parameters
    ----------
    pattern : PatternFile
        Pieces in ``pattern.units``: outlines are cut lines (``sew``: sew lines).
    title, note : str
        Printed in the test square.

    Returns
    -------
    svg : str
    layout : CuttingLayout
        One page: the whole sheet (its tile drawn ``margin`` in from its edges).
    """
    style = CutStyle()
    widest = max([float(p.extent[0]) for p in pattern.pieces] or [0.0])
    k = 10.0 * CM_PER.get(pattern.units, 1.0)  # (an unknown unit: cutting_layout says so)
    width = max(style.roll, widest * k + 2 * (style.margin + style.overlap) + 1.0)
    layout = cutting_layout(
        pattern, paper=Paper("sheet", width, None), title=title, note=note, style=style
    )
    w, h = layout.page
    m = style.margin
    out = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{w:.3f}mm" height="{h:.3f}mm" '
        f'viewBox="0 0 {w:.3f} {h:.3f}">',
        f"<title>{escape(title or 'pattern')}: cutting sheet</title>",
        f'<g fill="none" stroke="black" transform="matrix(1 0 0 -1 {m:g} {h - m:.3f})">',
    ]
    for kind, look in STROKES.items():  # a loop over kinds of line
        paths = [_path(s.points, s.closed) for s in layout.strokes if s.kind == kind]
        if not paths or kind == "mark":
            continue
        dash = ",".join(f"{d:g}" for d in look["dash"])
        out.append(
            f'<path class="{kind}" stroke-width="{getattr(style, look["width"]):g}"'
            + (f' stroke-dasharray="{dash}"' if dash else "")
            + f' d="{" ".join(paths)}"/>'
        )
    out.append("</g>")
    out.append('<g font-family="Helvetica, Arial, sans-serif" text-anchor="middle">')
    for lb in layout.labels:  # a loop over texts
        x, y = lb.x + m, h - m - lb.y
        turn = f' transform="rotate({-lb.angle:g} {x:.2f} {y:.2f})"' if lb.angle else ""
        out.append(
            f'<text x="{x:.2f}" y="{y:.2f}" font-size="{lb.size:g}"'
            + (' font-weight="bold"' if lb.bold else "")
            + f"{turn}>{escape(lb.text)}</text>"
        )
    out += ["</g>", "</svg>", ""]
    return "\n".join(out), layout


def _path(P: np.ndarray, closed: bool) -> str:
    """An SVG path's data for a polyline, in mm to 3 decimals."""
    pts = " ".join(f"{x:.3f},{y:.3f}" for x, y in np.round(P, 3).tolist())  # (formatting)
    return f"M{pts}" + ("Z" if closed else "")


def write_cut_svg(
    path: str | Path, pattern: PatternFile, *, title: str = "", note: str = ""
) -> CuttingLayout:
    """Write :func:`cut_svg`'s document to ``path``; return its layout."""
    text, layout = cut_svg(pattern, title=title, note=note)
    Path(path).write_text(text, encoding="utf-8")
    return layout
