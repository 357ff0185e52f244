"""DXF patterns through ``ptailor adjust``: pieces matched, marks carried, outputs chosen."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from ptailor.cli.main import cli
from ptailor.formats.dxf import read_dxf, write_dxf
from ptailor.formats.obj import write_garment
from ptailor.geometry.segments import nearest_segment_distance
from ptailor.model.garment import panels
from ptailor.model.pieces import PatternFile, Piece
from ptailor.model.polyline import signed_area
from ptailor.pieces.draw import mesh_pieces
from ptailor.samples import SAMPLES
from ptailor.samples.obj_text import sample_obj_text
from tests.conftest import real_path
from tests.test_dxf_roundtrip import _inside

IDENTITY = "steps: []\n"
UNIFORM = "steps: [{op: scale, region: all, direction: uniform, factor: 1.1}]\n"


def run(*args):
    return CliRunner().invoke(cli, [str(a) for a in args], catch_exceptions=False)


def _marked_pieces(g) -> list[Piece]:
    """The garment's mesh pieces plus notches mid-edge, a drill hole and an internal line."""
    out = []
    for pc in mesh_pieces(g.V2, g.F2, panels(g), F3=g.F3):
        P = pc.outline
        mid = 0.5 * (P[[3, 17]] + P[[4, 18]])  # halfway along two outline edges
        c = P.mean(axis=0)
        d = np.array([2.0, 1.0])
        out.append(
            replace(
                pc,
                notches=np.vstack([pc.notches, mid]),
                notch_angles=np.zeros(len(pc.notches) + 2),
                drills=c[None] + [0.5, 0.5],
                mirror=P[[0, 1]],  # along the first outline edge
                internal=(np.stack([c - d, c + d]),),
                quantity=1,
                size="M",
            )
        )
    return out


def _setup(tmp_path, sample="lantern_sleeve", move=None):
    """DXF + drape OBJ for a generated garment, as CLO 3D exports them.

    The DXF is written in mm (METRIC) and the drape's ``vt`` is the same pattern in mm.
    """
    g = SAMPLES[sample]()
    obj = tmp_path / f"{sample}.obj"
    write_garment(obj, g.with_pattern(g.V2 * 10.0), header=[f"{sample}: v in cm, vt in mm"])
    pieces = _marked_pieces(g)
    if move is not None:
        pieces = [move(pc) for pc in pieces]
    dxf = tmp_path / f"{sample}.dxf"
    pf = PatternFile(pieces=tuple(pieces), units="cm", style=sample, size="M", sizes=("M",))
    write_dxf(dxf, pf, layout="keep")
    return obj, dxf, pieces


def _recipe(tmp_path, text):
    p = tmp_path / "r.yaml"
    p.write_text(text)
    return p


def _by_name(pf):
    return {pc.name: pc for pc in pf.pieces}


def _close(a, b, size, rel=1e-6):
    np.testing.assert_allclose(a, b, atol=rel * size)


@pytest.mark.slow
def test_adjust_writes_every_format_by_default(tmp_path):
    obj = tmp_path / "s.obj"
    obj.write_text(sample_obj_text("lantern_sleeve"))
    r = run("adjust", obj, _recipe(tmp_path, UNIFORM), "-o", tmp_path / "o", "-q")
    assert r.exit_code == 0, r.output
    names = sorted(p.name for p in (tmp_path / "o").iterdir())
    assert names == [
        ".ptailor",
        "garment.obj",
        "pattern.dxf",
        "pattern.svg",
        "preview.png",
        "report.json",
    ]
    pf = read_dxf(tmp_path / "o" / "pattern.dxf")
    assert sorted(pc.name for pc in pf.pieces) == ["cuff", "sleeve"]
    report = json.loads((tmp_path / "o" / "report.json").read_text())
    assert [p["source"] for p in report["pattern"]["pieces"]] == ["mesh", "mesh"]


def test_formats_option_writes_only_those(tmp_path):
    obj = tmp_path / "s.obj"
    obj.write_text(sample_obj_text("lantern_sleeve"))
    r = run("adjust", obj, _recipe(tmp_path, IDENTITY), "-o", tmp_path / "o", "--formats", "dxf")
    assert r.exit_code == 0, r.output
    names = sorted(p.name for p in (tmp_path / "o").iterdir())
    assert names == [".ptailor", "pattern.dxf", "report.json"]
    r = CliRunner().invoke(
        cli, ["adjust", str(obj), str(tmp_path / "r.yaml"), "-o", str(tmp_path / "o2"),
              "--formats", "obj,stl"]
    )  # fmt: skip
    assert r.exit_code == 2 and "stl" in r.output and not (tmp_path / "o2").exists()


