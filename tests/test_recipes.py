"""Every example recipe in recipes/ validates and runs on a generated garment."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ptailor.geometry.topology import half_edges
from ptailor.pipeline import adjustment
from ptailor.recipe import load_recipe, parse_recipe
from ptailor.recipe.bundled import bundled_recipe
from ptailor.samples import SAMPLES, cone_skirt

RECIPES = sorted((Path(__file__).resolve().parents[1] / "recipes").glob("*.yaml"))


class ExpectMissedError(AssertionError):
    """A bundled recipe's ``expect:`` missed on a garment (a known one is marked
    ``xfail(raises=ExpectMissedError, strict=True)`` with its numbers: any other failure of the
    same test still fails it)."""


def _known_miss(reason: str):
    return pytest.mark.xfail(raises=ExpectMissedError, strict=True, reason=reason)


def expectations_met(g, adj, rec) -> list[dict]:
    """The recipe's ``expect:`` judged on ``adj`` (of ``g``), as ``adjust`` judges it; raises
    :class:`ExpectMissedError` naming every miss, and fails where nothing was judged (every
    expectation optional and absent)."""
    from ptailor.report.expect import (
        expect_records,
        garment_measure_dicts,
        measures_before,
        missed_line,
    )

    before = measures_before(g, rec, shown="garment")  # a lacking, not optional one: exit 2
    recs = expect_records(rec, before, garment_measure_dicts(adj.garment))
    assert len(recs) == len(rec.expect) > 0
    assert [r for r in recs if not r.get("skipped")], "no expectation judged on this garment"
    missed = [missed_line(r) for r in recs if not r["ok"]]
    if missed:
        raise ExpectMissedError("; ".join(missed))
    return recs


def _sample(path: Path) -> str:
    """The generated garment a recipe names in its '# sample: NAME' line (lantern_sleeve)."""
    lines = [ln for ln in path.read_text().splitlines() if ln.startswith("# sample:")]
    return lines[0].split(":", 1)[1].strip() if lines else "lantern_sleeve"


#: bundled recipes whose sample has none of the measures they expect (all optional)
NOT_MEASURED_ON_SAMPLE = {
    # the generated bodice's top opening is named waist: no neckline, no neck_drop (judged
    # on flat_tee and the shared tops)
    "deeper-neckline",
}
#: known misses of a bundled recipe's expect: on its sample
SAMPLE_MISSES: dict[str, str] = {}


def _sample_params():
    return [
        pytest.param(p, id=p.stem, marks=[_known_miss(SAMPLE_MISSES[p.stem])])
        if p.stem in SAMPLE_MISSES
        else pytest.param(p, id=p.stem)
        for p in RECIPES
    ]


def test_recipes_folder_is_bundled():
    assert RECIPES
    for p in RECIPES:
        assert bundled_recipe(p.stem) == p.read_text()


@pytest.mark.slow
@pytest.mark.parametrize("path", _sample_params())
def test_recipe_validates_and_runs(path):
    """Every bundled recipe runs on the generated garment its '# sample: NAME' line names,
    with no flipped triangle, and delivers what its ``expect:`` asks there."""
    rec = load_recipe(path)
    g = SAMPLES[_sample(path)]()
    adj = adjustment(g, rec)
    assert np.all(np.isfinite(adj.result.V2))
    F2 = adj.state.base.F2
    E = adj.result.V2[F2[:, 1:]] - adj.result.V2[F2[:, :1]]
    cross = E[:, 0, 0] * E[:, 1, 1] - E[:, 0, 1] * E[:, 1, 0]
    assert np.all(cross > 0)  # no flipped triangle
    if path.stem in NOT_MEASURED_ON_SAMPLE:
        with pytest.raises(AssertionError, match="no expectation judged"):
            expectations_met(g, adj, rec)
    else:
        expectations_met(g, adj, rec)


#: generated kinds other than its sample each bundled recipe is judged on (its expect:)
KINDS = {
    "deeper-neckline": ["flat_tee"],
    "fuller-skirt": ["gored_skirt"],
    "identity": ["cylinder", "cone_skirt", "flat_tee"],
    "lengthen-bodice": ["cone_skirt", "flat_tee"],
    "longer-hem": ["skirt", "bodice", "flat_tee"],
    "longer-sleeves": ["flat_tee"],
    "loosen-waist": ["halved_bodice"],
    "shorter-hem-pattern": ["skirt", "bodice", "flat_tee"],
    "shorter-hem": ["skirt", "bodice", "flat_tee"],
    "v-neck-front": ["cylinder", "bodice"],
    "wider-around": ["cylinder", "cone_skirt", "flat_tee"],
    "wider-sleeves": ["flat_tee"],
}


#: known misses on those kinds
KIND_MISSES = {
    ("loosen-waist", "halved_bodice"): "hem (the band's lower edge) +4.65 cm in the pattern "
    "(78.51 -> 83.16; drape +4.36) for +4 +-0.5 (the design's 2 pi x offset is 4.4): the "
    "three-panel bodice's pattern takes 0.3 cm more than its drape",
}


def _kind_params():
    return [
        pytest.param(
            n, k, id=f"{n}-{k}",
            marks=[_known_miss(KIND_MISSES[n, k])] if (n, k) in KIND_MISSES else [],
        )
        for n, ks in KINDS.items()
        for k in ks
    ]  # fmt: skip


def test_every_bundled_recipe_is_judged_on_other_generated_kinds():
    assert set(KINDS) == {p.stem for p in RECIPES}


@pytest.mark.slow
@pytest.mark.parametrize(("name", "kind"), _kind_params())
def test_recipe_delivers_its_expect_on_generated_kinds(name, kind):
    """Issue 42: the asked measure achieved within its tolerance on every generated kind a
    bundled recipe is meant for (a skirt, a bodice, a tee with sleeves: flat_tee)."""
    import ptailor.samples

    g = (SAMPLES.get(kind) or getattr(ptailor.samples, kind))()
    rec = _recipe(name)
    expectations_met(g, adjustment(g, rec, baseline=False), rec)


def edge_ratio(adj, g, V2):
    h3, h2 = half_edges(g.F3), half_edges(g.F2)
    l3 = np.linalg.norm(adj.state.V3[h3[:, 1]] - adj.state.V3[h3[:, 0]], axis=1)
    l2 = np.linalg.norm(V2[h2[:, 1]] - V2[h2[:, 0]], axis=1)
    return l2 / l3


def test_fuller_cone_skirt_pattern_is_the_exact_development():
    """A developable garment stays developable: the new pattern is isometric to the new drape
    (the recipe names the skirt panels, ``skirt_front`` and ``skirt_back`` of the cone skirt
    without panel names)."""
    from ptailor.samples import unnamed_skirt

    g = unnamed_skirt()
    adj = adjustment(
        g, load_recipe(Path(__file__).resolve().parents[1] / "recipes/fuller-skirt.yaml")
    )
    assert np.abs(edge_ratio(adj, g, adj.result.V2) - 1).max() < 1e-5
    # waist and hem arcs of each panel grow by the factor
    ys = g.V3[:, 1]
    for ring in (ys == ys.max(), ys == ys.min()):
        e = half_edges(g.F3)
        on = ring[e].all(axis=1)
        h2 = half_edges(g.F2)[on]
        before = np.linalg.norm(g.V2[h2[:, 1]] - g.V2[h2[:, 0]], axis=1).sum()
        after = np.linalg.norm(adj.result.V2[h2[:, 1]] - adj.result.V2[h2[:, 0]], axis=1).sum()
        assert after == pytest.approx(1.15 * before, rel=1e-5)


def test_keeping_the_outline_trades_intrinsic_scale():
    """boundary: similar keeps the skirt's arcs' tangents, so its triangles must stretch."""
    g = cone_skirt()
    free = adjustment(
        g,
        parse_recipe(
            "steps: [{op: scale, direction: around, axis: [0,1,0], factor: 1.15}]\n"
            "flatten: {boundary: free}"
        ),
    )
    similar = adjustment(
        g,
        parse_recipe(
            "steps: [{op: scale, direction: around, axis: [0,1,0], factor: 1.15}]\n"
            "flatten: {boundary: similar}"
        ),
    )
    err_free = np.abs(edge_ratio(free, g, free.result.V2) - 1).max()
    err_sim = np.abs(edge_ratio(similar, g, similar.result.V2) - 1).max()
    assert err_sim > 100 * err_free


def _recipe(name: str):
    return load_recipe(Path(__file__).resolve().parents[1] / "recipes" / f"{name}.yaml")


def _edge_length_2d(adj, V2, select3):
    """Total 2D length of pattern boundary edges whose drape ends both satisfy ``select3``."""
    from ptailor.model.boundary import boundary_edges

    g = adj.state.base
    to3 = np.empty(len(g.V2), dtype=np.int64)
    to3[g.F2.ravel()] = g.F3.ravel()
    E = boundary_edges(g.F2)
    keep = select3[to3[E[:, 0]]] & select3[to3[E[:, 1]]]
    return float(np.linalg.norm(V2[E[keep, 1]] - V2[E[keep, 0]], axis=1).sum())


def test_loosen_waist_adds_the_offset_circumference_to_the_pattern_waist():
    """girth: 4 over the band: the mean girth change is 4; the waist (the band's bottom, far
    from its falloff) gains the offset's full 2 pi by, in the pattern too (no stretch)."""
    g = SAMPLES["bodice"]()
    adj = adjustment(g, _recipe("loosen-waist"))
    rec = adj.state.log[0]
    assert rec["asked"] == {"girth": 4.0, "on": "both"}
    assert rec["achieved"]["drape"] == pytest.approx(4.0, abs=0.02)
    assert 4.0 / (2 * np.pi) < rec["by"] < 1.2 * 4.0 / (2 * np.pi)  # the falloff costs some
    low = adj.state.V3[:, 1] < 1e-9
    before = _edge_length_2d(adj, adj.state.base.V2, low)
    after = _edge_length_2d(adj, adj.result.V2, low)
    assert after - before == pytest.approx(2 * np.pi * rec["by"], rel=0.1)


