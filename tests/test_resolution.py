"""One answer per garment, whatever its resolution (issue 21).

The same garment subdivided (``bench/subdivide.py``: every triangle split at its edge
midpoints, drape and pattern alike) is the same surface and the same pattern, so an edit
of it must give the same adjusted pattern at the original vertices, and the stitching must
converge in about as many iterations with every seam at its ratio. Tolerances: 0.25 mm for
the flatten alone (the same edited drape, subdivided), 0.5 mm for the whole adjustment (the
edit too runs at each resolution), on garments about 1 m across.
"""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import numpy as np
import pytest

from ptailor import samples
from ptailor.method.solver import stitch
from ptailor.model.garment import Garment, panels
from ptailor.model.seams import seams
from ptailor.recipe import parse_recipe
from tests.conftest import ROOT, real_path

sys.path.insert(0, str(ROOT / "bench"))
from subdivide import midpoint_subdivision, subdivide_garment, subdivide_obj

LOOSEN = (ROOT / "src/ptailor/recipes/loosen-waist.yaml").read_text()
GATHER = (
    "units: cm\nsteps: [{op: scale_seam, seam: [sleeve, cuff], part: sleeve, "
    "direction: around, factor: 1.3, fix: [top]}]"
)
SCALE = (
    "units: cm\nsteps: [{op: scale, region: {box: {min: [-50, 20, -50], max: [50, 60, 50]}}, "
    "direction: around, factor: 1.1}]"
)
CASES = {
    "bodice-loosen": (samples.bodice, LOOSEN),
    "lantern-gather": (samples.lantern_sleeve, GATHER),
    "bodice-scale": (samples.bodice, SCALE),
}


def subdivided(g: Garment, levels: int = 1) -> Garment:
    V3, F3, V2, F2, parent = subdivide_garment(g.V3, g.F3, g.V2, g.F2, levels=levels)
    return dataclasses.replace(g, V3=V3, F3=F3, V2=V2, F2=F2, face_group=g.face_group[parent])


def test_midpoint_subdivision_splits_each_triangle_in_four_with_its_orientation():
    V = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0], [2.0, 2.0]])
    F = np.array([[0, 1, 2], [1, 3, 2]])
    W, G, E = midpoint_subdivision(V, F)
    assert len(G) == 8 and len(W) == 4 + 5  # 5 distinct edges
    np.testing.assert_array_equal(W[:4], V)
    np.testing.assert_allclose(W[4:], 0.5 * (V[E[:, 0]] + V[E[:, 1]]))

    def area(P, T):
        a, b, c = P[T[:, 0]], P[T[:, 1]], P[T[:, 2]]
        return 0.5 * ((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])

    np.testing.assert_allclose(area(W, G), np.repeat(area(V, F) / 4, 4))  # same winding
    assert V.shape == (4, 2) and F.shape == (2, 3)  # inputs untouched


def test_a_subdivided_garment_keeps_its_panels_seams_and_lengths():
    g = samples.bodice()
    s = subdivided(g)
    assert s.n_faces == 4 * g.n_faces
    np.testing.assert_array_equal(s.V2[: len(g.V2)], g.V2)
    np.testing.assert_array_equal(s.V3[: len(g.V3)], g.V3)
    pa, ps = panels(g), panels(s)
    assert [p.name for p in pa] == [p.name for p in ps]

    def seam_lengths(garment, plist):
        lab = np.zeros(garment.n_faces, dtype=np.int64)
        for i, p in enumerate(plist):
            lab[p.faces] = i
        return sorted(sorted(x.lengths(garment.V2)) for x in seams(garment.F3, garment.F2, lab))

    np.testing.assert_allclose(seam_lengths(s, ps), seam_lengths(g, pa), rtol=1e-12)


