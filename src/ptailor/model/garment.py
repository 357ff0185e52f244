"""The garment data model and its panels.

A garment is one triangle mesh seen twice: triangle ``i`` of ``F3`` (drape, 3D) and triangle
``i`` of ``F2`` (pattern, 2D) are the same piece of cloth. Vertices on a seam are one vertex
in 3D and two in 2D.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ptailor.geometry.labels import component_labels, scatter_labels, used_indices
from ptailor.geometry.triangles import signed_areas_2d
from ptailor.model.frame import DEFAULT_FRAME, Frame

__all__ = [
    "Garment",
    "Panel",
    "panel_labels",
    "panels",
    "vertex_labels",
    "with_panel_names",
]


#: ``Garment.cache`` key of a garment with the same ``V3, F3, V2, F2`` arrays and other groups
#: (:func:`with_panel_names`): its structure's group-free parts are this garment's too
SAME_CLOTH = "same_cloth"

#: ``Garment.cache`` key of the garment this one was moved from (:meth:`Garment.with_drape`,
#: :meth:`Garment.with_pattern`): the same triangles, groups and frame, so the same panels,
#: seams, openings and what each panel is, measured where this one lies
MOVED_FROM = "moved_from"

#: ``Garment.cache`` key of the garment this one was cut from (a cut, a shorten: triangles
#: removed, edges split), ``(source, face_parent, vertex_source)``: each triangle's source
#: triangle, each drape vertex's source vertex (-1 for a vertex the cut made). Its panels
#: are what their source panels were, and its openings keep their names where they keep
#: vertices (:mod:`ptailor.model.structure`)
CUT_FROM = "cut_from"


def read_only(a) -> np.ndarray:
    """``a`` as an array nobody can write: itself when it already is one (a garment's own
    array, shared by the garments made from it), else a read-only copy (the caller's array
    stays theirs to change).

    Examples
    --------
    >>> v = np.zeros(3)
    >>> r = read_only(v)
    >>> r.flags.writeable, v.flags.writeable, read_only(r) is r
    (False, True, True)
    """
    a = np.asarray(a)
    if not a.flags.writeable:
        return a
    a = a.copy()
    a.flags.writeable = False
    return a


@dataclass(frozen=True)
class Garment:
    """A drape and its pattern.

    The arrays are read-only (copied when given writable): derived data cached on the garment
    (:attr:`cache`) cannot go stale.

    Attributes
    ----------
    V3 : (n3, 3) float array
        Drape vertex positions.
    F3 : (m, 3) int array
        Drape triangles, indices into ``V3``.
    V2 : (n2, 2) float array
        Pattern vertex positions.
    F2 : (m, 3) int array
        Pattern triangles, indices into ``V2``; row ``i`` is the same cloth as ``F3[i]``.
    face_group : (m,) int array
        Index into ``group_names`` of each triangle's OBJ ``g``/``o`` group (-1: none).
    group_names : tuple of str
        Group names in file order.
    units : str
        Length unit of both ``V3`` and ``V2`` (everything is computed in one unit).
    frame : Frame
        The wearer's axes in ``V3``'s coordinates, resolved where the garment is read
        (:data:`~ptailor.model.frame.DEFAULT_FRAME`, y up and z front, where nothing says
        otherwise); every name from geometry and every measure reads it here. Garments made
        from this one (:meth:`with_drape`, ``dataclasses.replace``) keep it.
    """

    V3: np.ndarray
    F3: np.ndarray
    V2: np.ndarray
    F2: np.ndarray
    face_group: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    group_names: tuple[str, ...] = ()
    units: str = "cm"
    frame: Frame = DEFAULT_FRAME
    # derived structure (ptailor.model.structure), filled on first use; never copied
    _cache: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        m = len(self.F3)
        if len(self.face_group) != m:
            object.__setattr__(self, "face_group", np.full(m, -1, dtype=np.int64))
        if not isinstance(self.frame, Frame):
            raise TypeError(f"Garment.frame must be a Frame, not {type(self.frame).__name__}")
        # read-only: the cache (structure, ...) holds for as long as the garment lives
        for name in ("V3", "F3", "V2", "F2", "face_group"):
            object.__setattr__(self, name, read_only(getattr(self, name)))

    def __getstate__(self) -> dict:
        state = dict(self.__dict__)
        state["_cache"] = {}  # pickled garments (batch workers) recompute what they need
        return state

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)

    @property
    def cache(self) -> dict:
        """Derived data keyed by its maker (:func:`ptailor.model.structure.structure`)."""
        return self._cache

    @property
    def n_faces(self) -> int:
        return len(self.F3)

    def with_drape(self, V3: np.ndarray) -> Garment:
        """Return a copy with drape positions ``V3`` (same topology); it carries this
        garment's panels, openings and their names (``cache[MOVED_FROM]``)."""
        return self._moved(replace(self, V3=np.asarray(V3, dtype=np.float64)))

    def with_pattern(self, V2: np.ndarray) -> Garment:
        """Return a copy with pattern positions ``V2`` (same topology); it carries this
        garment's panels, openings and their names (``cache[MOVED_FROM]``)."""
        return self._moved(replace(self, V2=np.asarray(V2, dtype=np.float64)))

    def _moved(self, moved: Garment) -> Garment:
        moved.cache[MOVED_FROM] = self.cache.get(MOVED_FROM, self)  # the first: no chains
        return moved

    def with_frame(self, frame: Frame) -> Garment:
        """Return a copy whose wearer's axes are ``frame`` (same arrays)."""
        return replace(self, frame=frame)


