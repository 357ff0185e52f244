"""Pattern pieces through an adjustment: match DXF pieces to panels, carry their marks.

A CAD system's piece (outline, turn points, notches, grain line, internal lines, drill
holes) is matched to the panel of the triangulated pattern it outlines, by position or,
when it was moved, by shape (a rigid fit, reflections allowed). Every point of the piece
is then located in the panel's triangles and carried to the adjusted pattern with the
same barycentric coordinates (points just off the mesh keep their offset: the triangle's
affine map is extended). A grain line keeps its direction relative to the piece: its
middle is carried, its direction turns with the panel's best-fit rotation, its length
follows the carried ends. A panel that lost or gained triangles (shorten, cut, extend)
gets the mesh's new outline; marks on the part cut away are dropped and counted.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
from scipy.spatial import cKDTree

from ptailor import tolerances as tol
from ptailor.errors import PtailorError
from ptailor.method.transfer import carry_points, locate_points, segment_feet
from ptailor.model.boundary import boundary_loops
from ptailor.model.garment import Garment, Panel, signed_areas_2d
from ptailor.model.pieces import PatternFile, Piece
from ptailor.model.polyline import (
    clip_half_plane,
    corners,
    dedupe_closed,
    offset_closed,
    resample_closed,
    signed_area,
    unfold,
)
from ptailor.model.seams import edge_keys

if TYPE_CHECKING:
    from ptailor.pipeline import Adjustment

#: Points per outline when outlines are compared.
_SAMPLES = 256
#: Rigid-fit refinement iterations (ICP) when matching a moved piece by shape.
_ICP_ITER = 30


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


def outer_loop(F2: np.ndarray, faces: np.ndarray, V2: np.ndarray) -> np.ndarray:
    """The panel's outer boundary loop (largest enclosed area), counter-clockwise.

    Returns
    -------
    (k,) int array
        Vertex indices into ``V2``.
    """
    loops = boundary_loops(F2[faces])
    if not loops:
        return np.zeros(0, dtype=np.int64)
    areas = np.array([signed_area(V2[lp]) for lp in loops])  # a loop over loops, not vertices
    k = int(np.argmax(np.abs(areas)))
    return loops[k] if areas[k] > 0 else loops[k][::-1]


def _piece_curve(piece: Piece) -> np.ndarray:
    return piece.sew if piece.sew is not None else piece.outline


class _Curve:
    """A closed polyline that answers nearest-point queries on its segments.

    Candidates come from samples along the segments (about 4,000 per curve, at least one
    per segment end) in a k-d tree: a segment near the query has a sample within half the
    spacing of the foot point, however long the segment, so the answer is exact for points
    on the curve and within half a spacing (1/8,000 of the perimeter) elsewhere.
    """

    def __init__(self, P: np.ndarray) -> None:
        self.A = P
        self.B = np.roll(P, -1, axis=0)
        seg = np.linalg.norm(self.B - self.A, axis=1)
        h = max(float(seg.sum()) / 4096.0, 1e-300)
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
        _, idx = self.tree.query(X, k=self.k)
        seg = self.sid[np.asarray(idx).reshape(len(X), self.k)]
        d, Q = segment_feet(X[:, None, :], self.A[seg], self.B[seg])
        best = np.argmin(d, axis=1)
        r = np.arange(len(X))
        return d[r, best], Q[r, best]


def _outline_distance(A: np.ndarray, ca: _Curve, B: np.ndarray, cb: _Curve) -> float:
    """Symmetric mean distance between outlines ``ca`` and ``cb``, sampled as ``A``, ``B``."""
    return 0.5 * float(cb.nearest(A)[0].mean() + ca.nearest(B)[0].mean())


def _kabsch(A: np.ndarray, B: np.ndarray, *, reflect: bool) -> tuple[np.ndarray, np.ndarray]:
    """The rigid map (rotation, or reflection when ``reflect``) taking ``A`` closest to ``B``."""
    ca, cb = A.mean(axis=0), B.mean(axis=0)
    H = (A - ca).T @ (B - cb)
    U, _, Vt = np.linalg.svd(H)
    D = np.diag([1.0, -1.0 if reflect else 1.0])
    R = Vt.T @ D @ U.T
    if (np.linalg.det(R) < 0) != reflect:  # the SVD's own sign
        D = np.diag([1.0, 1.0 if reflect else -1.0])
        R = Vt.T @ D @ U.T
    return R, cb - R @ ca


def _fit_shape(
    A: np.ndarray, cb: _Curve, B: np.ndarray, diag: float
) -> tuple[np.ndarray, np.ndarray, float]:
    """Best rigid fit of outline samples ``A`` onto curve ``cb`` (sampled as ``B``).

    Principal axes give four starts (two rotations, two reflections); ICP against the
    curve's segments refines each; the lowest symmetric mean distance wins.
    """
    ca, cb0 = A.mean(axis=0), B.mean(axis=0)
    _, Ea = np.linalg.eigh(np.cov((A - ca).T))
    _, Eb = np.linalg.eigh(np.cov((B - cb0).T))
    best = (np.eye(2), np.zeros(2), np.inf)
    for sx in (1.0, -1.0):  # the four axis pairings
        for sy in (1.0, -1.0):
            R = Eb @ np.diag([sx, sy]) @ Ea.T
            t = cb0 - R @ ca
            reflect = bool(np.linalg.det(R) < 0)
            for _ in range(_ICP_ITER):
                _, Q = cb.nearest(A @ R.T + t)
                R, t = _kabsch(A, Q, reflect=reflect)
            moved = A @ R.T + t
            res = _outline_distance(moved, _Curve(moved), B, cb)
            if res < best[2]:
                best = (R, t, res / diag)
    return best


@dataclass(frozen=True)
class _Outline:
    """A closed outline ready for matching: samples, nearest-point queries, measures."""

    P: np.ndarray
    samples: np.ndarray
    curve: _Curve
    area: float
    perimeter: float
    diag: float

    @classmethod
    def of(cls, P: np.ndarray) -> _Outline:
        samples = resample_closed(P, _SAMPLES)
        return cls(
            P=P,
            samples=samples,
            curve=_Curve(P),
            area=abs(signed_area(P)),
            perimeter=float(np.linalg.norm(P - np.roll(P, -1, axis=0), axis=1).sum()),
            diag=float(np.linalg.norm(np.ptp(samples, axis=0))),
        )

    def threshold(self, allowance: float) -> float:
        """The largest mean outline distance, relative to the diagonal, that still matches."""
        return tol.PIECE_MATCH_REL + allowance / max(self.diag, 1e-300)


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

    Returns
    -------
    list of PieceMatch
        One per piece, in piece order.

    Raises
    ------
    PtailorError
        When a piece matches no panel (naming the pieces and the panels left over).
    """
    from scipy.optimize import linear_sum_assignment

    n_pc, n_pn = len(pieces), len(panel_list)
    outs = [_Outline.of(_piece_curve(pc)) for pc in pieces]
    pans = [_Outline.of(V2[outer_loop(F2, p.faces, V2)]) for p in panel_list]
    thr = np.array([o.threshold(allowance) for o in outs])  # per piece, relative
    cost = np.full((n_pc, n_pn), np.inf)
    for i, po in enumerate(outs):  # pieces x panels: a few dozen pairs
        for j, pn in enumerate(pans):
            lo, hi = pn.samples.min(axis=0), pn.samples.max(axis=0)
            clo, chi = po.samples.min(axis=0), po.samples.max(axis=0)
            reach = 0.1 * po.diag + allowance
            if np.any(clo > hi + reach) or np.any(chi < lo - reach):
                continue
            d = _outline_distance(po.samples, po.curve, pn.samples, pn.curve)
            cost[i, j] = d / po.diag
    matches: dict[int, PieceMatch] = {}
    ok = np.where(cost < thr[:, None], cost, 1e6)
    rows, cols = linear_sum_assignment(ok)
    for i, j in zip(rows.tolist(), cols.tolist(), strict=True):
        if ok[i, j] < 1e6:
            c = float(cost[i, j])
            matches[i] = PieceMatch(i, j, "position", np.eye(2), np.zeros(2), c, c * outs[i].diag)
    free_panels = [j for j in range(n_pn) if j not in {m.panel for m in matches.values()}]
    rest = [i for i in range(n_pc) if i not in matches]
    if rest and free_panels:
        fits = {}
        shape_cost = np.full((len(rest), len(free_panels)), 1e6)
        for a, i in enumerate(rest):
            for b, j in enumerate(free_panels):
                fit = _shape_match(outs[i], pans[j], allowance)
                if fit is not None:
                    fits[i, j] = fit
                    shape_cost[a, b] = fit[2]
        rr, cc = linear_sum_assignment(shape_cost)
        for a, b in zip(rr.tolist(), cc.tolist(), strict=True):
            if shape_cost[a, b] < 1e6:
                i, j = rest[a], free_panels[b]
                R, t, res = fits[i, j]
                matches[i] = PieceMatch(i, j, "shape", R, t, res, res * outs[i].diag)
    missing = [i for i in range(n_pc) if i not in matches]
    if missing:
        used = {m.panel for m in matches.values()}
        left = [panel_list[j].name for j in range(n_pn) if j not in used]
        names = ", ".join(repr(pieces[i].name) for i in missing)
        raise PtailorError(
            f"piece(s) {names} match no panel of the drape's pattern (vt) by position or "
            f"shape; panels left: {', '.join(left) or 'none'} (check the units and that the "
            "drape belongs to this pattern)",
            path=path,
        )
    return [matches[i] for i in range(n_pc)]


