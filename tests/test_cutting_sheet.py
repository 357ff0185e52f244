"""The cutting sheet (issue 45, item 5): ``--formats pdf`` writes ``pattern.pdf``, every
piece 1:1 on tiled pages with registration marks and a 10 cm test square.

The layout is data (:func:`ptailor.formats.cutting.cutting_layout`), measured here; the
PDF is read back by a small interpreter of its drawing operators (the page's coordinate
transformations followed), so the test square is measured in the file's own units.
"""

from __future__ import annotations

import base64
import re
import zlib

import numpy as np
import pytest
from click.testing import CliRunner

from ptailor.cli.main import cli
from ptailor.errors import PtailorError
from ptailor.formats.cut_marks import notch_ticks, quantity_words
from ptailor.formats.cutting import PAPERS, cutting_layout, parse_paper
from ptailor.model.pieces import PatternFile, Piece
from ptailor.run.options import RunOptions

#: points per millimetre
PT = 72 / 25.4


def rect(w: float, h: float) -> np.ndarray:
    return np.array([[0, 0], [w, 0], [w, h], [0, h]], dtype=float)


def pattern(units: str = "cm") -> PatternFile:
    """A front (cut on the fold, size M), a back cut 1 + 1 mirrored and a long band (wider
    than an A4 page), in ``units``."""
    k = {"cm": 1.0, "mm": 10.0, "in": 1 / 2.54}[units]
    front = Piece(
        "front", rect(30, 60) * k, notches=np.array([[30, 20], [0, 40]]) * k,
        grain=np.array([[15, 10], [15, 50]]) * k, sew=(rect(28, 58) + 1) * k,
        mirror=np.array([[0, 0], [0, 60]]) * k, size="M",
    )  # fmt: skip
    back = Piece(
        "back", rect(35, 62) * k, grain=np.array([[17, 10], [17, 50]]) * k, quantity=2,
        quantity_split=(1, 1), size="M",
    )  # fmt: skip
    band = Piece("band", rect(80, 6) * k, grain=np.array([[10, 3], [70, 3]]) * k)
    return PatternFile(pieces=(front, back, band), units=units, style="tee")


def inside_tiles(layout, P: np.ndarray) -> np.ndarray:
    """Per point, how many tiles hold it."""
    W, H = layout.tile
    x0 = np.array([t.x0 for t in layout.tiles])
    y0 = np.array([t.y0 for t in layout.tiles])
    x, y = P[:, :1], P[:, 1:]
    return ((x >= x0) & (x <= x0 + W) & (y >= y0) & (y <= y0 + H)).sum(axis=1)


@pytest.mark.parametrize("paper", ["A4", "Letter", "A3", "A0", "roll:914mm", "roll:36in"])
def test_every_piece_is_1_to_1_inside_the_tiles_and_apart(paper):
    pf = pattern()
    layout = cutting_layout(pf, paper=paper)
    assert len(layout.tiles) == layout.rows * layout.cols
    assert len({(t.row, t.col) for t in layout.tiles}) == len(layout.tiles)
    boxes = []
    for src, placed in zip(pf.pieces, layout.pieces, strict=True):
        shift = placed.outline - src.outline * 10  # cm -> mm, moved only
        assert np.ptp(shift, axis=0) == pytest.approx([0, 0], abs=1e-9)
        assert np.all(inside_tiles(layout, placed.outline) >= 1), placed.name
        boxes.append([*placed.outline.min(axis=0), *placed.outline.max(axis=0)])
    x, y, a = layout.square
    boxes.append([x, y, x + a, y + a])
    B = np.array(boxes)
    over = (
        (B[:, None, 0] < B[None, :, 2]) & (B[None, :, 0] < B[:, None, 2])
        & (B[:, None, 1] < B[None, :, 3]) & (B[None, :, 1] < B[:, None, 3])
    )  # fmt: skip
    assert not np.any(over & ~np.eye(len(B), dtype=bool)), "pieces overlap"


def test_the_test_square_is_on_page_a1_and_pages_join_on_their_crosshairs():
    layout = cutting_layout(pattern(), paper="A4")
    assert layout.rows * layout.cols > 1
    a1 = layout.tiles[0]
    assert a1.name == "A1"
    W, H = layout.tile
    x, y, a = layout.square
    assert a == 100
    assert a1.x0 <= x and x + a <= a1.x0 + W and a1.y0 <= y and y + a <= a1.y0 + H
    # neighbours share exactly the overlap strip
    o = layout.style.overlap
    by = {(t.row, t.col): t for t in layout.tiles}
    for (r, c), t in by.items():
        if (r, c + 1) in by:
            assert t.x0 + W - by[r, c + 1].x0 == pytest.approx(o)
        if (r + 1, c) in by:
            assert t.y0 - (by[r + 1, c].y0 + H) == pytest.approx(-o)
    # every crosshair prints whole on each page it touches; an inner one on 4 pages
    r = layout.style.cross
    arms = np.concatenate([layout.marks + d for d in ([r, 0], [-r, 0], [0, r], [0, -r])])
    whole = inside_tiles(layout, arms).reshape(4, -1).min(axis=0)
    assert np.array_equal(whole, inside_tiles(layout, layout.marks))
    inner = (layout.marks > o).all(axis=1) & (layout.marks < np.array(layout.extent) - o).all(
        axis=1
    )
    assert np.all(whole[inner] == 4) and np.all(whole >= 1)


