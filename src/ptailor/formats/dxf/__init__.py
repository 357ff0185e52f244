"""AAMA/ASTM D6673 DXF pattern files: read pieces with their marks, write them back.

A piece is a block INSERTed in modelspace (or, in files without blocks, a closed boundary
drawn straight into modelspace). Layers follow ASTM D6673: 1 boundary (cut line) and piece
text, 2 turn points, 3 curve points, 4 and 80-83 notches, 5 grade reference, 6 mirror line,
7 grain line, 8 internal lines, 11 internal cutouts, 13 drill holes, 14 sew line,
15 annotation text, 84 and up quality-validation curves (ignored).

The writer produces DXF R12 in the flavour Gerber AccuMark imports (no TABLES section, see
:mod:`ezdxf.addons.gerber_D6673`): one block per piece, INSERTed at the origin.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import io
import logging
import os
import re
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from ptailor import tolerances as _tol
from ptailor.errors import PtailorError
from ptailor.model.pieces import PatternFile, Piece
from ptailor.model.polyline import dedupe_closed, signed_area

#: centimetres per file unit
CM_PER_UNIT: dict[str, float] = {"mm": 0.1, "cm": 1.0, "in": 2.54}
#: $INSUNITS codes the reader understands
_INSUNITS = {1: "in", 4: "mm", 5: "cm"}

L_BOUNDARY, L_TURN, L_NOTCH, L_GRAIN, L_INTERNAL = "1", "2", "4", "7", "8"
L_CUTOUT, L_DRILL, L_SEW, L_TEXT = "11", "13", "14", "15"
L_MIRROR = "6"
NOTCH_LAYERS = frozenset({"4", "80", "81", "82", "83"})
LAYOUTS = ("auto", "keep", "row")

#: chaining / closing tolerance, relative to a piece's bounding-box diagonal
REL_TOL = 1e-3
#: consecutive outline points closer than this (relative) are one point
REL_DUP = 1e-9
#: a METRIC file whose largest piece is smaller than this many units is in centimetres
#: (a pattern's largest piece is 5-200 cm: 50-2000 in mm); otherwise METRIC is millimetres
CM_BELOW = 25.0
#: a pattern's largest piece, in cm, outside this range means the units are wrong
PLAUSIBLE_CM = (2.0, 500.0)
#: a file that names no unit is in millimetres when its largest piece exceeds this
MM_ABOVE = 300.0


# --------------------------------------------------------------------------- reading


@dataclass
class _Marks:
    """Geometry of one piece candidate, already in modelspace coordinates."""

    boundary: list[np.ndarray] = field(default_factory=list)
    turn: list[tuple[float, float]] = field(default_factory=list)
    notches: list[tuple[float, float]] = field(default_factory=list)
    notch_angles: list[float] = field(default_factory=list)
    notch_lines: list[np.ndarray] = field(default_factory=list)
    grain: list[np.ndarray] = field(default_factory=list)
    mirror: list[np.ndarray] = field(default_factory=list)
    internal: list[np.ndarray] = field(default_factory=list)
    drills: list[tuple[float, float]] = field(default_factory=list)
    sew: list[np.ndarray] = field(default_factory=list)
    internal_is_line: list[bool] = field(default_factory=list)
    texts: list[tuple[str, str, tuple[float, float]]] = field(default_factory=list)
    #: entities that could not be used: ``"boundary POLYLINE 3 (layer 1): vertex 2 is not a
    #: number"``; a piece built from these marks is refused with the first
    problems: list[str] = field(default_factory=list)


@dataclass
class _Candidate:
    """One INSERT (or one modelspace loop): a piece of some size."""

    block: str
    marks: _Marks
    name: str = ""
    size: str = ""
    quantity: int = 1
    annotations: tuple[str, ...] = ()
    quantity_split: tuple[int, int] | None = None
    has_quantity: bool = False


_QUANTITY = re.compile(r"^\s*(\d+)\s*(?:[,;/]\s*(\d+)\s*)?$")


def parse_quantity(text: str) -> tuple[int, tuple[int, int] | None] | None:
    """A ``Quantity:`` value: ``"2"`` -> ``(2, None)``; ASTM D6673's ``"a,b"`` (``a`` cut
    as drawn, ``b`` mirrored) -> ``(a + b, (a, b))``; anything else -> None."""
    m = _QUANTITY.match(text)
    if m is None:
        try:  # "2.0"
            f = float(text)
        except ValueError:
            return None
        ok = np.isfinite(f) and f.is_integer() and 0 <= f <= 1e9
        return (int(f), None) if ok else None
    a = int(m.group(1))
    if m.group(2) is None:
        return a, None
    b = int(m.group(2))
    return a + b, (a, b)


def quantity_text(p: Piece) -> str:
    """``Quantity:`` text of a piece: ``a,b`` when it was read so, else the count."""
    if p.quantity_split is not None and sum(p.quantity_split) == int(p.quantity):
        a, b = p.quantity_split
        return f"Quantity: {int(a)},{int(b)}"
    return f"Quantity: {int(p.quantity)}"


def read_dxf(path: str | Path, *, size: str | None = None, units: str | None = None) -> PatternFile:
    """Read the pieces of one size from an AAMA/ASTM DXF pattern file.

    Parameters
    ----------
    path : str or Path
        The DXF file (Gerber AccuMark, CLO 3D, Optitex, ... exports).
    size : str, optional
        The size to read; by default the file's sample size (``Sample Size:``), else its
        first size.
    units : {"mm", "cm", "in"}, optional
        The unit of the coordinates, overriding what the file says (or what is judged from
        the piece sizes when the file says ``METRIC`` or nothing).

    Returns
    -------
    PatternFile
        Pieces in file order, outlines counter-clockwise, coordinates as in the file.

    Raises
    ------
    PtailorError
        Not a readable DXF, no pieces, an unknown size, or a boundary that does not close.
    """
    spath = str(path)
    if units is not None and units not in CM_PER_UNIT:
        raise PtailorError(f"unknown DXF units {units!r} (known: mm, cm, in)", path=spath)
    with _quiet() as log:
        try:
            return _read(spath, size, units, log)
        except PtailorError:
            raise
        except (ArithmeticError, LookupError, TypeError, ValueError, RecursionError) as exc:
            # fail closed: a file this reader's checks did not foresee is refused, not a crash
            raise PtailorError(
                f"not a usable DXF pattern ({type(exc).__name__}: {_one_line(exc)})", path=spath
            ) from exc
        except Exception as exc:
            from ezdxf.lldxf.const import DXFError

            if not isinstance(exc, DXFError):
                raise
            raise PtailorError(
                f"not a usable DXF pattern ({type(exc).__name__}: {_one_line(exc)})", path=spath
            ) from exc


def _read(spath: str, size: str | None, units: str | None, log: list[str]) -> PatternFile:
    """:func:`read_dxf`'s work, ezdxf's log going to ``log``."""
    doc = _open(spath, log)
    _check_counts(doc, spath)
    msp = doc.modelspace()
    style_text = _style_text(msp, spath)
    cands = _candidates(doc, spath)
    if not cands:
        raise PtailorError(
            "no pattern pieces in the file (no boundary on layer 1 in a block or in modelspace)",
            path=spath,
        )
    for c in cands:
        _parse_piece_text(c, spath)
    _sizes_from_block_names(cands)

    sizes = tuple(dict.fromkeys(c.size for c in cands if c.size))
    sample = style_text.get("SAMPLE SIZE", "")
    chosen = _choose_size(sizes, size, sample, spath)
    chosen_c = [c for c in cands if c.size in (chosen, "")]
    pieces = tuple(_build_piece(c, spath) for c in chosen_c)
    warnings: tuple[str, ...] = _recover_warning(log)
    if sample and chosen != sample and sample in sizes:
        sample_c = [c for c in cands if c.size == sample]
        sample_p = [_build_piece(c, spath) for c in sample_c]
        pieces, filled = _fill_from_sample(pieces, chosen_c, sample_p, sample_c, chosen, sample)
        for p in pieces:
            _check_piece(p, spath)
        warnings += filled

    units_text = style_text.get("UNITS", "")
    unit, note = _units(
        units,
        units_text,
        _header_number(doc, "$INSUNITS"),
        pieces,
        _header_number(doc, "$MEASUREMENT"),
    )
    largest = max((float(p.extent.max()) for p in pieces), default=0.0) * CM_PER_UNIT[unit]
    if pieces and not PLAUSIBLE_CM[0] <= largest <= PLAUSIBLE_CM[1]:
        warnings += (
            f"the largest piece is {largest:.4g} cm read in {unit} ({note}): check the units "
            "(--dxf-units)",
        )
    return PatternFile(
        pieces=pieces,
        units=unit,
        units_note=note,
        style=style_text.get("STYLE NAME", ""),
        sizes=sizes,
        size=chosen,
        sample_size=sample,
        path=spath,
        units_text=units_text,
        warnings=warnings,
    )


def _fill_from_sample(
    pieces: tuple[Piece, ...],
    cands: list[_Candidate],
    sample_p: list[Piece],
    sample_c: list[_Candidate],
    size: str,
    sample: str,
) -> tuple[tuple[Piece, ...], tuple[str, ...]]:
    """Give a graded size's pieces what their sample-size piece has and they lack.

    Graded blocks often hold only the cut line. The quantity and annotations are copied;
    turn points, notches, grain and fold lines, drill holes and internal lines are
    carried when the two outlines have corresponding points (same count, an affine fit
    from the sample outline to this one within ``GRADE_FIT_REL`` of its diagonal): turn
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
        sp, sc = hit
        ch: dict[str, Any] = {}
        carried, lost = [], []
        if not c.has_quantity and sc.has_quantity:
            ch.update(quantity=sp.quantity, quantity_split=sp.quantity_split)
            carried.append(f"quantity {quantity_text(sp).split(': ')[1]}")
        if not p.annotations and sp.annotations:
            ch["annotations"] = sp.annotations
            carried.append("annotations")
        A = _grade_fit(sp.outline, p.outline)
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
            if not missing:
                continue
            if A is None:
                lost.append(what)
                continue
            carried.append(what)
            if what == "turn points":
                ch["turn"] = sp.turn.copy() if arc is None else arc.turn(sp.turn)
            elif what == "notches":
                ch["notches"] = (
                    _same_place(sp.outline, p.outline, sp.notches)
                    if arc is None
                    else arc.points(sp.notches)
                )
                ch["notch_angles"] = np.asarray(sp.notch_angles, dtype=float).copy()
            elif what == "grain line":
                ch["grain"] = _apply(sp.grain, A)
            elif what == "fold line":
                ch["mirror"] = _apply(sp.mirror, A)
            elif what == "drill holes":
                ch["drills"] = _apply(sp.drills, A)
            else:
                ch["internal"] = tuple(_apply(a, A) for a in sp.internal)
        if carried or lost:
            msg = f"size {size}: piece {p.name!r} lacks what sample size {sample} has"
            if carried:
                msg += f"; carried from size {sample}: {', '.join(carried)}"
            if arc is not None:
                msg += " (outlines matched by length along them, not point by point)"
            if lost:
                msg += f"; not carried (outlines that do not correspond): {', '.join(lost)}"
            warns.append(msg)
        out.append(replace(p, **ch) if ch else p)
    return tuple(out), tuple(warns)


