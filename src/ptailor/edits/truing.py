"""Trued seams: where a step cuts a seam short or grows it, both its sides keep the length
ratio they have in the input (a pattern maker trues them: sides that were equal lose, or
gain, the same length).

Where the two panels of a seam meet an opening at different angles, each panel's own
iso-line (``shorten`` and ``extend`` with ``measure: pattern``) crosses its side of the seam
at a different length from the opening (a skirt's side seam 65.25 / 65.25 became 62.25 /
61.99 where its panels meet the hem 10 degrees apart), and a seam eased unevenly along its
length keeps its ratio only as a whole. :func:`seam_sides` lists a garment's seam curves
with their sides oriented alike; :func:`true_cut` moves a cut on the two sides of the seam
edge it crosses so that the kept sides keep the input's ratio; :func:`seam_copy_weights`
weighs the copies of a seam vertex on an opening for ``extend``'s new columns.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor import tolerances as tol
from ptailor.geometry.topology import edge_keys
from ptailor.model.garment import Garment
from ptailor.model.structure import structure


@dataclass(frozen=True)
class SeamSides:
    """A garment's seam edges, curve by curve, each with its two pattern sides.

    Attributes
    ----------
    curve : (s,) int array
        The seam curve of each seam edge (one per :class:`~ptailor.model.seams.Seam`).
    e3 : (s, 2) int array
        Its drape edge.
    side : (s, 2, 2) int array
        Its pattern edges: ``side[:, 0]`` on the curve's side ``a``, ``side[:, 1]`` on its
        side ``b`` (ends in ``e3``'s order); the sides of one curve are alike along it.
    length : (c, 2) float array
        Each curve's two side lengths in the pattern the sides were found in.
    """

    curve: np.ndarray
    e3: np.ndarray
    side: np.ndarray
    length: np.ndarray

    def edge_lengths(self, V2: np.ndarray) -> np.ndarray:
        """Both sides' length of every seam edge at ``V2``, ``(s, 2)`` float."""
        return np.linalg.norm(V2[self.side[:, :, 1]] - V2[self.side[:, :, 0]], axis=2)


def _self_sides(ea: np.ndarray, eb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The sides of a seam sewn to its own panel, oriented alike along the curve.

    :func:`ptailor.model.seams.seams` puts a self-seam's smaller half-edge first, which may
    change sides along the curve; the pattern edges of one side form a chain through shared
    pattern vertices (a pair's own two edges, which share a dart's tip, are not linked), so
    with exactly two chains each pair takes side ``a`` from the chain of the first pair's.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    k = len(ea)
    E = np.concatenate([ea, eb])
    n = int(E.max()) + 1
    B = coo_matrix((np.ones(4 * k), (np.repeat(np.arange(2 * k), 2), E.ravel())), (2 * k, n))
    M = (B.tocsr() @ B.T.tocsr()).tocoo()
    keep = (M.row % k) != (M.col % k)  # no link between a pair's own two sides
    G = coo_matrix((M.data[keep], (M.row[keep], M.col[keep])), (2 * k, 2 * k))
    n_comp, comp = connected_components(G, directed=False)
    if n_comp != 2:
        return ea, eb
    swap = comp[:k] != comp[0]
    return np.where(swap[:, None], eb, ea), np.where(swap[:, None], ea, eb)


def seam_sides(g: Garment) -> SeamSides:
    """The seam edges of ``g`` with their sides (see :class:`SeamSides`)."""
    curve, e3, side, length = [], [], [], []
    for i, sm in enumerate(structure(g).seams):  # a loop over seam curves
        ea, eb = sm.edges_a, sm.edges_b
        if sm.panels[0] == sm.panels[1]:
            ea, eb = _self_sides(ea, eb)
        S = np.stack([ea, eb], 1)
        curve.append(np.full(len(ea), i, dtype=np.int64))
        e3.append(sm.edges3)
        side.append(S)
        L = np.linalg.norm(g.V2[S[:, :, 1]] - g.V2[S[:, :, 0]], axis=2)
        length.append(L.sum(axis=0))
    if not curve:
        z = np.zeros((0, 2), dtype=np.int64)
        return SeamSides(curve=z[:, 0], e3=z, side=z.reshape(0, 2, 2), length=np.zeros((0, 2)))
    return SeamSides(
        curve=np.concatenate(curve),
        e3=np.concatenate(e3),
        side=np.concatenate(side),
        length=np.array(length, dtype=float),
    )


def _lookup(sides: SeamSides, a2: np.ndarray, b2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The seam edge and side (0 ``a``, 1 ``b``) of pattern edges ``(a2, b2)``, ``(r,)``
    each; ``-1`` for an edge on no seam side."""
    none = np.full(len(a2), -1, dtype=np.int64)
    if not len(sides.curve) or not len(a2):
        return none, none
    E = sides.side.reshape(-1, 2)  # row 2 j + side
    n = int(max(E.max(), a2.max(), b2.max())) + 1
    keys = edge_keys(E, n=n)
    order = np.argsort(keys, kind="stable")
    q = edge_keys(np.stack([a2, b2], 1), n=n)
    pos = np.minimum(np.searchsorted(keys[order], q), len(keys) - 1)
    found = keys[order][pos] == q
    hit = np.where(found, order[pos], -1)
    return np.where(found, hit // 2, -1), np.where(found, hit % 2, -1)


def true_cut(
    sides: SeamSides,
    V2: np.ndarray,
    s3: np.ndarray,
    a2: np.ndarray,
    b2: np.ndarray,
    t: np.ndarray,
    keep_a: np.ndarray,
    *,
    margin: float,
) -> np.ndarray:
    """Where to cut each side of the seam edges a split crosses, the seam trued.

    On a seam curve the split crosses once, the kept sides would be ``K_a + f_a |e_a|`` and
    ``K_b + f_b |e_b|`` (``K`` the sides of its wholly kept edges, ``f`` the kept fraction
    of the crossed edge's side). They become the nearest pair in the input's ratio
    ``r = L_b / L_a`` (``k_a = (k_a0 + r k_b0) / (1 + r^2)``, ``k_b = r k_a``), each side
    cut where its kept length is reached: sides that were equal lose the same length.
    Curves crossed more than once keep their cuts.

    Parameters
    ----------
    sides : SeamSides
        Of the garment being split (:func:`seam_sides`).
    V2 : (n2, 2) float array
        Its pattern.
    s3 : (n3,) float array
        The split's field on the drape vertices (kept where ``>= 0``).
    a2, b2 : (r,) int arrays
        The crossed pattern edges.
    t : (r,) float array
        Where each is cut, from ``a2``.
    keep_a : (r,) bool array
        The end ``a2`` is kept.
    margin : float, keyword-only
        A moved cut stays this far (in ``t``) from the edge's ends.

    Returns
    -------
    (r,) float array
        ``t`` with the trued seams' cuts moved (clipped to the edge: a seam whose cut would
        leave its crossed edge is met as nearly as that allows).
    """
    out = np.asarray(t, dtype=float).copy()
    if not len(sides.curve) or not len(a2):
        return out
    j, side = _lookup(sides, a2, b2)
    sv = s3[sides.e3]
    crossed = sv[:, 0] * sv[:, 1] < 0
    kept = (sv >= 0).all(axis=1)
    nc = len(sides.length)
    L = sides.edge_lengths(V2)
    K = np.stack([np.bincount(sides.curve[kept], L[kept, i], nc) for i in (0, 1)], 1)
    once = np.bincount(sides.curve[crossed], minlength=nc) == 1
    on = (j >= 0) & crossed[np.maximum(j, 0)] & once[sides.curve[np.maximum(j, 0)]]
    # both sides of the crossed edge must be among the rows
    f0 = np.full((len(L), 2), np.nan)
    f0[j[on], side[on]] = np.where(keep_a, out, 1.0 - out)[on]
    both = np.isfinite(f0).all(axis=1)
    on &= both[np.maximum(j, 0)]
    if not on.any():
        return out
    jj = j[on]
    c = sides.curve[jj]
    r = sides.length[c, 1] / np.maximum(sides.length[c, 0], tol.TINY)
    ka0 = K[c, 0] + f0[jj, 0] * L[jj, 0]
    kb0 = K[c, 1] + f0[jj, 1] * L[jj, 1]
    ka = (ka0 + r * kb0) / (1.0 + r * r)
    kept_len = np.where(side[on] == 0, ka, r * ka)
    mine = K[c, side[on]]
    f = (kept_len - mine) / np.maximum(L[jj, side[on]], tol.TINY)
    f = np.clip(f, margin, 1.0 - margin)
    out[on] = np.where(keep_a[on], f, 1.0 - f)
    return out


def seam_copy_weights(sides: SeamSides, cols: np.ndarray, vert3: np.ndarray) -> np.ndarray:
    """The input length of the seam side each copy of a seam vertex lies on, ``(c,)``.

    Where a seam reaches an opening its drape vertex has two pattern copies, one on each
    side of the seam: weighed by their sides' lengths, they grow the seam in its input
    ratio (as :func:`ptailor.edits.extend.drape.match_seam_steps` weighs them).

    Parameters
    ----------
    sides : SeamSides
    cols : (c,) int array
        Pattern vertices (an opening's columns).
    vert3 : (c,) int array
        The drape vertex of each.

    Returns
    -------
    (c,) float array
        NaN but where a drape vertex has exactly two copies among ``cols``, on the two
        sides of one seam curve (and on no other seam): a vertex where three panels meet,
        or whose copies lie on different seams, is left to the caller.
    """
    out = np.full(len(cols), np.nan)
    if not len(sides.curve) or not len(cols):
        return out
    ident = 2 * sides.curve[:, None] + np.arange(2)[None]  # (s, 2): curve and side
    ends = sides.side.reshape(-1, 2).ravel()  # row 2 j + side: the ends of edge j
    which = np.repeat(ident.ravel(), 2)
    colid = np.full(int(max(ends.max(), cols.max())) + 1, -1, dtype=np.int64)
    colid[cols] = np.arange(len(cols))
    ci = colid[ends]
    ok = ci >= 0
    pairs = np.unique(np.stack([ci[ok], which[ok]], 1), axis=0)
    count = np.bincount(pairs[:, 0], minlength=len(cols))
    one = pairs[count[pairs[:, 0]] == 1]
    cs = np.full(len(cols), -1, dtype=np.int64)  # the one (curve, side) of each column
    cs[one[:, 0]] = one[:, 1]
    _, grp = np.unique(vert3, return_inverse=True)
    ng = int(grp.max()) + 1
    lo = np.full(ng, np.iinfo(np.int64).max)
    hi = np.full(ng, -1, dtype=np.int64)
    np.minimum.at(lo, grp, cs)
    np.maximum.at(hi, grp, cs)
    copies = np.bincount(grp, minlength=ng)
    clean = (copies == 2) & (lo >= 0) & (lo // 2 == hi // 2) & (lo != hi)
    on = clean[grp]
    out[on] = sides.length[cs[on] // 2, cs[on] % 2]
    return out