def _edge_partners(F2: np.ndarray, F3: np.ndarray | None, panel_list: list[Panel]):
    """Sorted 2D edge keys of the pattern's half-edges and the panel across each (or -1)."""
    from ptailor.method.flatten import panel_labels
    from ptailor.model.seams import half_edges, seam_halfedges

    m = len(F2)
    keys = edge_keys(half_edges(F2), n=int(F2.max(initial=0)) + 1)
    partner = np.full(3 * m, -1, dtype=np.int64)
    if F3 is not None and m:
        face = np.repeat(np.arange(m), 3)
        flab = panel_labels(panel_list, m)
        pairs = seam_halfedges(F3, F2)
        partner[pairs[:, 0]] = flab[face[pairs[:, 1]]]
        partner[pairs[:, 1]] = flab[face[pairs[:, 0]]]
    order = np.argsort(keys, kind="stable")
    return keys[order], partner[order]


def grain_directions(
    V2: np.ndarray,
    F2: np.ndarray,
    V3: np.ndarray,
    F3: np.ndarray,
    panel_list: list[Panel],
    *,
    up: tuple[float, float, float] = (0.0, 1.0, 0.0),
) -> np.ndarray:
    """Each panel's lengthwise grain in the pattern, read off the drape.

    The grain runs along the body part the panel wraps: the axis of a tube-like panel (a
    sleeve, a torso or skirt panel: the direction its normals avoid, as ``axis: auto``
    finds it), or the body's ``up`` for a panel too flat to have one. It is mapped into the
    pattern through each triangle's 2D-to-3D map (the least-squares preimage) and averaged
    over the panel by area, pointing up the body where the axis has an up component.

    Parameters
    ----------
    V2 : (n2, 2) float array
    F2 : (m, 3) int array
    V3 : (n3, 3) float array
    F3 : (m, 3) int array
    panel_list : list of Panel
    up : (3,) sequence of float

    Returns
    -------
    (n_panels, 2) float array
        Unit directions; ``(0, 1)`` where the drape says nothing (a degenerate panel).
    """
    from ptailor.method.flatten import panel_labels

    n = len(panel_list)
    flab = panel_labels(panel_list, len(F2))
    u = np.asarray(up, dtype=np.float64)
    u = u / np.linalg.norm(u)
    axes = np.empty((n, 3))
    for p in panel_list:  # a loop over panels: each one's normal tensor
        axes[p.index] = _panel_axis(V3, F3, p.faces, u)
    target = axes[flab]  # (m, 3)
    e1, e2 = V3[F3[:, 1]] - V3[F3[:, 0]], V3[F3[:, 2]] - V3[F3[:, 0]]
    a3 = 0.5 * np.linalg.norm(np.cross(e1, e2), axis=1)
    # least-squares preimage of the target through J = E3 E2^-1 (3x2): (J^T J)^-1 J^T t
    E2 = np.stack([V2[F2[:, 1]] - V2[F2[:, 0]], V2[F2[:, 2]] - V2[F2[:, 0]]], axis=2)  # (m,2,2)
    E3 = np.stack([e1, e2], axis=2)  # (m, 3, 2)
    det = E2[:, 0, 0] * E2[:, 1, 1] - E2[:, 0, 1] * E2[:, 1, 0]
    ok = np.abs(det) > 0
    inv = (
        np.stack(
            [np.stack([E2[:, 1, 1], -E2[:, 0, 1]], 1), np.stack([-E2[:, 1, 0], E2[:, 0, 0]], 1)], 1
        )
        / np.where(ok, det, 1.0)[:, None, None]
    )
    J = E3 @ inv
    JtJ = np.einsum("mki,mkj->mij", J, J)
    rhs = np.einsum("mki,mk->mi", J, target)
    dj = JtJ[:, 0, 0] * JtJ[:, 1, 1] - JtJ[:, 0, 1] ** 2
    good = ok & (dj > 0)
    sol = np.stack(
        [JtJ[:, 1, 1] * rhs[:, 0] - JtJ[:, 0, 1] * rhs[:, 1],
         JtJ[:, 0, 0] * rhs[:, 1] - JtJ[:, 0, 1] * rhs[:, 0]], 1
    ) / np.where(good, dj, 1.0)[:, None]  # fmt: skip
    norm = np.linalg.norm(sol, axis=1)
    good &= norm > 0
    unit = np.where(good[:, None], sol / np.where(good, norm, 1.0)[:, None], 0.0)
    g = np.stack([np.bincount(flab, a3 * unit[:, k], n) for k in range(2)], 1)
    length = np.linalg.norm(g, axis=1)
    out = np.tile([0.0, 1.0], (n, 1))
    has = length > 0
    out[has] = g[has] / length[has, None]
    return out


