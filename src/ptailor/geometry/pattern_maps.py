"""Per-triangle linear maps between the pattern (2D) and the drape (3D) of the same cloth."""

from __future__ import annotations

import numpy as np

from ptailor.geometry.closed_forms import inv2
from ptailor.geometry.triangles import edge_matrices


def pattern_jacobians(
    V3: np.ndarray, F3: np.ndarray, V2: np.ndarray, F2: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The pattern-to-drape maps ``J = E3 E2^-1`` of triangles.

    Parameters
    ----------
    V3 : (n3, 3) float array
    F3 : (m, 3) int array
    V2 : (n2, 2) float array
    F2 : (m, 3) int array
        Row ``i`` of ``F2`` is the same cloth as row ``i`` of ``F3``.

    Returns
    -------
    J : (m, 3, 2) float array
        A pattern displacement in triangle ``i`` to the drape displacement of the same
        cloth. Where the pattern triangle is degenerate, ``E3`` times its adjugate.
    ok : (m,) bool array
        Pattern triangles with a non-zero determinant.

    Examples
    --------
    >>> V2, F = np.array([[0.0, 0], [1, 0], [0, 1]]), np.array([[0, 1, 2]])
    >>> J, ok = pattern_jacobians(np.c_[2 * V2, [0, 0, 0]], F, V2, F)
    >>> J[0], ok
    (array([[2., 0.],
           [0., 2.],
           [0., 0.]]), array([ True]))
    """
    E2 = edge_matrices(V2, F2)
    det = E2[:, 0, 0] * E2[:, 1, 1] - E2[:, 0, 1] * E2[:, 1, 0]
    ok = np.abs(det) > 0
    adj = np.stack(
        [np.stack([E2[:, 1, 1], -E2[:, 0, 1]], 1), np.stack([-E2[:, 1, 0], E2[:, 0, 0]], 1)], 1
    )
    return edge_matrices(V3, F3) @ (adj / np.where(ok, det, 1.0)[:, None, None]), ok


def pseudo_inverses(J: np.ndarray) -> np.ndarray:
    """Pseudo-inverses ``J+ = (J^T J)^-1 J^T`` of pattern-to-drape maps.

    Parameters
    ----------
    J : (m, 3, 2) float array
        From :func:`pattern_jacobians`.

    Returns
    -------
    (m, 2, 3) float array
        A 3D displacement in the triangle's plane to the pattern displacement of the same
        cloth (inf/nan for a degenerate drape triangle).

    Examples
    --------
    >>> J = np.array([[[2.0, 0], [0, 2], [0, 0]]])
    >>> pseudo_inverses(J)[0]
    array([[0.5, 0. , 0. ],
           [0. , 0.5, 0. ]])
    """
    Jt = np.swapaxes(J, 1, 2)
    return inv2(Jt @ J) @ Jt


def least_squares_preimages(
    J: np.ndarray, T: np.ndarray, ok: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Pattern vectors that ``J`` maps closest to drape vectors ``T``: ``(J^T J)^-1 J^T t``.

    Parameters
    ----------
    J : (m, 3, 2) float array
    T : (m, 3) float array
        One drape vector per triangle.
    ok : (m,) bool array, optional
        Triangles whose ``J`` is valid (``pattern_jacobians``' second result).

    Returns
    -------
    X : (m, 2) float array
        Zero where not ``good``.
    good : (m,) bool array
        ``ok`` and ``J^T J`` invertible.

    Examples
    --------
    >>> J = np.array([[[2.0, 0], [0, 2], [0, 0]]])
    >>> least_squares_preimages(J, np.array([[1.0, 1.0, 5.0]]))
    (array([[0.5, 0.5]]), array([ True]))
    """
    JtJ = np.einsum("mki,mkj->mij", J, J)
    rhs = np.einsum("mki,mk->mi", J, T)
    dj = JtJ[:, 0, 0] * JtJ[:, 1, 1] - JtJ[:, 0, 1] ** 2
    good = dj > 0 if ok is None else ok & (dj > 0)
    sol = np.stack(
        [JtJ[:, 1, 1] * rhs[:, 0] - JtJ[:, 0, 1] * rhs[:, 1],
         JtJ[:, 0, 0] * rhs[:, 1] - JtJ[:, 0, 1] * rhs[:, 0]], 1
    ) / np.where(good, dj, 1.0)[:, None]  # fmt: skip
    return np.where(good[:, None], sol, 0.0), good
