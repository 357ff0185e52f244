"""Where a garment's points of measure lie: its underarm, high point shoulder, crotch, waist and
limbs, found from its openings and panel roles, and the material lines through them.

Everything here reads the garment's frame (``Garment.frame``): ``up`` for heights, the wearer's
``left`` and ``front`` for halves. Functions return None where the landmark is missing.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor.geometry.pattern_maps import pattern_jacobians
from ptailor.geometry.topology import half_edges, loop_halfedges
from ptailor.measures import tolerances as measures_tol
from ptailor.measures.lines import (
    MaterialLine,
    edge_line,
    line_pieces,
    line_points,
    plane_section,
)
from ptailor.measures.measure import Measure
from ptailor.model.garment import Garment
from ptailor.model.structure import structure

#: panel roles of a sleeve (a short sleeve can be named a strap)
_LIMB_ROLES = ("sleeve", "cuff", "strap")


@dataclass(frozen=True)
class Limb:
    """A sleeve: its faces, axis and openings.

    Attributes
    ----------
    faces : (m,) bool array
    origin : (3,) float array
        The centre of the seam where it meets the torso (of its top opening, alone).
    axis : (3,) float array
        Unit vector from ``origin`` to the cuff's centre.
    reach : float
        The cuff centre's distance along ``axis``.
    under : float
        The underarm's (the seam's lowest point's) distance along ``axis``.
    cuff : MaterialLine
    """

    faces: np.ndarray
    origin: np.ndarray
    axis: np.ndarray
    reach: float
    under: float
    cuff: MaterialLine


@dataclass
class Context:
    """What every landmark reads, computed once per garment."""

    g: Garment
    R: np.ndarray  # rows left, up, front
    X: np.ndarray  # V3 in (left, up, front)
    s0: float
    f0: float
    openings: dict
    role: np.ndarray  # per face
    face_side: np.ndarray
    face_face: np.ndarray
    face_tier: np.ndarray
    torso: np.ndarray  # body panels' faces
    lower: np.ndarray  # body and waistband panels' faces
    lone_limb: Limb | None = None

    @property
    def is_top(self) -> bool:
        sided = any(f"{k}_left" in self.openings for k in ("cuff", "armhole"))
        return "neckline" in self.openings and sided

    @property
    def has_legs(self) -> bool:
        return "leg_left" in self.openings and "leg_right" in self.openings

    @property
    def waist_seamed(self) -> bool:
        """A bodice sewn to legs (a jumpsuit)."""
        t = set(self.face_tier[self.torso].tolist())
        return {"bodice", "leg"} <= t

    @property
    def tiered(self) -> bool:
        t = set(self.face_tier[self.torso].tolist())
        return {"bodice", "skirt"} <= t

    def opening_line(self, name: str) -> MaterialLine | None:
        op = self.openings.get(name)
        if op is None or not op.closed:
            return None
        return edge_line(self.g.F3, loop_halfedges(self.g.F3, op.loop))

    def height(self, P: np.ndarray) -> np.ndarray:
        return P @ self.R[1]


def _on_faces(g: Garment, faces: np.ndarray) -> np.ndarray:
    """``(n3,) bool``: the drape vertices of the triangles in mask ``faces``."""
    on = np.zeros(len(g.V3), dtype=bool)
    on[g.F3[faces].ravel()] = True
    return on


def _shared_vertices(g: Garment, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The drape vertices used by triangles in mask ``a`` and by triangles in mask ``b``."""
    return np.flatnonzero(_on_faces(g, a) & _on_faces(g, b))


