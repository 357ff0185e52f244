"""``ptailor measure`` and ``inspect --json``'s ``measures``: a garment's points of measure as
a table and as JSON, on generated garments with known answers."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from click.testing import CliRunner

from ptailor.cli.main import cli
from ptailor.formats.obj import write_garment
from ptailor.samples import cone_skirt, cylinder, flat_tee


def run(*args):
    return CliRunner().invoke(cli, [str(a) for a in args], catch_exceptions=False)


@pytest.fixture
def tube(tmp_path) -> Path:
    p = tmp_path / "tube.obj"
    write_garment(p, cylinder(circumference=40.0, height=24.0, n_around=32, n_along=8))
    return p


@pytest.fixture
def tee(tmp_path) -> Path:
    p = tmp_path / "tee.obj"
    write_garment(p, flat_tee())
    return p


def _json(*args) -> dict:
    r = run("measure", *args, "--json")
    assert r.exit_code == 0, r.output
    return json.loads(r.stdout)


def test_json_of_a_tube_has_its_girths_and_length(tube):
    out = _json(tube)
    assert out["units"] == "cm"
    by = {d["name"]: d for d in out["measures"]}
    assert {"waist", "hem"} <= set(by)
    for name in ("waist", "hem"):  # a regular 32-gon of perimeter 40
        assert by[name]["kind"] == "girth"
        assert by[name]["drape"] == pytest.approx(40.0, rel=5e-3)
        assert by[name]["pattern"] == pytest.approx(40.0, rel=5e-3)
    length = [d for d in out["measures"] if d["kind"] == "length"]
    assert length and all(d["drape"] == pytest.approx(24.0, rel=5e-3) for d in length)


def test_units_scale_every_length(tube):
    cm, mm = _json(tube), _json(tube, "--units", "mm")
    assert mm["units"] == "mm"
    assert [d["name"] for d in mm["measures"]] == [d["name"] for d in cm["measures"]]
    for a, b in zip(cm["measures"], mm["measures"], strict=True):
        assert b["drape"] == pytest.approx(10 * a["drape"], rel=1e-6)
        assert b["pattern"] == pytest.approx(10 * a["pattern"], rel=1e-6)
        if "height" in a:
            assert b["height"] == pytest.approx(10 * a["height"], rel=1e-6, abs=1e-3)


def test_table_lists_each_measure_with_its_difference(tee):
    r = run("measure", tee)
    assert r.exit_code == 0, r.output
    lines = r.stdout.splitlines()
    assert lines[0].split()[:2] == ["measure", "kind"] and "pattern-drape" in lines[0]
    rows = {ln.split()[0]: ln.split() for ln in lines[2:]}
    out = {d["name"]: d for d in _json(tee)["measures"]}
    assert {"chest", "hem", "sleeve_length_left", "sleeve_length_right"} <= set(rows)
    assert list(rows) == list(out)  # the same measures, in the same order
    for name, cells in rows.items():
        kind, drape, pattern, diff = cells[1], *map(float, cells[2:5])
        assert kind == out[name]["kind"]
        assert drape == pytest.approx(out[name]["drape"], abs=0.006)
        assert pattern == pytest.approx(out[name]["pattern"], abs=0.006)
        assert diff == pytest.approx(pattern - drape, abs=0.011)


def test_the_cone_skirt_matches_its_closed_form(tmp_path):
    g = cone_skirt()
    p = tmp_path / "skirt.obj"
    write_garment(p, g)
    by = {d["name"]: d for d in _json(p)["measures"]}
    # the waist and hem rings are regular polygons: their perimeters are the drape's rings
    ys = g.V3[:, 1]
    for name, y in (("waist", ys.max()), ("hem", ys.min())):
        ring = g.V3[abs(ys - y) < 1e-9]
        r = float(math.hypot(*ring[0, [0, 2]]))
        n = len(ring)
        assert by[name]["drape"] == pytest.approx(2 * n * r * math.sin(math.pi / n), rel=5e-3)
        assert by[name]["pattern"] == pytest.approx(by[name]["drape"], rel=5e-3)


def test_inspect_json_has_the_same_measures(tube):
    r = run("inspect", tube, "--json")
    assert r.exit_code == 0, r.output
    assert json.loads(r.stdout)["measures"] == _json(tube)["measures"]


def test_a_missing_garment_is_one_line_exit_2(tmp_path):
    r = run("measure", tmp_path / "nope.obj")
    assert r.exit_code == 2
    assert r.stderr.count("\n") == 1 and "nope.obj" in r.stderr
