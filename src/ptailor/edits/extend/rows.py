"""The rows ``extend`` adds: their container, their triangles, and when they cross."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor.errors import PtailorError
from ptailor.geometry.triangles import triangle_normals

#: Smoothing passes of the row directions tried before giving up on crossing rows.
MAX_SMOOTHING = 200


@dataclass(frozen=True)
class Rows:
    """New rows beyond an opening, in the drape (edited and original) and the pattern.

    Attributes
    ----------
    new_e, new_b : (rows k, 3) float arrays
        Edited and original drape positions, row by row (``k`` per row, opening order).
    new_2 : (rows c, 2) float array
        Pattern positions, ``c`` columns per row.
    use_b : (rows, k) bool array
        Quad diagonals (:func:`quad_rows`).
    smoothing : int
        Smoothing passes of the drape rows.
    pattern_smoothing : int
        Smoothing passes of the pattern directions (``measure: pattern``).
    """

    new_e: np.ndarray
    new_b: np.ndarray
    new_2: np.ndarray
    use_b: np.ndarray
    smoothing: int
    pattern_smoothing: int = 0


def quad_rows(A: np.ndarray, B: np.ndarray, use_b: np.ndarray) -> np.ndarray:
    """Triangulate the quads between consecutive rows of vertex indices.

    Parameters
    ----------
    A, B : (r + 1, k) int arrays
        Row ``j`` holds the vertex at the start and at the end of each opening edge; row 0
        is the opening, whose half-edge ``A[0] -> B[0]`` has its triangle on the left.
    use_b : (r, k) bool array
        Split each quad along ``A[j] - B[j + 1]`` (else ``B[j] - A[j + 1]``).

    Returns
    -------
    (2 r k, 3) int array
        Two triangles per quad, row by row; oriented like the triangles at the opening
        (each row's edge ``B[j] -> A[j]`` is the twin of the row below).
    """
    a0, a1, b0, b1 = A[:-1], A[1:], B[:-1], B[1:]
    u = use_b[..., None]
    t0 = np.where(u, np.stack([b0, a0, b1], -1), np.stack([b0, a0, a1], -1))
    t1 = np.where(u, np.stack([a0, a1, b1], -1), np.stack([b0, a1, b1], -1))
    return np.stack([t0, t1], axis=2).reshape(-1, 3)


def face_normals(V: np.ndarray, F: np.ndarray) -> np.ndarray:
    """Unit normals of triangles, ``(m, 3)`` (zero for degenerate ones)."""
    return triangle_normals(V, F)


def shorter_diagonals(V: np.ndarray, A: np.ndarray, B: np.ndarray, odd: np.ndarray) -> np.ndarray:
    """Which diagonal splits each quad between rows: the shorter one, ties in a checkerboard.

    Parameters
    ----------
    V : (n, d) float array
        Positions of the grid's vertices.
    A, B : (r + 1, k) int arrays
        The rows' vertices (as :func:`quad_rows` takes them).
    odd : (r, k) bool array
        The checkerboard used on ties.

    Returns
    -------
    (r, k) bool array
        ``use_b`` of :func:`quad_rows`: split along ``A[j] - B[j + 1]``.
    """
    dA = np.linalg.norm(V[A[1:]] - V[B[:-1]], axis=2)
    dB = np.linalg.norm(V[A[:-1]] - V[B[1:]], axis=2)
    tie = np.abs(dA - dB) <= 1e-9 * (dA + dB)
    return np.where(tie, odd, dB < dA)


def crossing_error(name: str, by: float, where: str) -> PtailorError:
    return PtailorError(
        f"extend {name} by {by:g}: the new rows would cross {where} (the opening turns too "
        "sharply for that length); extend by less"
    )
