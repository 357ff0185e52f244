"""The outline rule delivers the ask (issue 42, item 1): an ``around`` scale is no similarity
of a panel's pattern, so ``flatten.boundary: auto`` leaves the outline of every panel it moves
free, and at every level of an around-scaled panel the pattern's width changes by the 3D
factor within 1 %. A ``uniform`` scale is a similarity: those panels keep their outline."""

from __future__ import annotations

import numpy as np
import pytest

from ptailor.measures import garment_measures
from ptailor.measures.lines import line_length, plane_section
from ptailor.pipeline import adjustment
from ptailor.recipe import parse_recipe
from ptailor.samples import SAMPLES, cone_skirt, flat_tee


def scale(region: str, direction: str, factor: float = 1.1) -> str:
    return (
        f"steps: [{{op: scale, region: {region}, direction: {direction}, axis: auto,"
        f" factor: {factor}}}]\n"
    )


def level_ratios(g, adj, heights) -> np.ndarray:
    """``(k, 2)``: the drape's and the pattern's section length after over before, at each
    height (an around scale about the up axis keeps heights)."""
    up = g.frame.matrix()[1]
    a = adj.garment
    out = []
    for h in heights:  # a loop over a few levels
        s0 = plane_section(g.V3, g.F3, point=h * up, normal=up)
        s1 = plane_section(a.V3, a.F3, point=h * up, normal=up)
        out.append(
            (
                line_length(s1, a.V3, a.F3) / line_length(s0, g.V3, g.F3),
                line_length(s1, a.V2, a.F2) / line_length(s0, g.V2, g.F2),
            )
        )
    return np.array(out)


@pytest.mark.parametrize(
    ("make", "region"), [(SAMPLES["skirt"], "{panels: [skirt]}"), (cone_skirt, "all")]
)
def test_every_level_of_a_fuller_skirt_is_wider_by_the_factor_in_its_pattern(make, region):
    g = make()
    adj = adjustment(g, parse_recipe(scale(region, "around")), baseline=False)
    y = g.V3[:, 1]
    r = level_ratios(g, adj, np.linspace(y.min(), y.max(), 9)[1:-1])
    np.testing.assert_allclose(r[:, 0], 1.1, rtol=1e-3)  # the drape: exactly the ask
    np.testing.assert_allclose(r[:, 1], 1.1, rtol=0.01)  # the pattern: within 1 %
    assert not adj.state.even.any()  # no panel kept its outline


def test_a_sleeve_made_wider_keeps_its_length_in_the_pattern():
    g = flat_tee()
    adj = adjustment(g, parse_recipe(scale("{panels: [sleeve]}", "around")), baseline=False)
    m0 = {m.name: m for m in garment_measures(g)}
    m1 = {m.name: m for m in garment_measures(adj.garment)}
    for side in ("left", "right"):
        for name, want in ((f"cuff_{side}", 1.1), (f"bicep_{side}", 1.1)):
            assert m1[name].pattern / m0[name].pattern == pytest.approx(want, rel=0.01), name
        n = f"sleeve_length_{side}"
        assert m1[n].pattern / m0[n].pattern == pytest.approx(1.0, abs=0.01), n


def test_a_uniform_scale_keeps_the_outline_of_the_panels_wholly_inside():
    g = cone_skirt()
    adj = adjustment(g, parse_recipe(scale("all", "uniform")), baseline=False)
    assert adj.state.even.all()
    m0 = {m.name: m for m in garment_measures(g)}
    m1 = {m.name: m for m in garment_measures(adj.garment)}
    for name in ("waist", "hem", "skirt_length"):
        assert m1[name].pattern / m0[name].pattern == pytest.approx(1.1, rel=1e-3)


@pytest.mark.slow
@pytest.mark.parametrize(("key", "units"), [("tshirt", ("auto", "cm")), ("dress", ("auto", "cm"))])
def test_shared_garments_take_the_width_asked(key, units):
    from ptailor.formats.garment import load_garment
    from tests.conftest import real_path

    g = load_garment(real_path(key), pattern_units=units[0], drape_units=units[1]).garment
    region, names = (
        ("{panels: [sleeve]}", ("bicep_left", "cuff_left", "bicep_right", "cuff_right"))
        if key == "tshirt"
        else ("{panels: [skirt]}", ("hip", "hem"))
    )
    adj = adjustment(g, parse_recipe(scale(region, "around")), baseline=False)
    m0 = {m.name: m for m in garment_measures(g)}
    m1 = {m.name: m for m in garment_measures(adj.garment)}
    for n in names:
        drape = m1[n].drape / m0[n].drape
        assert m1[n].pattern / m0[n].pattern == pytest.approx(drape, abs=0.01), n
