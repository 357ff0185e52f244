"""The panel layout: where each panel sits on the garment, and the name that follows."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ptailor.model import tolerances as model_tol
from ptailor.model.frame import Frame
from ptailor.model.names.measures import (
    OpeningTouch,
    edge_graph,
    inscribed_radius,
    panel_measures,
    pattern_shape,
)
from ptailor.model.names.roles import (
    base_names,
    faces,
    limbs,
    mirror_pairs,
    mirrored_names,
    reasons,
    sides,
    strip_roles,
    strip_shape,
    tiers,
    unique_names,
)
from ptailor.model.openings import Opening, openings


@dataclass(frozen=True)
class PanelLayout:
    """Where each panel sits on the garment, and the name that follows.

    Attributes
    ----------
    names : list of str
        Geometric name per panel, unique.
    role : list of str
        ``body``, ``sleeve``, ``cuff``, ``collar``, ``waistband`` or ``strap``.
    side : list of str
        ``left``, ``right`` or ``centre``.
    face : list of str
        ``front`` or ``back``; ``""`` for a body panel around the body (a tube).
    tier : list of str
        ``""`` (one-tier garment, limbs and strips), ``bodice`` or ``skirt``.
    centroid : (n_p, 3) float array
        Area-weighted 3D centroid per panel in the wearer's frame ``(left, up, front)``,
        relative to the garment's centre (area-weighted mean left and front coordinates, the
        lowest point's height).
    lo, hi : (n_p, 3) float arrays
        Per-panel extents in the same coordinates.
    height : float
        The garment's height along up.
    s0, f0 : float
        The centre line's left and front coordinates (absolute, in the frame).
    h0 : float
        The garment's lowest height (absolute).
    frame : (3, 3) float array
        Rows ``(left, up, front)``.
    openings : list of Opening
    mirror : (n_p,) int array
        Each panel's mirror image across the centre line (a centred panel its own, -1 none
        found): left/right panels whose mirrored centroids and areas match are named alike.
    why : list of str
        Per panel, the rules that named it and the measures they used, in words.
    """

    names: list[str]
    role: list[str]
    side: list[str]
    face: list[str]
    tier: list[str]
    centroid: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    height: float
    s0: float
    f0: float
    h0: float
    frame: np.ndarray
    openings: list[Opening]
    mirror: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    why: list[str] = field(default_factory=list)

    def position(self, p: int) -> str:
        """A short phrase for panel ``p``'s place: side, front/back and height band.

        Returns
        -------
        str
            For example ``"left, back, upper"``: ``left``/``right``/``centre``; ``front`` or
            ``back``, left out when the centroid is within 10 % of the garment's depth of
            the centre; height bands of the garment's height: ``top`` >= 80 %, ``upper`` >=
            55 %, ``middle`` >= 30 %, ``lower`` >= 10 %, else ``bottom``.
        """
        c = self.centroid[p]
        t = c[1] / self.height if self.height > 0 else 0.5
        band = (
            "top"
            if t >= 0.8
            else "upper"
            if t >= 0.55
            else "middle"
            if t >= 0.3
            else "lower"
            if t >= 0.1
            else "bottom"
        )
        depth = float(self.hi[:, 2].max() - self.lo[:, 2].min()) if len(self.hi) else 0.0
        if abs(c[2]) < 0.1 * depth or not self.face[p]:
            return f"{self.side[p]}, {band}"
        return f"{self.side[p]}, {self.face[p]}, {band}"


#: why a garment's panels are ``panel_k``
UNRECOGNISED = (
    "no rule recognised this garment: none of its openings is a neckline, hem, waist, cuff,"
    " top, leg or armhole (check --up and --front)"
)


def recognised(ops: list[Opening]) -> bool:
    """Whether the naming rules recognise a garment: at least one opening has a name."""
    return any(not o.name.startswith("opening_") for o in ops)


def panel_layout(
    V3: np.ndarray,
    F3: np.ndarray,
    F2: np.ndarray,
    face_panel: np.ndarray,
    n_panels: int,
    *,
    frame: Frame,
    opening_list: list[Opening] | None = None,
    V2: np.ndarray | None = None,
) -> PanelLayout:
    """Name every panel from where it sits on the drape.

    Parameters
    ----------
    V3 : (n3, 3) float array
        Drape positions.
    F3, F2 : (m, 3) int arrays
        Drape and pattern triangles.
    face_panel : (m,) int array
        Panel index per triangle, ``0 .. n_panels - 1``.
    n_panels : int
    frame : Frame
        The wearer's axes (``Garment.frame``).
    opening_list : list of Opening, optional
        ``openings(V3, F3, frame=frame, F2=F2)``, when the caller already has it.
    V2 : (n2, 2) float array, optional
        Pattern positions: a strip is one by its pattern's shape (a box mesh's stretched
        seam rows inflate the drape's); without them, by its drape's.

    Returns
    -------
    PanelLayout
        See the module docstring of :mod:`ptailor.model.names` for the rules.
    """
    n_p = int(n_panels)
    R = frame.matrix()
    V3 = np.asarray(V3, dtype=np.float64)
    F3 = np.asarray(F3, dtype=np.int64).reshape(-1, 3)
    lab = np.asarray(face_panel, dtype=np.int64)
    pm = panel_measures(V3, F3, lab, n_p, R)
    graph = edge_graph(V3, F3, F2, lab, n_p)
    ops = openings(V3, F3, frame=frame, F2=F2) if opening_list is None else opening_list
    touches = OpeningTouch(ops, len(V3), graph, n_p)

    L, strip, aspect = _strips(graph.perim, pm.At, V2, F2, lab)
    side, s_rel, centred = sides(pm)
    role = strip_roles(strip, L, centred, touches)
    role, side, limb_side = limbs(role, side, graph.W, centred, s_rel, touches)
    body = np.array([r == "body" for r in role])
    tier = tiers(body, touches, ops, pm)
    face = faces(body, tier, centred, pm)
    base = base_names(role, side, face, tier, limb_side, pm.cen_abs)
    origin = np.array([pm.s0, pm.h0, pm.f0])
    rel = pm.cen_abs - origin
    ext = pm.hi_abs - pm.lo_abs
    names, mirror = _mirrored_names(base, side, pm.At, rel, ext, np.abs(s_rel))
    why = reasons(pm, aspect, strip, role, side, face, tier, s_rel, touches)
    if not recognised(ops):  # no rule knows this garment: plain names, never a wrong role
        names = [f"panel_{p}" for p in range(n_p)]
        why = [UNRECOGNISED] * n_p
    return PanelLayout(
        names=names,
        role=role,
        side=side,
        face=face,
        tier=tier,
        **_positions(pm),
        frame=R,
        openings=ops,
        mirror=mirror,
        why=why,
    )


def moved_layout(
    source: PanelLayout,
    V3: np.ndarray,
    F3: np.ndarray,
    face_panel: np.ndarray,
    *,
    opening_list: list[Opening],
) -> PanelLayout:
    """The layout ``source`` of a garment, on the same cloth draped as ``V3``.

    An edit that moves the drape but keeps its triangles keeps what each panel is: its name,
    role, side, face, tier and mirror image are ``source``'s (a sleeve widened 40 % is still
    the sleeve; a skirt shortened to a peplum keeps its name), so measures taken before and
    after an edit read the same panels and openings. The positions (centroids, extents,
    height, centre line) are measured on ``V3``.

    Parameters
    ----------
    source : PanelLayout
        :func:`panel_layout` of the garment before the move.
    V3 : (n3, 3) float array
        The moved drape (the same vertices).
    F3 : (m, 3) int array
    face_panel : (m,) int array
        Panel index per triangle, as ``source`` read it.
    opening_list : list of Opening
        The moved openings (:func:`ptailor.model.openings.moved_openings`).

    Returns
    -------
    PanelLayout
    """
    n_p = len(source.names)
    pm = panel_measures(np.asarray(V3, dtype=np.float64), F3, face_panel, n_p, source.frame)
    return replace(source, **_positions(pm), openings=opening_list)


def descended_layout(
    source: PanelLayout,
    source_face_panel: np.ndarray,
    V3: np.ndarray,
    F3: np.ndarray,
    face_panel: np.ndarray,
    n_panels: int,
    face_parent: np.ndarray,
    *,
    opening_list: list[Opening],
) -> PanelLayout:
    """The layout of a garment cut from another (triangles removed, edges split): each
    panel is what the source panel most of its triangles came from was (a front cut in two
    by a V neckline is two pieces of the front, not two straps); positions are measured on
    ``V3``.

    Parameters
    ----------
    source : PanelLayout
        The source garment's layout.
    source_face_panel : (m0,) int array
        The source garment's panel per triangle.
    V3 : (n3, 3) float array
    F3 : (m, 3) int array
    face_panel : (m,) int array
        The cut garment's panel per triangle, ``0 .. n_panels - 1``.
    n_panels : int
    face_parent : (m,) int array
        Each triangle's source triangle.
    opening_list : list of Opening
        The cut garment's openings (:func:`ptailor.model.openings.descended_openings`).

    Returns
    -------
    PanelLayout
        Names the source's, a second piece of one source panel ``<name>_<k>``; ``mirror``
        where both a panel's source and that source's mirror image have one piece each.
    """
    n_p = int(n_panels)
    lab = np.asarray(face_panel, dtype=np.int64)
    src_of = np.asarray(source_face_panel, dtype=np.int64)[np.asarray(face_parent)]
    votes = np.zeros((n_p, len(source.names)), dtype=np.int64)
    np.add.at(votes, (lab, src_of), 1)
    src = votes.argmax(axis=1) if n_p else np.zeros(0, dtype=np.int64)
    count = np.bincount(src, minlength=len(source.names))
    seen: dict[int, int] = {}
    names = []
    for p in range(n_p):  # a loop over the panels (a few dozen at most)
        k = seen[int(src[p])] = seen.get(int(src[p]), 0) + 1
        names.append(source.names[src[p]] if k == 1 else f"{source.names[src[p]]}_{k}")
    mirror = np.full(n_p, -1, dtype=np.int64)
    one = count[src] == 1
    piece_of = {int(src[p]): p for p in range(n_p) if one[p]}
    for p in range(n_p):  # a loop over the panels
        m = int(source.mirror[src[p]]) if len(source.mirror) else -1
        if one[p] and m >= 0 and m in piece_of:
            mirror[p] = piece_of[m]
    R = source.frame
    pm = panel_measures(np.asarray(V3, dtype=np.float64), F3, lab, n_p, R)
    pick = [int(k) for k in src]
    return PanelLayout(
        names=names,
        role=[source.role[k] for k in pick],
        side=[source.side[k] for k in pick],
        face=[source.face[k] for k in pick],
        tier=[source.tier[k] for k in pick],
        **_positions(pm),
        frame=R,
        openings=opening_list,
        mirror=mirror,
        why=[f"{source.why[k]} (the panel it was cut from)" if source.why else "" for k in pick],
    )


def _positions(pm) -> dict:
    """A layout's positions from :func:`panel_measures`' ``pm``: centroids and extents
    relative to the garment's centre, its height, the centre line and the lowest height."""
    origin = np.array([pm.s0, pm.h0, pm.f0])
    return {
        "centroid": pm.cen_abs - origin,
        "lo": pm.lo_abs - origin,
        "hi": pm.hi_abs - origin,
        "height": pm.H,
        "s0": pm.s0,
        "f0": pm.f0,
        "h0": pm.h0,
    }