@pytest.mark.slow
@pytest.mark.parametrize("sample", ["lantern_sleeve", "cone_skirt"])
def test_identity_on_a_dxf_and_its_drape_gives_back_outlines_and_marks(tmp_path, sample):
    obj, dxf, _ = _setup(tmp_path, sample)
    r = run("adjust", dxf, _recipe(tmp_path, IDENTITY), "--drape", obj, "-o", tmp_path / "o")
    assert r.exit_code == 0, r.output
    before = _by_name(read_dxf(dxf))
    after = _by_name(read_dxf(tmp_path / "o" / "pattern.dxf"))
    assert sorted(before) == sorted(after)
    for name, a in before.items():
        b = after[name]
        size = float(np.linalg.norm(a.extent))
        _close(b.outline, a.outline, size)
        assert b.turn.tolist() == a.turn.tolist()
        _close(b.notches, a.notches, size)
        _close(b.grain, a.grain, size)
        _close(b.drills, a.drills, size)
        _close(b.internal[0], a.internal[0], size)
        _close(b.mirror, a.mirror, size)
        assert b.size == "M"
    report = json.loads((tmp_path / "o" / "report.json").read_text())
    recs = report["pattern"]["pieces"]
    assert all(p["source"] == "file" and p["matched_by"] == "position" for p in recs)
    assert report["units"]["pattern"] == "mm" and "METRIC" in report["units"]["pattern_note"]


@pytest.mark.slow
def test_a_uniform_scale_scales_every_mark_and_keeps_the_grain_direction(tmp_path):
    obj, dxf, _ = _setup(tmp_path)
    r = run("adjust", dxf, _recipe(tmp_path, UNIFORM), "--drape", obj, "-o", tmp_path / "o")
    assert r.exit_code == 0, r.output
    before = _by_name(read_dxf(dxf))
    after = _by_name(read_dxf(tmp_path / "o" / "pattern.dxf"))
    for name, a in before.items():
        b = after[name]
        assert abs(signed_area(b.outline)) == pytest.approx(1.21 * abs(signed_area(a.outline)))
        pa = np.vstack([a.notches, a.drills, a.grain, a.mirror])
        pb = np.vstack([b.notches, b.drills, b.grain, b.mirror])
        da = np.linalg.norm(pa[:, None] - pa[None], axis=-1)
        db = np.linalg.norm(pb[:, None] - pb[None], axis=-1)
        np.testing.assert_allclose(db, 1.1 * da, atol=1e-6 * da.max())
        ga, gb = np.diff(a.grain, axis=0)[0], np.diff(b.grain, axis=0)[0]
        assert abs(ga[0] * gb[1] - ga[1] * gb[0]) < 1e-9 * np.dot(ga, ga)  # parallel


@pytest.mark.slow
def test_a_moved_piece_is_matched_by_shape_and_written_where_the_file_had_it(tmp_path):
    c, s = np.cos(np.pi / 2), np.sin(np.pi / 2)
    R, t = np.array([[c, -s], [s, c]]), np.array([400.0, 50.0])

    def move(pc):
        return pc if pc.name != "cuff" else pc.map_points(lambda a: a @ R.T + t)

    obj, dxf, _ = _setup(tmp_path, move=move)
    r = run("adjust", dxf, _recipe(tmp_path, IDENTITY), "--drape", obj, "-o", tmp_path / "o")
    assert r.exit_code == 0, r.output
    a = _by_name(read_dxf(dxf))["cuff"]
    b = _by_name(read_dxf(tmp_path / "o" / "pattern.dxf"))["cuff"]
    size = float(np.linalg.norm(a.extent))
    _close(b.outline, a.outline, size)
    _close(b.notches, a.notches, size)
    _close(b.grain, a.grain, size)
    _close(b.mirror, a.mirror, size)
    recs = {p["name"]: p for p in json.loads((tmp_path / "o" / "report.json").read_text())[
        "pattern"]["pieces"]}  # fmt: skip
    assert recs["cuff"]["matched_by"] == "shape" and recs["sleeve"]["matched_by"] == "position"


