"""Small dense symmetric systems of the seam step: Cholesky once, many right-hand sides,
with the seam curves' free factors as a border (:func:`bordered_solver`)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ptailor import tolerances as tol
from ptailor.method import tolerances as method_tol


def spd_factor(M: np.ndarray) -> Callable[[np.ndarray], np.ndarray | None] | None:
    """The solution operator of a small symmetric positive (semi-)definite ``M``, factored
    once: Cholesky; where ``M`` is singular (dependent seam rows, as on a degenerate drape),
    Cholesky of ``M + eps I`` (``eps`` 1e-12, then 1e-9 of the largest diagonal entry: the
    least-squares solution to that precision, at a Cholesky's cost); least squares only
    where neither factors. None when ``M`` is not finite.

    A least-squares solve per right-hand side (an SVD of the whole seam system) once made
    every step of a degenerate run cost 20 s."""
    import scipy.linalg as sla

    if not np.all(np.isfinite(M)):
        return None
    d = float(np.abs(np.diag(M)).max(initial=0.0)) if M.size else 0.0
    for eps in method_tol.SPD_SHIFTS:
        try:
            A = M if eps == 0.0 else M + (eps * max(d, tol.TINY)) * np.eye(len(M))
            cho = sla.cho_factor(A)
        except (sla.LinAlgError, ValueError):
            continue
        return lambda r: _finite_or_none(sla.cho_solve(cho, r)) if np.all(np.isfinite(r)) else None

    def lstsq(r: np.ndarray) -> np.ndarray | None:
        if not np.all(np.isfinite(r)):
            return None
        try:
            return _finite_or_none(np.linalg.lstsq(M, r, rcond=None)[0])
        except (np.linalg.LinAlgError, ValueError):
            return None

    return lstsq


def solve_spd(M: np.ndarray, r: np.ndarray) -> np.ndarray | None:
    """Solve a small symmetric positive (semi-)definite system (:func:`spd_factor`).

    None when there is no finite solution (the caller skips the constraints).
    """
    if not np.all(np.isfinite(r)):
        return None
    solve = spd_factor(M)
    return None if solve is None else solve(r)


def solve_bordered(M: np.ndarray, B: np.ndarray | None, r: np.ndarray) -> np.ndarray | None:
    """``u`` of ``[[M, B], [B^T, 0]] [u; w] = [r; 0]`` for a symmetric positive
    (semi-)definite ``M``: :func:`bordered_solver` applied once. None when there is no
    finite solution.

    Parameters
    ----------
    M : (k, k) float array
    B : (k, t) float array or None
    r : (k,) float array
    """
    solve = bordered_solver(M, B)
    return None if solve is None else solve(r)


def bordered_solver(
    M: np.ndarray, B: np.ndarray | None
) -> Callable[[np.ndarray], np.ndarray | None] | None:
    """The solution operator ``r -> u`` of ``[[M, B], [B^T, 0]] [u; w] = [r; 0]`` for a
    symmetric positive (semi-)definite ``M`` (the seam step's system with free factors
    ``w``, one per column of ``B``), factored once for many right-hand sides.

    By the range space on ``M' = M + rho B B^T`` (the same solution, as ``B^T u = 0``;
    positive definite where ``M`` is singular only along directions ``B`` sees, as when a
    curve's total row is the sum of its pairs' rows): ``(B^T M'^-1 B) w = B^T M'^-1 r``,
    ``u = M'^-1 (r - B w)``. Without ``B``, :func:`solve_spd`'s Cholesky (least squares
    where singular).

    Parameters
    ----------
    M : (k, k) float array
    B : (k, t) float array or None
        Columns with disjoint supports (each row in at most one column: a seam curve's
        pairs), so ``B B^T`` is one rank-1 block per column.

    Returns
    -------
    callable or None
        ``solve(r)``, ``r`` a ``(k,)`` float array, giving ``u`` or None where it is not
        finite; None when ``M`` or ``B`` is not finite or the system has no solution.
    """

    if not np.all(np.isfinite(M)):
        return None
    if B is None or B.shape[1] == 0:
        return spd_factor(M)
    if not np.all(np.isfinite(B)):
        return None
    Mp = M.copy()
    rho = float(np.abs(np.diag(M)).max(initial=0.0)) / max(float((B * B).sum(1).max()), tol.TINY)
    for j in range(B.shape[1]):  # a loop over the seam curves
        idx = np.flatnonzero(B[:, j])
        b = B[idx, j]
        Mp[np.ix_(idx, idx)] += rho * np.outer(b, b)
    inner = spd_factor(Mp)
    if inner is None:
        return None
    MB = inner(B)
    if MB is None:
        return None
    S = B.T @ MB

    def solve(r: np.ndarray) -> np.ndarray | None:
        if not np.all(np.isfinite(r)):
            return None
        u0 = inner(r)
        if u0 is None:
            return None
        w = solve_spd(S, B.T @ u0)
        return None if w is None else _finite_or_none(u0 - MB @ w)

    return solve


def _finite_or_none(u: np.ndarray) -> np.ndarray | None:
    return u if np.all(np.isfinite(u)) else None
