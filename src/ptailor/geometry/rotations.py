"""Rotations: closest rotations to 2x2 matrices, trace-maximising 3x3 rotations, and rigid
best fits of point sets (one set, or many labelled sets at once)."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp


def closest_rotations(J: np.ndarray) -> np.ndarray:
    """Closest rotations (det +1) to 2x2 matrices, in closed form.

    Parameters
    ----------
    J : (m, 2, 2) float array

    Returns
    -------
    (m, 2, 2) float array

    Examples
    --------
    >>> closest_rotations(np.array([[[0.0, -2.0], [2.0, 0.0]]])).round(12)[0]
    array([[ 0., -1.],
           [ 1.,  0.]])
    """
    ang = np.arctan2(J[:, 1, 0] - J[:, 0, 1], J[:, 0, 0] + J[:, 1, 1])
    c, s = np.cos(ang), np.sin(ang)
    return np.stack([np.stack([c, -s], 1), np.stack([s, c], 1)], 1)


def rigid_fit(
    A: np.ndarray, B: np.ndarray, *, reflect: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """The rigid map taking points ``A`` closest to ``B`` in least squares (Kabsch).

    Parameters
    ----------
    A, B : (n, d) float arrays
        Corresponding points.
    reflect : bool
        False: a rotation (det +1); True: a reflection (det -1).

    Returns
    -------
    R : (d, d) float array
    t : (d,) float array
        ``A @ R.T + t`` is closest to ``B``.

    Examples
    --------
    >>> A = np.array([[0.0, 0], [1, 0], [0, 2]])
    >>> R, t = rigid_fit(A, A @ np.array([[0.0, -1], [1, 0]]).T + [3, 4])
    >>> R.round(12), t.round(12)
    (array([[ 0., -1.],
           [ 1.,  0.]]), array([3., 4.]))
    """
    ca, cb = A.mean(axis=0), B.mean(axis=0)
    H = (A - ca).T @ (B - cb)
    U, _, Vt = np.linalg.svd(H)
    d = len(ca)
    D = np.eye(d)
    D[-1, -1] = -1.0 if reflect else 1.0
    R = Vt.T @ D @ U.T
    if (np.linalg.det(R) < 0) != reflect:  # the SVD's own sign
        D[-1, -1] = 1.0 if reflect else -1.0
        R = Vt.T @ D @ U.T
    return R, cb - R @ ca


def rigid_fit_groups(X: np.ndarray, Y: np.ndarray, labels: np.ndarray, n_groups: int) -> np.ndarray:
    """Move each group of 2D points of ``X`` by the rotation + translation that best fits it
    onto ``Y`` (closed form, all groups at once).

    Parameters
    ----------
    X, Y : (n, 2) float arrays
        Moving and reference positions of the same points.
    labels : (n,) int array
        Group per point; points with -1 are returned unchanged.
    n_groups : int

    Returns
    -------
    (n, 2) float array

    Examples
    --------
    >>> X = np.array([[0.0, 0], [1, 0], [5, 5]])
    >>> rigid_fit_groups(X, X @ [[0.0, 1], [-1, 0]] + 2, np.array([0, 0, -1]), 1).round(12)
    array([[2., 2.],
           [2., 3.],
           [5., 5.]])
    """
    used = np.flatnonzero(labels >= 0)
    lab = labels[used]
    cnt = np.maximum(np.bincount(lab, minlength=n_groups), 1).astype(float)

    def centroid(P: np.ndarray) -> np.ndarray:
        return np.stack([np.bincount(lab, P[:, c], n_groups) for c in range(2)], 1) / cnt[:, None]

    cx, cy = centroid(X[used]), centroid(Y[used])
    a = X[used] - cx[lab]
    b = Y[used] - cy[lab]
    dot = np.bincount(lab, a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1], n_groups)
    crs = np.bincount(lab, a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], n_groups)
    ang = np.arctan2(crs, dot)
    c, s = np.cos(ang)[lab], np.sin(ang)[lab]
    out = X.copy()
    out[used] = np.stack([c * a[:, 0] - s * a[:, 1], s * a[:, 0] + c * a[:, 1]], 1) + cy[lab]
    return out


def det3(M: np.ndarray) -> np.ndarray:
    """Determinants of a stack ``M (k, 3, 3)``, elementwise (faster than LAPACK here).

    Examples
    --------
    >>> det3(np.array([2.0 * np.eye(3)]))
    array([8.])
    """
    a, b, c = M[:, 0], M[:, 1], M[:, 2]
    return (
        a[:, 0] * (b[:, 1] * c[:, 2] - b[:, 2] * c[:, 1])
        - a[:, 1] * (b[:, 0] * c[:, 2] - b[:, 2] * c[:, 0])
        + a[:, 2] * (b[:, 0] * c[:, 1] - b[:, 1] * c[:, 0])
    )


def max_trace_rotations(S: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rotations maximising ``trace(R S)`` for a stack ``S (k, 3, 3)`` (by SVD).

    Returns
    -------
    R : (k, 3, 3) float array
        Proper rotations (``det = +1``).
    trace : (k,) float array
        The maxima, ``trace(R S)``.

    Examples
    --------
    >>> R, tr = max_trace_rotations(np.array([np.diag([1.0, 2.0, 3.0])]))
    >>> R.round(12)[0], tr
    (array([[1., 0., 0.],
           [0., 1., 0.],
           [0., 0., 1.]]), array([6.]))
    """
    U, sv, Vh = np.linalg.svd(S)
    # S = U diag(s) Vh, R = Vh^T U^T; a reflection is fixed by flipping the sign of U's
    # last column, the singular vector of the smallest singular value
    d = np.where(det3(U) * det3(Vh) < 0.0, -1.0, 1.0)
    U[:, :, 2] *= d[:, None]
    return np.swapaxes(U @ Vh, 1, 2), sv[:, 0] + sv[:, 1] + d * sv[:, 2]


