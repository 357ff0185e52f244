"""Seams a pattern maker names by the pieces they join: a centre seam off the centre line,
darts, a poncho's shoulders (issue 42, item 9)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ptailor.geometry.labels import component_labels
from ptailor.model.garment import Garment
from ptailor.model.names import seam_names
from ptailor.model.structure import structure
from ptailor.samples import cone_skirt, flat_tee
from ptailor.samples.grid import split_pattern


def cut(g: Garment, lab: np.ndarray) -> Garment:
    """``g`` with its pattern cut into the pieces ``lab`` (per triangle), no panel names."""
    V2, F2, _ = split_pattern(g.V2, g.F2, lab)
    return replace(g, V2=V2, F2=F2, face_group=np.full(g.n_faces, -1), group_names=())


def named_seams(g: Garment) -> dict[str, tuple[str, str]]:
    st = structure(g)
    pn = [p.name for p in st.panels]
    names = seam_names(g.V3, st.seams, st.layout, pn)
    return {n: (pn[s.panels[0]], pn[s.panels[1]]) for s, n in zip(st.seams, names, strict=True)}


def test_a_centre_back_seam_off_the_centre_line_is_the_centre_back():
    """A skirt whose back halves meet 15 degrees off the centre back (the seam's midpoint a
    quarter of the radius to the left): the seam joins a right and a left panel."""
    g = cone_skirt()
    c = g.V3[g.F3].mean(axis=1)
    angle = np.degrees(np.mod(np.arctan2(c[:, 2], c[:, 0]), 2.0 * np.pi))
    g = cut(g, np.where(angle < 180.0, 0, np.where(angle < 285.0, 1, 2)))
    seams = named_seams(g)
    assert set(seams["skirt_center_back"]) == {"skirt_back_right", "skirt_back_left"}
    assert not any("princess" in n for n in seams)


def slit(g: Garment, *, angle: float, depth: float) -> Garment:
    """``g`` with its pattern slit open from the top down ``depth`` along the column of
    vertices at ``angle`` degrees (from the wearer's left, towards the front), the drape
    sewn: a dart, a seam of a panel with itself."""
    ang = np.degrees(np.mod(np.arctan2(g.V3[:, 2], g.V3[:, 0]), 2.0 * np.pi))
    col = ang[np.argmin(np.abs(ang - angle))]
    top = float(g.V3[:, 1].max())
    on = (np.abs(ang - col) < 1e-6) & (g.V3[:, 1] > top - depth + 1e-6)
    c = g.V3[g.F3].mean(axis=1)
    beyond = np.degrees(np.mod(np.arctan2(c[:, 2], c[:, 0]), 2.0 * np.pi)) > col
    corner = beyond[:, None] & on[g.F3]  # corners on the slit, of triangles beyond it
    moved, copy = np.unique(g.F2[corner], return_inverse=True)  # one copy per vertex
    F2 = g.F2.copy()
    F2[corner] = len(g.V2) + copy
    V2 = np.concatenate([g.V2, g.V2[moved]])
    return replace(g, V2=V2, F2=F2, face_group=np.full(g.n_faces, -1), group_names=())


def test_a_dart_is_a_dart():
    """A seam of a panel with itself (a skirt's back dart) is ``dart_<face>_<side>``."""
    g = slit(cone_skirt(), angle=300.0, depth=12.0)
    seams = named_seams(g)
    assert seams["skirt_dart_back_left"] == ("skirt_back", "skirt_back")
    assert [n for n in seams if "dart" in n] == ["skirt_dart_back_left"]


def test_a_poncho_s_strips_and_side_panels():
    """Centre strips and side panels (a poncho-like torso): the strips' shoulder seams are
    the inner ones, each seam's name has one side word at most."""
    g = flat_tee(sleeves="none")
    c = g.V3[g.F3].mean(axis=1)
    lab = component_labels(g.F2, len(g.V2)) * 3
    lab += np.where(np.abs(c[:, 0]) < 14.0, 0, np.where(c[:, 0] > 0, 1, 2))
    seams = named_seams(cut(g, lab))
    assert seams["shoulder_left_inner"] == ("front", "back")
    assert seams["shoulder_left_outer"] == ("front_left", "back_left")
    assert set(seams["princess_front_left"]) == {"front", "front_left"}
    assert not [n for n in seams if {"left", "right"} <= set(n.split("_"))]
