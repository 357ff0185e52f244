"""Pieces drawn from the triangulated pattern, for panels no CAD piece outlines.

A panel's outline is its outer boundary loop; its turn points are the outline's corners,
its notches mark where the panel across the seam changes (and the middle of every seam, by
length in the drape), and its grain line follows the body part the panel wraps, read off
the drape.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ptailor import tolerances as tol
from ptailor.geometry.pattern_maps import least_squares_preimages, pattern_jacobians
from ptailor.geometry.topology import edge_keys, half_edges
from ptailor.geometry.triangles import signed_areas_2d, triangle_areas
from ptailor.geometry.tube_axis import tube_axis
from ptailor.model.boundary import boundary_loops
from ptailor.model.frame import Frame
from ptailor.model.garment import Panel, panel_labels
from ptailor.model.pieces import Piece
from ptailor.model.polyline import corners, signed_area
from ptailor.model.seams import seam_halfedges


def outer_loop(F2: np.ndarray, faces: np.ndarray, V2: np.ndarray) -> np.ndarray:
    """The panel's outer boundary loop (largest enclosed area), counter-clockwise.

    Parameters
    ----------
    F2 : (m, 3) int array
        The pattern's triangles.
    faces : (j,) int array
        The panel's triangles (rows of ``F2``).
    V2 : (n, 2) float array
        The pattern's vertices, which decide which loop is outermost.

    Returns
    -------
    (k,) int array
        Vertex indices into ``V2``.
    """
    return _outermost(boundary_loops(F2[faces]), V2)


def _outermost(loops: list[np.ndarray], V2: np.ndarray) -> np.ndarray:
    """The loop enclosing the largest area, counter-clockwise (empty when there is none)."""
    if not loops:
        return np.zeros(0, dtype=np.int64)
    areas = np.array([signed_area(V2[lp]) for lp in loops])  # a loop over loops, not vertices
    k = int(np.argmax(np.abs(areas)))
    return loops[k] if areas[k] > 0 else loops[k][::-1]


def _edge_partners(F2: np.ndarray, F3: np.ndarray | None, panel_list: list[Panel], pairs=None):
    """Sorted 2D edge keys of the pattern's half-edges and the panel across each (or -1);
    ``pairs``: ``seam_halfedges(F3, F2)`` when a cache has it."""
    m = len(F2)
    keys = edge_keys(half_edges(F2), n=int(F2.max(initial=0)) + 1)
    partner = np.full(3 * m, -1, dtype=np.int64)
    if F3 is not None and m:
        face = np.repeat(np.arange(m), 3)
        flab = panel_labels(panel_list, m)
        pairs = seam_halfedges(F3, F2) if pairs is None else pairs
        partner[pairs[:, 0]] = flab[face[pairs[:, 1]]]
        partner[pairs[:, 1]] = flab[face[pairs[:, 0]]]
    order = np.argsort(keys, kind="stable")
    return keys[order], partner[order]


def grain_directions(
    V2: np.ndarray,
    F2: np.ndarray,
    V3: np.ndarray,
    F3: np.ndarray,
    panel_list: list[Panel],
    *,
    frame: Frame,
) -> np.ndarray:
    """Each panel's lengthwise grain in the pattern, read off the drape.

    The grain runs along the body part the panel wraps: the axis of a tube-like panel (a
    sleeve, a torso or skirt panel: the direction its normals avoid, as ``axis: auto``
    finds it), or the body's ``up`` for a panel too flat to have one. It is mapped into the
    pattern through each triangle's 2D-to-3D map (the least-squares preimage) and averaged
    over the panel by area, pointing up the body where the axis has an up component.

    Parameters
    ----------
    V2 : (n2, 2) float array
        The pattern.
    F2 : (m, 3) int array
        Its triangles.
    V3 : (n3, 3) float array
        The drape.
    F3 : (m, 3) int array
        Its triangles, row for row the same cloth as ``F2``.
    panel_list : list of Panel
    frame : Frame
        The garment's frame (its up is the body's).

    Returns
    -------
    (n_panels, 2) float array
        Unit directions; ``(0, 1)`` where the drape says nothing (a degenerate panel).
    """
    n = len(panel_list)
    flab = panel_labels(panel_list, len(F2))
    axes = np.empty((n, 3))
    for p in panel_list:  # a loop over panels: each one's normal tensor
        axes[p.index] = _panel_axis(V3, F3, p.faces, frame)
    J, ok = pattern_jacobians(V3, F3, V2, F2)
    sol, good = least_squares_preimages(J, axes[flab], ok)
    norm = np.linalg.norm(sol, axis=1)
    good &= norm > 0
    unit = np.where(good[:, None], sol / np.where(good, norm, 1.0)[:, None], 0.0)
    a3 = triangle_areas(V3, F3)
    g = np.stack([np.bincount(flab, a3 * unit[:, k], n) for k in range(2)], 1)
    length = np.linalg.norm(g, axis=1)
    out = np.tile([0.0, 1.0], (n, 1))
    has = length > 0
    out[has] = g[has] / length[has, None]
    return out


def _panel_axis(V3: np.ndarray, F3: np.ndarray, faces: np.ndarray, frame: Frame) -> np.ndarray:
    """A panel's tube axis (the direction its normals avoid), else the frame's up; pointing
    up."""
    up = frame.matrix()[1]
    axis = tube_axis(V3, F3[faces])
    ax = up if axis is None else axis
    s = float(ax @ up)
    return ax * (-1.0 if s < -tol.ROUNDING_REL else 1.0)


def mesh_pieces(
    V2: np.ndarray,
    F2: np.ndarray,
    panel_list: list[Panel],
    *,
    F3: np.ndarray | None = None,
    V3: np.ndarray | None = None,
    grain: np.ndarray | None = None,
    loops: Callable[[Panel], list[np.ndarray]] | None = None,
    seam_pairs: np.ndarray | None = None,
) -> list[Piece]:
    """Pieces drawn from a triangulated pattern: outline, turn points, notches, grain line.

    The outline is each panel's outer boundary (counter-clockwise), holes become internal
    lines (closed), turn points are where the outline turns by more than
    ``tolerances.CORNER_DEG``. With the drape's triangles ``F3``, a notch marks each point
    of the outline (other than a turn point) where the panel across the seam changes, or a
    seam ends: the match points for sewing; with the drape ``V3`` too, a balance notch marks
    the middle of every seam (by length in the drape, so both sides' notches meet when
    sewn). The grain line runs through the panel's centroid along ``grain`` (default the
    pattern's y axis), across half the panel.

    Parameters
    ----------
    V2 : (n, 2) float array
    F2 : (m, 3) int array
    panel_list : list of Panel
    F3 : (m, 3) int array, optional
        The drape's triangles, for seam notches.
    V3 : (n3, 3) float array, optional
        The drape, for balance notches (with ``F3``).
    grain : (n_panels, 2) float array, optional
        Unit grain direction per panel (:func:`grain_directions`).
    loops : callable, optional
        ``loops(panel)``: the panel's boundary loops, ``boundary_loops(F2[panel.faces])``,
        when a cache has them (:meth:`ptailor.model.structure.GarmentStructure.panel_loops`);
        computed here otherwise.
    seam_pairs : (s, 2) int array, optional
        ``seam_halfedges(F3, F2)`` when a cache has it
        (:attr:`ptailor.model.structure.GarmentStructure.seam_halfedges`).

    Returns
    -------
    list of Piece
    """
    keys, partner = _edge_partners(F2, F3, panel_list, seam_pairs)
    n_v = int(F2.max(initial=0)) + 1
    to3 = np.zeros(n_v, dtype=np.int64)
    if F3 is not None:
        to3[F2.ravel()] = F3.ravel()  # pattern vertex -> drape vertex
    out = []
    areas = signed_areas_2d(V2, F2)
    for p in panel_list:  # a loop over panels
        lps = loops(p) if loops is not None else boundary_loops(F2[p.faces])
        outer = _outermost(lps, V2)
        P = V2[outer]
        turn = corners(P)
        ek = edge_keys(np.stack([outer, np.roll(outer, -1)], axis=1), n=n_v)
        across = partner[np.minimum(np.searchsorted(keys, ek), len(keys) - 1)]
        notch = (across != np.roll(across, 1)) & ~turn
        balance = np.zeros((0, 2))
        if V3 is not None and F3 is not None:
            balance = _balance_notches(P, outer, across, to3, V3)
        a = np.abs(areas[p.faces])
        c = (V2[F2[p.faces]].mean(axis=1) * a[:, None]).sum(axis=0) / max(a.sum(), tol.TINY)
        gd = np.array([0.0, 1.0]) if grain is None else grain[p.index]
        half = 0.25 * float(np.ptp(P @ gd))
        holes = tuple(np.vstack([V2[lp], V2[lp[:1]]]) for lp in lps if len(lp) != len(outer))
        out.append(
            Piece(
                name=p.name,
                outline=P,
                turn=turn,
                notches=np.vstack([P[notch], balance]),
                notch_angles=np.zeros(int(notch.sum()) + len(balance)),
                grain=np.stack([c - half * gd, c + half * gd]),
                internal=holes,
            )
        )
    return out


def _balance_notches(
    P: np.ndarray, loop: np.ndarray, across: np.ndarray, to3: np.ndarray, V3: np.ndarray
) -> np.ndarray:
    """The middle (by drape length) of each seam run along an outline, ``(k, 2)``.

    ``across[i]`` is the panel across outline edge ``i`` (``loop[i] -> loop[i + 1]``), -1
    on a free edge; a run of one partner is one seam. Runs of fewer than
    ``BALANCE_MIN_EDGES`` edges get none.
    """
    k = len(loop)
    change = np.flatnonzero(across != np.roll(across, 1))
    if len(change) == 0:
        return np.zeros((0, 2))
    order = np.roll(np.arange(k), -int(change[0]))  # start at a run boundary
    lab = across[order]
    run = np.cumsum(lab != np.roll(lab, 1)) - 1
    run[0] = 0
    a3, b3 = V3[to3[loop[order]]], V3[to3[loop[np.roll(order, -1)]]]
    length = np.linalg.norm(b3 - a3, axis=1)
    out = []
    for r in np.unique(run[lab >= 0]).tolist():  # a loop over the seams of one panel
        idx = np.flatnonzero(run == r)
        if len(idx) < tol.BALANCE_MIN_EDGES:
            continue
        cum = np.cumsum(length[idx])
        half = 0.5 * cum[-1]
        j = int(np.searchsorted(cum, half))
        before = cum[j] - length[idx[j]]
        t = (half - before) / max(length[idx[j]], tol.TINY)
        e = order[idx[j]]
        out.append((1 - t) * P[e] + t * P[(e + 1) % k])
    return np.array(out).reshape(-1, 2)