def test_lengthen_bodice_adds_4_cm_to_both_panels():
    from ptailor.model.garment import panels, vertex_labels
    from ptailor.report.metrics import panel_sizes

    g = SAMPLES["bodice"]()
    adj = adjustment(g, _recipe("lengthen-bodice"))
    h0 = panel_sizes(g.V2, vertex_labels(panels(g), len(g.V2)), 2)[:, 1]
    st = adj.state
    h1 = panel_sizes(adj.result.V2, vertex_labels(st.panels, len(adj.result.V2)), 2)[:, 1]
    np.testing.assert_allclose(h1 - h0, 4.0, atol=0.05)


def test_deeper_neckline_cuts_the_front_only_down_to_the_sketch():
    from ptailor.geometry.triangles import signed_areas_2d
    from ptailor.model.garment import panels

    g = SAMPLES["bodice"]()
    adj = adjustment(g, _recipe("deeper-neckline"))
    st = adj.state
    area = {
        p.name: abs(signed_areas_2d(adj.result.V2, st.base.F2[p.faces]).sum()) for p in st.panels
    }
    area0 = {p.name: abs(signed_areas_2d(g.V2, g.F2[p.faces]).sum()) for p in panels(g)}
    assert area["back"] == pytest.approx(area0["back"], rel=1e-9)
    assert area["front"] < 0.97 * area0["front"]
    front = st.V3[:, 2] > 0
    assert st.V3[front, 1].max() > 39 and st.V3[np.abs(st.V3[:, 0]) < 0.5, 1].min() < 1
    top_centre = st.V3[(np.abs(st.V3[:, 0]) < 0.3) & front, 1].max()
    assert top_centre == pytest.approx(29.9, abs=0.3)