def _strips(
    perim: np.ndarray, At: np.ndarray, V2: np.ndarray | None, F2: np.ndarray, lab: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The strip test, on the pattern's shape where given, else the drape's.

    Parameters
    ----------
    perim, At : (n_p,) float arrays
        The drape's panel outline lengths and areas.
    V2 : (n2, 2) float array or None
    F2 : (m, 3) int array
    lab : (m,) int array

    Returns
    -------
    L : (n_p,) float array
        The drape's long side (for the lengths along openings).
    strip : (n_p,) bool array
    aspect : (n_p,) float array
        The length/width the test read.
    """
    L, strip = strip_shape(perim, At)
    aspect = L * L / np.maximum(At, 1e-300)
    if V2 is not None:  # length / width of the pattern: area over the widest width squared
        area2, _ = pattern_shape(V2, F2, lab, len(At))
        r = inscribed_radius(V2, F2, lab, len(At))
        aspect = area2 / np.maximum(4.0 * r * r, 1e-300)
        strip = aspect >= model_tol.NAMES_STRIP_ASPECT
    return L, strip, aspect


def _mirrored_names(
    base: list[str],
    side: list[str],
    area: np.ndarray,
    rel: np.ndarray,
    ext: np.ndarray,
    s_abs: np.ndarray,
) -> tuple[list[str], np.ndarray]:
    """Unique panel names, mirror images named alike, and each panel's mirror image.

    Parameters
    ----------
    base : list of str
        The role names (:func:`~ptailor.model.names.roles.base_names`).
    side : list of str
    area : (n_p,) float array
        Panel areas.
    rel, ext : (n_p, 3) float arrays
        Centroids relative to the garment's centre, and extents.
    s_abs : (n_p,) float array
        Distance of each centroid from the centre line.

    Returns
    -------
    names : list of str
    mirror : (n_p,) int array
        A centred panel's own index, a paired panel's partner, else -1.
    """
    n_p = len(side)
    pairs = mirror_pairs(rel, area, ext, side)
    mirror = np.full(n_p, -1, dtype=np.int64)
    mirror[[p for p in range(n_p) if side[p] == "centre"]] = [
        p for p in range(n_p) if side[p] == "centre"
    ]
    for p, q in pairs:
        mirror[p], mirror[q] = q, p
    # a panel and its mirror image are told apart from others by their shared place: the
    # means of the one's measures and the other's mirrored (mirror names, whichever side
    # the last bits of an asymmetric mesh fall on)
    img = np.where(mirror >= 0, mirror, np.arange(n_p))
    flip = np.array([-1.0, 1.0, 1.0])
    rel_s = np.where((img == np.arange(n_p))[:, None], rel, (rel + rel[img] * flip) / 2.0)
    names = unique_names(
        base, (area + area[img]) / 2.0, rel_s, (ext + ext[img]) / 2.0, (s_abs + s_abs[img]) / 2.0
    )
    return mirrored_names(names, pairs), mirror
