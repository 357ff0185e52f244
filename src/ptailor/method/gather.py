"""A gather's extra length in the pattern, near its seam: slash and spread.

A gathered seam (``scale_seam``'s ``around`` with no fixed end on the part) keeps the
drape as it is (gathers are fabric bunched into the seam, not a new silhouette) and asks
the gathered panel's pattern for its extra length in a band along the seam: each triangle
within ``band`` of the seam (in the pattern) is stretched along the seam's direction by
``1 + (factor - 1) * (1 - d / band)`` at its distance ``d``, so the seam's side grows by
``factor`` and the panel beyond the band keeps its shape. Along a straight seam that
stretch is exactly developable (the fan a pattern maker's slashes from the seam, spread at
the seam and pivoted ``band`` away, make).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from ptailor import tolerances as tol
from ptailor.geometry.closed_forms import inv2
from ptailor.geometry.triangles import edge_matrices

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
    factor : float
        The seam side's length factor.
    band : float
        How far from the seam the extra length is spread (pattern units).
    """

    faces: np.ndarray
    seam_vertices: np.ndarray
    factor: float
    band: float


def gather_stretch(V2: np.ndarray, F2: np.ndarray, gather: GatherBand) -> np.ndarray:
    """The stretch ``S`` of each of the gather's triangles, ``(k, 2, 2)``, in the frame of
    ``V2``: ``I + (s - 1) t t^T`` with ``t`` the unit direction along the seam (across the
    gradient of the distance to it) and ``s`` the stretch at the triangle's distance.

    Parameters
    ----------
    V2 : (n2, 2) float array
        The pattern (mirrored panels flipped, as the targets are).
    F2 : (m, 3) int array
    gather : GatherBand
    """
    tri = F2[gather.faces]
    d = cKDTree(V2[gather.seam_vertices]).query(V2[tri.ravel()])[0].reshape(tri.shape)
    E = edge_matrices(V2, tri)
    # the distance's gradient g on each triangle: E^T g = (d1 - d0, d2 - d0)
    dd = (d[:, 1:] - d[:, :1])[:, :, None]
    g = (np.swapaxes(inv2(E), 1, 2) @ dd)[:, :, 0]
    norm = np.linalg.norm(g, axis=1)
    t = np.stack([-g[:, 1], g[:, 0]], 1) / np.maximum(norm, tol.TINY)[:, None]
    # at its nearest corner: a triangle on the seam takes the whole factor along it
    w = np.clip(1.0 - d.min(axis=1) / gather.band, 0.0, 1.0)
    s = np.where(norm > tol.TINY, (gather.factor - 1.0) * w, 0.0)
    return np.eye(2) + s[:, None, None] * (t[:, :, None] * t[:, None, :])


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
