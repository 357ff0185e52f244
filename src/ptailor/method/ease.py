"""Seam ease: each seam's two sides keep their designed length ratio, exactly.

A seam edge joins two pattern edges, side ``a`` and side ``b``, that become one drape edge.
Their length ratio ``|e_b| / |e_a|`` is part of the design (ease, a gathered sleeve cap).
With the current edge directions ``d`` (unit vectors of the last iterate), each side's
length is linear in the positions, ``|e| ~ d . e``, so keeping the ratio ``r`` is the linear
equality::

    (d_b . (x_b1 - x_b0) - r d_a . (x_a1 - x_a0)) / sqrt(1 + r^2) = 0

added to the stitching's global step with Lagrange multipliers
(:func:`ptailor.method.solver.stitch`) and re-linearised every iteration; at convergence
the directions are the edges' own, so the lengths meet the ratio exactly.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
import scipy.sparse as sp

from ptailor import tolerances as tol
from ptailor.geometry.topology import half_edges
from ptailor.method import tolerances as method_tol
from ptailor.model.seams import seam_curve_labels, seam_halfedges

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
    curve : (s,) int array, optional
        With one row per edge pair: the seam curve of each pair (-1: none), whose two
        sides' totals keep ``total``: each pair's ratio is scaled, one factor per curve,
        so that ``sum L_b = total * sum L_a`` along the curve while the pairs keep their
        ratios' proportions (see :meth:`ratios`).
    total : (c,) float array, optional
        Target ratio of each curve's side totals.
    """

    ea: np.ndarray
    eb: np.ndarray
    row: np.ndarray
    ratio: np.ndarray
    curve: np.ndarray | None = None
    total: np.ndarray | None = None

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

    def ratios(self, X: np.ndarray) -> np.ndarray:
        """Each row's target ratio at ``X``, ``(k,)`` float: :attr:`ratio`, scaled on each
        seam curve by ``total * sum L_a / sum (ratio L_a)`` (``L_a`` at ``X``).

        One ratio per edge pair keeps the ease where the design put it (balance points
        meet all along the seam), but as the edit lengthens some of a curve's edges more
        than others, the totals drift from the curve's ratio (0.1 mm on a 50 cm armhole).
        The one factor per curve, taken at the iterate like the edges' directions, makes
        both hold at the fixed point: the curve's totals at their ratio, and its pairs at
        ratios in the original proportions."""
        if self.curve is None or self.total is None:
            return self.ratio
        la = np.linalg.norm(X[self.ea[:, 1]] - X[self.ea[:, 0]], axis=1)
        on = self.curve >= 0
        c, nc = self.curve[on], len(self.total)
        want = self.total * np.bincount(c, la[on], nc)
        have = np.bincount(c, (self.ratio[self.row] * la)[on], nc)
        with np.errstate(divide="ignore", invalid="ignore"):
            f = np.where(have > 0, want / have, 1.0)
        f = np.where(np.isfinite(f) & (f > 0), f, 1.0)
        gain = np.ones(len(la))
        gain[on] = f[c]
        return (
            self.ratio
            * np.bincount(self.row, gain, self.n_rows)
            / np.bincount(self.row, minlength=self.n_rows)
        )

    def violation(self, X: np.ndarray) -> np.ndarray:
        """Relative mismatch ``|L_b - r L_a| / L_b`` of each row (``r`` its
        :meth:`ratios` at ``X``), ``(k,)`` float."""
        la, lb = self.lengths(X)
        return np.abs(lb - self.ratios(X) * la) / np.maximum(lb, tol.TINY)

    @property
    def n_totals(self) -> int:
        """Number of seam curves whose totals are constrained, ``t``."""
        return 0 if self.curve is None or self.total is None else len(self.total)

    def rows(self, X: np.ndarray) -> sp.csr_matrix:
        """The constraints linearised at positions ``X``.

        Parameters
        ----------
        X : (n, 2) float array
            Current positions.

        Returns
        -------
        (k + t, 2n) sparse matrix
            Over unknowns ``[x; y]``; row ``g < k`` is ``(L_b - r_g L_a) / sqrt(1 + r_g^2)``
            (``r_g`` the row's :meth:`ratios` at ``X``), row ``k + c`` the same for curve
            ``c``'s totals at its ``total``, with each edge's length replaced by its
            projection on its current direction.
        """
        n, k = len(X), self.n_rows

        def side(E, coef, row) -> tuple[np.ndarray, ...]:
            e = X[E[:, 1]] - X[E[:, 0]]
            d = e / np.maximum(np.linalg.norm(e, axis=1), tol.TINY)[:, None]
            d = d * coef[:, None]
            rows = np.tile(row, 4)
            cols = np.concatenate([E[:, 1], E[:, 1] + n, E[:, 0], E[:, 0] + n])
            vals = np.concatenate([d[:, 0], d[:, 1], -d[:, 0], -d[:, 1]])
            return rows, cols, vals

        coef_a, coef_b = self._coefficients(self.ratios(X))
        parts = [side(self.ea, coef_a, self.row), side(self.eb, coef_b, self.row)]
        if self.n_totals:
            on = self.curve >= 0
            c = self.curve[on]
            norm = 1.0 / np.sqrt(1.0 + self.total**2)
            parts.append(side(self.ea[on], -(self.total * norm)[c], k + c))
            parts.append(side(self.eb[on], norm[c], k + c))
        r, c, v = (np.concatenate(x) for x in zip(*parts, strict=True))
        return sp.csr_matrix((v, (r, c)), shape=(k + self.n_totals, 2 * n))

    def total_columns(self, X: np.ndarray) -> np.ndarray | None:
        """The rows' derivatives in each curve's factor (:meth:`ratios`), ``(k + t, t)``
        float, or None without curve totals.

        The step treats each curve's factor as an unknown of its own, beside the
        positions: the pairs' rows keep their proportions whatever it is, and the curve's
        total row fixes it, so one step meets both (the factor taken at the iterate alone
        would lag a step behind and slow the iterations about twofold)."""
        t = self.n_totals
        if not t:
            return None
        k = self.n_rows
        la = np.linalg.norm(X[self.ea[:, 1]] - X[self.ea[:, 0]], axis=1)
        r = self.ratios(X)[self.row]
        on = self.curve >= 0
        B = np.zeros((k + t, t))
        # d/df of (L_b - ratio f L_a) / sqrt(1 + (ratio f)^2), the norm taken as constant
        np.add.at(
            B,
            (self.row[on], self.curve[on]),
            -(self.ratio[self.row] * la / np.sqrt(1.0 + r**2))[on],
        )
        return B

    def _coefficients(self, ratio: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Each edge's coefficient in its row for the rows' ``ratio``: ``-r / sqrt(1 + r^2)``
        on side a, ``1 / sqrt(1 + r^2)`` on side b, two ``(s,)`` float arrays."""
        norm = 1.0 / np.sqrt(1.0 + ratio**2)
        return -(ratio * norm)[self.row], norm[self.row]

    def curvature(
        self, X: np.ndarray, lam: np.ndarray, *, min_rel: float = method_tol.SEAM_CURVATURE_MIN_REL
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
        lam : (k,) or (k + t,) float array
            Multipliers of the rows (``A x + C^T lam = b``), the curves' total rows'
            last (:meth:`rows`).
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
        ca, cb = self._coefficients(self.ratios(X))
        E = np.concatenate([self.ea, self.eb])
        c_a, c_b = ca * lam[self.row], cb * lam[self.row]
        if self.n_totals and len(lam) > self.n_rows:  # the curves' total rows, too
            on = self.curve >= 0
            cv = self.curve[on]
            norm = 1.0 / np.sqrt(1.0 + self.total**2)
            lt = lam[self.n_rows :][cv]
            c_a[on] -= (self.total * norm)[cv] * lt
            c_b[on] += norm[cv] * lt
        c = np.concatenate([c_a, c_b])
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
    min_length_rel: float = method_tol.SEAM_MIN_LENGTH_REL,
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
    curve = seam_curve_labels(F3, pairs[ok], face_panel)
    row = np.arange(len(ea)) if granularity == "edge" else curve
    k = int(row.max()) + 1
    ratio = np.bincount(row, lb, k) / np.bincount(row, la, k)
    gain = _gains(pa, pb, factors)
    # a row's pairs share their panels, so one gain per row
    ratio = ratio * np.bincount(row, gain, k) / np.bincount(row, minlength=k)
    if granularity != "edge":
        return SeamEase(ea=ea, eb=eb, row=row, ratio=ratio)
    number, total = _curve_totals(curve, pa, pb, la, lb * gain, ratio[row])
    return SeamEase(ea=ea, eb=eb, row=row, ratio=ratio, curve=number[curve], total=total)


def _gains(
    pa: np.ndarray, pb: np.ndarray, factors: dict[tuple[int, int], float] | None
) -> np.ndarray:
    """Per edge pair (sides on panels ``pa`` and ``pb``), the factor its ratio changes by
    (:func:`seam_ease`'s ``factors``; 1 elsewhere)."""
    gain = np.ones(len(pa))
    for (p, q), f in (factors or {}).items():  # a loop over the gathered seams
        if p != q:
            gain[(pa == p) & (pb == q)] = 1.0 / f  # ratio is side b (on q) over side a
            gain[(pa == q) & (pb == p)] = f
    return gain


def _curve_totals(
    curve: np.ndarray,
    pa: np.ndarray,
    pb: np.ndarray,
    la: np.ndarray,
    lb_gained: np.ndarray,
    pair_ratio: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """The seam curves that get a total row: ``(number, total)``, each curve's number
    among them (-1 for none) and their total ratios.

    The curves' totals: where each curve's pairs all run from one panel to another (a
    tube's own seam, both sides on one panel, keeps its pairs' ratios only) and their
    ratios ``pair_ratio`` differ; ``lb_gained`` is side b's length times its gain."""
    nc = int(curve.max()) + 1
    lo = np.bincount(curve, pa < pb, nc)
    hi = np.bincount(curve, pa > pb, nc)
    cnt = np.bincount(curve, minlength=nc)
    whole = (lo == cnt) | (hi == cnt)
    total = np.bincount(curve, lb_gained, nc) / np.maximum(np.bincount(curve, la, nc), tol.TINY)
    # a curve whose pairs all have about its total's ratio needs no total row: the pairs
    # hold the total to that fraction of its length
    off = np.abs(pair_ratio / total[curve] - 1.0) > method_tol.SEAM_TOTAL_UNIFORM_REL
    whole &= np.bincount(curve, off, nc) > 0
    number = np.full(nc, -1, dtype=np.int64)
    number[whole] = np.arange(int(whole.sum()))  # the whole curves, renumbered
    return number, total[whole]


def side_zigzag(V0: np.ndarray, V1: np.ndarray, E: np.ndarray) -> np.ndarray:
    """How much more each seam-side vertex's turning alternates with its neighbours' in
    ``V1`` than in ``V0``: a sawtooth the stitching made, not a bend.

    At a vertex ``k`` of a side (its edges ``u -> k`` and ``k -> w`` both in ``E``) with
    turning angle ``t_k``, a bend turns neighbours alike and a sawtooth (every other vertex
    pushed out) alternately, so its alternation is ``|t_k - (t_u + t_w) / 2|`` where the
    neighbours have a turning too; the measure is its growth from ``V0`` to ``V1``
    (an edit that evens out a jagged outline lowers it: 0 then), taken as the least of the
    vertex's and its two neighbours' growths: a sawtooth alternates along a run of vertices,
    while a corner or a single kink whose angle the edit changes by ``d`` grows ``d`` at its
    vertex and ``d / 2`` beside it (the shared dress loosened at 1x: 33-44 degree kinks at one
    vertex of two bodice panels, no sawtooth).

    A side the seam constraint stretches (its panel wants it shorter than its partner asks)
    can gain true length by zigzagging at a cost that a fine mesh makes small: the exact
    length constraint then has a sawtooth minimum (measured on the shared long-sleeve at 16x
    its resolution: 0.58 rad at every other vertex of the back's side seam).

    Parameters
    ----------
    V0, V1 : (n, 2) float arrays
        The pattern before and after.
    E : (s, 2) int array
        The seam sides' edges as half-edges of their triangles (each side a chain).

    Returns
    -------
    (n,) float array
        The growth of the alternation in radians per vertex, ``>= 0`` (0 off the sides'
        inner vertices and where a neighbour is not one).
    """
    n = len(V0)
    E = np.asarray(E, dtype=np.int64).reshape(-1, 2)
    out = np.zeros(n)
    if not len(E):
        return out
    prev = np.full(n, -1, dtype=np.int64)
    nxt = np.full(n, -1, dtype=np.int64)
    prev[E[:, 1]] = E[:, 0]
    nxt[E[:, 0]] = E[:, 1]
    k = np.flatnonzero((prev >= 0) & (nxt >= 0))

    def alternation(V: np.ndarray) -> np.ndarray:
        a = V[k] - V[prev[k]]
        b = V[nxt[k]] - V[k]
        t = np.full(n, np.nan)
        t[k] = np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], (a * b).sum(1))
        return np.abs(t[k] - 0.5 * (t[prev[k]] + t[nxt[k]]))  # NaN without both turnings

    grow = np.zeros(n)
    g = alternation(V1) - alternation(V0)
    ok = np.isfinite(g)
    grow[k[ok]] = np.maximum(g[ok], 0.0)
    # a sawtooth alternates along a run: the least growth of a vertex and its neighbours
    # (an isolated kink of d grows d at its vertex but only d / 2 beside it)
    out[k] = np.minimum(grow[k], np.minimum(grow[prev[k]], grow[nxt[k]]))
    return out