def test_a_roll_is_one_sheet_and_a_wide_piece_turns():
    layout = cutting_layout(pattern(), paper="roll:500mm")
    assert len(layout.tiles) == 1 and layout.page[0] == 500
    band = layout.pieces[2]
    assert np.ptp(band.outline, axis=0) == pytest.approx([60, 800])  # turned, not mirrored
    assert np.allclose(band.outline.min(axis=0) >= 0, True)
    a0 = cutting_layout(pattern(), paper="A0")
    assert len(a0.tiles) == 1 and a0.page == PAPERS["A0"]


def test_units_are_read_and_marks_drawn():
    for units in ("mm", "in"):
        layout = cutting_layout(pattern(units), paper="A4")
        assert layout.pieces[0].extent == pytest.approx([300, 600])
    kinds = [s.kind for s in cutting_layout(pattern()).strokes]
    assert kinds.count("notch") == 2 and kinds.count("sew") == 1 and kinds.count("fold") == 1
    assert kinds.count("grain") == 9 and kinds.count("square") == 1  # a line + 2 heads each
    texts = {lb.text for lb in cutting_layout(pattern()).labels}
    assert {"front", "back", "band", "Size M", "Cut 1 + 1 mirrored", "Place on fold"} <= texts
    assert quantity_words(Piece("x", rect(1, 1), quantity=3)) == "Cut 3"


def test_notch_ticks_point_inward_whatever_the_orientation():
    sq = rect(10, 10)
    for P in (sq, sq[::-1]):
        t = notch_ticks(P, np.array([[0, 5], [5, -1]]), length=2)
        assert t[:, 0] == pytest.approx(np.array([[0, 5], [5, 0]]))
        assert t[:, 1] == pytest.approx(np.array([[2, 5], [5, 2]]))


@pytest.mark.parametrize(
    "paper, says",
    [("B5", "--paper must be one of"), ("roll:5cm", "a roll must be"),
     ("roll:wide", "not a length"), ("roll:3ft", "not a length"),
     ("roll:9000mm", "a roll must be")],
)  # fmt: skip
def test_a_bad_paper_is_refused(paper, says):
    with pytest.raises(PtailorError, match=says):
        parse_paper(paper)
    with pytest.raises(PtailorError, match=says):
        RunOptions(paper=paper)


def test_paper_is_stamped_unless_the_default():
    assert "paper" not in RunOptions(formats=("pdf",)).stamped()  # stamps before it stay valid
    assert RunOptions(formats=("pdf",), paper="Letter").stamped()["paper"] == "Letter"
    assert "pdf" not in RunOptions().formats


# -- the PDF read back ---------------------------------------------------------------


def pdf_pages(data: bytes) -> list[str]:
    """Each page's content stream, decompressed, in page order."""
    streams = re.findall(rb"<<(.*?)>>\s*stream\r?\n(.*?)endstream", data, flags=re.S)
    out = []
    for head, body in streams:
        if b"/FlateDecode" in head and b"/Length1" not in head:
            if b"/ASCII85Decode" in head:  # reportlab's default: ASCII85, then Flate
                body = base64.a85decode(body.strip().removesuffix(b"~>"))
            text = zlib.decompress(body).decode("latin-1")
            if " re" in text or " l\n" in text or "BT" in text:
                out.append(text)
    return out


def rectangles(content: str) -> list[tuple[float, ...]]:
    """Every ``re`` of a content stream as drawn on the page: ``(x, y, w, h)`` through the
    transformations (``cm``) in force, their ``q``/``Q`` nesting followed."""
    content = re.sub(r"\((?:\\.|[^\\)])*\)", " ", content)  # text strings
    ctm, stack, args, out = np.eye(3), [], [], []
    for tok in content.split():
        try:
            args.append(float(tok))
            continue
        except ValueError:
            pass
        if tok == "q":
            stack.append(ctm.copy())
        elif tok == "Q":
            ctm = stack.pop()
        elif tok == "cm":
            a, b, c, d, e, f = args[-6:]
            ctm = np.array([[a, b, 0], [c, d, 0], [e, f, 1]]) @ ctm
        elif tok == "re":
            x, y, w, h = args[-4:]
            p0 = np.array([x, y, 1]) @ ctm
            p1 = np.array([x + w, y + h, 1]) @ ctm
            out.append((p0[0], p0[1], p1[0] - p0[0], p1[1] - p0[1]))
        args = []
    return out


