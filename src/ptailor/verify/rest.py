"""Rest shapes for a re-drape: each pattern triangle through the original intrinsic scale.

A garment's drape is not at rest against its pattern: elastic cuffs, gathers and smocking
make the drape smaller than the pattern on purpose (``docs/method.md``, the intrinsic
scale ``U0 = sqrt(J0^T J0)``, ``J0 = D0 P^-1``). To re-drape a new pattern the way the
designer meant it, each new pattern triangle is mapped through the original garment's
intrinsic scale: with ``M = E_new P^-1`` (the map from the original pattern triangle to the
new one) and ``S = sqrt(M^T M)`` its stretch tensor, the rest triangle is

    rest = U0 S P                     (mode "intrinsic")
    rest = S P                        (mode "pattern": plain cloth cut from the pattern)

as a 2 x 2 edge matrix in the original pattern's frame. Then the original pattern rests
exactly as the original drape (``rest^T rest = D0^T D0``), ptailor's adjusted pattern as
the edited drape, and a pattern that lost the intrinsic scale (uniform flattening) comes
out too small where the design had gathers. ``S`` ignores any rotation or mirror of the
new pattern; ``det(rest)`` has the sign of ``det(P)`` (a clockwise, mirrored pattern
triangle gives a mirrored rest triangle).
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from ptailor.geometry.closed_forms import inv2, sqrt_spd2
from ptailor.geometry.triangles import edge_matrices
from ptailor.method.intrinsic import stretch_tensors

__all__ = ["RestMode", "pattern_stretch", "rest_shapes"]

RestMode = Literal["intrinsic", "pattern"]
REST_MODES: tuple[str, ...] = ("intrinsic", "pattern")


def pattern_stretch(E_new: np.ndarray, P: np.ndarray) -> np.ndarray:
    """Stretch tensors of the maps from original to new pattern triangles.

    Parameters
    ----------
    E_new, P : (m, 2, 2) float arrays
        New and original pattern edge matrices.

    Returns
    -------
    (m, 2, 2) float array
        ``S = sqrt(M^T M)`` with ``M = E_new P^-1``: symmetric positive definite, the same
        for any rotation or mirror of the new pattern.
    """
    M = E_new @ inv2(P)
    return sqrt_spd2(np.swapaxes(M, 1, 2) @ M)


def rest_shapes(
    V2_new: np.ndarray,
    F2: np.ndarray,
    V2_orig: np.ndarray,
    V3_orig: np.ndarray,
    F3: np.ndarray,
    *,
    mode: RestMode = "intrinsic",
) -> np.ndarray:
    """Rest triangles of a new pattern, through the original garment's intrinsic scale.

    Parameters
    ----------
    V2_new : (n2, 2) float array
        The new pattern (same triangles ``F2`` as the original); any rotation, translation
        or mirror of it gives the same rest shapes.
    F2 : (m, 3) int array
    V2_orig : (n2, 2) float array
        The original pattern.
    V3_orig : (n3, 3) float array
        The original drape.
    F3 : (m, 3) int array
    mode : {"intrinsic", "pattern"}
        ``intrinsic``: ``U0 S P`` (the design's gathers and elastic kept); ``pattern``:
        ``S P`` (plain cloth, the pattern as cut).

    Returns
    -------
    (m, 2, 2) float array
        Edge matrices (columns ``p1 - p0``, ``p2 - p0``) in the original pattern's frame and
        units; ``det`` has the sign of the original pattern triangle's.

    Examples
    --------
    >>> V2 = np.array([[0.0, 0], [2, 0], [0, 1]])
    >>> V3 = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    >>> F = np.array([[0, 1, 2]])
    >>> rest_shapes(V2, F, V2, V3, F)[0]
    array([[1., 0.],
           [0., 1.]])
    >>> rest_shapes(V2 * 1.5, F, V2, V3, F, mode="pattern")[0]
    array([[3. , 0. ],
           [0. , 1.5]])
    """
    if mode not in REST_MODES:
        raise ValueError(f"rest mode must be one of {REST_MODES}, got {mode!r}")
    P = edge_matrices(np.asarray(V2_orig, dtype=float), F2)
    S = pattern_stretch(edge_matrices(np.asarray(V2_new, dtype=float), F2), P)
    if mode == "pattern":
        return S @ P
    U0 = stretch_tensors(P, edge_matrices(np.asarray(V3_orig, dtype=float), F3))
    return U0 @ S @ P
