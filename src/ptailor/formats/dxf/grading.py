"""Graded sizes: carrying the marks a sample-size piece has to the same piece of
another size, by an affine fit of corresponding outlines or by length along them.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ptailor import tolerances as tol
from ptailor.formats.dxf.astm import quantity_text
from ptailor.formats.dxf.entities import Candidate, apply_affine
from ptailor.model.correspond import grade_fit
from ptailor.model.pieces import Piece


def fill_from_sample(
    pieces: tuple[Piece, ...],
    cands: list[Candidate],
    sample_p: list[Piece],
    sample_c: list[Candidate],
    size: str,
    sample: str,
) -> tuple[tuple[Piece, ...], tuple[str, ...]]:
    """Give a graded size's pieces what their sample-size piece has and they lack.

    Graded blocks often hold only the cut line. The quantity and annotations are copied;
    turn points, notches, grain and fold lines, drill holes and internal lines are
    carried when the two outlines have corresponding points (same count, an affine fit
    from the sample outline to this one within ``DXF_GRADE_FIT_REL`` of its diagonal): turn
    flags by index, notches at the same fraction of the same outline segment, the rest by
    the affine fit. Each piece that lacked something gets a warning saying what was
    carried and what could not be.

    Returns
    -------
    pieces : tuple of Piece
    warnings : tuple of str
    """
    by_name = {sp.name.casefold(): (sp, sc) for sp, sc in zip(sample_p, sample_c, strict=True)}
    out, warns = [], []
    for p, c in zip(pieces, cands, strict=True):  # a loop over pieces
        hit = by_name.get(p.name.casefold())
        if hit is None:
            out.append(p)
            continue
        piece, msg = _carry_from_sample(p, c, *hit, size=size, sample=sample)
        if msg:
            warns.append(msg)
        out.append(piece)
    return tuple(out), tuple(warns)


def _carry_from_sample(
    p: Piece, c: Candidate, sp: Piece, sc: Candidate, *, size: str, sample: str
) -> tuple[Piece, str]:
    """Piece ``p`` of size ``size`` with what its sample-size piece ``sp`` has and it lacks,
    and the warning saying so (``""`` when nothing was lacking)."""
    ch: dict[str, Any] = {}
    carried, lost = [], []
    if not c.has_quantity and sc.has_quantity:
        ch.update(quantity=sp.quantity, quantity_split=sp.quantity_split)
        carried.append(f"quantity {quantity_text(sp).split(': ')[1]}")
    if not p.annotations and sp.annotations:
        ch["annotations"] = sp.annotations
        carried.append("annotations")
    A = grade_fit(sp.outline, p.outline)
    arc = _ArcMap.fit(sp.outline, p.outline) if A is None else None
    if arc is not None:
        A = arc.box
    lacks = {
        "turn points": bool(sp.turn.any()) and not p.turn.any(),
        "notches": len(sp.notches) > 0 and len(p.notches) == 0,
        "grain line": sp.grain is not None and p.grain is None,
        "fold line": sp.mirror is not None and p.mirror is None,
        "drill holes": len(sp.drills) > 0 and len(p.drills) == 0,
        "internal lines": len(sp.internal) > 0 and len(p.internal) == 0,
    }
    for what, missing in lacks.items():  # six kinds of mark
        if missing:
            (lost if A is None else carried).append(what)
            if A is not None:
                ch.update(_carried_mark(what, sp, p, A, arc))
    msg = ""
    if carried or lost:
        msg = f"size {size}: piece {p.name!r} lacks what sample size {sample} has"
        if carried:
            msg += f"; carried from size {sample}: {', '.join(carried)}"
        if arc is not None:
            msg += " (outlines matched by length along them, not point by point)"
        if lost:
            msg += f"; not carried (outlines that do not correspond): {', '.join(lost)}"
    return (replace(p, **ch) if ch else p), msg


def _carried_mark(
    what: str,
    sp: Piece,
    p: Piece,
    A: tuple[np.ndarray, np.ndarray],
    arc: _ArcMap | None,
) -> dict[str, Any]:
    """The fields of ``p`` that carry mark ``what`` from sample-size piece ``sp``: by index
    or segment fraction when the outlines correspond point by point, else by ``arc``; the
    affine fit ``A`` places the free marks."""
    if what == "turn points":
        return {"turn": sp.turn.copy() if arc is None else arc.turn(sp.turn)}
    if what == "notches":
        notches = (
            _same_place(sp.outline, p.outline, sp.notches)
            if arc is None
            else arc.points(sp.notches)
        )
        return {
            "notches": notches,
            "notch_angles": np.asarray(sp.notch_angles, dtype=float).copy(),
        }
    if what == "grain line":
        return {"grain": apply_affine(sp.grain, A)}
    if what == "fold line":
        return {"mirror": apply_affine(sp.mirror, A)}
    if what == "drill holes":
        return {"drills": apply_affine(sp.drills, A)}
    return {"internal": tuple(apply_affine(a, A) for a in sp.internal)}


def _arc_params(P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each point's arc-length parameter along closed outline ``P`` (0 at ``P[0]``, total
    1), ``(k,)``, and each segment's length as a fraction, ``(k,)``."""
    seg = np.linalg.norm(np.roll(P, -1, axis=0) - P, axis=1)
    total = max(float(seg.sum()), tol.TINY)
    return np.r_[0.0, np.cumsum(seg)[:-1]] / total, seg / total


