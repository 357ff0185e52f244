"""AAMA/ASTM DXF pattern files: round trips, layout, the real CAD exports, errors, inspect."""

from __future__ import annotations

import itertools
import json

import ezdxf
import numpy as np
import pytest
from click.testing import CliRunner

from ptailor.cli.main import cli
from ptailor.errors import PtailorError
from ptailor.formats import PATTERN_READERS, PATTERN_WRITERS
from ptailor.formats.dxf import (
    layout_pieces,
    piece_bounds,
    read_dxf,
    write_dxf,
)
from ptailor.model.pieces import PatternFile, Piece
from tests.conftest import SHARED

DXF_DIR = SHARED / "dxf"
TANK = DXF_DIR / "WM_SLIM_TANK.DXF"
CLO = DXF_DIR / "clo-pattern.dxf"
CM = {"mm": 0.1, "cm": 1.0, "in": 2.54}


def real(path):
    if not path.is_file():
        pytest.skip(f"{path} not available (../shared is absent)")
    return path


# ----------------------------------------------------------------------------- builders


def bodice(x0=0.0, y0=0.0, n=120) -> Piece:
    """A 40 x 60 front with a curved neckline, corners as turn points and every mark."""
    off = np.array([x0, y0])
    t = np.linspace(0.0, 1.0, n // 4, endpoint=False)
    bottom = np.c_[40 * t, 0 * t]
    right = np.c_[40 + 0 * t, 60 * t]
    neck = np.c_[40 - 40 * t, 60 - 8 * np.sin(np.pi * t)]  # a curve along the top
    left = np.c_[0 * t, 60 - 60 * t]
    outline = np.vstack([bottom, right, neck, left]) + off
    turn = np.zeros(len(outline), dtype=bool)
    turn[[0, n // 4, n // 2, 3 * n // 4]] = True
    return Piece(
        name="Front",
        outline=outline,
        turn=turn,
        notches=np.array([[20.0, 0.0], [40.0, 30.0]]) + off,
        notch_angles=np.array([90.0, 180.0]),
        grain=np.array([[20.0, 10.0], [20.0, 50.0]]) + off,
        internal=(
            np.array([[5.0, 20.0], [15.0, 20.0], [15.0, 30.0]]) + off,
            np.array([[30.0, 5.0], [30.0, 25.0]]) + off,
        ),
        drills=np.array([[10.0, 40.0]]) + off,
        sew=np.array([[1.0, 1.0], [39.0, 1.0], [39.0, 51.0], [1.0, 51.0]]) + off,
        mirror=np.array([[0.0, 0.0], [0.0, 60.0]]) + off,
        quantity=2,
        size="M",
        annotations=("Category: FRONT", "Annotation: 1X FABRIC"),
    )


def mirrored_sleeve(x0=60.0, y0=0.0) -> Piece:
    """A clockwise (mirrored) sleeve with a name that is not DXF-safe."""
    off = np.array([x0, y0])
    t = np.linspace(0.0, np.pi, 60)
    cap = np.c_[15 - 15 * np.cos(t), 30 + 10 * np.sin(t)]
    outline = np.vstack([[[0.0, 0.0], [30.0, 0.0]], cap[::-1][:-1]])[::-1] + off
    assert _signed_area(outline) < 0
    turn = np.zeros(len(outline), dtype=bool)
    turn[-2:] = True
    return Piece(
        name="Sleeve / left",
        outline=outline,
        turn=turn,
        notches=np.array([[15.0, 40.0]]) + off,
        grain=np.array([[15.0, 5.0], [15.0, 35.0]]) + off,
        size="M",
    )


def _signed_area(p):
    x, y = p[:, 0], p[:, 1]
    return 0.5 * (np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _length(pts):
    return float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum())


def pattern(units="in", pieces=None) -> PatternFile:
    pieces = pieces if pieces is not None else (bodice(), mirrored_sleeve())
    return PatternFile(
        pieces=tuple(pieces),
        units=units,
        style="Test Blouse",
        sizes=("M",),
        size="M",
        sample_size="M",
    )


def same_loop(a, b, tol):
    """``b`` is ``a`` up to where the loop starts."""
    if a.shape != b.shape:
        return False
    k = int(np.argmin(np.linalg.norm(b - a[0], axis=1)))
    return bool(np.abs(np.roll(b, -k, axis=0) - a).max() <= tol)


# ----------------------------------------------------------------------------- round trip


def test_round_trip_in_inches(tmp_path):
    src = pattern("in")
    out = tmp_path / "p.dxf"
    write_dxf(out, src, layout="keep")

    raw = out.read_text()
    assert "TABLES" not in raw and "$ACADVER" not in raw
    doc = ezdxf.readfile(out)
    assert doc.dxfversion == "AC1009"
    blocks = [b for b in doc.blocks if not b.name.startswith("*")]
    assert [b.name for b in blocks] == ["Front", "Sleeve___left"]
    inserts = doc.modelspace().query("INSERT")
    assert [i.dxf.name for i in inserts] == ["Front", "Sleeve___left"]
    front = doc.blocks["Front"]
    by = {}
    for e in front:
        by.setdefault((e.dxftype(), e.dxf.layer), []).append(e)
    assert len(by[("POLYLINE", "1")]) == 1 and by[("POLYLINE", "1")][0].is_closed
    assert len(by[("POINT", "2")]) == 4
    assert len(by[("POINT", "4")]) == 2
    assert len(by[("LINE", "7")]) == 1
    assert len(by[("POLYLINE", "8")]) == 2
    assert len(by[("POINT", "13")]) == 1
    assert len(by[("POLYLINE", "14")]) == 1 and by[("POLYLINE", "14")][0].is_closed
    texts = [e.dxf.text for e in by[("TEXT", "1")]]
    assert texts[:3] == ["Piece Name: Front", "Quantity: 2", "Size: M"]
    msp_texts = [e.dxf.text for e in doc.modelspace().query("TEXT")]
    assert "Units: ENGLISH" in msp_texts and "Style Name: Test Blouse" in msp_texts

    back = read_dxf(out)
    assert back.units == "in" and back.units_text == "ENGLISH"
    assert back.style == "Test Blouse" and back.sizes == ("M",) and back.size == "M"
    assert [p.name for p in back.pieces] == ["Front", "Sleeve / left"]
    for a, b in zip(src.pieces, back.pieces, strict=True):
        tol = 1e-6 * float(a.extent.max())
        assert b.quantity == a.quantity and b.size == a.size
        assert _signed_area(b.outline) > 0
        if _signed_area(a.outline) > 0:
            np.testing.assert_allclose(b.outline, a.outline, atol=tol)
            np.testing.assert_array_equal(b.turn, a.turn)
        else:  # the mirrored sleeve comes back counter-clockwise, turn flags with it
            assert same_loop(a.outline[::-1], b.outline, tol)
            assert b.turn.sum() == a.turn.sum()
            np.testing.assert_allclose(
                np.sort(b.outline[b.turn], axis=0), np.sort(a.outline[a.turn], axis=0), atol=tol
            )
        np.testing.assert_allclose(b.notches, a.notches, atol=tol)
        expect = a.notch_angles if len(a.notch_angles) else np.zeros(len(a.notches))
        np.testing.assert_allclose(b.notch_angles, expect, atol=1e-9)
        np.testing.assert_allclose(b.grain, a.grain, atol=tol)
    f0, f1 = src.pieces[0], back.pieces[0]
    assert len(f1.internal) == 2
    for x, y in zip(f0.internal, f1.internal, strict=True):
        np.testing.assert_allclose(y, x, atol=1e-6)
    np.testing.assert_allclose(f1.drills, f0.drills, atol=1e-6)
    np.testing.assert_allclose(f1.mirror, f0.mirror, atol=1e-6)
    assert same_loop(f0.sew, f1.sew, 1e-6)
    assert f1.annotations == f0.annotations


def test_centimetres_are_written_as_millimetres(tmp_path):
    src = pattern("cm")
    out = tmp_path / "cm.dxf"
    write_dxf(out, src, layout="keep")
    doc = ezdxf.readfile(out)
    assert "Units: METRIC" in [e.dxf.text for e in doc.modelspace().query("TEXT")]
    poly = doc.blocks["Front"].query("POLYLINE[layer=='1']")[0]
    written = np.array([(p[0], p[1]) for p in poly.points()])
    np.testing.assert_allclose(written, 10.0 * src.pieces[0].outline, atol=1e-9)

    back = read_dxf(out)
    assert back.units == "mm" and back.units_text == "METRIC"
    assert "METRIC" in back.units_note and "mm" in back.units_note
    front = back.pieces[0]
    np.testing.assert_allclose(front.outline, 10.0 * src.pieces[0].outline, atol=1e-6)
    np.testing.assert_allclose(front.grain, 10.0 * src.pieces[0].grain, atol=1e-6)
    # the same lengths in cm
    np.testing.assert_allclose(front.extent * CM[back.units], src.pieces[0].extent, rtol=1e-9)


def test_units_override_and_bad_units(tmp_path):
    out = tmp_path / "p.dxf"
    write_dxf(out, pattern("mm"), layout="keep")
    got = read_dxf(out, units="cm")
    assert got.units == "cm" and "given" in got.units_note
    with pytest.raises(PtailorError, match="units"):
        read_dxf(out, units="furlong")
    with pytest.raises(PtailorError, match="cannot write"):
        write_dxf(tmp_path / "f.dxf", pattern("furlong"))
    write_dxf(tmp_path / "m.dxf", pattern("m"))  # metres: written in millimetres (issue 22)
    np.testing.assert_allclose(
        read_dxf(tmp_path / "m.dxf").pieces[0].outline,
        1000 * pattern("m").pieces[0].outline,
    )


def test_output_is_deterministic(tmp_path, monkeypatch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1700000000")
    a, b = tmp_path / "a.dxf", tmp_path / "b.dxf"
    write_dxf(a, pattern())
    write_dxf(b, pattern())
    assert a.read_bytes() == b.read_bytes()
    assert "Creation Date: 14-11-2023" in a.read_text()


def test_writer_does_not_mutate_its_input(tmp_path):
    src = pattern("cm", pieces=(bodice(), bodice(5, 5)))
    before = [p.outline.copy() for p in src.pieces]
    write_dxf(tmp_path / "x.dxf", src, layout="row")
    for p, o in zip(src.pieces, before, strict=True):
        np.testing.assert_array_equal(p.outline, o)


def test_written_with_ezdxfs_gerber_exporter(tmp_path):
    """The file is what ezdxf + gerber_D6673 write: empty HEADER, no TABLES, no layout blocks."""
    out = tmp_path / "p.dxf"
    write_dxf(out, pattern("cm"))
    text = out.read_text()
    assert text.startswith("  0\nSECTION\n  2\nHEADER\n  0\nENDSEC\n")
    assert "TABLES" not in text and "*Model_Space" not in text and "*Paper_Space" not in text
    assert text.rstrip().endswith("EOF")


def test_write_errors_name_the_file(tmp_path):
    bad = Piece("Bad", np.array([[0.0, 0.0], [np.nan, 1.0], [1.0, 1.0]]))
    with pytest.raises(PtailorError, match=r"'Bad'.*finite") as exc:
        write_dxf(tmp_path / "bad.dxf", pattern("cm", pieces=(bad,)))
    assert "bad.dxf" in str(exc.value)
    with pytest.raises(PtailorError, match="cannot write"):
        write_dxf(tmp_path / "no" / "such" / "dir.dxf", pattern("cm"))


def test_registered_in_dispatch_tables():
    assert PATTERN_READERS["dxf"] is read_dxf
    assert PATTERN_WRITERS["dxf"] is write_dxf


def test_names_and_text_survive(tmp_path):
    p = Piece("Ärmel links", bodice().outline, quantity=3)
    q = Piece("Ärmel links", bodice(60).outline)
    out = tmp_path / "u.dxf"
    write_dxf(out, pattern("cm", pieces=(p, q)))
    doc = ezdxf.readfile(out)
    names = [b.name for b in doc.blocks if not b.name.startswith("*")]
    assert len(set(names)) == 2 and all(n.isascii() for n in names)
    back = read_dxf(out)
    assert [x.name for x in back.pieces] == ["Ärmel links", "Ärmel links"]
    assert [x.quantity for x in back.pieces] == [3, 1]


# ----------------------------------------------------------------------------- layout


def _overlaps(pieces):
    boxes = [piece_bounds(p) for p in pieces]
    for i in range(len(boxes)):
        for j in range(i + 1, len(boxes)):
            lo = np.maximum(boxes[i][0], boxes[j][0])
            hi = np.minimum(boxes[i][1], boxes[j][1])
            if np.all(hi > lo):
                return True
    return False


def test_auto_layout_separates_overlapping_pieces(tmp_path):
    stacked = (bodice(), bodice(10, 10), mirrored_sleeve(20, 20))
    assert _overlaps(stacked)
    out = tmp_path / "auto.dxf"
    write_dxf(out, pattern("cm", pieces=stacked))
    back = read_dxf(out)
    assert not _overlaps(back.pieces)
    for a, b in zip(stacked, back.pieces, strict=True):  # moved, not reshaped
        np.testing.assert_allclose(b.extent, 10 * a.extent, rtol=1e-9)
        d = b.notches - 10 * a.notches
        np.testing.assert_allclose(d, np.broadcast_to(d[0], d.shape), atol=1e-6)


def test_auto_layout_keeps_separate_pieces(tmp_path):
    out = tmp_path / "keep.dxf"
    src = pattern("in")
    assert not _overlaps(src.pieces)
    write_dxf(out, src)
    back = read_dxf(out)
    np.testing.assert_allclose(back.pieces[0].outline, src.pieces[0].outline, atol=1e-9)


def test_layout_row_moves_and_rejects_unknown():
    pieces = (bodice(), bodice())
    rowed = layout_pieces(pieces, layout="row")
    assert not _overlaps(rowed)
    assert layout_pieces(pieces, layout="keep") == pieces
    assert _overlaps(layout_pieces(pieces, layout="keep"))
    with pytest.raises(PtailorError, match="layout"):
        layout_pieces(pieces, layout="diagonal")


# ----------------------------------------------------------------------------- reader details


def _new_r12():
    from ezdxf.document import Drawing

    return Drawing.new("R12")


def test_boundary_segments_are_chained_in_any_order_and_direction(tmp_path):
    src = bodice()
    ol = src.outline
    n = len(ol)
    cuts = [0, 17, 40, 41, 75, 101, n]
    segs = [np.vstack([ol, ol[:1]])[a : b + 1] for a, b in itertools.pairwise(cuts)]
    order = [3, 0, 5, 2, 4, 1]
    doc = _new_r12()
    blk = doc.blocks.new("FRONT_M")
    for k in order:
        s = segs[k][::-1] if k % 2 else segs[k]
        blk.add_polyline2d(s.tolist(), dxfattribs={"layer": "1"})
    for q in ol[src.turn].tolist():
        blk.add_point(q, dxfattribs={"layer": "2"})
    blk.add_text("Piece Name: FRONT", dxfattribs={"layer": "1"})
    blk.add_text("SIZE: M", dxfattribs={"layer": "1"})
    doc.modelspace().add_blockref("FRONT_M", (0, 0))
    doc.modelspace().add_text("Units: METRIC")
    doc.saveas(tmp_path / "seg.dxf")

    got = read_dxf(tmp_path / "seg.dxf", units="cm").pieces[0]
    assert got.name == "FRONT" and got.size == "M"
    assert same_loop(ol, got.outline, 1e-9)
    np.testing.assert_array_equal(
        np.sort(got.outline[got.turn], axis=0), np.sort(ol[src.turn], axis=0)
    )


def test_open_boundary_is_an_error_naming_the_piece(tmp_path):
    doc = _new_r12()
    blk = doc.blocks.new("BACK")
    blk.add_polyline2d([(0, 0), (50, 0), (50, 60), (0, 60), (0, 10)], dxfattribs={"layer": "1"})
    doc.modelspace().add_blockref("BACK", (0, 0))
    doc.saveas(tmp_path / "open.dxf")
    with pytest.raises(PtailorError, match=r"'BACK'.*does not close") as exc:
        read_dxf(tmp_path / "open.dxf")
    assert "open.dxf" in str(exc.value)


def test_insert_transform_is_applied(tmp_path):
    doc = _new_r12()
    blk = doc.blocks.new("P")
    square = np.array([[0.0, 0.0], [40.0, 0.0], [40.0, 60.0], [0.0, 60.0]])
    blk.add_polyline2d(square.tolist(), close=True, dxfattribs={"layer": "1"})
    blk.add_point((40.0, 30.0), dxfattribs={"layer": "4", "angle": 180.0})
    blk.add_line((20, 10), (20, 50), dxfattribs={"layer": "7"})
    blk.add_text("Size: 38", dxfattribs={"layer": "1"})
    doc.modelspace().add_blockref("P", (100, 200), dxfattribs={"rotation": 90, "xscale": 2})
    doc.saveas(tmp_path / "ins.dxf")
    got = read_dxf(tmp_path / "ins.dxf", units="mm").pieces[0]
    # x' = 100 - y, y' = 200 + 2 x
    expect = np.c_[100 - square[:, 1], 200 + 2 * square[:, 0]]
    assert same_loop(expect, got.outline, 1e-9)
    np.testing.assert_allclose(got.notches, [[70.0, 280.0]], atol=1e-9)
    assert got.notch_angles[0] == pytest.approx(270.0)
    np.testing.assert_allclose(got.grain, [[90.0, 240.0], [50.0, 240.0]], atol=1e-9)
    assert got.name == "P" and got.size == "38"


def test_modelspace_only_file(tmp_path):
    doc = _new_r12()
    msp = doc.modelspace()
    a = np.array([[0.0, 0.0], [40.0, 0.0], [40.0, 60.0], [0.0, 60.0]])
    b = a + np.array([100.0, 0.0])
    msp.add_polyline2d(a.tolist(), close=True, dxfattribs={"layer": "1"})
    msp.add_polyline2d(b[::-1].tolist(), close=True, dxfattribs={"layer": "1"})
    msp.add_point((140.0, 30.0), dxfattribs={"layer": "4"})
    msp.add_point((40.0, 30.0), dxfattribs={"layer": "4"})
    msp.add_point((0.0, 20.0), dxfattribs={"layer": "4"})
    msp.add_text("Piece Name: LEFT", dxfattribs={"layer": "1", "insert": (10, 30)})
    msp.add_text("Piece Name: RIGHT", dxfattribs={"layer": "1", "insert": (110, 30)})
    doc.saveas(tmp_path / "msp.dxf")
    got = read_dxf(tmp_path / "msp.dxf")
    assert [p.name for p in got.pieces] == ["LEFT", "RIGHT"]
    assert [len(p.notches) for p in got.pieces] == [2, 1]
    assert all(_signed_area(p.outline) > 0 for p in got.pieces)
    assert got.units == "cm" and "no units in the file" in got.units_note


def test_sizes_from_block_names_and_sample_size(tmp_path):
    doc = _new_r12()
    for size, w in (("S", 40.0), ("M", 44.0), ("L", 48.0)):
        blk = doc.blocks.new(f"BACK_{size}")
        blk.add_polyline2d(
            [(0, 0), (w, 0), (w, 60), (0, 60)], close=True, dxfattribs={"layer": "1"}
        )
        doc.modelspace().add_blockref(f"BACK_{size}", (0, 0))
    doc.modelspace().add_text("Sample Size: M")
    doc.saveas(tmp_path / "graded.dxf")
    got = read_dxf(tmp_path / "graded.dxf")
    assert got.sizes == ("S", "M", "L") and got.size == "M" and got.sample_size == "M"
    assert [p.name for p in got.pieces] == ["BACK"]
    assert got.pieces[0].extent[0] == pytest.approx(44.0)
    assert read_dxf(tmp_path / "graded.dxf", size="l").pieces[0].extent[0] == pytest.approx(48.0)
    with pytest.raises(PtailorError, match=r"no size 'XL'.*S, M, L"):
        read_dxf(tmp_path / "graded.dxf", size="XL")


# ----------------------------------------------------------------------------- errors


def test_not_a_dxf(tmp_path):
    p = tmp_path / "notes.dxf"
    p.write_text("these are my notes\nnot a drawing\n")
    with pytest.raises(PtailorError, match="not a readable DXF") as exc:
        read_dxf(p)
    assert exc.value.path == str(p)
    with pytest.raises(PtailorError, match="no such file"):
        read_dxf(tmp_path / "missing.dxf")


def test_empty_dxf_has_no_pieces(tmp_path):
    p = tmp_path / "empty.dxf"
    ezdxf.new("R2010").saveas(p)
    with pytest.raises(PtailorError, match="no pattern pieces"):
        read_dxf(p)


@pytest.mark.parametrize("case", ["text", "empty", "size"])
def test_cli_errors_exit_2_naming_the_file(tmp_path, case):
    p = tmp_path / f"{case}.dxf"
    args = ["inspect", str(p)]
    if case == "text":
        p.write_text("hello\n")
    elif case == "empty":
        ezdxf.new("R12").saveas(p)
    else:
        write_dxf(p, pattern("in"))
        args += ["--size", "XXL"]
    r = CliRunner().invoke(cli, args)
    assert r.exit_code == 2, r.output
    assert str(p) in r.stderr and r.stderr.startswith("ptailor: error:")


# ----------------------------------------------------------------------------- inspect


def test_inspect_dxf_text_and_json(tmp_path):
    p = tmp_path / "pat.DXF"
    write_dxf(p, pattern("cm"))
    r = CliRunner().invoke(cli, ["inspect", str(p)])
    assert r.exit_code == 0, r.output
    assert "2 pieces" in r.output and "Front" in r.output and "Sleeve / left" in r.output
    assert "units: mm" in r.output and "sizes: M" in r.output
    r = CliRunner().invoke(cli, ["inspect", str(p), "--json", "--dxf-units", "mm"])
    assert r.exit_code == 0, r.output
    info = json.loads(r.output)
    assert info["count"] == 2 and info["units"]["file"] == "mm"
    front = info["pieces"][0]
    assert front["size_cm"] == pytest.approx([40.0, 60.0], abs=0.01)
    assert front["size"] == pytest.approx([400.0, 600.0], abs=0.01)
    assert front["quantity"] == 2 and front["notches"] == 2
    assert front["grain"] is True and front["grain_angle"] == pytest.approx(90.0)


def test_inspect_garment_rejects_dxf_options(tmp_path):
    from ptailor.samples.obj_text import sample_obj_text

    p = tmp_path / "sleeve.obj"
    p.write_text(sample_obj_text("lantern_sleeve"))
    assert CliRunner().invoke(cli, ["inspect", str(p)]).exit_code == 0
    r = CliRunner().invoke(cli, ["inspect", str(p), "--size", "M"])
    assert r.exit_code == 2 and "DXF" in r.stderr


# ------------------------------------------------------------------------- an independent reader


@pytest.mark.slow  # matplotlib.pyplot's import and a drawing: 1 s
def test_ezdxf_drawing_addon_renders_the_written_file(tmp_path):
    matplotlib = pytest.importorskip("matplotlib")  # the sim extra's, not a core dependency
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from ezdxf.addons.drawing import Frontend, RenderContext
    from ezdxf.addons.drawing.config import BackgroundPolicy, ColorPolicy, Configuration
    from ezdxf.addons.drawing.matplotlib import MatplotlibBackend

    out = tmp_path / "p.dxf"
    write_dxf(out, pattern("cm"))
    doc = ezdxf.readfile(out)
    fig = plt.figure(figsize=(4, 3))
    ax = fig.add_axes([0, 0, 1, 1])
    cfg = Configuration(background_policy=BackgroundPolicy.WHITE, color_policy=ColorPolicy.BLACK)
    Frontend(RenderContext(doc), MatplotlibBackend(ax), config=cfg).draw_layout(doc.modelspace())
    png = tmp_path / "p.png"
    fig.savefig(png, dpi=80)
    plt.close(fig)
    assert png.stat().st_size > 2000
    img = plt.imread(png)
    dark = (img[..., :3].mean(axis=2) < 0.5).mean()
    assert 0.002 < dark < 0.5  # lines drawn, not a blank or black page


# ----------------------------------------------------------------------------- real files


@pytest.mark.slow
def test_real_tank_gerber():
    pf = read_dxf(real(TANK))
    assert pf.units == "in" and pf.units_text == "ENGLISH"
    assert len(pf.sizes) == 14 and pf.sizes[0] == "26" and pf.sizes[-1] == "52"
    assert pf.sample_size == "36" and pf.size == "36"
    assert [p.name for p in pf.pieces] == ["TANK_SR_BK", "TANK_SR_FR"]
    for p in pf.pieces:
        cm = p.extent * 2.54
        assert np.all((cm > 10) & (cm < 150)), cm
        assert _signed_area(p.outline) > 0 and len(p.outline) > 10
        assert p.grain is not None and len(p.internal) >= 3
        assert p.turn.any() and p.quantity == 1 and p.size == "36"
        # one closed loop made of all six layer-1 segments: same total length as the file's
        segs = ezdxf.readfile(TANK).blocks[f"{p.name}_36"].query("POLYLINE[layer=='1']")
        assert len(segs) == 6
        raw = sum(_length(np.array([(v[0], v[1]) for v in s.points()])) for s in segs)
        assert _length(np.vstack([p.outline, p.outline[:1]])) == pytest.approx(raw, rel=1e-9)
    assert [len(p.notches) for p in pf.pieces] == [4, 2]
    small = read_dxf(TANK, size="26")
    assert small.size == "26"
    assert all(np.all(a.extent < b.extent) for a, b in zip(small.pieces, pf.pieces, strict=True))


@pytest.mark.slow
def test_real_clo3d():
    pf = read_dxf(real(CLO))
    assert len(pf.pieces) == 9 and pf.units == "mm" and pf.units_text == "METRIC"
    assert "AAMA/ASTM" in pf.units_note
    assert pf.sizes == ("M",) and pf.size == "M" and pf.style == "clo-pattern"
    for p in pf.pieces:
        cm = p.extent.max() * 0.1
        assert 10 < cm < 150, (p.name, cm)
        assert p.grain is not None and _signed_area(p.outline) > 0
    assert sum(len(p.notches) for p in pf.pieces) >= 9
    assert all(len(p.notches) >= 1 for p in pf.pieces)
    assert any(np.any(p.notch_angles != 0) for p in pf.pieces)


@pytest.mark.slow
@pytest.mark.parametrize("path", [TANK, CLO], ids=["tank", "clo"])
def test_real_files_round_trip(tmp_path, path):
    pf = read_dxf(real(path))
    out = tmp_path / "rt.dxf"
    write_dxf(out, pf, layout="keep")
    back = read_dxf(out, units=pf.units)
    assert [p.name for p in back.pieces] == [p.name for p in pf.pieces]
    for a, b in zip(pf.pieces, back.pieces, strict=True):
        np.testing.assert_allclose(b.outline, a.outline, atol=1e-6 * a.extent.max())
        np.testing.assert_array_equal(b.turn, a.turn)
        np.testing.assert_allclose(b.notches, a.notches, atol=1e-6 * a.extent.max())
        if a.mirror is not None:
            np.testing.assert_allclose(b.mirror, a.mirror, atol=1e-6 * a.extent.max())


def test_real_tank_pieces_are_halves_with_their_fold_line():
    pf = read_dxf(real(TANK))
    for p in pf.pieces:
        assert p.mirror is not None
        # the fold runs along the outline (the centre front / back edge)
        d = np.min(np.linalg.norm(p.outline[:, None] - p.mirror[None], axis=-1), axis=0)
        assert d.max() < 1e-3 * p.extent.max()


@pytest.mark.slow
def test_inspect_real_tank_sizes():
    real(TANK)
    r = CliRunner().invoke(cli, ["inspect", str(TANK)])
    assert r.exit_code == 0, r.output
    assert "2 pieces" in r.output and "showing 36" in r.output and "in (" in r.output
    r26 = CliRunner().invoke(cli, ["inspect", str(TANK), "--size", "26", "--json"])
    info = json.loads(r26.output)
    assert info["size"] == "26" and len(info["sizes"]) == 14
    assert info["pieces"][0]["size_cm"][0] < 63.0


def _outline_extents(path) -> list[list[float]]:
    doc = ezdxf.readfile(path)
    out = []
    for block in doc.blocks:
        for e in block:
            if e.dxftype() == "POLYLINE" and e.dxf.layer == "1":
                P = np.array([[v.dxf.location.x, v.dxf.location.y] for v in e.vertices])
                out.append(np.ptp(P, axis=0).round(6).tolist())
    return sorted(out)


def test_a_recipe_in_metres_writes_its_dxf_in_millimetres(tmp_path):
    """Issue 22: ``units: m`` passed ``validate``, then ``adjust`` computed everything and
    exited 2 at the DXF ("cannot write DXF in 'm'"). Any recipe unit is written: metric in
    millimetres (ASTM/AAMA METRIC), the same file as the same recipe in cm."""
    from ptailor.formats.obj import write_garment
    from ptailor.samples import lantern_sleeve

    g = tmp_path / "sleeve.obj"  # the demo's sleeve with a quarter of its triangles
    write_garment(g, lantern_sleeve(n_around=24, n_sleeve=10, n_cuff=2))
    step = "steps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.2}]\n"
    extents = []
    for unit in ("m", "cm"):
        rec = tmp_path / f"{unit}.yaml"
        rec.write_text(f"units: {unit}\n{step}")
        out = tmp_path / unit
        r = CliRunner().invoke(
            cli, ["adjust", str(g), str(rec), "-o", str(out), "--no-baseline", "-q"]
        )
        assert r.exit_code == 0, r.output
        extents.append(_outline_extents(out / "pattern.dxf"))
    np.testing.assert_allclose(extents[0], extents[1], atol=1e-3)  # mm
