"""Graded nests (issue 45, item 3): ``--sizes`` adjusts every size of a graded DXF as the
drape's size was, each keeping its grade (graded_s = adjusted_base + original_s -
original_base), and ``inspect`` shows each size's grade."""

from __future__ import annotations

import json
from dataclasses import replace

import ezdxf
import numpy as np
import pytest
from click.testing import CliRunner

from ptailor.cli.main import cli
from ptailor.formats.dxf import read_dxf, read_dxf_sizes
from ptailor.formats.obj import write_garment
from ptailor.model.correspond import Places, at_places, by_length, corresponding, nearest_places
from ptailor.model.garment import panels
from ptailor.pieces import mesh_pieces
from ptailor.samples import SAMPLES
from tests.conftest import SHARED

TANK = SHARED / "dxf" / "WM_SLIM_TANK.DXF"
UNIFORM = "steps: [{op: scale, region: all, direction: uniform, factor: 1.1}]\n"
SHORTER = "units: cm\nsteps: [{op: shorten, opening: hem, by: 5}]\n"
SIZES = ("S", "M", "L")


def run(*args):
    return CliRunner().invoke(cli, [str(a) for a in args], catch_exceptions=False)


def grade(size: str, P: np.ndarray, c: np.ndarray) -> np.ndarray:
    """The known grade of ``size`` from M at points ``P`` (mm): wider and longer with a
    wobble, so no affine map undoes it; S the other way."""
    a = {"S": -1.0, "M": 0.0, "L": 1.0}[size]
    d = P - c
    return a * np.c_[0.05 * d[:, 0], 0.03 * d[:, 1] + 2.0 * np.sin(d[:, 0] / 40.0)]


def _points(blk, pts, layer):
    for q in np.asarray(pts).reshape(-1, 2):
        blk.add_point(q.tolist(), dxfattribs={"layer": layer})


def graded_nest(tmp_path, *, dense_l: bool = False):
    """The generated skirt's drape (v in cm, vt in mm) and ptailor's pieces of it graded
    into S, M (the sample) and L by :func:`grade`, written with ezdxf; ``dense_l``: size L's
    outlines have a point between every two (they no longer correspond point by point)."""
    g = SAMPLES["cone_skirt"]()
    obj = tmp_path / "skirt.obj"
    write_garment(obj, g.with_pattern(g.V2 * 10.0), header=["v in cm, vt in mm"])
    pieces = []
    for pc in mesh_pieces(g.V2 * 10.0, g.F2, panels(g), F3=g.F3, V3=g.V3):
        c = pc.outline.mean(axis=0)
        drills = c + np.array([[-0.2, 0.0], [0.2, 0.0]]) * pc.extent[0]
        pieces.append(replace(pc, name=pc.name.upper(), drills=drills))
    doc = ezdxf.new("R2000")
    for size in SIZES:
        for pc in pieces:
            c = pc.outline.mean(axis=0)
            P = pc.outline
            if dense_l and size == "L":
                P = np.repeat(P, 2, axis=0)
                P[1::2] = 0.5 * (pc.outline + np.roll(pc.outline, -1, axis=0))
            blk = doc.blocks.new(f"{pc.name}_{size}")
            blk.add_lwpolyline((P + grade(size, P, c)).tolist(), close=True,
                               dxfattribs={"layer": "1"})  # fmt: skip
            _points(blk, pc.notches + grade(size, pc.notches, c), "4")
            _points(blk, pc.drills + grade(size, pc.drills, c), "13")
            G = pc.grain + grade(size, pc.grain, c)
            blk.add_line(G[0].tolist(), G[1].tolist(), dxfattribs={"layer": "7"})
            if size == "M":
                _points(blk, pc.outline[pc.turn], "2")
            for i, t in enumerate((f"Piece Name: {pc.name}", f"Size: {size}", "Quantity: 1")):
                blk.add_text(t, dxfattribs={"layer": "1", "insert": (c[0], c[1] - 20 * i)})
            doc.modelspace().add_blockref(blk.name, (0, 0))
    doc.modelspace().add_text("Sample Size: M", dxfattribs={"layer": "1"})
    doc.modelspace().add_text("Units: METRIC", dxfattribs={"layer": "1"})
    doc.saveas(tmp_path / "graded.dxf")
    return tmp_path / "graded.dxf", obj


