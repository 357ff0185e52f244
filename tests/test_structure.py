"""A garment's derived structure: computed once, equal to the direct computations."""

from __future__ import annotations

import pickle

import numpy as np

from ptailor.model.boundary import boundary_curves, boundary_loops
from ptailor.model.garment import panel_labels, panels, vertex_labels
from ptailor.model.names import panel_layout
from ptailor.model.openings import openings
from ptailor.model.seams import seam_halfedges, seams
from ptailor.model.structure import structure
from ptailor.samples import bodice, lantern_sleeve


def test_structure_matches_direct_computation():
    g = bodice()
    s = structure(g)
    plist = panels(g)
    assert [p.name for p in s.panels] == [p.name for p in plist]
    assert np.array_equal(s.face_panel, panel_labels(plist, g.n_faces))
    assert np.array_equal(s.vertex_panel, vertex_labels(plist, len(g.V2)))
    assert np.array_equal(s.seam_halfedges, seam_halfedges(g.F3, g.F2))
    assert [x.panels for x in s.seams] == [x.panels for x in seams(g.F3, g.F2, s.face_panel)]
    loops, closed = boundary_curves(g.F3, V=g.V3, F2=g.F2)
    assert all(np.array_equal(a, b) for a, b in zip(s.drape_boundary[0], loops, strict=True))
    assert np.array_equal(s.drape_boundary[1], closed)
    assert [o.name for o in s.openings] == [o.name for o in openings(g.V3, g.F3, F2=g.F2)]
    lay = panel_layout(g.V3, g.F3, g.F2, s.face_panel, len(plist))
    assert s.layout.names == lay.names
    for p in s.panels:
        want = boundary_loops(g.F2[p.faces])
        assert all(np.array_equal(a, b) for a, b in zip(s.panel_loops(p.index), want, strict=True))


def test_structure_is_cached_per_garment_and_axes():
    g = lantern_sleeve()
    s = structure(g)
    assert structure(g) is s
    assert structure(g, up=[0, 1, 0], front=(0.0, 0.0, 1.0)) is s
    assert structure(g, up=(0.0, 0.0, 1.0), front=(0.0, 1.0, 0.0)) is not s
    assert s.seams is s.seams and s.face_panel is s.face_panel
    # a garment made from another starts afresh; pickles carry no cache
    g2 = g.with_drape(g.V3 * 2.0)
    assert g2.cache == {} and structure(g2) is not s
    g3 = pickle.loads(pickle.dumps(g))
    assert g3.cache == {} and len(structure(g3).panels) == len(s.panels)
    # the garment's arrays are untouched
    assert np.array_equal(g.V3, lantern_sleeve().V3)
