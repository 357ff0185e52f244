"""Outward normals of a drape for ``loosen``: consistent orientation across seams, and
their smoothing by implicit diffusion."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.sparse as sp

from ptailor import tolerances as tol
from ptailor.edits import tolerances as edit_tol
from ptailor.edits.region import region_axis, region_centroid
from ptailor.geometry.topology import half_edges
from ptailor.geometry.triangles import triangle_areas, triangle_normals
from ptailor.method.deform import cotangent_weights
from ptailor.method.solver import factor
from ptailor.model.garment import Panel, panel_labels
from ptailor.model.seams import seam_halfedges


def panel_orientation(
    F3: np.ndarray, F2: np.ndarray, plist: list[Panel], *, pairs: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Flips that orient the drape triangles of all panels consistently.

    Within a panel the drape triangles are consistently oriented because its pattern
    triangles are. Across a seam two panels agree when the shared drape edge runs in
    opposite directions in their two triangles; each pair of panels takes the majority of
    its seam edges, and the flips are propagated breadth first over the panel graph.

    Parameters
    ----------
    F3, F2 : (m, 3) int arrays
    plist : list of Panel
    pairs : (k, 2) int array, optional, keyword-only
        :func:`ptailor.model.seams.seam_halfedges` of ``F3, F2`` when already known (the
        garment's structure holds them); computed otherwise.

    Returns
    -------
    sign : (n_panels,) float array
        ``+1`` or ``-1`` per panel; the first panel of each group keeps ``+1``.
    group : (n_panels,) int array
        Connected groups of panels (joined by seams).
    """
    n_p = len(plist)
    fp = panel_labels(plist, len(F3))
    pairs = seam_halfedges(F3, F2) if pairs is None else pairs
    h3 = half_edges(F3)
    pa, pb = fp[pairs[:, 0] // 3], fp[pairs[:, 1] // 3]
    agree = np.where(h3[pairs[:, 0], 0] == h3[pairs[:, 1], 0], -1.0, 1.0)
    other = pa != pb
    link = sp.coo_matrix((agree[other], (pa[other], pb[other])), shape=(n_p, n_p)).tocsr()
    votes = np.sign((link + link.T).toarray())
    pairs_p = sp.coo_matrix((np.ones(int(other.sum())), (pa[other], pb[other])), shape=(n_p, n_p))
    graph = sp.csr_matrix((pairs_p + pairs_p.T) > 0)
    from scipy.sparse.csgraph import breadth_first_order, connected_components

    _, group = connected_components(graph, directed=False)
    sign = np.zeros(n_p)
    for start in range(n_p):  # loops over panels, not triangles
        if sign[start]:
            continue
        order, pred = breadth_first_order(graph, start, directed=False)
        sign[start] = 1.0
        for p in order[1:]:
            sign[p] = sign[pred[p]] * (votes[pred[p], p] or 1.0)
    return sign, group


def outward_normals(
    V: np.ndarray,
    F3: np.ndarray,
    F2: np.ndarray,
    plist: list[Panel],
    *,
    pairs: np.ndarray | None = None,
) -> np.ndarray:
    """Outward, area-weighted unit vertex normals of a drape.

    Triangles are oriented consistently (:func:`panel_orientation`); then each connected
    group of panels is turned so that its normals point away from the garment's axis: the
    sum over its triangles of ``2 area n . r``, with ``r`` the offset of the triangle's
    centroid from the axis line (perpendicular to it), is made positive. For a closed-ish
    garment that sum is about twice the enclosed volume when the normals point outward, so
    an offset along them by ``+by`` increases the distance from the axis. The axis is the
    whole garment's principal axis (:func:`ptailor.edits.region.region_axis`) through its
    area-weighted centroid.

    Parameters
    ----------
    V : (n, 3) float array
    F3, F2 : (m, 3) int arrays
    plist : list of Panel
    pairs : (k, 2) int array, optional, keyword-only
        The seam half-edge pairs of ``F3, F2`` when known (:func:`panel_orientation`).

    Returns
    -------
    (n, 3) float array
        Unit normals (the sum of the oriented face normals times twice the face areas,
        normalised); zero at vertices no triangle uses.
    """
    sign, group = panel_orientation(F3, F2, plist, pairs=pairs)
    fp = panel_labels(plist, len(F3))
    a, b, c = V[F3[:, 0]], V[F3[:, 1]], V[F3[:, 2]]
    cross = triangle_normals(V, F3, unit=False) * sign[fp][:, None]
    every = np.arange(len(F3))
    ax = region_axis(V, F3, every)
    r = (a + b + c) / 3.0 - region_centroid(V, F3, every)
    r -= (r @ ax)[:, None] * ax
    fg = group[fp]
    outward = np.bincount(fg, weights=np.einsum("ij,ij->i", cross, r), minlength=group.max() + 1)
    cross *= np.where(outward[fg] < 0.0, -1.0, 1.0)[:, None]
    corners = F3.ravel()
    N = np.stack(
        [
            np.bincount(corners, weights=np.repeat(cross[:, k], 3), minlength=len(V))
            for k in range(3)
        ],
        axis=1,
    )
    length = np.linalg.norm(N, axis=1)
    return N / np.where(length > 0.0, length, 1.0)[:, None]


def normal_smoother(
    V: np.ndarray, F: np.ndarray, *, tau: float, symbolic=None
) -> Callable[[np.ndarray], np.ndarray]:
    """One implicit heat-diffusion step on a drape, factored once.

    The step is ``X -> (M + tau L)^-1 M X`` with ``L`` the cotangent stiffness matrix
    (:func:`ptailor.method.deform.cotangent_weights`, positive semi-definite for any mesh)
    and ``M`` the lumped (barycentric) vertex areas, over the vertices ``F`` uses. ``s``
    steps low-pass a field with the response ``(1 + tau k^2)^-s`` at a spatial wavenumber
    ``k``: about a Gaussian of width ``sigma = sqrt(2 s tau)``. A field that is an
    eigenfunction of ``L`` keeps its direction: the normals of a tube (radial) only
    shrink, so after normalising they are unchanged.

    Parameters
    ----------
    V : (n, 3) float array
    F : (m, 3) int array
    tau : float, keyword-only
        Diffusion time of one step, in squared length units.

    Returns
    -------
    callable
        ``step(X)`` for an ``(n, c)`` float array: the diffused field, ``(n, c)``; rows of
        vertices no triangle uses are returned unchanged.
    """
    n = len(V)
    seen = np.zeros(n, dtype=bool)
    seen[F] = True
    used = np.flatnonzero(seen)  # as np.unique(F), cheaper
    if used.size == n:  # every vertex used (a drape): no renumbering, no copies
        Fl, Vl = F, V
    else:
        loc = np.full(n, -1, dtype=np.int64)
        loc[used] = np.arange(used.size)
        Fl, Vl = loc[F], V[used]
    W = cotangent_weights(Vl, Fl)
    area = triangle_areas(Vl, Fl)
    mass = np.bincount(Fl.ravel(), weights=np.repeat(area / 3.0, 3), minlength=used.size)
    # a vertex whose triangles are all degenerate keeps its value (positive diagonal)
    mass = np.maximum(mass, edit_tol.LOOSEN_MASS_FLOOR_REL * max(float(mass.mean()), tol.TINY))
    # sparse Cholesky, once (``symbolic``: a SymbolicCache shared with a mirrored twin)
    solve = factor(_lower_system(W, mass, tau=tau), lower=True, symbolic=symbolic)

    def step(X: np.ndarray) -> np.ndarray:
        if used.size == n:
            return solve(mass[:, None] * X)
        out = X.copy()
        out[used] = solve(mass[:, None] * X[used])
        return out

    return step


def _lower_system(W: sp.csr_matrix, mass: np.ndarray, *, tau: float) -> sp.csc_matrix:
    """The lower triangle of ``diag(mass) + tau (diag(W 1) - W)``, CSC.

    Its pattern is the diagonal and the mesh's edges whatever the values (an edge whose
    cotangents cancel stays an explicit zero: one assembly from triplets, where sparse
    arithmetic would drop it), so matrices over the same triangles share one symbolic
    analysis (a mirrored step's two applications).

    Parameters
    ----------
    W : (k, k) scipy.sparse.csr_matrix
        Symmetric cotangent weights with no diagonal
        (:func:`ptailor.method.deform.cotangent_weights`).
    mass : (k,) float array
    tau : float, keyword-only

    Returns
    -------
    (k, k) scipy.sparse.csc_matrix
    """
    k = W.shape[0]
    W = W.sorted_indices().tocoo()  # each row summed in column order
    Wl = sp.tril(W, k=-1)
    diag = mass + tau * np.bincount(W.row, weights=W.data, minlength=k)
    rows = np.concatenate([np.arange(k), Wl.row])
    cols = np.concatenate([np.arange(k), Wl.col])
    return sp.csc_matrix((np.concatenate([diag, -tau * Wl.data]), (rows, cols)), shape=(k, k))


def unit_rows(X: np.ndarray) -> np.ndarray:
    """Rows of ``X (n, 3)`` scaled to unit length; zero rows stay zero."""
    length = np.linalg.norm(X, axis=1)
    return X / np.where(length > 0.0, length, 1.0)[:, None]


def turned_faces(before: np.ndarray, after: np.ndarray, T: np.ndarray) -> np.ndarray:
    """Triangles turned over (normal rotated by 90 degrees or more), ``(k,)`` bool.

    Parameters
    ----------
    before, after : (n, 3) float arrays
        Vertex positions.
    T : (k, 3) int array

    Returns
    -------
    (k,) bool array
        ``n_before . n_after <= 0``, already degenerate triangles left aside.
    """
    c0 = triangle_normals(before, T, unit=False)
    c1 = triangle_normals(after, T, unit=False)
    return (np.einsum("ij,ij->i", c0, c1) <= 0.0) & np.any(c0 != 0.0, axis=1)
