"""The re-drape check's simulation mesh (:mod:`ptailor.verify.proxy`): a garment larger than
``Settings.sim_faces`` is simulated on a decimated copy that keeps every pattern boundary,
and the result is carried back exactly where it can be (kept vertices, pattern-affine
fields). On generated garments (a lantern sleeve, a bodice, a cone skirt, mirrored, turned,
unwelded-free) and, when ../shared is there, tee6 subdivided to 82k triangles."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from ptailor import samples
from ptailor.verify.proxy import SimMesh, simulation_mesh
from tests.conftest import ROOT

sys.path.insert(0, str(ROOT / "bench"))
from subdivide import subdivide_garment


def _fine(make, levels=1):
    g = make()
    V3, F3, V2, F2, _ = subdivide_garment(g.V3, g.F3, g.V2, g.F2, levels=levels)
    return V3, F3, V2, F2


def _boundary(F3, F2, n3):
    E = np.sort(np.concatenate([F2[:, [0, 1]], F2[:, [1, 2]], F2[:, [2, 0]]]), axis=1)
    E3 = np.concatenate([F3[:, [0, 1]], F3[:, [1, 2]], F3[:, [2, 0]]])
    _, inv, c = np.unique(E, axis=0, return_inverse=True, return_counts=True)
    return np.unique(E3[c[inv.reshape(-1)] == 1])


def _area(V2, F2):
    a, b, c = V2[F2[:, 0]], V2[F2[:, 1]], V2[F2[:, 2]]
    return 0.5 * ((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])


def test_a_garment_under_the_size_is_simulated_as_it_is():
    g = samples.lantern_sleeve()
    assert simulation_mesh(g.V3, g.F3, g.V2, g.F2, max_faces=g.n_faces) is None


def _mirrored(make):
    g = make()
    return g.V3 * [-1.0, 1.0, 1.0], g.F3[:, ::-1], g.V2, g.F2[:, ::-1]


@pytest.mark.parametrize(
    "case",
    ["lantern", "bodice", "cone", "bodice-mirrored-turned"],
)
def test_the_simulation_mesh_keeps_every_boundary_and_carries_back_exactly(case):
    if case == "bodice-mirrored-turned":
        g = samples.bodice()
        c, s = np.cos(0.7), np.sin(0.7)
        R = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
        V3, F3, V2, F2, _ = subdivide_garment(
            (g.V3 * [-1.0, 1.0, 1.0]) @ R.T, g.F3[:, ::-1], g.V2, g.F2[:, ::-1], levels=1
        )
    else:
        make = {"lantern": lambda: samples.lantern_sleeve(n_around=32, n_sleeve=24, n_cuff=6),
                "bodice": samples.bodice, "cone": samples.cone_skirt}[case]  # fmt: skip
        V3, F3, V2, F2 = _fine(make)
    inputs = [x.copy() for x in (V3, F3, V2, F2)]
    target = len(F3) // 4
    sim = simulation_mesh(V3, F3, V2, F2, max_faces=target)
    for x, y in zip(inputs, (V3, F3, V2, F2), strict=True):
        np.testing.assert_array_equal(x, y)  # inputs untouched
    assert isinstance(sim, SimMesh)
    assert sim.n_faces <= 1.05 * target
    # every pattern boundary vertex (seams, hems, openings) is a simulation vertex
    assert np.isin(_boundary(F3, F2, len(V3)), sim.keep3).all()
    # the pattern corners are copies of the drape corners
    p2v = np.full(len(V2), -1)
    p2v[F2.reshape(-1)] = F3.reshape(-1)
    np.testing.assert_array_equal(p2v[sim.keep2[sim.F2]], sim.keep3[sim.F3])
    # same pattern area, no folds
    a_fine, a_sim = _area(V2, F2), _area(V2[sim.keep2], sim.F2)
    assert abs(a_sim.sum() - a_fine.sum()) < 1e-6 * abs(a_fine.sum())
    assert (np.sign(a_sim) == np.sign(a_fine.sum())).mean() >= 0.999
    # kept vertices come back exactly; a field affine on the pattern comes back exactly
    # wherever it is one function of the drape vertex (simulation triangles with no seam
    # corner: a seam vertex has a pattern position in each panel it joins)
    used = np.unique(F3)
    first = np.full(len(V3), -1)
    first[F3.reshape(-1)] = F2.reshape(-1)
    field = np.c_[V2[first], 2.0 * V2[first][:, 0] - V2[first][:, 1] + 3.0]  # (n3, 3)
    back = sim.carry(field[sim.keep3])
    np.testing.assert_array_equal(back[sim.keep3], field[sim.keep3])
    inner = np.ones(len(V3), dtype=bool)
    inner[_boundary(F3, F2, len(V3))] = False
    clear = np.zeros(len(V3), dtype=bool)
    clear[used] = inner[sim.keep3[sim.F3[sim.tri[used]]]].all(axis=1)
    assert clear.sum() > 0.5 * len(used)
    np.testing.assert_allclose(back[clear], field[clear], atol=1e-9)
    assert (sim.bary[used] >= -1e-9).all()
    # the drape itself comes back close (the decimation's chord error)
    d = np.linalg.norm(sim.carry(V3[sim.keep3])[used] - V3[used], axis=1)
    assert np.percentile(d, 95) < 0.5  # cm, garments about 50 cm across


@pytest.mark.slow
def test_a_production_resolution_tee_is_simulated_on_8000_triangles():
    """tee6 subdivided 1 -> 16 (82,480 triangles): 8,000 simulation triangles, every seam
    and opening kept, the drape carried back within 0.2 cm at the 95th percentile."""
    from ptailor.formats.garment import load_garment
    from tests.conftest import real_path

    g = load_garment(real_path("tee6"), pattern_units="0.3333cm", drape_units="0.3333cm").garment
    V3, F3, V2, F2, _ = subdivide_garment(g.V3, g.F3, g.V2, g.F2, levels=2)
    sim = simulation_mesh(V3, F3, V2, F2, max_faces=8000)
    assert sim is not None and abs(sim.n_faces - 8000) <= 80
    assert np.isin(_boundary(F3, F2, len(V3)), sim.keep3).all()
    used = np.unique(F3)
    d = np.linalg.norm(sim.carry(V3[sim.keep3])[used] - V3[used], axis=1)
    assert np.percentile(d, 95) < 0.2
