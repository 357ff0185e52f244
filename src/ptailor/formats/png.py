"""PNG preview of a pattern: the sheet of ``pattern.svg`` rendered with matplotlib (Agg)."""

from __future__ import annotations

import os

import numpy as np

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
from ptailor.formats.sheet import Sheet, preview_sheet

#: matplotlib's bundled font: the same glyphs on every machine.
_FONT = "DejaVu Sans"
#: Path codes of one closed triangle.
_TRI_CODES = np.array([1, 2, 2, 79], dtype=np.uint8)  # MOVETO, LINETO, LINETO, CLOSEPOLY


def _signed_area(L: np.ndarray) -> float:
    x, y = L[:, 0], L[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _evenodd(loops: list[np.ndarray]):
    """One path filling ``loops`` by the even-odd rule under Agg's non-zero rule.

    Each loop is turned counter-clockwise when it lies inside an even number of the others,
    clockwise when odd (holes), so the non-zero fill equals the even-odd one for
    non-crossing loops.
    """
    from matplotlib.path import Path

    paths = [Path(L) for L in loops]
    verts, codes = [], []
    for i, L in enumerate(loops):
        depth = sum(paths[j].contains_point(tuple(L[0])) for j in range(len(loops)) if j != i)
        ccw = _signed_area(L) >= 0
        if ccw == (depth % 2 == 1):
            L = L[::-1]
        verts.append(np.vstack([L, L[:1]]))
        codes.append(np.r_[1, np.full(len(L) - 1, 2), 79].astype(np.uint8))
    return Path(np.concatenate(verts), np.concatenate(codes))


def _closed(L: np.ndarray) -> np.ndarray:
    return np.vstack([L, L[:1]])


def _fills(pat: Pattern, s: Sheet) -> tuple[list, list[str]]:
    """The fills: per (panel, bin) one compound path of closed triangles, or the adjusted
    outline's even-odd fill where a panel has no triangles; and each path's colour."""
    from matplotlib.path import Path

    paths, colours = [], []
    for p in range(len(pat.names)):
        if pat.triangles is not None and len(pat.triangles[p][1]):
            V, F = pat.triangles[p]
            T = s.to_sheet(V, p)[F]  # (m, 3, 2)
            b = pat.bins[p]
            for bb in np.unique(b).tolist():
                sel = T[b == bb]
                verts = np.concatenate([sel, sel[:, :1]], axis=1).reshape(-1, 2)
                paths.append(Path(verts, np.tile(_TRI_CODES, len(sel))))
                colours.append(bin_colour(bb))
        elif pat.after[p]:
            paths.append(_evenodd([s.to_sheet(L, p) for L in pat.after[p]]))
            colours.append(FILL)
    return paths, colours


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
        Resolution written in the file (and the points-to-pixels factor of matplotlib);
        does not change the pixel size.

    Returns
    -------
    (int, int)
        The image's width and height in pixels.

    Raises
    ------
    ValueError
        As :func:`ptailor.formats.preview.check_inputs`, or when ``size`` < 16 or
        ``dpi`` <= 0.

    Notes
    -----
    Each bin's triangles of a panel are one compound path (one fill, no hairline seams
    between triangles of a bin) and the whole pattern one ``PathCollection``: no Python
    loop over triangles. Identical inputs give identical bytes (RGB written by Pillow with no
    software/time metadata, matplotlib's bundled font, everything set explicitly on the
    artists).
    """
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.collections import LineCollection, PathCollection
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle
    from PIL import Image

    if int(size) < 16:
        raise ValueError(f"pattern_png: size must be at least 16 pixels, got {size}")
    if not dpi > 0:
        raise ValueError(f"pattern_png: dpi must be positive, got {dpi}")
    pat, s = preview_sheet(
        outlines_before, outlines_after, names, triangles, errors,
        units=units, title=title, caller="pattern_png",
    )  # fmt: skip
    n = len(pat.names)

    scale = int(size) / max(s.width, s.height)  # pixels per pattern unit
    pw = max(1, round(s.width * scale))
    ph = max(1, round(s.height * scale))
    pt = scale * 72.0 / dpi  # points per pattern unit
    fig = Figure(figsize=(pw / dpi, ph / dpi), dpi=dpi, facecolor="white")
    ax = fig.add_axes((0.0, 0.0, 1.0, 1.0))
    ax.set_axis_off()
    ax.set_xlim(0.0, pw / scale)
    ax.set_ylim(ph / scale, 0.0)  # y down, as the sheet

    # outlines at least 1.5 / 2 pixels wide: the sheet's widths suit print at 1:1, not a
    # whole pattern on 1800 pixels
    lw_before = max(s.stroke_before * scale, 1.5) * 72.0 / dpi
    lw_after = max(s.stroke_after * scale, 2.0) * 72.0 / dpi
    k = lw_before if matplotlib.rcParams["lines.scale_dashes"] else 1.0
    dashes = (0.0, (s.dash[0] * pt / k, s.dash[1] * pt / k))
    text = {"fontfamily": _FONT, "color": INK, "fontsize": s.font * pt}

    paths, colours = _fills(pat, s)
    if paths:
        ax.add_collection(
            PathCollection(paths, facecolors=colours, edgecolors="none", linewidths=0.0, zorder=1),
            autolim=False,
        )

    before = [_closed(s.to_sheet(L, p)) for p in range(n) for L in pat.before[p]]
    after = [_closed(s.to_sheet(L, p)) for p in range(n) for L in pat.after[p]]
    ax.add_collection(
        LineCollection(
            before, colors=BEFORE, linewidths=lw_before, linestyles=[dashes],
            joinstyle="round", capstyle="butt", zorder=2,
        ),
        autolim=False,
    )  # fmt: skip
    ax.add_collection(
        LineCollection(after, colors=AFTER, linewidths=lw_after, joinstyle="round", zorder=3),
        autolim=False,
    )
    for p in range(n):
        x, y = s.labels[p]
        ax.text(x, y, pat.names[p], ha="center", va="baseline", zorder=4, **text)
    if s.title:
        ax.text(
            *s.title_xy, s.title, ha="left", va="baseline", fontweight="bold", zorder=4,
            **{**text, "fontsize": s.title_size * pt},
        )  # fmt: skip

    # scale bar with ticks every tenth, longer every fifth
    bx, by = s.bar_xy
    ticks = bx + s.bar * np.arange(11) / 10.0
    tick_len = np.where(np.arange(11) % 5 == 0, 1.0, 0.5) * s.bar_tick
    segs = [np.array([[bx, by], [bx + s.bar, by]])] + [
        np.array([[t, by], [t, by + h]]) for t, h in zip(ticks, tick_len, strict=True)
    ]
    ax.add_collection(
        LineCollection(segs, colors=INK, linewidths=lw_after, capstyle="butt", zorder=4),
        autolim=False,
    )
    ax.text(*s.bar_label_xy, s.bar_label, ha="left", va="baseline", zorder=4, **text)

    # legends
    for ls in s.lines:
        seg = [np.array([[ls.x0, ls.y], [ls.x1, ls.y]])]
        style = (
            {"colors": BEFORE, "linewidths": lw_before, "linestyles": [dashes]}
            if ls.kind == "before"
            else {"colors": AFTER, "linewidths": lw_after}
        )
        ax.add_collection(LineCollection(seg, capstyle="butt", zorder=4, **style), autolim=False)
        ax.text(*ls.text_xy, ls.label, ha="left", va="baseline", zorder=4, **text)
    if s.error_title_xy is not None:
        ax.text(*s.error_title_xy, ERROR_TITLE, ha="left", va="baseline", zorder=4, **text)
    for sw in s.swatches:
        ax.add_artist(
            Rectangle(
                (sw.x, sw.y), sw.w, sw.h, facecolor=sw.colour, edgecolor=FRAME,
                linewidth=lw_before, zorder=4,
            )
        )  # fmt: skip
        ax.text(*sw.text_xy, sw.label, ha="center", va="baseline", zorder=4, **text)

    # encode RGB ourselves (the sheet is opaque): a quarter less to compress than matplotlib's
    # RGBA, and zlib level 3 is twice as fast as the default 6 for a few % more bytes; Pillow
    # writes no time or software chunk, so the bytes depend on the pixels (and dpi) only
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    rgb = np.asarray(canvas.buffer_rgba())[:, :, :3]
    Image.fromarray(np.ascontiguousarray(rgb)).save(
        os.fspath(path), format="png", dpi=(dpi, dpi), compress_level=3
    )
    return pw, ph
