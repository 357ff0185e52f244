"""Points of measure (ptailor.measures): material lines, analytic garments, invariance under a
rigid motion, a mirror, subdivision and units, and the measures each kind of garment has."""

from __future__ import annotations

import dataclasses
import sys

import numpy as np
import pytest

from ptailor import samples
from ptailor.measures import MEASURES, garment_measures, measure_dicts
from ptailor.measures.lines import line_length, line_pieces, plane_section
from ptailor.model.frame import Frame
from tests.garment_checks import subdivided

REL = 0.005  # the 0.5 %


def values(g) -> dict[str, tuple[float, float]]:
    return {
        d["name"]: (d["drape"], d["pattern"]) for d in measure_dicts(garment_measures(g), g.units)
    }


def assert_close(a: dict, b: dict, rel: float = REL, atol: float = 0.02) -> None:
    """Equal names, and values within ``rel`` (or ``atol`` cm, 0.2 mm: a flat neckline's drop
    is 0)."""
    assert a.keys() == b.keys()
    for k in a:
        np.testing.assert_allclose(a[k], b[k], rtol=rel, atol=atol, err_msg=k)


# --- material lines ---------------------------------------------------------------------


def test_a_plane_through_an_edge_counts_it_once():
    V = np.array([[0.0, 0, 0], [0, 1, 0], [1, 0, 0], [-1, 0, 0]])
    F = np.array([[0, 1, 2], [1, 0, 3]])  # the edge 0-1 lies in the plane x = 0
    line = plane_section(V, F, point=[0, 0, 0], normal=[1, 0, 0])
    assert len(line) == 1 and line_length(line, V, F) == pytest.approx(1.0)
    assert line_length(line, V[:, :2] * 3.0, F) == pytest.approx(3.0)  # the same line, scaled


def test_a_tube_section_is_one_closed_loop_of_its_circumference():
    g = samples.cylinder()
    h = 0.5 * (g.V3[:, 1].min() + g.V3[:, 1].max())
    line = plane_section(g.V3, g.F3, point=[0, h, 0], normal=[0, 1, 0])
    _, count, closed = line_pieces(line)
    assert count == 1 and closed.all()
    assert line_length(line, g.V3, g.F3) == pytest.approx(30.0)  # the sample's circumference
    open_line = line.subset(np.arange(len(line)) > 0)
    assert not line_pieces(open_line)[2].any()


# --- analytic garments --------------------------------------------------------------------


def test_the_cylinder_measures_its_circumference_and_height():
    v = values(samples.cylinder())
    height = 20.0  # cylinder()'s default
    for name in ("waist", "hem", "hip"):
        np.testing.assert_allclose(v[name], (30.0, 30.0), rtol=1e-9)
    np.testing.assert_allclose(v["skirt_length"], (height, height), rtol=1e-9)
    assert "chest" not in v and "sleeve_length_left" not in v


def test_the_cone_skirt_measures_its_polygon_rings_and_slant_length():
    n, rw, rh, length = 64, 12.0, 30.0, 60.0
    v = values(samples.cone_skirt(waist_radius=rw, hem_radius=rh, length=length, n_around=n))
    ring = lambda r: n * 2 * r * np.sin(np.pi / n)  # noqa: E731
    np.testing.assert_allclose(v["waist"], (ring(rw), ring(rw)), rtol=1e-6)
    np.testing.assert_allclose(v["hem"], (ring(rh), ring(rh)), rtol=1e-6)
    np.testing.assert_allclose(v["skirt_length"], (length, length), rtol=1e-6)
    # hip: 18 cm below the waist (vertically) on the frustum
    height = np.sqrt(length**2 - (rh - rw) ** 2)
    r_hip = rw + (rh - rw) * 18.0 / height
    np.testing.assert_allclose(v["hip"], (ring(r_hip), ring(r_hip)), rtol=1e-3)
    assert v["hem"][0] > v["hip"][0] > v["waist"][0]


def test_the_flat_tee_pattern_measures_are_its_design():
    width, length, sleeve, sleeve_width = 48.0, 66.0, 20.0, 18.0
    g = samples.flat_tee(width=width, length=length, sleeve=sleeve, sleeve_width=sleeve_width)
    v = values(g)
    assert v["chest"][1] == pytest.approx(2 * width, rel=REL)
    assert v["hem"][1] == pytest.approx(2 * width, rel=REL)
    assert v["body_length"][1] == pytest.approx(length, rel=REL)
    for side in ("left", "right"):
        assert v[f"sleeve_length_{side}"][1] == pytest.approx(sleeve, rel=REL)
        assert v[f"cuff_{side}"][1] == pytest.approx(2 * sleeve_width, rel=REL)
        assert v[f"bicep_{side}"][1] == pytest.approx(2 * sleeve_width, rel=REL)
    # the pillow drape bulges: each girth longer in the drape, never shorter
    assert all(v[k][0] >= v[k][1] - 1e-9 for k in v if MEASURES[k].kind == "girth")