def _recipe(tmp_path, text):
    p = tmp_path / "r.yaml"
    p.write_text(text)
    return p


def _rule(adjusted_m, orig_s, orig_m):
    """The additive rule, outline by outline: adjusted M + (size s - M), ``(k, 2)``."""
    return adjusted_m + (orig_s - orig_m)


@pytest.mark.slow  # two runs of the generated skirt: 2-3 s
def test_sizes_all_keeps_every_grade_and_the_sample_equals_the_single_size_run(tmp_path):
    dxf, obj = graded_nest(tmp_path)
    rec = _recipe(tmp_path, UNIFORM)
    common = ("--drape", obj, "--no-baseline", "--formats", "dxf")
    r = run("adjust", dxf, rec, "-o", tmp_path / "one", *common)
    assert r.exit_code == 0, r.output
    r = run("adjust", dxf, rec, "-o", tmp_path / "all", "--sizes", "all", *common)
    assert r.exit_code == 0, r.output
    out = tmp_path / "all"
    rep = json.loads((out / "report.json").read_text())
    assert sorted(rep["outputs"]) == sorted(
        ["report.json", "pattern.dxf", *(f"pattern_{s}.dxf" for s in SIZES)]
    )
    grading = rep["pattern"]["grading"]
    assert grading["base_size"] == "M" and grading["sizes"] == list(SIZES)
    assert {p["outline"] for p in grading["pieces"]} == {"point by point"}
    single = read_dxf(tmp_path / "one" / "pattern.dxf")
    nest = {p.size: p for p in read_dxf_sizes(out / "pattern.dxf")}
    assert tuple(nest) == SIZES
    orig = {p.size: p for p in read_dxf_sizes(dxf)}
    gaps = {}
    for s in SIZES:
        alone = read_dxf(out / f"pattern_{s}.dxf")
        assert alone.size == s and len(alone.pieces) == len(single.pieces) == 2
        for a, b in zip(alone.pieces, nest[s].pieces, strict=True):
            np.testing.assert_allclose(a.outline, b.outline, atol=1e-6)  # the nest holds it
        for pa, pm, ps, pm0 in zip(
            alone.pieces, single.pieces, orig[s].pieces, orig["M"].pieces, strict=True
        ):
            assert pa.name == pm.name and pa.size == s
            want = _rule(pm.outline, ps.outline, pm0.outline)
            gaps[s, pa.name] = float(np.abs(pa.outline - want).max())
            for what in ("notches", "drills", "grain"):
                got = getattr(pa, what)
                assert len(got) == len(getattr(pm, what)) > 0, (s, pa.name, what)
                exp = _rule(getattr(pm, what), getattr(ps, what), getattr(pm0, what))
                assert np.abs(got - exp).max() < 0.5, (s, pa.name, what)
    # the sample size is the single-size run (0.1 mm), the others follow the rule (0.5 mm)
    assert max(v for (s, _), v in gaps.items() if s == "M") < 0.1
    assert max(gaps.values()) < 0.5
    # and the grade is real: the sizes differ by centimetres after the adjustment too
    assert np.abs(nest["L"].pieces[0].outline - nest["M"].pieces[0].outline).max() > 10.0


