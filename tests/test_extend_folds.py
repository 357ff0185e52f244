"""Extend continues the surface behind the opening and warns where its new rows fold back.

A simulated drape's last row is often bent, flared or turned in; continuing that row alone
flared the new rows (a tube whose last row flares 20 degrees: its hem +26 % for 4 cm) or
folded them back onto the cloth without a word (issue 42, item 7).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import ptailor.edits.extend.drape as extend_drape
from ptailor.formats.garment import load_garment
from ptailor.measures import garment_measures
from ptailor.pipeline import adjustment
from ptailor.recipe import parse_recipe
from ptailor.samples import cone_skirt, cylinder, flat_tee
from tests.conftest import REAL, real_path


def bent_tube(theta_deg: float):
    """A tube (cylinder, 30 around, 20 long, 16 rows) whose last row at the hem is turned
    ``theta_deg`` outward from straight down (over 90: turned back up; negative: in)."""
    g = cylinder(n_around=40, n_along=16)
    V = g.V3.copy()
    e = 20.0 / 16
    ring = np.isclose(V[:, 1], 0.0)
    r = np.linalg.norm(V[ring][:, [0, 2]], axis=1)
    th = np.radians(theta_deg)
    V[np.ix_(ring, [0, 2])] *= ((r + e * np.sin(th)) / r)[:, None]
    V[ring, 1] = e - e * np.cos(th)
    return replace(g, V3=V)


def extended(g, opening: str, by: float):
    text = f"steps: [{{op: extend, opening: {opening}, by: {by}}}]"
    adj = adjustment(g, parse_recipe(text), baseline=False)
    rec = next(r for r in adj.state.log if r.get("op") == "extend")
    return adj.garment, rec


def measure(g, name: str):
    return next(m for m in garment_measures(g) if m.name == name)


def test_flared_last_row_does_not_flare_the_new_rows():
    """Was hem 32.68 -> 41.22 cm (+26 %, the 20 degree flare of one row extrapolated);
    now 35.38 (the tube behind it is straight; 30 cm around)."""
    g = bent_tube(20.0)
    g1, rec = extended(g, "hem", 4.0)
    before, after = measure(g, "hem").drape, measure(g1, "hem").drape
    assert after / before < 1.12, (before, after)
    assert measure(g1, "skirt_length").drape == pytest.approx(24.0, abs=0.02)
    assert "warnings" not in rec


@pytest.mark.parametrize("theta", [150.0, -110.0])
def test_turned_back_last_row_warns_naming_the_opening(theta):
    """The drape's own last row turned back: the new rows, continuing the tube, fold
    against it; the step says so (was: no warning)."""
    _, rec = extended(bent_tube(theta), "hem", 4.0)
    assert rec["folds"]["edges"] == 40
    assert rec["folds"]["row"] == 1
    assert rec["folds"]["min_cos"] < 0.0
    assert any("'hem'" in w and "fold back" in w for w in rec["warnings"])


def test_rows_forced_against_the_surface_warn(monkeypatch):
    """Rows forced to grow back into the cloth (the directions turned round) are found by
    the growth check, whatever built them."""
    real = extend_drape.surface_directions
    monkeypatch.setattr(extend_drape, "surface_directions", lambda V, F, oe: -real(V, F, oe))
    _, rec = extended(cylinder(n_around=24, n_along=8), "hem", 3.0)
    assert rec["folds"]["columns"] == 24
    assert any("'hem'" in w for w in rec["warnings"])


@pytest.mark.parametrize("by", [4.0, 15.0])
def test_cone_hem_grows_with_its_flare(by):
    """The cone's hem continues along its generators: 188.42 -> 195.93 (by 4), 216.59
    (by 15); the pattern's exact development gives 195.96, 216.68."""
    g = cone_skirt(n_around=32, n_along=12)
    g1, rec = extended(g, "hem", by)
    hem = measure(g1, "hem")
    assert hem.drape == pytest.approx(hem.pattern, rel=2e-3)
    assert hem.drape > measure(g, "hem").drape + 0.3 * by
    assert measure(g1, "skirt_length").drape == pytest.approx(
        measure(g, "skirt_length").drape + by, abs=0.02
    )
    assert "warnings" not in rec


def test_tee_cuff_keeps_its_girth_without_warning():
    g = flat_tee(cell=4.0)
    g1, rec = extended(g, "cuff_left", 8.0)
    assert measure(g1, "cuff_left").drape == pytest.approx(measure(g, "cuff_left").drape, rel=1e-3)
    assert measure(g1, "sleeve_length_left").drape == pytest.approx(
        measure(g, "sleeve_length_left").drape + 8.0, abs=0.02
    )
    assert "warnings" not in rec


@pytest.mark.slow
@pytest.mark.parametrize("by", [4.0, 15.0])
def test_shared_dress_hem_follows_its_flare(by):
    """The dress's last row turns in: the 3D hem shrank while the pattern's grew (by 4:
    341.16 -> 328.22 cm against 352.86; by 15: 315.71 against 385.55). Now 354.08 / 354.06
    and 394.86 / 389.51."""
    g = load_garment(real_path("dress"), pattern_units=REAL["dress"][1]).garment
    g1, rec = extended(g, "hem", by)
    hem = measure(g1, "hem")
    assert hem.drape > measure(g, "hem").drape
    assert hem.drape == pytest.approx(hem.pattern, rel=0.02)
    assert "warnings" not in rec


@pytest.mark.slow
def test_shared_tshirt_cuff_no_fold():
    g = load_garment(real_path("tshirt"), pattern_units=REAL["tshirt"][1]).garment
    g1, rec = extended(g, "cuff_left", 4.0)
    assert measure(g1, "sleeve_length_left").drape == pytest.approx(
        measure(g, "sleeve_length_left").drape + 4.0, abs=0.05
    )
    assert "warnings" not in rec
