"""The DXF reader fails closed (issue 12): every traceback signature of the DXF fuzzing
campaign as a regression test, plus the size limits. Each bad file is exit 2 with one line
naming the file and the piece or entity, and nothing else printed."""

from __future__ import annotations

import itertools
import re
from pathlib import Path

import pytest
from click.testing import CliRunner

from ptailor import tolerances
from ptailor.cli.main import cli
from ptailor.errors import PtailorError
from ptailor.formats.dxf import read_dxf

from .conftest import SHARED

CORPUS = Path(__file__).parent / "corpus" / "dxf"


def square(tmp_path: Path, name: str = "good.dxf", **kw) -> Path:
    """A one-piece R12 pattern (block FRONT: a 100 x 80 square, turn points, a notch, a
    grain line), written with ezdxf; ``kw`` changes it (see the keys below)."""
    from ezdxf.document import Drawing

    doc = Drawing.new("R12")
    blk = doc.blocks.new("FRONT")
    outline = kw.get("outline", [(0, 0), (100, 0), (100, 80), (0, 80)])
    blk.add_polyline2d(outline, close=True, dxfattribs={"layer": "1"})
    for q in kw.get("turn", outline):
        blk.add_point(q, dxfattribs={"layer": "2"})
    blk.add_point(kw.get("notch", (50, 0)), dxfattribs={"layer": "4"})
    blk.add_line((50, 10), (50, 70), dxfattribs={"layer": "7"})
    blk.add_text(f"Piece Name: {kw.get('piece', 'FRONT')}", dxfattribs={"layer": "1"})
    blk.add_text(f"Quantity: {kw.get('quantity', 1)}", dxfattribs={"layer": "1"})
    doc.modelspace().add_blockref("FRONT", (0, 0), dxfattribs=kw.get("insert", {}))
    doc.modelspace().add_text("Units: METRIC")
    p = tmp_path / name
    doc.saveas(p)
    return p


def edited(path: Path, fn) -> Path:
    """``path`` with its lines (group code, value, ...) changed by ``fn(lines) -> lines``."""
    lines = path.read_text().splitlines()
    path.write_text("\n".join(fn(lines)) + "\n")
    return path


def vertex_value(lines: list[str], vertex: int, code: str, value: str | None) -> list[str]:
    """Set (or, with None, drop) group ``code`` of the ``vertex``-th VERTEX."""
    seen = -1
    for i in range(0, len(lines) - 1, 2):
        if lines[i].strip() == "0" and lines[i + 1].strip() == "VERTEX":
            seen += 1
            if seen == vertex:
                j = i + 2
                while lines[j].strip() != "0":
                    if lines[j].strip() == code:
                        if value is None:
                            return lines[:j] + lines[j + 2 :]
                        return [*lines[: j + 1], value, *lines[j + 2 :]]
                    j += 2
    raise AssertionError(f"no VERTEX {vertex} with group {code}")


def cli_fails(path: Path, *args: str, match: str) -> str:
    """``ptailor inspect PATH`` exits 2 with one line naming the file and matching."""
    r = CliRunner().invoke(cli, ["inspect", str(path), *args])
    assert r.exit_code == 2, (r.exit_code, r.output, r.exception)
    out = r.output.strip()
    assert len(out.splitlines()) == 1, out
    assert str(path) in out
    assert re.search(match, out), out
    return out


def test_the_good_square_reads(tmp_path):
    pf = read_dxf(square(tmp_path))
    (p,) = pf.pieces
    assert p.name == "FRONT" and len(p.outline) == 4 and p.turn.all() and len(p.notches) == 1
    assert pf.warnings == ()


# ---- the signatures of the campaign ---------------------------------------------------------


def test_vertex_without_x(tmp_path):
    """``_xy``: TypeError 'NoneType' object is not subscriptable."""
    p = edited(square(tmp_path), lambda ls: vertex_value(ls, 2, "10", None))
    cli_fails(p, match=r"piece 'FRONT': boundary POLYLINE \d+ \(layer 1\): vertex 2 has no")


def test_vertex_without_location(tmp_path):
    def drop_xy(ls):
        return vertex_value(vertex_value(ls, 1, "10", None), 1, "20", None)

    p = edited(square(tmp_path), drop_xy)
    cli_fails(p, match=r"piece 'FRONT': .*vertex 1")


