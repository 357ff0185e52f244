"""T-seams (a strip sewn onto the middle of a panel) and non-manifold boundaries.

A drape edge used by three faces (two of a panel, one of a strip sewn onto it) is a seam
between the strip and the panel, never a boundary; the strip's free edge is an open
opening; everything is the same over repeated runs and shuffled face order.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from ptailor.cli.main import cli
from ptailor.formats.obj import read_obj, write_garment
from ptailor.geometry.topology import half_edges
from ptailor.method.ease import seam_ease
from ptailor.model.boundary import boundary_curves, boundary_edges, boundary_loops
from ptailor.model.frame import Frame
from ptailor.model.garment import panel_labels, panels
from ptailor.model.openings import openings
from ptailor.model.seams import seam_halfedges, seams
from ptailor.samples import tseam_tube

N_AROUND, N_ALONG, HEIGHT = 24, 16, 40.0


def _labels(g):
    return panel_labels(panels(g), len(g.F3))


def _shuffled(g, seed):
    """Faces in a random order, each with its corners rotated (same cloth, same sides)."""
    rng = np.random.default_rng(seed)
    p = rng.permutation(len(g.F3))
    rot = rng.integers(0, 3, len(p))
    cols = (np.arange(3)[None, :] + rot[:, None]) % 3
    rows = np.arange(len(p))[:, None]
    return g.F3[p][rows, cols], g.F2[p][rows, cols], p


def _seam_set(F3, F2, flab, V2):
    """Seams as comparable values: panels, sorted drape edges, side lengths."""
    out = []
    for s in seams(F3, F2, flab):
        e = np.sort(s.edges3, axis=1)
        out.append((s.panels, tuple(map(tuple, e[np.lexsort(e.T[::-1])])), s.lengths(V2)))
    return sorted(out)


def _open_set(V3, F3, F2=None):
    return [
        (o.name, tuple(o.loop.tolist()), o.closed, o.length)
        for o in openings(V3, F3, F2=F2, frame=Frame())
    ]


@pytest.mark.parametrize("rows", [(4, 12), (8, 16), (0, 16)])
def test_tseam_is_a_seam_with_its_full_length(rows):
    g = tseam_tube(rows=rows)
    flab = _labels(g)
    tube, strip = 0, 1
    got = {s.panels: s for s in seams(g.F3, g.F2, flab)}
    assert set(got) == {(tube, tube), (tube, strip)}
    t = got[(tube, strip)]
    k = rows[1] - rows[0]
    length = HEIGHT * k / N_ALONG
    assert len(t.edges3) == k
    np.testing.assert_allclose(t.lengths(g.V2), (length, length), rtol=1e-12)
    # the tube side is the tube's interior column, the strip side the strip's sewn edge
    assert (flab[np.isin(g.F2, t.edges_a.ravel()).any(axis=1)] == tube).all()
    assert (flab[np.isin(g.F2, t.edges_b.ravel()).any(axis=1)] == strip).all()
    np.testing.assert_allclose(got[(tube, tube)].lengths(g.V2), (HEIGHT, HEIGHT))


def test_tseam_pairs_one_per_sewn_edge_against_the_strip():
    g = tseam_tube()
    flab = _labels(g)
    pairs = seam_halfedges(g.F3, g.F2)
    h3 = half_edges(g.F3)
    fa, fb = flab[pairs[:, 0] // 3], flab[pairs[:, 1] // 3]
    t = pairs[fa != fb]
    assert len(t) == 8
    assert (t[:, 0] < t[:, 1]).all()
    # one pair per drape edge, and the tube's half-edge runs against the strip's
    keys = np.sort(h3[t[:, 0]], axis=1)
    assert len(np.unique(keys, axis=0)) == 8
    np.testing.assert_array_equal(h3[t[:, 0]], h3[t[:, 1]][:, ::-1])


def test_tseam_seam_ease_keeps_strip_against_panel():
    g = tseam_tube()
    flab = _labels(g)
    se = seam_ease(g.F3, g.F2, g.V2, face_panel=flab)
    assert se.n_rows == 16 + 8
    np.testing.assert_allclose(se.ratio, 1.0)
    assert se.violation(g.V2).max() < 1e-12
    cur = seam_ease(g.F3, g.F2, g.V2, face_panel=flab, granularity="seam")
    assert cur.n_rows == 2


@pytest.mark.parametrize("rows", [(4, 12), (8, 16), (0, 16)])
def test_tseam_openings_strip_edge_is_an_open_opening(rows):
    g = tseam_tube(rows=rows)
    for F2 in (None, g.F2):
        ops = openings(g.V3, g.F3, F2=F2, frame=Frame())
        names = [o.name for o in ops]
        assert names[:2] == ["hem", "waist"] and len(ops) == 3
        assert all(o.closed for o in ops[:2])
        np.testing.assert_allclose([o.length for o in ops[:2]], [60.0, 60.0])
        chain = ops[2]
        assert not chain.closed
        k = rows[1] - rows[0]
        assert chain.length == pytest.approx(3.0 + HEIGHT * k / N_ALONG + 3.0)
        assert len(chain.loop) == 2 * 2 + k + 1
        # it runs from one end of the sewn line to the other, over the strip's free edge
        line = {(r0 + i) * N_AROUND + N_AROUND // 2 for r0 in [rows[0]] for i in range(k + 1)}
        assert {int(chain.loop[0]), int(chain.loop[-1])} <= line
        assert not set(chain.loop[1:-1].tolist()) & line
        assert all(o.length > 0 for o in ops)


def test_tseam_without_tseam_edges_on_any_boundary():
    g = tseam_tube()
    loops, closed = boundary_curves(g.F3, V=g.V3, F2=g.F2)
    h3 = np.sort(half_edges(g.F3), axis=1)
    _, inv, cnt = np.unique(h3, axis=0, return_inverse=True, return_counts=True)
    multi = {tuple(e) for e in h3[cnt[inv.ravel()] >= 3]}
    for lp, c in zip(loops, closed, strict=True):
        e = np.stack([lp, np.roll(lp, -1)], axis=1)[: len(lp) if c else len(lp) - 1]
        assert not {tuple(x) for x in np.sort(e, axis=1)} & multi


@pytest.mark.parametrize("rows", [(4, 12), (8, 16)])
def test_tseam_deterministic_over_runs_and_face_order(rows):
    g = tseam_tube(rows=rows)
    flab = _labels(g)
    ref_s = _seam_set(g.F3, g.F2, flab, g.V2)
    ref_o = _open_set(g.V3, g.F3, g.F2)
    ref_p = seam_halfedges(g.F3, g.F2)
    for _ in range(6):
        assert _seam_set(g.F3, g.F2, flab, g.V2) == ref_s
        assert _open_set(g.V3, g.F3, g.F2) == ref_o
        np.testing.assert_array_equal(seam_halfedges(g.F3, g.F2), ref_p)
    for seed in range(8):
        F3, F2, p = _shuffled(g, seed)
        assert _seam_set(F3, F2, flab[p], g.V2) == ref_s
        assert _open_set(g.V3, F3, F2) == ref_o
        assert _open_set(g.V3, F3) == ref_o  # without the pattern too
        # the same 3D/2D edges are paired
        h2 = half_edges(F2)
        got = {tuple(sorted(map(tuple, np.sort(h2[q], axis=1)))) for q in seam_halfedges(F3, F2)}
        h2r = half_edges(g.F2)
        want = {tuple(sorted(map(tuple, np.sort(h2r[q], axis=1)))) for q in ref_p}
        assert got == want


def test_tseam_strip_lying_flat_on_the_panel():
    """Placket-like: the strip lies on the tube's surface, so geometry alone is ambiguous."""
    for sign in (1.0, -1.0):
        for rows in ((4, 12), (8, 16)):
            g = tseam_tube(rows=rows)
            V3 = g.V3.copy()
            n3 = N_AROUND * (N_ALONG + 1)
            r = float(np.hypot(*g.V3[N_AROUND // 2, [0, 2]]))
            w = V3[n3:, 2] - r
            V3[n3:, 0] = sign * w
            V3[n3:, 2] = r + 0.2
            for F2 in (None, g.F2):
                ops = openings(V3, g.F3, F2=F2, frame=Frame())
                assert [o.name for o in ops] == ["hem", "waist", "opening_2"]
                assert [o.closed for o in ops] == [True, True, False]
                np.testing.assert_allclose([o.length for o in ops[:2]], [60.0, 60.0])


def _tri_pair(touch: bool):
    """Two triangles (a bow-tie when ``touch``) in 3D and 2D."""
    V3 = np.array([[0, 0, 0], [1, 1, 0], [1, -1, 0], [-1, 1, 0], [-1, -1, 0]], float)
    F3 = np.array([[0, 2, 1], [0, 3, 4]])
    return V3, F3


def test_bow_tie_vertex_gives_two_simple_loops():
    V3, F3 = _tri_pair(True)
    for F in (F3, F3[::-1], np.roll(F3, 1, axis=1)):
        loops = boundary_loops(F)
        assert [lp.tolist() for lp in loops] == [[0, 2, 1], [0, 3, 4]]
        ops = openings(V3, F, frame=Frame())
        assert len(ops) == 2 and all(o.closed and o.length > 0 for o in ops)


def _grid(nx, ny, x0=0.0, y0=0.0, base=0):
    x, y = np.meshgrid(np.arange(nx + 1) + x0, np.arange(ny + 1) + y0)
    V = np.stack([x.ravel(), y.ravel()], axis=1).astype(float)
    i = np.arange((nx + 1) * (ny + 1)).reshape(ny + 1, nx + 1) + base
    a, b, c, d = i[:-1, :-1], i[:-1, 1:], i[1:, 1:], i[1:, :-1]
    F = np.concatenate(
        [np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)]
    )
    return V, F


def test_panels_touching_at_one_boundary_vertex(tmp_path):
    """Two square panels meeting at one corner: four boundary edges at that vertex."""
    Va, Fa = _grid(3, 3)
    Vb, Fb = _grid(3, 3, 3.0, 3.0, base=16)
    V2 = np.concatenate([Va, Vb + np.array([1.0, 1.0])])  # apart in the pattern
    F2 = np.concatenate([Fa, Fb])
    # one drape vertex for the shared corner (a: index 15, b: index 16)
    remap = np.r_[np.arange(16), np.arange(16) + 15]
    F3 = remap[F2]
    V3 = np.c_[np.concatenate([Va, Vb[1:]]), np.zeros(31)]
    ref = None
    for seed in range(6):
        rng = np.random.default_rng(seed)
        p = rng.permutation(len(F3))
        loops = boundary_loops(F3[p], V=V3)
        assert [len(lp) for lp in loops] == [12, 12]
        assert all(len(np.unique(lp)) == len(lp) for lp in loops)
        got = [lp.tolist() for lp in loops]
        ref = got if ref is None else ref
        assert got == ref
        ops = openings(V3, F3[p], frame=Frame())
        assert [o.length for o in ops] == [12.0, 12.0]
    # the CLI reads it with exit 0
    from ptailor.model.garment import Garment

    g = Garment(
        V3=V3, F3=F3, V2=V2, F2=F2, face_group=np.full(len(F3), -1), group_names=(), units="cm"
    )
    write_garment(tmp_path / "bow.obj", g)
    args = ["inspect", str(tmp_path / "bow.obj"), "--drape-units", "cm", "--pattern-units", "cm"]
    r = CliRunner().invoke(cli, args, catch_exceptions=False)  # 6 cm across: units given
    assert r.exit_code == 0, r.output


def test_pinched_loop_is_split_into_simple_loops():
    # a C of five triangles whose tips touch at vertex 0: one boundary through 0 twice
    F = np.array([[0, 1, 2], [2, 1, 3], [2, 3, 4], [4, 3, 5], [4, 5, 0]])
    for seed in range(4):
        p = np.random.default_rng(seed).permutation(len(F))
        loops, closed = boundary_curves(F[p])
        assert closed.all()
        assert sorted(sorted(lp.tolist()) for lp in loops) == [[0, 1, 3, 5], [0, 2, 4]]
        for lp in loops:
            assert len(np.unique(lp)) == len(lp) and lp[0] == lp.min()


def test_degenerate_faces_and_short_loops_dropped():
    V3 = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 5, 5]], float)
    F = np.array([[0, 1, 2], [0, 0, 1], [3, 3, 3]])
    assert [lp.tolist() for lp in boundary_loops(F)] == [[0, 1, 2]]
    ops = openings(V3, F, frame=Frame())
    assert len(ops) == 1 and ops[0].length > 0


