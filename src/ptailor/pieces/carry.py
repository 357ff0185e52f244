"""Carrying one piece's outline and marks through an adjustment.

Every point of the piece is located in its panel's triangles and carried to the adjusted
pattern with the same barycentric coordinates (points just off the mesh keep their offset:
the triangle's affine map is extended). A grain line keeps its direction relative to the
piece: its middle is carried, its direction turns with the panel's best-fit rotation, its
length follows the carried ends. A panel that lost or gained triangles (shorten, cut,
extend) gets the mesh's new outline; marks on the part cut away are dropped and counted.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ptailor import tolerances as tol
from ptailor.method.transfer import carry_points, locate_points
from ptailor.model import tolerances as model_tol
from ptailor.model.offset import offset_closed
from ptailor.model.pieces import Piece
from ptailor.model.polyline import clip_half_plane, corners, dedupe_closed
from ptailor.pieces.draw import outer_loop
from ptailor.pieces.match import ClosedCurve, PieceMatch


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
    preimage : (k, 2) float array or None
        With ``outline_from == "mesh"``: where each point of the new outline was before the
        adjustment, in the original piece's coordinates (None for a fold piece's half,
        whose outline is clipped, and for carried outlines, whose points are the piece's).
    marks_kept : MarksKept or None
        Which of the original piece's notches, drill holes and internal-line points the
        new piece holds (None for pieces drawn from the mesh).
    """

    piece: Piece
    outline_from: str
    dropped: int
    kept: np.ndarray | None = None
    preimage: np.ndarray | None = None
    marks_kept: MarksKept | None = None


@dataclass(frozen=True)
class MarksKept:
    """Which of a piece's marks an adjustment kept, in the original piece's order.

    Attributes
    ----------
    notches : (m,) bool array
    drills : (h,) bool array
    internal : tuple of (j_i,) bool arrays
        Per internal line, its points kept; a line of fewer than 2 kept points is dropped.
    """

    notches: np.ndarray
    drills: np.ndarray
    internal: tuple[np.ndarray, ...]


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
    groups = _mark_groups(piece, unchanged=unchanged)
    # every point located at once (one search structure per piece), then split by group
    X = match.to_panel(np.vstack([np.asarray(g, dtype=np.float64).reshape(-1, 2) for g in groups]))
    loc = locate_points(V2, F2, X, faces=faces)
    moved = match.to_piece(carry_points(V2_new, F2, loc)) if len(X) else np.zeros((0, 2))
    kept = _kept_points(
        X, loc.distance, unchanged=unchanged, original=original, keep_d=keep_d, diag=diag
    )
    cuts = np.cumsum([len(g) for g in groups])[:-1]
    moved_g, kept_g = np.split(moved, cuts), np.split(kept, cuts)
    outline, turn, sew, how, pre = _new_outline(
        piece, match, moved_g, V2=V2, F2=F2, faces=faces, V2_new=V2_new, unchanged=unchanged
    )
    keep_n = kept_g[2]
    if not unchanged:  # on the mesh's outline, before a fold piece is halved
        keep_n = keep_n & _on_outline(moved_g[2], outline, diag=diag, keep_d=keep_d)
    # a fold line is a line: its ends extend; one cut away is 2 marks dropped
    mirror = moved_g[5] if piece.mirror is not None and (kept_g[5].all() or match.fold) else None
    dropped = 2 if piece.mirror is not None and mirror is None else 0
    if match.fold and not unchanged and mirror is not None:
        outline, turn, mirror = _fold_half(piece, outline, turn, mirror, diag=diag)
        pre = None
    new, lost = _with_carried_marks(
        piece, moved_g, kept_g,
        keep_n=keep_n, outline=outline, turn=turn, sew=sew, mirror=mirror,
        Rq=_piece_rotation(match, V2=V2, F2=F2, faces=faces, V2_new=V2_new),
    )  # fmt: skip
    # a grain line is never lost (drawn again)
    marks_kept = np.concatenate([*kept_g[2:4], np.ones(len(kept_g[4]), dtype=bool), *kept_g[5:]])
    kept_by_kind = MarksKept(keep_n.copy(), kept_g[3].copy(), tuple(kept_g[6:]))
    return CarriedPiece(new, how, dropped + lost, marks_kept, pre, kept_by_kind)


def _kept_points(
    X: np.ndarray,
    distance: np.ndarray,
    *,
    unchanged: bool,
    original: tuple[np.ndarray, np.ndarray, np.ndarray] | None,
    keep_d: float,
    diag: float,
) -> np.ndarray:
    """Which located mark points are kept, as :func:`carry_piece` says.

    Parameters
    ----------
    X : (q, 2) float array
        The points, in panel coordinates.
    distance : (q,) float array
        How far each lies from the remaining triangles (:func:`locate_points`).
    unchanged : bool
        The panel kept all its triangles: every point is kept.
    original : (V2_0, F2_0, faces_0) or None
        The input pattern and the panel's triangles in it: a point is kept when it lies no
        further from the remaining triangles than from these (plus ``MARK_KEEP_REL`` of
        ``diag``); without, when within ``keep_d``.

    Returns
    -------
    (q,) bool array
    """
    if unchanged:
        return np.ones(len(X), dtype=bool)
    if original is not None:
        d_orig = locate_points(original[0], original[1], X, faces=original[2])
        return distance <= d_orig.distance + tol.MARK_KEEP_REL * diag
    return distance <= keep_d


