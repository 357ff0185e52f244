"""Seam allowances: a simple cut line always (GEOS), per seam and opening, named on the CLI."""

from __future__ import annotations

import doctest
import importlib
import json

import numpy as np
import pytest
import shapely
from click.testing import CliRunner

from ptailor.cli.main import cli
from ptailor.model.offset import offset_closed
from ptailor.model.pieces import Piece
from ptailor.pieces import with_seam_allowance
from ptailor.samples.obj_text import sample_obj_text
from tests.conftest import REAL, real_path


@pytest.mark.parametrize("name", ["ptailor.model.offset", "ptailor.pieces.allowance"])
def test_docstring_examples(name):
    res = doctest.testmod(importlib.import_module(name), extraglobs={"np": np})
    assert res.attempted > 0 and res.failed == 0


def _simple(cut: np.ndarray, sew: np.ndarray, least: float = 0.0) -> None:
    """The cut line is one simple closed line (no loop) around the sew line, at least
    ``least`` (the smallest allowance) from every sew line point: no slit reaches in."""
    ring = shapely.LinearRing(cut)
    assert ring.is_simple and ring.is_valid
    outer = shapely.Polygon(cut)
    assert outer.is_valid
    inner = shapely.make_valid(shapely.Polygon(sew))
    eps = 1e-8 * np.ptp(sew, axis=0).max()  # the grid and simplification: 1e-9 of it
    assert outer.buffer(eps).contains(inner)
    # (GEOS's buffer simplifies its input curve by up to 1e-2 of the distance: measured 4e-7)
    assert shapely.distance(ring, shapely.points(sew)).min() >= least * (1 - 1e-4) - eps


def _star(rng, k: int) -> np.ndarray:
    """A random star-shaped outline of ``k`` points: deep concave notches, short edges."""
    t = np.sort(rng.uniform(0, 2 * np.pi, k))
    r = rng.uniform(3.0, 10.0, k)
    return np.stack([r * np.cos(t), r * np.sin(t)], axis=1)


@pytest.mark.slow
def test_random_outlines_with_random_allowances_per_edge_are_simple_and_cover_their_strips():
    rng = np.random.default_rng(7)
    for _ in range(60):  # a few dozen outlines
        P = _star(rng, int(rng.integers(5, 40)))
        if not shapely.LinearRing(P).is_simple:
            continue
        d = rng.choice([0.0, 0.5, 1.0, 3.0], size=len(P))
        cut = offset_closed(P, d)
        _simple(cut, P)
        _simple(offset_closed(P, np.maximum(d, 0.2)), P, least=0.2)
        # every edge moved out by its allowance lies inside the cut line ...
        n = np.roll(P, -1, axis=0) - P
        n = np.stack([n[:, 1], -n[:, 0]], 1) / np.linalg.norm(n, axis=1)[:, None]  # CCW: out
        mid = 0.5 * (P + np.roll(P, -1, axis=0)) + (d - 1e-6)[:, None] * n
        assert shapely.Polygon(cut).buffer(1e-9).contains(shapely.points(mid)).all()
        # ... and the cut line is nowhere further than the mitre limit's reach
        far = shapely.Polygon(P).hausdorff_distance(shapely.Polygon(cut))
        assert far <= (4.0 + 1.0) * d.max()  # (a clipped mitre: its two ends a bit further)


def test_one_allowance_per_edge_equal_everywhere_is_geos_mitre_buffer():
    rng = np.random.default_rng(3)
    for _ in range(20):
        P = _star(rng, 30)
        if not shapely.LinearRing(P).is_simple:
            continue
        one = shapely.Polygon(offset_closed(P, 1.0))
        d = np.full(len(P), 1.0)
        d[0] += 1e-12  # not all equal: the strips' union
        strips = shapely.Polygon(offset_closed(P, d))
        assert one.symmetric_difference(strips).area < 1e-6 * one.area


