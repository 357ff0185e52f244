"""``verify.png``: the settled re-drapes side by side, coloured by stretch, the body in grey.

Drawn with matplotlib's Agg canvas (imported only here, lazily) as flat triangles sorted
back to front (painter's algorithm) in one orthographic camera shared by every panel, so
the drapes compare at a glance. Identical inputs give identical bytes: the pixels are
written by Pillow with no time or software metadata.
"""

from __future__ import annotations

import os

import numpy as np

from ptailor import tolerances as tol
from ptailor.geometry.triangles import triangle_normals
from ptailor.model.frame import Frame

__all__ = ["STRETCH_RANGE", "TITLES", "bisect_long", "camera", "verify_png"]

#: Panel titles by re-drape.
TITLES: dict[str, str] = {
    "ours": "ours",
    "baseline": "uniform baseline",
    "original": "original pattern",
}
#: Colour range of the largest principal stretch (diverging, centred on 1).
STRETCH_RANGE: tuple[float, float, float] = (0.8, 1.0, 1.25)
_CMAP = "RdYlBu_r"
_BODY = np.array([0.80, 0.80, 0.80])
_FONT = "DejaVu Sans"


def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def camera(frame: Frame, *, azimuth: float = 30.0, elevation: float = 15.0) -> np.ndarray:
    """An orthographic camera looking at the wearer's front from a little to the side and above.

    Parameters
    ----------
    frame : Frame
        The wearer's axes.
    azimuth, elevation : float
        Degrees: turned from ``front`` towards the wearer's left (``up x front``), then up.

    Returns
    -------
    (3, 3) float array
        Rows: screen right, screen up, towards the viewer (depth).

    Examples
    --------
    >>> camera(Frame((0, 1, 0), (0, 0, 1)), azimuth=0, elevation=0).round(6)
    array([[1., 0., 0.],
           [0., 1., 0.],
           [0., 0., 1.]])
    """
    side, u, f = frame.matrix()
    a, e = np.radians(azimuth), np.radians(elevation)
    eye = np.cos(e) * (np.cos(a) * f + np.sin(a) * side) + np.sin(e) * u
    right = _unit(np.cross(u, eye))
    return np.stack([right, np.cross(eye, right), eye])


def _shade(V: np.ndarray, F: np.ndarray, eye: np.ndarray) -> np.ndarray:
    """Soft two-sided Lambert factors in [0.75, 1] per triangle (m,)."""
    n = triangle_normals(V, F)
    return 0.75 + 0.25 * np.abs(n @ eye)


def bisect_long(T: np.ndarray, size: float, *, levels: int = 12) -> np.ndarray:
    """Split triangles across their longest edge until every edge is at most ``size``.

    Parameters
    ----------
    T : (k, 3, 3) float array
        A triangle soup.
    size : float
    levels : int
        At most this many rounds of bisection.

    Returns
    -------
    (k', 3, 3) float array
        The same surface in triangles short enough to sort by depth against the garment's.

    Examples
    --------
    >>> T = np.array([[[0.0, 0, 0], [4, 0, 0], [0, 1, 0]]])
    >>> S = bisect_long(T, 1.5)
    >>> len(S), bool(np.linalg.norm(S - S[:, [1, 2, 0]], axis=2).max() <= 1.5)
    (9, True)
    """
    for _ in range(levels):
        e = np.linalg.norm(T[:, [1, 2, 0]] - T, axis=2)  # edge k: corner k to k + 1
        k = np.argmax(e, axis=1)
        long = e[np.arange(len(T)), k] > size
        if not np.any(long):
            break
        L = T[long]
        r = np.arange(len(L))
        a, b, c = L[r, k[long]], L[r, (k[long] + 1) % 3], L[r, (k[long] + 2) % 3]
        mid = 0.5 * (a + b)
        halves = np.concatenate([np.stack([a, mid, c], 1), np.stack([mid, b, c], 1)])
        T = np.concatenate([T[~long], halves])
    return T


def _scene(V, F, rgb, body, cam):
    """Screen triangles (k, 3, 2) and colours (k, 3) of a drape and the body, back to front."""
    tris = [V[F] @ cam.T]
    cols = [rgb * _shade(V, F, cam[2])[:, None]]
    if body is not None:
        Vb, Fb = body
        edge = float(np.median(np.linalg.norm(V[F[:, 1]] - V[F[:, 0]], axis=1)))
        T = bisect_long(Vb[Fb], 2.0 * edge)
        n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
        lam = np.abs(n @ cam[2]) / np.maximum(np.linalg.norm(n, axis=1), tol.TINY)
        # cloth lying on the body sorts in front of it: the body one edge further back
        tris.append(T @ cam.T - [0.0, 0.0, edge])
        cols.append(_BODY[None, :] * (0.75 + 0.25 * lam)[:, None])
    t = np.concatenate(tris)
    c = np.concatenate(cols)
    order = np.argsort(t[:, :, 2].mean(axis=1), kind="stable")
    return t[order, :, :2], np.clip(c[order], 0.0, 1.0)