def _panel_axis(V3: np.ndarray, F3: np.ndarray, faces: np.ndarray, up: np.ndarray) -> np.ndarray:
    """A panel's tube axis (the direction its normals avoid), else ``up``; pointing up."""
    T = F3[faces]
    cr = np.cross(V3[T[:, 1]] - V3[T[:, 0]], V3[T[:, 2]] - V3[T[:, 0]])
    w = np.linalg.norm(cr, axis=1)
    nrm = cr / np.maximum(w, 1e-300)[:, None]
    N = (nrm * w[:, None]).T @ nrm
    lam, vec = np.linalg.eigh(N / max(np.trace(N), 1e-300))
    tube = lam[1] > tol.GRAIN_TUBE_MIN and lam[1] > tol.GRAIN_TUBE_RATIO * lam[0]
    ax = vec[:, 0] if tube else up
    s = float(ax @ up)
    return ax * (-1.0 if s < -1e-9 else 1.0)


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
    for i, pc in enumerate(pieces):  # a loop over pieces
        if pc.quantity < 2:
            continue
        free = [p for p in panel_list if p.index not in used]
        if not free:
            break
        po = _Outline.of(_piece_curve(pc))
        fits = []
        for p in free:  # a loop over the panels left
            fit = _shape_match(po, _Outline.of(V2[outer_loop(F2, p.faces, V2)]), allowance)
            if fit is not None:
                R, t, res = fit
                fits.append((res, p.index, R, t))
        for res, j, R, t in sorted(fits, key=lambda f: f[0])[: pc.quantity - 1]:
            out.append(PieceMatch(i, j, "shape", R, t, float(res), float(res) * po.diag))
            used.add(j)
    return out


