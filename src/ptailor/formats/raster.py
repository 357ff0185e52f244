"""Rasterising what ``preview.png`` draws, with numpy and Pillow: filled triangles (one
label per pixel, no Python loop over triangles), even-odd fills, dashed polylines, fonts.

Pixel ``(i, j)`` (row, column) covers ``[j, j + 1) x [i, i + 1)``; a fill takes the pixels
whose centre ``(j + 0.5, i + 0.5)`` lies inside (top-left rule: a pixel centre on a shared
edge goes to exactly one side), so triangles that tile a panel fill it without gaps or
double coverage. Antialiasing is the caller's: draw ``k`` times larger, then downsample.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import numpy as np

#: DejaVu Sans (regular and bold), the glyphs matplotlib bundles, subset to Latin (U+0020-
#: U+024F), Greek, Cyrillic, general punctuation, currency, arrows, mathematical operators and
#: geometric shapes (215 KB together); unhinted (the preview is drawn supersampled). Licence:
#: ``fonts/LICENSE_DEJAVU``.
FONT_DIR = Path(__file__).resolve().parent / "fonts"


@lru_cache(maxsize=16)
def font(size: int, *, bold: bool = False):
    """The preview's font at ``size`` pixels (em), as a Pillow ``FreeTypeFont``."""
    from PIL import ImageFont

    name = "DejaVuSans-Bold.ttf" if bold else "DejaVuSans.ttf"
    return ImageFont.truetype(str(FONT_DIR / name), max(1, int(size)))