def _at_params(P: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Points at arc-length parameters ``u`` (``(q,)``, modulo 1) along closed outline ``P``."""
    cum, frac = _arc_params(P)
    u = np.mod(u, 1.0)
    i = np.clip(np.searchsorted(cum, u, side="right") - 1, 0, len(P) - 1)
    t = (u - cum[i]) / np.maximum(frac[i], tol.TINY)
    return P[i] + np.clip(t, 0.0, 1.0)[:, None] * (np.roll(P, -1, axis=0)[i] - P[i])


@dataclass(frozen=True)
class _ArcMap:
    """A graded outline matched to the sample's by length along them (point counts differ).

    ``S`` is the sample outline put into the graded one's bounding box (``box``, row
    vectors ``x @ A + t``), ``D`` the graded outline started at the point nearest ``S[0]``
    (``j0``); a parameter ``u`` in ``[0, 1)`` is the same fraction of the way round both.
    """

    box: tuple[np.ndarray, np.ndarray]
    S: np.ndarray
    D: np.ndarray
    j0: int

    @classmethod
    def fit(cls, src: np.ndarray, dst: np.ndarray) -> _ArcMap | None:
        """The map, or None when the outlines, so matched, lie further apart on average than
        ``DXF_GRADE_FIT_REL`` of the graded outline's diagonal."""
        if len(src) < 3 or len(dst) < 3:
            return None
        lo_s, lo_d = src.min(axis=0), dst.min(axis=0)
        k = np.ptp(dst, axis=0) / np.maximum(np.ptp(src, axis=0), tol.TINY)
        box = (np.diag(k), lo_d - lo_s * k)
        S = apply_affine(src, box)
        j0 = int(np.argmin(np.linalg.norm(dst - S[0], axis=1)))
        D = np.roll(dst, -j0, axis=0)
        u = np.linspace(0.0, 1.0, 256, endpoint=False)
        gap = float(np.linalg.norm(_at_params(S, u) - _at_params(D, u), axis=1).mean())
        diag = float(np.hypot(*np.ptp(dst, axis=0)))
        return cls(box, S, D, j0) if gap <= tol.DXF_GRADE_FIT_REL * max(diag, tol.TINY) else None

    def points(self, pts: np.ndarray) -> np.ndarray:
        """Points on (or near) the sample outline, at the same parameter on the graded one."""
        pts = apply_affine(np.asarray(pts, dtype=float).reshape(-1, 2), self.box)
        seg, tk = _nearest_segment(self.S, pts)
        cum, frac = _arc_params(self.S)
        u = cum[seg] + tk * frac[seg]
        return _at_params(self.D, u)

    def turn(self, flags: np.ndarray) -> np.ndarray:
        """Turn flags of the sample outline's points as flags of the graded outline's points
        nearest them by parameter, ``(len(dst),)``."""
        cu, _ = _arc_params(self.S)
        cd, _ = _arc_params(self.D)
        diff = np.abs(cd[None, :] - cu[np.asarray(flags, dtype=bool)][:, None])
        near = np.argmin(np.minimum(diff, 1.0 - diff), axis=1)
        out = np.zeros(len(self.D), dtype=bool)
        out[(near + self.j0) % len(self.D)] = True
        return out


def _same_place(src: np.ndarray, dst: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """Points near outline ``src`` at the same segment and fraction on ``dst``, ``(k, 2)``
    (the outlines correspond point by point)."""
    seg, tk = _nearest_segment(src, np.asarray(pts, dtype=float).reshape(-1, 2))
    A2, B2 = dst[seg], np.roll(dst, -1, axis=0)[seg]
    return A2 + tk[:, None] * (B2 - A2)


def _nearest_segment(P: np.ndarray, pts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The segment of closed outline ``P`` (``(n, 2)``; segment ``i`` runs from ``P[i]`` to
    ``P[i + 1]``) nearest to each of ``pts`` (``(k, 2)``), and the fraction along it of each
    point's foot: ``(k,)`` int and ``(k,)`` float in ``[0, 1]``."""
    A, B = P, np.roll(P, -1, axis=0)
    d = B - A  # (n, 2)
    dd = np.maximum(np.einsum("ij,ij->i", d, d), tol.TINY)
    t = np.clip(np.einsum("kij,ij->ki", pts[:, None] - A[None], d) / dd, 0.0, 1.0)  # (k, n)
    foot = A[None] + t[..., None] * d[None]
    seg = np.argmin(np.linalg.norm(pts[:, None] - foot, axis=2), axis=1)
    return seg, t[np.arange(len(pts)), seg]