@pytest.mark.parametrize(
    ("name", "low", "high"), [("wider-sleeves", 0.18, 0.23), ("longer-sleeves", 0.08, 0.11)]
)
@pytest.mark.slow  # three real shirts, two recipes each: 2.4 s (the long sleeves 0.8 s a run)
@pytest.mark.parametrize("key", ["tee6", "tshirt", "longsleeve"])
def test_the_sleeve_recipes_change_the_sleeves_of_a_real_shirt_and_not_the_shirt(
    key, name, low, high
):
    """Issue 23, item 5: ``wider-sleeves.yaml`` used ``region: all`` with ``axis: auto``,
    which on a real tee scaled the whole shirt (front +27.5 %). Now the sleeve family
    (``sleeve_left``, ``sleeve_right_front``, ...), each sleeve about its own arm: the
    sleeves' pattern area +20 %, the torso's within 2 %; ``longer-sleeves.yaml`` (the same
    fault, along): sleeves +9-10 %."""
    from ptailor.formats.garment import load_garment
    from tests.conftest import REAL, real_path

    pu = REAL[key][1]
    g = load_garment(real_path(key), pattern_units=pu, drape_units="cm" if pu == "auto" else pu)
    g = g.garment
    rec = load_recipe(Path(__file__).resolve().parents[1] / "recipes" / f"{name}.yaml")
    a = adjustment(g, rec, baseline=False)
    assert a.result.info.converged
    assert len(a.state.log[-1]["parts"]) == 2  # one per arm

    def area(V2, faces):
        T = V2[g.F2[faces]]
        e1, e2 = T[:, 1] - T[:, 0], T[:, 2] - T[:, 0]
        return 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]).sum()

    for p in a.state.panels:
        change = area(a.result.V2, p.faces) / area(g.V2, p.faces) - 1
        if p.name.startswith("sleeve"):
            assert low < change < high, (p.name, change)
        elif p.name in ("front", "back"):
            assert abs(change) < 0.02, (p.name, change)


def _garment_cases() -> list[tuple[Path, str]]:
    """(recipe, shared garment) for every garment a recipe's '# garments:' line names."""
    out = []
    for p in RECIPES:
        for ln in p.read_text().splitlines():
            if ln.startswith("# garments:"):
                out += [(p, k.strip()) for k in ln.split(":", 1)[1].split(",") if k.strip()]
    return out


