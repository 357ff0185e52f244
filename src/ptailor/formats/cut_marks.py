"""What a cutting sheet draws of one piece: cut line, sew line, notches, grain line, texts.

Everything here is in millimetres, in the piece's own frame (``y`` up, never mirrored):
the layout (:mod:`ptailor.formats.cutting`) moves the strokes and labels onto the sheet,
and the writers (:mod:`ptailor.formats.pdf`, :mod:`ptailor.formats.cut_svg`) only draw
them, so both show the same content.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor.geometry.segments import segment_feet
from ptailor.model.pieces import Piece
from ptailor.model.polyline import signed_area


@dataclass(frozen=True)
class CutStyle:
    """Sizes of a cutting sheet's drawing, in millimetres.

    Attributes
    ----------
    margin : float
        The border of a page left unprinted (home printers print to 3 to 5 mm of the edge;
        page labels sit in it).
    overlap : float
        The strip two neighbouring tiles both print: registration marks sit on its centre
        line, so one page laid over the next matches crosshair on crosshair.
    gap : float
        Between two pieces (and a piece and the test square).
    square : float
        The test square's side (10 cm: a ruler checks the print's scale).
    cross : float
        Half the arm of a registration crosshair (below ``overlap / 2``: it prints whole on
        both pages).
    notch : float
        A notch tick's length, from the cut line inward.
    arrow : float
        A grain line's arrowhead length.
    name_size, text_size, page_text : float
        Heights of a piece's name, its other texts, and the page labels.
    cut_width, line_width, mark_width : float
        Stroke widths: the cut line, the other lines of a piece, registration and frame.
    max_page : float
        The longest side of a PDF page (PDF 1.7: 14 400 pt, 200 in): a roll longer than
        this is cut into pages.
    roll : float
        The one-sheet SVG's width unless a piece is wider (36 in: a plotter's roll).
    """

    margin: float = 10.0
    overlap: float = 10.0
    gap: float = 10.0
    square: float = 100.0
    cross: float = 4.0
    notch: float = 5.0
    arrow: float = 6.0
    name_size: float = 6.0
    text_size: float = 4.0
    page_text: float = 3.5
    cut_width: float = 0.5
    line_width: float = 0.25
    mark_width: float = 0.2
    max_page: float = 5080.0
    roll: float = 914.4


#: the kinds of stroke, in the order drawn: line style per kind (``width``: the style's
#: ``cut_width``, ``line_width`` or ``mark_width``; ``dash``: on/off lengths in mm)
STROKES = {
    "sew": {"width": "line_width", "dash": (3.0, 2.0)},
    "internal": {"width": "line_width", "dash": ()},
    "fold": {"width": "line_width", "dash": (6.0, 2.0, 1.0, 2.0)},
    "grain": {"width": "line_width", "dash": ()},
    "drill": {"width": "line_width", "dash": ()},
    "cut": {"width": "cut_width", "dash": ()},
    "notch": {"width": "cut_width", "dash": ()},
    "square": {"width": "cut_width", "dash": ()},
    "mark": {"width": "mark_width", "dash": ()},
}


@dataclass(frozen=True)
class Stroke:
    """One line of the sheet.

    Attributes
    ----------
    kind : str
        A key of :data:`STROKES`.
    points : (k, 2) float array
        Millimetres.
    closed : bool
        Whether the last point joins the first.
    """

    kind: str
    points: np.ndarray
    closed: bool = False


@dataclass(frozen=True)
class Label:
    """One line of text, centred on ``(x, y)`` (its baseline's middle), in millimetres,
    turned ``angle`` degrees counter-clockwise about that point."""

    x: float
    y: float
    text: str
    size: float
    bold: bool = False
    angle: float = 0.0


def quantity_words(p: Piece) -> str:
    """What to cut: ``Cut 2``, or ``Cut 1 + 1 mirrored`` for ASTM's ``Quantity: a,b``."""
    if p.quantity_split is not None and sum(p.quantity_split) == int(p.quantity):
        a, b = p.quantity_split
        return f"Cut {int(a)} + {int(b)} mirrored" if b else f"Cut {int(a)}"
    return f"Cut {int(p.quantity)}"


def notch_ticks(outline: np.ndarray, notches: np.ndarray, *, length: float) -> np.ndarray:
    """Notch ticks: from the cut line's point nearest each notch, inward along that edge's
    normal (a notch on the sew line is marked where its seam allowance is cut).

    Parameters
    ----------
    outline : (k, 2) float array
        The closed cut line.
    notches : (m, 2) float array
    length : float

    Returns
    -------
    (m, 2, 2) float array
        Each tick's two ends.
    """
    N = np.asarray(notches, dtype=float).reshape(-1, 2)
    if not len(N) or len(outline) < 3:
        return np.zeros((0, 2, 2))
    A = np.asarray(outline, dtype=float)
    B = np.roll(A, -1, axis=0)
    dist, foot = segment_feet(N[:, None, :], A[None], B[None])  # (m, k)
    j = np.argmin(dist, axis=1)
    q = foot[np.arange(len(N)), j]
    e = B[j] - A[j]
    e /= np.maximum(np.linalg.norm(e, axis=1, keepdims=True), 1e-12)
    inward = np.sign(signed_area(A) or 1.0) * np.stack([-e[:, 1], e[:, 0]], axis=1)
    return np.stack([q, q + length * inward], axis=1)


def grain_arrow(grain: np.ndarray, *, length: float) -> list[np.ndarray]:
    """A grain line with an arrowhead at both ends: the line and two open heads."""
    a, b = np.asarray(grain, dtype=float)
    d = b - a
    n = float(np.hypot(*d))
    if n == 0:
        return []
    u = d / n
    v = np.array([-u[1], u[0]])
    h = min(length, n / 3)
    heads = [
        np.array([end - s * h * u + 0.4 * h * v, end, end - s * h * u - 0.4 * h * v])
        for end, s in ((b, 1.0), (a, -1.0))
    ]
    return [np.array([a, b]), *heads]


def _label_anchor(p: Piece) -> tuple[np.ndarray, np.ndarray]:
    """Where a piece's texts go, and which way their block moves off it: beside the grain
    line's middle (inside the piece; right of an upright grain line, above a lying one),
    else on the outline's centroid (no move)."""
    if p.grain is not None and np.all(np.isfinite(p.grain)):
        g = np.asarray(p.grain, dtype=float)
        dx, dy = np.abs(g[1] - g[0])
        return g.mean(axis=0), np.array([0.0, 1.0]) if dx > dy else np.array([1.0, 0.0])
    P = np.asarray(p.outline, dtype=float)
    x, y = P[:, 0], P[:, 1]
    cross = x * np.roll(y, -1) - np.roll(x, -1) * y
    a = cross.sum() / 2
    if abs(a) <= 1e-12:
        return P.mean(axis=0), np.zeros(2)
    c = np.array([(x + np.roll(x, -1)) @ cross, (y + np.roll(y, -1)) @ cross]) / (6 * a)
    return c, np.zeros(2)


def piece_texts(p: Piece) -> list[str]:
    """A piece's name, size, what to cut, and ``Cut on fold`` where it has a fold line."""
    lines = [p.name or "piece"]
    if p.size:
        lines.append(f"Size {p.size}")
    lines.append(quantity_words(p))
    if p.mirror is not None:
        lines.append("Place on fold")
    return lines


def piece_drawing(p: Piece, *, style: CutStyle) -> tuple[list[Stroke], list[Label]]:
    """Every stroke and text of one piece, in millimetres (the piece's coordinates).

    Parameters
    ----------
    p : Piece
        In millimetres; ``outline`` is the cut line (with a seam allowance, ``sew`` the
        sew line).
    style : CutStyle

    Returns
    -------
    strokes : list of Stroke
    labels : list of Label
    """
    s: list[Stroke] = [Stroke("cut", np.asarray(p.outline, dtype=float), True)]
    if p.sew is not None and len(p.sew) >= 3:
        s.append(Stroke("sew", np.asarray(p.sew, dtype=float), True))
    for t in notch_ticks(p.outline, p.notches, length=style.notch):  # a loop over notches
        s.append(Stroke("notch", t))
    if p.grain is not None:
        s += [Stroke("grain", a) for a in grain_arrow(p.grain, length=style.arrow)]
    if p.mirror is not None:
        s.append(Stroke("fold", np.asarray(p.mirror, dtype=float)))
    s += [Stroke("internal", np.asarray(a, dtype=float)) for a in p.internal if len(a) >= 2]
    arms = style.notch / 2 * np.array([[[-1.0, 0.0], [1.0, 0.0]], [[0.0, -1.0], [0.0, 1.0]]])
    for d in np.asarray(p.drills, dtype=float).reshape(-1, 2):  # a loop over drill holes
        s += [Stroke("drill", d + a) for a in arms]
    at, move = _label_anchor(p)
    lines = piece_texts(p)
    sizes = [style.name_size] + [style.text_size] * (len(lines) - 1)
    step = 1.4 * np.array(sizes)
    # the block's half width and half height (Helvetica's mean advance: about 0.6 em)
    half = np.array([max(len(t) * h for t, h in zip(lines, sizes, strict=True)) * 0.3,
                     step.sum() / 2])  # fmt: skip
    x, mid = at + move * (half + style.arrow / 2)
    ys = mid + half[1] - sizes[0] - np.concatenate([[0.0], np.cumsum(step[1:])])
    labels = [
        Label(float(x), float(y), t, float(h), bold=i == 0)
        for i, (t, y, h) in enumerate(zip(lines, ys, sizes, strict=True))
    ]
    return s, labels