def verify_png(
    path: str | os.PathLike,
    drapes: dict[str, np.ndarray],
    F3: np.ndarray,
    stretch: dict[str, np.ndarray],
    *,
    body: tuple[np.ndarray, np.ndarray] | None = None,
    frame: Frame,
    captions: dict[str, str] | None = None,
    height: int = 900,
    dpi: int = 100,
) -> None:
    """Write the re-drapes side by side, coloured by their largest principal stretch.

    Parameters
    ----------
    path : str or os.PathLike
        The PNG to write.
    drapes : dict of str to (n, 3) float array
        Settled drapes by re-drape (``"ours"``, ``"baseline"``, ``"original"``: titled from
        :data:`TITLES`, any other name as itself), drawn left to right in the dict's order.
    F3 : (m, 3) int array
    stretch : dict of str to (m, 2) float array
        Principal stretches of each drape (:func:`ptailor.verify.measure.principal_stretches`);
        the largest colours each triangle on a diverging map over :data:`STRETCH_RANGE`
        (blue compressed, yellow at rest, red stretched; nan in grey).
    body : (V (nb, 3), F (mb, 3)), optional
        Drawn in light grey, in every panel.
    frame : Frame
        The drapes' wearer's axes: one camera for every panel, from the front, a little to
        the side and above.
    captions : dict of str to str, optional
        A line under each title (the report's worst panel, say); by default the 95th
        percentile of the largest stretch over all triangles.
    height, dpi : int
        Image height in pixels and the resolution written in the file.
    """
    from matplotlib import colormaps
    from matplotlib.colors import TwoSlopeNorm
    from matplotlib.figure import Figure

    F3 = np.asarray(F3)
    cam = camera(frame)
    body = None if body is None else (np.asarray(body[0], float), np.asarray(body[1]))
    norm = TwoSlopeNorm(vmin=STRETCH_RANGE[0], vcenter=STRETCH_RANGE[1], vmax=STRETCH_RANGE[2])
    cmap = colormaps[_CMAP].with_extremes(bad=(0.5, 0.5, 0.5))
    scenes = []
    for name, V in drapes.items():
        smax = np.asarray(stretch[name], dtype=float)[:, 0]
        rgb = cmap(norm(np.ma.masked_invalid(smax)))[:, :3]
        scenes.append((name, smax, *_scene(np.asarray(V, float), F3, rgb, body, cam)))
    lo, hi = _view_box(drapes, F3, cam)
    k = max(len(scenes), 1)
    aspect = (hi[0] - lo[0]) / (hi[1] - lo[1])
    h_in = height / dpi
    w_panel = max(h_in * 0.8 * aspect, 2.2)
    fig = Figure(figsize=(k * w_panel + 1.3, h_in), dpi=dpi, facecolor="white")
    w = w_panel / (k * w_panel + 1.3)
    for i, (name, smax, tris, cols) in enumerate(scenes):
        p95 = np.nanpercentile(smax, 95) if np.any(np.isfinite(smax)) else float("nan")
        caption = (captions or {}).get(name, f"stretch p95 {p95:.3f}")
        _draw_panel(fig, i, w, (lo, hi), tris, cols, TITLES.get(name, name), caption)
    _colour_bar(fig, k * w, norm, cmap)
    _write_png(fig, path)


def _view_box(drapes: dict[str, np.ndarray], F3: np.ndarray, cam: np.ndarray):
    """The screen box ``(lo (2,), hi (2,))`` every panel shows: all drapes' used vertices,
    padded by 6 % of its larger side."""
    used = np.unique(F3)  # unreferenced vertices are not drawn
    pts = np.concatenate([np.asarray(V, float)[used] @ cam[:2].T for V in drapes.values()])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = 0.06 * float((hi - lo).max())
    return lo - pad, hi + pad


def _draw_panel(fig, i: int, w: float, box, tris, cols, title: str, caption: str) -> None:
    """Panel ``i`` (``w`` the figure's width fraction of a panel): the triangles ``tris``
    (k, 3, 2) coloured ``cols`` (k, 3) over the screen ``box``, the title and caption above."""
    from matplotlib.collections import PolyCollection

    lo, hi = box
    text = {"fontfamily": _FONT, "color": "black"}
    ax = fig.add_axes((i * w, 0.02, w, 0.80))
    ax.set_axis_off()
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal", adjustable="box")
    ax.add_collection(
        PolyCollection(tris, facecolors=cols, edgecolors=cols, linewidths=0.3),
        autolim=False,
    )
    fig.text((i + 0.5) * w, 0.955, title, ha="center", va="center",
             fontsize=15, fontweight="bold", **text)  # fmt: skip
    fig.text((i + 0.5) * w, 0.93, caption, ha="center", va="top",
             fontsize=11, **text)  # fmt: skip


def _colour_bar(fig, used: float, norm, cmap) -> None:
    """The stretch colour bar, in the figure's width right of the panels (``used`` of it)."""
    from matplotlib.cm import ScalarMappable

    cax = fig.add_axes((used + 0.15 * (1 - used), 0.12, 0.22 * (1 - used), 0.72))
    bar = fig.colorbar(ScalarMappable(norm=norm, cmap=cmap), cax=cax, extend="both")
    bar.set_label("max principal stretch", fontsize=11, fontfamily=_FONT)
    bar.set_ticks([0.8, 0.9, 1.0, 1.1, 1.2])


def _write_png(fig, path: str | os.PathLike) -> None:
    """Draw ``fig`` on the Agg canvas and write its pixels with Pillow (no metadata)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from PIL import Image

    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    rgb = np.asarray(canvas.buffer_rgba())[:, :, :3].copy()
    Image.fromarray(rgb, "RGB").save(os.fspath(path), format="PNG", optimize=False)