@pytest.mark.slow  # one run of the generated skirt and a shortened hem: 1-2 s
def test_a_changed_panel_and_points_that_do_not_correspond_go_by_length(tmp_path):
    """Size L has a point between every two of M's; the hem shortened changes the panels
    (their outline is the mesh's): L keeps its grade within 0.5 mm of the rule, read along
    the outlines, and a warning names each piece of L."""
    dxf, obj = graded_nest(tmp_path, dense_l=True)
    out = tmp_path / "o"
    r = run("adjust", dxf, _recipe(tmp_path, SHORTER), "--drape", obj, "-o", out, "--sizes",
            "M,L", "--no-baseline", "--formats", "dxf")  # fmt: skip
    assert r.exit_code == 0, r.output
    rep = json.loads((out / "report.json").read_text())
    warned = [w for w in rep["warnings"] if w.startswith("size L: piece")]
    assert len(warned) == 2 and all("by length between turn points" in w for w in warned)
    assert {p["outline"] for p in rep["pattern"]["pieces"]} == {"mesh"}
    nest = {p.size: p for p in read_dxf_sizes(out / "pattern.dxf")}
    orig = {p.size: p for p in read_dxf_sizes(dxf)}
    for pm, pl, pm0, pl0 in zip(
        nest["M"].pieces, nest["L"].pieces, orig["M"].pieces, orig["L"].pieces, strict=True
    ):
        c = pm0.outline.mean(axis=0)
        # above the new hem the shortened M is the original: there L is M + L's grade
        on = np.hypot(*(pm.outline[:, None] - pm0.outline[None]).transpose(2, 0, 1)).min(1) < 1e-6
        assert 10 < on.sum() < len(pm.outline)
        want = pm.outline[on] + grade("L", pm.outline[on], c)
        near = nearest_places(pl.outline, want)  # L's outline passes through each
        gap = float(np.linalg.norm(at_places(pl.outline, near) - want, axis=1).max())
        assert gap < 0.5, (pm.name, gap)
        # the hem: 5 cm shorter in L as in M (additive grades keep the difference)
        short_m = np.ptp(pm0.outline[:, 1]) - np.ptp(pm.outline[:, 1])
        short_l = np.ptp(pl0.outline[:, 1]) - np.ptp(pl.outline[:, 1])
        assert short_m > 40 and abs(short_l - short_m) < 1.0, (short_m, short_l)
        assert len(pl.notches) == len(pm.notches)


def test_correspondence_by_length_between_turn_points():
    """A square with 3 points a side against one with 2 a side, laid elsewhere and larger:
    each point falls at the same fraction between the same corners."""
    sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    t3 = np.linspace(0, 1, 3, endpoint=False)[:, None]
    A = np.vstack([sq[i] + t3 * (sq[(i + 1) % 4] - sq[i]) for i in range(4)]) * 2 + 5
    t2 = np.linspace(0, 1, 2, endpoint=False)[:, None]
    B = np.vstack([sq[i] + t2 * (sq[(i + 1) % 4] - sq[i]) for i in range(4)])
    B = np.roll(B, 3, axis=0)  # starting elsewhere
    ta, tb = np.arange(12) % 3 == 0, np.zeros(8, bool)
    tb[np.flatnonzero(np.all(np.isin(B, [0.0, 1.0]), axis=1))] = True
    pl = by_length(A, ta, B, tb)
    assert pl.how == "by length between turn points"
    np.testing.assert_allclose(at_places(B, pl), (A - 5) / 2, atol=1e-12)
    same = corresponding(A, ta, A * 1.01, ta)
    assert same.how == "point by point" and np.array_equal(same.seg, np.arange(12))
    assert at_places(np.arange(4.0)[:, None], Places(np.array([3]), np.array([0.5]), "")) == [[1.5]]


@pytest.mark.slow  # the generated skirt graded and written: 0.6-0.8 s
def test_bad_sizes_exit_2_with_one_line_and_nothing_written(tmp_path):
    dxf, obj = graded_nest(tmp_path)
    rec = _recipe(tmp_path, UNIFORM)
    single = tmp_path / "single.dxf"
    pf = read_dxf(dxf)
    from ptailor.formats.dxf import write_dxf

    write_dxf(single, replace(pf, sizes=("M",)), layout="keep")
    cases = [
        (dxf, ("--sizes", "S,XXL"), "no size 'XXL' in the file (sizes: S, M, L)"),
        (single, ("--sizes", "all"), "the pattern is not graded (it holds one size, M)"),
        (obj, ("--sizes", "all"), "--sizes applies to a graded DXF pattern"),
        (dxf, ("--sizes", "S,,L"), "--sizes must be all or a comma-separated list"),
    ]
    for k, (garment, opts, needle) in enumerate(cases):
        out = tmp_path / f"o{k}"
        drape = ("--drape", obj) if garment != obj else ()
        r = CliRunner().invoke(cli, ["adjust", str(garment), str(rec), *map(str, drape),
                                     "-o", str(out), *opts])  # fmt: skip
        assert r.exit_code == 2, (needle, r.output)
        lines = r.output.strip().splitlines()
        assert len(lines) == 1 and needle in lines[0], r.output
        assert str(garment) in lines[0] or needle.startswith("--sizes must"), lines[0]
        assert not out.exists()