def test_a_hem_of_3_and_seams_of_1_give_a_square_stepped_rectangle():
    P = np.array([[0.0, 0], [10, 0], [10, 20], [0, 20]])  # bottom edge: the hem
    cut = offset_closed(P, np.array([3.0, 1.0, 1.0, 1.0]))
    np.testing.assert_allclose(np.sort(cut, axis=0)[[0, -1]], [[-1, -3], [11, 21]])
    assert abs(shapely.Polygon(cut).area) == pytest.approx(12 * 24)
    fold = with_seam_allowance(Piece(name="half", outline=P, mirror=P[[0, 3]]), 1.0)
    np.testing.assert_allclose(np.sort(fold.outline, axis=0)[[0, -1]], [[0, -1], [11, 21]])
    np.testing.assert_array_equal(fold.sew, P)


def _real_pieces(key: str, levels: int = 0):
    from ptailor.formats.garment import load_garment
    from ptailor.pieces import piece_plan

    g = load_garment(real_path(key), pattern_units=REAL[key][1]).garment
    if levels:
        from tests.garment_checks import subdivided

        g = subdivided(g, levels)
    return g, piece_plan(g).pieces


@pytest.mark.slow
@pytest.mark.parametrize("key", sorted(REAL))
def test_every_cut_line_of_every_shared_garment_is_simple_at_1_2_5_and_5_cm(key):
    """The diffavatar tshirt's back at 2.5 cm had an 18 mm2 loop (the hand mitre offset)."""
    from ptailor.model.units import CM_PER

    g, pieces = _real_pieces(key)
    for cm in (1.0, 2.5, 5.0):
        d = cm / CM_PER[g.units]
        for pc in pieces:  # a loop over pieces
            _simple(with_seam_allowance(pc, d).outline, pc.outline, least=d)
            k = len(pc.outline)
            per_edge = np.where(np.arange(k) % 7 < 3, d, 2 * d)  # two allowances, mixed
            _simple(with_seam_allowance(pc, d, edges=per_edge).outline, pc.outline, least=d)


@pytest.mark.slow
@pytest.mark.parametrize("key", ["tshirt", "tee6"])
def test_cut_lines_at_16x_are_simple(key):
    from ptailor.model.units import CM_PER

    g, pieces = _real_pieces(key, levels=2)
    for cm in (1.0, 2.5, 5.0):
        for pc in pieces:  # a loop over pieces
            d = cm / CM_PER[g.units]
            _simple(with_seam_allowance(pc, d).outline, pc.outline, least=d)
            per_edge = np.where(np.arange(len(pc.outline)) % 40 < 20, d, 3 * d)
            _simple(with_seam_allowance(pc, d, edges=per_edge).outline, pc.outline, least=d)


def _run(*args):
    return CliRunner().invoke(cli, [str(a) for a in args], catch_exceptions=False)


def _sew_to_cut(piece: Piece, run: slice) -> np.ndarray:
    """Distance from sew line points ``run`` to the cut line."""
    return shapely.distance(shapely.LinearRing(piece.outline), shapely.points(piece.sew[run]))


@pytest.mark.slow
def test_the_hem_gets_its_own_allowance_the_seams_the_default_and_the_report_says_so(tmp_path):
    from ptailor.formats.dxf.reader import read_dxf

    obj = tmp_path / "skirt.obj"
    obj.write_text(sample_obj_text("cone_skirt"))
    rec = tmp_path / "id.yaml"
    rec.write_text("steps: []\n")
    out = tmp_path / "o"
    args = ["--formats", "dxf", "--seam-allowance", "hem=3cm", "--seam-allowance", "1cm"]
    r = _run("adjust", obj, rec, "-o", out, *args)
    assert r.exit_code == 0, r.output
    report = json.loads((out / "report.json").read_text())
    assert report["pattern"]["seam_allowance"] == 1.0
    assert report["pattern"]["seam_allowances"] == {"hem": 3.0}
    pieces = {p.name: p for p in read_dxf(out / "pattern.dxf").pieces}
    for rec_p in report["pattern"]["pieces"]:
        runs = {x["name"]: x for x in rec_p["allowances"]}
        assert runs["hem"]["allowance"] == 3.0 and runs["waist"]["allowance"] == 1.0
        assert {x["kind"] for x in rec_p["allowances"]} == {"seam", "opening"}
        pc = pieces[rec_p["name"]]
        _simple(pc.outline, pc.sew, least=10.0)  # mm
        # the sew line's hem (its lowest points, away from the corners) is 3 cm (30 mm) in
        y = pc.sew[:, 1]
        low = np.flatnonzero(y <= y.min() + 0.02 * np.ptp(y))
        x = pc.sew[low, 0]
        inner = low[(x > x.min() + 0.1 * np.ptp(x)) & (x < x.max() - 0.1 * np.ptp(x))]
        assert len(inner) >= 3
        np.testing.assert_allclose(_sew_to_cut(pc, inner), 30.0, rtol=0.02)
        high = np.flatnonzero(y >= y.max() - 0.02 * np.ptp(y))  # the waist: 1 cm
        assert np.median(_sew_to_cut(pc, high)) == pytest.approx(10.0, rel=0.05)
    assert "seam allowance 1 (hem 3)" in r.output