def mesh_pieces(
    V2: np.ndarray,
    F2: np.ndarray,
    panel_list: list[Panel],
    *,
    F3: np.ndarray | None = None,
    V3: np.ndarray | None = None,
    grain: np.ndarray | None = None,
) -> list[Piece]:
    """Pieces drawn from a triangulated pattern: outline, turn points, notches, grain line.

    The outline is each panel's outer boundary (counter-clockwise), holes become internal
    lines (closed), turn points are where the outline turns by more than
    ``tolerances.CORNER_DEG``. With the drape's triangles ``F3``, a notch marks each point
    of the outline (other than a turn point) where the panel across the seam changes, or a
    seam ends: the match points for sewing; with the drape ``V3`` too, a balance notch marks
    the middle of every seam (by length in the drape, so both sides' notches meet when
    sewn). The grain line runs through the panel's centroid along ``grain`` (default the
    pattern's y axis), across half the panel.

    Parameters
    ----------
    V2 : (n, 2) float array
    F2 : (m, 3) int array
    panel_list : list of Panel
    F3 : (m, 3) int array, optional
        The drape's triangles, for seam notches.
    V3 : (n3, 3) float array, optional
        The drape, for balance notches (with ``F3``).
    grain : (n_panels, 2) float array, optional
        Unit grain direction per panel (:func:`grain_directions`).

    Returns
    -------
    list of Piece
    """
    keys, partner = _edge_partners(F2, F3, panel_list)
    n_v = int(F2.max(initial=0)) + 1
    to3 = np.zeros(n_v, dtype=np.int64)
    if F3 is not None:
        to3[F2.ravel()] = F3.ravel()  # pattern vertex -> drape vertex
    out = []
    areas = signed_areas_2d(V2, F2)
    for p in panel_list:  # a loop over panels
        loops = boundary_loops(F2[p.faces])
        outer = outer_loop(F2, p.faces, V2)
        P = V2[outer]
        turn = corners(P)
        ek = edge_keys(np.stack([outer, np.roll(outer, -1)], axis=1), n=n_v)
        across = partner[np.minimum(np.searchsorted(keys, ek), len(keys) - 1)]
        notch = (across != np.roll(across, 1)) & ~turn
        balance = np.zeros((0, 2))
        if V3 is not None and F3 is not None:
            balance = _balance_notches(P, outer, across, to3, V3)
        a = np.abs(areas[p.faces])
        c = (V2[F2[p.faces]].mean(axis=1) * a[:, None]).sum(axis=0) / max(a.sum(), 1e-300)
        gd = np.array([0.0, 1.0]) if grain is None else grain[p.index]
        half = 0.25 * float(np.ptp(P @ gd))
        holes = tuple(np.vstack([V2[lp], V2[lp[:1]]]) for lp in loops if len(lp) != len(outer))
        out.append(
            Piece(
                name=p.name,
                outline=P,
                turn=turn,
                notches=np.vstack([P[notch], balance]),
                notch_angles=np.zeros(int(notch.sum()) + len(balance)),
                grain=np.stack([c - half * gd, c + half * gd]),
                internal=holes,
            )
        )
    return out


def _balance_notches(
    P: np.ndarray, loop: np.ndarray, across: np.ndarray, to3: np.ndarray, V3: np.ndarray
) -> np.ndarray:
    """The middle (by drape length) of each seam run along an outline, ``(k, 2)``.

    ``across[i]`` is the panel across outline edge ``i`` (``loop[i] -> loop[i + 1]``), -1
    on a free edge; a run of one partner is one seam. Runs of fewer than
    ``BALANCE_MIN_EDGES`` edges get none.
    """
    k = len(loop)
    change = np.flatnonzero(across != np.roll(across, 1))
    if len(change) == 0:
        return np.zeros((0, 2))
    order = np.roll(np.arange(k), -int(change[0]))  # start at a run boundary
    lab = across[order]
    run = np.cumsum(lab != np.roll(lab, 1)) - 1
    run[0] = 0
    a3, b3 = V3[to3[loop[order]]], V3[to3[loop[np.roll(order, -1)]]]
    length = np.linalg.norm(b3 - a3, axis=1)
    out = []
    for r in np.unique(run[lab >= 0]).tolist():  # a loop over the seams of one panel
        idx = np.flatnonzero(run == r)
        if len(idx) < tol.BALANCE_MIN_EDGES:
            continue
        cum = np.cumsum(length[idx])
        half = 0.5 * cum[-1]
        j = int(np.searchsorted(cum, half))
        before = cum[j] - length[idx[j]]
        t = (half - before) / max(length[idx[j]], 1e-300)
        e = order[idx[j]]
        out.append((1 - t) * P[e] + t * P[(e + 1) % k])
    return np.array(out).reshape(-1, 2)


def _panel_rotation(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """The rotation best taking points ``X`` onto ``Y`` (both ``(k, 2)``)."""
    a, b = X - X.mean(axis=0), Y - Y.mean(axis=0)
    ang = np.arctan2(
        (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]).sum(), (a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1]).sum()
    )
    c, s = np.cos(ang), np.sin(ang)
    return np.array([[c, -s], [s, c]])


@dataclass(frozen=True)
class CarriedPiece:
    """A piece after the adjustment, and what happened to its marks.

    Attributes
    ----------
    piece : Piece
        In the original piece's coordinates (the panel's rigid map undone).
    outline_from : str
        ``carried`` (the piece's own outline points) or ``mesh`` (the panel's triangles
        changed: the adjusted mesh boundary).
    dropped : int
        Marks (notches, drill holes, internal-line points, fold-line ends) cut away; a
        grain line on the part cut away is drawn again through the piece's middle.
    kept : (q,) bool array or None
        Per mark point located (notches, drill holes, grain ends and middle, fold-line
        ends, internal-line points, in that order), whether it was kept.
    """

    piece: Piece
    outline_from: str
    dropped: int
    kept: np.ndarray | None = None


