"""The preview's rasteriser: triangle labels, even-odd fills and dashes against brute force."""

from __future__ import annotations

import numpy as np
import pytest

from ptailor.formats.raster import (
    FONT_DIR,
    dashes,
    evenodd_mask,
    font,
    labels_inside,
    triangle_labels,
)


def inside_triangles(shape, T):
    """Brute force: the triangles (index + 1) whose closed inside holds each pixel centre."""
    h, w = shape
    y, x = np.mgrid[0:h, 0:w] + 0.5
    P = np.c_[x.ravel(), y.ravel()]
    hits = np.zeros((len(P), len(T)), dtype=bool)
    for t, (a, b, c) in enumerate(T):  # a loop over a test's few triangles
        d = [
            (q - p)[0] * (P - p)[:, 1] - (q - p)[1] * (P - p)[:, 0]
            for p, q in ((a, b), (b, c), (c, a))
        ]
        hits[:, t] = (np.all(np.array(d) >= 0, axis=0)) | (np.all(np.array(d) <= 0, axis=0))
    return hits.reshape(h, w, len(T))


@pytest.mark.parametrize("seed", range(4))
def test_a_tiling_is_filled_once_everywhere(seed):
    """A jittered triangulated grid: every pixel centre strictly inside the grid takes the
    label of a triangle that holds it; outside, 0. No gaps, no double coverage."""
    rng = np.random.default_rng(seed)
    n = 8
    xs, ys = np.meshgrid(np.linspace(3.2, 52.7, n + 1), np.linspace(2.9, 40.1, n + 1))
    jitter = rng.uniform(-1.5, 1.5, (2, n - 1, n - 1))
    xs[1:-1, 1:-1] += jitter[0]
    ys[1:-1, 1:-1] += jitter[1]
    V = np.c_[xs.ravel(), ys.ravel()]
    i = (np.arange(n)[:, None] * (n + 1) + np.arange(n)[None, :]).ravel()
    F = np.r_[np.c_[i, i + 1, i + n + 2], np.c_[i, i + n + 2, i + n + 1]]
    flip = rng.random(len(F)) < 0.5
    F[flip] = F[flip][:, [0, 2, 1]]  # both orientations
    labels = rng.integers(1, 8, len(F))
    shape = (45, 58)
    got = triangle_labels(shape, V[F], labels)
    hits = inside_triangles(shape, V[F])
    count = hits.sum(axis=2)
    allowed = np.where(hits, labels[None, None, :], 0)
    one = count == 1
    assert np.all(got[one] == allowed[one].max(axis=1))
    shared = count > 1  # centre on an edge: one of its triangles
    assert all(
        got[r, c] in allowed[r, c][hits[r, c]] for r, c in zip(*np.nonzero(shared), strict=True)
    )
    assert np.all(got[count == 0] == 0)


def test_evenodd_mask_with_a_hole():
    outer = np.array([[2.0, 2.0], [30.0, 2.0], [30.0, 30.0], [2.0, 30.0]])
    hole = np.array([[10.0, 10.0], [20.0, 10.0], [20.0, 20.0], [10.0, 20.0]])
    m = evenodd_mask((32, 32), [outer, hole])
    assert m[5, 5] and not m[15, 15] and not m[0, 0] and m[25, 25]
    assert m.sum() == 28 * 28 - 10 * 10


def test_dashes_cover_the_on_lengths():
    P = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 10.0]])
    ds = dashes(P, 3.0, 2.0)
    lengths = [np.hypot(*np.diff(D, axis=0).T).sum() for D in ds]
    np.testing.assert_allclose(lengths, [3.0, 3.0, 3.0, 3.0])
    np.testing.assert_allclose(ds[2], [[10.0, 0.0], [10.0, 3.0]])  # turns the corner
    np.testing.assert_allclose(ds[1], [[5.0, 0.0], [8.0, 0.0]])


def test_bundled_font_has_the_legend_glyphs():
    assert (FONT_DIR / "LICENSE_DEJAVU").is_file()
    f = font(40)
    assert f.getname()[0] == "DejaVu Sans"
    assert font(40, bold=True).getname() == ("DejaVu Sans", "Bold")
    notdef = f.getmask("\uffff").getbbox()
    for ch in "≥–…%äÄéøßΩλЖжЁ×≤":
        assert f.getmask(ch).getbbox() != notdef, ch


def test_labels_inside_is_both_in_one_pass():
    outer = np.array([[2.0, 2.0], [30.0, 2.0], [30.0, 30.0], [2.0, 30.0]])
    hole = np.array([[10.0, 10.0], [20.0, 10.0], [20.0, 20.0], [10.0, 20.0]])
    T = np.array([[[3.0, 3.0], [9.0, 3.0], [3.0, 9.5]], [[25.0, 25.0], [21.0, 29.0], [29.0, 28.0]]])
    labels = np.array([3, 7])
    inside, lab = labels_inside((32, 32), [outer, hole], T, labels)
    np.testing.assert_array_equal(inside, evenodd_mask((32, 32), [outer, hole]))
    np.testing.assert_array_equal(lab, triangle_labels((32, 32), T, labels))
