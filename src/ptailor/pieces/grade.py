"""Graded nests: the alteration made on one size carried to every size, grades kept.

A graded CAD pattern holds each piece in every size; the drape is of one size (the base:
the sample size, or ``--size``). The adjustment carries the base size's pieces; every other
size's piece then keeps its grade (its difference from the base) as grade rules do:

    graded_s[k] = adjusted_base[k] + (original_s[k] - original_base[k])

point by point, and likewise for every mark (notches, drill holes, the grain line's and fold
line's ends, internal-line points, the sew line). Outlines that do not correspond point by
point (another number of points) are corresponded by length between turn points
(:mod:`ptailor.model.correspond`), and a warning names the piece and size. A piece whose
panel lost or gained triangles takes the adjusted base outline, each point moved by the grade
where it was before the adjustment.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ptailor import tolerances as tol
from ptailor.model.correspond import (
    Places,
    at_places,
    by_length,
    corresponding,
    nearest_places,
)
from ptailor.model.pieces import PatternFile, Piece
from ptailor.model.units import CM_PER
from ptailor.pieces.carry import CarriedPiece, MarksKept, scale_piece
from ptailor.pieces.plan import PiecePlan


@dataclass(frozen=True)
class GradedNest:
    """Every size's adjusted pieces.

    Attributes
    ----------
    base : str
        The size the drape is of (its pieces were adjusted).
    sizes : tuple of str
        The sizes, in the file's order.
    pieces : tuple of tuple of (Piece or None)
        Per size, one per carried piece of the run (computation units; None where the
        base piece's panel was removed, or the size has no such piece).
    records : tuple of dict
        Per size and piece: ``size``, ``piece``, ``outline`` (how its points were
        corresponded with the base size's), ``marks`` (``by index`` or ``by place``),
        ``points``, ``grade_max`` (the largest distance between a point and its base-size
        point, in the pattern file's unit), ``area`` (the adjusted piece's, in the file's
        unit squared).
    warnings : tuple of str
    """

    base: str
    sizes: tuple[str, ...]
    pieces: tuple[tuple[Piece | None, ...], ...]
    records: tuple[dict, ...]
    warnings: tuple[str, ...]


def grade_nest(
    plan: PiecePlan,
    carried: list[CarriedPiece | None],
    base: PatternFile,
    sizes: tuple[PatternFile, ...],
    *,
    units: str,
) -> GradedNest:
    """Carry the base size's alteration to every size of a graded nest.

    Parameters
    ----------
    plan : PiecePlan
        The carried plan (:func:`ptailor.pieces.carry_plan`), in ``units``.
    carried : list of CarriedPiece or None
        One per piece of ``plan``.
    base : PatternFile
        The size the drape is of, as read (file units).
    sizes : tuple of PatternFile
        Every size to write, read in ``base.units``; the base size among them is written
        as carried.
    units : str
        The computation unit (the plan's pieces are in it).

    Returns
    -------
    GradedNest
    """
    k = CM_PER[base.units] / CM_PER[units]
    sources = plan.sources or (-1,) * len(plan.pieces)
    out, records, warnings = [], [], []
    for ps in sizes:  # a loop over sizes
        row: list[Piece | None] = []
        by_name = {p.name.casefold(): p for p in ps.pieces}
        for j, cp in enumerate(carried):  # a loop over pieces
            if cp is None:
                row.append(None)
                continue
            if ps.size == base.size:
                row.append(replace(cp.piece, size=ps.size))
                continue
            src = sources[j]
            own = by_name.get(base.pieces[src].name.casefold()) if src >= 0 else None
            if own is None:
                row.append(replace(cp.piece, size=ps.size) if src < 0 else None)
                warnings.append(
                    f"piece {cp.piece.name!r} is drawn from the mesh (no piece of the file): "
                    f"written in every size as size {base.size}'s"
                    if src < 0
                    else f"size {ps.size} has no piece {base.pieces[src].name!r}: "
                    f"{cp.piece.name!r} is not written in it"
                )
                continue
            own = scale_piece(own, k)
            piece, how, marks = grade_piece(plan.pieces[j], cp, own)
            piece = replace(piece, name=cp.piece.name, size=ps.size)
            row.append(piece)
            records.append(_record(ps.size, piece, plan.pieces[j], own, how, marks, k=k))
            if how != "point by point" or marks != "by index":
                warnings.append(
                    _warning(ps.size, base.size, piece.name, own, plan.pieces[j], how, marks)
                )
        out.append(tuple(row))
    return GradedNest(
        base=base.size,
        sizes=tuple(ps.size for ps in sizes),
        pieces=tuple(out),
        records=tuple(records),
        warnings=tuple(dict.fromkeys(warnings)),
    )


def _warning(size: str, base: str, name: str, own: Piece, p0: Piece, how, marks) -> str:
    """The warning for a piece of ``size`` not corresponded point by point with ``base``."""
    counts = f" ({len(own.outline)} points, size {base} {len(p0.outline)})"
    msg = f"size {size}: piece {name!r}: outline corresponded with size {base}'s {how}{counts}"
    if marks != "by index":
        msg += "; marks that do not correspond one to one moved as the nearest point of size "
        msg += f"{base}'s"
    return msg


def _record(size: str, piece: Piece, p0: Piece, ps: Piece, how: str, marks: str, *, k: float):
    """A size's piece for the report (lengths in the file's unit)."""
    pl = corresponding(p0.outline, p0.turn, ps.outline, ps.turn)
    grade = at_places(ps.outline, pl) - p0.outline
    return {
        "size": size,
        "piece": piece.name,
        "outline": how,
        "marks": marks,
        "points": len(piece.outline),
        "grade_max": round(float(np.linalg.norm(grade, axis=1).max(initial=0.0)) / k, 4),
        "area": round(piece.area / (k * k), 4),
    }


def grade_piece(p0: Piece, cp: CarriedPiece, ps: Piece) -> tuple[Piece, str, str]:
    """One size's piece adjusted as the base size's was, its grade kept.

    Parameters
    ----------
    p0 : Piece
        The base size's piece as read (the plan's), computation units.
    cp : CarriedPiece
        ``p0`` carried through the adjustment.
    ps : Piece
        The same piece in the other size, as read, computation units.

    Returns
    -------
    Piece
        ``ps`` adjusted.
    str
        How the outlines were corresponded (``point by point``, ``by length between turn
        points``, ...).
    str
        ``by index`` (every mark corresponds one to one with the base size's) or ``by
        place`` (some moved as the nearest point of the base size's piece).
    """
    p1 = cp.piece
    if cp.outline_from == "carried" and len(p1.outline) == len(p0.outline):
        pl = corresponding(ps.outline, ps.turn, p0.outline, p0.turn)
        outline = ps.outline + at_places(p1.outline - p0.outline, pl)
        turn, how = ps.turn, pl.how
    else:  # the panel changed: the adjusted outline, moved by the grade where it was
        pl0 = corresponding(p0.outline, p0.turn, ps.outline, ps.turn)
        grade = at_places(ps.outline, pl0) - p0.outline  # (n0, 2)
        pre = cp.preimage
        if pre is not None and len(pre) == len(p1.outline):
            where = nearest_places(p0.outline, pre)
        else:
            where = by_length(p1.outline, p1.turn, p0.outline, p0.turn)
        outline, turn, how = p1.outline + at_places(grade, where), p1.turn, pl0.how
    field = _alteration_field(p0, cp)
    new, by_index = _graded_marks(p0, cp, ps, field)
    new = replace(new, outline=outline, turn=np.asarray(turn, dtype=bool).copy())
    return new, how, "by index" if by_index else "by place"


def _alteration_field(p0: Piece, cp: CarriedPiece) -> tuple[np.ndarray, np.ndarray]:
    """Where the base size's alteration is known, in ``p0``'s coordinates, ``(q, 2)``, and
    its displacement there, ``(q, 2)``: the outline's points (or, for a changed panel, where
    the new outline's points were) and every mark kept."""
    p1, mk = cp.piece, cp.marks_kept
    if cp.outline_from == "carried" and len(p1.outline) == len(p0.outline):
        K, D = [p0.outline], [p1.outline - p0.outline]
    elif cp.preimage is not None and len(cp.preimage) == len(p1.outline):
        K, D = [cp.preimage], [p1.outline - cp.preimage]
    else:
        K, D = [p0.outline], [at_places(p1.outline, _on(p0, p1)) - p0.outline]
    if mk is not None:
        for a0, a1, m in ((p0.notches, p1.notches, mk.notches), (p0.drills, p1.drills, mk.drills)):
            if len(a0) == len(m) and int(m.sum()) == len(a1):
                K.append(a0[m])
                D.append(a1 - a0[m])
    return np.vstack(K), np.vstack(D)


def _on(p0: Piece, p1: Piece) -> Places:
    """Where ``p0``'s points fall on ``p1``'s outline, by length between turn points."""
    return by_length(p0.outline, p0.turn, p1.outline, p1.turn)


def _by_field(X: np.ndarray, ps: Piece, p0: Piece, field) -> np.ndarray:
    """Points ``X`` of size ``ps`` (``(q, 2)``) moved by the base size's alteration at the
    nearest place it is known, ``X`` laid over ``p0``'s bounding box first."""
    from scipy.spatial import cKDTree

    X = np.asarray(X, dtype=float).reshape(-1, 2)
    if not len(X):
        return X.copy()
    lo_s, lo_0 = ps.outline.min(axis=0), p0.outline.min(axis=0)
    scale = np.ptp(p0.outline, axis=0) / np.maximum(np.ptp(ps.outline, axis=0), tol.TINY)
    K, D = field
    _, i = cKDTree(K).query((X - lo_s) * scale + lo_0)
    return X + D[np.asarray(i, dtype=np.int64)]


def _graded_marks(
    p0: Piece, cp: CarriedPiece, ps: Piece, field: tuple[np.ndarray, np.ndarray]
) -> tuple[Piece, bool]:
    """``ps`` with every mark moved as the base size's corresponding mark was (by index),
    or, where the marks do not correspond one to one, by the alteration ``field`` at the
    nearest place; and whether every mark went by index."""
    p1 = cp.piece
    mk = cp.marks_kept or MarksKept(
        np.ones(len(p0.notches), bool), np.ones(len(p0.drills), bool),
        tuple(np.ones(len(a), bool) for a in p0.internal),
    )  # fmt: skip
    notches, n_ok = _points(ps.notches, p0.notches, p1.notches, mk.notches, ps, p0, field)
    drills, d_ok = _points(ps.drills, p0.drills, p1.drills, mk.drills, ps, p0, field)
    ok = n_ok and d_ok
    angles = np.asarray(p1.notch_angles, dtype=float)
    if n_ok and len(ps.notch_angles) == len(ps.notches) and len(p0.notch_angles) == len(mk.notches):
        turn = angles - np.asarray(p0.notch_angles, dtype=float)[mk.notches]
        angles = np.mod(np.asarray(ps.notch_angles, dtype=float)[mk.notches] + turn, 360.0)
    elif not n_ok:
        angles = np.asarray(ps.notch_angles, dtype=float)
        if len(angles) != len(notches):
            angles = np.zeros(len(notches))
    lines = {}
    for what in ("grain", "mirror", "sew"):  # the lines that correspond end to end
        a0, a1, a_s = getattr(p0, what), getattr(p1, what), getattr(ps, what)
        if a1 is None or a_s is None or a0 is None:
            lines[what] = a1 if a_s is None and what == "grain" else None
        elif len(a0) == len(a1) == len(a_s):
            lines[what] = a_s + (a1 - a0)
        elif what == "sew" and len(a0) == len(a1):
            pl = corresponding(a_s, np.zeros(len(a_s), bool), a0, np.zeros(len(a0), bool))
            lines[what] = a_s + at_places(a1 - a0, pl)
        else:
            lines[what], ok = _by_field(a_s, ps, p0, field), False
    internal, i_ok = _internal(p0, p1, ps, mk, field)
    ok = ok and i_ok
    new = replace(
        ps, notches=notches, notch_angles=angles, drills=drills, internal=internal, **lines,
        quantity=p1.quantity, quantity_split=p1.quantity_split, annotations=p1.annotations,
    )  # fmt: skip
    return new, ok


def _points(
    a_s: np.ndarray,
    a0: np.ndarray,
    a1: np.ndarray,
    kept: np.ndarray,
    ps: Piece,
    p0: Piece,
    field: tuple[np.ndarray, np.ndarray],
) -> tuple[np.ndarray, bool]:
    """Marks of one kind (``(m, 2)``) of size ``ps``: those the base size kept, each moved
    as its base-size mark (``a0`` -> ``a1``, ``kept`` saying which ``a0`` survive), when
    the sizes' marks correspond one to one; else every one by the ``field``."""
    a_s = np.asarray(a_s, dtype=float).reshape(-1, 2)
    if len(a_s) == len(a0) == len(kept) and int(kept.sum()) == len(a1):
        return a_s[kept] + (a1 - a0[kept]), True
    return _by_field(a_s, ps, p0, field), not len(a_s)


def _internal(
    p0: Piece, p1: Piece, ps: Piece, mk: MarksKept, field: tuple[np.ndarray, np.ndarray]
) -> tuple[tuple[np.ndarray, ...], bool]:
    """Size ``ps``'s internal lines, each moved as the base size's (by index, the points the
    adjustment kept), or by the ``field`` when they do not correspond one to one."""
    same = len(ps.internal) == len(p0.internal) == len(mk.internal) and all(
        len(a) == len(b) == len(m)
        for a, b, m in zip(ps.internal, p0.internal, mk.internal, strict=True)
    )
    same = same and sum(int(m.sum() >= 2) for m in mk.internal) == len(p1.internal)
    if not same:
        return tuple(_by_field(a, ps, p0, field) for a in ps.internal), not ps.internal
    out, r = [], 0
    for a_s, a0, m in zip(ps.internal, p0.internal, mk.internal, strict=True):  # lines
        if m.sum() >= 2:
            out.append(a_s[m] + (p1.internal[r] - a0[m]))
            r += 1
    return tuple(out), True
