"""Regions by part of the body (``region: {part: torso}``) and the warning of a girth edit
whose region holds only part of the girth (issue 42, item 4)."""

from __future__ import annotations

import numpy as np
import pytest

from ptailor.edits import EditOptions
from ptailor.edits import tolerances as edit_tol
from ptailor.edits.coverage import girth_coverage
from ptailor.edits.parts import PARTS, mirror_part, part_masks
from ptailor.edits.region import region_faces
from ptailor.errors import AbsentError, RecipeError
from ptailor.measures import garment_measures
from ptailor.model.structure import structure
from ptailor.pipeline import apply_steps
from ptailor.recipe import parse_recipe
from ptailor.samples import flat_tee, gored_skirt
from tests.conftest import REAL, real_path

GORES = 6


def names_of(g, region) -> set[str]:
    """The panels a region selects, by name."""
    faces = region_faces(region, g, g.V3, structure(g).panels)
    lab, _ = structure(g).panel_components
    return {structure(g).panels[i].name for i in np.unique(lab[faces])}


def drape_value(g, V3, name: str) -> float:
    """The drape value of a point of measure on the drape ``V3``."""
    return next(m.drape for m in garment_measures(g.with_drape(V3)) if m.name == name)


def run(g, text: str):
    """The recipe's steps on the drape (no flatten)."""
    return apply_steps(g, parse_recipe(text), options=EditOptions())


def test_parts_of_a_tee_from_its_structure():
    g = flat_tee()
    assert names_of(g, {"part": "torso"}) == {"front", "back"}
    assert names_of(g, {"part": "bodice"}) == {"front", "back"}
    assert names_of(g, {"part": "sleeves"}) == {
        f"sleeve_{s}_{f}" for s in ("left", "right") for f in ("front", "back")
    }
    assert names_of(g, {"part": "sleeve_left"}) == {"sleeve_left_front", "sleeve_left_back"}
    masks = part_masks(g)
    assert set(masks) == set(PARTS)
    assert not masks["skirt"].any() and not masks["legs"].any()


def test_a_part_the_garment_lacks_is_absent_naming_what_it_has():
    g = flat_tee(sleeves="none")  # the sleeves cut with the body: no sleeve panel
    with pytest.raises(AbsentError, match=r"no part sleeves on this garment \(it has: torso"):
        region_faces({"part": "sleeves"}, g, g.V3, structure(g).panels)


def test_parts_do_not_go_by_names():
    # a six-gore skirt without panel names: its centre strips and side gores are one skirt
    g = gored_skirt(gores=GORES)
    every = {p.name for p in structure(g).panels}
    assert len(every) == GORES
    assert names_of(g, {"part": "torso"}) == every == names_of(g, {"part": "skirt"})
    with pytest.raises(AbsentError, match="no part bodice"):
        names_of(g, {"part": "bodice"})


def test_mirror_part():
    assert mirror_part("sleeve_left") == "sleeve_right"
    assert mirror_part("leg_right") == "leg_left"
    assert mirror_part("torso") == "torso"


def test_coverage_of_centre_strips_and_of_the_torso():
    """A six-gore skirt's centre front and back strips hold 2 of its 6 equal gores."""
    g = gored_skirt(gores=GORES)
    strips = region_faces({"panels": ["skirt_front", "skirt_back"]}, g, g.V3, structure(g).panels)
    (c,) = girth_coverage(g.V3, g.F3, strips, garment=g)
    assert c.part == "torso"
    assert c.fraction == pytest.approx(2 / GORES, abs=0.02)
    assert c.levels == edit_tol.GIRTH_COVERAGE_LEVELS
    whole = region_faces({"part": "torso"}, g, g.V3, structure(g).panels)
    (w,) = girth_coverage(g.V3, g.F3, whole, garment=g)
    assert w.fraction == pytest.approx(1.0, abs=1e-9) and w.lowest == pytest.approx(1.0)


def test_coverage_of_half_a_sleeve_is_across_the_arm():
    g = flat_tee()
    half = region_faces({"panels": ["sleeve_left_front"]}, g, g.V3, structure(g).panels)
    (c,) = girth_coverage(g.V3, g.F3, half, garment=g)
    assert c.part == "sleeve_left"
    assert c.fraction == pytest.approx(0.5, abs=0.02)  # front and back halves alike