def carry_piece(
    piece: Piece,
    match: PieceMatch,
    *,
    V2: np.ndarray,
    F2: np.ndarray,
    faces: np.ndarray,
    V2_new: np.ndarray,
    unchanged: bool,
    reach: float = 0.0,
    original: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
) -> CarriedPiece:
    """Carry one piece's outline and marks to the adjusted pattern.

    Parameters
    ----------
    piece : Piece
        In computation units.
    match : PieceMatch
    V2, F2 : arrays
        The pattern the marks are located in (the original pattern after any surgery).
    faces : (j,) int array
        The panel's triangles in ``F2``.
    V2_new : (n, 2) float array
        The adjusted pattern (same ``F2``).
    unchanged : bool
        The panel kept all its triangles: the piece's own outline is carried; otherwise the
        mesh's boundary is the new outline, and notches that no longer lie on it (left
        inside the piece by an extension) are dropped.
    reach : float
        How far the piece's outline lies from the original panel's mesh (its chord error):
        without ``original``, marks further than that (plus ``MARK_KEEP_REL`` of the
        diagonal) from every remaining triangle were cut away.
    original : (V2_0, F2_0, faces_0), optional
        The input pattern and the panel's triangles in it. A mark is then cut away when it
        lies further from the remaining triangles than from the original panel (plus
        ``MARK_KEEP_REL`` of the diagonal): marks drawn outside the cut line (a hem's
        turn-back line, a seam allowance's notches) are kept, carried by their nearest
        triangle's extended map. A panel that kept all its triangles keeps every mark.

    Returns
    -------
    CarriedPiece
    """
    diag = float(np.linalg.norm(piece.extent))
    keep_d = reach + tol.MARK_KEEP_REL * diag
    grain_pts = (
        np.vstack([piece.grain, piece.grain.mean(axis=0, keepdims=True)])
        if piece.grain is not None
        else np.zeros((0, 2))
    )
    groups = [
        piece.outline if unchanged else np.zeros((0, 2)),
        piece.sew if unchanged and piece.sew is not None else np.zeros((0, 2)),
        piece.notches,
        piece.drills,
        grain_pts,
        piece.mirror if piece.mirror is not None else np.zeros((0, 2)),
        *piece.internal,
    ]
    # every point located at once (one search structure per piece), then split by group
    X = np.vstack([np.asarray(g, dtype=np.float64).reshape(-1, 2) for g in groups])
    loc = locate_points(V2, F2, match.to_panel(X), faces=faces)
    moved = match.to_piece(carry_points(V2_new, F2, loc)) if len(X) else np.zeros((0, 2))
    if unchanged:
        kept = np.ones(len(X), dtype=bool)
    elif original is not None:
        d_orig = locate_points(original[0], original[1], match.to_panel(X), faces=original[2])
        kept = loc.distance <= d_orig.distance + tol.MARK_KEEP_REL * diag
    else:
        kept = loc.distance <= keep_d
    cuts = np.cumsum([len(g) for g in groups])[:-1]
    moved_g, kept_g = np.split(moved, cuts), np.split(kept, cuts)

    dropped = 0
    if unchanged:
        outline, turn, how = moved_g[0], piece.turn, "carried"
        sew = moved_g[1] if piece.sew is not None else None
    else:
        loop = outer_loop(F2, faces, V2_new)
        outline = match.to_piece(V2_new[loop])
        if np.linalg.det(match.R) < 0:
            outline = outline[::-1]
        turn, sew, how = corners(outline), None, "mesh"
    notches, keep_n = moved_g[2], kept_g[2]
    if not unchanged and len(notches):
        # a notch marks the outline: one the edit left inside the piece (the old hem of an
        # extended skirt) no longer marks anything
        scale = float(np.linalg.norm(np.ptp(outline, axis=0))) / max(diag, 1e-300)
        keep_n = keep_n & (_Curve(outline).nearest(notches)[0] <= keep_d * max(scale, 1.0))
    drills, keep_d_ = moved_g[3], kept_g[3]
    dropped += int((~keep_n).sum() + (~keep_d_).sum())
    internal = []
    mirror = None
    if piece.mirror is not None:
        if kept_g[5].all() or match.fold:  # a fold line is a line: its ends extend
            mirror = moved_g[5]
        else:
            dropped += 2
    if match.fold and not unchanged and mirror is not None:
        # the mesh outlines the whole panel: a fold piece is its half on the piece's side
        # of the carried fold line
        a0, b0 = np.asarray(piece.mirror, dtype=float)[[0, -1]]
        d0 = b0 - a0
        side = float(np.sign(np.mean((piece.outline - a0) @ np.array([-d0[1], d0[0]]))))
        half = clip_half_plane(outline, mirror[0], mirror[-1], side or 1.0)
        half = half[dedupe_closed(half, rel=1e-9)]
        if len(half) >= 3:
            u = mirror[-1] - mirror[0]
            u = u / max(float(np.linalg.norm(u)), 1e-300)
            on = np.abs((half - mirror[0]) @ np.array([-u[1], u[0]])) <= 1e-9 * diag + 1e-12
            if on.sum() >= 2:
                t = (half[on] - mirror[0]) @ u
                mirror = mirror[0] + np.outer([t.min(), t.max()], u)
            outline, turn = half, corners(half)
    for L, keep in zip(moved_g[6:], kept_g[6:], strict=True):  # a piece's internal lines
        dropped += int((~keep).sum())
        if keep.sum() >= 2:
            internal.append(L[keep])
    # the panel's rotation, seen in piece coordinates: notch directions and the grain turn
    # with it
    vs = np.unique(F2[faces])
    Rq = match.R.T @ _panel_rotation(V2[vs], V2_new[vs]) @ match.R
    turn_deg = float(np.degrees(np.arctan2(Rq[1, 0], Rq[0, 0])))
    grain = None
    if piece.grain is not None:
        ends, mid, keep_g = moved_g[4][:2], moved_g[4][2], kept_g[4]
        if keep_g[:2].all() or keep_g[2]:
            d0 = piece.grain[1] - piece.grain[0]
            u = Rq @ (d0 / max(np.linalg.norm(d0), 1e-300))
            length = float(np.linalg.norm(ends[1] - ends[0]))
            grain = np.stack([mid - 0.5 * length * u, mid + 0.5 * length * u])
        else:
            # the grain line lay on the part cut away: a cutter needs one, so it is drawn
            # again through the piece's middle, in the same direction (turned with the
            # panel), across half the piece
            d0 = piece.grain[1] - piece.grain[0]
            u = Rq @ (d0 / max(np.linalg.norm(d0), 1e-300))
            c = outline.mean(axis=0)
            half = 0.25 * float(np.ptp(outline @ u))
            grain = np.stack([c - half * u, c + half * u])
    angles = piece.notch_angles if len(piece.notch_angles) == len(keep_n) else np.zeros(len(keep_n))
    angles = np.mod(angles[keep_n] + turn_deg, 360.0)
    new = replace(
        piece,
        outline=outline,
        turn=turn,
        notches=notches[keep_n],
        notch_angles=angles,
        grain=grain,
        internal=tuple(internal),
        drills=drills[keep_d_],
        sew=sew,
        mirror=mirror,
    )
    n_fixed = sum(len(g) for g in groups[:2])
    marks_kept = kept.copy()
    g0 = int(cuts[3]) if len(cuts) > 3 else len(kept)
    marks_kept[g0 : g0 + len(grain_pts)] = True  # a grain line is never lost (drawn again)
    return CarriedPiece(piece=new, outline_from=how, dropped=dropped, kept=marks_kept[n_fixed:])


