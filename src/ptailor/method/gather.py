"""A gather's extra length in the pattern, near its seam: slash and spread.

A gathered seam (``scale_seam``'s ``around`` with no fixed end on the part) keeps the
drape as it is (gathers are fabric bunched into the seam, not a new silhouette) and asks
the gathered panel's pattern for its extra length in a band along the seam. The targets
are the Jacobians of a map of the panel's pattern (one sparse least-squares solve): the
identity beyond ``band`` from the seam; each seam edge ``factor`` times as long, turning as
it did (the seam line scaled about a point the solve finds); between, as near as a map can
be to a stretch along the seam of ``1 + (factor - 1) w(d)``, ``w`` a smoothstep from 1 on
the seam to 0 at ``band``. Along a straight seam that is the fan a pattern maker's slashes
from the seam make, spread at the seam and pivoted ``band`` away; along a curved one the
curve itself grows (a sleeve cap taller, a neckline deeper). A map, not the stretch field
itself: that field is not flat where the seam curves or ends (its Gaussian curvature about
``2 w' kappa``), and the stitching crawled there at 88k triangles (100 iterations, 21
before), the seam's exact ratio pulling its side into a sawtooth where the field gave an
edge less than ``factor``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

from ptailor import tolerances as tol
from ptailor.geometry.closed_forms import inv2
from ptailor.geometry.triangles import edge_matrices
from ptailor.method import tolerances as method_tol
from ptailor.method.operators import gradient_operator
from ptailor.method.solver import counted

__all__ = ["GatherBand", "gather_stretch", "stretch_targets"]


@dataclass(frozen=True)
class GatherBand:
    """One gathered seam's spread in the pattern.

    Attributes
    ----------
    faces : (k,) int array
        The gathered panel's triangles.
    seam_vertices : (s,) int array
        The pattern vertices of the gathered seam on that panel's side.
    seam_edges : (e, 2) int array
        Its pattern edges (those vertices' pairs along the seam).
    factor : float
        The seam side's length factor.
    band : float
        How far from the seam the extra length is spread (pattern units).
    """

    faces: np.ndarray
    seam_vertices: np.ndarray
    seam_edges: np.ndarray
    factor: float
    band: float


def _band_field(V2: np.ndarray, tri: np.ndarray, d: np.ndarray, band: float) -> np.ndarray:
    """The asked stretch's unit part ``w t t^T`` ``(k, 2, 2)``: ``t`` the unit direction
    along the seam (across the gradient of the distance ``d`` ``(k, 3)`` to it on each
    triangle ``tri`` ``(k, 3)``), ``w`` from 1 on the seam to 0 at ``band`` (a smoothstep:
    no kink where the band meets the kept panel)."""
    E = edge_matrices(V2, tri)
    # the distance's gradient g on each triangle: E^T g = (d1 - d0, d2 - d0)
    dd = (d[:, 1:] - d[:, :1])[:, :, None]
    g = (np.swapaxes(inv2(E), 1, 2) @ dd)[:, :, 0]
    norm = np.linalg.norm(g, axis=1)
    t = np.stack([-g[:, 1], g[:, 0]], 1) / np.maximum(norm, tol.TINY)[:, None]
    x = np.clip(1.0 - d.mean(axis=1) / band, 0.0, 1.0)
    w = np.where(norm > tol.TINY, x * x * (3.0 - 2.0 * x), 0.0)
    return w[:, None, None] * (t[:, :, None] * t[:, None, :])


def gather_stretch(V2: np.ndarray, F2: np.ndarray, gather: GatherBand) -> np.ndarray:
    """The Jacobians ``(k, 2, 2)`` of the gather's map of its triangles, in the frame of
    ``V2``: the identity beyond the band (those vertices held; the farthest at least),
    each seam edge ``gather.factor`` times as long (rows ``GATHER_SEAM_WEIGHT`` times a
    triangle's), the rest the area-weighted least-squares fit of the stretch
    ``I + (factor - 1) w t t^T`` (:func:`_band_field`).

    Parameters
    ----------
    V2 : (n2, 2) float array
        The pattern (mirrored panels flipped, as the targets are).
    F2 : (m, 3) int array
    gather : GatherBand
    """
    from scipy.spatial import cKDTree  # (imports scipy.spatial only when a gather is asked)

    tri = F2[gather.faces]
    verts, local = np.unique(tri, return_inverse=True)
    local = local.reshape(tri.shape)
    P = V2[verts]
    d = cKDTree(V2[gather.seam_vertices]).query(P)[0]
    field = _band_field(P, local, d[local], gather.band)
    E = edge_matrices(P, local)
    D = gradient_operator(local, E, len(P))
    area = np.abs(np.linalg.det(E)) / 2.0
    # the seam's edges as rows too: each ``factor`` times as long, turning as it does (the
    # seam line scaled about a point the solve finds), so the stitching's exact ratio, edge
    # by edge, asks nothing the targets do not
    se = np.searchsorted(verts, gather.seam_edges)
    k = len(se)
    G = sp.csr_matrix(
        (np.tile([-1.0, 1.0], k), se.ravel(), np.arange(0, 2 * k + 1, 2)), shape=(k, len(P))
    )
    A_all = sp.vstack([D, G]).tocsc()
    e = P[se[:, 1]] - P[se[:, 0]]
    w_seam = method_tol.GATHER_SEAM_WEIGHT * area.mean() / np.mean(np.sum(e * e, axis=1))
    W = sp.diags(np.concatenate([np.tile(area, 2), np.full(k, w_seam)]))
    # the displacement u, per unit of ``factor - 1``: D u = the field's columns stacked
    # (rows j m + i: column j), G u = the seam's edges
    rhs = np.concatenate([field[:, :, 0], field[:, :, 1], e], 0)
    free = d < gather.band
    free[np.argmax(d)] = False  # held: beyond the band (the farthest at least)
    A = (A_all[:, free].T @ W @ A_all[:, free]).tocsc()
    u = np.zeros_like(P)
    counted(sp.tril(A, format="csc"))  # spsolve's SuperLU factorisation
    u[free] = spsolve(A, A_all[:, free].T @ (W @ rhs)).reshape(-1, 2)
    J = (D @ u).reshape(2, -1, 2).transpose(1, 2, 0)
    return np.eye(2) + (gather.factor - 1.0) * J


def stretch_targets(
    V2: np.ndarray, F2: np.ndarray, targets: np.ndarray, gathers
) -> tuple[np.ndarray, np.ndarray]:
    """``targets`` with each gather's stretch applied (``S @ T``), and ``(m,)`` bool: the
    triangles a gather stretched.

    Parameters
    ----------
    V2 : (n2, 2) float array
    F2 : (m, 3) int array
    targets : (m, 2, 2) float array
    gathers : sequence of GatherBand
    """
    out = targets.copy()
    hit = np.zeros(len(F2), dtype=bool)
    for gb in gathers:  # a loop over the recipe's gathers
        out[gb.faces] = gather_stretch(V2, F2, gb) @ out[gb.faces]
        hit[gb.faces] = True
    return out, hit