@pytest.mark.parametrize("kind", ["FOO", "garbage"])
def test_unknown_entity_type_is_skipped(tmp_path, kind):
    """ezdxf's DXFAttributeError ('Invalid DXF attribute "layer" for entity garbage'): an
    entity type the reader does not use is skipped, as CAD importers do."""

    def rename_notch(ls):
        # the notch is the 5th POINT (after four turn points)
        idx = [i for i in range(0, len(ls) - 1, 2) if ls[i].strip() == "0" and ls[i + 1] == "POINT"]
        ls[idx[4] + 1] = kind
        return ls

    p = edited(square(tmp_path), rename_notch)
    (piece,) = read_dxf(p).pieces
    assert len(piece.notches) == 0 and len(piece.outline) == 4
    r = CliRunner().invoke(cli, ["inspect", str(p)])
    assert r.exit_code == 0, r.output


def test_unknown_entity_type_on_the_cut_line(tmp_path):
    """The only layer-1 entity renamed: no piece, exit 2, not a traceback."""

    def rename_polyline(ls):
        i = next(i for i in range(0, len(ls) - 1, 2) if ls[i + 1] == "POLYLINE")
        ls[i + 1] = "garbage"
        return ls

    p = edited(square(tmp_path), rename_polyline)
    cli_fails(p, match="no pattern pieces|not a readable DXF|not a usable DXF")


def test_one_vertex_cut_line(tmp_path):
    """``_diag``: np.vstack of no arrays."""
    p = square(tmp_path, outline=[(0, 0)], turn=[])
    cli_fails(p, match=r"piece 'FRONT': boundary POLYLINE \d+ \(layer 1\): has 1 vertex")


def test_no_vertex_cut_line(tmp_path):
    def drop_vertices(ls):
        out, skip = [], False
        for i in range(0, len(ls) - 1, 2):
            code, val = ls[i], ls[i + 1]
            if code.strip() == "0":
                skip = val == "VERTEX"
            if not skip:
                out += [code, val]
        return out

    p = edited(square(tmp_path), drop_vertices)
    cli_fails(p, match=r"piece 'FRONT': the boundary \(layer 1\) has no line")


@pytest.mark.parametrize(
    ("value", "says"),
    [
        ("1e300", r"vertex 3 lies 1e\+300 units from the origin \(limit 1e\+07\)"),
        ("-1e300", r"vertex 3 lies 1e\+300 units"),
        ("1e308", r"vertex 3 lies"),
        ("inf", "vertex 3 is infinite"),
        ("nan", "vertex 3 is not a number"),
        ("NaN", "vertex 3 is not a number"),
    ],
)
def test_extreme_boundary_coordinate(tmp_path, value, says):
    """``_Curve`` (1e300); a NaN vertex was 'does not close, its ends 0 apart'."""
    p = edited(square(tmp_path), lambda ls: vertex_value(ls, 3, "10", value))
    out = cli_fails(p, match=rf"piece 'FRONT': boundary POLYLINE \d+ \(layer 1\): {says}")
    assert "does not close" not in out


@pytest.mark.parametrize("value", ["inf", "-inf", "nan", "1e300"])
def test_extreme_turn_point(tmp_path, value):
    """cKDTree ('data must be finite') on an inf turn point."""
    p = square(tmp_path, turn=[(0, 0), (100, 0), (100, 80), (0, 80), (1.5, 2.5)])
    p = edited(p, lambda ls: [value if v == "1.5" else v for v in ls])
    cli_fails(p, match=r"piece 'FRONT': turn point POINT \d+ \(layer 2\): its point (is|lies)")


def test_extreme_notch_angle(tmp_path):
    from ezdxf.document import Drawing

    doc = Drawing.new("R12")
    blk = doc.blocks.new("FRONT")
    blk.add_polyline2d(
        [(0, 0), (100, 0), (100, 80), (0, 80)], close=True, dxfattribs={"layer": "1"}
    )
    blk.add_point((50, 0), dxfattribs={"layer": "4", "angle": 12.5})
    doc.modelspace().add_blockref("FRONT", (0, 0))
    p = tmp_path / "angle.dxf"
    doc.saveas(p)
    edited(p, lambda ls: ["nan" if v.strip() == "12.5" else v for v in ls])
    cli_fails(p, match=r"piece 'FRONT': notch POINT \d+ \(layer 4\): has an angle")


