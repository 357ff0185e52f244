"""The cloth engine (ptailor.verify.engine): tubes over a cylinder with known answers.

The simulating tests skip when newton is not installed (``pip install 'ptailor[sim]'``).
"""

from __future__ import annotations

import sys

import numpy as np
import pytest

from ptailor.geometry.triangles import edge_matrices
from ptailor.samples.tubes import cylinder
from ptailor.verify import engine

RADIUS = 5.0  # cm: the tube's circumradius, the cylinder's radius
HEIGHT = 20.0
N_AROUND, N_ALONG = 64, 24  # 3,072 triangles


def _tube(rest_scale: float, *, mirrored: bool = False):
    """A tube of radius RADIUS (cm), its rest ``rest_scale`` x around, the top ring.

    Returns
    -------
    V3 : (n, 3) float array
    F3 : (m, 3) int array
    rest : (m, 2, 2) float array
    top : (k,) int array
    """
    c = 2 * N_AROUND * RADIUS * np.sin(np.pi / N_AROUND)  # the polygon's perimeter
    g = cylinder(
        circumference=c,
        height=HEIGHT,
        stretch=1.0 / rest_scale,
        n_around=N_AROUND,
        n_along=N_ALONG,
        mirrored=mirrored,
    )
    top = np.flatnonzero(g.V3[:, 1] > g.V3[:, 1].max() - 1e-9)
    return g.V3, g.F3, edge_matrices(g.V2, g.F2), top


def _body(settings: engine.Settings):
    """A closed cylinder (y axis) under the tube: the cloth, ``radius`` outside it, rests at
    RADIUS (the tube's inscribed radius, the flats of its polygon)."""
    import trimesh

    r = RADIUS * np.cos(np.pi / N_AROUND) - settings.radius / 0.01
    cyl = trimesh.creation.cylinder(radius=r, height=1.5 * HEIGHT, sections=128)
    return cyl.vertices[:, [0, 2, 1]] + [0.0, HEIGHT / 2, 0.0], cyl.faces


def _around(V, F, rest):
    """Each face's largest principal stretch against its rest shape, (m,)."""
    J = edge_matrices(V, F) @ np.linalg.inv(rest)
    return np.linalg.svd(J, compute_uv=False)[:, 0]


def test_panel_triangles_are_counter_clockwise_with_the_rest_metric():
    rng = np.random.default_rng(3)
    rest = rng.normal(size=(50, 2, 2))
    P = engine.panel_triangles(rest)
    E = np.stack([P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]], axis=2)
    assert (np.linalg.det(E) > 0).all()
    np.testing.assert_allclose(E.transpose(0, 2, 1) @ E, rest.transpose(0, 2, 1) @ rest)


def test_missing_engine_says_how_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "newton", None)  # `import newton` raises ImportError
    assert not engine.engine_available()
    V3, F3, rest, top = _tube(1.0)
    with pytest.raises(engine.EngineMissingError) as e:
        engine.redrape(V3, F3, rest, units_m=0.01, pinned=top)
    assert str(e.value) == "the cloth engine is not installed: pip install 'ptailor[sim]'"
    assert isinstance(e.value, engine.PtailorError)


def test_bad_inputs_are_named():
    V3, F3, rest, top = _tube(1.0)
    bad = [
        ({"V3": V3[:, :2]}, "V3 must be"),
        ({"F3": F3 + len(V3)}, "F3 indexes"),
        ({"rest": rest[:-1]}, "rest must be"),
        ({"units_m": 0.0}, "units_m must be"),
        ({"pinned": np.array([len(V3)])}, "pinned indexes"),
    ]
    for change, message in bad:
        args = {"V3": V3, "F3": F3, "rest": rest, "units_m": 0.01, "pinned": top} | change
        with pytest.raises(ValueError, match=message):
            engine.redrape(args.pop("V3"), args.pop("F3"), args.pop("rest"), **args)


@pytest.mark.slow
@pytest.mark.parametrize(("scale", "mirrored", "wide"), [(0.9, True, 1.08), (0.7, False, 1.15)])
def test_a_tight_tube_is_stretched_over_the_cylinder(scale, mirrored, wide):
    """Rest ``scale`` x around (a mirrored pattern: every rest triangle clockwise), started
    ``wide`` x too wide: it shrinks onto the cylinder, not through it, and stays stretched
    1/scale around."""
    pytest.importorskip("newton")
    s = engine.Settings(max_steps=900)
    V3, F3, rest, top = _tube(scale, mirrored=mirrored)
    assert (np.linalg.det(rest) < 0).all() == mirrored
    wide = V3 * [wide, 1.0, wide]
    d = engine.redrape(wide, F3, rest, units_m=0.01, pinned=top, body=_body(s), settings=s)
    assert d.settled and d.steps < s.max_steps
    assert d.device in ("cpu", "cuda:0") and d.engine.startswith("newton 1.8.0")
    np.testing.assert_array_equal(d.V[top], wide[top])
    below = np.flatnonzero(d.V[F3].mean(axis=1)[:, 1] < 0.75 * HEIGHT)  # clear of the top ring
    stretch = np.median(_around(d.V, F3, rest)[below])
    assert stretch == pytest.approx(1 / scale, rel=0.03)
    r = np.hypot(d.V[:, 0], d.V[:, 2])
    assert np.median(r[d.V[:, 1] < 0.75 * HEIGHT]) == pytest.approx(RADIUS, rel=0.03)


@pytest.mark.slow
@pytest.mark.parametrize("on_body", [True, False])
def test_a_tube_at_rest_barely_moves_and_says_nothing(on_body, capfd):
    """Rest = drape, on its cylinder or hanging from its top ring alone: it barely moves, and
    neither newton nor warp writes to stdout."""
    pytest.importorskip("newton")
    s = engine.Settings(max_steps=600)
    V3, F3, rest, top = _tube(1.0)
    body = _body(s) if on_body else None
    d = engine.redrape(V3, F3, rest, units_m=0.01, pinned=top, body=body, settings=s)
    assert capfd.readouterr().out == ""
    assert d.settled
    assert d.V.shape == V3.shape
    disp = np.linalg.norm(d.V - V3, axis=1)
    assert disp.mean() < 0.3  # cm
    assert disp.max() < 1.0
    np.testing.assert_allclose(np.median(_around(d.V, F3, rest)), 1.0, atol=0.02)
