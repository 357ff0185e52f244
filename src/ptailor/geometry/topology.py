"""Mesh topology over a triangle list ``F``: half-edges, undirected edge keys, edge groups.

Pure functions of integer arrays; every module that walks edges (seams, boundaries,
openings, repair, the edits) shares these.
"""

from __future__ import annotations

import numpy as np


def half_edges(F: np.ndarray) -> np.ndarray:
    """Directed half-edges of a triangle list.

    Parameters
    ----------
    F : (m, 3) int array

    Returns
    -------
    (3m, 2) int array
        Row ``3 * i + k`` is the edge from corner ``k`` to corner ``k + 1`` of triangle ``i``.
    """
    return np.stack([F, np.roll(F, -1, axis=1)], axis=2).reshape(-1, 2)


def edge_keys(E: np.ndarray, *, n: int | None = None) -> np.ndarray:
    """One int64 key per undirected edge, equal for ``(a, b)`` and ``(b, a)``.

    Parameters
    ----------
    E : (k, 2) int array
    n : int, optional
        A bound on the vertex indices (all below it). Keys of different edge lists are
        comparable only when made with the same ``n``; default ``E.max() + 1``.

    Returns
    -------
    (k,) int64 array
    """
    lo, hi = np.minimum(E[:, 0], E[:, 1]), np.maximum(E[:, 0], E[:, 1])
    base = int(E.max(initial=0)) + 1 if n is None else int(n)
    return lo.astype(np.int64) * base + hi


def edge_groups(keys: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Group equal keys with one stable sort.

    The same groups as ``np.unique(keys, return_inverse=True, return_counts=True)`` and the
    sorting order, at a fraction of its time on half-edge keys (a stable sort runs fast on
    keys of a mesh whose faces come in order).

    Parameters
    ----------
    keys : (k,) int array

    Returns
    -------
    order : (k,) int array
        Indices sorting ``keys``; equal keys in ascending index order.
    inv : (k,) int array
        Group of each key: the rank of its value among the distinct values.
    cnt : (g,) int array
        Size of each group.

    Examples
    --------
    >>> order, inv, cnt = edge_groups(np.array([7, 3, 7, 5]))
    >>> order.tolist(), inv.tolist(), cnt.tolist()
    ([1, 3, 0, 2], [2, 0, 2, 1], [1, 1, 2])
    """
    keys = np.asarray(keys)
    k = len(keys)
    order = np.argsort(keys, kind="stable")
    s = keys[order]
    new = np.ones(k, dtype=bool)
    np.not_equal(s[1:], s[:-1], out=new[1:])
    inv = np.empty(k, dtype=np.intp)
    inv[order] = np.cumsum(new) - 1
    cnt = np.diff(np.append(np.flatnonzero(new), k))
    return order, inv, cnt


def loop_halfedges(F3: np.ndarray, loop: np.ndarray) -> np.ndarray:
    """Half-edge ids (``3 * face + corner``) of the triangles along a boundary loop.

    Parameters
    ----------
    F3 : (m, 3) int array
    loop : (k,) int array
        Ordered vertex indices of a closed loop of boundary edges.

    Returns
    -------
    (j,) int array
        The half-edges whose two ends are consecutive on the loop (either direction).
    """
    h = half_edges(F3)
    nxt = np.roll(loop, -1)
    n = int(F3.max()) + 1
    on = np.zeros(n, dtype=bool)
    on[loop] = True
    cand = np.flatnonzero(on[h[:, 0]] & on[h[:, 1]])  # both ends on the loop
    key = h[cand, 0].astype(np.int64) * n + h[cand, 1]
    fwd = loop.astype(np.int64) * n + nxt
    bwd = nxt.astype(np.int64) * n + loop
    return cand[np.isin(key, fwd) | np.isin(key, bwd)]