@dataclass(frozen=True)
class Panel:
    """One connected piece of the pattern.

    Attributes
    ----------
    index : int
        Position in the garment's panel list.
    name : str
        From the OBJ groups when its faces share one, else ``panel_<index>``.
    faces : (k,) int array
        Indices of the garment triangles of this panel, ascending.
    vertices : (p,) int array
        Indices into ``V2`` of the pattern vertices this panel uses, ascending.
    mirrored : bool
        True when the panel's 2D triangles are clockwise.
    """

    index: int
    name: str
    faces: np.ndarray
    vertices: np.ndarray
    mirrored: bool


def panel_labels(panel_list: list[Panel], m: int) -> np.ndarray:
    """Panel index (``Panel.index``) per triangle, ``(m,)`` int, -1 for none."""
    return scatter_labels([p.faces for p in panel_list], m, labels=[p.index for p in panel_list])


def vertex_labels(panel_list: list[Panel], n: int) -> np.ndarray:
    """Panel index per pattern vertex, ``(n,)`` int, -1 for unused vertices."""
    return scatter_labels([p.vertices for p in panel_list], n, labels=[p.index for p in panel_list])


def panels(garment: Garment) -> list[Panel]:
    """The panels of a garment: connected components of ``F2``.

    Parameters
    ----------
    garment : Garment
        Its ``frame`` names the panels no group names.

    Returns
    -------
    list of Panel
        In order of each panel's first triangle. Names come from the OBJ group shared by
        most of the panel's triangles; a panel no group names (every panel, when one group
        covers them all: it names the mesh) is named from the drape's geometry by
        :func:`ptailor.model.names.panel_layout` (``front``, ``sleeve_left``, ...; a
        geometric name a group already uses gets ``_2``...); a group over several panels
        names them ``name``, ``name_1``, ... (a panel a cut split in two keeps its name
        that way).
    """
    lab = component_labels(garment.F2, len(garment.V2))
    n_p = int(lab.max()) + 1 if lab.size else 0
    names = group_panel_names(garment, lab, n_p)
    geo = None
    if any(n is None for n in names):
        from ptailor.model.names import panel_layout

        geo = panel_layout(
            garment.V3, garment.F3, garment.F2, lab, n_p, frame=garment.frame, V2=garment.V2
        ).names
    return named_panels(garment, lab, names, geo)


