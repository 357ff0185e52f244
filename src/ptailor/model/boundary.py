"""Boundary loops of a triangle mesh, traced deterministically on non-manifold meshes.

Real garment exports are not always manifold: a placket or a pocket sewn onto the middle of
a panel makes drape edges shared by three faces (T-seams), and panels touching at a single
vertex make non-manifold boundary vertices. The rules here:

- a *boundary edge* is an edge used by exactly one face (an edge used by two faces is
  inside the cloth or a seam; one used by three or more faces is a T-seam, sewn, never
  boundary); faces with a repeated vertex are ignored;
- faces sharing an edge are *linked* into one surface across it: always for an edge of two
  faces; for an edge of three or more faces only one pair is linked, the two faces that
  use the same pattern edge (the panel the others are sewn onto) when the pattern is given,
  else the two whose half-planes are the most nearly opposite (the flattest pair) when
  positions are given; the other faces there are *fins* (a strip sewn on);
- the faces around a vertex, linked across their edges, form *fans* (sectors); a fan is a
  path or a cycle of corners, so it touches at most two boundary edges, and the boundary
  continues from one to the other: each sector of a non-manifold (bow-tie) vertex is traced
  separately;
- a boundary edge ending in a fan with no second boundary edge (a fin's corner at a T-seam)
  is *dangling*; dangling ends at one vertex are paired in order of their other vertex and
  a leftover ends an open chain (the free edge of a strip sewn onto a panel's middle);
- a loop visiting a vertex twice is split there into simple loops; loops of fewer than
  three vertices (and chains of fewer than three) are dropped, and so are loops of zero
  length when positions are given.

Everything is a function of the mesh, not of the face order: loops start at their smallest
vertex and run along the majority of their half-edges.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ptailor import tolerances as tol
from ptailor.geometry.topology import edge_groups, edge_keys, half_edges


def _proper(F: np.ndarray) -> np.ndarray:
    """Triangles with three distinct vertices, ``(m', 3)`` int64."""
    F = np.asarray(F, dtype=np.int64).reshape(-1, 3)
    ok = (F[:, 0] != F[:, 1]) & (F[:, 1] != F[:, 2]) & (F[:, 2] != F[:, 0])
    return F[ok]


def boundary_edges(F: np.ndarray) -> np.ndarray:
    """Directed boundary half-edges (edges used by exactly one face).

    Parameters
    ----------
    F : (m, 3) int array
        Triangles; those with a repeated vertex are ignored.

    Returns
    -------
    (b, 2) int array
        Oriented as in their triangle, so a counter-clockwise 2D panel's outer loop runs
        counter-clockwise. Edges of three or more faces (T-seams) are not boundary.
    """
    F = _proper(F)
    h = half_edges(F)
    if len(h) == 0:
        return h
    _, inv, cnt = edge_groups(edge_keys(h))
    return h[cnt[inv] == 1]


def _multi_links(
    h: np.ndarray,
    idx: np.ndarray,
    inv: np.ndarray,
    F: np.ndarray,
    V: np.ndarray | None,
    F2: np.ndarray | None,
) -> np.ndarray:
    """The linked pair at each edge of three or more faces.

    Parameters
    ----------
    h : (3m, 2) int array
        Half-edges of ``F``.
    idx : (q,) int array
        Half-edge ids on edges used by three or more faces, sorted by edge.
    inv : (3m,) int array
        Edge id of each half-edge.
    F : (m, 3) int array
    V : (n, d) float array or None
    F2 : (m, 3) int array or None

    Returns
    -------
    (p, 2) int array
        Half-edge pairs, at most one per edge.
    """
    if len(idx) == 0:
        return np.zeros((0, 2), dtype=np.int64)
    e = inv[idx]
    opp = F[idx // 3, (idx % 3 + 2) % 3]  # the vertex of each face across the edge
    start = np.flatnonzero(np.r_[True, e[1:] != e[:-1]])
    size = np.diff(np.r_[start, len(idx)])
    cmax = int(size.max())
    # candidate pairs (i, j) of half-edges on one edge, i before j in the sorted list
    ci, cj = [], []
    for d in range(1, cmax):  # a loop over offsets (at most the largest edge degree)
        i = np.arange(len(idx) - d)
        same = e[i] == e[i + d]
        ci.append(i[same])
        cj.append(i[same] + d)
    ci, cj = np.concatenate(ci), np.concatenate(cj)
    score = np.zeros(len(ci))  # lower is better
    if F2 is not None:
        k2 = edge_keys(half_edges(F2)[idx], n=int(F2.max()) + 1)
        score -= 4.0 * (k2[ci] == k2[cj])  # one pattern edge: the panel under a T-seam
    if V is not None:
        V = np.asarray(V, dtype=np.float64)
        a, b = V[h[idx, 0]], V[h[idx, 1]]
        t = b - a
        t /= np.maximum(np.linalg.norm(t, axis=1), tol.TINY)[:, None]
        w = V[opp] - a
        w -= (w * t).sum(axis=1)[:, None] * t
        w /= np.maximum(np.linalg.norm(w, axis=1), tol.TINY)[:, None]
        score += (w[ci] * w[cj]).sum(axis=1)  # -1: the two half-planes are opposite (flat)
    elif F2 is None:
        return np.zeros((0, 2), dtype=np.int64)
    # the best pair of each edge; ties by the faces' far vertices (not by face order)
    lo, hi = np.minimum(opp[ci], opp[cj]), np.maximum(opp[ci], opp[cj])
    order = np.lexsort((hi, lo, np.round(score, 12), e[ci]))
    first = order[np.r_[True, e[ci][order][1:] != e[ci][order][:-1]]]
    if F2 is not None and V is None:
        first = first[score[first] < 0]  # without positions only a shared pattern edge links
    return np.stack([idx[ci[first]], idx[cj[first]]], axis=1)


def _pair_ends(ep_vert: np.ndarray, ep_fan: np.ndarray, ep_other: np.ndarray) -> np.ndarray:
    """Partner of each boundary-edge end at its vertex (the next end of the loop), or -1.

    Ends in one fan are partners; ends alone in their fan (dangling) are paired at their
    vertex in the order of their edges' other vertices, a leftover one ends a chain.
    """
    n_ep = len(ep_vert)
    partner = np.full(n_ep, -1, dtype=np.int64)
    order = np.lexsort((ep_other, ep_fan))
    f = ep_fan[order]
    start = np.r_[True, f[1:] != f[:-1]]
    size = np.diff(np.r_[np.flatnonzero(start), n_ep])
    gsize = np.repeat(size, size)
    two = order[(gsize == 2) & start]
    partner[two] = order[np.flatnonzero((gsize == 2) & start) + 1]
    partner[partner[two]] = two
    lone = order[gsize == 1]
    if len(lone):
        o = lone[np.lexsort((ep_other[lone], ep_vert[lone]))]
        v = ep_vert[o]
        gstart = np.flatnonzero(np.r_[True, v[1:] != v[:-1]])
        rank = np.arange(len(o)) - np.repeat(gstart, np.diff(np.r_[gstart, len(o)]))
        nxt_same = np.r_[v[1:] == v[:-1], False]
        a = np.flatnonzero((rank % 2 == 0) & nxt_same)
        partner[o[a]] = o[a + 1]
        partner[o[a + 1]] = o[a]
    return partner


def _orient(seq: np.ndarray, fwd: np.ndarray, closed: bool) -> tuple[np.ndarray, np.ndarray]:
    """A curve in its canonical direction and, closed, its canonical rotation.

    Parameters
    ----------
    seq : (k,) int array
        Vertices in walking order.
    fwd : (k,) bool array for a loop, (k - 1,) for a chain
        Whether the walked edge from ``seq[i]`` to the next vertex runs along its
        half-edge.
    closed : bool

    Returns
    -------
    seq, fwd : arrays as above
        Running along the majority of the half-edges (ties: the lexicographically smaller
        sequence); a loop starts at its smallest vertex (a loop through it twice: the
        lexicographically smallest such rotation). Independent of where the walk started.
    """

    def rev(s: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        if closed:  # s0 s_{k-1} ... s1; edge i of the reversed loop is edge k-1-i reversed
            return np.roll(s[::-1], 1), ~f[::-1]
        return s[::-1], ~f[::-1]

    def rot(s: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        if not closed:
            return s, f
        at = np.flatnonzero(s == s.min())
        if len(at) > 1:  # the lexicographically smallest rotation among those
            R = s[(at[:, None] + np.arange(len(s))[None, :]) % len(s)]
            at = at[np.lexsort(R.T[::-1])[:1]]
        return np.roll(s, -int(at[0])), np.roll(f, -int(at[0]))

    n_fwd, n_bwd = int(fwd.sum()), int((~fwd).sum())
    a = rot(seq, fwd)
    if n_fwd > n_bwd:
        return a
    b = rot(*rev(seq, fwd))
    if n_bwd > n_fwd:
        return b
    d = np.flatnonzero(a[0] != b[0])
    return b if len(d) and b[0][d[0]] < a[0][d[0]] else a


def _simple_parts(seq: np.ndarray, fwd: np.ndarray, closed: bool) -> list[tuple[np.ndarray, bool]]:
    """Split a canonical curve at repeated vertices into simple loops (and one chain).

    Parameters
    ----------
    seq, fwd, closed
        As returned by :func:`_orient`.

    Returns
    -------
    list of (vertices, closed)
        Each canonical (:func:`_orient`). The loop between two visits of a vertex is cut
        off at the first repeated vertex, again and again.
    """
    out: list[tuple[np.ndarray, bool]] = []
    s, f = seq, fwd
    while True:  # a loop over sub-loops
        _, first, cnt = np.unique(s, return_index=True, return_counts=True)
        rep = first[cnt > 1]
        if len(rep) == 0:
            break
        i = int(rep.min())
        j = i + 1 + int(np.flatnonzero(s[i + 1 :] == s[i])[0])
        out.extend((*x, True) for x in _cut(s[i:j], f[i:j]))
        s, f = np.r_[s[:i], s[j:]], np.r_[f[:i], f[j:]]
    out.append((*_orient(s, f, closed), closed))
    return [(p, c) for p, _, c in out]


def _cut(s: np.ndarray, f: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """A closed piece cut off a curve, itself split into simple canonical loops."""
    return [_orient(p, fp, True) for p, fp in _loop_pieces(*_orient(s, f, True))]


def _loop_pieces(s: np.ndarray, f: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """Split a canonical closed loop at repeated vertices (before canonical ordering)."""
    _, first, cnt = np.unique(s, return_index=True, return_counts=True)
    rep = first[cnt > 1]
    if len(rep) == 0:
        return [(s, f)]
    i = int(rep.min())
    j = i + 1 + int(np.flatnonzero(s[i + 1 :] == s[i])[0])
    inner = _loop_pieces(*_orient(s[i:j], f[i:j], True))
    outer = _loop_pieces(*_orient(np.r_[s[:i], s[j:]], np.r_[f[:i], f[j:]], True))
    return inner + outer


def boundary_curves(
    F: np.ndarray,
    *,
    V: np.ndarray | None = None,
    F2: np.ndarray | None = None,
) -> tuple[list[np.ndarray], np.ndarray]:
    """Boundary loops and open chains, traced deterministically (module notes).

    Parameters
    ----------
    F : (m, 3) int array
        Triangles, manifold or not.
    V : (n, d) float array, optional
        Vertex positions: choose the linked pair at edges of three or more faces by
        flatness, and drop zero-length loops.
    F2 : (m, 3) int array, optional
        Pattern triangles (row ``i`` the same cloth as ``F[i]``): at an edge of three or
        more faces, the two faces using one pattern edge are the panel, the others fins.

    Returns
    -------
    curves : list of (k,) int arrays
        Vertex indices in boundary half-edge order (majority), longest first (ties by
        their vertex sequences). A closed loop starts at its smallest vertex and is simple; an open
        chain (the free edge of a strip sewn onto a panel, ending inside the cloth) runs
        from one end to the other.
    closed : (c,) bool array
        Whether each curve is a closed loop.
    """
    F = np.asarray(F, dtype=np.int64).reshape(-1, 3)
    V = None if V is None else np.asarray(V, dtype=np.float64)
    F2 = None if F2 is None else np.asarray(F2, dtype=np.int64).reshape(-1, 3)
    return _trace(F, V, F2)


def _pair_at_vertices(ep_vert: np.ndarray) -> np.ndarray:
    """Partner of each boundary-edge end when every vertex has exactly two ends."""
    o = np.argsort(ep_vert, kind="stable")
    partner = np.empty(len(ep_vert), dtype=np.int64)
    partner[o[0::2]] = o[1::2]
    partner[o[1::2]] = o[0::2]
    return partner


def _end_fans(
    h: np.ndarray,
    order: np.ndarray,
    c: np.ndarray,
    inv: np.ndarray,
    bh: np.ndarray,
    F: np.ndarray,
    V: np.ndarray | None,
    F2: np.ndarray | None,
) -> np.ndarray:
    """The fan (sector of linked corners) of each boundary-edge end, ``(2 * len(bh),)``.

    Parameters
    ----------
    h : (3m, 2) int array
        Half-edges of ``F``.
    order, inv : (3m,) int arrays
        :func:`~ptailor.geometry.topology.edge_groups` of their edge keys.
    c : (3m,) int array
        Faces on each half-edge's edge.
    bh : (b,) int array
        Boundary half-edges.
    F, V, F2
        As in :func:`boundary_curves`.
    """
    from scipy.sparse.csgraph import connected_components

    m = len(F)
    ids = np.arange(3 * m)
    end_corner = 3 * (ids // 3) + (ids % 3 + 1) % 3  # the corner at a half-edge's end
    # links: the two faces of a two-face edge; one pair at edges of three or more faces
    # (half-edges by edge, then by id)
    c_order = c[order]
    two = order[c_order == 2]
    multi = order[c_order >= 3]
    links = np.concatenate([two.reshape(-1, 2), _multi_links(h, multi, inv, F, V, F2)])
    la, lb = links[:, 0], links[:, 1]

    def corner_at(hh: np.ndarray, x: np.ndarray) -> np.ndarray:
        return np.where(h[hh, 0] == x, hh, end_corner[hh])

    a, b = h[la, 0], h[la, 1]
    G = sp.coo_matrix(
        (
            np.ones(2 * len(la)),
            (np.r_[corner_at(la, a), corner_at(la, b)], np.r_[corner_at(lb, a), corner_at(lb, b)]),
        ),
        shape=(3 * m, 3 * m),
    )
    fan = connected_components(G, directed=False)[1]
    return np.stack([fan[bh], fan[end_corner[bh]]], axis=1).ravel()


def _trace(
    F: np.ndarray, V: np.ndarray | None, F2: np.ndarray | None
) -> tuple[list[np.ndarray], np.ndarray]:
    """:func:`boundary_curves` of int64 ``F``, ``F2`` and float ``V`` (or None), traced."""
    from scipy.sparse.csgraph import breadth_first_order, connected_components

    F = np.asarray(F, dtype=np.int64).reshape(-1, 3)
    ok = (F[:, 0] != F[:, 1]) & (F[:, 1] != F[:, 2]) & (F[:, 2] != F[:, 0])
    F = F[ok]
    if F2 is not None:
        F2 = np.asarray(F2, dtype=np.int64).reshape(-1, 3)[ok]
    m = len(F)
    if m == 0:
        return [], np.zeros(0, dtype=bool)
    h = half_edges(F)
    order, inv, cnt = edge_groups(edge_keys(h))
    c = cnt[inv]

    # boundary edge ends: end 2j at the start of boundary half-edge j, end 2j+1 at its end
    bh = np.flatnonzero(c == 1)
    nb = len(bh)
    if nb == 0:
        return [], np.zeros(0, dtype=bool)
    E = h[bh]
    ep_vert = E.ravel()
    if cnt.max() <= 2 and bool((np.bincount(ep_vert)[ep_vert] == 2).all()):
        # no edge of three faces and two ends at every boundary vertex: both lie in one fan
        # (a fan is then a cycle of corners or a path with a boundary edge at each end)
        partner = _pair_at_vertices(ep_vert)
    else:
        ep_fan = _end_fans(h, order, c, inv, bh, F, V, F2)
        partner = _pair_ends(ep_vert, ep_fan, E[:, ::-1].ravel())

    # walk: entering an edge at end p, leave at p ^ 1 and enter the partner's edge
    ep = np.arange(2 * nb)
    succ = partner[ep ^ 1]
    has = succ >= 0
    W = sp.csr_matrix((np.ones(int(has.sum())), (ep[has], succ[has])), shape=(2 * nb, 2 * nb))
    U = sp.csr_matrix((np.ones(int(has.sum())), (ep[has] // 2, succ[has] // 2)), shape=(nb, nb))
    n_comp, comp = connected_components(U, directed=False)
    dangling = partner < 0
    comp_order = np.argsort(comp, kind="stable")
    bounds = np.r_[0, np.cumsum(np.bincount(comp, minlength=n_comp))]

    Vpos = None if V is None else np.asarray(V, dtype=np.float64)
    curves: list[np.ndarray] = []
    closed: list[bool] = []
    for k in range(n_comp):  # a loop over boundary curves
        edges = comp_order[bounds[k] : bounds[k + 1]]
        ends = np.r_[2 * edges, 2 * edges + 1]
        free = ends[dangling[ends]]
        is_closed = len(free) == 0
        start = int(free.min()) if len(free) else int(2 * edges.min())
        walk = breadth_first_order(W, start, directed=True, return_predecessors=False)
        seq = ep_vert[walk]
        fwd = walk % 2 == 0
        if not is_closed:
            seq = np.r_[seq, ep_vert[walk[-1] ^ 1]]
        parts = _simple_parts(*_orient(seq, fwd, is_closed), is_closed)
        for p, cl in parts:
            if len(p) < 3:
                continue
            if Vpos is not None:
                P = Vpos[p]
                seg = np.linalg.norm(np.diff(P, axis=0, append=P[:1] if cl else P[-1:]), axis=1)
                if not seg.sum() > 0.0:
                    continue
            curves.append(p)
            closed.append(cl)
    order = sorted(range(len(curves)), key=lambda i: (-len(curves[i]), curves[i].tolist()))
    return [curves[i] for i in order], np.array([closed[i] for i in order], dtype=bool)


def boundary_loops(
    F: np.ndarray,
    *,
    V: np.ndarray | None = None,
    F2: np.ndarray | None = None,
) -> list[np.ndarray]:
    """Ordered boundary loops.

    Parameters
    ----------
    F : (m, 3) int array
        Triangles, manifold or not (see the module notes for non-manifold vertices and
        edges of three or more faces).
    V, F2 : arrays, optional
        As in :func:`boundary_curves`.

    Returns
    -------
    list of (k,) int arrays
        Vertex indices of each loop in half-edge order, longest loop first; a loop starts at
        its smallest vertex index so the result does not depend on face order. Open chains
        (:func:`boundary_curves`) are included, read as closed by the chord between their
        ends; they only arise at edges of three or more faces.
    """
    return boundary_curves(F, V=V, F2=F2)[0]
