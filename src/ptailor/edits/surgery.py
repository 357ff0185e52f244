"""Surgery: split a garment exactly on the zero level of a scalar field and keep one side.

Shorten and cut both reduce to this. The field lives on drape vertices; every triangle it
crosses is split on the crossing (new vertices on edges, linearly interpolated in the
original drape, the edited drape and the pattern alike), so the kept triangles are unchanged
and the pattern follows by barycentric transfer, as the paper does. A crossing on a seam
edge is one new drape vertex and one new pattern vertex per side.

Distances measured in the pattern live in :mod:`ptailor.edits.pattern_distance`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from ptailor.edits import tolerances as edit_tol
from ptailor.edits.state import EditState
from ptailor.edits.truing import seam_sides, true_cut
from ptailor.errors import PtailorError
from ptailor.geometry.topology import edge_keys
from ptailor.model.garment import CUT_FROM, Garment, panel_labels
from ptailor.model.structure import structure

#: ``crossing(a2, b2, t, face) -> t``, see :func:`split_keep`.
Crossing = Callable[[np.ndarray, np.ndarray, np.ndarray, np.ndarray], np.ndarray]


@dataclass(frozen=True)
class SplitResult:
    """The kept part of a garment and how it relates to the input.

    Attributes
    ----------
    state : EditState
        The new state (base garment, edited drape, panels, outline flags).
    face_parent : (m_new,) int array
        Input triangle each new triangle comes from.
    new_vertices2 : (k,) int array
        Pattern vertices (in the new numbering) created on the zero level: the new edge.
    new_vertices3 : (k3,) int array
        Drape vertices (new numbering) created on the zero level.
    removed_triangles : int
        Input triangles wholly or partly removed.
    split_triangles : int
        Input triangles the zero level crossed.
    edge3 : (k3, 2) int array
        Input drape edge (ends in the input numbering, lower index first) each new drape
        vertex lies on, row for row with ``new_vertices3``.
    t3 : (k3,) float array
        Where on that edge: ``V = (1 - t) V[edge3[:, 0]] + t V[edge3[:, 1]]``.
    on_level3, on_level2 : (j3,) and (j2,) int arrays
        Kept input vertices the zero level passes through (snapped onto it), in the new
        numbering: with the new vertices, they make the new edge.
    source3 : (j3,) int array
        The input drape vertex of each of ``on_level3``.
    """

    state: EditState
    face_parent: np.ndarray
    new_vertices2: np.ndarray
    new_vertices3: np.ndarray
    removed_triangles: int
    split_triangles: int
    edge3: np.ndarray
    t3: np.ndarray
    on_level3: np.ndarray
    on_level2: np.ndarray
    source3: np.ndarray


def _edge_points(
    A: np.ndarray, B: np.ndarray, key: np.ndarray, t: np.ndarray, base: int
) -> tuple[np.ndarray, np.ndarray]:
    """Unique points ``A + t (B - A)`` per edge key; return (new index per row, points)."""
    _, first, inv = np.unique(key, return_index=True, return_inverse=True)
    P = A[first] + t[first, None] * (B[first] - A[first])
    return base + inv, P


def _group_mean(key: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Mean of ``x`` over the rows sharing each row's key, ``(k,)``."""
    _, inv = np.unique(key, return_inverse=True)
    return (np.bincount(inv, x) / np.bincount(inv))[inv]


def _source_name(name: str, old: dict) -> str:
    """The input panel a kept panel came from (a panel cut in two gets a ``_k`` suffix)."""
    return name if name in old else name.rsplit("_", 1)[0]


@dataclass(frozen=True)
class _Cuts:
    """Where the zero level crosses the edges of the split triangles (see :func:`_cut_edges`)."""

    rows: np.ndarray
    other: np.ndarray
    idx3: np.ndarray
    idx2: np.ndarray
    Pbase: np.ndarray
    Pedit: np.ndarray
    P2: np.ndarray
    edge3: np.ndarray
    t3: np.ndarray