def test_subdivide_obj_writes_the_same_garment_four_times_finer(tmp_path):
    from ptailor.formats.garment import load_garment
    from ptailor.formats.obj import write_garment

    g = samples.lantern_sleeve()
    src, dst = tmp_path / "g.obj", tmp_path / "g4.obj"
    write_garment(src, g, header=["units: cm"])
    assert subdivide_obj(src, dst, levels=1) == 4 * g.n_faces
    s = load_garment(dst).garment
    assert [p.name for p in panels(s)] == [p.name for p in panels(g)]  # groups kept
    np.testing.assert_allclose(s.V2[: len(g.V2)], g.V2, atol=1e-5)


@pytest.mark.slow
@pytest.mark.parametrize("case", sorted(CASES))
def test_the_flatten_of_one_edit_agrees_at_1x_and_4x(case):
    """The 1x edited drape subdivided and flattened at 4x: within 0.25 mm of the 1x pattern
    at the 1x vertices, converged, seams met."""
    from ptailor import pipeline as pl
    from ptailor.method.flatten import flatten

    make, text = CASES[case]
    g = make()
    calls = []

    def keep(garment, V3, **kw):
        calls.append((garment, V3, kw))
        return flatten(garment, V3, **kw)

    pl_flatten, pl.flatten = pl.flatten, keep
    try:
        a1 = pl.adjustment(g, parse_recipe(text), baseline=False)
    finally:
        pl.flatten = pl_flatten
    base, V3e, kw = calls[0]
    kw = {k: v for k, v in kw.items() if k not in ("panel_list", "seam_pairs")}
    assert kw.get("outline_free") is None
    fine = subdivided(base)
    V3f = subdivide_garment(V3e, base.F3, base.V2, base.F2, levels=1)[0]
    r = flatten(fine, V3f, **kw)
    n = len(a1.result.V2)
    assert r.info.converged and a1.result.info.converged
    assert r.info.seam_violation < 1e-9
    assert r.info.iterations <= a1.result.info.iterations + 5
    assert np.linalg.norm(r.V2[:n] - a1.result.V2, axis=1).max() < 0.025


@pytest.mark.slow
@pytest.mark.parametrize("case", sorted(CASES))
def test_one_adjustment_agrees_at_1x_and_4x(case):
    """The whole adjustment (edit and flatten) of the garment and of the same garment
    subdivided: within 0.5 mm at the 1x vertices."""
    from ptailor.pipeline import adjustment

    make, text = CASES[case]
    g = make()
    a1 = adjustment(g, parse_recipe(text), baseline=False)
    a4 = adjustment(subdivided(g), parse_recipe(text), baseline=False)
    n = len(g.V2)
    assert a4.result.info.converged and a4.result.info.seam_violation < 1e-9
    assert np.linalg.norm(a4.result.V2[:n] - a1.result.V2, axis=1).max() < 0.05


def test_loosen_smooths_over_lengths_of_the_edit_not_of_the_mesh():
    from ptailor.pipeline import adjustment

    g = samples.bodice()
    by = LOOSEN.replace("girth: 4", "by: 1.5")
    assert by != LOOSEN
    logs = [
        adjustment(x, parse_recipe(by), baseline=False).state.log[0]["smoothing"]
        for x in (g, subdivided(g))
    ]
    assert logs == [1.5, 1.5]


@pytest.fixture(scope="module")
def tee6_16x(tmp_path_factory) -> Path:
    src = real_path("tee6")
    dst = tmp_path_factory.mktemp("res") / "tee6_x16.obj"
    subdivide_obj(src, dst, levels=2)
    return dst


@pytest.mark.slow
def test_a_production_resolution_tee_loosened_converges_with_its_seams_closed(tee6_16x, tmp_path):
    """Issue 21's reproduction: the shared tee subdivided 1 -> 16 (82k triangles), the
    torso loosened by 2 cm. Before the seam constraints' curvature: the 100-iteration cap,
    residual 1.4e-5, seams 1e-5 off (a compressed seam side zigzagging under linearised
    constraints). Now about 21 iterations, seams exact, no warning, and within 1.5 mm of the
    1x garment's pattern at its vertices (the loosen's own discretisation; 0.6 mm of it is
    the stitching's)."""
    from ptailor.formats.garment import load_garment
    from ptailor.pipeline import adjustment, solver_warnings

    rec = parse_recipe("units: cm\nsteps: [{op: loosen, region: {panels: [front, back]}, by: 2}]")
    u = "0.3333cm"
    g16 = load_garment(tee6_16x, pattern_units=u, drape_units=u).garment
    g1 = load_garment(real_path("tee6"), pattern_units=u, drape_units=u).garment
    a16 = adjustment(g16, rec, baseline=False)
    info = a16.result.info
    assert info.converged and info.iterations <= 35 and not info.stalled
    assert info.seam_violation < 1e-9
    assert not solver_warnings(a16)
    a1 = adjustment(g1, rec, baseline=False)
    n = len(g1.V2)
    assert np.linalg.norm(a16.result.V2[:n] - a1.result.V2, axis=1).max() < 0.15


