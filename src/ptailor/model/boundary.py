"""Boundary loops of a triangle mesh."""

from __future__ import annotations

import numpy as np

from ptailor.model.seams import edge_keys, half_edges


def boundary_edges(F: np.ndarray) -> np.ndarray:
    """Directed boundary half-edges (those whose twin is missing).

    Parameters
    ----------
    F : (m, 3) int array

    Returns
    -------
    (b, 2) int array
        Oriented as in their triangle, so a counter-clockwise 2D panel's outer loop runs
        counter-clockwise.
    """
    h = half_edges(F)
    _, inv, cnt = np.unique(edge_keys(h), return_inverse=True, return_counts=True)
    return h[cnt[inv] == 1]


def boundary_loops(F: np.ndarray) -> list[np.ndarray]:
    """Ordered boundary loops.

    Parameters
    ----------
    F : (m, 3) int array
        A manifold (edge-manifold on the boundary) triangle mesh.

    Returns
    -------
    list of (k,) int arrays
        Vertex indices of each loop in half-edge order, longest loop first; a loop starts at
        its smallest vertex index so the result does not depend on face order.
    """
    E = boundary_edges(F)
    if len(E) == 0:
        return []
    # successor map; a non-manifold boundary vertex keeps one successor (the first seen)
    n = int(F.max()) + 1
    nxt = np.full(n, -1, dtype=np.int64)
    nxt[E[::-1, 0]] = E[::-1, 1]
    # label loops by pointer jumping: each vertex learns the minimum vertex on its loop
    on = np.zeros(n, dtype=bool)
    on[E[:, 0]] = True
    verts = np.flatnonzero(on)
    succ = np.where(nxt[verts] >= 0, nxt[verts], verts)
    pos = np.full(n, -1, dtype=np.int64)
    pos[verts] = np.arange(len(verts))
    succ_local = pos[succ]
    succ_local = np.where(succ_local >= 0, succ_local, np.arange(len(verts)))
    low = verts.copy()
    jump = succ_local.copy()
    for _ in range(int(np.ceil(np.log2(max(len(verts), 2)))) + 1):
        low = np.minimum(low, low[jump])
        jump = jump[jump]
    # list ranking: steps from the loop's smallest vertex, by pointer jumping on predecessors
    pred = np.empty(len(verts), dtype=np.int64)
    pred[succ_local] = np.arange(len(verts))
    is_start = low == verts
    pred = np.where(is_start, np.arange(len(verts)), pred)
    rank = np.where(is_start, 0, 1).astype(np.int64)
    for _ in range(int(np.ceil(np.log2(max(len(verts), 2)))) + 1):
        rank = rank + rank[pred]
        pred = pred[pred]
    order = np.lexsort((rank, low))
    cuts = np.flatnonzero(np.diff(low[order])) + 1
    loops = [verts[g] for g in np.split(order, cuts)]
    loops.sort(key=lambda a: (-len(a), int(a[0])))
    return loops