def scale_piece(piece: Piece, k: float) -> Piece:
    """Every coordinate of ``piece`` times ``k`` (a change of units)."""
    return piece.map_points(lambda a: a * k)


def with_seam_allowance(piece: Piece, d: float) -> Piece:
    """The piece with its outline as the sew line and the outline offset by ``d`` as cut line.

    Turn points of the new outline are its mitred corners (where it turns by more than
    ``tolerances.CORNER_DEG``).
    """
    cut = offset_closed(piece.outline, d)
    return replace(piece, sew=piece.outline, outline=cut, turn=corners(cut))


@dataclass(frozen=True)
class PiecePlan:
    """The pieces a run writes, and the panel each one belongs to.

    Attributes
    ----------
    pieces : tuple of Piece
        In the garment's computation units: the CAD file's pieces, then pieces drawn from
        the mesh for panels no file piece outlines.
    matches : tuple of PieceMatch
        One per piece.
    from_file : tuple of bool
        Whether each piece came from the pattern file.
    units : str
        The unit pieces are written in (the pattern file's, else the computation unit).
    panels : tuple of Panel
        The input garment's panels, which ``matches`` index (``-1``: a panel the
        adjustment made, see ``panel_names``).
    panel_names : tuple of str
        After :func:`carry_plan`: per piece, the adjusted garment's panel it is; empty
        before.
    """

    pieces: tuple[Piece, ...]
    matches: tuple[PieceMatch, ...]
    from_file: tuple[bool, ...]
    units: str
    panels: tuple[Panel, ...]
    panel_names: tuple[str, ...] = ()


def unfolded(piece: Piece) -> Piece | None:
    """A piece cut on the fold as the whole it cuts: its outline (or sew line) and its
    mirror image across the fold line (layer 6) joined; None when it has no fold line
    along its outline."""
    if piece.mirror is None:
        return None
    a, b = np.asarray(piece.mirror, dtype=float)[[0, -1]]
    whole = unfold(piece.outline, a, b)
    if whole is None:
        return None
    sew = unfold(piece.sew, a, b) if piece.sew is not None else None
    return replace(piece, outline=whole, turn=np.zeros(len(whole), dtype=bool), sew=sew)


def _match_with_folds(
    pieces: list[Piece],
    V2: np.ndarray,
    F2: np.ndarray,
    panel_list: list[Panel],
    *,
    path: str,
    allowance: float,
) -> tuple[list[PieceMatch], list[Piece]]:
    """Match pieces to panels, pieces cut on the fold by their unfolded whole.

    A drape holds the whole panel that a fold piece (a half with a fold line on layer 6)
    cuts. Pieces are matched unfolded first, then, when that fails, as drawn (a fold line
    that is not the piece's edge of symmetry); the error names the fold pieces.

    Returns
    -------
    matches : list of PieceMatch
        ``fold`` set where the unfolded piece matched.
    pieces : list of Piece
        What was matched (the unfolded pieces where they matched).
    """
    whole = [unfolded(pc) for pc in pieces]
    if not any(w is not None for w in whole):
        return match_pieces(pieces, V2, F2, panel_list, path=path, allowance=allowance), pieces
    src = [w if w is not None else pc for pc, w in zip(pieces, whole, strict=True)]
    try:
        ms = match_pieces(src, V2, F2, panel_list, path=path, allowance=allowance)
        return [replace(m, fold=whole[m.piece] is not None) for m in ms], src
    except PtailorError as first:
        try:
            ms = match_pieces(pieces, V2, F2, panel_list, path=path, allowance=allowance)
            return ms, pieces
        except PtailorError:
            names = ", ".join(repr(pc.name) for pc, w in zip(pieces, whole, strict=True) if w)
            raise PtailorError(
                f"{first.message}; piece(s) {names} are cut on the fold (a fold line on "
                "layer 6) and matched neither as drawn nor unfolded across the fold line",
                path=first.path,
            ) from None