def test_the_lantern_sleeve_is_a_lone_limb_with_its_elastic_cuff():
    v = values(samples.lantern_sleeve())
    assert {"sleeve_length", "bicep", "cuff"} <= v.keys()
    assert v["cuff"][1] > v["cuff"][0]  # the cuff's pattern is longer than its 3D girth
    assert v["cuff"][0] == pytest.approx(28.0, rel=REL)
    assert v["cuff"][1] == pytest.approx(40.0, rel=REL)


# --- invariance -------------------------------------------------------------------------

GARMENTS = {
    "cone_skirt": samples.cone_skirt,
    "flat_tee": samples.flat_tee,
    "bodice": samples.bodice,
    "lantern": samples.lantern_sleeve,
}


def _rotation(seed: int) -> np.ndarray:
    q, _ = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    return q * np.sign(np.linalg.det(q))


@pytest.mark.parametrize("key", sorted(GARMENTS))
def test_a_rigid_motion_with_its_frame_changes_no_measure(key):
    g = GARMENTS[key]()
    R = _rotation(7)
    moved = dataclasses.replace(
        g,
        V3=g.V3 @ R.T + [3.0, -40.0, 7.5],
        frame=Frame(up=tuple(R @ g.frame.up), front=tuple(R @ g.frame.front)),
    )
    assert_close(values(g), values(moved), rel=1e-6)


@pytest.mark.parametrize("key", sorted(GARMENTS))
def test_a_mirror_swaps_left_and_right(key):
    g = GARMENTS[key]()
    mirrored = dataclasses.replace(g, V3=g.V3 * [-1.0, 1.0, 1.0])
    swap = lambda n: n.replace("_left", "_@").replace("_right", "_left").replace("_@", "_right")  # noqa: E731
    assert_close({swap(k): x for k, x in values(g).items()}, values(mirrored), rel=1e-6)


@pytest.mark.slow
@pytest.mark.parametrize("key", sorted(GARMENTS))
def test_sixteen_times_the_triangles_measure_the_same(key):
    g = GARMENTS[key]()
    assert_close(values(g), values(subdivided(g, 2)))


@pytest.mark.parametrize("key", sorted(GARMENTS))
def test_millimetres_measure_the_same_centimetres(key):
    g = GARMENTS[key]()
    mm = dataclasses.replace(g, V3=g.V3 * 10.0, V2=g.V2 * 10.0, units="mm")
    assert_close(values(g), values(mm), rel=1e-6, atol=1e-4)


# --- real garments ----------------------------------------------------------------------

KINDS = {
    "shared-tee6": "top",
    "shared-tshirt": "top",
    "shared-longsleeve": "top",
    "shared-shirt_mean": "top",
    "shared-shirt_longsleeve": "top",
    "shared-dress": "dress",
    "shared-skirt_flared": "skirt",
    "shared-shorts": "trousers",
    "shared-jumpsuit": "jumpsuit",
}
SIDED = lambda *names: {f"{n}_{s}" for n in names for s in ("left", "right")}  # noqa: E731
EXPECTED = {
    "top": {"neck", "chest", "hem", "body_length"} | SIDED("sleeve_length", "bicep", "cuff"),
    "dress": {"neck", "chest", "waist", "hip", "hem", "body_length", "skirt_length"}
    | SIDED("armhole"),
    "skirt": {"waist", "hip", "hem", "skirt_length"},
    "trousers": {"waist", "hip"} | SIDED("thigh", "inseam", "leg_opening"),
    "jumpsuit": {"neck", "chest", "waist", "hip"}
    | SIDED("sleeve_length", "bicep", "cuff", "thigh", "inseam", "leg_opening"),
}


@pytest.mark.slow
@pytest.mark.parametrize("key", sorted(KINDS))
def test_each_kind_of_shared_garment_has_its_measures(key):
    sys.path.insert(0, str(__import__("tests.conftest").conftest.ROOT / "tests"))
    from tests.names.cases import CASES, garment_of, shared_file

    case = next(c for c in CASES if c.key == key)
    if not shared_file(case).is_file():
        pytest.skip(f"{shared_file(case)} absent (no ../shared)")
    g = garment_of(case)
    v = values(g)
    assert EXPECTED[KINDS[key]] <= v.keys(), sorted(EXPECTED[KINDS[key]] - v.keys())
    assert all(x > 0 for pair in v.values() for x in pair)
    lower_only = {"waist", "hip", "skirt_length"} | SIDED("thigh", "inseam", "leg_opening")
    if KINDS[key] == "top":
        assert not lower_only & v.keys()
    if KINDS[key] in ("skirt", "trousers"):
        assert not {"chest", "neck", "body_length"} & v.keys()
