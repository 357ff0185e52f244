"""The points-of-measure pictures (issue 41): the drawing function on the samples, the committed
pictures of docs/measures/, and ``adjust --show-measures`` on pattern.svg and preview.png."""

from __future__ import annotations

import importlib.util
import re
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from ptailor.cli.main import cli
from ptailor.formats.obj import write_garment
from ptailor.formats.pom import POM_COLOURS, pattern_lines, pom_colour
from ptailor.formats.pom_svg import measures_svg
from ptailor.measures import MEASURES, garment_measures
from ptailor.model.structure import structure
from ptailor.samples import cone_skirt, flat_tee, gored_skirt

ROOT = Path(__file__).resolve().parents[1]
PICTURES = ROOT / "docs" / "measures"
NUMBER = re.compile(r"-?\d+\.\d+")


def _make():
    """docs/measures/make.py as a module."""
    spec = importlib.util.spec_from_file_location("make_measures", PICTURES / "make.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _labels(svg: str) -> list[str]:
    return re.findall(r'class="pom-label"[^>]*>([^<]+)</text>', svg)


def _box(paths: list[str]) -> tuple[np.ndarray, np.ndarray]:
    P = np.array([float(x) for d in paths for x in NUMBER.findall(d)]).reshape(-1, 2)
    return P.min(axis=0), P.max(axis=0)


def _between(svg: str, a: str, b: str) -> str:
    return svg[svg.index(a) : svg.index(b)]


@pytest.mark.parametrize("make", [flat_tee, gored_skirt], ids=["tee", "skirt"])
def test_every_measure_is_named_and_drawn_inside_the_garment(make):
    g = make()
    ms = garment_measures(g)
    assert len(ms) >= 4
    svg = measures_svg(g, ms, title="t")
    labels = _labels(svg)
    for m in ms:
        assert m.name in MEASURES
        # beside the drape with its value, on the pieces by name, in the table
        assert f"{m.name} {m.drape:.1f}" in labels
        assert m.name in labels
        assert f">{m.name}</text>" in svg.split('<g class="pom-table">')[1]
        assert f'data-name="{m.name}"' in svg
    # the drape's lines inside the drape's panels' box, the pattern's inside the pieces' box
    drape = _between(svg, '<g id="drape">', '<g id="pattern">')
    pattern = _between(svg, '<g id="pattern">', '<g class="pom-table">')
    for part, outline in ((drape, "panel"), (pattern, "piece")):
        lo, hi = _box(re.findall(rf'class="{outline}" d="([^"]+)"', part))
        seen = re.findall(r'class="(?:seen|pom)"[^>]* d="([^"]+)"', part)
        a, b = _box(seen)
        assert np.all(a >= lo - 0.01) and np.all(b <= hi + 0.01), (part[:20], a, b, lo, hi)


def test_pattern_lines_lie_in_their_panels_box():
    g = flat_tee()
    st = structure(g)
    lines = pattern_lines(garment_measures(g), g.V2, g.F2, st.face_panel)
    assert {ml.name for ml in lines} == {m.name for m in garment_measures(g)}
    for ml in lines:
        for p in np.unique(ml.panel):
            V = g.V2[st.panels[p].vertices]
            mine = ml.panel == p
            lo, hi = V.min(axis=0) - 1e-9, V.max(axis=0) + 1e-9
            for E in (ml.A[mine], ml.B[mine]):
                assert np.all(E - lo >= 0) and np.all(hi - E >= 0)
        assert ml.colour == POM_COLOURS[ml.name.removesuffix("_left").removesuffix("_right")]
    assert pom_colour("bicep_left") == pom_colour("bicep_right") != pom_colour("chest")


def _same_numbers(a: str, b: str, tol: float = 0.02) -> bool:
    """The same text but for numbers within ``tol`` (another platform's last decimal)."""
    if NUMBER.sub("#", a) != NUMBER.sub("#", b):
        return False
    x = np.array(NUMBER.findall(a), dtype=float)
    y = np.array(NUMBER.findall(b), dtype=float)
    return bool(np.all(np.abs(x - y) <= tol))


@pytest.mark.slow
def test_the_committed_pictures_are_what_is_drawn_today():
    """docs/measures/*.svg as ``docs/measures/make.py`` draws them (rerun it after a change
    of the measures or of the drawing); the dress only where ../shared is."""
    drawn = _make().pictures()
    assert {"tee", "skirt"} <= set(drawn)
    for name, svg in drawn.items():
        committed = (PICTURES / f"{name}.svg").read_text()
        assert _same_numbers(svg, committed), f"docs/measures/{name}.svg: run make.py"
    for name in ("tee", "skirt", "dress"):
        labels = _labels((PICTURES / f"{name}.svg").read_text())
        assert len(labels) >= 8, name


def _adjust(tmp_path, *options):
    g = tmp_path / "skirt.obj"
    if not g.exists():
        write_garment(g, cone_skirt(n_around=16, n_along=8))
    recipe = tmp_path / "wider.yaml"
    recipe.write_text("steps: [{op: scale, region: all, direction: around, factor: 1.1}]\n")
    out = tmp_path / ("with" if options else "without")
    args = ["adjust", str(g), str(recipe), "-o", str(out), "--formats", "svg,png", "--no-baseline"]
    r = CliRunner().invoke(cli, [*args, *options], catch_exceptions=False)
    assert r.exit_code == 0, r.output
    return out


@pytest.mark.slow
def test_show_measures_draws_them_on_pattern_svg_and_preview_png(tmp_path):
    """``--show-measures`` adds the adjusted garment's measures (a ``<g id="measures">``, each
    measure named) to pattern.svg and draws them on preview.png; without it the outputs are
    as before (the golden runs hold that too)."""
    from PIL import Image

    plain = _adjust(tmp_path)
    shown = _adjust(tmp_path, "--show-measures")
    a, b = (plain / "pattern.svg").read_text(), (shown / "pattern.svg").read_text()
    assert "pom" not in a
    labels = _labels(b)
    for name in ("waist", "hip", "hem", "skirt_length"):
        assert name in labels
    # the flag adds the measures' group and changes nothing else
    assert b[: b.index('<g id="measures">')] + b[b.index('<g id="scale-bar">') :] == a
    pa = np.asarray(Image.open(plain / "preview.png").convert("RGB"))
    pb = np.asarray(Image.open(shown / "preview.png").convert("RGB"))
    assert pa.shape == pb.shape and (pa != pb).any(axis=2).mean() > 0.002
    hip = tuple(int(POM_COLOURS["hip"][i : i + 2], 16) for i in (1, 3, 5))
    assert (pb == hip).all(axis=2).sum() > 50 and (pa == hip).all(axis=2).sum() == 0