def _cut_edges(
    state: EditState,
    R3: np.ndarray,
    R2: np.ndarray,
    RS: np.ndarray,
    fs: np.ndarray,
    *,
    crossing: Crossing | None,
    trued: np.ndarray | None = None,
) -> _Cuts:
    """New vertices where the zero level crosses the split triangles' edges.

    Parameters
    ----------
    state : EditState
    R3, R2 : (r, 3) int arrays
        The split triangles (drape, pattern), rotated so the odd corner comes first.
    RS : (r, 3) float array
        The snapped field at their corners.
    fs : (r,) int array
        Their input triangles.
    crossing : callable or None, keyword-only
        See :func:`split_keep`.
    trued : (n3,) float array or None, keyword-only
        The snapped field on the drape vertices, to true the seams the level crosses
        (:func:`ptailor.edits.truing.true_cut`); None leaves each side where it crosses.

    Returns
    -------
    _Cuts
        Per crossing (split row ``rows``, edge ``other`` 1 or 2): the new drape and pattern
        vertex indices (after the input's), and the new points (original drape, edited
        drape, pattern); per crossed drape edge (lower end first): ``edge3`` and ``t3``.
    """
    g = state.base
    # crossings on the edges (c0, c1) and (c0, c2) where the signs are strictly opposite
    cross1 = RS[:, 0] * RS[:, 1] < 0
    cross2 = RS[:, 0] * RS[:, 2] < 0
    rows = np.concatenate([np.flatnonzero(cross1), np.flatnonzero(cross2)])
    other = np.concatenate([np.ones(cross1.sum(), int), np.full(cross2.sum(), 2)])
    a3, b3 = R3[rows, 0], R3[rows, other]
    a2, b2 = R2[rows, 0], R2[rows, other]
    sa, sb = RS[rows, 0], RS[rows, other]
    t = sa / (sa - sb)
    n3, n2 = len(g.V3), len(g.V2)
    key3 = edge_keys(np.stack([a3, b3], 1))
    # orient t from the lower vertex so duplicates of one edge give the same point
    lo3 = a3 < b3
    t2 = t  # where each side of the pattern is cut
    if crossing is not None:
        lim = edit_tol.SPLIT_SNAP_REL  # no sliver next to a corner
        t2 = np.clip(crossing(a2, b2, t, fs[rows]), lim, 1.0 - lim)
    if trued is not None:
        lim = edit_tol.SPLIT_SNAP_REL
        t2 = true_cut(seam_sides(g), g.V2, trued, a2, b2, t2, sa > 0, margin=lim)
    if crossing is not None:
        tm = _group_mean(key3, np.where(lo3, t2, 1.0 - t2))
        t = np.where(lo3, tm, 1.0 - tm)
    tl = np.where(lo3, t, 1.0 - t)
    A3, B3 = np.where(lo3, a3, b3), np.where(lo3, b3, a3)
    idx3, Pbase = _edge_points(g.V3[A3], g.V3[B3], key3, tl, n3)
    _, first3 = np.unique(key3, return_index=True)
    edge3, t3 = np.stack([A3[first3], B3[first3]], 1), tl[first3]
    _, Pedit = _edge_points(state.V3[A3], state.V3[B3], key3, tl, n3)
    key2 = edge_keys(np.stack([a2, b2], 1))
    lo2 = a2 < b2
    A2, B2 = np.where(lo2, a2, b2), np.where(lo2, b2, a2)
    idx2, P2 = _edge_points(g.V2[A2], g.V2[B2], key2, np.where(lo2, t2, 1.0 - t2), n2)
    return _Cuts(
        rows=rows,
        other=other,
        idx3=idx3,
        idx2=idx2,
        Pbase=Pbase,
        Pedit=Pedit,
        P2=P2,
        edge3=edge3,
        t3=t3,
    )


