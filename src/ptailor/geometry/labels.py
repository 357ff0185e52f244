"""Labels of triangles and vertices: connected components, and labels scattered from sets."""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np
import scipy.sparse as sp


def used_indices(idx: np.ndarray, n: int) -> np.ndarray:
    """The distinct indices in ``idx``, ascending (``np.unique(idx)`` in linear time).

    Parameters
    ----------
    idx : int array, any shape
        Indices in ``0 .. n - 1`` (the vertices triangles use).
    n : int
        A bound on the indices.

    Returns
    -------
    (k,) int array

    Examples
    --------
    >>> used_indices(np.array([[4, 1, 2], [2, 1, 0]]), 6)
    array([0, 1, 2, 4])
    """
    idx = np.asarray(idx)
    mask = np.zeros(int(n), dtype=bool)
    mask[idx.ravel()] = True
    return np.flatnonzero(mask).astype(idx.dtype, copy=False)


def component_labels(F: np.ndarray, n: int) -> np.ndarray:
    """Label triangles by the connected component of the vertices they use.

    Parameters
    ----------
    F : (m, 3) int array
    n : int
        Number of vertices.

    Returns
    -------
    (m,) int array
        Component label per triangle, numbered in order of first appearance.

    Examples
    --------
    >>> component_labels(np.array([[3, 4, 5], [0, 1, 2], [5, 4, 6]]), 7)
    array([0, 1, 0])
    """
    from scipy.sparse.csgraph import connected_components  # (imports scipy.sparse.linalg)

    m = len(F)
    if m == 0:
        return np.zeros(0, dtype=np.int64)
    F = np.asarray(F)
    # two edges of each triangle connect its three vertices (no incidence product needed)
    G = sp.coo_matrix(
        (np.ones(2 * m), (np.r_[F[:, 0], F[:, 1]], np.r_[F[:, 1], F[:, 2]])), shape=(n, n)
    )
    _, vlab = connected_components(G, directed=False)
    flab = vlab[F[:, 0]]
    # renumber by first appearance so labels are stable under vertex renumbering
    # (the first face of each label: the stable sort's first of each run)
    srt = np.argsort(flab, kind="stable")
    s = flab[srt]
    first = srt[np.r_[True, s[1:] != s[:-1]]]
    order = np.argsort(first)
    # sized for every vertex component: unused vertices make components no face has
    remap = np.empty(int(vlab.max()) + 1, dtype=np.int64)
    remap[flab[first[order]]] = np.arange(order.size)
    return remap[flab]


def scatter_labels(
    sets: Iterable[np.ndarray], n: int, *, labels: Sequence[int] | None = None, fill: int = -1
) -> np.ndarray:
    """One label per element from sets of element indices.

    Parameters
    ----------
    sets : iterable of (k_i,) int arrays
        Indices of the elements of each set (a panel's triangles or vertices).
    n : int
        Number of elements.
    labels : sequence of int, optional
        The label of each set; by default its position ``0, 1, ...``.
    fill : int
        Label of elements in no set.

    Returns
    -------
    (n,) int array
        An element in several sets takes the last one's label.

    Examples
    --------
    >>> scatter_labels([np.array([0, 2]), np.array([3])], 5)
    array([ 0, -1,  0,  1, -1])
    >>> scatter_labels([np.array([1])], 3, labels=[7])
    array([-1,  7, -1])
    """
    out = np.full(n, fill, dtype=np.int64)
    for k, idx in enumerate(sets):  # a loop over sets, not elements
        out[idx] = k if labels is None else labels[k]
    return out
