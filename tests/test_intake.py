"""Mesh intake: welding unwelded exports, dropping duplicate and zero-area faces, unit sanity."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from ptailor.cli.main import cli
from ptailor.formats.garment import load_garment, parse_weld
from ptailor.formats.obj import read_obj
from ptailor.model.garment import panels
from ptailor.model.repair import (
    UNIT_RATIO_RANGE,
    duplicate_faces,
    intake,
    non_manifold_edges,
    topology,
    unit_ratios,
    weld_vertices,
    zero_area_faces,
)
from ptailor.pipeline import adjustment
from ptailor.recipe import parse_recipe
from ptailor.samples.obj_text import sample_obj_text
from tests.conftest import REAL, real_path

ROOT = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location("unweld", ROOT / "bench" / "unweld.py")
unweld_mod = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(unweld_mod)

WIDER = "steps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.2}]\n"


@pytest.fixture
def runner():
    return CliRunner()


def run(runner, *args):
    return runner.invoke(cli, [str(a) for a in args])


# ---- the pure functions ------------------------------------------------------------------


def test_weld_vertices_index_maps_and_transitive_clusters():
    V = np.array(
        [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0], [0.6e-3, 0, 0], [1.2e-3, 0, 0], [9, 9, 9]],
        dtype=float,
    )
    F = np.array([[0, 1, 2], [3, 2, 4], [5, 1, 2]])
    W, G, I, J = weld_vertices(V, F, distance=1e-3)
    # 0, 4, 5 chain within 1e-3 (pymeshlab's greedy merge leaves two); 1 and 3 coincide;
    # 6 is unreferenced and kept
    np.testing.assert_array_equal(I, [0, 1, 2, 6])
    np.testing.assert_array_equal(J, [0, 1, 2, 1, 0, 0, 3])
    np.testing.assert_array_equal(G, J[F])
    np.testing.assert_array_equal(W, V[I])
    # clusters do not depend on the vertex order
    perm = np.array([5, 3, 6, 0, 2, 4, 1])  # new position of old vertex k is perm[k]
    Vp = np.empty_like(V)
    Vp[perm] = V
    _, Gp, Ip, _ = weld_vertices(Vp, perm[F], distance=1e-3)
    assert len(Ip) == len(I)
    np.testing.assert_allclose(Vp[Ip][Gp], W[G])  # the same triangles, exactly


def test_duplicate_zero_area_and_non_manifold_edges():
    F3 = np.array([[0, 1, 2], [2, 0, 1], [0, 1, 2], [0, 1, 3], [0, 1, 4], [0, 0, 1]])
    F2 = np.array([[0, 1, 2], [2, 0, 1], [5, 6, 7], [0, 1, 3], [0, 1, 4], [0, 0, 1]])
    # row 1 repeats row 0 (corners rotated) in 3D and 2D; row 2 only in 3D (another panel)
    np.testing.assert_array_equal(duplicate_faces(F3, F2), [0, 1, 0, 0, 0, 0])
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0, -1, 0]], dtype=float)
    np.testing.assert_array_equal(zero_area_faces(V, F3), [0, 0, 0, 0, 0, 1])
    V2 = np.array([[0, 0], [1, 0], [2, 0], [0, 1], [0, -1], [0, 0], [1, 0], [1, 1]], float)
    np.testing.assert_array_equal(zero_area_faces(V2, F2), [1, 1, 0, 0, 0, 1])
    # edge (0, 1) carries five triangles, a T-seam and more
    np.testing.assert_array_equal(non_manifold_edges(F3[[0, 3, 4]]), [[0, 1]])


def test_pymeshlab_topology_agrees_with_numpy():
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0, -1, 0]], dtype=float)
    F = np.array([[0, 1, 2], [1, 0, 3], [1, 0, 4]])
    for _ in range(2):  # (pymeshlab's own edge count changes after a manifold mesh)
        t = topology(V, F)
        assert t["non_manifold_edges"] == len(non_manifold_edges(F)) == 1
        assert t["faces_on_non_manifold_edges"] == 3
        assert t["components"] == 1 and t["genus"] is None  # undefined when non-manifold
        assert topology(V, F[:1])["non_manifold_edges"] == 0


def test_unit_ratios_per_panel():
    g = load_garment(_sample_path("cone_skirt")).garment
    ratio, per = unit_ratios(g.V3, g.F3, g.V2, g.F2)
    assert 0.9 < ratio < 1.1 and len(per) == len(panels(g))
    r2, per2 = unit_ratios(g.V3, g.F3, g.V2 * 3.0, g.F2)
    assert r2 == pytest.approx(3 * ratio) and np.allclose(per2, 3 * per)


def test_parse_weld():
    assert parse_weld("auto", units="cm") == "auto"
    assert parse_weld("OFF", units="cm") == "off"
    assert parse_weld("1mm", units="cm") == pytest.approx(0.1)
    assert parse_weld("0.5", units="mm") == 0.5
    for bad in ("yes", "-1mm", "1parsec", ""):
        with pytest.raises(Exception, match="--weld"):
            parse_weld(bad, units="cm")


# ---- unwelded garments give what the welded ones give -----------------------------------


_SAMPLES: dict[str, Path] = {}


def _sample_path(name: str) -> Path:
    import tempfile

    if name not in _SAMPLES:
        p = Path(tempfile.mkdtemp()) / f"{name}.obj"
        p.write_text(sample_obj_text(name))
        _SAMPLES[name] = p
    return _SAMPLES[name]


def _inspect(runner, path, *extra) -> dict:
    r = run(runner, "inspect", path, "--json", *extra)
    assert r.exit_code == 0, r.output
    return json.loads(r.output)


def _structure(info: dict) -> tuple:
    seams = sorted((tuple(s["panels"]), tuple(s["lengths"])) for s in info["seams"])
    opens = sorted((o["name"], o["length"]) for o in info["openings"])
    return seams, opens


def _assert_same_structure(a: dict, b: dict) -> None:
    sa, oa = _structure(a)
    sb, ob = _structure(b)
    assert len(sa) == len(sb)
    for x, y in zip(sa, sb, strict=True):
        assert x[0] == y[0]
        np.testing.assert_allclose(x[1], y[1], atol=1e-9)
    assert [o[0] for o in oa] == [o[0] for o in ob]
    np.testing.assert_allclose([o[1] for o in oa], [o[1] for o in ob], atol=1e-9)


def _adjusted(path, recipe: str, **load) -> np.ndarray:
    g = load_garment(path, **load).garment
    return adjustment(g, parse_recipe(recipe), baseline=False).result.V2


@pytest.mark.slow
@pytest.mark.parametrize("name", ["lantern_sleeve", "cone_skirt"])
def test_generated_unwelded_every_vertex_welds_back(runner, tmp_path, name):
    src = _sample_path(name)
    dst = tmp_path / f"{name}_unwelded.obj"
    n = unweld_mod.unweld_obj(src, dst, every_vertex=True, shuffle=7)
    assert n > len(np.unique(read_obj(src).fv))  # really apart
    a, b = _inspect(runner, src), _inspect(runner, dst)
    assert b["intake"]["welded_vertices"] == n - len(np.unique(read_obj(src).fv))
    _assert_same_structure(a, b)
    np.testing.assert_allclose(_adjusted(dst, WIDER), _adjusted(src, WIDER), atol=1e-9)


@pytest.mark.slow
def test_generated_weld_off_keeps_pieces_apart_and_warns(runner, tmp_path):
    src = _sample_path("cone_skirt")
    dst = tmp_path / "skirt_unwelded.obj"
    unweld_mod.unweld_obj(src, dst)
    info = _inspect(runner, dst, "--weld", "off")
    assert info["intake"]["welded_vertices"] == 0
    assert info["seams"] == []  # as before this option: the panels are separate cloth
    assert any("--weld off" in w for w in info["intake"]["warnings"])
    r = run(runner, "inspect", dst, "--weld", "off")
    assert "warning:" in r.output and "coincide" in r.output


def test_welded_garment_is_not_touched(runner):
    info = _inspect(runner, _sample_path("lantern_sleeve"))
    rec = info["intake"]
    assert rec["welded_vertices"] == 0 and rec["duplicate_faces"] == 0
    assert rec["zero_area_faces_3d"] == rec["zero_area_faces_2d"] == 0
    assert rec["units"]["pattern_source"] == "default, size checked"
    assert rec["topology"]["non_manifold_edges"] == 0


REAL_UNWELD = {
    # garment, pattern units, the panels of one sleeve
    "tee6": ([0, 1],),
    "tshirt": ([0],),
}


@pytest.mark.slow
@pytest.mark.parametrize("key", sorted(REAL_UNWELD))
def test_real_unwelded_gives_the_same_seams_openings_and_pattern(runner, tmp_path, key):
    src = real_path(key)
    units = REAL[key][1]
    dst = tmp_path / f"{key}_unwelded.obj"
    unweld_mod.unweld_obj(src, dst, shuffle=3)
    opts = ("--pattern-units", units, "--drape-units", "cm")
    a, b = _inspect(runner, src, *opts), _inspect(runner, dst, *opts)
    assert a["intake"]["welded_vertices"] == 0
    assert b["intake"]["welded_vertices"] > 0 and b["intake"]["pieces_after"] == 1
    assert len(b["seams"]) == len(a["seams"]) >= 4
    _assert_same_structure(a, b)
    g = load_garment(src, pattern_units=units).garment
    names = [panels(g)[i].name for i in REAL_UNWELD[key][0]]
    sleeve = (
        f"steps: [{{op: scale, region: {{panels: [{', '.join(names)}]}}, direction: around, "
        "factor: 1.1}]"
    )
    for recipe, moved in ((sleeve, 1.0), ("steps: []", 0.0)):
        va = _adjusted(src, recipe, pattern_units=units)
        vb = _adjusted(dst, recipe, pattern_units=units)
        assert np.abs(va - vb).max() < 1e-6  # measured: 3e-12 (tee6, tshirt)
        assert np.abs(va - g.V2).max() >= moved  # the sleeve recipe changes the pattern
    # --weld off: as before (the panels apart), with a warning
    c = _inspect(runner, dst, *opts, "--weld", "off")
    assert len(c["seams"]) < len(a["seams"]) and c["intake"]["warnings"]


@pytest.mark.slow
def test_adjust_report_has_intake(runner, tmp_path):
    src = _sample_path("cone_skirt")
    dst = tmp_path / "skirt_unwelded.obj"
    unweld_mod.unweld_obj(src, dst)
    rec = tmp_path / "r.yaml"
    rec.write_text(WIDER)
    out = tmp_path / "out"
    r = run(runner, "adjust", dst, rec, "-o", out, "--formats", "obj")
    assert r.exit_code == 0, r.output
    report = json.loads((out / "report.json").read_text())
    it = report["intake"]
    assert it["weld"] == "auto" and it["welded_vertices"] > 0 and it["pieces_before"] == 2
    assert it["units"]["pattern_source"] == "default, size checked"
    assert UNIT_RATIO_RANGE[0] < it["units"]["pattern_drape_ratio"] < UNIT_RATIO_RANGE[1]
    # the output garment is welded: it reads back with nothing to weld
    again = load_garment(out / "garment.obj")
    assert again.intake["welded_vertices"] == 0


# ---- duplicate and zero-area faces ------------------------------------------------------


@pytest.mark.slow
def test_duplicate_and_zero_area_faces_are_dropped_and_counted(runner, tmp_path):
    src = _sample_path("lantern_sleeve")
    text = src.read_text()
    faces = [ln for ln in text.splitlines() if ln.startswith("f ")]
    a, b, c = faces[0].split()[1:4]
    extra = f"f {a} {b} {c}\nf {b} {c} {a}\nf {a} {b} {b}\n"  # two copies, one null face
    bad = tmp_path / "messy.obj"
    bad.write_text(text + extra)
    loaded = load_garment(bad)
    it = loaded.intake
    assert it["duplicate_faces"] == 2 and it["zero_area_faces_3d"] == 1
    assert it["faces_read"] == len(faces) + 3 and loaded.garment.n_faces == len(faces)
    assert any("dropped 3 triangle(s)" in w for w in it["warnings"])
    np.testing.assert_allclose(_adjusted(bad, WIDER), _adjusted(src, WIDER), atol=1e-12)
    r = run(runner, "inspect", bad)
    assert "2 duplicate, 1 zero-area 3D" in r.output


def test_zero_area_in_2d_only_is_dropped(tmp_path):
    V3 = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0.5]], dtype=float)
    F = np.array([[0, 1, 2], [1, 3, 2]])
    V2 = np.array([[0, 0], [1, 0], [0, 1], [0.5, 0.5]], dtype=float)  # 2nd collinear in 2D
    res = intake(V3, F, V2, F, weld="auto")
    assert res.record["zero_area_faces_2d"] == 1 and res.record["zero_area_faces_3d"] == 0
    np.testing.assert_array_equal(res.faces, [0])


# ---- unit sanity -------------------------------------------------------------------------


def test_unit_mistake_is_exit_2_naming_the_options_and_ratio(runner, tmp_path):
    src = _sample_path("lantern_sleeve")
    out = tmp_path / "out"
    rec = tmp_path / "r.yaml"
    rec.write_text(WIDER)
    r = run(runner, "adjust", src, rec, "-o", out, "--pattern-units", "mm")
    assert r.exit_code == 2
    line = r.output.strip()
    assert len(line.splitlines()) == 1
    assert str(src) in line and "--pattern-units" in line and "--drape-units" in line
    assert "ratio 0.1 " in line
    assert not out.exists()
    # the same with both units scaled alike runs
    r = run(runner, "inspect", src, "--pattern-units", "mm", "--drape-units", "mm")
    assert r.exit_code == 0, r.output


@pytest.mark.slow
def test_tee6_unit_mistake(runner, tmp_path):
    src = real_path("tee6")
    rec = tmp_path / "r.yaml"
    rec.write_text("steps: [{op: shorten, opening: hem, by: 5}]\n")
    out = tmp_path / "out"
    r = run(runner, "adjust", src, rec, "-o", out, "--pattern-units", "0.3333cm")
    assert r.exit_code == 2
    assert "ratio 0.33" in r.output and "--pattern-units" in r.output and str(src) in r.output
    assert not out.exists()
    both = ("--pattern-units", "0.3333cm", "--drape-units", "0.3333cm")
    r = run(runner, "adjust", src, rec, "-o", out, *both, "--formats", "obj", "--no-baseline")
    assert r.exit_code == 0, r.output
    ratio = json.loads((out / "report.json").read_text())["intake"]["units"]
    assert 0.95 < ratio["pattern_drape_ratio"] < 1.05


@pytest.mark.slow
def test_real_garments_pass_the_unit_check(real_garment):
    key, loaded = real_garment
    u = loaded.intake["units"]
    lo, hi = UNIT_RATIO_RANGE
    assert lo < u["pattern_drape_ratio"] < hi
    assert all(lo < r < hi for r in u["pattern_drape_ratio_per_panel"])
    assert u["pattern_source"] == ("estimate" if REAL[key][1] == "auto" else "command line")
    assert loaded.intake["welded_vertices"] == 0  # welded files stay as they are


# ---- --weld on the command line --------------------------------------------------------------


@pytest.mark.parametrize("cmd", ["adjust", "inspect", "batch"])
def test_bad_weld_value_is_exit_2(runner, tmp_path, cmd):
    src = _sample_path("cone_skirt")
    rec = tmp_path / "r.yaml"
    rec.write_text(WIDER)
    out = tmp_path / "out"
    args = {
        "adjust": ["adjust", src, rec, "-o", out],
        "inspect": ["inspect", src],
        "batch": ["batch", rec, src, "-o", out, "-j", "1"],
    }[cmd]
    r = run(runner, *args, "--weld", "sometimes")
    assert r.exit_code == 2
    assert "--weld" in r.output and "'sometimes'" in r.output
    assert len(r.output.strip().splitlines()) == 1
    assert not out.exists()


@pytest.mark.slow
def test_weld_distance_and_batch_stamp(runner, tmp_path):
    src = _sample_path("cone_skirt")
    dst = tmp_path / "skirt_unwelded.obj"
    unweld_mod.unweld_obj(src, dst)
    info = _inspect(runner, dst, "--weld", "0.01mm")
    assert info["intake"]["weld"] == "distance" and info["intake"]["welded_vertices"] > 0
    assert info["intake"]["weld_distance"] == pytest.approx(1e-3)
    rec = tmp_path / "r.yaml"
    rec.write_text(WIDER)
    out = tmp_path / "out"
    r = run(runner, "batch", rec, dst, "-o", out, "-j", "1", "--weld", "off", "--formats", "obj")
    assert r.exit_code == 0, r.output
    folder = out / "skirt_unwelded"
    stamp = json.loads((folder / "batch.json").read_text())
    assert stamp["options"]["weld"] == "off"
    assert json.loads((folder / "report.json").read_text())["intake"]["welded_vertices"] == 0


@pytest.mark.slow
def test_dxf_pattern_reports_where_its_units_came_from(runner, tmp_path):
    demo = tmp_path / "demo"
    assert run(runner, "demo", demo).exit_code == 0
    out = tmp_path / "out"
    dxf, drape = demo / "pattern.dxf", demo / "garment.obj"
    r = run(runner, "adjust", dxf, demo / "recipe.yaml", "--drape", drape, "-o", out)
    assert r.exit_code == 0, r.output
    u = json.loads((out / "report.json").read_text())["intake"]["units"]
    assert u["pattern"] == "mm" and u["pattern_source"] in ("file", "estimate")
    assert u["vt_source"] in ("file", "estimate") and 0.9 < u["pattern_drape_ratio"] < 1.1
    out2 = tmp_path / "out2"
    r = run(
        runner,
        "adjust",
        dxf,
        demo / "recipe.yaml",
        "--drape",
        drape,
        "-o",
        out2,
        "--dxf-units",
        "mm",
        "--formats",
        "obj",
    )
    assert r.exit_code == 0, r.output
    u = json.loads((out2 / "report.json").read_text())["intake"]["units"]
    assert u["pattern_source"] == "command line"


def test_no_pair_shortcut_agrees_with_the_k_d_tree():
    """``_clearly_apart`` says "no pair" only where ``query_pairs`` finds none (issue 15)."""
    from scipy.spatial import cKDTree

    from ptailor.model.repair import _clearly_apart

    rng = np.random.default_rng(0)
    apart = 0
    for _ in range(400):
        n = int(rng.integers(2, 300))
        P = rng.uniform(-1, 1, (n, 3)) * 10 ** rng.uniform(-3, 3)
        if rng.random() < 0.3:  # on a grid: many equal projections' neighbours
            P = np.round(P, int(rng.integers(0, 3)))
        d = float(10 ** rng.uniform(-6, 0)) * float(np.abs(P).max())
        for _ in range(int(rng.integers(0, 3))):  # pairs near the distance
            i, j = rng.integers(0, n, 2)
            P[j] = P[i] + rng.normal(size=3) * d * rng.choice([0.5, 1.0, 1.0000001, 2]) / 3**0.5
        if _clearly_apart(P, d):
            apart += 1
            assert len(cKDTree(P).query_pairs(d, output_type="ndarray")) == 0
    assert apart > 50


def test_duplicate_faces_keys_match_unique_rows():
    rng = np.random.default_rng(1)
    for _ in range(200):
        m, n = int(rng.integers(1, 200)), int(rng.integers(3, 15))
        F3, F2 = rng.integers(0, n, (m, 3)), rng.integers(0, n, (m, 3))
        if rng.random() < 0.5:
            F2 = F3.copy()
            F2[::3] = rng.permuted(F2[::3], axis=1)
        key = np.concatenate([np.sort(F3, axis=1), np.sort(F2, axis=1)], axis=1)
        want = np.ones(m, dtype=bool)
        want[np.unique(key, axis=0, return_index=True)[1]] = False
        assert np.array_equal(duplicate_faces(F3, F2), want)