def _piece_rotation(
    match: PieceMatch, *, V2: np.ndarray, F2: np.ndarray, faces: np.ndarray, V2_new: np.ndarray
) -> np.ndarray:
    """The panel's best-fit rotation from ``V2`` to ``V2_new``, seen in piece coordinates
    (``(2, 2)``): notch directions and the grain turn with it."""
    vs = np.zeros(len(V2), dtype=bool)  # the panel's vertices, ascending (np.unique's, no sort)
    vs[F2[faces].ravel()] = True
    return match.R.T @ _panel_rotation(V2[vs], V2_new[vs]) @ match.R


def _with_carried_marks(
    piece: Piece,
    moved_g: list[np.ndarray],
    kept_g: list[np.ndarray],
    *,
    keep_n: np.ndarray,
    outline: np.ndarray,
    turn: np.ndarray,
    sew: np.ndarray | None,
    mirror: np.ndarray | None,
    Rq: np.ndarray,
) -> tuple[Piece, int]:
    """The adjusted piece: its new outline, turn points, sew and fold lines, and the marks
    kept of the carried ones (:func:`_carried_points`).

    Parameters
    ----------
    keep_n : (k,) bool array
        The notches kept (``kept_g[2]``, less those off a changed panel's outline).
    Rq : (2, 2) float array
        :func:`_piece_rotation`: notch angles and the grain turn with it.

    Returns
    -------
    Piece
    int
        The notches, drill holes and internal-line points dropped.
    """
    notches = moved_g[2]
    drills, keep_d_ = moved_g[3], kept_g[3]
    dropped = int((~keep_n).sum() + (~keep_d_).sum())
    internal = []
    for L, keep in zip(moved_g[6:], kept_g[6:], strict=True):  # a piece's internal lines
        dropped += int((~keep).sum())
        if keep.sum() >= 2:
            internal.append(L[keep])
    turn_deg = float(np.degrees(np.arctan2(Rq[1, 0], Rq[0, 0])))
    angles = piece.notch_angles if len(piece.notch_angles) == len(keep_n) else np.zeros(len(keep_n))
    new = replace(
        piece,
        outline=outline,
        turn=turn,
        notches=notches[keep_n],
        # to 1e-9 degrees first: a turn of -1e-16 is 0, not 360 (which it would be after mod)
        notch_angles=np.mod(np.round(angles[keep_n] + turn_deg, 9), 360.0),
        grain=_carried_grain(piece, moved_g[4], kept_g[4], Rq=Rq, outline=outline),
        internal=tuple(internal),
        drills=drills[keep_d_],
        sew=sew,
        mirror=mirror,
    )
    return new, dropped


def _mark_groups(piece: Piece, *, unchanged: bool) -> list[np.ndarray]:
    """A piece's points by group: outline and sew line (when ``unchanged``, else empty),
    notches, drill holes, grain line (ends and middle), fold line, each internal line."""
    empty = np.zeros((0, 2))
    grain_pts = (
        np.vstack([piece.grain, piece.grain.mean(axis=0, keepdims=True)])
        if piece.grain is not None
        else empty
    )
    return [
        piece.outline if unchanged else empty,
        piece.sew if unchanged and piece.sew is not None else empty,
        piece.notches,
        piece.drills,
        grain_pts,
        piece.mirror if piece.mirror is not None else empty,
        *piece.internal,
    ]


def _new_outline(
    piece: Piece,
    match: PieceMatch,
    moved_g: list[np.ndarray],
    *,
    V2: np.ndarray,
    F2: np.ndarray,
    faces: np.ndarray,
    V2_new: np.ndarray,
    unchanged: bool,
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, str, np.ndarray | None]:
    """The carried outline ``(k, 2)``, its turn points, sew line, where it came from: the
    piece's own points (``carried``) or the adjusted mesh's boundary (``mesh``), and for a
    mesh outline where its points were in ``V2`` (piece coordinates, ``(k, 2)``)."""
    if unchanged:
        sew = moved_g[1] if piece.sew is not None else None
        return moved_g[0], piece.turn, sew, "carried", None
    loop = outer_loop(F2, faces, V2_new)
    outline, pre = match.to_piece(V2_new[loop]), match.to_piece(V2[loop])
    if np.linalg.det(match.R) < 0:
        outline, pre = outline[::-1], pre[::-1]
    return outline, corners(outline), None, "mesh", pre