#: known misses of a bundled recipe's expect: on a shared garment it names (issue 42)
SHARED_MISSES = {
    ("deeper-neckline", "dress"): "neck_drop +7.7 cm in the drape (4.08 -> 11.8) for +10 +-0.2 "
    "(the V's tip is 10.1 below the front neck point, as asked): the high point the drop is "
    "measured from moves down 2.3 cm; not the reading of the parts (the cut garment keeps "
    "its source's panel roles and opening names since 2026-12-06: the same miss)",
    ("wider-sleeves", "longsleeve"): "bicep pattern +18.8 % left (41.81 -> 49.7), +17.8 % "
    "right (43.21 -> 50.9), cuff_right drape +18.2 % (31.55 -> 37.3) for +20 % +-1 % "
    "(drape biceps +20 %), with the cuffs in the region ({part: sleeves}) or not",
}


def _garment_params():
    return [
        pytest.param(
            p, k, id=f"{p.stem}-{k}",
            marks=[_known_miss(SHARED_MISSES[p.stem, k])] if (p.stem, k) in SHARED_MISSES else [],
        )
        for p, k in _garment_cases()
    ]  # fmt: skip


@pytest.mark.slow
@pytest.mark.parametrize(("path", "key"), _garment_params())
def test_recipe_runs_on_the_shared_garments_it_names(path, key):
    """Issue 23, item 5: every bundled recipe does what its name says on the real garments
    it is written for (its '# garments:' line): it runs, converges with every seam at its
    ratio and no flipped triangle, and no cut takes most of a panel. Issue 42: and delivers
    what its ``expect:`` asks there (the known misses marked, with their numbers)."""
    from ptailor.formats.garment import load_garment
    from ptailor.report.build import build_report
    from tests.conftest import REAL, real_path

    units = "0.3333cm" if key == "tee6" else "auto"
    g = load_garment(
        real_path(key), pattern_units=units, drape_units="0.3333cm" if key == "tee6" else "cm"
    ).garment
    assert REAL[key]
    adj = adjustment(g, load_recipe(path), baseline=False)
    info = adj.result.info
    assert info.converged and info.seam_violation <= 1e-9
    r = build_report(adj, inputs={}, units_note={}, warnings=[], timing_s={})
    assert sum(p["flipped_triangles"] for p in r["panels"]) == 0
    for rec in adj.state.log:
        for w in rec.get("warnings", []):
            assert "removes" not in w, w
    expectations_met(g, adj, load_recipe(path))


# ----------------------------------------------------------------- the README's recipe


def readme_recipe() -> str:
    """The YAML block under the README's "## A recipe"."""
    import re

    text = (Path(__file__).resolve().parents[1] / "README.md").read_text(encoding="utf-8")
    return re.search(r"## A recipe.*?```yaml\n(.*?)```", text, re.S).group(1)


def test_the_readmes_recipe_is_valid_and_asks_in_measures():
    rec = parse_recipe(readme_recipe())
    assert [s.op for s in rec.steps] == ["scale", "loosen", "shorten"]
    assert rec.steps[1].girth == 2.0
    assert {e.name for e in rec.expect} == {"chest", "bicep_left", "bicep_right"}


@pytest.mark.slow
def test_the_readmes_recipe_on_the_tshirt_delivers_what_the_readme_says(tmp_path):
    """The numbers the README quotes under its recipe (exit 0: every expectation met)."""
    import json

    from click.testing import CliRunner

    from ptailor.cli.main import cli
    from tests.conftest import real_path

    garment = real_path("tshirt")
    rec = tmp_path / "r.yaml"
    rec.write_text(readme_recipe())
    out = tmp_path / "o"
    args = ["adjust", garment, rec, "-o", out, "--pattern-units", "auto", "-q", "--no-baseline"]
    r = CliRunner().invoke(cli, [str(a) for a in args])
    assert r.exit_code == 0, r.stderr
    rep = json.loads((out / "report.json").read_text())
    b = {d["name"]: d for d in rep["measures"]["before"]}
    a = {d["name"]: d for d in rep["measures"]["after"]}
    gain = {n: (a[n]["drape"] - b[n]["drape"], a[n]["pattern"] - b[n]["pattern"]) for n in a}
    np.testing.assert_allclose(gain["chest"], (2.19, 2.24), atol=0.05)
    np.testing.assert_allclose(gain["body_length"], (-4.2, -4.2), atol=0.1)
    for side in ("left", "right"):
        n = f"bicep_{side}"
        ratio = (a[n]["drape"] / b[n]["drape"], a[n]["pattern"] / b[n]["pattern"])
        np.testing.assert_allclose(ratio, (1.100, 1.100), atol=0.002)
