"""Matching a CAD file's pieces to the panels of the triangulated pattern they outline.

A piece matches by position (its outline lies on the panel's outer boundary) or, when it
was moved in the CAD file, by shape: a rigid fit (reflections allowed) from the outlines'
principal axes, refined by ICP against the panel's boundary segments. Pieces and panels
are paired by an assignment over the mean outline distances, so each panel gets at most
one piece. A piece cut more than once (``Quantity: 2``) claims further panels by shape.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor import tolerances as tol
from ptailor.errors import PtailorError
from ptailor.geometry.rotations import rigid_fit
from ptailor.geometry.segments import segment_feet
from ptailor.model.garment import Panel
from ptailor.model.pieces import Piece
from ptailor.model.polyline import resample_closed, signed_area
from ptailor.pieces.draw import outer_loop


@dataclass(frozen=True)
class PieceMatch:
    """Which panel a piece outlines, and the rigid map from piece to panel coordinates.

    Attributes
    ----------
    piece : int
        Index into the pieces.
    panel : int
        Index into the panels.
    how : str
        ``position`` (the piece lies on the panel) or ``shape`` (it was moved).
    R : (2, 2) float array
        Rotation or reflection; panel point = ``R @ piece point + t``.
    t : (2,) float array
    residual : float
        Mean distance between the fitted outlines, relative to the piece's diagonal.
    distance : float
        The same mean distance, in the pattern's units (a seam allowance shows here).
    fold : bool
        The piece is cut on the fold: its unfolded whole (mirrored across the fold line)
        is what matched the panel; it is carried and written back as the half.
    """

    piece: int
    panel: int
    how: str
    R: np.ndarray
    t: np.ndarray
    residual: float
    distance: float = 0.0
    fold: bool = False

    def to_panel(self, X: np.ndarray) -> np.ndarray:
        """Piece coordinates ``(k, 2)`` to panel coordinates."""
        return X @ self.R.T + self.t

    def to_piece(self, Y: np.ndarray) -> np.ndarray:
        """Panel coordinates ``(k, 2)`` back to piece coordinates."""
        return (Y - self.t) @ self.R


def piece_curve(piece: Piece) -> np.ndarray:
    """The closed curve a piece is matched by: its sew line when it has one, else its
    outline, ``(k, 2)``."""
    return piece.sew if piece.sew is not None else piece.outline


class ClosedCurve:
    """A closed polyline that answers nearest-point queries on its segments.

    Candidates come from samples along the segments (about 4,000 per curve, at least one
    per segment end) in a k-d tree: a segment near the query has a sample within half the
    spacing of the foot point, however long the segment, so the answer is exact for points
    on the curve and within half a spacing (1/8,000 of the perimeter) elsewhere.

    Parameters
    ----------
    P : (k, 2) float array
        The polyline's points; the last joins the first.
    """

    def __init__(self, P: np.ndarray) -> None:
        from scipy.spatial import cKDTree  # 0.1 s of imports a run without CAD pieces skips

        self.A = P
        self.B = np.roll(P, -1, axis=0)
        seg = np.linalg.norm(self.B - self.A, axis=1)
        h = max(float(seg.sum()) / tol.PIECE_CURVE_SAMPLES, tol.TINY)
        count = np.ceil(seg / h).astype(np.int64) + 1
        sid = np.repeat(np.arange(len(P)), count)
        start = np.repeat(np.cumsum(count) - count, count)
        t = (np.arange(len(sid)) - start) / np.maximum(count[sid] - 1, 1)
        samples = self.A[sid] + t[:, None] * (self.B - self.A)[sid]
        self.sid = sid
        self.tree = cKDTree(samples)
        self.k = min(8, len(sid))

    def nearest(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Distance from each point ``(j, 2)`` to the curve, and the nearest points."""
        d, Q, _ = self._nearest(X)
        return d, Q

    def nearest_segment(self, X: np.ndarray) -> np.ndarray:
        """The segment ``(j,)`` (``i``: ``P[i] -> P[i + 1]``) nearest each point ``(j, 2)``."""
        return self._nearest(X)[2]

    def _nearest(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        _, idx = self.tree.query(X, k=self.k)
        seg = self.sid[np.asarray(idx).reshape(len(X), self.k)]
        d, Q = segment_feet(X[:, None, :], self.A[seg], self.B[seg])
        best = np.argmin(d, axis=1)
        r = np.arange(len(X))
        return d[r, best], Q[r, best], seg[r, best]


def _outline_distance(A: np.ndarray, ca: ClosedCurve, B: np.ndarray, cb: ClosedCurve) -> float:
    """Symmetric mean distance between outlines ``ca`` and ``cb``, sampled as ``A``, ``B``."""
    return 0.5 * float(cb.nearest(A)[0].mean() + ca.nearest(B)[0].mean())


def icp_fit(
    A: np.ndarray,
    cb: ClosedCurve,
    R: np.ndarray,
    t: np.ndarray,
    diag: float,
    *,
    iterations: int = tol.PIECE_ICP_ITER,
) -> tuple[np.ndarray, np.ndarray]:
    """Refine the rigid map ``(R, t)`` of outline samples ``A`` onto curve ``cb`` by ICP
    against its segments (a reflection stays one), until a step moves it by less than
    ``PIECE_ICP_STILL`` or after ``iterations`` steps."""
    reflect = bool(np.linalg.det(R) < 0)
    for _ in range(iterations):
        _, Q = cb.nearest(A @ R.T + t)
        R1, t1 = rigid_fit(A, Q, reflect=reflect)
        step = np.abs(R1 - R).max() + np.abs(t1 - t).max() / max(diag, tol.TINY)
        R, t = R1, t1
        if step < tol.PIECE_ICP_STILL:  # converged: the next steps would not move it
            break
    return R, t


def fit_residual(A: np.ndarray, R, t, cb: ClosedCurve, B: np.ndarray, diag: float) -> float:
    """Symmetric mean distance of ``A`` moved by ``(R, t)`` and curve ``cb`` (sampled as
    ``B``), over ``diag``."""
    moved = A @ R.T + t
    return _outline_distance(moved, ClosedCurve(moved), B, cb) / diag


def shape_fits(
    A: np.ndarray,
    cb: ClosedCurve,
    B: np.ndarray,
    diag: float,
    *,
    iterations: int = tol.PIECE_ICP_ITER,
) -> list[tuple[np.ndarray, np.ndarray, float]]:
    """Rigid fits of outline samples ``A`` onto curve ``cb`` (sampled as ``B``).

    Principal axes give four starts (two rotations, two reflections); ICP against the
    curve's segments refines each (:func:`icp_fit`). A symmetric outline fits more than one
    way equally well: the caller that can tell them apart (by where the panel sits in 3D)
    gets all four.

    Returns
    -------
    list of (R, t, residual)
        Panel point = ``R @ A point + t``; residual = symmetric mean outline distance over
        ``diag``; in the order of the starts (the principal axes as they are first).
    """
    ca, cb0 = A.mean(axis=0), B.mean(axis=0)
    _, Ea = np.linalg.eigh(np.cov((A - ca).T))
    _, Eb = np.linalg.eigh(np.cov((B - cb0).T))
    fits = []
    for sx in (1.0, -1.0):  # the four axis pairings
        for sy in (1.0, -1.0):
            R = Eb @ np.diag([sx, sy]) @ Ea.T
            R, t = icp_fit(A, cb, R, cb0 - R @ ca, diag, iterations=iterations)
            fits.append((R, t, fit_residual(A, R, t, cb, B, diag)))
    return fits


def _fit_shape(
    A: np.ndarray, cb: ClosedCurve, B: np.ndarray, diag: float
) -> tuple[np.ndarray, np.ndarray, float]:
    """The best of :func:`shape_fits`; of fits equally good (a symmetric outline), the first
    start's."""
    fits = shape_fits(A, cb, B, diag)
    best = min(f[2] for f in fits)
    return next(f for f in fits if f[2] <= best + tol.PIECE_FIT_TIE_REL)


@dataclass(frozen=True)
class _Outline:
    """A closed outline ready for matching: samples, nearest-point queries, measures."""

    P: np.ndarray
    samples: np.ndarray
    curve: ClosedCurve
    area: float
    perimeter: float
    diag: float

    @classmethod
    def of(cls, P: np.ndarray) -> _Outline:
        """The outline through points ``P`` ``(k, 2)`` (closed)."""
        samples = resample_closed(P, tol.PIECE_SAMPLES)
        return cls(
            P=P,
            samples=samples,
            curve=ClosedCurve(P),
            area=abs(signed_area(P)),
            perimeter=float(np.linalg.norm(P - np.roll(P, -1, axis=0), axis=1).sum()),
            diag=float(np.linalg.norm(np.ptp(samples, axis=0))),
        )

    def threshold(self, allowance: float) -> float:
        """The largest mean outline distance, relative to the diagonal, that still matches."""
        return tol.PIECE_MATCH_REL + allowance / max(self.diag, tol.TINY)


def _shape_match(
    piece: _Outline, panel: _Outline, allowance: float
) -> tuple[np.ndarray, np.ndarray, float] | None:
    """The rigid map fitting a piece onto a panel by shape, when its area is plausible and
    the fit close enough (``(R, t, relative residual)``); None otherwise."""
    slack = tol.PIECE_AREA_REL * panel.area + panel.perimeter * allowance
    if abs(piece.area - panel.area) > slack:
        return None
    R, t, res = _fit_shape(piece.samples, panel.curve, panel.samples, piece.diag)
    return (R, t, res) if res < piece.threshold(allowance) else None


def match_pieces(
    pieces: list[Piece] | tuple[Piece, ...],
    V2: np.ndarray,
    F2: np.ndarray,
    panel_list: list[Panel],
    *,
    path: str = "",
    allowance: float = 0.0,
) -> list[PieceMatch]:
    """Match each piece to the panel it outlines.

    Parameters
    ----------
    pieces : sequence of Piece
        In the pattern's computation units (the sew line is matched when a piece has one).
    V2 : (n, 2) float array
    F2 : (m, 3) int array
    panel_list : list of Panel
    path : str
        The pattern file, for the error message.
    allowance : float
        A seam allowance the pieces' outlines may have around the panels (a CAD cut line
        over a mesh of the sew line), in the same units: a piece matches when the mean
        distance between the outlines is below ``PIECE_MATCH_REL`` of its diagonal plus
        this, and its area within ``PIECE_AREA_REL`` plus the panel's perimeter times this.

    Notes
    -----
    Costs within ``PIECE_TIE_REL`` of each other are a tie, and a tie goes to the panel with
    the piece's name: panels that overlap where they lie (tee6's four sleeves share one spot
    of its pattern) or identical pieces placed by shape are matched by name, not by the
    last digits of their costs.

    Returns
    -------
    list of PieceMatch
        One per piece, in piece order.

    Raises
    ------
    PtailorError
        When a piece matches no panel (naming the pieces and the panels left over).
    """
    outs = [_Outline.of(piece_curve(pc)) for pc in pieces]
    pans = [_Outline.of(V2[outer_loop(F2, p.faces, V2)]) for p in panel_list]
    same = np.array([[pc.name == p.name for p in panel_list] for pc in pieces], dtype=bool)
    matches = _position_matches(outs, pans, allowance, same)
    matches.update(_shape_matches(outs, pans, matches, allowance, same))
    missing = [i for i in range(len(pieces)) if i not in matches]
    if missing:
        used = {m.panel for m in matches.values()}
        left = [p.name for j, p in enumerate(panel_list) if j not in used]
        names = ", ".join(repr(pieces[i].name) for i in missing)
        raise PtailorError(
            f"piece(s) {names} match no panel of the drape's pattern (vt) by position or "
            f"shape; panels left: {', '.join(left) or 'none'} (check the units and that the "
            "drape belongs to this pattern)",
            path=path,
        )
    return [matches[i] for i in range(len(pieces))]


def _position_cost(piece: _Outline, panel: _Outline, allowance: float) -> float:
    """Mean distance between a piece's and a panel's outlines as they lie, relative to the
    piece's diagonal; inf when their boxes are too far apart to compare."""
    lo, hi = panel.samples.min(axis=0), panel.samples.max(axis=0)
    clo, chi = piece.samples.min(axis=0), piece.samples.max(axis=0)
    reach = tol.PIECE_MATCH_REACH_REL * piece.diag + allowance
    if np.any(clo > hi + reach) or np.any(chi < lo - reach):
        return np.inf
    d = _outline_distance(piece.samples, piece.curve, panel.samples, panel.curve)
    return d / piece.diag


def _named_ties(cost: np.ndarray, same: np.ndarray) -> np.ndarray:
    """``cost`` for the assignment with ties broken by name: costs compare on a grid of
    ``tol.PIECE_TIE_REL`` and, within one step, a piece goes to the panel with its name
    (infeasible pairs, ``>= COST_NONE``, stay as they are).

    Parameters
    ----------
    cost : (p, q) float array
        Relative costs, ``COST_NONE`` where a pair cannot match.
    same : (p, q) bool array
        Whether each piece has each panel's name.

    Returns
    -------
    (p, q) float array
    """
    step = tol.PIECE_TIE_REL
    tied = np.round(cost / step) * step - 0.5 * step * same
    return np.where(cost < tol.COST_NONE, tied, cost)


def _position_matches(
    outs: list[_Outline], pans: list[_Outline], allowance: float, same: np.ndarray
) -> dict[int, PieceMatch]:
    """Pieces that lie on a panel, assigned one panel each (by least total cost)."""
    from scipy.optimize import linear_sum_assignment

    thr = np.array([o.threshold(allowance) for o in outs])  # per piece, relative
    cost = np.full((len(outs), len(pans)), np.inf)
    for i, po in enumerate(outs):  # pieces x panels: a few dozen pairs
        for j, pn in enumerate(pans):
            cost[i, j] = _position_cost(po, pn, allowance)
    matches: dict[int, PieceMatch] = {}
    ok = np.where(cost < thr[:, None], cost, tol.COST_NONE)
    rows, cols = linear_sum_assignment(_named_ties(ok, same))
    for i, j in zip(rows.tolist(), cols.tolist(), strict=True):
        if ok[i, j] < tol.COST_NONE:
            c = float(cost[i, j])
            matches[i] = PieceMatch(i, j, "position", np.eye(2), np.zeros(2), c, c * outs[i].diag)
    return matches


def _shape_matches(
    outs: list[_Outline],
    pans: list[_Outline],
    found: dict[int, PieceMatch],
    allowance: float,
    same: np.ndarray,
) -> dict[int, PieceMatch]:
    """The pieces not in ``found`` fitted by shape onto the panels left, one panel each."""
    from scipy.optimize import linear_sum_assignment

    free_panels = [j for j in range(len(pans)) if j not in {m.panel for m in found.values()}]
    rest = [i for i in range(len(outs)) if i not in found]
    if not (rest and free_panels):
        return {}
    fits = {}
    shape_cost = np.full((len(rest), len(free_panels)), tol.COST_NONE)
    for a, i in enumerate(rest):
        for b, j in enumerate(free_panels):
            fit = _shape_match(outs[i], pans[j], allowance)
            if fit is not None:
                fits[i, j] = fit
                shape_cost[a, b] = fit[2]
    matches: dict[int, PieceMatch] = {}
    rr, cc = linear_sum_assignment(_named_ties(shape_cost, same[np.ix_(rest, free_panels)]))
    for a, b in zip(rr.tolist(), cc.tolist(), strict=True):
        if shape_cost[a, b] < tol.COST_NONE:
            i, j = rest[a], free_panels[b]
            R, t, res = fits[i, j]
            matches[i] = PieceMatch(i, j, "shape", R, t, res, res * outs[i].diag)
    return matches


def more_instances(
    pieces: list[Piece] | tuple[Piece, ...],
    matches: list[PieceMatch],
    V2: np.ndarray,
    F2: np.ndarray,
    panel_list: list[Panel],
    *,
    allowance: float = 0.0,
) -> list[PieceMatch]:
    """Panels that are further copies of a piece cut more than once (``Quantity: 2``).

    A CAD file draws a left/right pair once with quantity 2; the drape has both panels. For
    each piece with ``quantity > 1``, the panels no piece matched are fitted by shape
    (reflections allowed, as :func:`match_pieces` does), and up to ``quantity - 1`` that
    fit become further instances of it.

    Returns
    -------
    list of PieceMatch
        The extra matches (``piece`` indexes ``pieces``), best fits first.
    """
    used = {m.panel for m in matches}
    out: list[PieceMatch] = []
    outlines: dict[int, _Outline] = {}  # a panel's outline is made once, on first use
    for i, pc in enumerate(pieces):  # a loop over pieces
        if pc.quantity < 2:
            continue
        free = [p for p in panel_list if p.index not in used]
        if not free:
            break
        po = _Outline.of(piece_curve(pc))
        fits = []
        for p in free:  # a loop over the panels left
            if p.index not in outlines:
                outlines[p.index] = _Outline.of(V2[outer_loop(F2, p.faces, V2)])
            fit = _shape_match(po, outlines[p.index], allowance)
            if fit is not None:
                R, t, res = fit
                fits.append((res, p.index, R, t))
        for res, j, R, t in sorted(fits, key=lambda f: f[0])[: pc.quantity - 1]:
            out.append(PieceMatch(i, j, "shape", R, t, float(res), float(res) * po.diag))
            used.add(j)
    return out