def group_panel_names(garment: Garment, lab: np.ndarray, n_p: int) -> list[str | None]:
    """Each panel's name from the OBJ groups (:func:`panels`), None where none names it.

    Parameters
    ----------
    garment : Garment
    lab : (m,) int array
        Panel per triangle (``component_labels(F2, len(V2))``).
    n_p : int
        Number of panels.

    Returns
    -------
    list of str or None
    """
    # majority group per panel, vectorised through a (panel, group) count table
    g = garment.face_group
    n_g = len(garment.group_names)
    names: list[str | None] = [None] * n_p
    if n_g:
        valid = g >= 0
        table = np.zeros((n_p, n_g), dtype=np.int64)
        np.add.at(table, (lab[valid], g[valid]), 1)
        best = table.argmax(axis=1)
        # one group over every panel names the whole mesh, not a panel
        covered = table[np.arange(n_p), best] > 0
        whole_mesh = int((table.sum(axis=0) > 0).sum()) == 1 and n_p > 1 and bool(covered.all())
        for p in range(n_p):
            if table[p, best[p]] > 0 and not whole_mesh:
                names[p] = garment.group_names[best[p]]
    return names


def named_panels(
    garment: Garment,
    lab: np.ndarray,
    names: list[str | None],
    geometric: list[str] | None,
) -> list[Panel]:
    """The panels of :func:`panels` from their labels and names.

    Parameters
    ----------
    garment : Garment
    lab : (m,) int array
        Panel per triangle (``component_labels(F2, len(V2))``).
    names : list of str or None
        :func:`group_panel_names`.
    geometric : list of str or None
        ``panel_layout(...).names`` over ``lab``: the names of the panels no group names
        (required when there is one).

    Returns
    -------
    list of Panel
    """
    F2 = garment.F2
    n_p = len(names)
    order = np.argsort(lab, kind="stable")
    bounds = np.searchsorted(lab[order], np.arange(n_p + 1))
    sa = signed_areas_2d(garment.V2, F2)
    names = list(names)
    if any(n is None for n in names):
        if geometric is None:
            raise ValueError("a panel no group names needs its name from geometry")
        taken = {n for n in names if n is not None}
        for p in range(n_p):
            if names[p] is None:
                name, k = geometric[p], 2
                while name in taken:
                    name, k = f"{geometric[p]}_{k}", k + 1
                taken.add(name)
                names[p] = name
    seen: dict[str, int] = {}
    out: list[Panel] = []
    for p in range(n_p):
        name = names[p]
        if name in seen:
            seen[name] += 1
            name = f"{name}_{seen[name]}"
        else:
            seen[name] = 0
        faces = np.sort(order[bounds[p] : bounds[p + 1]])
        verts = used_indices(F2[faces], len(garment.V2))
        out.append(
            Panel(
                index=p,
                name=name,
                faces=faces,
                vertices=verts,
                mirrored=bool(sa[faces].sum() < 0),
            )
        )
    return out


def with_panel_names(garment: Garment, *, plist: list[Panel] | None = None) -> Garment:
    """The garment with every panel's name written into its groups.

    Geometric names depend on the drape and the frame; once written as groups they stay put
    whatever later steps do to the drape, and later :func:`panels` calls read them cheaply.

    Parameters
    ----------
    garment : Garment
    plist : list of Panel, optional
        ``panels(garment)``, when the caller already has it.

    Returns
    -------
    Garment
        ``face_group`` is each triangle's panel index and ``group_names`` the panel names, so
        ``panels`` of the result lists the same panels under the same names. Its
        derived structure (:mod:`ptailor.model.structure`) reuses what ``garment``'s has
        computed and does not depend on the groups (components, seams, openings, layout).
    """
    pl = panels(garment) if plist is None else plist
    lab = panel_labels(pl, garment.n_faces)
    named = replace(garment, face_group=lab, group_names=tuple(p.name for p in pl))
    # the same cloth (arrays): its derived structure reads what this garment's has computed
    named.cache[SAME_CLOTH] = garment
    return named