@pytest.mark.slow
def test_the_dress_skirt_widened_converges_near_its_optimum(monkeypatch):
    """The shared dress, its skirt 1.1 around: its 46 x 7.6 cm bodice strip bent, where
    local/global steps crawl (the 100-iteration cap, 1.7 mm from the optimum, before the
    Newton steps; 28 iterations with them). The strip shares no vertex with the skirt: it
    now moves rigidly in the edit and keeps its pattern, and the run converges in 20
    iterations, every seam at its ratio, within 0.05 mm of the same run iterated to a 100
    times smaller step."""
    from ptailor.formats.garment import load_garment
    from ptailor.pipeline import adjustment, solver_warnings

    g = load_garment(real_path("dress"), pattern_units="auto", drape_units="cm").garment
    text = (
        "units: cm\nsteps: [{op: scale, region: {panels: [skirt_front, skirt_back_left, "
        "skirt_back_right]}, direction: around, axis: auto, factor: 1.1}]"
    )
    a = adjustment(g, parse_recipe(text), baseline=False)
    info = a.result.info
    assert info.converged and info.iterations < 30
    assert info.seam_violation < 1e-9 and not solver_warnings(a)
    import ptailor.method.flatten as flatten_module

    def tight(*args, **kwargs):
        return stitch(*args, **{**kwargs, "step_tol": 1e-9, "max_iter": 400})

    monkeypatch.setattr(flatten_module, "stitch", tight)
    ref = adjustment(g, parse_recipe(text), baseline=False)
    assert ref.result.info.converged
    assert np.linalg.norm(a.result.V2 - ref.result.V2, axis=1).max() < 0.005


@pytest.mark.slow
def test_a_production_resolution_tshirt_gathered_at_both_armholes_converges(tmp_path):
    """The shared tshirt subdivided 1 -> 16 (88k triangles), both armholes gathered 1.2:
    the sleeves' armhole sides are held longer than their cloth wants, and the exact length
    constraint alone has a sawtooth minimum on a mesh this fine (the 100-iteration cap
    before the seam sides' bending, ``method/bend.py``). Then converged in about 21
    iterations; with the gather taken in a band of the sleeve's pattern (issue 42, item 5:
    the drape kept) the stitching hit the cap again while the band's targets were a
    stretch field (not flat); as a map's Jacobians (``method/gather.py``): 14 iterations,
    seams exact, no warning."""
    from ptailor.formats.garment import load_garment
    from ptailor.pipeline import adjustment, solver_warnings

    dst = tmp_path / "tshirt_x16.obj"
    subdivide_obj(real_path("tshirt"), dst, levels=2)
    g = load_garment(dst, pattern_units="auto", drape_units="cm").garment
    rec = parse_recipe(
        "units: cm\nsteps: [{op: scale_seam, seam: [front, sleeve_left], part: sleeve_left, "
        "direction: around, factor: 1.2, symmetric: true}]"
    )
    a = adjustment(g, rec, baseline=False)
    info = a.result.info
    assert info.converged and info.iterations <= 30 and not info.stalled
    assert info.seam_violation < 1e-9
    assert not solver_warnings(a)


