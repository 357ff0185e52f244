"""How the rest of a garment follows an edit of one part of it."""

from __future__ import annotations

import numpy as np

from ptailor.method.deform import arap_deform


def rigid_apart(
    V3: np.ndarray,
    V_follow: np.ndarray,
    F3: np.ndarray,
    plist: list,
    in_region: np.ndarray,
    handles: np.ndarray,
    moved: np.ndarray,
) -> np.ndarray:
    """The drape after an edit of a region, with the panels that share no vertex with the
    region moved rigidly: the rest of the garment changes shape only in the panels sewn to
    the region (a sleeve made wider stretches the body's armhole, not the collar).

    Each connected group of such panels takes the rigid motion that best fits where the
    as-rigid-as-possible follow-up ``V_follow`` took it (Kabsch), so it goes where the
    garment goes (a bodice above a skirt scaled about its centre moves up with the waist);
    then the deformation is solved again with those panels as handles too.

    Parameters
    ----------
    V3, V_follow : (n, 3) float arrays
        The drape before the edit, and after it with the rest following freely.
    F3 : (m, 3) int array
    plist : list of Panel
    in_region : (n,) bool array
    handles : (h,) int array
        The region's vertices (sorted), and ``moved`` ``(h, 3)`` their positions.

    Returns
    -------
    (n, 3) float array
    """
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components

    from ptailor.geometry.rotations import rigid_fits_3d

    apart = [p.faces for p in plist if not in_region[F3[p.faces]].any()]  # a loop over panels
    if not apart:
        return V_follow
    T = F3[np.concatenate(apart)]
    n = len(V3)
    adj = sp.csr_matrix(
        (np.ones(T.size), (T.ravel(), np.roll(T, -1, axis=1).ravel())), shape=(n, n)
    )
    lab = connected_components(adj, directed=False)[1]
    fv = np.unique(T)
    _, comp = np.unique(lab[fv], return_inverse=True)
    k = int(comp.max()) + 1
    R, cp, cq = rigid_fits_3d(V3[fv], V_follow[fv], comp, k, collinear_rel=1e-10)
    target = np.einsum("kij,kj->ki", R[comp], V3[fv] - cp[comp]) + cq[comp]
    both = np.concatenate([handles, fv])
    order = np.argsort(both, kind="stable")
    return arap_deform(V3, F3, both[order], np.concatenate([moved, target])[order])
