"""Closed forms for stacks of 2x2 matrices: determinants, inverses, SPD square roots."""

from __future__ import annotations

import numpy as np

from ptailor import tolerances as tol


def det2(A: np.ndarray) -> np.ndarray:
    """Determinants of 2x2 matrices in closed form.

    Parameters
    ----------
    A : (m, 2, 2) float array

    Returns
    -------
    (m,) float array

    Examples
    --------
    >>> det2(np.array([[[1.0, 2.0], [3.0, 4.0]]]))
    array([-2.])
    """
    return A[:, 0, 0] * A[:, 1, 1] - A[:, 0, 1] * A[:, 1, 0]


def inv2(A: np.ndarray) -> np.ndarray:
    """Inverses of 2x2 matrices in closed form (adjugate over determinant).

    Parameters
    ----------
    A : (m, 2, 2) float array

    Returns
    -------
    (m, 2, 2) float array
        Singular matrices give inf/nan entries.

    Examples
    --------
    >>> inv2(np.array([[[2.0, 1.0], [0.0, 4.0]]]))[0]
    array([[ 0.5  , -0.125],
           [-0.   ,  0.25 ]])
    """
    det = det2(A)
    out = np.empty_like(A)
    out[:, 0, 0] = A[:, 1, 1]
    out[:, 1, 1] = A[:, 0, 0]
    out[:, 0, 1] = -A[:, 0, 1]
    out[:, 1, 0] = -A[:, 1, 0]
    return out / det[:, None, None]


def sqrt_spd2(C: np.ndarray) -> np.ndarray:
    """Square roots of symmetric positive definite 2x2 matrices, in closed form.

    Parameters
    ----------
    C : (m, 2, 2) float array

    Returns
    -------
    (m, 2, 2) float array
        ``U`` with ``U @ U = C``, ``U`` symmetric positive definite.

    Examples
    --------
    >>> sqrt_spd2(np.array([[[4.0, 0.0], [0.0, 9.0]]]))[0]
    array([[2., 0.],
           [0., 3.]])
    """
    s = np.sqrt(np.maximum(det2(C), 0.0))
    t = np.sqrt(np.maximum(C[:, 0, 0] + C[:, 1, 1] + 2.0 * s, tol.TINY))
    return (C + s[:, None, None] * np.eye(2)) / t[:, None, None]