@pytest.mark.slow
def test_a_sleeve_widened_converges_without_newton_steps_at_4x():
    """The shared long-sleeve subdivided 1 -> 4 (32k triangles), one sleeve 1.1 around: its
    collars, kept slender strips sewn to the neckline, bend by the neckline's uneven
    lengthening; at 1000 times the kept panels' weight that bend (1e-5 of their size) was
    closed by local/global at 1.5 % a step and only Newton steps finished it (23 iterations,
    2 Newton steps); at 10000 it falls below the step tolerance (docs/method.md, "What
    crawls"): converged in at most 30 iterations, no Newton step, every seam at its ratio."""
    from ptailor.formats.garment import load_garment
    from ptailor.method import tolerances as method_tol
    from ptailor.pipeline import adjustment, solver_warnings

    g = load_garment(real_path("longsleeve"), pattern_units="auto", drape_units="cm").garment
    text = (
        "units: cm\nsteps: [{op: scale, region: {part: sleeve_left}, direction: around, "
        "axis: auto, factor: 1.1}]"
    )
    a = adjustment(subdivided(g, 1), parse_recipe(text), baseline=False)
    info = a.result.info
    assert info.converged and info.iterations <= 30 and not info.stalled
    assert info.newton_steps == 0
    assert info.seam_violation < method_tol.SEAM_EXACT_REL and not solver_warnings(a)


@pytest.fixture(scope="module")
def tshirt_4x_16x(tmp_path_factory) -> dict:
    """The shared tshirt subdivided 1 -> 4 (22k triangles) and 1 -> 16 (88k), loaded."""
    from ptailor.formats.garment import load_garment

    src, out = real_path("tshirt"), tmp_path_factory.mktemp("tshirt")
    got = {}
    for levels, key in ((1, "4x"), (2, "16x")):
        dst = out / f"tshirt_{key}.obj"
        subdivide_obj(src, dst, levels=levels)
        got[key] = load_garment(dst, pattern_units="auto", drape_units="cm").garment
    return got


#: edit -> (recipe step, largest distance between the 4x and 16x patterns at the 4x vertices
#: in cm, measured 2026-12-06: 0.038 / 0.054 / 0.128 cm)
PRODUCTION_EDITS = {
    "loosen": ("{op: loosen, region: {panels: [front, back]}, by: 2}", 0.05),
    "sleeve": (
        "{op: scale, region: {panels: [sleeve_left]}, direction: around, axis: auto, factor: 1.1}",
        0.07,
    ),
    "gather": (
        "{op: scale_seam, seam: [front, sleeve_left], part: sleeve_left, direction: around, "
        "factor: 1.2}",
        0.15,
    ),
}


@pytest.mark.slow
@pytest.mark.parametrize("edit", sorted(PRODUCTION_EDITS))
def test_production_resolutions_agree_converged_with_their_seams_closed(tshirt_4x_16x, edit):
    """Issue 44: between production resolutions (the shared tshirt at 4x and 16x) every
    edit converges in at most 30 iterations without a Newton step, every seam at its ratio
    (1e-9 cm), and the two patterns agree at the 4x vertices: 99 % of them within 0.5 mm.
    The largest distance is within 0.5 mm for the loosen (0.38 mm); the widened sleeve's
    0.54 mm and the gather's 1.28 mm lie on the edited sleeve, where the asked stretch jumps
    (the gathered seam's ends, 1.2 against the shoulder's 1.0; the scaled region's border):
    the 16x mesh resolves that jump further, so those bounds are what was measured, not
    0.5 mm."""
    from ptailor.pipeline import adjustment, solver_warnings

    step, worst = PRODUCTION_EDITS[edit]
    rec = parse_recipe(f"units: cm\nsteps:\n  - {step}\n")
    a4, a16 = (adjustment(tshirt_4x_16x[k], rec, baseline=False) for k in ("4x", "16x"))
    for a in (a4, a16):
        info = a.result.info
        assert info.converged and info.iterations <= 30 and info.newton_steps == 0
        assert info.seam_violation < 1e-9 and not solver_warnings(a)
    n = len(a4.result.V2)
    d = np.linalg.norm(a16.result.V2[:n] - a4.result.V2, axis=1)
    assert np.percentile(d, 99) < 0.05
    assert d.max() < worst