@pytest.fixture
def tseam_obj(tmp_path) -> Path:
    p = tmp_path / "tseam.obj"
    write_garment(p, tseam_tube())
    return p


@pytest.mark.slow
def test_cli_inspect_and_adjust_on_a_tseam(tseam_obj, tmp_path):
    runner = CliRunner()
    r = runner.invoke(cli, ["inspect", str(tseam_obj), "--json"], catch_exceptions=False)
    assert r.exit_code == 0, r.output
    info = json.loads(r.output)
    sm = [x for x in info["seams"] if sorted(x["panels"]) == ["strip", "tube"]]
    assert len(sm) == 1 and sm[0]["edges"] == 8
    np.testing.assert_allclose(sm[0]["lengths"], [20.0, 20.0])
    ops = info["openings"]
    assert len(ops) == 3 and all(o["length"] > 0 for o in ops)
    (tmp_path / "id.yaml").write_text("steps: []\n")
    (tmp_path / "wide.yaml").write_text(
        "steps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.2}]\n"
    )
    out = tmp_path / "out_id"
    r = runner.invoke(
        cli,
        ["adjust", str(tseam_obj), str(tmp_path / "id.yaml"), "-o", str(out)],
        catch_exceptions=False,
    )
    assert r.exit_code == 0, r.output
    a, b = read_obj(tseam_obj), read_obj(out / "garment.obj")
    np.testing.assert_allclose(b.vt, a.vt, atol=1e-6)
    np.testing.assert_allclose(b.v, a.v, atol=1e-6)
    out = tmp_path / "out_wide"
    r = runner.invoke(
        cli,
        ["adjust", str(tseam_obj), str(tmp_path / "wide.yaml"), "-o", str(out)],
        catch_exceptions=False,
    )
    assert r.exit_code == 0, r.output
    rep = json.loads((out / "report.json").read_text())
    t = [x for x in rep["seams"] if sorted(x["panels"]) == ["strip", "tube"]]
    assert len(t) == 1 and t[0]["ratio_after"] == pytest.approx(1.0, abs=1e-6)


