"""DXF entities to piece marks: the outline, notches, grain and internal lines of one
block (or modelspace), with the block transforms applied and line segments chained.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ptailor import tolerances as _tol
from ptailor.formats.dxf.astm import (
    L_BOUNDARY,
    L_CUTOUT,
    L_DRILL,
    L_GRAIN,
    L_INTERNAL,
    L_MIRROR,
    L_SEW,
    L_TEXT,
    L_TURN,
    NOTCH_LAYERS,
)
from ptailor.formats.dxf.document import (
    BadEntityError,
    bad_coordinate,
    describe_entity,
    entity_xy,
    one_line,
    text_of,
)


@dataclass
class Marks:
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
class Candidate:
    """One INSERT (or one modelspace loop): a piece of some size."""

    block: str
    marks: Marks
    name: str = ""
    size: str = ""
    quantity: int = 1
    annotations: tuple[str, ...] = ()
    quantity_split: tuple[int, int] | None = None
    has_quantity: bool = False


def affine_of(m44: Any) -> tuple[np.ndarray, np.ndarray] | None:
    """An ezdxf Matrix44 as (2, 2) linear part and (2,) translation (row vectors)."""
    m = np.array([list(r) for r in m44.rows()], dtype=float)
    A, t = m[:2, :2], m[3, :2]
    if np.array_equal(A, np.eye(2)) and not t.any():
        return None
    return A, t


def apply_affine(pts: np.ndarray, T: tuple[np.ndarray, np.ndarray] | None) -> np.ndarray:
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


def has_boundary(entities: Any) -> bool:
    return any(
        _layer(e) == L_BOUNDARY and e.dxftype() in _USED - {"TEXT", "MTEXT", "POINT"}
        for e in entities
    )


def _polyline_points(e: Any) -> np.ndarray | None:
    """Vertices of a (LW)POLYLINE, ``(n, 2)``, arcs flattened, closed ones repeating the
    first; None for a mesh POLYLINE (not a curve)."""
    kind = e.dxftype()
    if kind == "POLYLINE" and (e.is_poly_face_mesh or e.is_polygon_mesh):
        return None
    count = len(e.vertices) if kind == "POLYLINE" else len(e)
    if count > _tol.DXF_MAX_VERTICES:
        raise BadEntityError(f"has {count} vertices (limit {_tol.DXF_MAX_VERTICES})")
    if kind == "POLYLINE":
        raw = np.zeros((count, 2))
        for j, v in enumerate(e.vertices):  # a loop over vertices: which one is bad
            try:
                raw[j] = entity_xy(v.dxf.get("location"))
            except BadEntityError as exc:
                raise BadEntityError(f"vertex {j} {exc}") from exc
    else:
        raw = np.array(e.get_points("xy"), dtype=float).reshape(-1, 2)
    _refuse_bad(raw)
    pts = _flatten(e) if e.has_arc else raw.reshape(-1, 2)
    if e.is_closed and len(pts) > 2:
        pts = np.vstack([pts, pts[:1]])
    return pts


def _refuse_bad(pts: np.ndarray, prefix: str = "") -> None:
    """Raise :class:`BadEntityError` when a coordinate of ``pts`` is unusable."""
    bad = bad_coordinate(pts)
    if bad:
        raise BadEntityError(prefix + bad)


def _entity_points(e: Any, T: tuple[np.ndarray, np.ndarray] | None) -> np.ndarray | None:
    """Vertices of a curve entity in modelspace, ``(n, 2)``; closed ones repeat the first."""
    kind = e.dxftype()
    if kind == "LINE":
        pts = np.array([entity_xy(e.dxf.get("start")), entity_xy(e.dxf.get("end"))], dtype=float)
    elif kind in ("POLYLINE", "LWPOLYLINE"):
        pts = _polyline_points(e)
        if pts is None:
            return None
    elif kind in ("ARC", "CIRCLE", "ELLIPSE", "SPLINE"):
        pts = _flatten(e)
    else:
        return None
    if not len(pts):
        return None
    _refuse_bad(pts)
    out = apply_affine(pts, T)
    _refuse_bad(out, "placed by its INSERT: ")  # the INSERT's transform may take it out of range
    return out


def _flatten(e: Any) -> np.ndarray:
    """Curves (arcs, bulges, splines) as polylines, sagitta 0.1 % of their size.

    The control points are checked (finite, in range) before flattening, and the result's
    size is bounded by ``DXF_MAX_VERTICES``.
    """
    from ezdxf import path as ezpath

    p = ezpath.make_path(e)
    ctrl = np.array([entity_xy(v) for v in p.control_vertices()], dtype=float).reshape(-1, 2)
    bad = bad_coordinate(ctrl, "control point")
    if bad:
        raise BadEntityError(bad)
    size = float(np.ptp(ctrl, axis=0).max()) if len(ctrl) > 1 else 1.0
    dist = max(size, 1e-9) * _tol.DXF_FLATTEN_REL
    out = []
    for v in p.flattening(distance=dist):
        out.append(entity_xy(v))
        if len(out) > _tol.DXF_MAX_VERTICES:
            raise BadEntityError(f"flattens to over {_tol.DXF_MAX_VERTICES} vertices")
    return np.array(out, dtype=float).reshape(-1, 2)


def _point(e: Any, T: tuple[np.ndarray, np.ndarray] | None) -> tuple[float, float]:
    loc = e.dxf.get("location") if e.dxftype() == "POINT" else e.dxf.get("center")
    raw = np.array([entity_xy(loc)], dtype=float)
    bad = bad_coordinate(raw, "point")
    if bad:
        raise BadEntityError(bad.replace("point 0 ", "its point "))
    p = apply_affine(raw, T)[0]
    bad = bad_coordinate(p[None], "point")
    if bad:
        raise BadEntityError("placed by its INSERT: " + bad.replace("point 0 ", "its point "))
    return float(p[0]), float(p[1])


def _angle(deg: float, T: tuple[np.ndarray, np.ndarray] | None) -> float:
    deg = float(deg)
    if not np.isfinite(deg):
        raise BadEntityError("has an angle that is not a finite number")
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


def collect_marks(entities: Any, T: tuple[np.ndarray, np.ndarray] | None) -> Marks:
    """Sort a block's (or modelspace's) entities into marks by layer.

    An entity that cannot be used (a vertex without x, a coordinate that is not a finite
    number in range, an attribute ezdxf cannot give) is left out and described in
    ``problems``; a piece built from these marks is refused with the first.
    """
    m = Marks()
    for i, e in enumerate(entities):
        try:
            _collect_one(m, e, T)
        except (BadEntityError, ValueError, TypeError, AttributeError, IndexError) as exc:
            # ezdxf's DXFAttributeError, DXFValueError, ... are among these
            layer = _layer(e)
            what = _LAYER_NAMES.get(layer, "notch" if layer in NOTCH_LAYERS else "")
            msg = (
                str(exc) if isinstance(exc, BadEntityError) else f"cannot be read ({one_line(exc)})"
            )
            m.problems.append(f"{what + ' ' if what else ''}{describe_entity(e, i)}: {msg}")
    return m


def _collect_one(m: Marks, e: Any, T: tuple[np.ndarray, np.ndarray] | None) -> None:
    """Sort one entity into ``m`` (raises on an entity that cannot be used)."""
    kind = e.dxftype()
    if kind not in _USED:
        return
    layer = _layer(e)
    if kind in ("TEXT", "MTEXT"):
        _collect_text(m, e, layer, T)
    elif kind == "POINT" or (kind == "CIRCLE" and layer == L_DRILL):
        _collect_point(m, e, layer, T)
    elif layer in _CURVE_LAYERS or (layer in NOTCH_LAYERS and kind == "LINE"):
        _collect_curve(m, e, layer, T)


#: layers whose curve entities the reader uses (and notch LINEs)
_CURVE_LAYERS = (L_BOUNDARY, L_GRAIN, L_MIRROR, L_INTERNAL, L_CUTOUT, L_SEW)


def _collect_text(m: Marks, e: Any, layer: str, T: tuple[np.ndarray, np.ndarray] | None) -> None:
    """A TEXT or MTEXT on the boundary or text layer into ``m.texts``."""
    if layer in (L_BOUNDARY, L_TEXT):
        text = text_of(e)
        pos = np.array([entity_xy(e.dxf.get("insert", (0.0, 0.0)))], dtype=float)
        # where a text sits only matters in modelspace-only files
        pos = apply_affine(pos, T)[0] if bad_coordinate(pos) is None else np.zeros(2)
        m.texts.append((text, layer, (float(pos[0]), float(pos[1]))))


def _collect_point(m: Marks, e: Any, layer: str, T: tuple[np.ndarray, np.ndarray] | None) -> None:
    """A POINT (or a drill-hole CIRCLE): a turn point, a notch or a drill hole."""
    if layer == L_TURN:
        m.turn.append(_point(e, T))
    elif layer in NOTCH_LAYERS:
        q = _point(e, T)
        has = e.dxf.hasattr("angle")
        m.notch_angles.append(_angle(e.dxf.angle, T) if has else 0.0)
        m.notches.append(q)
    elif layer == L_DRILL:
        m.drills.append(_point(e, T))


def _collect_curve(m: Marks, e: Any, layer: str, T: tuple[np.ndarray, np.ndarray] | None) -> None:
    """A curve entity on a boundary, notch, grain, fold, internal or sew layer."""
    pts = _entity_points(e, T)
    if pts is None or len(pts) < 2:
        if layer == L_BOUNDARY and pts is not None:
            raise BadEntityError(f"has {len(pts)} vertex, a cut line needs 2 or more")
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
        m.internal_is_line.append(e.dxftype() == "LINE" and layer == L_INTERNAL)


def join_lines(lines: list[np.ndarray], is_line: list[bool], tol: float) -> list[np.ndarray]:
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


def chain_segments(
    segments: list[np.ndarray], tol: float
) -> tuple[list[np.ndarray], list[np.ndarray]]:
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
    ends = _SegmentEnds(segs, tol)
    for start in range(len(segs)):
        if not ends.alive[start]:
            continue
        ends.alive[start] = False
        parts, count = _grow(ends, [segs[start]], len(segs[start]))
        pts = np.vstack(parts)
        if count >= 4 and float(np.hypot(*(parts[-1][-1] - parts[0][0]))) <= tol:
            loops.append(pts[:-1])
        else:
            opens.append(pts)
    return loops, opens


class _SegmentEnds:
    """The two ends of each segment on a grid of cells of size ``tol``: the ends within
    ``tol`` of a point lie in its cell or the 8 around it, so each join looks at a few ends,
    not all (linear, not quadratic). ``alive[i]``: segment ``i`` is not used yet."""

    def __init__(self, segs: list[np.ndarray], tol: float) -> None:
        self.segs = segs
        self.tol = tol
        self.ends = np.array([[s[0], s[-1]] for s in segs], dtype=float)  # (n, 2, 2)
        self.cell = max(float(tol), _tol.TINY)
        keys = np.floor(self.ends / self.cell).astype(np.int64)
        self.grid: dict[tuple[int, int], list[tuple[int, int]]] = {}
        for i, j in np.ndindex(len(segs), 2):  # a loop over segment ends, once
            self.grid.setdefault((int(keys[i, j, 0]), int(keys[i, j, 1])), []).append((i, j))
        self.alive = np.ones(len(segs), dtype=bool)

    def nearest(self, q: np.ndarray) -> tuple[float, int, int] | None:
        """The remaining end within tol of ``q``: the nearest, ties to the earliest segment."""
        kx, ky = (int(v) for v in np.floor(q / self.cell))
        best: tuple[float, int, int] | None = None
        for dx, dy in _NEIGHBOURS:
            for i, j in self.grid.get((kx + dx, ky + dy), ()):
                if self.alive[i]:
                    d = float(np.hypot(*(self.ends[i, j] - q)))
                    if d <= self.tol and (best is None or (d, i, j) < best):
                        best = (d, i, j)
        return best


#: a grid cell and the 8 around it, in the order the nearest end is searched
_NEIGHBOURS = tuple((dx, dy) for dx in (-1, 0, 1) for dy in (-1, 0, 1))


def _grow(ends: _SegmentEnds, parts: list[np.ndarray], count: int) -> tuple[list[np.ndarray], int]:
    """Extend a chain at its end, else at its start, until it closes or nothing joins.

    Returns the parts (each without the point it shares with the previous) and the
    chain's point count.
    """
    segs, tol = ends.segs, ends.tol
    while True:
        gap = float(np.hypot(*(parts[-1][-1] - parts[0][0])))
        hit = ends.nearest(parts[-1][-1])
        if count >= 4 and gap <= tol and (hit is None or gap <= hit[0]):
            return parts, count  # closed (unless a part continues it more closely: dense outlines)
        if hit is not None:
            _, i, j = hit
            ends.alive[i] = False
            parts.append((segs[i] if j == 0 else segs[i][::-1])[1:])
            count += len(parts[-1])
            continue
        hit = ends.nearest(parts[0][0])
        if hit is None:
            return parts, count
        _, i, j = hit
        ends.alive[i] = False
        parts.insert(0, (segs[i][::-1] if j == 0 else segs[i])[:-1])
        count += len(parts[0])


def bbox_diagonal(arrays: list[np.ndarray]) -> float:
    """Bounding-box diagonal of the points of ``arrays`` (0 for none)."""
    arrays = [np.asarray(a, dtype=float).reshape(-1, 2) for a in arrays]
    if not arrays or not sum(len(a) for a in arrays):
        return 0.0
    pts = np.vstack(arrays)
    return float(np.hypot(*np.ptp(pts, axis=0)))
