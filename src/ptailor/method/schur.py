"""The block of ``A^-1`` on a few unknowns, from one Cholesky with those unknowns last.

For a symmetric positive definite ``A`` and unknowns ``U`` ordered last,
``P A P^T = L L^T`` has a trailing block ``L22`` with ``L22 L22^T = S``, the Schur
complement of the other unknowns, and ``A^-1[U, U] = S^-1``. So the seam constraints'
block of the inverse costs one factorisation and a dense ``q x q`` inverse, where the
back-substitution route costs one solve of the whole system per seam unknown (1,804
solves at 100,000 triangles).

CHOLMOD (through cvxopt) keeps a user ordering only with ``nmethods = 1`` (otherwise it
tries AMD as well and takes the ordering with less fill) and ``postorder = False``
(otherwise the elimination-tree postorder may move unknowns out of the tail).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = ["schur_inverse"]


def _cvx_lower(A: sp.spmatrix):
    """The lower triangle of ``A`` as a cvxopt sparse matrix."""
    from cvxopt import matrix, spmatrix

    T = sp.tril(A).tocsc()
    T.sort_indices()
    cols = np.repeat(np.arange(T.shape[1], dtype=np.int64), np.diff(T.indptr))
    return spmatrix(
        matrix(np.ascontiguousarray(T.data, dtype=float)),
        matrix(T.indices.astype(np.int64)),
        matrix(cols),
        T.shape,
    )


def _seam_last_order(A: sp.csc_matrix, order: np.ndarray) -> np.ndarray:
    """A fill-reducing permutation ending in ``order``: ``[AMD of the others; order]``."""
    from cvxopt import amd

    N = A.shape[0]
    rest = np.setdiff1d(np.arange(N), order, assume_unique=False)
    if len(rest) == 0:
        return order.copy()
    A11 = A[rest][:, rest]
    p11 = np.asarray(amd.order(_cvx_lower(A11)), dtype=np.int64).ravel()
    return np.concatenate([rest[p11], order])


def _trailing_factor(A: sp.csc_matrix, p: np.ndarray, q: int) -> np.ndarray:
    """The trailing ``q x q`` block of ``L`` in ``P A P^T = L L^T``, dense (lower)."""
    from cvxopt import cholmod, matrix

    from ptailor.errors import PtailorError

    N = A.shape[0]
    saved = dict(cholmod.options)
    cholmod.options.update({"supernodal": 2, "postorder": False, "nmethods": 1})
    try:
        Ac = _cvx_lower(A)
        F = cholmod.symbolic(Ac, p=matrix(p.astype(np.int64)))
        cholmod.numeric(Ac, F)
        Lf = cholmod.getfactor(F)
    except ArithmeticError:
        raise PtailorError(
            "flatten: the stitching matrix is not positive definite (degenerate target "
            "triangles or extreme flatten weights)"
        ) from None
    finally:
        cholmod.options.clear()
        cholmod.options.update(saved)
    rows = np.asarray(Lf.I, dtype=np.int64).ravel()
    cols = np.asarray(Lf.J, dtype=np.int64).ravel()
    vals = np.asarray(Lf.V, dtype=float).ravel()
    first = N - q
    tail = (rows >= first) & (cols >= first)
    L22 = np.zeros((q, q))
    L22[rows[tail] - first, cols[tail] - first] = vals[tail]
    return L22


def schur_inverse(A: sp.spmatrix, U: np.ndarray, *, block: np.ndarray | None = None) -> np.ndarray:
    """``A^-1`` restricted to the unknowns ``U``, from one seam-last Cholesky.

    Parameters
    ----------
    A : (N, N) sparse matrix
        Symmetric positive definite.
    U : (q,) int array
        Distinct unknowns (indices into ``A``).
    block : (q,) int array, optional
        A label per unknown. When ``A`` is block diagonal with the unknowns of different
        labels in different blocks, the inverse is zero across labels: pass the labels and
        only the within-label blocks are inverted (the rest of the result is zero).

    Returns
    -------
    G : (q, q) float array
        ``G[i, j] = (A^-1)[U[i], U[j]]`` (zero across labels when ``block`` is given).

    Raises
    ------
    PtailorError
        ``A`` is not positive definite.

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> A = sp.csc_matrix(np.array([[4.0, 1, 0], [1, 3, 1], [0, 1, 2]]))
    >>> G = schur_inverse(A, np.array([2, 0]))
    >>> bool(np.allclose(G, np.linalg.inv(A.toarray())[np.ix_([2, 0], [2, 0])]))
    True
    """
    from scipy.linalg import lapack

    A = sp.csc_matrix(A)
    U = np.asarray(U, dtype=np.int64)
    q = len(U)
    G = np.zeros((q, q))
    if q == 0:
        return G
    lab = np.zeros(q, dtype=np.int64) if block is None else np.asarray(block, dtype=np.int64)
    order = np.argsort(lab, kind="stable")  # the tail grouped by label: L22 block diagonal
    p = _seam_last_order(A, U[order])
    L22 = _trailing_factor(A, p, q)
    cuts = np.flatnonzero(np.diff(lab[order])) + 1
    for idx in np.split(np.arange(q), cuts):  # a loop over labels (panels), not unknowns
        Lb = L22[np.ix_(idx, idx)]
        inv, info = lapack.dpotri(Lb, lower=1)  # (Lb Lb^T)^-1, lower triangle
        if info != 0:
            from ptailor.errors import PtailorError

            raise PtailorError("flatten: the seam block of the stitching matrix is singular")
        inv = np.tril(inv) + np.tril(inv, -1).T
        G[np.ix_(order[idx], order[idx])] = inv
    return G
