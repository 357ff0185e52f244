"""Seam-side bending: a small stiffness against a seam side's turning changing.

A seam side that the length constraint holds longer than its cloth wants can gain length
by a sawtooth (every other vertex pushed out) instead of stretching, at an energy cost that
falls with the mesh's edge length: in the continuum the exact length constraint has no
minimum (ever finer wrinkles are ever cheaper), and on a production mesh its minimum is the
sawtooth (``docs/method.md``, "The other side"). A bending energy of each seam side, as a
curve,

    mu * integral (kappa - kappa_target)^2 ds,

makes the problem well posed: a wrinkle of wavelength ``lambda`` costs ``mu / lambda^2``
per unit of length gained, a smooth bend costs ``mu`` times its curvature change squared,
which on a panel of size ``L`` is about ``mu / L^3`` of its in-plane bending stiffness. The
discrete form, at a side's inner vertex ``k`` with edges ``i = (p, k)`` and ``o = (k, q)``
of target lengths ``l_i, l_o`` and target unit directions ``t_i, t_o``:

    2 mu / (l_i + l_o) * |u_o - u_i - sigma R (t_o - t_i)|^2,    u = e / l,

with ``u_o - u_i`` linear in the positions (the rows are fixed: one matrix for all steps)
and ``sigma R`` the similarity, one per panel, that best aligns the target turnings with
the current ones (weighted Procrustes): the term's own local step, so that its value is a
function of the positions whose gradient the global step sees, and a panel stretched or
turned as a whole is not bent. Two variants measured and dropped: each edge's own stretch
``s = |e| / l`` at the iterate in place of ``sigma``, and the triangles' rotations in place
of ``R``; neither is a minimiser of the term, so the local/global fixed point is not the
energy's stationary point and Newton steps drift or fail (the shared long-sleeve with both
armholes gathered, 4x: 83 iterations, against 35 with the panel similarity and 36 without
the term; at 1x with the triangles' rotations: the 100-iteration cap). Corners (a target
turning above ``method_tol.SEAM_BEND_CORNER_RAD``) are left out: their angle is the triangles'
business.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ptailor.geometry.topology import half_edges
from ptailor.method import tolerances as method_tol

__all__ = ["SeamBend", "seam_bend"]


@dataclass(frozen=True)
class SeamBend:
    """The bending rows of the seam sides' inner vertices.

    Attributes
    ----------
    S : (r, n) sparse matrix
        Row ``j``: ``u_o - u_i`` at vertex ``k[j]`` (``u = e / l`` over its target length).
    weight : (r,) float array
        ``2 mu / (l_i + l_o)`` per row.
    k, p, q : (r,) int arrays
        Each row's vertex, its predecessor and its successor along the boundary.
    li, lo : (r,) float arrays
        Target lengths of the edges ``(p, k)`` and ``(k, q)``.
    ti, to : (r, 2) float arrays
        Their target unit directions.
    panel : (r,) int array
        Each row's panel (its rows share one rotation).
    """

    S: sp.csr_matrix
    weight: np.ndarray
    k: np.ndarray
    p: np.ndarray
    q: np.ndarray
    li: np.ndarray
    lo: np.ndarray
    ti: np.ndarray
    to: np.ndarray
    panel: np.ndarray

    def matrix(self) -> sp.csr_matrix:
        """``S^T diag(weight) S``, ``(n, n)``: the term's part of each coordinate's system."""
        return (self.S.T @ sp.diags(self.weight) @ self.S).tocsr()

    def turning(self, X: np.ndarray | None) -> np.ndarray:
        """The target turnings ``sigma R (t_o - t_i)`` at ``X``, ``(r, 2)``, with ``sigma R``
        each panel's similarity that best aligns them with the current ``S @ X`` (weighted
        Procrustes; the term's own local step); at rest (``X`` None) ``t_o - t_i``."""
        if X is None:
            return self.to - self.ti
        b = self.to - self.ti
        g = self.S @ X
        nb = int(self.panel.max()) + 1
        w = self.weight
        c = np.bincount(self.panel, w * (g * b).sum(1), nb)
        s = np.bincount(self.panel, w * (b[:, 0] * g[:, 1] - b[:, 1] * g[:, 0]), nb)
        bb = np.bincount(self.panel, w * (b * b).sum(1), nb)
        r = np.hypot(c, s)
        ok = (r > 0) & (bb > 0)
        inv = np.divide(1.0, bb, out=np.zeros_like(bb), where=ok)
        c = np.where(ok, c * inv, 1.0)[self.panel]
        s = (s * inv)[self.panel]
        return np.stack([c * b[:, 0] - s * b[:, 1], s * b[:, 0] + c * b[:, 1]], axis=1)

    def rhs(self, X: np.ndarray | None) -> np.ndarray:
        """The term's right-hand side ``S^T (weight * turning(X))``, ``(n, 2)``."""
        return self.S.T @ (self.weight[:, None] * self.turning(X))

    def energy(self, X: np.ndarray) -> float:
        """The term's value at ``X``."""
        d = self.S @ X - self.turning(X)
        return float(self.weight @ (d * d).sum(1))