def test_an_unknown_seam_name_exits_2_naming_it_and_the_known_ones_writing_nothing(tmp_path):
    obj = tmp_path / "skirt.obj"
    obj.write_text(sample_obj_text("cone_skirt"))
    rec = tmp_path / "id.yaml"
    rec.write_text("steps: []\n")
    r = _run("adjust", obj, rec, "-o", tmp_path / "o", "--seam-allowance", "hems=3cm")
    assert r.exit_code == 2
    assert "hems" in r.output and "known: " in r.output and "hem" in r.output.split("known: ")[1]
    assert str(obj) in r.output and len(r.output.strip().splitlines()) == 1
    assert not (tmp_path / "o").exists()


@pytest.mark.slow
def test_file_pieces_moved_or_on_the_fold_take_their_seams_allowances(tmp_path):
    """A DXF's pieces: the cuff moved (matched by shape) and cut on the fold; the sleeve's
    top opening 3 cm, the rest 1 cm; the fold edge none."""
    from ptailor.formats.dxf.reader import read_dxf
    from tests.test_pattern_io import IDENTITY, _recipe, _setup

    R, t = np.array([[0.0, -1.0], [1.0, 0.0]]), np.array([400.0, 50.0])

    def move(pc):
        return pc if pc.name != "cuff" else pc.map_points(lambda a: a @ R.T + t)

    obj, dxf, _ = _setup(tmp_path, move=move)
    rec = _recipe(tmp_path, IDENTITY)
    out = {}
    for key, extra in (("one", []), ("top", ["--seam-allowance", "top=3cm"])):
        args = ["--drape", obj, "--formats", "dxf", "--seam-allowance", "1cm", *extra]
        r = _run("adjust", dxf, rec, "-o", tmp_path / key, *args)
        assert r.exit_code == 0, r.output
        pieces = {p.name: p for p in read_dxf(tmp_path / key / "pattern.dxf").pieces}
        report = json.loads((tmp_path / key / "report.json").read_text())["pattern"]
        out[key] = (pieces, {p["name"]: p for p in report["pieces"]})
    pieces, recs = out["top"]
    assert recs["cuff"]["matched_by"] == "shape"
    runs = {x["name"]: x for x in recs["sleeve"]["allowances"]}
    assert runs["top"]["allowance"] == 3.0 and runs["sleeve"]["allowance"] == 1.0
    assert all(x["allowance"] == 1.0 for x in recs["cuff"]["allowances"])
    for pc in pieces.values():
        _simple(pc.outline, pc.sew)
    # the top's 2 cm more (mm): the cut line's area grows by 20 mm times the top's length
    # and the sides' allowances at its square corners, which its strip runs on over
    grown = shapely.Polygon(pieces["sleeve"].outline).area
    grown -= shapely.Polygon(out["one"][0]["sleeve"].outline).area
    assert grown == pytest.approx(20.0 * (10.0 * runs["top"]["length"] + 2 * 10.0), rel=1e-3)
    cuff = pieces["cuff"]
    assert cuff.mirror is not None  # cut on the fold: the cut line runs on the fold line
    fold = shapely.LineString(cuff.mirror)
    assert shapely.LinearRing(cuff.outline).distance(fold.interpolate(0.5, normalized=True)) < 1e-6
