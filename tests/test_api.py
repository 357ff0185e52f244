"""The Python API (``ptailor.load_garment``, ``adjust``, ``write``, ``flatten``): lazy, the
command line's run, errors as :class:`ptailor.PtailorError`."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import ptailor
from ptailor.cli.main import cli
from ptailor.formats import reader_for
from ptailor.formats.obj import write_garment
from ptailor.samples import flat_tee

AROUND = "units: cm\nsteps: [{op: scale, region: all, direction: around, factor: 1.15}]\n"


@pytest.fixture(scope="module")
def tee_obj(tmp_path_factory) -> Path:
    p = tmp_path_factory.mktemp("api") / "tee.obj"
    write_garment(p, flat_tee())
    return p


@pytest.mark.slow
def test_import_ptailor_is_cheap_and_lends_the_api():
    code = (
        "import sys, ptailor; print('numpy' in sys.modules, 'ptailor.api' in sys.modules);"
        "ptailor.adjust; print('ptailor.api' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "False", "True"]
    for name in ptailor.__all__:
        assert getattr(ptailor, name) is not None
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        ptailor.nope  # noqa: B018


def test_recipe_forms(tmp_path):
    path = tmp_path / "r.yaml"
    path.write_text(AROUND)
    recipes = [
        ptailor.as_recipe(AROUND),
        ptailor.as_recipe(str(path)),
        ptailor.as_recipe(path),
        ptailor.as_recipe({"units": "cm", "steps": [
            {"op": "scale", "region": "all", "direction": "around", "factor": 1.15}]}),
    ]  # fmt: skip
    assert len({json.dumps(r.to_dict(), sort_keys=True) for r in recipes}) == 1
    with pytest.raises(ptailor.PtailorError, match="path, YAML text or a dict"):
        ptailor.as_recipe(3)
    with pytest.raises(ptailor.PtailorError, match="no such file"):
        ptailor.as_recipe(str(tmp_path / "missing.yaml"))
    with pytest.raises(ptailor.PtailorError, match="steps"):
        ptailor.as_recipe({"steps": [{"op": "nope"}]})


def test_load_errors_raise(tmp_path):
    with pytest.raises(ptailor.PtailorError, match=r"missing\.obj"):
        ptailor.load_garment(tmp_path / "missing.obj")
    with pytest.raises(ptailor.PtailorError, match="--up"):
        ptailor.load_garment(tmp_path / "missing.obj", up="w")


@pytest.mark.slow
def test_api_round_trip_equals_the_cli(tmp_path, tee_obj):
    recipe = tmp_path / "around.yaml"
    recipe.write_text(AROUND)
    r = CliRunner().invoke(cli, ["adjust", str(tee_obj), str(recipe), "-o", str(tmp_path / "c")])
    assert r.exit_code == 0, r.output
    g = ptailor.load_garment(tee_obj)
    a = ptailor.adjust(g, recipe)
    written = ptailor.write(a, tmp_path / "p")
    names = sorted(p.name for p in (tmp_path / "c").iterdir())
    assert names == sorted(p.name for p in (tmp_path / "p").iterdir())
    cli_obj = reader_for(tee_obj)(tmp_path / "c" / "garment.obj")
    api_obj = reader_for(tee_obj)(tmp_path / "p" / "garment.obj")
    assert np.abs(api_obj.vt - cli_obj.vt).max() < 1e-9
    assert np.abs(api_obj.v - cli_obj.v).max() < 1e-9
    assert np.abs(10 * a.garment.V2 - 10 * cli_obj.vt).max() < 1e-5  # (mm: the file's 9 digits)
    cli_report = json.loads((tmp_path / "c" / "report.json").read_text())
    for key in ("steps", "measures", "panels", "units", "method", "outputs"):
        assert written[key] == cli_report[key], key
    assert a.report["outputs"] == ["report.json"]
    assert a.report["measures"] == cli_report["measures"]


@pytest.mark.slow
def test_flatten_gives_the_runs_pattern(tee_obj):
    g = ptailor.load_garment(tee_obj)
    a = ptailor.adjust(g, AROUND, baseline=False)
    V2 = ptailor.flatten(g, a.garment.V3)
    assert V2.shape == g.garment.V2.shape
    assert 10 * np.abs(V2 - a.garment.V2).max() < 0.01  # mm
    assert 10 * np.abs(V2 - g.garment.V2).max() > 10  # (it did move: 1 cm and more)
    with pytest.raises(ptailor.PtailorError, match="has 1 step"):
        ptailor.flatten(g, a.garment.V3, recipe=AROUND)
    with pytest.raises(ptailor.PtailorError, match="1991 vertices"):
        ptailor.flatten(g, a.garment.V3[:-1])


@pytest.mark.slow
def test_recipe_units_read_the_garment_again(tee_obj):
    g = ptailor.load_garment(tee_obj)
    a = ptailor.adjust(g, AROUND.replace("cm", "mm"), baseline=False)
    assert a.garment.units == "mm"
    assert np.allclose(a.adjustment.original.V3, 10 * g.garment.V3)


def test_adjust_and_write_errors(tmp_path, tee_obj):
    g = ptailor.load_garment(tee_obj)
    with pytest.raises(ptailor.PtailorError, match="a recipe or an edited_drape"):
        ptailor.adjust(g)
    with pytest.raises(ptailor.PtailorError, match="has 1 step"):
        ptailor.adjust(g, AROUND, edited_drape=g.garment.V3)
    a = ptailor.adjust(g, "units: cm\nsteps: []\n", baseline=False)
    with pytest.raises(ptailor.PtailorError, match="unknown output format"):
        ptailor.write(a, tmp_path / "o", formats=("obj", "pdfx"))
    foreign = tmp_path / "foreign"
    foreign.mkdir()
    (foreign / "notes.txt").write_text("mine")
    with pytest.raises(ptailor.PtailorError):
        ptailor.write(a, foreign)
    assert (foreign / "notes.txt").read_text() == "mine"


def test_the_api_runs_blas_on_one_thread_as_the_commands_do(monkeypatch):
    """A library's caller loaded numpy (and its BLAS threads) before ptailor: the API limits
    BLAS to one thread for the call (3x less CPU on a loaded machine), and gives the
    caller's setting back after."""
    from threadpoolctl import threadpool_info, threadpool_limits

    import ptailor.api as api
    from ptailor import samples

    seen = []
    real = api.adjustment

    def spy(*args, **kwargs):
        seen.append([i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"])
        return real(*args, **kwargs)

    monkeypatch.setattr(api, "adjustment", spy)
    g = samples.flat_tee()
    np.dot(np.ones((64, 64)), np.ones((64, 64)))  # BLAS loaded
    with threadpool_limits(limits=2, user_api="blas"):
        before = [i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"]
        api.flatten(g, g.V3 * 1.1)
        after = [i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"]
    assert seen and all(n == 1 for n in seen[0])
    assert 2 in before and after == before
