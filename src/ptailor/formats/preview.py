"""What the pattern previews (``pattern.svg``, ``preview.png``) share.

The sheet layout (where each panel, its name, the title, the scale bar and the legends go),
the colour scale of the intrinsic-scale error and the checking of the inputs. Everything here
is in *sheet coordinates*: pattern units (times ``Sheet.zoom``, 1 unless the SVG rescales),
origin at the sheet's top-left corner, y down (as in SVG); a panel's pattern coordinates ``P``
(y up) map to ``zoom * P * (1, -1) + sheet.offsets[p]`` (:meth:`Sheet.to_sheet`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ptailor.errors import PtailorError

#: Colours of the outlines and text.
BEFORE = "#5c5c5c"  # the original outline, dashed
FRAME = "#8a8a8a"  # legend boxes
AFTER = "#1f4e79"  # the adjusted outline, solid
FILL = "#dce8f4"  # the adjusted panel when no error is shown
INK = "#222222"  # text, scale bar

#: Upper edges of the error bins (relative error, ``0.01`` = 1 %); the last bin is open.
ERROR_EDGES: tuple[float, ...] = (0.005, 0.01, 0.02, 0.05, 0.10)
#: One colour per bin, pale to dark: ColorBrewer YlOrRd, 6 classes (sequential, colour-blind
#: safe, print friendly).
ERROR_COLOURS: tuple[str, ...] = ("#ffffb2", "#fed976", "#feb24c", "#fd8d3c", "#f03b20", "#bd0026")
#: The bins' ranges as shown in the legend.
ERROR_LABELS: tuple[str, ...] = ("< 0.5 %", "0.5–1 %", "1–2 %", "2–5 %", "5–10 %", "≥ 10 %")
#: Triangles whose error is NaN (unknown).
NAN_BIN = len(ERROR_COLOURS)
NAN_COLOUR = "#a6a6a6"
NAN_LABEL = "unknown"
#: Title of the error legend.
ERROR_TITLE = "intrinsic-scale error:"

#: Length of the scale bar per unit: 10 cm in every physical unit (4 in for inches).
_BAR = {"mm": 100.0, "cm": 10.0, "m": 0.1, "in": 4.0}
#: Estimated advance of one character, in font sizes (a little wide, to be safe).
_CHAR = 0.62


def error_bins(errors: np.ndarray) -> np.ndarray:
    """The bin of each error.

    Parameters
    ----------
    errors : (m,) float array
        Relative errors; the sign is ignored (``-0.03`` is a 3 % error).

    Returns
    -------
    (m,) int64 array
        ``k`` for ``ERROR_EDGES[k-1] <= |e| < ERROR_EDGES[k]`` (``0 .. len(ERROR_EDGES)``;
        an error on an edge goes to the upper bin: 2 % is in "2–5 %"), ``NAN_BIN`` for NaN.
        Infinite errors fall in the last bin.
    """
    e = np.abs(np.asarray(errors, dtype=np.float64))
    b = np.searchsorted(np.asarray(ERROR_EDGES), e, side="right").astype(np.int64)
    b[np.isnan(e)] = NAN_BIN
    return b


def bin_colour(b: int) -> str:
    """The colour of bin ``b`` (``NAN_BIN`` included)."""
    return NAN_COLOUR if b == NAN_BIN else ERROR_COLOURS[b]


def bin_label(b: int) -> str:
    """The legend text of bin ``b`` (``NAN_BIN`` included)."""
    return NAN_LABEL if b == NAN_BIN else ERROR_LABELS[b]


@dataclass(frozen=True)
class Pattern:
    """Checked inputs of a preview (float64 / int64 arrays; the caller's arrays untouched).

    Attributes
    ----------
    before, after : list (per panel) of list of (k, 2) float arrays
        The outlines in pattern coordinates.
    names : list of str
    triangles : list (per panel) of ((n, 2) float array, (m, 3) int array) or None
        The adjusted pattern's vertices and triangles, every triangle counter-clockwise
        (pattern coordinates, y up) so that a bin's triangles fill their union under the
        non-zero rule.
    bins : list (per panel) of (m,) int arrays or None
        Each triangle's error bin (see :func:`error_bins`).
    """

    before: list[list[np.ndarray]]
    after: list[list[np.ndarray]]
    names: list[str]
    triangles: list[tuple[np.ndarray, np.ndarray]] | None
    bins: list[np.ndarray] | None

    @property
    def used_bins(self) -> list[int]:
        """The bins with at least one triangle, ascending (``NAN_BIN`` last)."""
        if self.bins is None or not self.bins:
            return []
        return np.unique(np.concatenate(self.bins)).tolist()


class NonFiniteOutputError(PtailorError, ValueError):
    """NaN or infinity in what a preview would draw: the run fails (exit 2), nothing is
    written (a ``ValueError`` too, as the other input errors of the previews)."""


def _loops(loops, what: str, p: int) -> list[np.ndarray]:
    out = []
    for j, L in enumerate(loops):
        A = np.asarray(L, dtype=np.float64)
        if A.ndim != 2 or A.shape[1] != 2 or len(A) < 2:
            raise ValueError(f"{what}[{p}][{j}]: expected a (k, 2) array with k >= 2")
        if not np.all(np.isfinite(A)):
            raise NonFiniteOutputError(
                f"pattern preview: non-finite coordinates in {what}[{p}][{j}] (nothing written)"
            )
        out.append(A)
    return out


def _mesh(tri, err, p: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    try:
        V, F = tri
    except (TypeError, ValueError):
        raise ValueError(f"triangles[{p}]: expected a (V, F) pair") from None
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F)
    if F.size == 0:
        F = np.zeros((0, 3), dtype=np.int64)
    if V.ndim != 2 or V.shape[1] != 2:
        raise ValueError(f"triangles[{p}]: V must be an (n, 2) array, got shape {V.shape}")
    if F.ndim != 2 or F.shape[1] != 3 or F.dtype.kind not in "iu":
        raise ValueError(f"triangles[{p}]: F must be an (m, 3) integer array")
    F = F.astype(np.int64)
    if len(F) and (F.min() < 0 or F.max() >= len(V)):
        raise ValueError(f"triangles[{p}]: F indexes outside V (n = {len(V)})")
    if len(F) and not np.all(np.isfinite(V[F])):
        raise NonFiniteOutputError(
            f"pattern preview: non-finite vertices in triangles[{p}] (nothing written)"
        )
    E = np.asarray(err, dtype=np.float64)
    if E.shape != (len(F),):
        raise ValueError(f"errors[{p}]: expected shape ({len(F)},), got {E.shape}")
    # counter-clockwise, so that overlapping (flipped) triangles add up rather than cancel
    T = V[F]
    cross = (T[:, 1, 0] - T[:, 0, 0]) * (T[:, 2, 1] - T[:, 0, 1]) - (T[:, 1, 1] - T[:, 0, 1]) * (
        T[:, 2, 0] - T[:, 0, 0]
    )
    F = np.where((cross < 0)[:, None], F[:, [0, 2, 1]], F)
    return V, F, error_bins(E)


def check_inputs(
    outlines_before,
    outlines_after,
    names,
    triangles=None,
    errors=None,
    *,
    caller: str = "preview",
) -> Pattern:
    """Check and convert a preview's inputs.

    Parameters
    ----------
    outlines_before, outlines_after : list (per panel) of list of (k, 2) array-likes
    names : list of str
    triangles : list (per panel) of (V (n, 2), F (m, 3)) or None
    errors : list (per panel) of (m,) array-likes or None
        Given together with ``triangles`` or not at all.
    caller : str
        Prefix of the length-mismatch messages.

    Returns
    -------
    Pattern

    Raises
    ------
    ValueError
        When the lists differ in length, only one of ``triangles`` / ``errors`` is given, a
        loop is not a finite ``(k, 2)`` array, ``F`` is not an integer ``(m, 3)`` array
        indexing ``V``, or an error array is not ``(m,)``.
    """
    n = len(names)
    if len(outlines_before) != n or len(outlines_after) != n:
        raise ValueError(
            f"{caller}: {len(outlines_before)} 'before' panels, {len(outlines_after)} "
            f"'after' panels and {n} names"
        )
    if (triangles is None) != (errors is None):
        raise ValueError(f"{caller}: give both triangles and errors, or neither")
    if triangles is not None and (len(triangles) != n or len(errors) != n):
        raise ValueError(
            f"{caller}: {len(triangles)} triangle meshes, {len(errors)} error arrays and {n} names"
        )
    before = [_loops(ls, "outlines_before", p) for p, ls in enumerate(outlines_before)]
    after = [_loops(ls, "outlines_after", p) for p, ls in enumerate(outlines_after)]
    tris = bins = None
    if triangles is not None:
        meshes = [_mesh(t, e, p) for p, (t, e) in enumerate(zip(triangles, errors, strict=True))]
        tris = [(V, F) for V, F, _ in meshes]
        bins = [b for _, _, b in meshes]
    return Pattern(before, after, [_short(str(s)) for s in names], tris, bins)


def _short(name: str) -> str:
    """A panel name as drawn: at most ``PREVIEW_NAME_MAX`` characters (an ellipsis ends a
    shortened one), so that a long name cannot blow up the text layout."""
    from ptailor import tolerances as tol

    k = tol.PREVIEW_NAME_MAX
    return name if len(name) <= k else name[: k - 1] + "\u2026"


def nice(x: float) -> float:
    """The largest 1, 2 or 5 times a power of ten not above ``x`` (``x > 0``)."""
    e = math.floor(math.log10(x))
    for m in (5.0, 2.0, 1.0):
        if m * 10.0**e <= x:
            return m * 10.0**e
    return 10.0**e


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
        origin, width, height = _shelves(cell_w, cell_h, gap, t + 1e-9)
        sw, sh = (width, height) if sheet_size is None else sheet_size(width, height)
        sheet = max(sw / math.sqrt(2.0), sh)
        if best is None or sheet < best[0] - 1e-9:
            best = (sheet, origin, width, height)
    return best[1], best[2], best[3]


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
            pts = [*pts, V[F].reshape(-1, 2)]
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

    def footer(grid_w: float, y: float):
        """The footer under a grid ``grid_w`` wide, from height ``y`` down."""
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
        foot_w = x - 1.5 * font - gap
        y += 2.6 * font

        # the error legend: its title, then the bins as a row of touching boxes (an ordered
        # scale) with each range centred under its box; the title goes on a row of its own
        # when both do not fit the width of what is above
        error_title_xy = None
        swatches: list[Swatch] = []
        if pattern.triangles is not None:
            avail = max(grid_w, foot_w, title_w)
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
            foot_w = max(foot_w, x, head_w)
            y += bh + 1.6 * font
        return (
            {
                "bar": bar,
                "bar_label": bar_label,
                "bar_xy": (bx, by),
                "bar_label_xy": bar_label_xy,
                "lines": tuple(lines),
                "error_title_xy": error_title_xy,
                "swatches": tuple(swatches),
            },
            foot_w,
            y,
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
