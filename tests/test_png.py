"""PNG preview of a pattern before and after adjustment."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from ptailor.formats.png import pattern_png
from ptailor.formats.preview import (
    ERROR_COLOURS,
    ERROR_LABELS,
    FILL,
    NAN_COLOUR,
    check_inputs,
)
from ptailor.formats.sheet import sheet_layout

SIGNATURE = b"\x89PNG\r\n\x1a\n"


def imread(path) -> np.ndarray:
    """(h, w, 3) floats in 0..1."""
    with Image.open(path) as im:
        return np.asarray(im.convert("RGB"), dtype=np.float64) / 255.0


def to_rgb(colour: str) -> tuple[float, float, float]:
    c = colour.lstrip("#")
    return tuple(int(c[i : i + 2], 16) / 255.0 for i in (0, 2, 4))


def grid_mesh(x0, y0, w, h, n):
    xs, ys = np.meshgrid(np.linspace(x0, x0 + w, n + 1), np.linspace(y0, y0 + h, n + 1))
    V = np.c_[xs.ravel(), ys.ravel()]
    i = (np.arange(n)[:, None] * (n + 1) + np.arange(n)[None, :]).ravel()
    F = np.r_[np.c_[i, i + 1, i + n + 2], np.c_[i, i + n + 2, i + n + 1]]
    return V, F


def square(x0, y0, w):
    return np.array([[x0, y0], [x0 + w, y0], [x0 + w, y0 + w], [x0, y0 + w]], dtype=float)


@pytest.fixture
def squares():
    """Two 50-unit squares: uniform 3 % error, and unknown (NaN) error."""
    V0, F0 = grid_mesh(0, 0, 50, 50, 10)
    V1, F1 = grid_mesh(100, 0, 50, 50, 10)
    before = [[square(2, 2, 46)], [square(100, 0, 50)]]
    after = [[square(0, 0, 50)], [square(100, 0, 50)]]
    tris = [(V0, F0), (V1, F1)]
    errs = [np.full(len(F0), 0.03), np.full(len(F1), np.nan)]
    return before, after, ["front", "back"], tris, errs


def pixel_of(before, after, names, tris, errs, point, p, shape, units="cm", title=""):
    """Row, column of pattern ``point`` of panel ``p`` in an image of ``shape``."""
    sheet = sheet_layout(check_inputs(before, after, names, tris, errs), units=units, title=title)
    x, y = sheet.to_sheet(np.array([point], dtype=float), p)[0]
    scale = shape[1] / sheet.width  # pixels per unit
    assert shape[0] / sheet.height == pytest.approx(scale, rel=2e-3)  # equal aspect
    return int(y * scale), int(x * scale)


def test_written_and_sized(tmp_path, squares):
    before, after, names, tris, errs = squares
    out = tmp_path / "preview.png"
    w, h = pattern_png(out, before, after, names, title="Tee", triangles=tris, errors=errs)
    data = out.read_bytes()
    assert data.startswith(SIGNATURE)
    img = imread(out)
    assert img.shape[:2] == (h, w)
    assert 1600 <= max(w, h) <= 2000
    assert w > h  # two squares side by side: landscape


@pytest.mark.parametrize("units", ["cm", "mm", "in", "uv"])
def test_size_does_not_depend_on_units(tmp_path, squares, units):
    before, after, names, tris, errs = squares
    k = {"cm": 1.0, "mm": 10.0, "in": 0.4, "uv": 0.01}[units]
    w, h = pattern_png(
        tmp_path / "p.png",
        [[L * k for L in ls] for ls in before],
        [[L * k for L in ls] for ls in after],
        names,
        units=units,
        triangles=[(V * k, F) for V, F in tris],
        errors=errs,
    )
    assert 1600 <= max(w, h) <= 2000


def test_byte_identical(tmp_path, squares):
    before, after, names, tris, errs = squares
    a, b = tmp_path / "a.png", tmp_path / "b.png"
    pattern_png(a, before, after, names, title="T", triangles=tris, errors=errs)
    pattern_png(b, before, after, names, title="T", triangles=tris, errors=errs)
    assert a.read_bytes() == b.read_bytes()
    assert b"Software" not in a.read_bytes() and b"matplotlib" not in a.read_bytes()


def test_bin_colour_at_the_centre_and_white_corners(tmp_path, squares):
    before, after, names, tris, errs = squares
    out = tmp_path / "p.png"
    pattern_png(out, before, after, names, title="T", triangles=tris, errors=errs)
    img = imread(out)[..., :3]
    for p, colour in [(0, ERROR_COLOURS[ERROR_LABELS.index("2–5 %")]), (1, NAN_COLOUR)]:
        point = (p * 100 + 25, 25)
        r, c = pixel_of(before, after, names, tris, errs, point, p, img.shape, title="T")
        np.testing.assert_allclose(img[r, c], to_rgb(colour), atol=1.5 / 255)
        # a uniform panel is uniform: no seams between its triangles
        patch = img[r - 40 : r + 40, c - 40 : c + 40]
        want = np.broadcast_to(to_rgb(colour), patch.shape)
        np.testing.assert_allclose(patch, want, atol=1.5 / 255)
    for r, c in [(0, 0), (0, -1), (-1, 0), (-1, -1), (2, -3)]:
        np.testing.assert_array_equal(img[r, c], [1.0, 1.0, 1.0])


def test_without_triangles_light_fill(tmp_path, squares):
    before, after, names, *_ = squares
    out = tmp_path / "p.png"
    pattern_png(out, before, after, names)
    img = imread(out)[..., :3]
    r, c = pixel_of(before, after, names, None, None, (25, 25), 0, img.shape)
    np.testing.assert_allclose(img[r, c], to_rgb(FILL), atol=1.5 / 255)


def test_hole_stays_empty(tmp_path):
    outer = square(0, 0, 60)
    hole = square(20, 20, 20)  # same orientation as the outer loop: still a hole
    out = tmp_path / "p.png"
    pattern_png(out, [[outer, hole]], [[outer, hole]], ["ring"])
    img = imread(out)[..., :3]
    for point, colour in [((30, 30), (1.0, 1.0, 1.0)), ((10, 10), to_rgb(FILL))]:
        r, c = pixel_of([[outer, hole]], [[outer, hole]], ["ring"], None, None, point, 0, img.shape)
        np.testing.assert_allclose(img[r, c], colour, atol=1.5 / 255)


def test_inputs_untouched_and_checked(tmp_path, squares):
    before, after, names, tris, errs = squares
    copies = [[L.copy() for L in ls] for ls in before], [(V.copy(), F.copy()) for V, F in tris]
    pattern_png(tmp_path / "p.png", before, after, names, triangles=tris, errors=errs)
    for ls, ls0 in zip(before, copies[0], strict=True):
        for L, L0 in zip(ls, ls0, strict=True):
            np.testing.assert_array_equal(L, L0)
    for (V, F), (V0, F0) in zip(tris, copies[1], strict=True):
        np.testing.assert_array_equal(V, V0)
        np.testing.assert_array_equal(F, F0)
    with pytest.raises(ValueError, match="names"):
        pattern_png(tmp_path / "q.png", before, after, names[:1])
    with pytest.raises(ValueError, match="error arrays"):
        pattern_png(tmp_path / "q.png", before, after, names, triangles=tris, errors=errs[:1])
    with pytest.raises(ValueError, match="size"):
        pattern_png(tmp_path / "q.png", before, after, names, size=4)
    assert not (tmp_path / "q.png").exists()


def test_empty_pattern(tmp_path):
    w, h = pattern_png(tmp_path / "p.png", [], [], [], title="nothing")
    assert max(w, h) == 1800
    assert (tmp_path / "p.png").read_bytes().startswith(SIGNATURE)


def test_each_triangle_in_its_bin_colour(tmp_path):
    """A panel of mixed bins: the pixel at a triangle's centre has that triangle's colour
    (the most common bin fills the outline, the others are drawn over it)."""
    V, F = grid_mesh(0, 0, 60, 60, 6)
    rng = np.random.default_rng(1)
    err = rng.choice([0.001, 0.007, 0.03, 0.2, np.nan], size=len(F), p=[0.6, 0.1, 0.1, 0.1, 0.1])
    outline = [square(0, 0, 60)]
    args = ([outline], [outline], ["mix"], [(V, F)], [err])
    out = tmp_path / "p.png"
    pattern_png(out, *args[:3], triangles=args[3], errors=args[4])
    img = imread(out)
    from ptailor.formats.preview import bin_colour, error_bins

    bins = error_bins(err)
    for t in range(len(F)):  # a loop over 72 triangles of a test
        centre = V[F[t]].mean(axis=0)
        r, c = pixel_of(*args, centre, 0, img.shape)
        np.testing.assert_allclose(img[r, c], to_rgb(bin_colour(int(bins[t]))), atol=1.5 / 255)


def test_does_not_import_matplotlib(tmp_path, squares):
    """The preview is drawn with Pillow: matplotlib (a second of imports) stays out."""
    import subprocess
    import sys

    code = (
        "import sys, numpy as np\n"
        "from ptailor.formats.png import pattern_png\n"
        "sq = np.array([[0.0, 0], [1, 0], [1, 1], [0, 1]])\n"
        f"pattern_png({str(tmp_path / 'p.png')!r}, [[sq]], [[sq]], ['a'], title='t')\n"
        "assert 'matplotlib' not in sys.modules, 'matplotlib imported'\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def test_the_dpi_is_in_the_file(tmp_path, squares):
    """Pillow encodes the preview with its physical pixel size (pHYs)."""
    before, after, names, tris, errs = squares
    out = tmp_path / "p.png"
    pattern_png(out, before, after, names, triangles=tris, errors=errs, dpi=150)
    with Image.open(out) as im:
        assert im.mode == "RGB"
        assert im.info["dpi"] == pytest.approx((150.0, 150.0), abs=0.02)
