"""Piece assembly: candidates' marks checked and built into :class:`~ptailor.model.pieces.Piece`
objects (name, size, quantity from the piece text; notches, grain, internal lines).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ptailor import tolerances as _tol
from ptailor.errors import PtailorError
from ptailor.formats.dxf.astm import L_BOUNDARY, parse_quantity
from ptailor.formats.dxf.document import bad_coordinate, key_value, one_line, printable_text
from ptailor.formats.dxf.entities import (
    Candidate,
    Marks,
    affine_of,
    bbox_diagonal,
    chain_segments,
    collect_marks,
    has_boundary,
    join_lines,
)
from ptailor.model.pieces import Piece
from ptailor.model.polyline import dedupe_closed, signed_area


def piece_candidates(doc: Any, spath: str) -> list[Candidate]:
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
            boundary_blocks[name] = has_boundary(blk)
        if boundary_blocks[name]:
            try:
                T = affine_of(ins.matrix44())
            except Exception as exc:  # ezdxf cannot build the transform
                raise PtailorError(
                    f"the INSERT of block {name!r} has an unusable transform ({one_line(exc)})",
                    path=spath,
                ) from exc
            if T is not None and not (np.all(np.isfinite(T[0])) and np.all(np.isfinite(T[1]))):
                raise PtailorError(
                    f"the INSERT of block {name!r}: its position, scale or rotation is not a "
                    "finite number",
                    path=spath,
                )
            out.append(Candidate(name, collect_marks(blk, T)))
    if out:
        return out
    for blk in doc.blocks:
        if not blk.name.startswith("*") and has_boundary(blk):
            out.append(Candidate(printable_text(blk.name), collect_marks(blk, None)))
    if out:
        return out
    if has_boundary(msp):
        return _modelspace_candidates(collect_marks(msp, None), spath)
    return []


def _check_parts(m: Marks, who: str, spath: str) -> None:
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


def check_piece(p: Piece, spath: str) -> None:
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
        bad = bad_coordinate(arr, "point")
        if bad:
            raise PtailorError(f"{who}: {what}: {bad}", path=spath)
    if not np.all(np.isfinite(p.notch_angles)):
        raise PtailorError(f"{who}: a notch angle is not a finite number", path=spath)


def _modelspace_candidates(m: Marks, spath: str) -> list[Candidate]:
    """Files without blocks: one piece per closed layer-1 loop, marks go to the piece
    whose bounding box holds them (the smallest such), else the nearest."""
    _check_parts(m, "modelspace", spath)
    tol = _tol.DXF_CHAIN_REL * max(bbox_diagonal(m.boundary), _tol.DXF_DIAGONAL_MIN)
    loops, opens = chain_segments(m.boundary, tol)
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

    out = [Marks(boundary=[np.vstack([lp, lp[:1]])]) for lp in loops]
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
        k, _v = key_value(t[0])
        if k in ("STYLE NAME", "SAMPLE SIZE", "UNITS", "CREATION DATE", "CREATION TIME"):
            continue
        out[int(owner(np.array(t[2]))[0])].texts.append(t)
    return [Candidate(f"PIECE_{i + 1}", mk) for i, mk in enumerate(out)]


def parse_piece_text(c: Candidate, spath: str = "") -> None:
    """Name, size, quantity and annotations from the piece's text (keys any case)."""
    notes = []
    if len(c.block) > _tol.DXF_MAX_TEXT:
        raise PtailorError(
            f"a block name of {len(c.block)} characters (limit {_tol.DXF_MAX_TEXT})", path=spath
        )
    for text, layer, _pos in c.marks.texts:
        k, v = key_value(text)
        if layer == L_BOUNDARY and k == "PIECE NAME" and not c.name:
            c.name = v
        elif layer == L_BOUNDARY and k == "SIZE" and not c.size:
            c.size = v
        elif layer == L_BOUNDARY and k == "QUANTITY" and not c.has_quantity:
            q = parse_quantity(v)
            if q is None:  # once read as 1, silently, with the text kept as a note beside it
                raise PtailorError(
                    f"piece {c.name or c.block!r}: 'Quantity: {v[:40]}' is not a count (a whole"
                    " number >= 0, or ASTM's 'a,b': a cut as drawn, b mirrored)",
                    path=spath,
                )
            if q[0] > _tol.DXF_MAX_QUANTITY:
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


def sizes_from_block_names(cands: list[Candidate]) -> None:
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


def choose_size(sizes: tuple[str, ...], size: str | None, sample: str, spath: str) -> str:
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


def _first_line(lines, shortest: float) -> np.ndarray | None:
    """A copy of the first of ``lines`` (each ``(k, 2)``) whose ends lie more than
    ``shortest`` apart, or None."""
    return next((g.copy() for g in lines if np.hypot(*(g[-1] - g[0])) > shortest), None)


def build_piece(c: Candidate, spath: str) -> Piece:
    """Chain the boundary, orient it counter-clockwise, attach the marks."""
    m = c.marks
    _check_parts(m, f"piece {c.name!r}", spath)
    diag = max(bbox_diagonal(m.boundary), _tol.DXF_DIAGONAL_MIN)
    tol = _tol.DXF_CHAIN_REL * diag
    loops, opens = chain_segments(m.boundary, tol)
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
    outline = loops[k][dedupe_closed(loops[k], rel=_tol.DXF_DUPLICATE_REL)]
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
    internal += join_lines(m.internal, m.internal_is_line, tol)
    sew = None
    if m.sew:
        sloops, _ = chain_segments(
            m.sew, _tol.DXF_CHAIN_REL * max(bbox_diagonal(m.sew), _tol.DXF_DIAGONAL_MIN)
        )
        if sloops:
            sew = max(sloops, key=lambda s: abs(signed_area(s)))
            if signed_area(sew) < 0:
                sew = sew[::-1].copy()
    grain, mirror = (_first_line(lines, _tol.ROUNDING_REL * diag) for lines in (m.grain, m.mirror))
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
    check_piece(piece, spath)
    return piece


def _nearest(ref: np.ndarray, query: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distance from each query point to its nearest ``ref`` point, and that point's index."""
    from scipy.spatial import cKDTree

    if len(query) == 0:
        return np.zeros(0), np.zeros(0, dtype=int)
    d, idx = cKDTree(ref).query(query)
    return np.asarray(d, dtype=float), np.asarray(idx, dtype=int)