@pytest.mark.slow
def test_shorten_drops_the_marks_it_cuts_away_and_outlines_the_new_hem(tmp_path):
    obj, dxf, pieces = _setup(tmp_path, "cone_skirt")
    r = run(
        "adjust", dxf, _recipe(tmp_path, "steps: [{op: shorten, opening: hem, by: 5}]\n"),
        "--drape", obj, "-o", tmp_path / "o",
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    report = json.loads((tmp_path / "o" / "report.json").read_text())
    recs = report["pattern"]["pieces"]
    assert all(p["outline"] == "mesh" for p in recs)
    before = _by_name(read_dxf(dxf))
    after = _by_name(read_dxf(tmp_path / "o" / "pattern.dxf"))
    for pc in pieces:
        b = after[pc.name]
        assert abs(signed_area(b.outline)) < 0.95 * abs(signed_area(before[pc.name].outline))
        assert len(b.drills) == 1 and b.grain is not None


@pytest.mark.slow
def test_seam_allowance_offsets_the_cut_line_and_keeps_the_sew_line(tmp_path):
    obj = tmp_path / "s.obj"
    obj.write_text(sample_obj_text("lantern_sleeve"))
    rec = _recipe(tmp_path, IDENTITY)
    assert run("adjust", obj, rec, "-o", tmp_path / "a", "--formats", "dxf").exit_code == 0
    r = run("adjust", obj, rec, "-o", tmp_path / "b", "--formats", "dxf", "--seam-allowance", "1cm")
    assert r.exit_code == 0, r.output
    plain = _by_name(read_dxf(tmp_path / "a" / "pattern.dxf"))
    sa = _by_name(read_dxf(tmp_path / "b" / "pattern.dxf"))
    for name, a in plain.items():
        b = sa[name]
        _close(b.sew, a.outline, float(np.linalg.norm(a.extent)))
        w, h = a.extent  # mm: the allowance is 10 mm
        assert abs(signed_area(b.outline)) == pytest.approx((w + 20) * (h + 20), rel=1e-6)
    bad = run("adjust", obj, rec, "-o", tmp_path / "c", "--seam-allowance", "-1")
    assert bad.exit_code == 2 and not (tmp_path / "c").exists()


def test_dxf_errors_exit_2_naming_the_file_and_write_nothing(tmp_path):
    obj, dxf, _ = _setup(tmp_path)
    rec = _recipe(tmp_path, IDENTITY)
    r = CliRunner().invoke(cli, ["adjust", str(dxf), str(rec), "-o", str(tmp_path / "o")])
    assert r.exit_code == 2 and str(dxf) in r.output and "--drape" in r.output
    stray = PatternFile(
        pieces=(Piece(name="pocket", outline=np.array([[0.0, 0], [3, 0], [3, 2], [0, 2]]) + 900),),
        units="cm",
    )
    bad = tmp_path / "stray.dxf"
    write_dxf(bad, stray)
    r = CliRunner().invoke(
        cli, ["adjust", str(bad), str(rec), "--drape", str(obj), "-o", str(tmp_path / "o")]
    )
    assert r.exit_code == 2 and "pocket" in r.output and str(bad) in r.output
    assert not (tmp_path / "o").exists()
    novt = tmp_path / "novt.obj"
    novt.write_text("\n".join(ln for ln in obj.read_text().splitlines() if not ln.startswith("vt")))
    r = CliRunner().invoke(
        cli, ["adjust", str(dxf), str(rec), "--drape", str(novt), "-o", str(tmp_path / "o")]
    )
    assert r.exit_code == 2 and str(novt) in r.output
    assert not (tmp_path / "o").exists()


@pytest.mark.slow
def test_units_override_for_a_metric_file(tmp_path):
    obj, dxf, _ = _setup(tmp_path)
    r = run(
        "adjust", dxf, _recipe(tmp_path, IDENTITY), "--drape", obj, "-o", tmp_path / "o",
        "--dxf-units", "mm", "--formats", "dxf",
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    report = json.loads((tmp_path / "o" / "report.json").read_text())
    assert report["units"]["pattern"] == "mm"


@pytest.mark.slow
def test_outputs_are_byte_identical_across_runs(tmp_path, monkeypatch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1700000000")
    obj, dxf, _ = _setup(tmp_path)
    rec = _recipe(tmp_path, UNIFORM)
    for o in ("o1", "o2"):
        assert run("adjust", dxf, rec, "--drape", obj, "-o", tmp_path / o, "-q").exit_code == 0
    for name in ("pattern.dxf", "pattern.svg", "preview.png", "garment.obj"):
        assert (tmp_path / "o1" / name).read_bytes() == (tmp_path / "o2" / name).read_bytes(), name


def test_dxf_pieces_of_a_real_garment_round_trip_through_adjust(tmp_path):
    """tee6: pieces drawn from its mesh, written as DXF, read back with the drape."""
    src = real_path("tee6")
    out = tmp_path / "a"
    r = run(
        "adjust", src, _recipe(tmp_path, IDENTITY), "-o", out, "--formats", "dxf",
        "--pattern-units", "0.3333333cm", "--drape-units", "0.3333333cm", "--no-baseline",
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    pf = read_dxf(out / "pattern.dxf")
    assert len(pf.pieces) == 6
    assert sum(len(pc.notches) for pc in pf.pieces) > 0
    assert all(pc.grain is not None for pc in pf.pieces)
    assert pf.units == "mm"
    sizes = np.array([pc.extent for pc in pf.pieces])
    assert sizes.max() < 2000 and sizes.min() > 50  # plausible garment pieces in mm
    assert Path(out / "pattern.dxf").read_text().count("Piece Name:") == 6


def _flat_drape(pf, path: Path) -> None:
    """A flat 'drape' OBJ triangulating a pattern file's pieces: v in cm, vt in file units.

    Outline points plus an interior grid, Delaunay-triangulated, triangles whose centroid
    falls outside the outline dropped: the mesh's boundary is close to, not equal to, the
    DXF outline (as a simulator's mesh is).
    """
    from scipy.spatial import Delaunay

    from ptailor.model.garment import Garment
    from ptailor.model.units import CM_PER

    k = CM_PER[pf.units]
    V, F, group, names = [], [], [], []
    n = 0
    for i, pc in enumerate(pf.pieces):
        P = pc.outline
        step = 0.04 * float(pc.extent.max())
        lo, hi = P.min(0), P.max(0)
        gx, gy = np.meshgrid(np.arange(lo[0], hi[0], step), np.arange(lo[1], hi[1], step))
        grid = np.stack([gx.ravel(), gy.ravel()], 1)
        inside = _inside(grid, P)
        far = np.min(np.linalg.norm(grid[:, None] - P[None], axis=-1), axis=1) > 0.5 * step
        pts = np.vstack([P, grid[inside & far]])
        tri = Delaunay(pts).simplices
        keep = _inside(pts[tri].mean(axis=1), P)
        tri = tri[keep]
        V.append(pts)
        F.append(tri + n)
        group.append(np.full(len(tri), i))
        names.append(pc.name)
        n += len(pts)
    V2 = np.vstack(V)
    g = Garment(
        V3=np.column_stack([V2 * k, np.zeros(len(V2))]),
        F3=np.vstack(F),
        V2=V2,
        F2=np.vstack(F),
        face_group=np.concatenate(group),
        group_names=tuple(names),
        units="cm",
    )
    write_garment(path, g, header=["flat drape of a DXF: v in cm, vt in the DXF's units"])


CLO = Path(__file__).resolve().parents[2] / "shared" / "dxf" / "clo-pattern.dxf"


@pytest.mark.slow  # a real CAD pattern, two runs: 1.2 s
@pytest.mark.skipif(not CLO.is_file(), reason="../shared/dxf is absent")
def test_a_real_clo_pattern_through_identity_and_a_uniform_scale(tmp_path):
    pf = read_dxf(CLO)
    drape = tmp_path / "clo.obj"
    _flat_drape(pf, drape)
    before = _by_name(pf)
    for name, text, k in (("id", IDENTITY, 1.0), ("up", UNIFORM, 1.1)):
        out = tmp_path / name
        r = run("adjust", CLO, _recipe(tmp_path, text), "--drape", drape, "-o", out,
                "--formats", "dxf", "--no-baseline")  # fmt: skip
        assert r.exit_code == 0, r.output
        after = _by_name(read_dxf(out / "pattern.dxf"))
        assert sorted(after) == sorted(before)
        for pname, a in before.items():
            b = after[pname]
            size = float(np.linalg.norm(a.extent))
            assert len(b.notches) == len(a.notches) and b.grain is not None
            if k == 1.0:
                _close(b.outline, a.outline, size)
                _close(b.notches, a.notches, size)
                _close(b.grain, a.grain, size)
            else:
                ratio = abs(signed_area(b.outline)) / abs(signed_area(a.outline))
                assert ratio == pytest.approx(k * k, rel=1e-6)
        report = json.loads((out / "report.json").read_text())
        assert report["units"]["pattern"] == "mm"
        assert all(p["source"] == "file" for p in report["pattern"]["pieces"])


@pytest.mark.slow
@pytest.mark.parametrize("sample", ["lantern_sleeve", "cone_skirt"])
def test_cut_lines_with_a_seam_allowance_match_the_mesh_of_the_sew_line(tmp_path, sample):
    """A CAD cut line 1 cm outside the drape's mesh (no sew line in the file) still matches,
    and an identity edit gives it back; the report shows the 1 cm."""
    from ptailor.model.offset import offset_closed
    from ptailor.model.polyline import corners

    def allowance(pc):
        cut = offset_closed(pc.outline, 1.0)
        return replace(pc, outline=cut, turn=corners(cut))

    obj, dxf, _ = _setup(tmp_path, sample, move=allowance)
    r = run("adjust", dxf, _recipe(tmp_path, IDENTITY), "--drape", obj, "-o", tmp_path / "o",
            "--formats", "dxf")  # fmt: skip
    assert r.exit_code == 0, r.output
    before = _by_name(read_dxf(dxf))
    after = _by_name(read_dxf(tmp_path / "o" / "pattern.dxf"))
    for name, a in before.items():
        _close(after[name].outline, a.outline, float(np.linalg.norm(a.extent)))
    recs = json.loads((tmp_path / "o" / "report.json").read_text())["pattern"]["pieces"]
    for p in recs:
        assert p["matched_by"] == "position"
        assert p["match_distance"] == pytest.approx(1.0, rel=0.05)  # cm, the report's unit


@pytest.mark.slow
def test_a_piece_cut_twice_matches_both_panels_and_is_written_as_two(tmp_path):
    """The skirt's back is a copy of its front: a file holding only the front with
    quantity 2 covers both panels; each instance is written with quantity 1."""
    g = SAMPLES["cone_skirt"]()
    obj = tmp_path / "skirt.obj"
    write_garment(obj, g.with_pattern(g.V2 * 10.0), header=["v in cm, vt in mm"])
    front = next(pc for pc in _marked_pieces(g) if pc.name == "front")
    front = replace(front.map_points(lambda a: a * 10.0), quantity=2)
    dxf = tmp_path / "skirt.dxf"
    write_dxf(dxf, PatternFile(pieces=(front,), units="mm", size="M"), layout="keep")
    r = run("adjust", dxf, _recipe(tmp_path, UNIFORM), "--drape", obj, "-o", tmp_path / "o",
            "--formats", "dxf")  # fmt: skip
    assert r.exit_code == 0, r.output
    out = _by_name(read_dxf(tmp_path / "o" / "pattern.dxf"))
    assert sorted(out) == ["front", "front-2"]
    assert [p.quantity for p in out.values()] == [1, 1]
    for p in out.values():
        assert abs(signed_area(p.outline)) == pytest.approx(1.21 * abs(signed_area(front.outline)))
        assert len(p.notches) == len(front.notches) and len(p.drills) == 1
    recs = json.loads((tmp_path / "o" / "report.json").read_text())["pattern"]["pieces"]
    assert {(p["name"], p["panel"], p["source"]) for p in recs} == {
        ("front", "front", "file"),
        ("front-2", "back", "file"),
    }


@pytest.mark.slow
def test_extend_drops_the_notches_it_leaves_inside_the_piece(tmp_path):
    obj, dxf, _ = _setup(tmp_path, "cone_skirt")
    before = _by_name(read_dxf(dxf))
    r = run("adjust", dxf, _recipe(tmp_path, "steps: [{op: extend, opening: hem, by: 5}]\n"),
            "--drape", obj, "-o", tmp_path / "o", "--formats", "dxf")  # fmt: skip
    assert r.exit_code == 0, r.output
    after = _by_name(read_dxf(tmp_path / "o" / "pattern.dxf"))
    report = json.loads((tmp_path / "o" / "report.json").read_text())
    dropped = sum(p["marks_dropped"] for p in report["pattern"]["pieces"])
    kept = sum(len(p.notches) for p in after.values())
    assert kept + dropped == sum(len(p.notches) for p in before.values())
    for name, b in after.items():
        size = float(np.linalg.norm(b.extent))
        assert abs(signed_area(b.outline)) > abs(signed_area(before[name].outline))
        if len(b.notches):  # every notch left is on the new outline
            A, B = b.outline, np.roll(b.outline, -1, axis=0)
            assert nearest_segment_distance(b.notches, A, B).max() < 1e-3 * size
