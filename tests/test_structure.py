"""A garment's derived structure: computed once, equal to the direct computations."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from ptailor.model.boundary import boundary_curves, boundary_loops
from ptailor.model.frame import Frame
from ptailor.model.garment import (
    CUT_FROM,
    MOVED_FROM,
    Garment,
    panel_labels,
    panels,
    vertex_labels,
)
from ptailor.model.names import panel_layout
from ptailor.model.openings import openings
from ptailor.model.seams import seam_halfedges, seams
from ptailor.model.structure import structure
from ptailor.samples import bodice, flat_tee, lantern_sleeve


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
    assert [o.name for o in s.openings] == [
        o.name for o in openings(g.V3, g.F3, F2=g.F2, frame=Frame())
    ]
    lay = panel_layout(g.V3, g.F3, g.F2, s.face_panel, len(plist), frame=Frame())
    assert s.layout.names == lay.names
    for p in s.panels:
        want = boundary_loops(g.F2[p.faces])
        assert all(np.array_equal(a, b) for a, b in zip(s.panel_loops(p.index), want, strict=True))


def test_structure_seams_reuse_its_seam_halfedges(monkeypatch):
    """The seams are built from the structure's half-edge pairs, not from a second trace."""
    import importlib

    seams_module = importlib.import_module("ptailor.model.seams")  # (the package's
    # ``seams`` attribute is the function)
    g = bodice()
    s = structure(g)
    pairs = s.seam_halfedges
    want = seams(g.F3, g.F2, s.face_panel)

    def traced_again(*args, **kwargs):
        raise AssertionError("seam_halfedges computed a second time")

    monkeypatch.setattr(seams_module, "seam_halfedges", traced_again)
    got = s.seams
    assert [x.panels for x in got] == [x.panels for x in want]
    for a, b in zip(got, want, strict=True):
        assert np.array_equal(a.edges3, b.edges3) and np.array_equal(a.edges_a, b.edges_a)
        assert np.array_equal(a.edges_b, b.edges_b)
    assert [x.panels for x in seams(g.F3, g.F2, s.face_panel, halfedges=pairs)] == [
        x.panels for x in want
    ]


def test_structure_is_cached_per_garment_and_frame():
    g = lantern_sleeve()
    s = structure(g)
    assert structure(g) is s
    assert structure(g.with_frame(Frame((0, 0, 1), (0, 1, 0)))) is not s
    assert s.seams is s.seams and s.face_panel is s.face_panel
    # a garment made from another starts afresh (a moved one remembers only where it came
    # from: MOVED_FROM); pickles carry no cache
    g2 = g.with_drape(g.V3 * 2.0)
    assert set(g2.cache) == {MOVED_FROM} and structure(g2) is not s
    g3 = pickle.loads(pickle.dumps(g))
    assert g3.cache == {} and len(structure(g3).panels) == len(s.panels)
    # the garment's arrays are untouched
    assert np.array_equal(g.V3, lantern_sleeve().V3)


def _ungrouped(g):
    """``g`` without its OBJ groups: every panel named from the drape's geometry."""
    from dataclasses import replace

    return replace(g, face_group=np.full(g.n_faces, -1), group_names=())


def test_ungrouped_panels_name_from_the_structures_own_layout():
    g = _ungrouped(bodice())
    s = structure(g)
    assert [p.name for p in s.panels] == [p.name for p in panels(g)]
    assert "layout" in s.__dict__  # the layout panels() needed is the structure's, kept
    lab, n_p = s.panel_components
    assert np.array_equal(lab, s.face_panel) and n_p == len(s.panels)


def test_named_garment_reads_its_sources_structure():
    from ptailor.model.garment import with_panel_names

    g = _ungrouped(bodice())
    s = structure(g)
    for name in ("panels", "seams", "openings", "layout", "drape_boundary"):
        getattr(s, name)
    named = with_panel_names(g, plist=s.panels)
    t = structure(named)
    assert t is not s
    assert t.panels is s.panels  # its groups are these names: nothing recomputed
    assert t.layout is s.layout and t.openings is s.openings and t.seams is s.seams
    assert [p.name for p in panels(named)] == [p.name for p in s.panels]
    # another frame: another garment, nothing computed there yet
    other = structure(named.with_frame(Frame((0, 0, 1), (0, 1, 0))))
    assert other.__dict__.get("layout") is None
    # a garment with other names as groups does not take the source's panels
    renamed = with_panel_names(g, plist=[replace_name(p, f"x{p.index}") for p in s.panels])
    assert [p.name for p in structure(renamed).panels] == [f"x{p.index}" for p in s.panels]


def replace_name(p, name):
    from dataclasses import replace

    return replace(p, name=name)