def context(g: Garment) -> Context:
    """The landmarks' shared data for ``g``."""
    st = structure(g)
    lay = st.layout
    fp = st.face_panel
    pick = lambda attr: np.asarray(getattr(lay, attr), dtype=object)[fp]  # noqa: E731
    R = g.frame.matrix()
    role = pick("role")
    ctx = Context(
        g=g,
        R=R,
        X=g.V3 @ R.T,
        s0=float(lay.s0),
        f0=float(lay.f0),
        openings={op.name: op for op in st.openings},
        role=role,
        face_side=pick("side"),
        face_face=pick("face"),
        face_tier=pick("tier"),
        torso=role == "body",
        lower=(role == "body") | (role == "waistband"),
    )
    if "top" in ctx.openings and "cuff" in ctx.openings:
        ctx.lone_limb = _limb(ctx, np.ones(len(g.F3), dtype=bool), ctx.openings["top"].loop, "cuff")
    return ctx


def _limb(ctx: Context, faces: np.ndarray, seam: np.ndarray, cuff_name: str) -> Limb | None:
    cuff = ctx.openings[cuff_name]
    line = ctx.opening_line(cuff_name)
    if len(seam) == 0 or line is None:
        return None
    V3 = ctx.g.V3
    origin = V3[seam].mean(axis=0)
    d = cuff.centroid - origin
    reach = float(np.linalg.norm(d))
    if reach == 0.0:
        return None
    axis = d / reach
    low = seam[np.argmin(ctx.X[seam, 1])]
    return Limb(faces, origin, axis, reach, float((V3[low] - origin) @ axis), line)


def sleeve(g: Garment, ctx: Context, side: str) -> Limb | None:
    """The sleeve on ``side`` (``left``/``right``): its faces are the sleeve, cuff and strap
    panels on that side; its seam the drape vertices they share with the torso panels."""
    if f"cuff_{side}" not in ctx.openings:
        return None
    faces = np.isin(ctx.role, _LIMB_ROLES) & (ctx.face_side == side)
    if not faces.any():
        return None
    seam = _shared_vertices(g, faces, ctx.torso)
    return _limb(ctx, faces, seam, f"cuff_{side}")


def underarm_height(g: Garment, ctx: Context) -> float | None:
    """The lower of the two armholes' lowest points (the sleeve seams' where sleeves are
    sewn, else the armhole openings')."""
    lows = []
    for side in ("left", "right"):
        limb_faces = np.isin(ctx.role, _LIMB_ROLES) & (ctx.face_side == side)
        seam = _shared_vertices(g, limb_faces, ctx.torso)
        if f"armhole_{side}" in ctx.openings:
            seam = ctx.openings[f"armhole_{side}"].loop
        if len(seam):
            lows.append(float(ctx.X[seam, 1].min()))
    return min(lows) if len(lows) == 2 else None


def _best_piece(line: MaterialLine, g: Garment, *, closed: bool, near=None) -> MaterialLine | None:
    """The longest piece (the closed ones only, when ``closed``) or the one nearest ``near``."""
    label, count, is_closed = line_pieces(line)
    if count == 0:
        return None
    A, B = line_points(line, g.V3, g.F3)
    ok = is_closed if closed else np.ones(count, dtype=bool)
    if not ok.any():
        return None
    if near is None:
        score = -np.bincount(label, weights=np.linalg.norm(B - A, axis=1), minlength=count)
    else:
        dist = np.linalg.norm(0.5 * (A + B) - near, axis=1)
        score = np.full(count, np.inf)
        np.minimum.at(score, label, dist)
    score = np.where(ok, score, np.inf)
    return line.subset(label == int(np.argmin(score)))


def horizontal_girth(g: Garment, ctx: Context, h: float, faces) -> MaterialLine | None:
    """The longest closed piece of the section of ``faces`` at height ``h``."""
    line = plane_section(g.V3, g.F3, point=h * ctx.R[1], normal=ctx.R[1], faces=faces)
    return _best_piece(line, g, closed=True)


def limb_girth(g: Garment, limb: Limb, point: np.ndarray) -> MaterialLine | None:
    """The closed piece of the limb's section across its axis at ``point`` nearest it."""
    line = plane_section(g.V3, g.F3, point=point, normal=limb.axis, faces=limb.faces)
    return _best_piece(line, g, closed=True, near=point)


