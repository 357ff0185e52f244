"""Rigid (rotation + translation, no scale) best fits of pattern panels."""

from __future__ import annotations

import numpy as np


def rigid_fit(X: np.ndarray, Y: np.ndarray, vlab: np.ndarray, n_panels: int) -> np.ndarray:
    """Move each panel of ``X`` by the rotation + translation that best fits it onto ``Y``.

    Parameters
    ----------
    X, Y : (n, 2) float arrays
        Moving and reference positions with the same vertices.
    vlab : (n,) int array
        Panel per vertex; vertices with -1 are returned unchanged.
    n_panels : int

    Returns
    -------
    (n, 2) float array
    """
    used = np.flatnonzero(vlab >= 0)
    lab = vlab[used]
    cnt = np.maximum(np.bincount(lab, minlength=n_panels), 1).astype(float)

    def centroid(P: np.ndarray) -> np.ndarray:
        return np.stack([np.bincount(lab, P[:, c], n_panels) for c in range(2)], 1) / cnt[:, None]

    cx, cy = centroid(X[used]), centroid(Y[used])
    a = X[used] - cx[lab]
    b = Y[used] - cy[lab]
    dot = np.bincount(lab, a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1], n_panels)
    crs = np.bincount(lab, a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], n_panels)
    ang = np.arctan2(crs, dot)
    c, s = np.cos(ang)[lab], np.sin(ang)[lab]
    out = X.copy()
    out[used] = np.stack([c * a[:, 0] - s * a[:, 1], s * a[:, 0] + c * a[:, 1]], 1) + cy[lab]
    return out