def seam_bend(
    F2: np.ndarray,
    targets: np.ndarray,
    vertices: np.ndarray,
    mu: np.ndarray,
    panel: np.ndarray,
    *,
    corner: float = method_tol.SEAM_BEND_CORNER_RAD,
) -> SeamBend | None:
    """The bending rows of the seam sides through ``vertices``.

    Parameters
    ----------
    F2 : (m, 3) int array
        Pattern triangles (counter-clockwise: boundary half-edges run along each outline).
    targets : (m, 2, 2) float array
        Per-triangle target edge vectors ``[e01, e02]`` as columns.
    vertices : (v,) int array
        The seam vertices (:meth:`ptailor.method.ease.SeamEase.vertices`).
    mu : (n,) float array
        Bending stiffness per vertex (length cubed).
    panel : (n,) int array
        Panel per vertex.
    corner : float
        Vertices whose target turning exceeds this (radians) get no row.

    Returns
    -------
    SeamBend or None
        None when no seam vertex has both boundary neighbours.
    """
    n = len(mu)
    h = half_edges(F2)
    key = np.minimum(h[:, 0], h[:, 1]) * n + np.maximum(h[:, 0], h[:, 1])
    _, inv, cnt = np.unique(key, return_inverse=True, return_counts=True)
    bnd = np.flatnonzero(cnt[inv] == 1)
    out_h = np.full(n, -1, dtype=np.int64)
    in_h = np.full(n, -1, dtype=np.int64)
    out_h[h[bnd, 0]] = bnd
    in_h[h[bnd, 1]] = bnd
    vertices = np.asarray(vertices, dtype=np.int64)
    k = vertices[(out_h[vertices] >= 0) & (in_h[vertices] >= 0)]
    hi, ho = in_h[k], out_h[k]

    def edge(he: np.ndarray) -> np.ndarray:
        T = targets[he // 3]
        j = (he % 3)[:, None]
        e01, e02 = T[:, :, 0], T[:, :, 1]
        return np.where(j == 0, e01, np.where(j == 1, e02 - e01, -e02))

    vi, vo = edge(hi), edge(ho)
    li, lo = np.linalg.norm(vi, axis=1), np.linalg.norm(vo, axis=1)
    ok = (li > 0) & (lo > 0) & (mu[k] > 0)
    ti = vi / np.where(ok, li, 1.0)[:, None]
    to = vo / np.where(ok, lo, 1.0)[:, None]
    turn = np.arctan2(ti[:, 0] * to[:, 1] - ti[:, 1] * to[:, 0], (ti * to).sum(1))
    ok &= np.abs(turn) < corner
    if not ok.any():
        return None
    k, hi, ho, li, lo, ti, to = k[ok], hi[ok], ho[ok], li[ok], lo[ok], ti[ok], to[ok]
    p, q = h[hi, 0], h[ho, 1]
    r = len(k)
    S = sp.csr_matrix(
        (
            np.concatenate([1.0 / li, -(1.0 / li + 1.0 / lo), 1.0 / lo]),
            (np.tile(np.arange(r), 3), np.concatenate([p, k, q])),
        ),
        shape=(r, n),
    )
    return SeamBend(S, mu[k] * 2.0 / (li + lo), k, p, q, li, lo, ti, to, panel[k])