def overarm(g: Garment, limb: Limb) -> MaterialLine | None:
    """The upper half of the limb's section by the plane of its axis and the up axis."""
    R = g.frame.matrix()
    u = R[1] - (R[1] @ limb.axis) * limb.axis
    if np.linalg.norm(u) < measures_tol.VERTICAL_LIMB:  # a hanging limb: over its front
        u = R[2] - (R[2] @ limb.axis) * limb.axis
    u /= np.linalg.norm(u)
    line = plane_section(
        g.V3, g.F3, point=limb.origin, normal=np.cross(limb.axis, u), faces=limb.faces
    )
    A, B = line_points(line, g.V3, g.F3)
    line = line.subset((0.5 * (A + B) - limb.origin) @ u > 0.0)
    return _best_piece(line, g, closed=False)


def neck_vertices(g: Garment, ctx: Context) -> np.ndarray | None:
    """The torso's neck edge: the neckline's drape vertices on the torso panels, else (a collar
    sewn on) the vertices the torso shares with the collar; None without a neckline."""
    op = ctx.openings.get("neckline")
    if op is None:
        return None
    on_torso = _on_faces(g, ctx.torso)
    loop = op.loop[on_torso[op.loop]]
    if len(loop) == 0:
        loop = _shared_vertices(g, ctx.torso, ctx.role == "collar")
    return loop if len(loop) else None


def high_point_shoulder(g: Garment, ctx: Context) -> int | None:
    """The high point shoulder: of the neckline's drape vertices on the torso panels and on the
    wearer's left, the highest where a front and a back torso panel meet (the shoulder seam),
    else the highest (a strap dress: the bodice's top at the strap); None without a neckline
    on the torso's left."""
    loop = neck_vertices(g, ctx)
    if loop is None:
        return None
    front = ctx.torso & (ctx.face_face == "front")
    back = ctx.torso & (ctx.face_face == "back")
    seam = _on_faces(g, front) & _on_faces(g, back)
    left = loop[ctx.X[loop, 0] > ctx.s0]
    for cand in (left[seam[left]], left):
        if len(cand):
            top = ctx.X[cand, 1]
            ties = cand[top >= top.max() - _snap(ctx)]  # a flat neckline: its outer end
            return int(ties[np.argmax(ctx.X[ties, 0])])
    return None


def _snap(ctx: Context) -> float:
    """Heights closer than this are level (``PLANE_SNAP`` of the drape's size)."""
    return measures_tol.PLANE_SNAP * float(np.linalg.norm(np.ptp(ctx.X, axis=0)))


def _front_half(g: Garment, ctx: Context, line: MaterialLine) -> MaterialLine:
    """The segments on front panels, and of a panel around the body (a tube: no face) those
    in front of the centre."""
    face = ctx.face_face[line.face]
    A, B = line_points(line, g.V3, g.F3)
    ahead = (0.5 * (A + B)) @ ctx.R[2] > ctx.f0
    return line.subset((face == "front") | ((face == "") & ahead))


def front_length(g: Garment, ctx: Context, hps: int) -> MaterialLine | None:
    """The front's section straight down from the high point shoulder: the piece nearest it,
    when that piece reaches the hem (else None: a strap's or a side's piece is not the body
    length). Where the neckline curves out past the point, the piece starts below it (see
    :func:`body_length` for the gap)."""
    faces = ctx.torso & (ctx.face_face != "back")
    line = plane_section(g.V3, g.F3, point=g.V3[hps], normal=ctx.R[0], faces=faces)
    line = _front_half(g, ctx, line)
    piece = _best_piece(line, g, closed=False, near=g.V3[hps])
    top = hem_top(g, ctx)
    if piece is None or top is None:
        return None
    A, B = line_points(piece, g.V3, g.F3)
    low = float(min(ctx.height(A).min(), ctx.height(B).min()))
    return piece if low <= top else None


