"""A garment's derived structure, computed once per garment and reused.

Panels, their face and vertex labels, seams, the per-panel pattern outlines and the
drape's openings all follow from a :class:`~ptailor.model.garment.Garment`'s arrays,
which never change (the garment is frozen and its arrays are not written to). So they are
computed on first use and kept on the garment (as trimesh caches derived data on a mesh):
every consumer asks :func:`structure` instead of recomputing them. A garment made from
another (``with_drape``, ``dataclasses.replace``) starts with an empty cache.

Examples
--------
>>> from ptailor.model.garment import Garment
>>> V2 = np.array([[0.0, 0], [1, 0], [0, 1], [3, 0], [4, 0], [3, 1]])
>>> F = np.array([[0, 1, 2], [3, 4, 5]])
>>> g = Garment(V3=np.c_[V2, np.zeros(6)], F3=F, V2=V2, F2=F)
>>> s = structure(g)
>>> s is structure(g), len(s.panels), s.face_panel.tolist()
(True, 2, [0, 1])
>>> [lp.tolist() for lp in s.panel_loops(1)]
[[3, 4, 5]]
"""

from __future__ import annotations

from functools import cached_property

import numpy as np

from ptailor.geometry.labels import component_labels
from ptailor.model.boundary import boundary_curves, boundary_loops
from ptailor.model.garment import (
    CUT_FROM,
    MOVED_FROM,
    SAME_CLOTH,
    Garment,
    Panel,
    group_panel_names,
    named_panels,
    panel_labels,
    vertex_labels,
)
from ptailor.model.names import PanelLayout, panel_layout, seam_names
from ptailor.model.names.layout import descended_layout, moved_layout
from ptailor.model.openings import Opening, descended_openings, moved_openings, openings
from ptailor.model.seams import Seam, seam_halfedges, seams

#: ``Garment.cache`` key of the garment's structure
_KEY = "structure"


