"""Writing AAMA/ASTM DXF R12 (the flavour Gerber AccuMark imports): one block per piece,
INSERTed at the origin, with the layout of the pieces on the sheet.
"""

from __future__ import annotations

import datetime as _dt
import os
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ptailor.errors import PtailorError
from ptailor.formats.dxf.astm import (
    L_BOUNDARY,
    L_DRILL,
    L_GRAIN,
    L_INTERNAL,
    L_MIRROR,
    L_NOTCH,
    L_SEW,
    L_TURN,
    LAYOUTS,
    quantity_text,
)
from ptailor.model.pieces import PatternFile, Piece
from ptailor.model.polyline import signed_area


def write_dxf(path: str | Path, pattern: PatternFile, *, layout: str = "auto") -> None:
    """Write pieces as an AAMA/ASTM DXF R12 file (the flavour Gerber AccuMark imports).

    Parameters
    ----------
    path : str or Path
        The file to write.
    pattern : PatternFile
        Pieces and style text. Millimetres and centimetres are written as ``METRIC``
        millimetres (centimetres times 10), inches as ``ENGLISH`` inches. Pieces of
        several sizes (each piece's ``size``) make a graded nest: one block per piece and
        size (``NAME_SIZE``), the sizes laid over each other as graded, ``Sample Size:``
        ``pattern.sample_size`` (else ``pattern.size``).
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
    from ptailor.model.units import CM_PER

    if pattern.units not in CM_PER:
        raise PtailorError(f"cannot write DXF in {pattern.units!r} (mm, cm, m or in)", path=path)
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
    pieces = layout_nest(pattern.pieces, size=pattern.size, layout=layout)
    if pattern.units not in ("mm", "in"):  # a metric file is in mm (ASTM/AAMA "METRIC")
        to_mm = CM_PER[pattern.units] / CM_PER["mm"]
        pieces = tuple(_map_piece(p, to_mm, np.zeros(2)) for p in pieces)
    used: set[str] = set()
    graded = len({p.size for p in pieces}) > 1
    blocks = tuple(
        (_block_name(f"{p.name}_{p.size}" if graded else p.name, used), _piece_entities(p))
        for p in pieces
    )

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


def layout_nest(
    pieces: tuple[Piece, ...], *, size: str = "", layout: str = "auto"
) -> tuple[Piece, ...]:
    """Pieces laid out (:func:`layout_pieces`); in a graded nest (pieces of several sizes)
    the pieces of ``size`` (else of the first piece's size) are laid out and every other
    size's piece of the same name moves with its own, so the sizes stay nested as graded.

    Parameters
    ----------
    pieces : tuple of Piece
    size : str
    layout : {"auto", "keep", "row"}

    Returns
    -------
    tuple of Piece
    """
    sizes = {p.size for p in pieces}
    if len(sizes) <= 1:
        return layout_pieces(pieces, layout=layout)
    base = size if size in sizes else pieces[0].size
    own = [p for p in pieces if p.size == base]
    laid = layout_pieces(tuple(own), layout=layout)
    shift = {p.name: q.outline[0] - p.outline[0] for p, q in zip(own, laid, strict=True)}
    return tuple(_map_piece(p, 1.0, shift[p.name]) if p.name in shift else p for p in pieces)


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