def body_length(g: Garment, ctx: Context, hps: int) -> list[Measure]:
    """The body length: :func:`front_length`, plus the straight gap from the high point
    shoulder to where that line enters the front (across the neckline's curve, in the drape
    and in the panel's pattern)."""
    piece = front_length(g, ctx, hps)
    if piece is None:
        return []
    A, B = line_points(piece, g.V3, g.F3)
    ends = np.r_[A, B]
    k = int(np.argmax(ctx.height(ends)))
    gap3 = float(np.linalg.norm(ends[k] - g.V3[hps]))
    a2, b2 = line_points(piece, g.V2, g.F2)
    top2 = np.r_[a2, b2][k]
    face = int(piece.face[k % len(piece)])
    panel = structure(g).face_panel
    mine = np.flatnonzero((panel == panel[face]) & (hps == g.F3).any(axis=1))
    if len(mine) == 0:  # the point is on another panel than the line's top: no gap in 2D
        gap2 = gap3 if gap3 == 0.0 else float("nan")
    else:
        f = int(mine[0])
        gap2 = float(np.linalg.norm(top2 - g.V2[g.F2[f, np.flatnonzero(g.F3[f] == hps)[0]]]))
    if not np.isfinite(gap2):
        return []
    drape = float(np.linalg.norm(B - A, axis=1).sum()) + gap3
    pattern = float(np.linalg.norm(b2 - a2, axis=1).sum()) + gap2
    return [Measure("body_length", "length", drape, pattern, piece)]


def centre_front_length(g: Garment, ctx: Context, h_top: float) -> MaterialLine | None:
    """The front half of the lower part's section by the centre plane, below ``h_top``."""
    faces = ctx.lower & (ctx.face_tier != "bodice") if ctx.tiered else ctx.lower
    point = ctx.s0 * ctx.R[0]
    line = plane_section(g.V3, g.F3, point=point, normal=ctx.R[0], faces=faces)
    return _best_piece(_front_half(g, ctx, line), g, closed=False)


def _grain_up(g: Garment, faces: np.ndarray, up: np.ndarray) -> np.ndarray:
    """The up axis carried into the pattern: over ``faces``, the mean pattern direction each
    triangle's map takes to ``up``'s projection on it (least squares on ``J``,
    :func:`~ptailor.geometry.pattern_maps.pattern_jacobians`), normalised."""
    J, ok = pattern_jacobians(g.V3, g.F3[faces], g.V2, g.F2[faces])
    J = J[ok]
    G = np.einsum("kdi,kdj->kij", J, J)  # (k, 2, 2)
    b = np.einsum("kdi,d->ki", J, up)
    det = G[:, 0, 0] * G[:, 1, 1] - G[:, 0, 1] ** 2
    good = det > 0.0
    w = (
        np.stack(
            [
                G[:, 1, 1] * b[:, 0] - G[:, 0, 1] * b[:, 1],
                G[:, 0, 0] * b[:, 1] - G[:, 0, 1] * b[:, 0],
            ],
            axis=1,
        )[good]
        / det[good, None]
    )
    s = w.sum(axis=0)
    n = np.linalg.norm(s)
    return s / n if n > 0 else s


def neck_drop(g: Garment, ctx: Context, hps: int) -> list[Measure]:
    """How far the neckline's lowest front point lies below the high point shoulder."""
    loop = neck_vertices(g, ctx)
    ahead = ctx.X[loop, 2] > ctx.f0
    on_front = _on_faces(g, ctx.torso & (ctx.face_face == "front"))[loop]
    on_tube = _on_faces(g, ctx.torso & (ctx.face_face == ""))[loop]
    front = loop[on_front | (on_tube & ahead)]
    if len(front) == 0:
        return []
    h = ctx.X[front, 1]
    ties = front[h <= h.min() + _snap(ctx)]  # a flat neckline: its centre
    low = int(ties[np.argmin(np.abs(ctx.X[ties, 0] - ctx.s0))])
    faces = np.flatnonzero(ctx.torso & (ctx.face_face != "back"))
    F = g.F3[faces]
    f_hps = faces[(hps == F).any(axis=1)]
    f_low = faces[(low == F).any(axis=1)]
    if len(f_hps) == 0 or len(f_low) == 0:
        return []
    panel = structure(g).face_panel
    same = np.isin(panel[f_low], panel[f_hps])
    f_low = f_low[same] if same.any() else f_low
    fa, fb = int(f_hps[0]), int(f_low[0])
    ca, cb = int(np.flatnonzero(g.F3[fa] == hps)[0]), int(np.flatnonzero(g.F3[fb] == low)[0])
    grain = _grain_up(g, panel == panel[fa], ctx.R[1])
    drop2 = float((g.V2[g.F2[fa, ca]] - g.V2[g.F2[fb, cb]]) @ grain)
    drop3 = float(ctx.X[hps, 1] - ctx.X[low, 1])
    eye = np.eye(3)
    line = MaterialLine(
        np.array([fa, fb]),
        eye[[ca, cb]],
        eye[[ca, cb]],
        np.array([-1 - hps, -1 - low]),
        np.array([-1 - hps, -1 - low]),
    )
    return [Measure("neck_drop", "depth", drop3, drop2, line)]


