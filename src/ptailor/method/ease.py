"""Seam ease: each seam's two sides keep their designed length ratio, exactly.

A seam edge joins two pattern edges, side ``a`` and side ``b``, that become one drape edge.
Their length ratio ``|e_b| / |e_a|`` is part of the design (ease, a gathered sleeve cap).
With the current edge directions ``d`` (unit vectors of the last iterate), each side's
length is linear in the positions, ``|e| ~ d . e``, so keeping the ratio ``r`` is the linear
equality::

    (d_b . (x_b1 - x_b0) - r d_a . (x_a1 - x_a0)) / sqrt(1 + r^2) = 0

added to the stitching's global step with Lagrange multipliers
(:func:`ptailor.method.stitch.stitch`) and re-linearised every iteration; at convergence
the directions are the edges' own, so the lengths meet the ratio exactly.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
import scipy.sparse as sp

from ptailor import tolerances as tol
from ptailor.model.seams import half_edges, seam_halfedges

Granularity = Literal["edge", "seam"]


@dataclass(frozen=True)
class SeamEase:
    """Seam-length constraints, one row per seam edge pair (or per seam curve).

    Attributes
    ----------
    ea, eb : (s, 2) int arrays
        Pattern edges (vertex indices into ``V2``) of the two sides of each seam edge.
    row : (s,) int array
        The constraint row each edge pair belongs to.
    ratio : (k,) float array
        Target length ratio ``L_b / L_a`` of each row.
    """

    ea: np.ndarray
    eb: np.ndarray
    row: np.ndarray
    ratio: np.ndarray

    @property
    def n_rows(self) -> int:
        """Number of constraints ``k``."""
        return len(self.ratio)

    def vertices(self) -> np.ndarray:
        """Pattern vertices the constraints touch, sorted, ``(q,)`` int."""
        return np.unique(np.concatenate([self.ea.ravel(), self.eb.ravel()]))

    def lengths(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Side lengths ``(L_a, L_b)`` of each row, two ``(k,)`` float arrays, at ``X``."""
        la = np.linalg.norm(X[self.ea[:, 1]] - X[self.ea[:, 0]], axis=1)
        lb = np.linalg.norm(X[self.eb[:, 1]] - X[self.eb[:, 0]], axis=1)
        k = self.n_rows
        return np.bincount(self.row, la, k), np.bincount(self.row, lb, k)

    def violation(self, X: np.ndarray) -> np.ndarray:
        """Relative mismatch ``|L_b - r L_a| / L_b`` of each row, ``(k,)`` float."""
        la, lb = self.lengths(X)
        return np.abs(lb - self.ratio * la) / np.maximum(lb, 1e-300)

    def rows(self, X: np.ndarray) -> sp.csr_matrix:
        """The constraints linearised at positions ``X``.

        Parameters
        ----------
        X : (n, 2) float array
            Current positions.

        Returns
        -------
        (k, 2n) sparse matrix
            Over unknowns ``[x; y]``; row ``g`` is ``(L_b - r_g L_a) / sqrt(1 + r_g^2)``
            with each edge's length replaced by its projection on its current direction.
        """
        n = len(X)

        def side(E: np.ndarray, coef: np.ndarray) -> tuple[np.ndarray, ...]:
            e = X[E[:, 1]] - X[E[:, 0]]
            d = e / np.maximum(np.linalg.norm(e, axis=1), 1e-300)[:, None]
            d = d * coef[:, None]
            rows = np.tile(self.row, 4)
            cols = np.concatenate([E[:, 1], E[:, 1] + n, E[:, 0], E[:, 0] + n])
            vals = np.concatenate([d[:, 0], d[:, 1], -d[:, 0], -d[:, 1]])
            return rows, cols, vals

        coef_a, coef_b = self._coefficients()
        ra, ca, va = side(self.ea, coef_a)
        rb, cb, vb = side(self.eb, coef_b)
        return sp.csr_matrix(
            (np.concatenate([va, vb]), (np.concatenate([ra, rb]), np.concatenate([ca, cb]))),
            shape=(self.n_rows, 2 * n),
        )

    def _coefficients(self) -> tuple[np.ndarray, np.ndarray]:
        """Each edge's coefficient in its row: ``-r / sqrt(1 + r^2)`` on side a,
        ``1 / sqrt(1 + r^2)`` on side b, two ``(s,)`` float arrays."""
        norm = 1.0 / np.sqrt(1.0 + self.ratio**2)
        return -(self.ratio * norm)[self.row], norm[self.row]

    def curvature(
        self, X: np.ndarray, lam: np.ndarray, *, min_rel: float = tol.SEAM_CURVATURE_MIN_REL
    ) -> tuple[sp.csr_matrix, np.ndarray]:
        """The constraints' curvature at ``X`` under multipliers ``lam``, projected.

        A side's length ``|e|`` is linear along its direction ``d`` but curved across it:
        its Hessian in the edge vector is ``n n^T / |e|`` with ``n`` the unit normal of the
        edge. Row ``g`` weighted by its multiplier ``lam_g`` adds, for each of its edges
        with coefficient ``c`` (see :meth:`rows`), ``lam_g c n n^T / |e|`` to the Hessian of
        the Lagrangian. Kept where it is positive (the side the panel pushes against the
        constraint: without it, that side's edges can turn, zigzag, and keep their
        projected length while growing their true length), dropped where negative (the
        Hessian projected onto the positive semi-definite cone, as projected Newton does).

        The global step adds ``1/2 sum_e kappa_e (n_e . (e(x) - e(X)))^2``: zero at
        ``X``, so a fixed point of the iteration is unchanged by it.

        Parameters
        ----------
        X : (n, 2) float array
            Where the constraints are linearised.
        lam : (k,) float array
            Multipliers of the rows (``A x + C^T lam = b``).
        min_rel : float, keyword-only
            Edges whose weight is below this fraction of the largest get no row: they
            change the step by little and each row costs a row of the step's dense solve
            (about half the rows of a loosened tee; the fixed point is the same).

        Returns
        -------
        P : (p, 2n) sparse matrix
            One row per kept edge over unknowns ``[x; y]``: ``n_e . (x_1 - x_0)``.
        kappa : (p,) float array
            Each row's curvature weight, ``> 0``.
        """
        n = len(X)
        ca, cb = self._coefficients()
        E = np.concatenate([self.ea, self.eb])
        c = np.concatenate([ca, cb]) * np.concatenate([lam[self.row], lam[self.row]])
        e = X[E[:, 1]] - X[E[:, 0]]
        length = np.linalg.norm(e, axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            kappa = np.where((c > 0) & (length > 0), c / length, 0.0)
        keep = (kappa > 0) & (kappa >= min_rel * kappa.max(initial=0.0))
        E, e, length, kappa = E[keep], e[keep], length[keep], kappa[keep]
        nx, ny = -e[:, 1] / length, e[:, 0] / length
        p = len(E)
        P = sp.csr_matrix(
            (
                np.concatenate([nx, ny, -nx, -ny]),
                (
                    np.tile(np.arange(p), 4),
                    np.concatenate([E[:, 1], E[:, 1] + n, E[:, 0], E[:, 0] + n]),
                ),
            ),
            shape=(p, 2 * n),
        )
        return P, kappa


def seam_ease(
    F3: np.ndarray,
    F2: np.ndarray,
    V2: np.ndarray,
    *,
    face_panel: np.ndarray,
    factors: dict[tuple[int, int], float] | None = None,
    granularity: Granularity = "edge",
    min_length_rel: float = 1e-6,
    pairs: np.ndarray | None = None,
) -> SeamEase | None:
    """The seam-ease constraints of a garment, at the ratios its pattern ``V2`` has.

    Parameters
    ----------
    F3, F2 : (m, 3) int arrays
        Drape and pattern triangles.
    V2 : (n, 2) float array
        The pattern whose ratios are kept (the input's).
    face_panel : (m,) int array
        Panel index of each triangle.
    factors : dict, optional
        ``{(p, q): f}``: on seams between panels ``p`` and ``q`` the side on ``p`` becomes
        ``f`` times longer relative to the side on ``q`` than it was (a gather a step asked
        for).
    granularity : {"edge", "seam"}
        One row per seam edge pair (balance points all along the seam meet), or one per
        seam curve (only the totals match).
    min_length_rel : float
        Edge pairs with a side shorter than this times the mean seam edge get no row.
    pairs : (s, 2) int array, optional
        ``seam_halfedges(F3, F2)`` when the caller already has it (a garment's
        :attr:`~ptailor.model.structure.GarmentStructure.seam_halfedges`); computed
        otherwise.

    Returns
    -------
    SeamEase or None
        None when the garment has no seams.
    """
    pairs = seam_halfedges(F3, F2) if pairs is None else pairs
    if len(pairs) == 0:
        return None
    h2 = half_edges(F2)
    ea, eb = h2[pairs[:, 0]], h2[pairs[:, 1]]
    pa, pb = face_panel[pairs[:, 0] // 3], face_panel[pairs[:, 1] // 3]
    la = np.linalg.norm(V2[ea[:, 1]] - V2[ea[:, 0]], axis=1)
    lb = np.linalg.norm(V2[eb[:, 1]] - V2[eb[:, 0]], axis=1)
    ok = np.minimum(la, lb) > min_length_rel * float(np.mean(np.concatenate([la, lb])))
    ea, eb, pa, pb, la, lb = ea[ok], eb[ok], pa[ok], pb[ok], la[ok], lb[ok]
    if len(ea) == 0:
        return None
    if granularity == "edge":
        row = np.arange(len(ea))
    else:
        from ptailor.model.seams import seam_curve_labels

        row = seam_curve_labels(F3, pairs[ok], face_panel)
    k = int(row.max()) + 1
    ratio = np.bincount(row, lb, k) / np.bincount(row, la, k)
    if factors:
        gain = np.ones(len(ea))
        for (p, q), f in factors.items():  # a loop over the gathered seams
            if p != q:
                gain[(pa == p) & (pb == q)] = 1.0 / f  # ratio is side b (on q) over side a
                gain[(pa == q) & (pb == p)] = f
        # a row's pairs share their panels, so one gain per row
        ratio = ratio * np.bincount(row, gain, k) / np.bincount(row, minlength=k)
    return SeamEase(ea=ea, eb=eb, row=row, ratio=ratio)
