"""The points-of-measure picture of a garment: its drape seen from the front and its pattern
pieces, each measure's line drawn in its colour and named, and a table of the values.

``docs/measures.md``'s pictures are this function's output (``docs/measures/make.py``).
Everything is in centimetres, the drape and the pattern at the same scale.

Examples
--------
>>> from ptailor.samples import cone_skirt
>>> from ptailor.measures import garment_measures
>>> g = cone_skirt()
>>> svg = measures_svg(g, garment_measures(g), title="cone skirt")
>>> svg.startswith("<?xml"), svg.count('class="pom-label"') >= 4
(True, True)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ptailor.formats.drape_view import depth_buffer, front_view
from ptailor.formats.footer import text_width
from ptailor.formats.pom import (
    pattern_lines,
    placed_labels,
    pom_colour,
    segments,
    segments_path,
)
from ptailor.formats.preview import INK
from ptailor.formats.sheet import grid_layout
from ptailor.formats.svg import escape
from ptailor.measures.measure import Measure
from ptailor.model.boundary import boundary_loops
from ptailor.model.garment import Garment
from ptailor.model.structure import structure
from ptailor.model.units import factor

#: The drape's panels and the pattern pieces: fill and outline.
PANEL_FILL = "#e8eef5"
PANEL_EDGE = "#7d8ea3"
#: Leader lines and the pieces' names.
MUTED = "#6b6b6b"

_FONT = 'font-family="Helvetica, Arial, sans-serif"'
#: A label's white halo, drawn under its letters.
_HALO = 'stroke="#ffffff" stroke-linejoin="round" paint-order="stroke"'


@dataclass(frozen=True)
class _Drape:
    """The front view, y up, cm: each panel's outline loops (far panels first), each
    measure's segments and whether each is seen, the view's box."""

    fills: list[list[np.ndarray]]
    lines: list[tuple[Measure, np.ndarray, np.ndarray, np.ndarray]]
    lo: np.ndarray
    hi: np.ndarray


def _drape(g: Garment, measures: Sequence[Measure], k: float) -> _Drape:
    """Each panel's outline and every measure's segments in the front view."""
    P, depth = front_view(g.V3 * k, g.frame)
    buf = depth_buffer(P, depth, g.F3)
    F = g.F3
    st = structure(g)
    fills = [[P[loop] for loop in boundary_loops(F[p.faces])] for p in st.panels]
    # far panels first: the near ones are painted over them
    far = [float(depth[F[p.faces]].mean()) if len(p.faces) else 0.0 for p in st.panels]
    fills = [fills[i] for i in np.argsort(far, kind="stable")[::-1]]
    lines = []
    for m in measures:  # a loop over measures
        A3, B3 = segments(m, g.V3 * k, F)
        (A, da), (B, db) = front_view(A3, g.frame), front_view(B3, g.frame)
        if m.kind == "depth":  # a drop: across at the high point's level, then down
            corner = np.stack([B[:, 0], A[:, 1]], axis=1)
            A, B = np.concatenate([A, corner]), np.concatenate([corner, B])
            da = db = np.concatenate([da, db])
        seen = buf.seen(0.5 * (A + B), 0.5 * (da + db))
        lines.append((m, A, B, seen))
    used = P[np.unique(F)]
    return _Drape(fills, lines, used.min(axis=0), used.max(axis=0))


@dataclass(frozen=True)
class _Pieces:
    """The pattern pieces, cm, each at its place in the grid (y down): outlines, names,
    where the names go, each measure's segments and its labels (name, middle, angle in
    degrees, clockwise on the page)."""

    outlines: list[list[np.ndarray]]
    names: list[str]
    name_xy: np.ndarray
    lines: list[tuple[str, np.ndarray, np.ndarray]]
    labels: list[tuple[str, np.ndarray, float]]
    width: float
    height: float


def _pieces(g: Garment, measures: Sequence[Measure], k: float, *, font: float) -> _Pieces:
    """The pieces laid out in a grid about as wide as 1.4 times its height, at the drape's
    scale."""
    st = structure(g)
    V2 = g.V2 * k
    loops = [[V2[lp] for lp in st.panel_loops(i)] for i in range(len(st.panels))]
    lo = np.array([np.concatenate(ls).min(axis=0) for ls in loops])
    hi = np.array([np.concatenate(ls).max(axis=0) for ls in loops])
    names = [p.name for p in st.panels]
    size = hi - lo
    cell_w = np.maximum(size[:, 0], [text_width(s, font) for s in names])
    cell_h = size[:, 1] + 3.0 * font
    gap = 2.0 * font
    origin, width, height = grid_layout(
        cell_w, cell_h, gap, lambda w, h: (w * math.sqrt(2.0) / 1.4, h)
    )
    off = np.stack([origin[:, 0] + 0.5 * (cell_w - size[:, 0]) - lo[:, 0], origin[:, 1] + hi[:, 1]])
    off = off.T  # piece p's point (x, y) goes to (x, -y) + off[p]

    def place(Q: np.ndarray, p) -> np.ndarray:
        return Q * np.array([1.0, -1.0]) + off[p]

    outlines = [[place(L, p) for L in ls] for p, ls in enumerate(loops)]
    name_xy = np.stack([origin[:, 0] + 0.5 * cell_w, origin[:, 1] + size[:, 1] + 2.4 * font], 1)
    lines, labels = [], []
    for ml in pattern_lines(measures, V2, g.F2, st.face_panel):  # a loop over measures
        lines.append((ml.name, place(ml.A, ml.panel), place(ml.B, ml.panel)))
        centres = 0.5 * (lo + hi)
        labels += [(ml.name, place(xy, p), a) for p, xy, a, _ in placed_labels(ml, centres, font)]
    return _Pieces(outlines, names, name_xy, lines, labels, width, height)


def _spread(y: np.ndarray, step: float) -> np.ndarray:
    """Sorted label heights pushed down until each is ``step`` below the one before."""
    i = np.arange(len(y)) * step
    return np.maximum.accumulate(y - i) + i


def _closed_path(L: np.ndarray) -> str:
    return "M" + "L".join(f"{x:.2f},{y:.2f}" for x, y in np.round(L, 2).tolist()) + "Z"


def _text(xy, size: float, text: str, *, fill: str = INK, attrs: str = "") -> str:
    lead = f"{attrs} " if attrs else ""
    return (
        f'<text x="{xy[0]:.2f}" y="{xy[1]:.2f}" font-size="{size:.2f}" {lead}{_FONT} '
        f'fill="{fill}">{escape(text)}</text>'
    )


def _drape_labels(d: _Drape, font: float) -> list[tuple[Measure, np.ndarray, int, float]]:
    """Where each measure's label goes beside the drape: the viewer's right (the wearer's
    left) for left-side measures and the centre's girths, the viewer's left for the rest.

    Returns
    -------
    list of (Measure, (2,) float array, int, float)
        The measure, its anchor on the line (view coordinates), its side (1: right, -1:
        left) and its label's baseline as a depth below the view's top (``hi[1] - y``),
        spread so that labels on one side do not overlap.
    """
    cx = 0.5 * (d.lo[0] + d.hi[0])
    rows = []
    for m, A, B, seen in d.lines:  # a loop over measures
        M = 0.5 * (A + B)
        pick = M[seen] if seen.any() else M
        if m.kind == "girth" and not m.name.endswith("_right"):
            anchor, side = pick[np.argmax(pick[:, 0])], 1
        elif m.kind == "girth":
            anchor, side = pick[np.argmin(pick[:, 0])], -1
        else:
            anchor = pick[np.argmin(np.linalg.norm(pick - pick.mean(axis=0), axis=1))]
            side = 1 if anchor[0] > cx + 0.01 * (d.hi[0] - d.lo[0]) else -1
        rows.append((m, anchor, side))
    out = []
    for side in (1, -1):
        mine = [r for r in rows if r[2] == side]
        if not mine:
            continue
        t = np.array([d.hi[1] - r[1][1] for r in mine]) + 0.35 * font
        order = np.argsort(t, kind="stable")
        spread = _spread(t[order], 1.35 * font)
        out += [(mine[i][0], mine[i][1], side, tt) for i, tt in zip(order, spread, strict=True)]
    return out


def _label_text(m: Measure, k: float) -> str:
    return f"{m.name} {m.drape * k:.1f}"


def measures_svg(
    g: Garment, measures: Sequence[Measure], *, title: str = "", width_px: int = 1200
) -> str:
    """A garment's points of measure drawn on its drape and its pattern, as an SVG document.

    Parameters
    ----------
    g : Garment
    measures : sequence of Measure
        Its measures (:func:`ptailor.measures.garment_measures`), in its units.
    title : str
        The heading (none when empty).
    width_px : int
        The document's width in pixels (its ``viewBox`` is in centimetres).

    Returns
    -------
    str
        Left, the drape seen from the front (orthographic along the garment's front axis:
        the wearer's left on the viewer's right), each panel's seen part filled, each
        measure's line in its colour (:data:`ptailor.formats.pom.POM_COLOURS`), dashed where
        hidden behind the garment, named with its drape value beside the drape
        (``class="pom-label"``); right, the pattern pieces at the same scale with the same
        lines, named on each piece they cross; under both a table of every measure's kind and
        its drape and pattern values in cm (``class="pom-table"``). Depends only on its
        inputs (2 decimals).
    """
    k = factor(g.units, "cm")
    d = _drape(g, measures, k)
    u = float(max(d.hi - d.lo))
    font = 0.026 * u
    rows = _drape_labels(d, font)
    texts = {m.name: _label_text(m, k) for m in measures}

    def col(side: int) -> float:
        w = [text_width(texts[r[0].name], font) for r in rows if r[2] == side]
        return max(w) + 3.0 * font if w else font

    margin = 1.5 * font
    top = margin + (2.8 * font if title else 0.0) + 2.0 * font
    x0 = margin + col(-1)
    dw, dh = d.hi - d.lo
    pieces = _pieces(g, measures, k, font=0.8 * font)
    px = x0 + dw + col(1) + 2.0 * font
    block = max(dh, max((r[3] for r in rows), default=0.0) + font, pieces.height)
    ty = top + block + 3.0 * font
    W = px + pieces.width + margin
    H = ty + 1.5 * font * (len(measures) + 1) + margin

    def to_doc(Q: np.ndarray) -> np.ndarray:
        return np.stack([Q[..., 0] - d.lo[0] + x0, d.hi[1] - Q[..., 1] + top], axis=-1)

    out = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{width_px}" '
        f'height="{round(width_px * H / W)}" viewBox="0 0 {W:.2f} {H:.2f}">',
    ]
    if title:
        out.append(f"<title>{escape(title)}</title>")
    out.append(f'<rect x="0" y="0" width="{W:.2f}" height="{H:.2f}" fill="#ffffff"/>')
    if title:
        out.append(
            _text((margin, margin + 1.4 * font), 1.4 * font, title, attrs='font-weight="bold"')
        )
    out.append(_text((x0, top - 1.2 * font), font, "drape, seen from the front", fill=MUTED))
    out.append(_text((px, top - 1.2 * font), font, "pattern", fill=MUTED))
    out += _drape_svg(d, rows, to_doc, font=font, texts=texts, units=u)
    shift = np.array([px, top])
    out += _pieces_svg(pieces, shift, font=0.8 * font, units=u)
    out += _table_svg(measures, k, (margin, ty), font=font)
    out.append("</svg>")
    return "\n".join(out) + "\n"


def _drape_svg(d: _Drape, rows, to_doc, *, font: float, texts: dict, units: float) -> list[str]:
    """The drape's ``<g>``: the panels' seen parts, then each measure's ``<g class="pom">``
    (hidden segments dashed, seen ones solid, a leader to its label)."""
    out = ['<g id="drape">']
    for polys in d.fills:  # a loop over panels
        path = "".join(_closed_path(to_doc(L)) for L in polys)
        out.append(
            f'<path class="panel" d="{path}" fill="{PANEL_FILL}" '
            f'stroke="{PANEL_EDGE}" stroke-width="{0.0018 * units:.3f}" stroke-linejoin="round"/>'
        )
    lw = 0.006 * units
    top = to_doc(np.array([0.0, d.hi[1]]))[1]
    place = {r[0].name: r for r in rows}
    for m, A, B, seen in d.lines:  # a loop over measures
        c = pom_colour(m.name)
        a, b = to_doc(A), to_doc(B)
        out.append(f'<g class="pom" data-name="{escape(m.name)}">')
        hidden = segments_path(a[~seen], b[~seen])
        if hidden:
            out.append(
                f'<path class="hidden" d="{hidden}" fill="none" stroke="{c}" '
                f'stroke-width="{0.6 * lw:.3f}" stroke-dasharray="{1.5 * lw:.3f},{1.5 * lw:.3f}" '
                'stroke-opacity="0.6"/>'
            )
        seen_d = segments_path(a[seen], b[seen])
        if seen_d:
            out.append(
                f'<path class="seen" d="{seen_d}" fill="none" stroke="{c}" '
                f'stroke-width="{lw:.3f}" stroke-linecap="round"/>'
            )
        _, anchor, side, t = place[m.name]
        p = to_doc(anchor)
        edge = d.hi[0] if side > 0 else d.lo[0]
        lx, ly = to_doc(np.array([edge, 0.0]))[0] + side * font, top + t
        out.append(
            f'<path class="leader" d="M{p[0]:.2f},{p[1]:.2f}L{lx - side * 0.3 * font:.2f},'
            f'{ly - 0.35 * font:.2f}" fill="none" stroke="{c}" stroke-width="{0.3 * lw:.3f}"/>'
        )
        out.append(f'<circle cx="{p[0]:.2f}" cy="{p[1]:.2f}" r="{0.9 * lw:.3f}" fill="{c}"/>')
        anchor_attr = 'text-anchor="start"' if side > 0 else 'text-anchor="end"'
        out.append(
            _text((lx, ly), font, texts[m.name], fill=c, attrs=f'class="pom-label" {anchor_attr}')
        )
        out.append("</g>")
    out.append("</g>")
    return out


def _pieces_svg(pieces: _Pieces, shift: np.ndarray, *, font: float, units: float) -> list[str]:
    """The pattern's ``<g>``: the pieces filled and outlined, named under them, each
    measure's segments and its name on each piece it crosses (a white halo under the
    letters)."""
    out = ['<g id="pattern">']
    for ls in pieces.outlines:  # a loop over pieces
        path = "".join(_closed_path(L + shift) for L in ls)
        out.append(
            f'<path class="piece" d="{path}" fill="{PANEL_FILL}" fill-rule="evenodd" '
            f'stroke="{PANEL_EDGE}" stroke-width="{0.0025 * units:.3f}" stroke-linejoin="round"/>'
        )
    for name, xy in zip(pieces.names, pieces.name_xy + shift, strict=True):
        out.append(_text(xy, font, name, fill=MUTED, attrs='text-anchor="middle"'))
    lw = 0.006 * units
    for name, A, B in pieces.lines:  # a loop over measures
        d = segments_path(A + shift, B + shift)
        out.append(
            f'<path class="pom" data-name="{escape(name)}" d="{d}" fill="none" '
            f'stroke="{pom_colour(name)}" stroke-width="{lw:.3f}" stroke-linecap="round"/>'
        )
    for name, xy, angle in pieces.labels:  # a loop over labels
        at = xy + shift
        attrs = (
            f'class="pom-label" text-anchor="middle" dominant-baseline="central" '
            f'transform="rotate({angle:.1f} {at[0]:.2f} {at[1]:.2f})" {_HALO} '
            f'stroke-width="{0.25 * font:.3f}"'
        )
        out.append(_text(at, font, name, fill=pom_colour(name), attrs=attrs))
    out.append("</g>")
    return out


def _table_svg(measures: Sequence[Measure], k: float, xy, *, font: float) -> list[str]:
    """The table of values: a swatch, the name, the kind, the drape's and the pattern's
    value in cm."""
    x, y = xy
    name_w = max([text_width(m.name, font) for m in measures] + [text_width("measure", font)])
    cols = [x + 3.0 * font, x + 4.0 * font + name_w]
    cols += [cols[1] + 11.0 * font, cols[1] + 18.0 * font]  # right ends of the numbers
    out = ['<g class="pom-table">']
    head = ("measure", "kind", "drape cm", "pattern cm")
    for c, text in enumerate(head):
        attrs = 'font-weight="bold"' + (' text-anchor="end"' if c >= 2 else "")
        out.append(_text((cols[c], y), font, text, attrs=attrs))
    for i, m in enumerate(measures):  # a loop over measures
        yy = y + 1.5 * font * (i + 1)
        c = pom_colour(m.name)
        out.append(
            f'<path d="M{x:.2f},{yy - 0.35 * font:.2f}h{2.2 * font:.2f}" stroke="{c}" '
            f'stroke-width="{0.3 * font:.3f}"/>'
        )
        values = (m.name, m.kind, f"{m.drape * k:.1f}", f"{m.pattern * k:.1f}")
        for col, text in enumerate(values):
            attrs = 'text-anchor="end"' if col >= 2 else ""
            out.append(_text((cols[col], yy), font, text, attrs=attrs))
    out.append("</g>")
    return out