def _on_outline(
    notches: np.ndarray, outline: np.ndarray, *, diag: float, keep_d: float
) -> np.ndarray:
    """Which notches ``(k, 2)`` still mark the outline, ``(k,)`` bool.

    One the edit left inside the piece (the old hem of an extended skirt) no longer marks
    anything.
    """
    if not len(notches):
        return np.ones(0, dtype=bool)
    scale = float(np.linalg.norm(np.ptp(outline, axis=0))) / max(diag, tol.TINY)
    return ClosedCurve(outline).nearest(notches)[0] <= keep_d * max(scale, 1.0)


def _fold_half(
    piece: Piece, outline: np.ndarray, turn: np.ndarray, mirror: np.ndarray, *, diag: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A fold piece's half of the mesh outline: the side of the carried fold line
    ``mirror`` the piece lies on; its outline, turn points and fold line trimmed to it."""
    a0, b0 = np.asarray(piece.mirror, dtype=float)[[0, -1]]
    d0 = b0 - a0
    side = float(np.sign(np.mean((piece.outline - a0) @ np.array([-d0[1], d0[0]]))))
    half = clip_half_plane(outline, mirror[0], mirror[-1], side or 1.0)
    half = half[dedupe_closed(half, rel=tol.ROUNDING_REL)]
    if len(half) < 3:
        return outline, turn, mirror
    u = mirror[-1] - mirror[0]
    u = u / max(float(np.linalg.norm(u)), tol.TINY)
    on = np.abs((half - mirror[0]) @ np.array([-u[1], u[0]])) <= tol.ROUNDING_REL * diag + 1e-12
    if on.sum() >= 2:
        t = (half[on] - mirror[0]) @ u
        mirror = mirror[0] + np.outer([t.min(), t.max()], u)
    return half, corners(half), mirror


def _carried_grain(
    piece: Piece, moved: np.ndarray, kept: np.ndarray, *, Rq: np.ndarray, outline: np.ndarray
) -> np.ndarray | None:
    """The grain line after the adjustment, ``(2, 2)``, from its carried ends and middle.

    Its direction turns with the panel (``Rq``, in piece coordinates). A grain line that
    lay on the part cut away is drawn again through the piece's middle, across half the
    piece: a cutter needs one.
    """
    if piece.grain is None:
        return None
    d0 = piece.grain[1] - piece.grain[0]
    u = Rq @ (d0 / max(np.linalg.norm(d0), tol.TINY))
    if kept[:2].all() or kept[2]:
        ends, mid = moved[:2], moved[2]
        length = float(np.linalg.norm(ends[1] - ends[0]))
        return np.stack([mid - 0.5 * length * u, mid + 0.5 * length * u])
    c = outline.mean(axis=0)
    half = 0.25 * float(np.ptp(outline @ u))
    return np.stack([c - half * u, c + half * u])


def scale_piece(piece: Piece, k: float) -> Piece:
    """Every coordinate of ``piece`` times ``k`` (a change of units)."""
    return piece.map_points(lambda a: a * k)


def with_seam_allowance(piece: Piece, d: float, *, edges: np.ndarray | None = None) -> Piece:
    """The piece with its outline as the sew line and the outline offset by ``d`` as cut line.

    The cut line is GEOS's (:func:`ptailor.model.offset.offset_closed`): a simple closed
    polygon, corners mitred. A piece cut on the fold (``mirror``) gets no allowance along
    the fold line. Turn points of the new outline are its corners (where it turns by more
    than ``tolerances.CORNER_DEG``).

    Parameters
    ----------
    piece : Piece
    d : float
        The allowance, ``>= 0``, in the piece's units.
    edges : (k,) float array, optional
        One allowance per outline edge (edge ``i`` runs from ``outline[i]`` to
        ``outline[i + 1]``), in place of ``d`` (a hem 3 cm, the seams 1 cm).

    Returns
    -------
    Piece
    """
    P = np.asarray(piece.outline, dtype=np.float64)
    dd = np.full(len(P), float(d)) if edges is None else np.asarray(edges, dtype=np.float64)
    if piece.mirror is not None and len(P):
        dd = np.where(_on_fold(P, np.asarray(piece.mirror, dtype=np.float64)), 0.0, dd)
    cut = offset_closed(P, dd)
    return replace(piece, sew=piece.outline, outline=cut, turn=corners(cut))


def _on_fold(P: np.ndarray, mirror: np.ndarray) -> np.ndarray:
    """Per outline edge ``(k,)``, whether both its ends lie on the fold line ``mirror``."""
    a, b = mirror[0], mirror[-1]
    u = (b - a) / max(float(np.linalg.norm(b - a)), tol.TINY)
    off = np.abs((P - a) @ np.array([-u[1], u[0]]))
    on = off <= model_tol.FOLD_ON_LINE_REL * max(float(np.linalg.norm(np.ptp(P, axis=0))), tol.TINY)
    return on & np.roll(on, -1)