def _crossings(A: np.ndarray, B: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Where edges ``A -> B`` cross the pixel rows' centres.

    Parameters
    ----------
    A, B : (e, 2) float arrays
        Edge ends, pixel coordinates (x right, y down).

    Returns
    -------
    edge : (c,) int array
        The edge of each crossing.
    row : (c,) int array
        The pixel row whose centre ``y = row + 0.5`` the edge crosses (``y0 <= y < y1``).
    col : (c,) int array
        The first column whose centre is right of (or on) the crossing:
        ``ceil(x - 0.5)``.

    Notes
    -----
    An edge and its reverse give the same crossings (the ends are ordered by ``y``, then
    ``x``, before anything is computed), so two triangles sharing an edge agree exactly.
    """
    swap = (A[:, 1] > B[:, 1]) | ((A[:, 1] == B[:, 1]) & (A[:, 0] > B[:, 0]))
    P = np.where(swap[:, None], B, A)
    Q = np.where(swap[:, None], A, B)
    r0 = np.ceil(P[:, 1] - 0.5).astype(np.int64)
    r1 = np.ceil(Q[:, 1] - 0.5).astype(np.int64)  # rows r0 .. r1 - 1
    n = np.maximum(r1 - r0, 0)
    edge = np.repeat(np.arange(len(A)), n)
    start = np.cumsum(n) - n
    row = r0[edge] + (np.arange(len(edge)) - start[edge])
    dy = (Q[:, 1] - P[:, 1])[edge]
    t = (row + 0.5 - P[edge, 1]) / np.where(dy > 0, dy, 1.0)
    x = P[edge, 0] + t * (Q[edge, 0] - P[edge, 0])
    col = np.ceil(x - 0.5).astype(np.int64)
    return edge, row, col


def _accumulate(shape, row, col, weights) -> np.ndarray:
    """Running sum along each row of ``weights`` dropped at ``(row, col)`` (clipped), modulo
    256: exact for sums in ``0 .. 255`` (uint8, a quarter of the memory traffic of int32)."""
    h, w = shape
    keep = (row >= 0) & (row < h)
    row, col = row[keep], np.clip(col[keep], 0, w)
    diff = np.zeros((h, w + 1), dtype=np.uint8)
    np.add.at(diff.reshape(-1), row * (w + 1) + col, np.asarray(weights)[keep].astype(np.uint8))
    return np.cumsum(diff[:, :w], axis=1, dtype=np.uint8)


def _triangle_crossings(T: np.ndarray, labels: np.ndarray):
    """Crossings (row, col) of the triangles' edges with their weights ``+-label``."""
    A = T.reshape(-1, 2)
    B = T[:, [1, 2, 0]].reshape(-1, 2)
    edge, row, col = _crossings(A, B)
    # a triangle of positive signed area (x, y as numbers) has its inside left of each
    # edge: an edge going to larger y is its right side (the row leaves), else its left
    down = (B[:, 1] > A[:, 1])[edge]
    D1, D2 = T[:, 1] - T[:, 0], T[:, 2] - T[:, 0]
    area = D1[:, 0] * D2[:, 1] - D1[:, 1] * D2[:, 0]
    sign = np.where(down, 1, -1) * np.where(area[edge // 3] >= 0, -1, 1)
    w = (sign * np.repeat(np.asarray(labels, dtype=np.int64), 3)[edge]) % 256
    return row, col, w


def _loop_crossings(loops: list[np.ndarray]):
    """Crossings (row, col) of closed loops' edges."""
    if not loops:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    A = np.concatenate(loops)
    B = np.concatenate([np.roll(L, -1, axis=0) for L in loops])
    _, row, col = _crossings(A, B)
    return row, col


def triangle_labels(shape: tuple[int, int], T: np.ndarray, labels: np.ndarray) -> np.ndarray:
    """Each pixel's label: that of the triangle covering its centre, 0 where none does.

    Parameters
    ----------
    shape : (int, int)
        Rows and columns of the result.
    T : (m, 3, 2) float array
        Triangles in pixel coordinates, either orientation (a tiling: no two overlap).
    labels : (m,) int array
        Labels, 1 to 255.

    Returns
    -------
    (rows, cols) uint8 array

    Notes
    -----
    Non-zero winding weighted by label: each edge drops ``+label`` where a row enters its
    triangle and ``-label`` where it leaves, and a running sum along the row gives the
    label of the triangle each pixel lies in (across an edge shared by triangles labelled
    ``a`` and ``b`` the sum steps from ``a`` to ``b``). Overlapping triangles add up: their
    common pixels get the sum of the labels (modulo 256), which the caller clips.
    """
    if len(T) == 0:
        return np.zeros(shape, dtype=np.uint8)
    return _accumulate(shape, *_triangle_crossings(T, labels))


def evenodd_mask(shape: tuple[int, int], loops: list[np.ndarray]) -> np.ndarray:
    """The pixels inside ``loops`` by the even-odd rule.

    Parameters
    ----------
    shape : (int, int)
    loops : list of (k, 2) float arrays
        Closed implicitly, pixel coordinates.

    Returns
    -------
    (rows, cols) bool array
    """
    row, col = _loop_crossings(loops)
    return (_accumulate(shape, row, col, np.ones(len(row), dtype=np.uint8)) & 1).astype(bool)


def labels_inside(
    shape: tuple[int, int], loops: list[np.ndarray], T: np.ndarray, labels: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`evenodd_mask` of ``loops`` and :func:`triangle_labels` of ``T`` in one pass.

    The loops' crossings weigh 128 (modulo 256 the sum's top bit is the even-odd parity),
    the triangles' their labels, which must then stay below 128 (overlaps included).

    Returns
    -------
    inside : (rows, cols) bool array
    labels : (rows, cols) uint8 array
    """
    r1, c1 = _loop_crossings(loops)
    if len(T):
        r2, c2, w2 = _triangle_crossings(T, labels)
    else:
        r2 = c2 = w2 = np.zeros(0, dtype=np.int64)
    w = np.concatenate([np.full(len(r1), 128, dtype=np.int64), w2])
    acc = _accumulate(shape, np.concatenate([r1, r2]), np.concatenate([c1, c2]), w)
    return (acc & 128).astype(bool), acc & 127


def dashes(P: np.ndarray, on: float, off: float) -> list[np.ndarray]:
    """The "on" pieces of a dash pattern along a polyline, starting "on" at its first point.

    Parameters
    ----------
    P : (k, 2) float array
        The polyline (repeat the first point to close it).
    on, off : float
        Dash and gap lengths, > 0.

    Returns
    -------
    list of (j, 2) float arrays
        Each dash as a polyline through the corners it turns.
    """
    ln = np.hypot(*np.diff(P, axis=0).T)
    s = np.concatenate([[0.0], np.cumsum(ln)])
    total = float(s[-1])
    if total <= 0.0:
        return []
    starts = np.arange(0.0, total, on + off)
    ends = np.minimum(starts + on, total)
    knots = np.unique(np.concatenate([s, starts, ends]))
    pts = np.c_[np.interp(knots, s, P[:, 0]), np.interp(knots, s, P[:, 1])]
    i0 = np.searchsorted(knots, starts)
    i1 = np.searchsorted(knots, ends)
    return [pts[a : b + 1] for a, b in zip(i0.tolist(), i1.tolist(), strict=True) if b > a]


def box_pixels(lo: np.ndarray, hi: np.ndarray, shape: tuple[int, int]):
    """The pixels whose centres lie in each box (clipped to the picture).

    Parameters
    ----------
    lo, hi : (m, 2) float arrays
        Boxes' corners, pixel coordinates (x, y).
    shape : (int, int)
        Rows and columns of the picture.

    Returns
    -------
    owner : (s,) int array
        The box of each pixel (a pixel in two boxes comes twice).
    i, j : (s,) int arrays
        Its row and column.
    """
    h, w = shape
    a = np.clip(np.ceil(np.asarray(lo) - 0.5), 0, [w, h]).astype(np.int64)
    b = np.clip(np.floor(np.asarray(hi) - 0.5), -1, [w - 1, h - 1]).astype(np.int64)
    nx = np.maximum(b[:, 0] - a[:, 0] + 1, 0)
    ny = np.maximum(b[:, 1] - a[:, 1] + 1, 0)
    count = nx * ny
    owner = np.repeat(np.arange(len(a)), count)
    k = np.arange(len(owner)) - np.repeat(np.cumsum(count) - count, count)
    step = np.maximum(nx[owner], 1)
    return owner, a[owner, 1] + k // step, a[owner, 0] + k % step


def segments_mask(shape: tuple[int, int], A: np.ndarray, B: np.ndarray, width: float):
    """The pixels a stroke of segments covers (round caps): centres within ``width / 2`` of
    a segment.

    Parameters
    ----------
    shape : (int, int)
    A, B : (k, 2) float arrays
        Segment ends, pixel coordinates.
    width : float
        In pixels.

    Returns
    -------
    (rows, cols) bool array
    """
    A, B = np.asarray(A, dtype=np.float64), np.asarray(B, dtype=np.float64)
    out = np.zeros(shape, dtype=bool)
    if len(A) == 0:
        return out
    r = 0.5 * width
    owner, i, j = box_pixels(np.minimum(A, B) - r, np.maximum(A, B) + r, shape)
    q = np.stack([j, i], axis=1) + 0.5 - A[owner]
    d = (B - A)[owner]
    t = np.clip((q * d).sum(axis=1) / np.maximum((d * d).sum(axis=1), 1e-12), 0.0, 1.0)
    near = np.hypot(*(q - t[:, None] * d).T) <= r
    out[i[near], j[near]] = True
    return out