def _fuzz_mesh(seed):
    """A grid with random vertices merged, faces dropped and reversed copies added."""
    rng = np.random.default_rng(seed)
    _, F = _grid(6, 5)
    n = int(F.max()) + 1
    m = np.arange(n)
    for _ in range(rng.integers(0, 6)):
        a, b = rng.integers(0, n, 2)
        m[m == a] = m[b]
    F = m[F]
    F = F[rng.random(len(F)) > 0.2]
    F = np.vstack([F, F[rng.integers(0, len(F), rng.integers(0, 4))][:, ::-1]])
    V = np.c_[rng.random((n, 2)), np.zeros(n)]
    return V, F


@pytest.mark.parametrize("seed", range(0, 120, 3))
def test_fuzzed_non_manifold_meshes_trace_simple_boundary_curves(seed):
    """Merged vertices, holes and doubled faces: simple curves of boundary edges, always."""
    V, F = _fuzz_mesh(seed)
    ref = {}
    for s in range(3):
        rng = np.random.default_rng(s)
        p = rng.permutation(len(F))
        cols = (np.arange(3)[None, :] + rng.integers(0, 3, len(p))[:, None]) % 3
        G = F[p][np.arange(len(p))[:, None], cols]
        be = {tuple(e) for e in np.sort(boundary_edges(G), axis=1).tolist()}
        for key, VV in (("topology", None), ("geometry", V)):
            loops, closed = boundary_curves(G, V=VV)
            got = ([lp.tolist() for lp in loops], closed.tolist())
            assert ref.setdefault(key, got) == got
            for lp, c in zip(loops, closed, strict=True):
                assert len(lp) >= 3 and len(np.unique(lp)) == len(lp)
                e = np.c_[lp, np.roll(lp, -1)][: len(lp) if c else len(lp) - 1]
                assert {tuple(x) for x in np.sort(e, axis=1).tolist()} <= be


@pytest.mark.parametrize("rows", [(4, 12), (8, 16)])
def test_cli_inspect_same_for_shuffled_faces(rows, tmp_path):
    import dataclasses

    g = tseam_tube(rows=rows)
    F3, F2, p = _shuffled(g, 7)
    write_garment(tmp_path / "a.obj", g)
    write_garment(
        tmp_path / "b.obj", dataclasses.replace(g, F3=F3, F2=F2, face_group=g.face_group[p])
    )
    runner = CliRunner()
    out = []
    for name in ("a.obj", "b.obj"):
        r = runner.invoke(cli, ["inspect", str(tmp_path / name), "--json"], catch_exceptions=False)
        assert r.exit_code == 0, r.output
        out.append(json.loads(r.output))
    for key in ("panels", "seams", "openings"):
        assert out[0][key] == out[1][key]
    assert [o["name"] for o in out[0]["openings"]][:2] == ["hem", "waist"]