def _kept_triangles(
    F3: np.ndarray,
    F2: np.ndarray,
    keep_whole: np.ndarray,
    fs: np.ndarray,
    caseA: np.ndarray,
    R3: np.ndarray,
    R2: np.ndarray,
    cuts: _Cuts,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The kept triangles: whole ones, and the kept parts of the split ones.

    A split triangle with one corner on the kept side keeps a triangle (case A), one with
    two keeps a quad, as two triangles (case B).

    Returns
    -------
    parent : (m_new,) int array
        Input triangle of each kept triangle, ascending (the input's order is kept).
    F3n, F2n : (m_new, 3) int arrays
        Drape and pattern triangles (vertex numbering: input, then the cuts').
    """
    rows, other, idx3, idx2 = cuts.rows, cuts.other, cuts.idx3, cuts.idx2
    # new vertex per (split row, edge 1|2)
    x3 = np.full((len(fs), 3), -1)
    x2 = np.full((len(fs), 3), -1)
    x3[rows, other], x2[rows, other] = idx3, idx2
    # case A: keep (c0, c1 or x01, c2 or x02); case B: keep quad (x01, c1, c2, x02)
    pick3 = np.where(x3 >= 0, x3, R3)
    pick2 = np.where(x2 >= 0, x2, R2)
    A_ = np.flatnonzero(caseA)
    B_ = np.flatnonzero(~caseA)
    T3 = [
        pick3[A_],
        np.stack([x3[B_, 1], R3[B_, 1], R3[B_, 2]], 1),
        np.stack([x3[B_, 1], R3[B_, 2], x3[B_, 2]], 1),
    ]
    T2 = [
        pick2[A_],
        np.stack([x2[B_, 1], R2[B_, 1], R2[B_, 2]], 1),
        np.stack([x2[B_, 1], R2[B_, 2], x2[B_, 2]], 1),
    ]
    whole = np.flatnonzero(keep_whole)
    parent = np.concatenate([whole, fs[A_], fs[B_], fs[B_]])
    F3n = np.concatenate([F3[whole], *T3])
    F2n = np.concatenate([F2[whole], *T2])
    order = np.argsort(parent, kind="stable")  # keep the input's triangle order
    parent, F3n, F2n = parent[order], F3n[order], F2n[order]
    return parent, F3n, F2n


def split_keep(
    state: EditState,
    phi: np.ndarray,
    *,
    crossing: Crossing | None = None,
    true_seams: bool = False,
) -> SplitResult:
    """Keep the part of the garment where ``phi >= 0``.

    Parameters
    ----------
    state : EditState
    phi : (n3,) float array
        Field on the drape vertices; triangles it crosses are split on ``phi = 0``. Values
        within ``edit_tol.SPLIT_SNAP_REL`` mean edge lengths of zero snap to zero, so no sliver is
        made next to a vertex.
    crossing : callable, optional, keyword-only
        ``crossing(a2, b2, t, face) -> t``: where each crossed edge is cut, given its
        pattern ends ``a2, b2`` ``(r,)``, the linear estimate ``t`` ``(r,)`` (from ``a2``)
        and the input triangle ``face`` ``(r,)`` it was found in (a field measured in the
        pattern places the cut exactly on its own iso-line, see :func:`refine_crossings`).
        Each pattern edge is cut where ``crossing`` says; a drape edge seen from two
        triangles (a seam, whose two sides are two pattern edges) is cut at the mean of
        its sides' parameters (one new drape vertex, one new pattern vertex per side: the
        sides differ only where their panels meet the iso-line at different angles or the
        seam is eased). Default: the linear estimate, the same on every side.
    true_seams : bool, keyword-only
        Move the cut on the two sides of each seam the level crosses once so that the kept
        sides keep the input's length ratio (:func:`ptailor.edits.truing.true_cut`: sides
        that were equal lose the same length); the drape vertex stays where the field
        (or, with ``crossing``, the mean of the sides) puts it.

    Returns
    -------
    SplitResult

    Raises
    ------
    PtailorError
        When nothing or everything would be removed.
    """
    g = state.base
    s, S, keep_whole, split = _signs(state, phi)
    fs, caseA, R3, R2, RS = _odd_corner_first(g.F3, g.F2, S, split)
    cuts = _cut_edges(state, R3, R2, RS, fs, crossing=crossing, trued=s if true_seams else None)
    parent, F3n, F2n = _kept_triangles(g.F3, g.F2, keep_whole, fs, caseA, R3, R2, cuts)
    n3, n2 = len(g.V3), len(g.V2)
    new_state, used3, used2 = _compacted_state(state, cuts, parent, F3n, F2n, keep_whole)
    map3 = np.cumsum(used3) - 1
    map2 = np.cumsum(used2) - 1
    kept3 = used3[n3:]
    zero3 = np.flatnonzero((s == 0.0) & used3[:n3])
    zero2 = np.unique(F2n[np.isin(F3n, zero3)])  # their pattern copies
    return SplitResult(
        state=new_state,
        face_parent=parent,
        new_vertices2=map2[np.arange(n2, len(used2))[used2[n2:]]],
        new_vertices3=map3[np.arange(n3, len(used3))[kept3]],
        removed_triangles=int((~keep_whole).sum()),
        split_triangles=int(split.sum()),
        edge3=cuts.edge3[kept3],
        t3=cuts.t3[kept3],
        on_level3=map3[zero3],
        on_level2=map2[zero2],
        source3=zero3,
    )


def _signs(
    state: EditState, phi: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The field snapped to zero near zero, and which triangles it keeps or splits.

    Returns
    -------
    s : (n3,) float array
        ``phi`` with values within ``edit_tol.SPLIT_SNAP_REL`` mean edge lengths of 0 set to 0.
    S : (m, 3) float array
        ``s`` at each triangle's corners.
    keep_whole : (m,) bool array
        Triangles with no negative corner.
    split : (m,) bool array
        Triangles with corners of both signs.

    Raises
    ------
    PtailorError
        When nothing or everything would be removed.
    """
    F3 = state.base.F3
    E = state.V3[F3[:, [1, 2, 0]]] - state.V3[F3]
    h = float(np.linalg.norm(E, axis=2).mean())
    s = np.where(np.abs(phi) <= edit_tol.SPLIT_SNAP_REL * h, 0.0, phi)
    S = s[F3]  # (m, 3)
    cp, cn = (S > 0).sum(1), (S < 0).sum(1)
    keep_whole = cn == 0
    split = (cp > 0) & (cn > 0)
    if not np.any(~keep_whole):
        raise PtailorError("the cut does not reach the garment: nothing to remove")
    if not np.any(keep_whole | split):
        raise PtailorError("the cut removes the whole garment")
    return s, S, keep_whole, split


def _odd_corner_first(
    F3: np.ndarray, F2: np.ndarray, S: np.ndarray, split: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The split triangles, rotated so that their odd corner comes first.

    Returns
    -------
    fs : (r,) int array
        The split triangles.
    caseA : (r,) bool array
        The odd corner is the only ``+`` one (else, case B, the only ``-`` one: two ``+``
        corners).
    R3, R2 : (r, 3) int arrays
        Their drape and pattern corners, rotated.
    RS : (r, 3) float array
        The field at the rotated corners.
    """
    # rotate split triangles so the odd corner comes first: the only + corner (case A),
    # or the only - corner (case B: two + corners)
    fs = np.flatnonzero(split)
    caseA = (S[fs] > 0).sum(1) == 1
    odd = np.where(caseA, np.argmax(S[fs] > 0, axis=1), np.argmax(S[fs] < 0, axis=1))
    cyc = (odd[:, None] + np.arange(3)[None]) % 3
    R3 = np.take_along_axis(F3[fs], cyc, axis=1)
    R2 = np.take_along_axis(F2[fs], cyc, axis=1)
    RS = np.take_along_axis(S[fs], cyc, axis=1)
    return fs, caseA, R3, R2, RS


def _compacted_state(
    state: EditState,
    cuts: _Cuts,
    parent: np.ndarray,
    F3n: np.ndarray,
    F2n: np.ndarray,
    keep_whole: np.ndarray,
) -> tuple[EditState, np.ndarray, np.ndarray]:
    """The state of the kept triangles, with the cuts' new vertices, unused vertices dropped.

    Parameters
    ----------
    state : EditState
    cuts : _Cuts
        :func:`_cut_edges`.
    parent : (k,) int array
        Input triangle of each kept one.
    F3n, F2n : (k, 3) int arrays
        Kept triangles on the old vertices followed by the cuts' new ones.
    keep_whole : (m,) bool array

    Returns
    -------
    state : EditState
        Panels rebuilt (:func:`ptailor.model.structure.structure`), a panel that lost
        triangles no longer ``even``, the new pattern vertices outline-free.
    used3, used2 : bool arrays
        Which drape and pattern vertices (old then new) the kept triangles use.
    """
    g = state.base
    n2 = len(g.V2)
    V3b = np.concatenate([g.V3, cuts.Pbase])
    V3e = np.concatenate([state.V3, cuts.Pedit])
    V2n = np.concatenate([g.V2, cuts.P2])
    # compact: drop vertices no kept triangle uses (and keep earlier unreferenced ones out)
    used3 = np.zeros(len(V3b), bool)
    used3[F3n.ravel()] = True
    used2 = np.zeros(len(V2n), bool)
    used2[F2n.ravel()] = True
    map3 = np.cumsum(used3) - 1
    map2 = np.cumsum(used2) - 1
    plist = state.panels
    flab = panel_labels(plist, len(g.F3))
    base = Garment(
        V3=V3b[used3],
        F3=map3[F3n],
        V2=V2n[used2],
        F2=map2[F2n],
        face_group=flab[parent],
        group_names=tuple(p.name for p in plist),
        units=g.units,
        frame=g.frame,
    )
    kept3 = np.flatnonzero(used3)  # each drape vertex's source, -1 for the cuts' new ones
    base.cache[CUT_FROM] = (g, parent, np.where(kept3 < len(g.V3), kept3, -1))
    new_panels = structure(base).panels
    # a panel that lost triangles has an edited outline: it no longer keeps its shape
    touched = np.zeros(len(plist), bool)
    touched[flab[np.flatnonzero(~keep_whole)]] = True
    old_even = {p.name: bool(state.even[p.index]) and not touched[p.index] for p in plist}
    even = np.array([old_even.get(_source_name(q.name, old_even), False) for q in new_panels])
    free = np.zeros(len(V2n), bool)
    if state.outline_free is not None:
        free[:n2] = state.outline_free
    free[n2:] = True
    new_state = replace(
        state,
        base=base,
        V3=V3e[used3],
        panels=new_panels,
        even=even,
        outline_free=free[used2],
    )
    return new_state, used3, used2


def panel_changes(before: EditState, res: SplitResult) -> tuple[dict, list[str]]:
    """What a split did to each panel of ``before``: the fraction of its pattern area
    removed and the panels it became (each with its share of the original's area), for
    the step record; and a warning for a panel that lost more than
    ``edit_tol.SURGERY_REMOVED_WARN`` of its area (a cut sketched too high on a taller garment
    once removed most of two bodice panels and said only ``removed_triangles``).

    Returns
    -------
    panels : dict
        ``{name: {"removed": fraction, "parts": {new name: share}}}`` for the panels the
        split touched (some area removed, or split into several).
    warnings : list of str
    """
    from ptailor import tolerances as tol
    from ptailor.geometry.triangles import signed_areas_2d
    from ptailor.model.garment import panel_labels

    g0, g1 = before.base, res.state.base
    n0 = len(before.panels)
    lab0 = panel_labels(before.panels, g0.n_faces)
    a0 = np.bincount(lab0, np.abs(signed_areas_2d(g0.V2, g0.F2)), n0)
    lab1 = panel_labels(res.state.panels, g1.n_faces)
    area1 = np.abs(signed_areas_2d(g1.V2, g1.F2))
    src = lab0[res.face_parent]  # each new triangle's panel before the split
    kept = np.bincount(src, area1, n0)
    out: dict = {}
    warnings = []
    for p in before.panels:  # a loop over the panels
        i = p.index
        mine = np.flatnonzero(src == i)
        parts = {}
        for q in np.unique(lab1[mine]):
            share = float(area1[mine[lab1[mine] == q]].sum()) / max(float(a0[i]), tol.TINY)
            parts[res.state.panels[int(q)].name] = round(share, 6)
        removed = 1.0 - float(kept[i]) / max(float(a0[i]), tol.TINY)
        if removed > tol.ROUNDING_REL or len(parts) > 1 or list(parts) != [p.name]:
            out[p.name] = {"removed": round(removed, 6), "parts": parts}
        if removed > edit_tol.SURGERY_REMOVED_WARN:
            warnings.append(f"removes {100 * removed:.0f} % of panel {p.name}'s pattern area")
    return out, warnings