def test_insert_scale_out_of_range(tmp_path):
    p = square(tmp_path, insert={"xscale": 1e299, "yscale": 1e299})
    cli_fails(p, match=r"piece 'FRONT': boundary POLYLINE \d+ \(layer 1\): placed by its INSERT")


def test_insert_scale_not_a_number(tmp_path):
    p = square(tmp_path, insert={"xscale": 7.25})
    p = edited(p, lambda ls: ["nan" if v.strip() == "7.25" else v for v in ls])
    cli_fails(p, match=r"FRONT")


def test_degenerate_outlines(tmp_path):
    line = square(tmp_path, "line.dxf", outline=[(0, 0), (50, 0), (100, 0), (60, 0)])
    cli_fails(line, match=r"piece 'FRONT': the boundary encloses no area")
    tiny = square(tmp_path, "tiny.dxf", outline=[(0, 0), (1e-5, 0), (1e-5, 1e-5), (0, 1e-5)])
    cli_fails(tiny, match=r"piece 'FRONT': the boundary spans 1e-05 units")


def test_header_units_extremes(tmp_path):
    """``$INSUNITS`` of 1e300 or NaN says nothing (was int() of a float: OverflowError)."""
    p = square(tmp_path)
    text = p.read_text()
    for value in ("1e300", "nan", "99999999999999999999"):
        q = tmp_path / f"units_{value}.dxf"
        q.write_text(
            text.replace("HEADER\n", f"HEADER\n  9\n$INSUNITS\n 70\n{value}\n", 1),
        )
        r = CliRunner().invoke(cli, ["inspect", str(q)])
        assert r.exit_code in (0, 2), (r.output, r.exception)
        if r.exit_code == 2:
            assert len(r.output.strip().splitlines()) == 1


# ---- ezdxf's recover mode: nothing printed ----------------------------------------------


def recovered(tmp_path: Path) -> Path:
    """A file only recover mode reads: a coordinate with trailing junk (``0.0abc``), which
    recover mode reads as ``0.0`` and logs."""
    return edited(square(tmp_path), _junk_float)


def _junk_float(ls: list[str]) -> list[str]:
    return vertex_value(ls, 1, "20", "0.0abc")


def test_recover_mode_lines_are_report_warnings_not_output(tmp_path, capfd):
    p = recovered(tmp_path)
    pf = read_dxf(p)
    assert len(pf.pieces) == 1
    assert any("recover mode" in w and "recovered invalid floating point" in w for w in pf.warnings)
    captured = capfd.readouterr()
    assert captured.out == "" and captured.err == ""
    r = CliRunner().invoke(cli, ["inspect", str(p)])
    assert r.exit_code == 0 and "recovered" not in r.output


def test_recover_mode_lines_before_an_error_are_not_printed(tmp_path, capfd):
    p = edited(recovered(tmp_path), lambda ls: vertex_value(ls, 3, "10", "nan"))
    with pytest.raises(PtailorError, match="vertex 3 is not a number"):
        read_dxf(p)
    captured = capfd.readouterr()
    assert captured.out == "" and captured.err == ""
    out = cli_fails(p, match="vertex 3 is not a number")
    assert "recovered" not in out


# ---- bounded sizes ------------------------------------------------------------------------


def test_file_size_limit(tmp_path, monkeypatch):
    p = square(tmp_path)
    monkeypatch.setattr(tolerances, "DXF_MAX_BYTES", 1000)
    cli_fails(p, match=r"the file is \d+ bytes, over the limit of 1000")


def test_entity_count_limit(tmp_path, monkeypatch):
    p = square(tmp_path)
    monkeypatch.setattr(tolerances, "DXF_MAX_ENTITIES", 5)
    cli_fails(p, match=r"\d+ entities, over the limit of 5")


def test_vertices_per_polyline_limit(tmp_path, monkeypatch):
    p = square(tmp_path)
    monkeypatch.setattr(tolerances, "DXF_MAX_VERTICES", 3)
    cli_fails(p, match=r"piece 'FRONT': boundary POLYLINE \d+ \(layer 1\): has 4 vertices")


