"""Intrinsic scale: per-triangle target pattern triangles after a 3D edit.

All targets are returned as ``(m, 2, 2)`` edge matrices ``[p1 - p0, p2 - p0]`` (columns)
expressed in the original pattern's own frame, so the stitching solver can start from
identity rotations and the result keeps the pattern's orientation.
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from ptailor.geometry.closed_forms import inv2, sqrt_spd2
from ptailor.geometry.triangles import edge_matrices

__all__ = ["Intrinsic", "intrinsic_targets", "local_frames", "stretch_tensors"]

Intrinsic = Literal["polar", "paper", "uniform"]


def local_frames(E: np.ndarray) -> np.ndarray:
    """The paper's local frame matrix (equation 0 with sin and cos in their right places).

    Parameters
    ----------
    E : (m, d, 2) float array
        Edge matrices ``[u, v]`` in 2D or 3D.

    Returns
    -------
    (m, 2, 2) float array
        ``[[|u|, |v| cos t], [0, |v| sin t]]``, ``u`` along +x, ``sin t >= 0``.
    """
    u, v = E[:, :, 0], E[:, :, 1]
    lu = np.linalg.norm(u, axis=1)
    dot = np.einsum("ij,ij->i", u, v)
    if E.shape[1] == 2:
        cross = np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
    else:
        cross = np.linalg.norm(np.cross(u, v), axis=1)
    L = np.zeros((len(E), 2, 2))
    L[:, 0, 0] = lu
    L[:, 0, 1] = dot / lu
    L[:, 1, 1] = cross / lu
    return L


def stretch_tensors(E2: np.ndarray, E3: np.ndarray) -> np.ndarray:
    """Right stretch tensors ``U = sqrt(J^T J)`` of the maps from pattern to drape triangles.

    Parameters
    ----------
    E2 : (m, 2, 2) float array
        Pattern edge matrices.
    E3 : (m, 3, 2) float array
        Drape edge matrices.

    Returns
    -------
    (m, 2, 2) float array
    """
    return _stretch(inv2(E2), E3)


def _stretch(E2inv: np.ndarray, E3: np.ndarray) -> np.ndarray:
    """:func:`stretch_tensors` from the inverse pattern edge matrices (shared by the two
    drapes of a target)."""
    J = E3 @ E2inv
    # J^T J with J^T made contiguous: matmul's product of a transposed view is 2.4x slower
    # (the same sums, bit for bit)
    return sqrt_spd2(np.ascontiguousarray(np.swapaxes(J, 1, 2)) @ J)


def intrinsic_targets(
    V2: np.ndarray,
    F2: np.ndarray,
    V3: np.ndarray,
    V3_edit: np.ndarray,
    F3: np.ndarray,
    *,
    intrinsic: Intrinsic = "polar",
) -> np.ndarray:
    """Target pattern triangles that keep the intrinsic scale through a 3D edit.

    Parameters
    ----------
    V2 : (n2, 2) float array
        Original pattern, counter-clockwise triangles (flip mirrored panels first).
    F2 : (m, 3) int array
    V3, V3_edit : (n3, 3) float arrays
        Original and edited drape.
    F3 : (m, 3) int array
    intrinsic : {"polar", "paper", "uniform"}
        ``polar``: the frame-free ``U0^-1 U1 P_i`` (DESIGN.md section 2, the default);
        ``paper``: the paper's ``T_i t_i^-1 t_i^edit``; ``uniform``: the edited drape
        triangle itself (uniform flattening, the baseline).

    Returns
    -------
    (m, 2, 2) float array
        Target edge matrices in the original pattern's frame.
    """
    E2 = edge_matrices(V2, F2)
    E3e = edge_matrices(V3_edit, F3)
    if intrinsic == "polar":
        E2inv = inv2(E2)
        U0 = _stretch(E2inv, edge_matrices(V3, F3))
        U1 = _stretch(E2inv, E3e)
        return inv2(U0) @ U1 @ E2
    te = local_frames(E3e)
    if intrinsic == "paper":
        # R_u T_i = E2, so R_u T_i t_i^-1 t_i^edit = E2 t_i^-1 t_i^edit
        t = local_frames(edge_matrices(V3, F3))
        return E2 @ inv2(t) @ te
    if intrinsic == "uniform":
        # rotate the edited drape triangle so its u edge has the pattern's u direction
        u = E2[:, :, 0]
        ang = np.arctan2(u[:, 1], u[:, 0])
        c, s = np.cos(ang), np.sin(ang)
        R = np.stack([np.stack([c, -s], 1), np.stack([s, c], 1)], 1)
        return R @ te
    raise ValueError(f"unknown intrinsic method {intrinsic!r}")