def waist(g: Garment, ctx: Context) -> tuple[MaterialLine, float] | None:
    """The waist line and its height: the waist opening, or on a dress (a jumpsuit) the girth
    at the mean height of the seam between bodice and skirt (legs)."""
    if ctx.tiered or ctx.waist_seamed:
        bod = ctx.torso & (ctx.face_tier == "bodice")
        skt = ctx.torso & np.isin(ctx.face_tier, ("skirt", "leg"))
        seam = _shared_vertices(g, bod, skt)
        if len(seam) == 0:
            return None
        h = float(ctx.X[seam, 1].mean())
        line = horizontal_girth(g, ctx, h, ctx.lower)
        return None if line is None else (line, h)
    line = ctx.opening_line("waist")
    if line is None:
        return None
    return line, float(ctx.height(ctx.openings["waist"].centroid))


def hem_top(g: Garment, ctx: Context) -> float | None:
    """The hem's highest point."""
    op = ctx.openings.get("hem")
    return None if op is None else float(ctx.X[op.loop, 1].max())


def crotch_height(g: Garment, ctx: Context) -> float | None:
    """The lowest point where the left and right lower panels meet."""
    left = ctx.lower & (ctx.face_side == "left")
    right = ctx.lower & (ctx.face_side == "right")
    v = _shared_vertices(g, left, right)
    return float(ctx.X[v, 1].min()) if len(v) else None


def inseam(g: Garment, ctx: Context, side: str, name: str) -> list[Measure]:
    """The seam inside the leg on ``side``: of the seams between two lower panels of that side
    that reach the leg opening, the one nearest the centre line."""
    op = ctx.openings.get(f"leg_{side}")
    if op is None:
        return []
    st = structure(g)
    lay = st.layout
    on_leg = np.zeros(len(g.V3), dtype=bool)
    on_leg[op.loop] = True
    best, best_d = None, np.inf
    for s in st.seams:
        a, b = s.panels
        if a == b or any(lay.side[p] != side or lay.role[p] != "body" for p in (a, b)):
            continue
        if not on_leg[s.edges3].any():
            continue
        d = float(np.abs(ctx.X[s.edges3.ravel(), 0] - ctx.s0).mean())
        if d < best_d:
            best, best_d = s, d
    if best is None:
        return []
    h = half_edges(g.F3)
    n = len(g.V3) + 1
    key = np.minimum(h[:, 0], h[:, 1]) * n + np.maximum(h[:, 0], h[:, 1])
    E = best.edges3
    want = np.minimum(E[:, 0], E[:, 1]) * n + np.maximum(E[:, 0], E[:, 1])
    on_a = st.face_panel[np.arange(len(h)) // 3] == best.panels[0]
    ids = np.flatnonzero(np.isin(key, want) & on_a)
    line = edge_line(g.F3, ids)
    drape = float(np.linalg.norm(g.V3[E[:, 1]] - g.V3[E[:, 0]], axis=1).sum())
    pattern = float(np.mean(best.lengths(g.V2)))
    return [Measure(name, "length", drape, pattern, line)]