def _one_side(pc: Piece, m: PieceMatch) -> tuple[int, int] | None:
    """An instance of a ``Quantity: a,b`` piece: ``1,0`` cut as drawn, ``0,1`` mirrored
    (its panel is the piece reflected); None for a plain quantity."""
    if pc.quantity_split is None:
        return None
    return (0, 1) if np.linalg.det(m.R) < 0 else (1, 0)


def piece_plan(
    garment: Garment,
    panel_list: list[Panel],
    *,
    pattern: PatternFile | None = None,
    up: tuple[float, float, float] = (0.0, 1.0, 0.0),
) -> PiecePlan:
    """Match a pattern file's pieces to the garment's panels; draw the rest from the mesh.

    Parameters
    ----------
    garment : Garment
        The input garment (pattern in ``garment.units``).
    panel_list : list of Panel
        ``panels(garment)``.
    pattern : PatternFile, optional
        Pieces in ``pattern.units``.
    up : (3,) sequence of float
        The drape's up axis: pieces drawn from the mesh take their grain from it.

    Returns
    -------
    PiecePlan

    Raises
    ------
    PtailorError
        A file piece that matches no panel.
    """
    from ptailor.model.units import CM_PER

    V2, F2 = garment.V2, garment.F2
    file_pieces: list[Piece] = []
    matches: list[PieceMatch] = []
    units = garment.units
    if pattern is not None:
        k = CM_PER[pattern.units] / CM_PER[garment.units]
        file_pieces = [scale_piece(pc, k) for pc in pattern.pieces]
        allowance = tol.PIECE_ALLOWANCE_CM / CM_PER[garment.units]
        matches, src = _match_with_folds(
            file_pieces, V2, F2, panel_list, path=pattern.path, allowance=allowance
        )
        extra = more_instances(src, matches, V2, F2, panel_list, allowance=allowance)
        extra = [replace(m, fold=matches[m.piece].fold) for m in extra]
        # every instance becomes its own piece of quantity 1: a mirrored pair may be
        # adjusted differently, and a cutter must not cut the first one twice
        copies = {m.piece for m in extra}
        count: dict[int, int] = {}
        for m in extra:
            count[m.piece] = count.get(m.piece, 1) + 1
            pc = file_pieces[m.piece]
            file_pieces.append(
                replace(
                    pc,
                    name=f"{pc.name}-{count[m.piece]}",
                    quantity=1,
                    quantity_split=_one_side(pc, m),
                )
            )
            matches.append(replace(m, piece=len(file_pieces) - 1))
        for i in copies:
            pc = file_pieces[i]
            file_pieces[i] = replace(pc, quantity=1, quantity_split=_one_side(pc, matches[i]))
        units = pattern.units
    used = {m.panel for m in matches}
    rest = [p for p in panel_list if p.index not in used]
    grain = grain_directions(V2, F2, garment.V3, garment.F3, panel_list, up=up)
    drawn = mesh_pieces(V2, F2, rest, F3=garment.F3, V3=garment.V3, grain=grain)
    pieces = file_pieces + drawn
    matches = matches + [
        PieceMatch(len(file_pieces) + a, p.index, "mesh", np.eye(2), np.zeros(2), 0.0)
        for a, p in enumerate(rest)
    ]
    return PiecePlan(
        pieces=tuple(pieces),
        matches=tuple(matches),
        from_file=tuple([True] * len(file_pieces) + [False] * len(drawn)),
        units=units,
        panels=tuple(panel_list),
    )


def _source_panels(adj: Adjustment, orig: tuple[Panel, ...]) -> dict[str, int]:
    """Adjusted panel name to the input panel it came from (index into ``orig``).

    A panel keeps its name through the edits; a panel a cut split in two is ``NAME``,
    ``NAME_1``, ... Panels whose name says nothing are located by a point of theirs in the
    input pattern (the kept part of a panel keeps its pattern coordinates).
    """
    g0 = adj.original if adj.original is not None else adj.state.base
    base = adj.state.base
    names = {p.name: p.index for p in orig}
    out: dict[str, int] = {}
    unknown = []
    for p in adj.state.panels:  # a loop over panels
        if p.name in names:
            out[p.name] = names[p.name]
        elif p.name.rsplit("_", 1)[0] in names and p.name.rsplit("_", 1)[-1].isdigit():
            out[p.name] = names[p.name.rsplit("_", 1)[0]]
        else:
            unknown.append(p)
    if unknown and len(g0.F2):
        from ptailor.method.flatten import panel_labels

        flab = panel_labels(list(orig), len(g0.F2))
        a = np.abs(signed_areas_2d(base.V2, base.F2))
        for p in unknown:  # a loop over panels
            f = p.faces[int(np.argmax(a[p.faces]))]
            loc = locate_points(g0.V2, g0.F2, base.V2[base.F2[f]].mean(axis=0, keepdims=True))
            if loc.distance[0] <= 1e-9 * max(float(np.ptp(g0.V2)), 1e-300):
                out[p.name] = int(flab[loc.face[0]])
    return out