@pytest.mark.slow  # the generated skirt graded and written: 0.6-0.8 s
def test_inspect_shows_each_sizes_grade(tmp_path):
    dxf, _ = graded_nest(tmp_path)
    r = run("inspect", dxf, "--json")
    assert r.exit_code == 0, r.output
    info = json.loads(r.output)
    rows = {(g["size"], g["piece"]): g for g in info["grades"]}
    assert sorted({s for s, _ in rows}) == ["L", "M", "S"]
    for (s, name), g in rows.items():
        pm = next(p for p in read_dxf(dxf).pieces if p.name == name)
        ps = next(p for p in read_dxf(dxf, size=s).pieces if p.name == name)
        assert g["width"] == pytest.approx(ps.extent[0] - pm.extent[0], abs=1e-3)
        assert g["area"] == pytest.approx(ps.area - pm.area, rel=1e-3, abs=1e-3)
        want = np.linalg.norm(grade(s, pm.outline, pm.outline.mean(axis=0)), axis=1).max()
        assert g["max_delta"] == pytest.approx(want, abs=1e-3)
    assert rows["M", name]["max_delta"] == 0 and rows["L", name]["max_delta"] > 5
    r = run("inspect", dxf)
    assert r.exit_code == 0 and "grade from sample size M" in r.output


@pytest.mark.slow  # the real graded nest, 14 sizes, with a drape of its pieces: 3-5 s
def test_the_gerber_tank_writes_back_every_size(tmp_path):
    """WM_SLIM_TANK.DXF (2 fold pieces x 14 sizes) with a flat drape of its sample size's
    wholes: every size is written and read back, with its piece count; identity gives each
    size's outlines back, a 10 % scale keeps each size's grade."""
    from tests.test_dxf_roundtrip import _triangulated

    if not TANK.is_file():
        pytest.skip(f"{TANK} not available (../shared is absent)")
    from ptailor.model.garment import Garment
    from ptailor.pieces import unfolded

    src = read_dxf(TANK)
    Vs, Fs, groups, off = [], [], [], 0
    for k, pc in enumerate(src.pieces):
        V, F = _triangulated(unfolded(pc).outline, 0.6)
        Vs.append(V)
        Fs.append(F + off)
        groups.append(np.full(len(F), k))
        off += len(V)
    V2, F2 = np.vstack(Vs), np.vstack(Fs)
    names = tuple(p.name for p in src.pieces)
    V3 = np.c_[V2 * 2.54, np.zeros(len(V2))]
    g = Garment(V3=V3, F3=F2, V2=V2, F2=F2, face_group=np.concatenate(groups), group_names=names)
    obj = tmp_path / "tank.obj"
    write_garment(obj, g, header=["flat drape: v in cm, vt in inches"])
    orig = read_dxf_sizes(TANK)
    for name, text in (("id", "steps: []\n"), ("up", UNIFORM)):
        out = tmp_path / name
        r = run("adjust", TANK, _recipe(tmp_path, text), "--drape", obj, "-o", out,
                "--sizes", "all", "--formats", "dxf", "--no-baseline")  # fmt: skip
        assert r.exit_code == 0, r.output
        back = read_dxf_sizes(out / "pattern.dxf")
        assert [p.size for p in back] == list(src.sizes) and len(back) == 14
        base = next(p for p in back if p.size == "36")
        for o, b in zip(orig, back, strict=True):
            alone = read_dxf(out / f"pattern_{o.size}.dxf")
            assert len(b.pieces) == len(o.pieces) == len(alone.pieces) == 2
            for po, pb, pa, p36, o36 in zip(o.pieces, b.pieces, alone.pieces, base.pieces,
                                            src.pieces, strict=True):  # fmt: skip
                assert po.name == pb.name and pb.mirror is not None
                np.testing.assert_allclose(pa.outline, pb.outline, atol=1e-6)
                want = po.outline if name == "id" else p36.outline + po.outline - o36.outline
                assert np.abs(pb.outline - want).max() < 0.5 / 25.4, (o.size, po.name)