def test_boundary_parts_limit(tmp_path, monkeypatch):
    from ezdxf.document import Drawing

    doc = Drawing.new("R12")
    blk = doc.blocks.new("BACK")
    pts = [(0, 0), (100, 0), (100, 80), (0, 80), (0, 0)]
    for a, b in itertools.pairwise(pts):
        blk.add_line(a, b, dxfattribs={"layer": "1"})
    doc.modelspace().add_blockref("BACK", (0, 0))
    p = tmp_path / "lines.dxf"
    doc.saveas(p)
    assert len(read_dxf(p).pieces[0].outline) == 4
    monkeypatch.setattr(tolerances, "DXF_MAX_BOUNDARY_PARTS", 3)
    cli_fails(p, match=r"piece 'BACK': the boundary \(layer 1\) comes in 4 parts \(limit 3\)")


def test_text_length_limit(tmp_path):
    long = "N" * (tolerances.DXF_MAX_TEXT + 1)
    p = square(tmp_path, piece=long)
    cli_fails(p, match=rf"TEXT \d+ \(layer 1\): has {len(long) + 12} characters of text")


def test_quantity_limit(tmp_path):
    p = square(tmp_path, quantity="99999999999999999999")
    cli_fails(p, match=r"piece 'FRONT': 'Quantity: 9+' is over the limit of 1000")


@pytest.mark.parametrize("text", ["1e300", "-1", "nan", "two", "1.5", "3,-1", "inf"])
def test_a_quantity_that_is_not_a_count_names_the_piece(tmp_path, text):
    """Issue 22: these were read as 1, silently, and the output carried both
    ``Quantity: 1`` and the original text."""
    p = square(tmp_path, quantity=text)
    cli_fails(p, match=r"piece 'FRONT': 'Quantity: .*' is not a count")


@pytest.mark.parametrize(("text", "count"), [("2", 2), ("2.0", 2), ("1,1", 2), (" 3 ", 3)])
def test_a_quantity_that_is_a_count_is_read_once(tmp_path, text, count):
    (piece,) = read_dxf(square(tmp_path, quantity=text)).pieces
    assert piece.quantity == count
    assert not any("QUANTITY" in a.upper() for a in piece.annotations)


# ---- the checked-in corpus ----------------------------------------------------------------

#: tests/corpus/dxf: file -> what its one-line message says
EXPECTED = {
    "vertex_without_x.dxf": r"piece 'FRONT': boundary POLYLINE \d+ \(layer 1\): vertex 2 has no",
    "one_vertex_cut_line.dxf": r"piece 'FRONT': boundary POLYLINE \d+ \(layer 1\): has 1 vertex",
    "x_1e300.dxf": r"vertex 3 lies 1e\+300 units from the origin",
    "inf_turn_point.dxf": r"turn point POINT \d+ \(layer 2\): its point is infinite",
    "nan_vertex.dxf": r"piece 'FRONT': boundary POLYLINE \d+ \(layer 1\): vertex 3 is not a number",
    "nan_vertex_recover_mode.dxf": r"vertex 3 is not a number",
    "collinear_outline.dxf": "encloses no area",
    "huge_quantity.dxf": "over the limit of 1000",
}


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_corpus(name, tmp_path, capfd):
    p = CORPUS / name
    assert p.is_file(), f"{p} missing from the corpus"
    cli_fails(p, match=EXPECTED[name])
    captured = capfd.readouterr()
    assert captured.out == "" and captured.err == ""


def test_corpus_unknown_entity_reads(tmp_path):
    (piece,) = read_dxf(CORPUS / "unknown_entity.dxf").pieces
    assert len(piece.outline) == 4


# ---- the shared real files, mutated -------------------------------------------------------