def test_the_pdf_test_square_measures_10_cm_and_pages_match_the_tiling(tmp_path):
    pytest.importorskip("reportlab")
    from ptailor.formats import writer_for

    path = tmp_path / "pattern.pdf"
    layout = writer_for(path)(path, pattern(), paper="A4", title="tee", note="no allowance")
    data = path.read_bytes()
    assert data.startswith(b"%PDF-")
    assert b"/UserUnit" not in data
    boxes = re.findall(rb"/MediaBox \[\s*([\d.\s]+)\]", data)
    assert len(boxes) == len(layout.tiles) == layout.rows * layout.cols > 1
    pw, ph = layout.page
    assert sorted(layout.page) == [210, 297]  # A4, portrait or landscape
    for b in boxes:
        assert [float(v) for v in b.split()] == pytest.approx([0, 0, pw * PT, ph * PT])
    assert len(re.findall(rb"/Type /Page\b", data)) == len(layout.tiles)
    pages = pdf_pages(data)
    assert len(pages) == len(layout.tiles)
    side = 100 * PT  # 10 cm in points
    squares = [r for r in rectangles(pages[0]) if r[2] == pytest.approx(side, abs=0.01)]
    assert len(squares) == 1, rectangles(pages[0])
    x, y, w, h = squares[0]
    assert w == pytest.approx(side, abs=0.01) and h == pytest.approx(side, abs=0.01)
    m = layout.style.margin
    assert x > 0 and x + w < pw * PT and y > 0 and y + h < ph * PT
    assert (x / PT - m + layout.tiles[0].x0) == pytest.approx(layout.square[0], abs=0.01)
    for content in pages[1:]:
        assert not [r for r in rectangles(content) if r[2] == pytest.approx(side, abs=0.01)]


@pytest.mark.slow
def test_adjust_writes_the_cutting_sheet_and_refuses_a_bad_paper(tmp_path):
    pytest.importorskip("reportlab")
    from ptailor.recipe.bundled import bundled_recipe
    from ptailor.samples.obj_text import sample_obj_text

    (tmp_path / "g.obj").write_text(sample_obj_text("lantern_sleeve"))
    (tmp_path / "r.yaml").write_text(bundled_recipe("wider-around"))
    args = ["adjust", str(tmp_path / "g.obj"), str(tmp_path / "r.yaml"), "--formats", "pdf,cut"]
    bad = CliRunner().invoke(cli, [*args, "-o", str(tmp_path / "bad"), "--paper", "B5"])
    assert bad.exit_code == 2 and "--paper" in bad.output
    assert not (tmp_path / "bad").exists()
    out = tmp_path / "out"
    r = CliRunner().invoke(cli, [*args, "-o", str(out), "--seam-allowance", "1cm"])
    assert r.exit_code == 0, r.output
    data = (out / "pattern.pdf").read_bytes()
    names = sorted(p.name for p in out.iterdir())
    assert names == [".ptailor", "pattern.pdf", "pattern_cut.svg", "report.json"]
    texts = " ".join(pdf_pages(data))
    assert "(sleeve)" in texts and "(cuff)" in texts and "Seam allowance 1 cm" in texts


def test_a_one_page_sheet_puts_the_square_where_it_fits():
    """Two A0-tall halves side by side fill the first shelf: the square goes below them
    rather than a second sheet."""
    halves = tuple(Piece(n, rect(40, 100), grain=np.array([[20, 10], [20, 90]])) for n in "ab")
    layout = cutting_layout(PatternFile(pieces=halves, units="cm"), paper="A0")
    assert len(layout.tiles) == 1
    x, y, a = layout.square
    assert np.all(inside_tiles(layout, np.array([[x, y], [x + a, y + a]])) == 1)
    assert y + a < min(p.outline[:, 1].min() for p in layout.pieces)


def test_the_cut_svg_is_one_sheet_in_mm_with_a_10_cm_square():
    from ptailor.formats.cut_svg import cut_svg

    text, layout = cut_svg(pattern(), title="tee <1>", note="")
    assert len(layout.tiles) == 1 and "tee &lt;1&gt;" in text
    w, h = (float(v) for v in re.search(r'width="([\d.]+)mm" height="([\d.]+)mm"', text).groups())
    assert re.search(r'viewBox="0 0 ([\d.]+) ([\d.]+)"', text).groups() == (f"{w:.3f}", f"{h:.3f}")
    assert (w, h) == pytest.approx(layout.page, abs=1e-3)
    d = re.search(r'class="square"[^>]* d="M([^"Z]+)Z"', text).group(1)
    P = np.array([[float(v) for v in p.split(",")] for p in d.split()])
    assert np.ptp(P, axis=0) == pytest.approx([100, 100], abs=1e-3)
    assert 'class="mark"' not in text  # one sheet: no registration marks
    cut = re.search(r'class="cut"[^>]* d="([^"]+)"', text).group(1)
    assert cut.count("M") == len(pattern().pieces)
