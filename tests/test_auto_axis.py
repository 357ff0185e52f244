"""``axis: auto`` that has nothing to go by says so (issue 22, item 6)."""

from __future__ import annotations

import numpy as np
import pytest

from ptailor.edits.scale import auto_axis_warnings
from ptailor.edits.state import EditOptions
from ptailor.pipeline import adjustment, solver_warnings
from ptailor.recipe import parse_recipe
from ptailor.samples import cylinder
from tests.conftest import real_path


def sheet(angle_deg: float):
    """A flat 40 x 4 strip in the xy plane, its long side ``angle_deg`` from y (up)."""
    t = np.radians(angle_deg)
    u, v = np.array([np.sin(t), np.cos(t), 0.0]), np.array([np.cos(t), -np.sin(t), 0.0])
    s, w = np.meshgrid(np.linspace(0, 40, 11), np.linspace(0, 4, 3), indexing="ij")
    V = s.reshape(-1, 1) * u + w.reshape(-1, 1) * v
    i = np.arange(10)[:, None] * 3 + np.arange(2)[None, :]
    F = np.concatenate([np.stack([i, i + 3, i + 4], -1), np.stack([i, i + 4, i + 1], -1)])
    return V, F.reshape(-1, 3)


@pytest.mark.parametrize(("angle", "warns"), [(0.0, False), (20.0, False), (55.0, True)])
def test_a_sheet_whose_longest_extent_leans_from_up_is_a_warning(angle, warns):
    V, F = sheet(angle)
    faces = np.arange(len(F))
    from ptailor.edits.region import region_axis

    ax = region_axis(V, F, faces)
    w = auto_axis_warnings(V, F, faces, ax, EditOptions())
    assert bool(w) == warns
    if warns:
        assert f"{angle:.0f} degrees from the garment's up" in w[0]


def test_a_tube_keeps_its_axis_without_a_warning_whatever_its_direction():
    g = cylinder(circumference=40.0, n_around=16, n_along=6)
    R = np.array([[0.0, -1, 0], [1, 0, 0], [0, 0, 1]])  # lying down: axis along x
    V = g.V3 @ R.T
    faces = np.arange(len(g.F3))
    from ptailor.edits.region import region_axis

    ax = region_axis(V, g.F3, faces)
    assert abs(ax[0]) > 0.99
    assert auto_axis_warnings(V, g.F3, faces, ax, EditOptions()) == []


def test_the_shared_tshirt_scaled_as_a_whole_along_auto_says_its_axis_leans():
    from ptailor.formats.garment import load_garment

    g = load_garment(real_path("tshirt"), pattern_units="auto", drape_units="cm").garment
    text = "steps: [{op: scale, region: all, direction: along, axis: auto, factor: 1.1}]"
    a = adjustment(g, parse_recipe(text), baseline=False)
    w = [x for x in solver_warnings(a) if "axis: auto" in x]
    assert len(w) == 1 and "55 degrees" in w[0] and w[0].startswith("scale step:")
    text = text.replace("axis: auto", "axis: [0, 1, 0]")
    assert not any("axis" in x for x in solver_warnings(adjustment(g, parse_recipe(text))))