def carry_plan(
    adj: Adjustment, plan: PiecePlan, *, up: tuple[float, float, float] = (0.0, 1.0, 0.0)
) -> tuple[PiecePlan, list[CarriedPiece | None]]:
    """Carry every planned piece through an adjustment; every adjusted panel gets a piece.

    A panel a cut split in two (a V-neck through a neckband) gets a piece per part: the
    first part keeps the piece's name, the others take the panel's suffix (``NECKBAND_1``);
    each part's outline is the mesh's, and each mark goes to the part it lies on (a mark on
    neither part counts once as dropped). A panel that no piece outlines (a panel the
    adjustment made) gets a piece drawn from the adjusted mesh.

    Parameters
    ----------
    adj : Adjustment
    plan : PiecePlan
        Made on ``adj.original`` (the input garment).
    up : (3,) sequence of float
        The drape's up axis, for the grain of pieces drawn from the mesh.

    Returns
    -------
    plan : PiecePlan
        ``plan`` with the parts' pieces added and ``panel_names`` filled in.
    pieces : list of CarriedPiece or None
        One per piece of the returned plan; ``None`` where the piece's panel was removed
        whole.
    """
    new_plan, carried, _ = _carry(adj, plan, up=up)
    return new_plan, carried


def _carry(
    adj: Adjustment, plan: PiecePlan, *, up: tuple[float, float, float]
) -> tuple[PiecePlan, list[CarriedPiece | None], list[int]]:
    """:func:`carry_plan`, and per planned piece the index of its (first) carried piece."""
    g0 = adj.original if adj.original is not None else adj.state.base
    base = adj.state.base
    orig = plan.panels
    source = _source_panels(adj, orig)
    first: list[int] = []
    parts: dict[int, list[Panel]] = {}
    for p in adj.state.panels:  # a loop over panels
        if p.name in source:
            parts.setdefault(source[p.name], []).append(p)
    a0 = np.abs(signed_areas_2d(g0.V2, g0.F2))
    ab = np.abs(signed_areas_2d(base.V2, base.F2))
    pieces: list[Piece] = []
    matches: list[PieceMatch] = []
    from_file: list[bool] = []
    names: list[str] = []
    out: list[CarriedPiece | None] = []
    covered: set[str] = set()
    for piece, m, ff in zip(plan.pieces, plan.matches, plan.from_file, strict=True):  # pieces
        p0 = orig[m.panel]
        now = parts.get(m.panel, [])
        first.append(len(out))
        if not now:
            pieces.append(piece)
            matches.append(m)
            from_file.append(ff)
            names.append(p0.name)
            out.append(None)
            continue
        s0 = float(a0[p0.faces].sum())
        reach = 0.0
        group = []
        for k, p in enumerate(now):  # the parts of one panel (one unless a cut split it)
            sb = float(ab[p.faces].sum())
            unchanged = (
                len(now) == 1 and len(p.faces) == len(p0.faces) and abs(sb - s0) <= 1e-9 * s0
            )
            if not unchanged and not reach:
                loc = locate_points(g0.V2, g0.F2, m.to_panel(_piece_curve(piece)), faces=p0.faces)
                reach = float(loc.distance.max(initial=0.0))
            cp = carry_piece(
                piece,
                m,
                V2=base.V2,
                F2=base.F2,
                faces=p.faces,
                V2_new=adj.result.V2,
                unchanged=unchanged,
                reach=reach,
                original=(g0.V2, g0.F2, p0.faces),
            )
            if k:
                suffix = p.name[len(p0.name) :] if p.name.startswith(p0.name) else f"_{k}"
                cp = replace(cp, piece=replace(cp.piece, name=f"{piece.name}{suffix}"))
            group.append(cp)
            pieces.append(replace(piece, name=cp.piece.name) if k else piece)
            matches.append(m)
            from_file.append(ff)
            names.append(p.name)
            covered.add(p.name)
        if len(group) > 1 and all(c.kept is not None for c in group):
            # a mark is dropped only when no part keeps it
            lost = ~np.logical_or.reduce([c.kept for c in group])
            group = [
                replace(c, dropped=int(lost.sum()) if k == 0 else 0) for k, c in enumerate(group)
            ]
        out += group
    rest = [p for p in adj.state.panels if p.name not in covered]
    if rest:
        g = adj.garment
        grain = grain_directions(g.V2, g.F2, g.V3, g.F3, list(adj.state.panels), up=up)
        drawn = mesh_pieces(g.V2, g.F2, rest, F3=g.F3, V3=g.V3, grain=grain)
        for p, pc in zip(rest, drawn, strict=True):  # a loop over panels
            pieces.append(pc)
            matches.append(PieceMatch(len(pieces) - 1, -1, "mesh", np.eye(2), np.zeros(2), 0.0))
            from_file.append(False)
            names.append(p.name)
            out.append(CarriedPiece(piece=pc, outline_from="mesh", dropped=0))
    matches = [replace(mm, piece=i) for i, mm in enumerate(matches)]
    new_plan = replace(
        plan,
        pieces=tuple(pieces),
        matches=tuple(matches),
        from_file=tuple(from_file),
        panel_names=tuple(names),
    )
    return new_plan, out, first


def adjusted_pieces(adj: Adjustment, plan: PiecePlan) -> list[CarriedPiece | None]:
    """Carry every planned piece through an adjustment (one per planned piece).

    Parameters
    ----------
    adj : Adjustment
    plan : PiecePlan
        Made on ``adj.original`` (the input garment).

    Returns
    -------
    list of CarriedPiece or None
        One per piece of ``plan`` (a split panel's first part); ``None`` where the piece's
        panel was removed whole. :func:`carry_plan` gives every part its piece.
    """
    _, carried, first = _carry(adj, plan, up=(0.0, 1.0, 0.0))
    return [carried[k] for k in first]