class GarmentStructure:
    """The derived structure of one garment, under its own frame (read-only).

    Every attribute is computed on first access and then kept. Arrays are shared with
    every consumer: do not write to them. A garment
    :func:`~ptailor.model.garment.with_panel_names` made takes the attributes that do not
    depend on the groups from its source garment's structure when that has computed them,
    and its panels when their names are its groups.

    Attributes
    ----------
    garment : Garment
        Its ``frame`` names the panels no group names and the openings.
    panel_components : ((m,) int array, int)
        The components of ``F2`` (a label per triangle, equal to ``face_panel``) and
        their count.
    panels : list of Panel
        ``panels(garment)``; panels no group names are named from
        this structure's ``layout`` (computed once, not once more inside ``panels``).
    face_panel : (m,) int array
        Panel index per triangle.
    vertex_panel : (n2,) int array
        Panel index per pattern vertex, -1 for unused vertices.
    seam_halfedges : (s, 2) int array
        :func:`ptailor.model.seams.seam_halfedges` of the garment.
    seams : list of Seam
        :func:`ptailor.model.seams.seams` over ``face_panel``.
    drape_boundary : (list of (k,) int arrays, (c,) bool array)
        :func:`ptailor.model.boundary.boundary_curves` of the drape (with ``V3``, ``F2``).
    openings : list of Opening
        :func:`ptailor.model.openings.openings` of the drape.
    layout : PanelLayout
        :func:`ptailor.model.names.panel_layout` over ``panel_components`` and
        ``openings``.
    seam_names : tuple of str
        :func:`ptailor.model.names.seam_names` of ``seams``, with ``panels``' names (what
        ``inspect`` and the report call them): the edits read seam names here, never from
        the naming rules.
    """

    def __init__(self, garment: Garment) -> None:
        self.garment = garment
        self._loops: dict[int, list[np.ndarray]] = {}

    def _same(self, name: str):
        """Attribute ``name`` as already computed for the garment of the same cloth (the
        one :func:`~ptailor.model.garment.with_panel_names` named), or None."""
        same = self.garment.cache.get(SAME_CLOTH)
        if same is None:
            return None
        return structure(same).__dict__.get(name)

    def _source(self) -> GarmentStructure | None:
        """The structure of the garment this one was moved from (same triangles, groups and
        frame: :meth:`~ptailor.model.garment.Garment.with_drape`), or None."""
        src = self.garment.cache.get(MOVED_FROM)
        return None if src is None else structure(src)

    @cached_property
    def panel_components(self) -> tuple[np.ndarray, int]:
        """``(labels, count)``: the connected components of ``F2``, a label per triangle
        (the panel index: ``face_panel``), before the panels are named."""
        g = self.garment
        same = self._same("panel_components")
        if same is not None:
            return same
        src = self._source()
        if src is not None:
            return src.panel_components
        lab = component_labels(g.F2, len(g.V2))
        return lab, int(lab.max()) + 1 if lab.size else 0

    @cached_property
    def panels(self) -> list[Panel]:
        same = self._same("panels")
        written = tuple(p.name for p in same) if same is not None else ()
        if written == self.garment.group_names and len(set(written)) == len(written) > 0:
            return same  # the groups are these panels' names, one group each: panels() again
        lab, n_p = self.panel_components
        names = group_panel_names(self.garment, lab, n_p)
        # names from geometry (no group names a panel): this structure's layout, once
        geo = self.layout.names if any(n is None for n in names) else None
        return named_panels(self.garment, lab, names, geo)

    @cached_property
    def face_panel(self) -> np.ndarray:
        same = self._same("face_panel")
        return same if same is not None else panel_labels(self.panels, self.garment.n_faces)

    @cached_property
    def vertex_panel(self) -> np.ndarray:
        same = self._same("vertex_panel")
        return same if same is not None else vertex_labels(self.panels, len(self.garment.V2))

    @cached_property
    def seam_halfedges(self) -> np.ndarray:
        same = self._same("seam_halfedges")
        if same is None and self._source() is not None:
            same = self._source().seam_halfedges
        return same if same is not None else seam_halfedges(self.garment.F3, self.garment.F2)

    @cached_property
    def seams(self) -> list[Seam]:
        g, same = self.garment, self._same("seams")
        if same is not None:
            return same
        return seams(g.F3, g.F2, self.face_panel, halfedges=self.seam_halfedges)

    @cached_property
    def drape_boundary(self) -> tuple[list[np.ndarray], np.ndarray]:
        g = self.garment
        same = self._same("drape_boundary")
        return same if same is not None else boundary_curves(g.F3, V=g.V3, F2=g.F2)

    @cached_property
    def openings(self) -> list[Opening]:
        g = self.garment
        same = self._same("openings")
        if same is not None:
            return same
        src = self._source()
        if src is not None:  # the same loops under the same names, measured where they lie
            return moved_openings(src.openings, g.V3)
        found = openings(g.V3, g.F3, frame=g.frame, F2=g.F2, curves=self.drape_boundary)
        cut = g.cache.get(CUT_FROM)
        if cut is not None:  # reshaped by a cut: the openings it kept keep their names
            return descended_openings(structure(cut[0]).openings, found, cut[2])
        return found

    @cached_property
    def layout(self) -> PanelLayout:
        g = self.garment
        same = self._same("layout")
        if same is not None:
            return same
        lab, n_p = self.panel_components
        src = self._source()
        if src is not None:  # what each panel is stays what it was before the move
            return moved_layout(src.layout, g.V3, g.F3, lab, opening_list=self.openings)
        cut = g.cache.get(CUT_FROM)
        if cut is not None:  # each piece is what the panel it was cut from was
            s0 = structure(cut[0])
            return descended_layout(
                s0.layout, s0.panel_components[0], g.V3, g.F3, lab, n_p, cut[1],
                opening_list=self.openings,
            )  # fmt: skip
        return panel_layout(
            g.V3,
            g.F3,
            g.F2,
            lab,
            n_p,
            frame=g.frame,
            opening_list=self.openings,
            V2=g.V2,
        )

    @cached_property
    def seam_names(self) -> tuple[str, ...]:
        g = self.garment
        names = [p.name for p in self.panels]
        return tuple(seam_names(g.V3, self.seams, self.layout, names))

    def panel_loops(self, index: int) -> list[np.ndarray]:
        """Boundary loops (pattern vertex indices) of panel ``index``.

        Returns
        -------
        list of (k,) int arrays
            ``boundary_loops(F2[panel.faces])``: longest first.
        """
        if index not in self._loops:
            self._loops[index] = boundary_loops(self.garment.F2[self.panels[index].faces])
        return self._loops[index]


def structure(garment: Garment) -> GarmentStructure:
    """The derived structure of ``garment`` under its frame (cached on the garment).

    Parameters
    ----------
    garment : Garment

    Returns
    -------
    GarmentStructure
        The same object for the same garment.
    """
    cache = garment.cache
    found = cache.get(_KEY)
    if found is None:
        found = cache[_KEY] = GarmentStructure(garment)
    return found
