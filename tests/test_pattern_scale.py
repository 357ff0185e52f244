"""``--pattern-units auto`` (issue 42, item 8): the pattern's scale from its interior
triangles, exact on GarmentCode's box meshes (whose seam triangles are stretched across the
gaps between the placed panels) and close to the area ratio on draped garments."""

from __future__ import annotations

import numpy as np
import pytest

from ptailor.model.unit_ratio import pattern_scale_estimate
from ptailor.samples import cone_skirt, flat_tee
from tests.conftest import GARMENTS

#: cm per vt unit, measured on interior edges (../shared/DATA.md)
BOX_MESHES = {
    "garmentcode/shirt_mean_boxmesh.obj": 134.79,
    "garmentcode_more/shorts_boxmesh.obj": 126.7879,
    "garmentcode_more/skirt_flared_boxmesh.obj": 224.96,
    "garmentcode_more/shirt_longsleeve_boxmesh.obj": 230.88,
    "garmentcode_more/jumpsuit_boxmesh.obj": 203.50,
}


@pytest.mark.parametrize("make", [cone_skirt, flat_tee])
def test_a_pattern_scaled_by_k_is_found_k(make):
    g = make()
    k = 0.0123
    assert pattern_scale_estimate(g.V3, g.F3, g.V2 * k, g.F2) == pytest.approx(
        pattern_scale_estimate(g.V3, g.F3, g.V2, g.F2) / k, rel=1e-9
    )


def test_seam_triangles_stretched_across_gaps_do_not_count():
    """A developable skirt (scale 1) whose outline triangles are made 3x larger in 3D (as a
    box mesh's seam rows): still 1."""
    g = cone_skirt()
    V3 = g.V3.copy()
    rim = np.zeros(len(g.V3), dtype=bool)
    rim[g.F3[:8].ravel()] = True  # a few triangles' corners pulled out
    V3[rim] *= 3.0
    assert pattern_scale_estimate(g.V3, g.F3, g.V2, g.F2) == pytest.approx(1.0, rel=1e-6)
    assert pattern_scale_estimate(V3, g.F3, g.V2, g.F2) == pytest.approx(1.0, rel=1e-3)


@pytest.mark.slow
@pytest.mark.parametrize(("path", "exact"), sorted(BOX_MESHES.items()))
def test_box_meshes_get_their_exact_scale(path, exact):
    from ptailor.formats.garment import load_garment

    p = GARMENTS / path
    if not p.is_file():
        pytest.skip(f"{p} not available (../shared is absent)")
    loaded = load_garment(p, pattern_units="auto", drape_units="cm")
    assert loaded.pattern_scale == pytest.approx(exact, rel=0.005)