#: a graded outline corresponds to the sample's point by point when an affine fit between
#: them leaves an RMS residual below this fraction of the diagonal
GRADE_FIT_REL = 0.05


def _grade_fit(src: np.ndarray, dst: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """The affine map (row vectors: ``x @ A + t``) from outline ``src`` to ``dst`` taken point
    by point, or None when they do not correspond."""
    if len(src) != len(dst) or len(src) < 3:
        return None
    X = np.c_[src, np.ones(len(src))]
    M, *_ = np.linalg.lstsq(X, dst, rcond=None)  # (3, 2)
    rms = float(np.sqrt(np.mean(np.sum((X @ M - dst) ** 2, axis=1))))
    diag = float(np.hypot(*np.ptp(dst, axis=0)))
    return (M[:2], M[2]) if rms <= GRADE_FIT_REL * max(diag, 1e-300) else None


def _arc_params(P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each point's arc-length parameter along closed outline ``P`` (0 at ``P[0]``, total
    1), ``(k,)``, and each segment's length as a fraction, ``(k,)``."""
    seg = np.linalg.norm(np.roll(P, -1, axis=0) - P, axis=1)
    total = max(float(seg.sum()), 1e-300)
    return np.r_[0.0, np.cumsum(seg)[:-1]] / total, seg / total


def _at_params(P: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Points at arc-length parameters ``u`` (``(q,)``, modulo 1) along closed outline ``P``."""
    cum, frac = _arc_params(P)
    u = np.mod(u, 1.0)
    i = np.clip(np.searchsorted(cum, u, side="right") - 1, 0, len(P) - 1)
    t = (u - cum[i]) / np.maximum(frac[i], 1e-300)
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
        ``GRADE_FIT_REL`` of the graded outline's diagonal."""
        if len(src) < 3 or len(dst) < 3:
            return None
        lo_s, lo_d = src.min(axis=0), dst.min(axis=0)
        k = np.ptp(dst, axis=0) / np.maximum(np.ptp(src, axis=0), 1e-300)
        box = (np.diag(k), lo_d - lo_s * k)
        S = _apply(src, box)
        j0 = int(np.argmin(np.linalg.norm(dst - S[0], axis=1)))
        D = np.roll(dst, -j0, axis=0)
        u = np.linspace(0.0, 1.0, 256, endpoint=False)
        gap = float(np.linalg.norm(_at_params(S, u) - _at_params(D, u), axis=1).mean())
        diag = float(np.hypot(*np.ptp(dst, axis=0)))
        return cls(box, S, D, j0) if gap <= GRADE_FIT_REL * max(diag, 1e-300) else None

    def points(self, pts: np.ndarray) -> np.ndarray:
        """Points on (or near) the sample outline, at the same parameter on the graded one."""
        pts = _apply(np.asarray(pts, dtype=float).reshape(-1, 2), self.box)
        A, B = self.S, np.roll(self.S, -1, axis=0)
        d = B - A
        dd = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
        t = np.clip(np.einsum("kij,ij->ki", pts[:, None] - A[None], d) / dd, 0.0, 1.0)
        foot = A[None] + t[..., None] * d[None]
        seg = np.argmin(np.linalg.norm(pts[:, None] - foot, axis=2), axis=1)
        cum, frac = _arc_params(self.S)
        u = cum[seg] + t[np.arange(len(pts)), seg] * frac[seg]
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
    pts = np.asarray(pts, dtype=float).reshape(-1, 2)
    A, B = src, np.roll(src, -1, axis=0)
    d = B - A  # (n, 2)
    dd = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    t = np.clip(np.einsum("kij,ij->ki", pts[:, None] - A[None], d) / dd, 0.0, 1.0)  # (k, n)
    foot = A[None] + t[..., None] * d[None]
    seg = np.argmin(np.linalg.norm(pts[:, None] - foot, axis=2), axis=1)
    tk = t[np.arange(len(pts)), seg]
    A2, B2 = dst[seg], np.roll(dst, -1, axis=0)[seg]
    return A2 + tk[:, None] * (B2 - A2)


class _Captured(logging.Handler):
    """Collects ezdxf's log records (recover mode's repairs) instead of printing them."""

    def __init__(self) -> None:
        super().__init__(level=logging.DEBUG)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        if record.levelno >= logging.WARNING and len(self.messages) < 1000:
            with contextlib.suppress(Exception):  # a record that cannot be formatted is dropped
                self.messages.append(" ".join(str(record.getMessage()).split())[:200])


@contextlib.contextmanager
def _quiet() -> Any:
    """ezdxf's log records captured (yielded), its prints and Python/numpy warnings
    swallowed: nothing reaches stdout or stderr while a DXF is read."""
    log = logging.getLogger("ezdxf")
    handler = _Captured()
    old = log.propagate, log.level
    log.addHandler(handler)
    log.propagate = False
    log.setLevel(logging.WARNING)
    sink = io.StringIO()
    try:
        with (
            contextlib.redirect_stdout(sink),
            contextlib.redirect_stderr(sink),
            warnings.catch_warnings(),
            np.errstate(all="ignore"),
        ):
            warnings.simplefilter("ignore")
            yield handler.messages
    finally:
        log.removeHandler(handler)
        log.propagate, log.level = old[0], old[1]


def _recover_warning(messages: list[str]) -> tuple[str, ...]:
    """Recover mode's repairs as one report warning (the first few quoted)."""
    if not messages:
        return ()
    shown = "; ".join(messages[:3])
    more = f" (and {len(messages) - 3} more)" if len(messages) > 3 else ""
    return (f"read in ezdxf's recover mode, {len(messages)} repair(s): {shown}{more}",)


def _open(spath: str, log: list[str] | None = None) -> Any:
    """The ezdxf document; strict reader first, then recover mode (CLO's group codes).

    Files over ``DXF_MAX_BYTES`` are refused unread; recover mode's repairs go to ``log``.
    """
    import ezdxf
    from ezdxf import recover

    p = Path(spath)
    if not p.is_file():
        raise PtailorError("no such file", path=spath)
    try:
        nbytes = p.stat().st_size
    except OSError as exc:
        raise PtailorError(f"cannot read: {exc.strerror or exc}", path=spath) from exc
    if nbytes > _tol.DXF_MAX_BYTES:
        raise PtailorError(
            f"the file is {nbytes} bytes, over the limit of {_tol.DXF_MAX_BYTES} for a DXF pattern",
            path=spath,
        )
    try:
        doc = ezdxf.readfile(spath)
    except Exception as strict_exc:  # any parse failure: retry leniently
        try:
            doc, _auditor = recover.readfile(spath)
        except Exception as exc:
            raise PtailorError(
                f"not a readable DXF file ({_one_line(exc or strict_exc)})", path=spath
            ) from exc
    else:
        if log is not None:
            log.clear()  # the strict reader's notes are not repairs
    return doc


def _one_line(exc: BaseException | str) -> str:
    """An exception's text on one line, at most 200 characters."""
    text = " ".join(str(exc).split()) or type(exc).__name__
    return text if len(text) <= 200 else text[:197] + "..."


class _BadEntityError(ValueError):
    """An entity this reader cannot use; the message says why (no file or piece named)."""


def _xy(v: Any) -> tuple[float, float]:
    """A point's x and y as floats (a missing point or coordinate is a :class:`_BadEntityError`)."""
    if v is None:
        raise _BadEntityError("has no coordinates")
    try:
        return float(v[0]), float(v[1])
    except (TypeError, IndexError, ValueError) as exc:
        raise _BadEntityError("has no x or y coordinate") from exc


def _bad_coordinate(pts: np.ndarray, what: str = "vertex") -> str | None:
    """Why ``(n, 2)`` points are unusable: ``"vertex 3 is not a number"``, ``"vertex 0 is
    infinite"``, ``"vertex 2 lies 1e+300 units from the origin (limit 1e+07)"``; None when
    every coordinate is finite and within ``DXF_MAX_COORD``."""
    pts = np.asarray(pts, dtype=float).reshape(-1, 2)
    nan = np.isnan(pts).any(axis=1)
    if nan.any():
        return f"{what} {int(np.flatnonzero(nan)[0])} is not a number"
    inf = np.isinf(pts).any(axis=1)
    if inf.any():
        return f"{what} {int(np.flatnonzero(inf)[0])} is infinite"
    far = np.abs(pts).max(axis=1) > _tol.DXF_MAX_COORD if len(pts) else np.zeros(0, bool)
    if far.any():
        i = int(np.flatnonzero(far)[0])
        return (
            f"{what} {i} lies {float(np.abs(pts[i]).max()):.3g} units from the origin "
            f"(limit {_tol.DXF_MAX_COORD:.3g})"
        )
    return None


def _header_number(doc: Any, name: str) -> int | None:
    """An integer header variable, or None when absent or not a sane integer."""
    try:
        v = doc.header.get(name)
    except Exception:  # a header that cannot be read says nothing
        return None
    if isinstance(v, bool) or not isinstance(v, int | float):
        return None
    if not np.isfinite(v) or abs(v) > 1e6:
        return None
    return int(v)


def _check_counts(doc: Any, spath: str) -> None:
    """Refuse more than ``DXF_MAX_ENTITIES`` entities (modelspace and blocks)."""
    try:
        n = len(doc.entitydb)
    except Exception:  # no database size: the file-size limit still holds
        return
    if n > _tol.DXF_MAX_ENTITIES:
        raise PtailorError(
            f"{n} entities, over the limit of {_tol.DXF_MAX_ENTITIES} for a DXF pattern",
            path=spath,
        )


_DXF_UNICODE = re.compile(r"\\U\+([0-9A-Fa-f]{4})")


def _printable(text: str) -> str:
    """``text`` with what UTF-8 cannot carry (lone surrogates from undecodable bytes)
    replaced by ``?``, so it can be printed and written back."""
    return text.encode("utf-8", "replace").decode("utf-8")


def _text_of(e: Any) -> str:
    """An entity's text, ``\\U+XXXX`` escapes decoded (over ``DXF_MAX_TEXT`` characters:
    a :class:`_BadEntityError`)."""
    if e.dxftype() == "MTEXT":
        raw = str(getattr(e, "text", ""))
        if len(raw) > 8 * _tol.DXF_MAX_TEXT:
            raise _BadEntityError(f"has {len(raw)} characters of text (limit {_tol.DXF_MAX_TEXT})")
        t = e.plain_text()
    else:
        t = e.dxf.get("text", "")
    t = _printable(_DXF_UNICODE.sub(lambda m: chr(int(m.group(1), 16)), str(t)).strip())
    if len(t) > _tol.DXF_MAX_TEXT:
        raise _BadEntityError(f"has {len(t)} characters of text (limit {_tol.DXF_MAX_TEXT})")
    return t


def _key_value(text: str) -> tuple[str, str]:
    """``"Piece Name: FRONT"`` -> ``("PIECE NAME", "FRONT")``; no colon -> ``("", text)``."""
    key, sep, value = text.partition(":")
    if not sep:
        return "", text
    return " ".join(key.split()).upper(), value.strip()


def _describe(e: Any, index: int | None = None) -> str:
    """``"POLYLINE 12 (layer 1)"``: an entity as messages name it (with its place in its
    block or in modelspace)."""
    try:
        kind = str(e.dxftype())
        layer = " ".join(str(e.dxf.get("layer", "0")).split())[:40]
    except Exception:
        return "an entity" if index is None else f"entity {index}"
    where = "" if index is None else f" {index}"
    return f"{kind}{where} (layer {layer or '0'})"


def _style_text(msp: Any, spath: str = "") -> dict[str, str]:
    """Modelspace ``KEY: value`` texts, keys upper-cased (first occurrence wins)."""
    out: dict[str, str] = {}
    for e in msp.query("TEXT MTEXT"):
        try:
            text = _text_of(e)
        except _BadEntityError as exc:
            raise PtailorError(f"modelspace: {_describe(e)} {exc}", path=spath) from exc
        k, v = _key_value(text)
        if k and k not in out:
            out[k] = v
    return out


def _affine(m44: Any) -> tuple[np.ndarray, np.ndarray] | None:
    """An ezdxf Matrix44 as (2, 2) linear part and (2,) translation (row vectors)."""
    m = np.array([list(r) for r in m44.rows()], dtype=float)
    A, t = m[:2, :2], m[3, :2]
    if np.array_equal(A, np.eye(2)) and not t.any():
        return None
    return A, t


def _apply(pts: np.ndarray, T: tuple[np.ndarray, np.ndarray] | None) -> np.ndarray:
    return pts if T is None else pts @ T[0] + T[1]


#: entity types the reader uses; others (ezdxf keeps unknown ones as tag storage) are
#: skipped, as CAD importers skip what they do not know
_USED = frozenset(
    {"LINE", "POLYLINE", "LWPOLYLINE", "ARC", "CIRCLE", "ELLIPSE", "SPLINE", "POINT", "TEXT"}
    | {"MTEXT"}
)


def _layer(e: Any) -> str:
    """An entity's layer name, stripped (``""`` when it has none that can be read)."""
    try:
        return str(e.dxf.get("layer", "0")).strip()
    except Exception:  # an entity ezdxf does not know may have no layer attribute
        return ""


def _has_boundary(entities: Any) -> bool:
    return any(
        _layer(e) == L_BOUNDARY and e.dxftype() in _USED - {"TEXT", "MTEXT", "POINT"}
        for e in entities
    )


def _candidates(doc: Any, spath: str) -> list[_Candidate]:
    """Piece candidates: INSERTed blocks, else defined blocks, else modelspace loops."""
    msp = doc.modelspace()
    out = []
    boundary_blocks: dict[str, bool] = {}
    for ins in msp.query("INSERT"):
        name = str(ins.dxf.get("name", "") or "")
        if not name or name.startswith("*") or name not in doc.blocks:
            continue
        blk = doc.blocks[name]
        if name not in boundary_blocks:
            boundary_blocks[name] = _has_boundary(blk)
        if boundary_blocks[name]:
            try:
                T = _affine(ins.matrix44())
            except Exception as exc:  # ezdxf cannot build the transform
                raise PtailorError(
                    f"the INSERT of block {name!r} has an unusable transform ({_one_line(exc)})",
                    path=spath,
                ) from exc
            if T is not None and not (np.all(np.isfinite(T[0])) and np.all(np.isfinite(T[1]))):
                raise PtailorError(
                    f"the INSERT of block {name!r}: its position, scale or rotation is not a "
                    "finite number",
                    path=spath,
                )
            out.append(_Candidate(name, _collect(blk, T)))
    if out:
        return out
    for blk in doc.blocks:
        if not blk.name.startswith("*") and _has_boundary(blk):
            out.append(_Candidate(_printable(blk.name), _collect(blk, None)))
    if out:
        return out
    if _has_boundary(msp):
        return _modelspace_candidates(_collect(msp, None), spath)
    return []


def _entity_points(e: Any, T: tuple[np.ndarray, np.ndarray] | None) -> np.ndarray | None:
    """Vertices of a curve entity in modelspace, ``(n, 2)``; closed ones repeat the first."""
    kind = e.dxftype()
    if kind == "LINE":
        pts = np.array([_xy(e.dxf.get("start")), _xy(e.dxf.get("end"))], dtype=float)
    elif kind in ("POLYLINE", "LWPOLYLINE"):
        if kind == "POLYLINE" and (e.is_poly_face_mesh or e.is_polygon_mesh):
            return None
        count = len(e.vertices) if kind == "POLYLINE" else len(e)
        if count > _tol.DXF_MAX_VERTICES:
            raise _BadEntityError(f"has {count} vertices (limit {_tol.DXF_MAX_VERTICES})")
        if kind == "POLYLINE":
            raw = np.zeros((count, 2))
            for j, v in enumerate(e.vertices):  # a loop over vertices: which one is bad
                try:
                    raw[j] = _xy(v.dxf.get("location"))
                except _BadEntityError as exc:
                    raise _BadEntityError(f"vertex {j} {exc}") from exc
        else:
            raw = np.array(e.get_points("xy"), dtype=float).reshape(-1, 2)
        bad = _bad_coordinate(raw)
        if bad:
            raise _BadEntityError(bad)
        pts = _flatten(e) if e.has_arc else raw.reshape(-1, 2)
        if e.is_closed and len(pts) > 2:
            pts = np.vstack([pts, pts[:1]])
    elif kind in ("ARC", "CIRCLE", "ELLIPSE", "SPLINE"):
        pts = _flatten(e)
    else:
        return None
    if not len(pts):
        return None
    bad = _bad_coordinate(pts)
    if bad:
        raise _BadEntityError(bad)
    out = _apply(pts, T)
    bad = _bad_coordinate(out)  # the INSERT's transform may take it out of range
    if bad:
        raise _BadEntityError(f"placed by its INSERT: {bad}")
    return out


def _flatten(e: Any) -> np.ndarray:
    """Curves (arcs, bulges, splines) as polylines, sagitta 0.1 % of their size.

    The control points are checked (finite, in range) before flattening, and the result's
    size is bounded by ``DXF_MAX_VERTICES``.
    """
    from ezdxf import path as ezpath

    p = ezpath.make_path(e)
    ctrl = np.array([_xy(v) for v in p.control_vertices()], dtype=float).reshape(-1, 2)
    bad = _bad_coordinate(ctrl, "control point")
    if bad:
        raise _BadEntityError(bad)
    size = float(np.ptp(ctrl, axis=0).max()) if len(ctrl) > 1 else 1.0
    dist = max(size, 1e-9) * 1e-3
    out = []
    for v in p.flattening(distance=dist):
        out.append(_xy(v))
        if len(out) > _tol.DXF_MAX_VERTICES:
            raise _BadEntityError(f"flattens to over {_tol.DXF_MAX_VERTICES} vertices")
    return np.array(out, dtype=float).reshape(-1, 2)


def _point(e: Any, T: tuple[np.ndarray, np.ndarray] | None) -> tuple[float, float]:
    loc = e.dxf.get("location") if e.dxftype() == "POINT" else e.dxf.get("center")
    raw = np.array([_xy(loc)], dtype=float)
    bad = _bad_coordinate(raw, "point")
    if bad:
        raise _BadEntityError(bad.replace("point 0 ", "its point "))
    p = _apply(raw, T)[0]
    bad = _bad_coordinate(p[None], "point")
    if bad:
        raise _BadEntityError("placed by its INSERT: " + bad.replace("point 0 ", "its point "))
    return float(p[0]), float(p[1])


def _angle(deg: float, T: tuple[np.ndarray, np.ndarray] | None) -> float:
    deg = float(deg)
    if not np.isfinite(deg):
        raise _BadEntityError("has an angle that is not a finite number")
    deg = deg % 360.0
    if T is None:
        return deg
    a = np.radians(deg)
    d = np.array([np.cos(a), np.sin(a)]) @ T[0]
    return float(np.degrees(np.arctan2(d[1], d[0])) % 360.0)


_LAYER_NAMES = {
    L_BOUNDARY: "boundary",
    L_TURN: "turn point",
    L_GRAIN: "grain line",
    L_MIRROR: "fold line",
    L_INTERNAL: "internal line",
    L_CUTOUT: "cutout",
    L_DRILL: "drill hole",
    L_SEW: "sew line",
    L_TEXT: "text",
}


def _collect(entities: Any, T: tuple[np.ndarray, np.ndarray] | None) -> _Marks:
    """Sort a block's (or modelspace's) entities into marks by layer.

    An entity that cannot be used (a vertex without x, a coordinate that is not a finite
    number in range, an attribute ezdxf cannot give) is left out and described in
    ``problems``; a piece built from these marks is refused with the first.
    """
    m = _Marks()
    for i, e in enumerate(entities):
        try:
            _collect_one(m, e, T)
        except (_BadEntityError, ValueError, TypeError, AttributeError, IndexError) as exc:
            # ezdxf's DXFAttributeError, DXFValueError, ... are among these
            layer = _layer(e)
            what = _LAYER_NAMES.get(layer, "notch" if layer in NOTCH_LAYERS else "")
            msg = (
                str(exc)
                if isinstance(exc, _BadEntityError)
                else f"cannot be read ({_one_line(exc)})"
            )
            m.problems.append(f"{what + ' ' if what else ''}{_describe(e, i)}: {msg}")
    return m


def _collect_one(m: _Marks, e: Any, T: tuple[np.ndarray, np.ndarray] | None) -> None:
    """Sort one entity into ``m`` (raises on an entity that cannot be used)."""
    kind = e.dxftype()
    if kind not in _USED:
        return
    layer = _layer(e)
    if kind in ("TEXT", "MTEXT"):
        if layer in (L_BOUNDARY, L_TEXT):
            text = _text_of(e)
            pos = np.array([_xy(e.dxf.get("insert", (0.0, 0.0)))], dtype=float)
            # where a text sits only matters in modelspace-only files
            pos = _apply(pos, T)[0] if _bad_coordinate(pos) is None else np.zeros(2)
            m.texts.append((text, layer, (float(pos[0]), float(pos[1]))))
        return
    if kind == "POINT" or (kind == "CIRCLE" and layer == L_DRILL):
        if layer == L_TURN:
            m.turn.append(_point(e, T))
        elif layer in NOTCH_LAYERS:
            q = _point(e, T)
            has = e.dxf.hasattr("angle")
            m.notch_angles.append(_angle(e.dxf.angle, T) if has else 0.0)
            m.notches.append(q)
        elif layer == L_DRILL:
            m.drills.append(_point(e, T))
        return
    if layer not in (L_BOUNDARY, L_GRAIN, L_MIRROR, L_INTERNAL, L_CUTOUT, L_SEW) and not (
        layer in NOTCH_LAYERS and kind == "LINE"
    ):
        return
    pts = _entity_points(e, T)
    if pts is None or len(pts) < 2:
        if layer == L_BOUNDARY and pts is not None:
            raise _BadEntityError(f"has {len(pts)} vertex, a cut line needs 2 or more")
        return
    if layer == L_BOUNDARY:
        m.boundary.append(pts)
    elif layer in NOTCH_LAYERS:
        m.notch_lines.append(pts[[0, -1]])
    elif layer == L_GRAIN:
        m.grain.append(pts[[0, -1]])
    elif layer == L_MIRROR:
        m.mirror.append(pts[[0, -1]])
    elif layer == L_SEW:
        m.sew.append(pts)
    elif layer in (L_INTERNAL, L_CUTOUT):
        m.internal.append(pts)
        m.internal_is_line.append(kind == "LINE" and layer == L_INTERNAL)


def _join_lines(lines: list[np.ndarray], is_line: list[bool], tol: float) -> list[np.ndarray]:
    """Consecutive internal LINEs sharing ends become one polyline."""
    out: list[np.ndarray] = []
    prev_line = False
    for pts, line in zip(lines, is_line, strict=True):
        if line and prev_line and float(np.hypot(*(out[-1][-1] - pts[0]))) <= tol:
            out[-1] = np.vstack([out[-1], pts[1:]])
        else:
            out.append(pts)
        prev_line = line
    return out


def _chain(segments: list[np.ndarray], tol: float) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Join segments end to end (reversing some) into loops and open chains.

    Parameters
    ----------
    segments : list of (n_i, 2) float arrays
        Open or closed (last point repeating the first) polylines.
    tol : float
        Ends closer than this join.

    Returns
    -------
    loops : list of (k, 2) float arrays
        Closed chains, first point not repeated.
    opens : list of (k, 2) float arrays
        Chains that do not close.
    """
    segs = [s for s in segments if len(s) >= 2]
    loops: list[np.ndarray] = []
    opens: list[np.ndarray] = []
    if not segs:
        return loops, opens
    # ends on a grid of cells of size tol: the ends within tol of a point lie in its cell
    # or the 8 around it, so each join looks at a few ends, not all (linear, not quadratic)
    ends = np.array([[s[0], s[-1]] for s in segs], dtype=float)  # (n, 2, 2)
    cell = max(float(tol), 1e-300)
    keys = np.floor(ends / cell).astype(np.int64)
    grid: dict[tuple[int, int], list[tuple[int, int]]] = {}
    for i, j in np.ndindex(len(segs), 2):  # a loop over segment ends, once
        grid.setdefault((int(keys[i, j, 0]), int(keys[i, j, 1])), []).append((i, j))
    alive = np.ones(len(segs), dtype=bool)

    def nearest(q: np.ndarray) -> tuple[float, int, int] | None:
        """The remaining end within tol of ``q``: the nearest, ties to the earliest segment."""
        kx, ky = (int(v) for v in np.floor(q / cell))
        best: tuple[float, int, int] | None = None
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for i, j in grid.get((kx + dx, ky + dy), ()):
                    if alive[i]:
                        d = float(np.hypot(*(ends[i, j] - q)))
                        if d <= tol and (best is None or (d, i, j) < best):
                            best = (d, i, j)
        return best

    nxt = 0
    while True:
        while nxt < len(segs) and not alive[nxt]:
            nxt += 1
        if nxt == len(segs):
            break
        alive[nxt] = False
        parts = [segs[nxt]]
        count = len(segs[nxt])
        while True:
            gap = float(np.hypot(*(parts[-1][-1] - parts[0][0])))
            hit = nearest(parts[-1][-1])
            if count >= 4 and gap <= tol and (hit is None or gap <= hit[0]):
                break  # closed (unless a part continues it more closely: dense outlines)
            if hit is not None:
                _, i, j = hit
                alive[i] = False
                parts.append((segs[i] if j == 0 else segs[i][::-1])[1:])
                count += len(parts[-1])
                continue
            hit = nearest(parts[0][0])
            if hit is not None:
                _, i, j = hit
                alive[i] = False
                parts.insert(0, (segs[i][::-1] if j == 0 else segs[i])[:-1])
                count += len(parts[0])
                continue
            break
        pts = np.vstack(parts)
        if count >= 4 and float(np.hypot(*(parts[-1][-1] - parts[0][0]))) <= tol:
            loops.append(pts[:-1])
        else:
            opens.append(pts)
    return loops, opens


def _diag(arrays: list[np.ndarray]) -> float:
    """Bounding-box diagonal of the points of ``arrays`` (0 for none)."""
    arrays = [np.asarray(a, dtype=float).reshape(-1, 2) for a in arrays]
    if not arrays or not sum(len(a) for a in arrays):
        return 0.0
    pts = np.vstack(arrays)
    return float(np.hypot(*np.ptp(pts, axis=0)))


def _check_parts(m: _Marks, who: str, spath: str) -> None:
    """Refuse marks with an unusable entity, no cut line, or too many cut-line parts;
    ``who`` (``"piece 'FRONT'"``, ``"modelspace"``) starts the message."""
    if m.problems:
        more = f" (and {len(m.problems) - 1} more)" if len(m.problems) > 1 else ""
        raise PtailorError(f"{who}: {m.problems[0]}{more}", path=spath)
    if not m.boundary:
        raise PtailorError(
            f"{who}: the boundary (layer 1) has no line or polyline of 2 or more points",
            path=spath,
        )
    for what, parts in (("the boundary (layer 1)", m.boundary), ("the sew line (layer 14)", m.sew)):
        if len(parts) > _tol.DXF_MAX_BOUNDARY_PARTS:
            raise PtailorError(
                f"{who}: {what} comes in {len(parts)} parts (limit {_tol.DXF_MAX_BOUNDARY_PARTS})",
                path=spath,
            )


def _check_piece(p: Piece, spath: str) -> None:
    """A piece's outline spans at least ``DXF_MIN_EXTENT`` and encloses an area (at least
    ``DXF_MIN_AREA_REL`` of its bounding box); every mark is finite and in range."""
    who = f"piece {p.name!r}"
    ext = p.extent
    if float(ext.max()) < _tol.DXF_MIN_EXTENT:
        raise PtailorError(
            f"{who}: the boundary spans {float(ext.max()):.3g} units, under "
            f"{_tol.DXF_MIN_EXTENT:g}: not a piece",
            path=spath,
        )
    if p.area < _tol.DXF_MIN_AREA_REL * float(ext[0]) * float(ext[1]) or p.area <= 0:
        raise PtailorError(
            f"{who}: the boundary encloses no area (its {len(p.outline)} points lie on a line)",
            path=spath,
        )
    named = {"notch": p.notches, "drill hole": p.drills}
    named.update(
        {k: v for k, v in (("grain line", p.grain), ("fold line", p.mirror)) if v is not None}
    )
    if p.sew is not None:
        named["sew line"] = p.sew
    for j, a in enumerate(p.internal):
        named[f"internal line {j}"] = a
    for what, arr in named.items():
        bad = _bad_coordinate(arr, "point")
        if bad:
            raise PtailorError(f"{who}: {what}: {bad}", path=spath)
    if not np.all(np.isfinite(p.notch_angles)):
        raise PtailorError(f"{who}: a notch angle is not a finite number", path=spath)


def _modelspace_candidates(m: _Marks, spath: str) -> list[_Candidate]:
    """Files without blocks: one piece per closed layer-1 loop, marks go to the piece
    whose bounding box holds them (the smallest such), else the nearest."""
    _check_parts(m, "modelspace", spath)
    tol = REL_TOL * max(_diag(m.boundary), 1e-12)
    loops, opens = _chain(m.boundary, tol)
    if opens:
        raise PtailorError(
            f"a boundary (layer 1) in modelspace does not close ({len(opens)} open chain(s))",
            path=spath,
        )
    lo = np.array([lp.min(axis=0) for lp in loops])  # (p, 2)
    hi = np.array([lp.max(axis=0) for lp in loops])
    area = np.prod(hi - lo, axis=1)

    def owner(pts: np.ndarray) -> np.ndarray:
        pts = np.asarray(pts, dtype=float).reshape(-1, 2)
        gap = np.maximum(lo[None] - pts[:, None], 0) + np.maximum(pts[:, None] - hi[None], 0)
        d = np.linalg.norm(gap, axis=2)  # (n, p)
        score = np.where(d > 0, area.max() + 1.0 + d, area[None])
        return np.argmin(score, axis=1) if len(pts) else np.zeros(0, dtype=int)

    out = [_Marks(boundary=[np.vstack([lp, lp[:1]])]) for lp in loops]
    for pts_name, ang_name in (("turn", None), ("notches", "notch_angles"), ("drills", None)):
        pts = getattr(m, pts_name)
        for k, o in enumerate(owner(np.array(pts))):
            getattr(out[o], pts_name).append(pts[k])
            if ang_name:
                getattr(out[o], ang_name).append(getattr(m, ang_name)[k])
    for name in ("notch_lines", "grain", "mirror", "sew"):
        for arr in getattr(m, name):
            getattr(out[int(owner(arr.mean(axis=0))[0])], name).append(arr)
    for arr, line in zip(m.internal, m.internal_is_line, strict=True):
        o = out[int(owner(arr.mean(axis=0))[0])]
        o.internal.append(arr)
        o.internal_is_line.append(line)
    for t in m.texts:
        k, _v = _key_value(t[0])
        if k in ("STYLE NAME", "SAMPLE SIZE", "UNITS", "CREATION DATE", "CREATION TIME"):
            continue
        out[int(owner(np.array(t[2]))[0])].texts.append(t)
    return [_Candidate(f"PIECE_{i + 1}", mk) for i, mk in enumerate(out)]


def _parse_piece_text(c: _Candidate, spath: str = "") -> None:
    """Name, size, quantity and annotations from the piece's text (keys any case)."""
    notes = []
    if len(c.block) > _tol.DXF_MAX_TEXT:
        raise PtailorError(
            f"a block name of {len(c.block)} characters (limit {_tol.DXF_MAX_TEXT})", path=spath
        )
    for text, layer, _pos in c.marks.texts:
        k, v = _key_value(text)
        if layer == L_BOUNDARY and k == "PIECE NAME" and not c.name:
            c.name = v
        elif layer == L_BOUNDARY and k == "SIZE" and not c.size:
            c.size = v
        elif layer == L_BOUNDARY and k == "QUANTITY" and not c.has_quantity:
            q = parse_quantity(v)
            if q is None:
                notes.append(text)
            elif q[0] > _tol.DXF_MAX_QUANTITY:
                raise PtailorError(
                    f"piece {c.name or c.block!r}: 'Quantity: {v}' is over the limit of "
                    f"{_tol.DXF_MAX_QUANTITY}",
                    path=spath,
                )
            else:
                c.quantity, c.quantity_split, c.has_quantity = q[0], q[1], True
        elif text and not (k and not v):  # skip empty "ANNOTATION:" fields
            notes.append(text)
    c.annotations = tuple(notes)


def _sizes_from_block_names(cands: list[_Candidate]) -> None:
    """Sizes from block names when no ``SIZE:`` text: ``NAME_SIZE`` blocks.

    The suffix counts as a size when the piece name text is the block name's prefix, or,
    without a name text, when the same prefix names more than one block (a graded file).
    """
    prefixes: dict[str, int] = {}
    for c in cands:
        head, sep, _tail = c.block.rpartition("_")
        if sep:
            prefixes[head] = prefixes.get(head, 0) + 1
    for c in cands:
        if not c.size:
            if c.name and c.block.startswith(c.name) and len(c.block) > len(c.name):
                tail = c.block[len(c.name) :]
                if tail[0] in "_-":
                    c.size = tail[1:]
            elif not c.name:
                head, sep, tail = c.block.rpartition("_")
                if sep and prefixes.get(head, 0) > 1 and tail:
                    c.size = tail
        if not c.name:
            suffix = f"_{c.size}"
            graded = c.size and c.block.endswith(suffix) and len(c.block) > len(suffix)
            c.name = c.block[: -len(suffix)] if graded else c.block


def _choose_size(sizes: tuple[str, ...], size: str | None, sample: str, spath: str) -> str:
    if size is None:
        if sample in sizes:
            return sample
        return sizes[0] if sizes else ""
    if size in sizes:
        return size
    folded = [s for s in sizes if s.casefold() == size.casefold()]
    if folded:
        return folded[0]
    listed = ", ".join(sizes) if sizes else "none"
    raise PtailorError(f"no size {size!r} in the file (sizes: {listed})", path=spath)


def _build_piece(c: _Candidate, spath: str) -> Piece:
    """Chain the boundary, orient it counter-clockwise, attach the marks."""
    m = c.marks
    _check_parts(m, f"piece {c.name!r}", spath)
    diag = max(_diag(m.boundary), 1e-12)
    tol = REL_TOL * diag
    loops, opens = _chain(m.boundary, tol)
    if not loops:
        gap = ""
        if opens:
            longest = max(opens, key=len)
            gap = f", its ends {float(np.hypot(*(longest[-1] - longest[0]))):.4g} apart"
            if len(longest) < 3:
                gap += f" (a chain of {len(longest)} points)"
        raise PtailorError(
            f"piece {c.name!r}: the boundary (layer 1) does not close{gap}", path=spath
        )
    areas = np.array([signed_area(lp) for lp in loops])
    k = int(np.argmax(np.abs(areas)))
    outline = loops[k][dedupe_closed(loops[k], rel=REL_DUP)]
    if len(outline) < 3:
        raise PtailorError(
            f"piece {c.name!r}: the boundary has {len(outline)} point(s), fewer than 3",
            path=spath,
        )
    turn = np.zeros(len(outline), dtype=bool)
    if m.turn:
        tp = np.array(m.turn, dtype=float)
        d, idx = _nearest(outline, tp)
        turn[idx[d <= tol]] = True
    if signed_area(outline) < 0:
        outline, turn = outline[::-1].copy(), turn[::-1].copy()

    notches = np.array(m.notches, dtype=float).reshape(-1, 2)
    angles = np.array(m.notch_angles, dtype=float)
    if m.notch_lines:
        nl = np.array(m.notch_lines, dtype=float)  # (q, 2, 2)
        d0, _ = _nearest(outline, nl[:, 0])
        d1, _ = _nearest(outline, nl[:, 1])
        flip = d1 < d0
        at = np.where(flip[:, None], nl[:, 1], nl[:, 0])
        to = np.where(flip[:, None], nl[:, 0], nl[:, 1])
        dv = to - at
        notches = np.vstack([notches, at])
        angles = np.concatenate([angles, np.degrees(np.arctan2(dv[:, 1], dv[:, 0])) % 360.0])
    internal = [lp for j, lp in enumerate(loops) if j != k]  # extra loops: internal shapes
    internal = [np.vstack([lp, lp[:1]]) for lp in internal]
    internal += _join_lines(m.internal, m.internal_is_line, tol)
    sew = None
    if m.sew:
        sloops, _ = _chain(m.sew, REL_TOL * max(_diag(m.sew), 1e-12))
        if sloops:
            sew = max(sloops, key=lambda s: abs(signed_area(s)))
            if signed_area(sew) < 0:
                sew = sew[::-1].copy()
    grain = next((g.copy() for g in m.grain if np.hypot(*(g[-1] - g[0])) > 1e-9 * diag), None)
    mirror = next((g.copy() for g in m.mirror if np.hypot(*(g[-1] - g[0])) > 1e-9 * diag), None)
    piece = Piece(
        name=c.name,
        outline=outline,
        turn=turn,
        notches=notches,
        notch_angles=angles,
        grain=grain,
        mirror=mirror,
        internal=tuple(internal),
        drills=np.array(m.drills, dtype=float).reshape(-1, 2),
        sew=sew,
        quantity=c.quantity,
        size=c.size,
        annotations=c.annotations,
        quantity_split=c.quantity_split,
    )
    _check_piece(piece, spath)
    return piece


def _nearest(ref: np.ndarray, query: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distance from each query point to its nearest ``ref`` point, and that point's index."""
    from scipy.spatial import cKDTree

    if len(query) == 0:
        return np.zeros(0), np.zeros(0, dtype=int)
    d, idx = cKDTree(ref).query(query)
    return np.asarray(d, dtype=float), np.asarray(idx, dtype=int)


def _units(
    override: str | None,
    text: str,
    insunits: Any,
    pieces: tuple[Piece, ...],
    measurement: Any = None,
) -> tuple[str, str]:
    """The coordinates' unit and where it came from.

    In order: the caller's override; ``Units: ENGLISH`` (inches); ``$INSUNITS`` in the
    header (mm, cm or in; an inch code under ``Units: METRIC`` is ignored); then, for
    ``METRIC``, ``$MEASUREMENT = 1`` or nothing said, millimetres, as AAMA/ASTM exports
    write metric patterns, unless the coordinates cannot be millimetres: a largest piece
    under ``CM_BELOW`` units (under 2.5 cm in mm) is in centimetres. A file that says
    nothing is in mm when its largest piece exceeds ``MM_ABOVE`` units, else cm. A drape, when there
    is one, has the last word (:func:`ptailor.formats.garment._load_dxf_pair`).
    """
    if override is not None:
        return override, f"{override} given by the caller"
    word = text.strip().upper()
    quoted = f"'Units: {text.strip()}' in the file"
    ok = isinstance(insunits, int | float) and np.isfinite(insunits) and abs(insunits) < 1e6
    code = _INSUNITS.get(int(insunits)) if ok else None
    if word == "ENGLISH":
        return "in", quoted
    if code is not None and (word != "METRIC" or code != "in"):
        src = f"{quoted}, " if word else ""
        return code, f"{src}$INSUNITS = {int(insunits)} ({code}) in the header"
    largest = max((float(p.extent.max()) for p in pieces), default=0.0)
    if word == "METRIC":
        src = quoted
    elif word:
        src = f"unknown {quoted}"
    elif isinstance(measurement, int | float) and measurement == 1:
        src = "$MEASUREMENT = 1 (metric) in the header"
    else:  # nothing said: pieces are 5-200 cm, 50-2000 mm
        unit = "mm" if largest > MM_ABOVE else "cm"
        return (
            unit,
            f"no units in the file; {unit} judged from the piece sizes (largest {largest:.4g})",
        )
    if 0 < largest < CM_BELOW:
        return "cm", (
            f"{src}; cm, as the coordinates are too small for mm (largest piece "
            f"{largest:.4g} units)"
        )
    return "mm", f"{src}; mm, as AAMA/ASTM metric files are written (largest piece {largest:.4g})"


#: a drape's ``vt`` is taken in a unit when its size, judged from the drape's area, is
#: within this factor of it
VT_UNIT_SLACK = 1.5
_VT_HEADER = re.compile(r"\bvt:\s*([0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*(mm|cm|m|in)\s+per unit")


def reconcile_units(
    pattern: PatternFile,
    *,
    v: np.ndarray,
    fv: np.ndarray,
    vt: np.ndarray,
    fvt: np.ndarray,
    header: tuple[str, ...] = (),
    drape_cm: float = 1.0,
    fixed: bool = False,
) -> tuple[PatternFile, str, str]:
    """The units of a DXF and of its drape's ``vt``, each decided on its own.

    A DXF and the ``vt`` that triangulates its pieces need not share a unit (ptailor writes
    the DXF in mm and the ``vt`` in the garment's unit, CLO 3D both in mm). A ``METRIC`` DXF
    (unless ``fixed``: the caller gave its unit, or ``$INSUNITS`` did) is in mm or cm,
    one that names no unit in mm, cm or in, whichever makes its pieces (times their
    quantity, twice for a fold piece) the drape's area. The ``vt`` unit comes
    from a ptailor header (``vt: 1 cm per unit``), else from the drape's area: the DXF's
    unit when the ``vt`` is within ``VT_UNIT_SLACK`` of that size, else the nearest of mm,
    cm, m and in, else the DXF's.

    Parameters
    ----------
    pattern : PatternFile
    v : (n, 3) float array
        The drape, in its file unit.
    fv : (m, 3) int array
    vt : (k, 2) float array
    fvt : (m, 3) int array
    header : tuple of str
        The drape OBJ's leading comments.
    drape_cm : float
        Centimetres per drape unit.
    fixed : bool
        The DXF's unit was given: keep it.

    Returns
    -------
    pattern : PatternFile
        With ``units`` and ``units_note`` decided.
    vt_unit : str
        For :func:`ptailor.formats.garment.load_garment`'s ``pattern_units`` (``cm``,
        ``0.1cm``, ...).
    note : str
        Where the ``vt`` unit came from.
    """
    from ptailor.model.garment import areas_3d, signed_areas_2d

    a3 = float(areas_3d(np.asarray(v, dtype=float) * drape_cm, fv).sum())  # cm^2
    word = pattern.units_text.strip().upper()
    said = "$INSUNITS" in pattern.units_note  # the header named the unit
    choices = ("mm", "cm") if word == "METRIC" else ("mm", "cm", "in") if not word else ()
    if not fixed and not said and choices:
        ap = sum(
            p.area * max(int(p.quantity), 1) * (2.0 if p.mirror is not None else 1.0)
            for p in pattern.pieces
        )
        ratio = float(np.sqrt(ap / a3)) if ap > 0 and a3 > 0 else 10.0  # file units per cm
        unit = min(choices, key=lambda u: abs(np.log(ratio * CM_PER_UNIT[u])))
        src = "'Units: METRIC' in the file" if word else "no units in the file"
        note = (
            f"{src}; {unit} judged from the drape (the pieces are {ratio:.3g} file units "
            "per cm of drape)"
        )
        kept = tuple(w for w in pattern.warnings if not w.startswith("the largest piece is"))
        pattern = replace(pattern, units=unit, units_note=note, warnings=kept)
    for line in header:  # ptailor's own garment.obj says its vt unit
        m = _VT_HEADER.search(line)
        if m:
            return (
                pattern,
                f"{m.group(1)}{m.group(2)}",
                f"vt: {m.group(1)} {m.group(2)} per unit (the drape's header)",
            )
    a2 = float(np.abs(signed_areas_2d(np.asarray(vt, dtype=float), fvt)).sum())
    if not (a2 > 0 and a3 > 0 and np.isfinite(a2) and np.isfinite(a3)):
        return pattern, pattern.units, f"vt in the DXF's unit ({pattern.units})"
    cm_per_vt = float(np.sqrt(a3 / a2))
    off = {u: abs(np.log(cm_per_vt / CM_PER_UNIT_ALL[u])) for u in CM_PER_UNIT_ALL}
    slack = np.log(VT_UNIT_SLACK)
    why = f"judged from the drape: {cm_per_vt:.4g} cm of drape per vt unit"
    if off.get(pattern.units, np.inf) <= slack:
        return pattern, pattern.units, f"vt in {pattern.units}, the DXF's unit ({why})"
    best = min(off, key=lambda u: off[u])
    if off[best] <= slack:
        return pattern, best, f"vt in {best}, unlike the DXF ({pattern.units}) ({why})"
    return pattern, pattern.units, f"vt taken in the DXF's unit ({pattern.units}); {why}"


#: centimetres per unit, for the ``vt`` of a drape (metres too)
CM_PER_UNIT_ALL: dict[str, float] = {"mm": 0.1, "cm": 1.0, "in": 2.54, "m": 100.0}


# --------------------------------------------------------------------------- writing


def write_dxf(path: str | Path, pattern: PatternFile, *, layout: str = "auto") -> None:
    """Write pieces as an AAMA/ASTM DXF R12 file (the flavour Gerber AccuMark imports).

    Parameters
    ----------
    path : str or Path
        The file to write.
    pattern : PatternFile
        Pieces and style text. Millimetres and centimetres are written as ``METRIC``
        millimetres (centimetres times 10), inches as ``ENGLISH`` inches.
    layout : {"auto", "keep", "row"}
        ``keep`` keeps the coordinates, ``row`` lays the pieces out in rows without
        overlap, ``auto`` keeps them unless two outlines' bounding boxes overlap.

    Notes
    -----
    One block per piece (named after it, made DXF-safe and unique) INSERTed at the origin;
    outlines are written counter-clockwise. ``Creation Date`` comes from
    ``SOURCE_DATE_EPOCH`` when set, so reruns give the same bytes.

    The document is built with ezdxf and saved with its Gerber D6673 exporter
    (:func:`ezdxf.addons.gerber_D6673.export_file`): an empty HEADER, BLOCKS without
    ``*Model_Space``/``*Paper_Space``, no TABLES, as Gerber's importer wants.
    """
    from ezdxf.addons import gerber_D6673

    spath = str(path)
    doc = _document(dxf_plan(pattern, layout=layout, path=spath))
    try:
        gerber_D6673.export_file(doc, spath)
    except OSError as exc:
        raise PtailorError(f"cannot write: {exc.strerror or exc}", path=spath) from exc


@dataclass(frozen=True)
class DxfEntity:
    """One entity to write: ``POLYLINE`` (``pts`` (n, 2), ``closed``), ``POINT`` (``pts``
    (1, 2), optional ``angle``), ``LINE`` (``pts`` (2, 2)) or ``TEXT`` (``pts`` (1, 2),
    ``text``, ``height``)."""

    kind: str
    layer: str
    pts: np.ndarray
    closed: bool = False
    angle: float | None = None
    text: str = ""
    height: float = 0.0


@dataclass(frozen=True)
class DxfPlan:
    """What :func:`write_dxf` writes: blocks (name, entities) and modelspace text; every
    block is INSERTed at the origin on layer 1."""

    blocks: tuple[tuple[str, tuple[DxfEntity, ...]], ...]
    texts: tuple[DxfEntity, ...]


def dxf_plan(pattern: PatternFile, *, layout: str = "auto", path: str | None = None) -> DxfPlan:
    """The entities :func:`write_dxf` writes for ``pattern``, in file units (mm or in).

    Parameters
    ----------
    pattern : PatternFile
    layout : {"auto", "keep", "row"}
    path : str, optional
        Named in errors.

    Returns
    -------
    DxfPlan
    """
    if pattern.units not in CM_PER_UNIT:
        raise PtailorError(f"cannot write DXF in {pattern.units!r} (mm, cm or in)", path=path)
    for p in pattern.pieces:
        if len(p.outline) < 3 or not np.all(np.isfinite(p.outline)):
            raise PtailorError(
                f"piece {p.name!r}: the outline needs 3 or more finite points", path=path
            )
        marks = [p.notches, p.notch_angles, p.drills, *p.internal]
        marks += [a for a in (p.grain, p.sew, p.mirror) if a is not None]
        if not all(np.all(np.isfinite(np.asarray(a, dtype=float))) for a in marks):
            raise PtailorError(
                f"piece {p.name!r}: a mark (notch, grain line, internal line, drill hole, sew "
                "or fold line) is not a finite number: nothing written",
                path=path,
            )
    pieces = layout_pieces(pattern.pieces, layout=layout)
    if pattern.units == "cm":
        pieces = tuple(_map_piece(p, 10.0, np.zeros(2)) for p in pieces)
    used: set[str] = set()
    blocks = tuple((_block_name(p.name, used), _piece_entities(p)) for p in pieces)

    ext = max((float(p.extent.max()) for p in pieces), default=1.0) or 1.0
    h = 0.01 * ext
    top = max((float(p.outline[:, 1].max()) for p in pieces), default=0.0) + 4 * h
    left = min((float(p.outline[:, 0].min()) for p in pieces), default=0.0)
    lines = [
        f"Style Name: {_clean(pattern.style)}",
        f"Creation Date: {_creation_date()}",
        f"Sample Size: {_clean(pattern.sample_size or pattern.size)}",
        f"Units: {'ENGLISH' if pattern.units == 'in' else 'METRIC'}",
    ]
    texts = tuple(
        DxfEntity("TEXT", L_BOUNDARY, np.array([[left, top + 1.6 * h * i]]), text=t, height=h)
        for i, t in enumerate(lines)
    )
    return DxfPlan(blocks, texts)


def _creation_date() -> str:
    sde = os.environ.get("SOURCE_DATE_EPOCH", "").strip()
    if sde:
        try:
            when = _dt.datetime.fromtimestamp(int(sde), tz=_dt.timezone.utc)
            return when.strftime("%d-%m-%Y")
        except (ValueError, OverflowError, OSError):
            pass
    return _dt.date.today().strftime("%d-%m-%Y")


def _block_name(name: str, used: set[str]) -> str:
    """A DXF-safe block name (letters, digits, ``_``, ``-``), unique in ``used``."""
    base = re.sub(r"[^A-Za-z0-9_-]", "_", name.strip()) or "PIECE"
    cand, n = base, 1
    while cand.upper() in used:
        n += 1
        cand = f"{base}_{n}"
    used.add(cand.upper())
    return cand


def _clean(text: str) -> str:
    """One line of printable ASCII: whitespace runs as one space, other characters as
    ``\\U+XXXX`` (``?`` beyond the Basic Multilingual Plane or for control characters)."""
    one = " ".join(str(text).split())
    return "".join(
        c if 32 <= ord(c) < 127 else f"\\U+{ord(c):04X}" if 127 < ord(c) <= 0xFFFF else "?"
        for c in one
    )


def _piece_entities(p: Piece) -> tuple[DxfEntity, ...]:
    """A piece's block content: boundary, marks, then its text."""
    out = []
    outline, turn = np.asarray(p.outline, dtype=float), np.asarray(p.turn, dtype=bool)
    if signed_area(outline) < 0:
        outline, turn = outline[::-1], turn[::-1]
    out.append(DxfEntity("POLYLINE", L_BOUNDARY, outline, closed=True))
    out += [DxfEntity("POINT", L_TURN, q[None]) for q in outline[turn]]
    notches = np.asarray(p.notches, dtype=float).reshape(-1, 2)
    angles = np.asarray(p.notch_angles, dtype=float).reshape(-1)
    if len(angles) != len(notches):  # none given (or one for all)
        angles = np.resize(angles, len(notches)) if len(angles) else np.zeros(len(notches))
    out += [
        DxfEntity("POINT", L_NOTCH, q[None], angle=a or None)
        for q, a in zip(notches, angles.tolist(), strict=True)
    ]
    if p.grain is not None:
        out.append(DxfEntity("LINE", L_GRAIN, np.asarray(p.grain, dtype=float)[[0, -1]]))
    if p.mirror is not None:
        out.append(DxfEntity("LINE", L_MIRROR, np.asarray(p.mirror, dtype=float)[[0, -1]]))
    out += [
        DxfEntity("POLYLINE", L_INTERNAL, np.asarray(line, dtype=float))
        for line in p.internal
        if len(line) >= 2
    ]
    out += [DxfEntity("POINT", L_DRILL, q[None]) for q in np.asarray(p.drills).reshape(-1, 2)]
    if p.sew is not None and len(p.sew) >= 3:
        sew = np.asarray(p.sew, dtype=float)
        out.append(
            DxfEntity("POLYLINE", L_SEW, sew[::-1] if signed_area(sew) < 0 else sew, closed=True)
        )

    lo, hi = outline.min(axis=0), outline.max(axis=0)
    h = 0.015 * float((hi - lo).max())
    texts = [f"Piece Name: {_clean(p.name)}", quantity_text(p)]
    if p.size:
        texts.append(f"Size: {_clean(p.size)}")
    texts += [_clean(a) for a in p.annotations]
    x0 = float(lo[0] + 0.1 * (hi - lo)[0])
    y0 = float((lo[1] + hi[1]) / 2 + 0.8 * h * len(texts))
    out += [
        DxfEntity("TEXT", L_BOUNDARY, np.array([[x0, y0 - 1.6 * h * i]]), text=t, height=h)
        for i, t in enumerate(texts)
    ]
    return tuple(out)


def _document(plan: DxfPlan) -> Any:
    """An ezdxf R12 document holding ``plan``'s blocks, INSERTs and style text."""
    from ezdxf.document import Drawing

    doc = Drawing.new("R12")  # not ezdxf.new: it sets $INSUNITS and warns that R12 has none

    def add(layout: Any, e: DxfEntity) -> None:
        attribs: dict[str, Any] = {"layer": e.layer}
        pts = e.pts.tolist()
        if e.kind == "POLYLINE":
            layout.add_polyline2d(pts, close=e.closed, dxfattribs=attribs)
        elif e.kind == "POINT":
            if e.angle is not None:
                attribs["angle"] = float(e.angle)
            layout.add_point(pts[0], dxfattribs=attribs)
        elif e.kind == "LINE":
            layout.add_line(pts[0], pts[1], dxfattribs=attribs)
        else:
            attribs.update(height=float(e.height), insert=pts[0])
            layout.add_text(e.text, dxfattribs=attribs)

    msp = doc.modelspace()
    for name, ents in plan.blocks:
        blk = doc.blocks.new(name=name, base_point=(0, 0))
        for e in ents:
            add(blk, e)
        msp.add_blockref(name, (0, 0), dxfattribs={"layer": L_BOUNDARY})
    for e in plan.texts:
        add(msp, e)
    return doc


def _map_piece(p: Piece, scale: float, offset: np.ndarray) -> Piece:
    """``p`` with every coordinate mapped ``x -> scale * x + offset`` (a new Piece)."""
    return p.map_points(lambda a: a * scale + offset)


def piece_bounds(p: Piece) -> np.ndarray:
    """Bounding box of a piece and all its marks, ``(2, 2)``: ``[[xmin, ymin], [xmax, ymax]]``."""
    parts = [p.outline, np.asarray(p.notches).reshape(-1, 2), np.asarray(p.drills).reshape(-1, 2)]
    parts += [np.asarray(a).reshape(-1, 2) for a in p.internal]
    parts += [np.asarray(a).reshape(-1, 2) for a in (p.grain, p.sew, p.mirror) if a is not None]
    pts = np.vstack(parts)
    return np.array([pts.min(axis=0), pts.max(axis=0)])


def layout_pieces(pieces: tuple[Piece, ...], *, layout: str = "auto") -> tuple[Piece, ...]:
    """Place pieces side by side without overlap.

    Parameters
    ----------
    pieces : tuple of Piece
    layout : {"auto", "keep", "row"}
        ``keep`` returns them as they are; ``row`` translates each piece (its marks with
        it) into rows, left to right, wrapping at about the width of a square sheet;
        ``auto`` keeps them when no two outlines' bounding boxes overlap, else ``row``
        (rows are packed by the bounding boxes of the outlines and all marks).

    Returns
    -------
    tuple of Piece
        New pieces (the input is not modified).
    """
    if layout not in LAYOUTS:
        raise PtailorError(f"unknown layout {layout!r} (known: {', '.join(LAYOUTS)})")
    pieces = tuple(pieces)
    if layout == "keep" or not pieces:
        return pieces
    if layout == "auto":
        lo = np.array([p.outline.min(axis=0) for p in pieces])  # (n, 2)
        hi = np.array([p.outline.max(axis=0) for p in pieces])
        over = np.all((lo[:, None] < hi[None]) & (lo[None] < hi[:, None]), axis=2)
        np.fill_diagonal(over, False)
        if not over.any():
            return pieces
    boxes = np.array([piece_bounds(p) for p in pieces])  # (n, 2, 2)
    lo, hi = boxes[:, 0], boxes[:, 1]
    size = hi - lo  # (n, 2)
    gap = 0.05 * float(size.max())
    width = max(float(size[:, 0].max()), 1.1 * float(np.sqrt(np.prod(size + gap, axis=1).sum())))
    offsets = np.zeros((len(pieces), 2))
    x = y = row_h = 0.0
    for i, (w, h) in enumerate(size.tolist()):  # a loop over pieces, not points
        if x > 0 and x + w > width:
            x, y, row_h = 0.0, y + row_h + gap, 0.0
        offsets[i] = (x, y)
        x += w + gap
        row_h = max(row_h, h)
    shift = offsets - lo
    return tuple(_map_piece(p, 1.0, s) for p, s in zip(pieces, shift, strict=True))
