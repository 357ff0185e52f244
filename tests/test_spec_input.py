"""Specification JSON read within limits and matched as written (issue 43): huge numbers,
wrong types, deep or repeated JSON refused where they are read (exit 2 naming the file and
the field); re-rooted edge loops, self-stitches and a missing ``units_in_meter`` matched."""

from __future__ import annotations

import copy
import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from ptailor import tolerances as tol
from ptailor.cli.main import cli
from ptailor.errors import PtailorError
from ptailor.formats.json_input import json_depth, parse_json, read_json
from ptailor.formats.obj import write_garment
from ptailor.formats.spec_json import read_specification
from ptailor.model.structure import structure
from ptailor.pieces.draw import outer_loop
from ptailor.samples import bodice, flat_tee
from ptailor.spec.match import match_specification

from .conftest import GARMENTS
from .test_spec import IDENTITY, TEE6, TEE6_UNITS, need, run, sample_spec


def _spec_dict() -> dict:
    """A small valid GarmentCode-style specification (two squares stitched twice)."""
    sq = {
        "vertices": [[0, 0], [10, 0], [10, 10], [0, 10]],
        "edges": [{"endpoints": [i, (i + 1) % 4]} for i in range(4)],
        "translation": [0, 0, 0],
        "rotation": [0, 0, 0],
    }
    return {
        "pattern": {
            "panels": {"front": copy.deepcopy(sq), "back": copy.deepcopy(sq)},
            "stitches": [
                [{"panel": "front", "edge": 1}, {"panel": "back", "edge": 3}],
                [{"panel": "front", "edge": 3}, {"panel": "back", "edge": 1}],
            ],
        },
        "properties": {"units_in_meter": 100, "curvature_coords": "relative"},
    }


def _refused(tmp_path: Path, text: str, *words: str) -> str:
    p = tmp_path / "s_specification.json"
    p.write_text(text)
    with pytest.raises(PtailorError) as exc:
        read_specification(p)
    msg = str(exc.value)
    assert str(p) in msg and "\n" not in msg, msg
    for w in words:
        assert w in msg, msg
    return msg


def _changed(change) -> str:
    d = _spec_dict()
    change(d)
    return json.dumps(d)


def test_the_small_specification_reads(tmp_path):
    p = tmp_path / "s.json"
    p.write_text(json.dumps(_spec_dict()))
    s = read_specification(p)
    assert len(s.panels) == 2 and len(s.stitches) == 2 and s.units_source == "file"


@pytest.mark.parametrize(
    ("where", "words"),
    [
        (lambda d: d["pattern"]["panels"]["front"]["vertices"].__setitem__(1, [1e300, 0]),
         ["vertex 1", "beyond"]),
        (lambda d: d["pattern"]["panels"]["front"]["translation"].__setitem__(0, -1e300),
         ["translation", "beyond"]),
        (lambda d: d["pattern"]["panels"]["front"]["edges"][0].__setitem__(
            "curvature", {"type": "circle", "params": [1e300, 0, 1]}), ["edge 0", "beyond"]),
        (lambda d: d["pattern"]["panels"]["front"]["edges"][0].__setitem__(
            "curvature", {"type": "quadratic", "params": [[0.5, 1e300]]}), ["edge 0", "beyond"]),
        (lambda d: d["properties"].__setitem__("units_in_meter", 1e-300), ["units_in_meter"]),
    ],
)  # fmt: skip
def test_a_huge_finite_number_is_refused_where_it_is_read(tmp_path, where, words):
    _refused(tmp_path, _changed(where), *words)


@pytest.mark.parametrize("value", [3, True, "x", {"a": 1}])
def test_stitches_not_a_list(tmp_path, value):
    _refused(
        tmp_path,
        _changed(lambda d: d["pattern"].__setitem__("stitches", value)),
        "pattern.stitches",
    )


def test_a_stitch_side_whose_panel_is_a_list(tmp_path):
    def change(d):
        d["pattern"]["stitches"][0][0]["panel"] = ["front"]

    _refused(tmp_path, _changed(change), "stitch 0", "panel name")