def rigid_fits_3d(
    P: np.ndarray, Q: np.ndarray, label: np.ndarray, k: int, *, collinear_rel: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Best rigid motion of 3D points ``P`` onto ``Q`` per label (Kabsch), all at once.

    Parameters
    ----------
    P, Q : (h, 3) float arrays
    label : (h,) int array
        Labels ``0 .. k - 1``, each used at least once.
    k : int
    collinear_rel : float
        Labels whose points' covariance has a second singular value at most this times the
        first (a single point, or collinear points) get ``R = I`` (translation only).

    Returns
    -------
    R : (k, 3, 3) float array
    cp, cq : (k, 3) float arrays
        A point ``p`` with label ``c`` maps to ``R[c] @ (p - cp[c]) + cq[c]``.

    Examples
    --------
    >>> P = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    >>> R, cp, cq = rigid_fits_3d(P, P + 2.0, np.zeros(4, int), 1, collinear_rel=1e-10)
    >>> bool(np.allclose(R[0], np.eye(3))), (cq - cp).tolist()
    (True, [[2.0, 2.0, 2.0]])
    """
    h = P.shape[0]
    G = sp.csr_matrix((np.ones(h), (label, np.arange(h))), shape=(k, h))
    cnt = np.asarray(G.sum(axis=1)).ravel()[:, None]
    cp = (G @ P) / cnt
    cq = (G @ Q) / cnt
    Pc = P - cp[label]
    Qc = Q - cq[label]
    H = (G @ (Pc[:, :, None] * Qc[:, None, :]).reshape(h, 9)).reshape(k, 3, 3)
    s = np.linalg.svd(H, compute_uv=False)
    R = max_trace_rotations(H)[0]
    R[s[:, 1] <= collinear_rel * s[:, 0]] = np.eye(3)
    return R, cp, cq
