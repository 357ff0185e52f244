"""The adjustment's flatten reuses the seams the garment's structure already found.

``pipeline`` hands ``flatten`` the structure's ``seam_halfedges`` (``seam_pairs=``): the
pairs equal what ``seam_ease`` would compute, on garments with several panels, T-seams
and holes, and the flatten comes out bit for bit the same with or without them.
"""

from __future__ import annotations

import numpy as np
import pytest

import ptailor.method.ease as ease_module
import ptailor.pipeline as pipeline
from ptailor.method.ease import seam_ease
from ptailor.method.flatten import flatten
from ptailor.model.garment import Garment, panel_labels, panels
from ptailor.model.seams import seam_halfedges
from ptailor.model.structure import structure
from ptailor.recipe import parse_recipe
from ptailor.samples import bodice, lantern_sleeve, tseam_tube

WIDER = "steps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.1}]"


def with_hole(g: Garment) -> Garment:
    """``g`` without a few neighbouring triangles of its first panel's interior (a hole in
    the drape and in the pattern, both sides of it in the same panel)."""
    F = g.F2[panel_labels(panels(g), g.n_faces) == 0]
    centre = g.V2[np.unique(F)].mean(axis=0)
    d = np.linalg.norm(g.V2[g.F2].mean(axis=1) - centre, axis=1)
    keep = np.ones(g.n_faces, dtype=bool)
    keep[np.argsort(d)[:6]] = False
    return Garment(V3=g.V3, F3=g.F3[keep], V2=g.V2, F2=g.F2[keep])


GARMENTS = {
    "tseam": tseam_tube,
    "bodice_hole": lambda: with_hole(bodice(n_around=32, n_along=12)),
    "sleeve_hole": lambda: with_hole(lantern_sleeve()),
}


def test_the_holes_are_holes():
    for key in ("bodice_hole", "sleeve_hole"):
        g = GARMENTS[key]()
        assert len(structure(g).panel_loops(0)) >= 2  # the outline and a hole


@pytest.mark.parametrize("key", sorted(GARMENTS))
def test_adjust_passes_the_structures_seams_equal_to_computed_ones(key, monkeypatch):
    g = GARMENTS[key]()
    seen = []
    real = pipeline.flatten

    def spy(garment, V3, **kw):
        seen.append((garment, V3, kw))
        return real(garment, V3, **kw)

    monkeypatch.setattr(pipeline, "flatten", spy)
    calls = []
    real_pairs = ease_module.seam_halfedges

    def counted(F3, F2):
        calls.append(len(F3))
        return real_pairs(F3, F2)

    monkeypatch.setattr(ease_module, "seam_halfedges", counted)
    adj = pipeline.adjustment(g, parse_recipe(WIDER), baseline=True)
    assert calls == []  # the flatten found no seams of its own
    base, V3, kw = seen[0]
    pairs = kw.pop("seam_pairs")
    assert pairs is not None and len(pairs) > 0
    np.testing.assert_array_equal(pairs, real_pairs(base.F3, base.F2))
    # the flatten with the pairs it computes itself: the very same pattern
    monkeypatch.setattr(ease_module, "seam_halfedges", real_pairs)
    again = real(base, V3, **kw)
    np.testing.assert_array_equal(again.V2, adj.result.V2)
    assert len(seen) == 2 and seen[1][2].get("seam_pairs") is None  # the baseline: free


def test_seam_ease_takes_the_pairs_it_is_given():
    g = tseam_tube()
    flab = panel_labels(panels(g), g.n_faces)
    pairs = seam_halfedges(g.F3, g.F2)
    full = seam_ease(g.F3, g.F2, g.V2, face_panel=flab)
    same = seam_ease(g.F3, g.F2, g.V2, face_panel=flab, pairs=pairs)
    for a, b in zip(
        (full.ea, full.eb, full.row, full.ratio),
        (same.ea, same.eb, same.row, same.ratio),
        strict=True,
    ):
        np.testing.assert_array_equal(a, b)
    part = seam_ease(g.F3, g.F2, g.V2, face_panel=flab, pairs=pairs[:5])
    assert part.n_rows == 5
    np.testing.assert_array_equal(part.ea, full.ea[:5])


def test_flatten_with_and_without_seam_pairs_is_the_same():
    g = GARMENTS["sleeve_hole"]()
    V3 = g.V3 * np.array([1.1, 1.0, 1.1])
    plain = flatten(g, V3)
    given = flatten(g, V3, seam_pairs=seam_halfedges(g.F3, g.F2))
    np.testing.assert_array_equal(plain.V2, given.V2)