@pytest.mark.parametrize("digits", [400, 5000])
def test_a_long_integer_is_refused(tmp_path, digits):
    text = _changed(lambda d: None).replace(
        '"units_in_meter": 100', f'"units_in_meter": {"9" * digits}'
    )
    _refused(tmp_path, text, "not a JSON specification", f"{digits} digits")


def test_deep_json_is_refused_before_it_is_parsed(tmp_path):
    deep = "[" * 100_000 + "]" * 100_000
    text = _changed(lambda d: None).replace('"relative"}', '"relative", "x": ' + deep + "}")
    _refused(tmp_path, text, "nested 100", "deep")
    assert json_depth('{"a": "[[[[", "b": [[1]]}') == 3  # strings do not count


def test_a_repeated_panel_key_is_refused(tmp_path):
    text = json.dumps(_spec_dict())
    one = json.dumps(_spec_dict()["pattern"]["panels"]["front"])
    text = text.replace('"panels": {', '"panels": {"front": ' + one + ", ", 1)
    _refused(tmp_path, text, "'front'", "twice")


@pytest.mark.parametrize("coords", ["Absolute", "abs", 1, None])
def test_curvature_coords_other_than_relative_or_absolute(tmp_path, coords):
    _refused(
        tmp_path,
        _changed(lambda d: d["properties"].__setitem__("curvature_coords", coords)),
        "curvature_coords",
    )


def test_a_repeated_stitch_is_refused_either_way_round(tmp_path):
    def change(d):
        st = d["pattern"]["stitches"]
        st += [list(reversed(st[0]))] * 10_000

    _refused(tmp_path, _changed(change), "stitch 2", "repeats stitch 0")


def test_a_stitch_of_an_edge_to_itself(tmp_path):
    def change(d):
        d["pattern"]["stitches"][0][1] = dict(d["pattern"]["stitches"][0][0])

    _refused(tmp_path, _changed(change), "stitch 0", "to itself")


@pytest.mark.parametrize(
    "inf", [{"panel": {"a": 1}, "edge_list": [0]}, [1], {"panel": "front", "edge_list": 3}]
)
def test_a_design_parameter_influence_of_the_wrong_type(tmp_path, inf):
    def change(d):
        d["parameters"] = {"length": {"influence": [inf], "type": "length", "value": 1}}

    _refused(tmp_path, _changed(change), "design parameter 'length'", "influence 0")


def test_the_shared_reader_limits(tmp_path):
    p = tmp_path / "c.json"
    p.write_text('{"a": 1}')
    assert read_json(p, what="catalogue") == {"a": 1}
    with pytest.raises(PtailorError, match="larger than 4 bytes"):
        read_json(p, what="catalogue", max_bytes=4)
    with pytest.raises(PtailorError, match="not a JSON catalogue"):
        parse_json("[" * (tol.JSON_MAX_DEPTH + 1), path=p, what="catalogue")
    assert parse_json('{"x": 1e400}', path=p, what="x")["x"] == np.inf  # bounded by callers


def test_cli_exit_2_names_the_file_and_writes_nothing(tmp_path):
    g = tmp_path / "g.obj"
    write_garment(g, bodice(n_around=24, n_along=8))
    bad = tmp_path / "g_specification.json"
    bad.write_text(_changed(lambda d: d["pattern"].__setitem__("stitches", 7)))
    recipe = tmp_path / "id.yaml"
    recipe.write_text(IDENTITY)
    r = run("adjust", g, recipe, "--spec", bad, "-o", tmp_path / "out")
    assert r.exit_code == 2 and str(bad) in r.output and "Traceback" not in r.output, r.output
    assert not (tmp_path / "out").exists()


# ---------------------------------------------------------------------------------------
# matched as written: re-rooted loops, self-stitches, no units_in_meter
# ---------------------------------------------------------------------------------------