@pytest.mark.slow
def test_loosen_the_torso_grows_the_chest_as_asked_without_warning():
    g = flat_tee()
    st = run(g, "steps:\n  - {op: loosen, region: {part: torso}, girth: 2, on: drape}\n")
    rec = st.log[-1]
    assert "warnings" not in rec and "girth_coverage" not in rec
    grown = drape_value(g, st.V3, "chest") - drape_value(g, g.V3, "chest")
    assert grown == pytest.approx(2.0, abs=0.05)
    # the same triangles as the tee's front and back by name
    same = run(
        g, "steps:\n  - {op: loosen, region: {panels: [front, back]}, girth: 2, on: drape}\n"
    )
    np.testing.assert_array_equal(same.V3, st.V3)


def test_loosen_the_front_alone_warns_with_its_share():
    g = flat_tee()
    st = run(g, "steps:\n  - {op: loosen, region: {panels: [front]}, girth: 2, on: drape}\n")
    rec = st.log[-1]
    assert rec["girth_coverage"]["torso"] == pytest.approx(0.5, abs=0.02)
    (w,) = [w for w in rec["warnings"] if "covers" in w]
    assert "covers 50 % of the torso girth" in w and "{part: torso}" in w


def test_around_scale_of_centre_strips_warns_and_the_skirt_does_not():
    g = gored_skirt(gores=GORES)
    scale = "steps:\n  - {op: scale, region: %s, direction: around, factor: 1.1}\n"
    st = run(g, scale % "{panels: [skirt_front, skirt_back]}")
    rec = st.log[-1]
    assert rec["girth_coverage"]["torso"] == pytest.approx(2 / GORES, abs=0.02)
    assert any("covers 33 % of the torso girth" in w for w in rec["warnings"])
    whole = run(g, scale % "{part: skirt}").log[-1]
    assert "girth_coverage" not in whole and not whole.get("warnings")
    hip = drape_value(g, run(g, scale % "{part: skirt}").V3, "hip") / drape_value(g, g.V3, "hip")
    assert hip == pytest.approx(1.1, abs=0.005)


@pytest.mark.slow
def test_symmetric_part_regions_mirror():
    g = flat_tee()
    st = run(
        g,
        "steps:\n  - {op: scale, region: {part: sleeve_left}, direction: around, factor: 1.1,"
        " symmetric: true}\n  - {op: loosen, region: {part: torso}, by: 0.5, symmetric: true}\n",
    )
    assert st.log[1]["mirrored"] is True  # applied to the left sleeve, then the right
    assert st.log[2]["mirrored"] == "self"  # the torso is its own mirror image


@pytest.mark.parametrize(
    "region, message",
    [
        ({"part": "arm"}, "region.part: expected one of torso, bodice"),
        ({"part": ["torso"]}, "region.part: expected one of"),
        ({"part": "torso", "panels": ["front"]}, "expected all, {panels: [...]}, {part: torso}"),
    ],
)
def test_bad_part_regions_are_recipe_errors(region, message):
    import yaml

    text = yaml.safe_dump({"steps": [{"op": "loosen", "region": region, "by": 1}]})
    with pytest.raises(RecipeError, match=message.replace("[", r"\[").replace("{", r"\{")):
        parse_recipe(text)


@pytest.mark.slow
@pytest.mark.parametrize("key", sorted(REAL))
def test_shared_garments_parts_and_coverage(key):
    """Every shared garment's torso and sleeves hold their whole girths; its front (a
    dress's skirt front) about half of the torso's."""
    from ptailor.formats.garment import load_garment

    g = load_garment(real_path(key), pattern_units=REAL[key][1]).garment
    plist = structure(g).panels
    for part in ("torso", "sleeves") if key != "dress" else ("torso", "bodice", "skirt"):
        faces = region_faces({"part": part}, g, g.V3, plist)
        found = girth_coverage(g.V3, g.F3, faces, garment=g)
        assert found and all(c.fraction >= 0.99 for c in found), (part, found)
    front = "skirt_front" if key == "dress" else "front"
    faces = region_faces({"panels": [front]}, g, g.V3, plist)
    (c,) = girth_coverage(g.V3, g.F3, faces, garment=g)
    assert 0.45 <= c.fraction <= 0.55, c