def test_boundary_fast_path_pairs_ends_as_the_fans_do():
    """Without T-edges and with two ends at every boundary vertex, pairing the ends by
    vertex is the fans' pairing (and the shortcut is not taken otherwise)."""
    from ptailor.model import boundary as bd

    taken = 0
    for g in (bodice(), lantern_sleeve()):
        rng = np.random.default_rng(3)
        subsets = [np.ones(g.n_faces, bool)] + [rng.random(g.n_faces) < 0.97 for _ in range(6)]
        for F in [g.F3[k] for k in subsets] + [g.F2[k] for k in subsets]:
            F = np.asarray(F, dtype=np.int64)
            h = bd.half_edges(F)
            order, inv, cnt = bd.edge_groups(bd.edge_keys(h))
            c = cnt[inv]
            bh = np.flatnonzero(c == 1)
            ends = h[bh].ravel()
            fans = bd._end_fans(h, order, c, inv, bh, F, None, None)
            partner = bd._pair_ends(ends, fans, h[bh][:, ::-1].ravel())
            if cnt.max() <= 2 and (np.bincount(ends)[ends] == 2).all():
                taken += 1
                assert np.array_equal(partner, bd._pair_at_vertices(ends))
    assert taken >= 2


def test_a_moved_garment_keeps_what_each_panel_is_and_measures_where_it_lies():
    """A drape moved by an edit (same triangles) keeps the input's panel roles and opening
    names, even where the naming rules would read the moved shape otherwise; positions and
    lengths are the moved drape's; a garment moved twice carries the first's reading."""
    g = flat_tee()
    s = structure(g)
    V3 = g.V3 * np.array([3.0, 0.3, 1.0])  # squashed: a rule reading it afresh could differ
    moved = g.with_drape(V3).with_pattern(g.V2 * 1.5)
    assert moved.cache[MOVED_FROM] is g
    m = structure(moved)
    assert m.layout.names == s.layout.names and m.layout.role == s.layout.role
    assert m.layout.side == s.layout.side and m.layout.tier == s.layout.tier
    assert [o.name for o in m.openings] == [o.name for o in s.openings]
    fresh = structure(Garment(V3=V3, F3=g.F3, V2=g.V2 * 1.5, F2=g.F2, frame=g.frame))
    np.testing.assert_allclose(m.layout.centroid, fresh.layout.centroid, atol=1e-9)
    np.testing.assert_allclose(m.layout.height, fresh.layout.height)
    got = {o.name: o.length for o in m.openings}
    for o in fresh.openings:  # the same loops, measured on the moved drape
        same = [x for x in m.openings if np.array_equal(np.sort(x.loop), np.sort(o.loop))]
        assert len(same) == 1 and got[same[0].name] == pytest.approx(o.length, rel=1e-12)
    assert [x.panels for x in m.seams] == [x.panels for x in s.seams]
    # lying on its side, the rules reading it afresh name it otherwise; moved, it is the tee
    R = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    side = Garment(V3=g.V3 @ R.T, F3=g.F3, V2=g.V2, F2=g.F2, frame=g.frame)
    assert [o.name for o in structure(side).openings] != [o.name for o in s.openings]
    on_side = structure(g.with_drape(g.V3 @ R.T))
    assert [o.name for o in on_side.openings] == [o.name for o in s.openings]
    assert on_side.layout.role == s.layout.role


def test_a_garment_cut_from_another_keeps_what_its_panels_and_openings_were():
    """A cut (triangles removed) reshapes panels and openings but leaves them what they
    were: the tee's front cropped to a band 15 % of its height tall is read afresh as a
    collar (and the back as the front), its hem as an unnamed opening; cut from the tee
    (``CUT_FROM``: each triangle's and drape vertex's source), the band is the front, the
    back the back, the hem the hem."""
    g = flat_tee()
    s = structure(g)
    front = next(p.index for p in s.panels if p.name == "front")
    height = g.V3[g.F3].mean(axis=1)[:, 1]
    lo, hi = g.V3[:, 1].min(), g.V3[:, 1].max()
    keep = ~((s.face_panel == front) & (height < lo + 0.85 * (hi - lo)))
    u3, u2 = np.unique(g.F3[keep]), np.unique(g.F2[keep])
    m3, m2 = np.full(len(g.V3), -1), np.full(len(g.V2), -1)
    m3[u3], m2[u2] = np.arange(len(u3)), np.arange(len(u2))
    arrays = dict(V3=g.V3[u3], F3=m3[g.F3[keep]], V2=g.V2[u2], F2=m2[g.F2[keep]], frame=g.frame)
    fresh = structure(Garment(**arrays))
    assert "collar" in fresh.layout.role and "hem" not in [o.name for o in fresh.openings]
    cut = Garment(**arrays)
    cut.cache[CUT_FROM] = (g, np.flatnonzero(keep), u3)
    c = structure(cut)
    assert c.layout.role == s.layout.role and c.layout.names == s.layout.names
    assert [o.name for o in c.openings] == [o.name for o in s.openings]
    assert c.layout.mirror.tolist() == s.layout.mirror.tolist()
    # positions are the cut garment's: the front band's centroid is high up
    p = c.layout.names.index("front")
    assert c.layout.centroid[p, 1] > 0.8 * c.layout.height