def _rerooted(d: dict, panel: str, r: int) -> dict:
    """``d`` with ``panel``'s edge loop starting ``r`` edges later (GarmentCode's loader
    re-roots loops), its stitches renumbered."""
    d = copy.deepcopy(d)
    p = d["pattern"]["panels"][panel]
    n = len(p["edges"])
    p["edges"] = p["edges"][r:] + p["edges"][:r]
    for s in d["pattern"]["stitches"]:
        for side in s:
            if side["panel"] == panel:
                side["edge"] = (side["edge"] - r) % n
    return d


@pytest.mark.slow
@pytest.mark.parametrize(("panel", "r"), [("front", 1), ("front", 3), ("back", 1), ("back", 3)])
def test_a_rerooted_loop_of_a_symmetric_panel_is_matched(tmp_path, panel, r):
    """The bodice's front and back are symmetric: both mirror fits are kept and the
    stitches choose (before: one fit kept, and 'no seam of the garment joins')."""
    g = bodice(n_around=48, n_along=16)
    st = structure(g)
    base = json.loads(sample_spec(g, tmp_path / "b.json").read_text())
    q = tmp_path / "rerooted.json"
    q.write_text(json.dumps(_rerooted(base, panel, r)))
    m = match_specification(g, read_specification(q), st.panels, seams=st.seams)
    names = [p.name for p in st.panels]
    spec = read_specification(q)
    assert [names[pm.panel] for pm in m.panels] == [p.name for p in spec.panels]
    assert len(m.stitches) == len(spec.stitches)


def tee_spec(g, path: Path) -> Path:
    """A specification of a generated tee: per panel its outline split where it turns or
    where the seam along it changes (a self-seam's two sides apart), straight edges; edges
    over the same drape vertices stitched (a one-piece sleeve's underarm to itself)."""
    from scipy.spatial.transform import Rotation

    st = structure(g)
    v3 = np.full(len(g.V2), -1)
    v3[g.F2.ravel()] = g.F3.ravel()
    side = {}
    for k, s in enumerate(st.seams):  # pattern edge -> (seam, side)
        for tag, E in (("a", s.edges_a), ("b", s.edges_b)):
            for a, b in E:
                side[min(a, b), max(a, b)] = (k, tag)
    panels, runs = {}, []
    for p in st.panels:  # a loop over panels
        L = outer_loop(g.F2, p.faces, g.V2)
        P = g.V2[L]
        lab = [
            side.get((min(a, b), max(a, b)), (-1, ""))
            for a, b in zip(L, np.roll(L, -1), strict=True)
        ]
        d0, d1 = P - np.roll(P, 1, axis=0), np.roll(P, -1, axis=0) - P
        turn = np.abs(d0[:, 0] * d1[:, 1] - d0[:, 1] * d1[:, 0]) > 1e-9 * (d0**2).sum(1)
        brk = [i for i in range(len(L)) if turn[i] or lab[i] != lab[i - 1]]
        verts = [P[i].tolist() for i in brk]
        edges = [{"endpoints": [k, (k + 1) % len(brk)]} for k in range(len(brk))]
        for k, i in enumerate(brk):  # each edge's drape vertices
            j = brk[(k + 1) % len(brk)]
            idx = L[i : j + 1] if j > i else np.concatenate([L[i:], L[: j + 1]])
            runs.append((p.name, k, frozenset(v3[idx].tolist()), lab[i][0] >= 0))
        u = np.unique(g.F2[p.faces])
        X3, X2 = g.V3[v3[u]], np.c_[g.V2[u], np.zeros(len(u))]
        rot, _ = Rotation.align_vectors(X3 - X3.mean(0), X2 - X2.mean(0))
        panels[p.name] = {
            "translation": (X3.mean(0) - rot.apply(X2.mean(0))).tolist(),
            "rotation": rot.as_euler("xyz", degrees=True).tolist(),
            "vertices": verts,
            "edges": edges,
        }
    stitches = [
        [{"panel": a[0], "edge": a[1]}, {"panel": b[0], "edge": b[1]}]
        for n, a in enumerate(runs)
        for b in runs[n + 1 :]
        if a[3] and b[3] and a[2] == b[2]
    ]
    spec = {
        "pattern": {"panels": panels, "stitches": stitches},
        "properties": {"units_in_meter": 100},
    }
    path.write_text(json.dumps(spec, indent=2))
    return path