@pytest.mark.slow
@pytest.mark.parametrize("fixture", ["clo-pattern.dxf", "WM_SLIM_TANK.DXF"])
@pytest.mark.parametrize("value", ["nan", "1e300", "inf"])
def test_shared_fixture_with_an_extreme_coordinate(tmp_path, fixture, value):
    src = SHARED / "dxf" / fixture
    if not src.is_file():
        pytest.skip(f"{src} not available (../shared is absent)")
    lines = src.read_bytes().decode("latin-1").splitlines()
    # the first group 10 after the first layer-1 POLYLINE (or LWPOLYLINE) of a block
    start = next(i for i in range(len(lines) - 1) if lines[i].strip() in ("POLYLINE", "LWPOLYLINE"))
    j = next(j for j in range(start, len(lines) - 1) if lines[j].strip() == "10" and j > start + 2)
    j = next(k for k in range(j + 2, len(lines) - 1) if lines[k].strip() == "10")  # a vertex
    lines[j + 1] = value
    p = tmp_path / fixture
    p.write_bytes(("\n".join(lines) + "\n").encode("latin-1"))
    r = CliRunner().invoke(cli, ["inspect", str(p)])
    assert r.exit_code in (0, 2), (r.output, r.exception)
    if r.exit_code == 2:
        out = r.output.strip()
        assert len(out.splitlines()) == 1 and str(p) in out
        assert "piece" in out or "modelspace" in out, out


def test_locate_points_refuses_non_finite_points():
    """The k-d tree behind mark transfer (cKDTree: 'data must be finite') never sees NaN."""
    import numpy as np

    from ptailor.method.transfer import locate_points

    V = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    F = np.array([[0, 1, 2]])
    assert locate_points(V, F, np.array([[0.2, 0.2]])).distance[0] == 0.0
    with pytest.raises(PtailorError, match="point 1 is not a finite number"):
        locate_points(V, F, np.array([[0.2, 0.2], [np.inf, 0.0]]))
    with pytest.raises(PtailorError, match="vertex that is not a finite number"):
        locate_points(np.array([[0.0, 0.0], [np.nan, 0.0], [0.0, 1.0]]), F, np.zeros((1, 2)))


@pytest.mark.slow
def test_many_shuffled_boundary_parts_chain_in_linear_time(tmp_path):
    """Chaining looked at every remaining part for each join (quadratic: 74 s for 5,000
    shuffled LINEs); ends are now found on a grid of cells."""
    import random
    import time

    import numpy as np
    from ezdxf.document import Drawing

    n = 3000
    t = np.linspace(0, 2 * np.pi, n + 1)
    pts = np.c_[100 * np.cos(t), 80 * np.sin(t)]
    order = list(range(n))
    random.Random(1).shuffle(order)
    doc = Drawing.new("R12")
    blk = doc.blocks.new("OVAL")
    for i in order:
        a, b = pts[i].tolist(), pts[i + 1].tolist()
        blk.add_line(*((b, a) if i % 3 == 0 else (a, b)), dxfattribs={"layer": "1"})
    doc.modelspace().add_blockref("OVAL", (0, 0))
    p = tmp_path / "oval.dxf"
    doc.saveas(p)
    t0 = time.perf_counter()
    (piece,) = read_dxf(p).pieces
    assert time.perf_counter() - t0 < 30.0
    assert len(piece.outline) == n


def test_writer_refuses_non_finite_marks(tmp_path):
    """No NaN on disk: a piece whose marks went non-finite is refused before writing."""
    from dataclasses import replace

    import numpy as np

    from ptailor.formats.dxf import write_dxf
    from ptailor.model.pieces import PatternFile

    (piece,) = read_dxf(square(tmp_path)).pieces
    bad = PatternFile(pieces=(piece,), units="mm")
    write_dxf(tmp_path / "ok.dxf", bad)
    bad = replace(bad, pieces=(replace(piece, notches=np.array([[np.nan, 0.0]])),))
    with pytest.raises(PtailorError, match=r"'FRONT': a mark .* is not a finite number"):
        write_dxf(tmp_path / "bad.dxf", bad)
    assert not (tmp_path / "bad.dxf").exists()


def test_text_utf8_cannot_carry_is_made_printable():
    """Campaign seed 31 (fuzz_dxf): a piece name decoded with lone surrogates crashed
    ``inspect``'s printing (UnicodeEncodeError); such text is read as ``?``."""
    from ptailor.formats.dxf import printable_text as _printable

    assert _printable("cu\udcff\udcfeff") == "cu??ff"
    assert _printable("Ärmel – links") == "Ärmel – links"
    "".join(_printable("x\ud800y")).encode("utf-8")  # encodable now