@pytest.mark.slow
def test_one_piece_sleeves_stitched_to_themselves_give_the_specification_back(tmp_path):
    g = flat_tee(sleeves="one")
    garment = tmp_path / "tee.obj"
    write_garment(garment, g)
    spec = tee_spec(g, tmp_path / "tee_specification.json")
    want = json.loads(spec.read_text())
    selfs = [s for s in want["pattern"]["stitches"] if s[0]["panel"] == s[1]["panel"]]
    assert {s[0]["panel"] for s in selfs} == {"sleeve_left", "sleeve_right"}
    recipe = tmp_path / "id.yaml"
    recipe.write_text(IDENTITY)
    out = tmp_path / "o"
    r = run("adjust", garment, recipe, "--spec", spec, "-o", out, "--formats", "obj")
    assert r.exit_code == 0, r.output
    got = json.loads((out / "specification.json").read_text())
    assert got["pattern"]["stitches"] == want["pattern"]["stitches"]
    for name, p in want["pattern"]["panels"].items():
        q = got["pattern"]["panels"][name]
        assert np.abs(np.array(q["vertices"]) - p["vertices"]).max() <= 0.01  # cm


@pytest.mark.slow
def test_tee6_without_units_in_meter_is_read_in_its_unit(tmp_path):
    """tee6's specification is in 1/300 m: without the key it is 3.0x the garment in cm;
    the unit comes from the garment, and identity writes the file back within 0.01 cm."""
    src = need(TEE6 / "tee6_specification.json")
    d = json.loads(src.read_text())
    del d["properties"]["units_in_meter"]
    spec = tmp_path / "tee6_specification.json"
    spec.write_text(json.dumps(d))
    recipe = tmp_path / "id.yaml"
    recipe.write_text(IDENTITY)
    out = tmp_path / "o"
    r = run("adjust", TEE6 / "tee6_sim.obj", recipe, *TEE6_UNITS, "--spec", spec, "-o", out,
            "--formats", "obj")  # fmt: skip
    assert r.exit_code == 0, r.output
    rep = json.loads((out / "report.json").read_text())
    assert rep["spec"]["units_in_meter"] == 300 and rep["spec"]["units_source"] == "garment"
    got = json.loads((out / "specification.json").read_text())
    assert "units_in_meter" not in got["properties"]
    for name, p in d["pattern"]["panels"].items():
        q = got["pattern"]["panels"][name]
        assert np.abs(np.array(q["vertices"]) - p["vertices"]).max() / 3.0 <= 0.01  # cm
    # forced: --spec-units cm reads it 3x too large, and no panel matches
    r = run("adjust", TEE6 / "tee6_sim.obj", recipe, *TEE6_UNITS, "--spec", spec, "-o",
            tmp_path / "o2", "--spec-units", "cm")  # fmt: skip
    assert r.exit_code == 2 and "shape and size" in r.output, r.output


@pytest.mark.slow
def test_garmentcode_shorts_darts_are_matched():
    """The shorts' back panels stitch their darts to themselves (before: 'no seam joins
    panels leg_back_right and leg_back_right'), and the waistband's flip is left to the
    stitches."""
    d = GARMENTS / "garmentcode_more"
    need(d / "shorts_specification.json")
    args = ["inspect", d / "shorts_boxmesh.obj", "--pattern-units", "auto"]
    args += ["--spec", d / "shorts_specification.json", "--json"]
    r = CliRunner().invoke(cli, [str(a) for a in args])
    assert r.exit_code == 0, r.output
    sec = json.loads(r.output)["spec"]
    darts = [
        s for s in sec["stitches"] if s["sides"][0].split(".")[0] == s["sides"][1].split(".")[0]
    ]
    assert len(darts) == 4 and len(sec["stitches"]) == 24
