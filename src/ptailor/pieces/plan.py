"""The pieces a run writes: planned on the input garment, carried through the adjustment.

The plan matches the pattern file's pieces to the garment's panels (a piece cut on the fold
by its unfolded whole, a piece cut more than once as one piece per instance) and draws a
piece from the mesh for every panel no file piece outlines. Carrying the plan gives every
adjusted panel its piece: a panel a cut split in two gets a piece per part, a panel the
adjustment made gets one drawn from the adjusted mesh.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from ptailor import tolerances as tol
from ptailor.errors import PtailorError
from ptailor.geometry.triangles import signed_areas_2d
from ptailor.method.transfer import locate_points
from ptailor.model.garment import Garment, Panel, panel_labels
from ptailor.model.pieces import PatternFile, Piece
from ptailor.model.polyline import unfold
from ptailor.model.structure import structure
from ptailor.model.units import CM_PER
from ptailor.pieces.carry import CarriedPiece, carry_piece, scale_piece
from ptailor.pieces.draw import grain_directions, mesh_pieces
from ptailor.pieces.match import PieceMatch, match_pieces, more_instances, piece_curve

if TYPE_CHECKING:
    from ptailor.pipeline import Adjustment


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
    sources : tuple of int
        Per piece, the index of the pattern file's piece it is (an instance of a piece cut
        more than once, a part of a split panel: that piece's); ``-1`` for pieces drawn from
        the mesh.
    """

    pieces: tuple[Piece, ...]
    matches: tuple[PieceMatch, ...]
    from_file: tuple[bool, ...]
    units: str
    panels: tuple[Panel, ...]
    panel_names: tuple[str, ...] = ()
    sources: tuple[int, ...] = ()


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
    panel_list: list[Panel] | None = None,
    *,
    pattern: PatternFile | None = None,
) -> PiecePlan:
    """Match a pattern file's pieces to the garment's panels; draw the rest from the mesh.

    Parameters
    ----------
    garment : Garment
        The input garment (pattern in ``garment.units``); pieces drawn from the mesh take
        their grain from its frame's up.
    panel_list : list of Panel, optional
        The garment's panels; by default those of its cached structure
        (:func:`ptailor.model.structure.structure`), which the adjustment shares.
    pattern : PatternFile, optional
        Pieces in ``pattern.units``.

    Returns
    -------
    PiecePlan

    Raises
    ------
    PtailorError
        A file piece that matches no panel.
    """
    loops = pairs = None
    if panel_list is None:
        st = structure(garment)
        panel_list = st.panels
        loops = st.panel_loops  # cached: the previews' outlines read them again
        pairs = st.seam_halfedges
    V2, F2 = garment.V2, garment.F2
    file_pieces: list[Piece] = []
    matches: list[PieceMatch] = []
    sources: list[int] = []
    if pattern is not None:
        file_pieces, matches, sources = _file_pieces(garment, panel_list, pattern)
    used = {m.panel for m in matches}
    rest = [p for p in panel_list if p.index not in used]
    grain = grain_directions(V2, F2, garment.V3, garment.F3, panel_list, frame=garment.frame)
    drawn = mesh_pieces(
        V2, F2, rest, F3=garment.F3, V3=garment.V3, grain=grain,
        loops=None if loops is None else (lambda p: loops(p.index)), seam_pairs=pairs,
    )  # fmt: skip
    pieces = file_pieces + drawn
    matches = matches + [
        PieceMatch(len(file_pieces) + a, p.index, "mesh", np.eye(2), np.zeros(2), 0.0)
        for a, p in enumerate(rest)
    ]
    return PiecePlan(
        pieces=tuple(pieces),
        matches=tuple(matches),
        from_file=tuple([True] * len(file_pieces) + [False] * len(drawn)),
        units=garment.units if pattern is None else pattern.units,
        panels=tuple(panel_list),
        sources=tuple(sources + [-1] * len(drawn)),
    )


def _file_pieces(
    garment: Garment, panel_list: list[Panel], pattern: PatternFile
) -> tuple[list[Piece], list[PieceMatch], list[int]]:
    """A pattern file's pieces in the garment's units, matched to its panels, and per
    piece the index of the file's piece it is.

    Every instance of a piece cut more than once becomes its own piece of quantity 1 (a
    mirrored pair may be adjusted differently, and a cutter must not cut the first one
    twice), named ``NAME-2``, ``NAME-3``, ... after the first.
    """
    V2, F2 = garment.V2, garment.F2
    k = CM_PER[pattern.units] / CM_PER[garment.units]
    file_pieces = [scale_piece(pc, k) for pc in pattern.pieces]
    allowance = tol.PIECE_ALLOWANCE_CM / CM_PER[garment.units]
    matches, src = _match_with_folds(
        file_pieces, V2, F2, panel_list, path=pattern.path, allowance=allowance
    )
    extra = more_instances(src, matches, V2, F2, panel_list, allowance=allowance)
    extra = [replace(m, fold=matches[m.piece].fold) for m in extra]
    copies = {m.piece for m in extra}
    count: dict[int, int] = {}
    sources = list(range(len(file_pieces)))
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
        sources.append(m.piece)
    for i in copies:
        pc = file_pieces[i]
        file_pieces[i] = replace(pc, quantity=1, quantity_split=_one_side(pc, matches[i]))
    return file_pieces, matches, sources


def source_panels(adj: Adjustment, orig: tuple[Panel, ...]) -> dict[str, int]:
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
        flab = panel_labels(list(orig), len(g0.F2))
        a = np.abs(signed_areas_2d(base.V2, base.F2))
        for p in unknown:  # a loop over panels
            f = p.faces[int(np.argmax(a[p.faces]))]
            loc = locate_points(g0.V2, g0.F2, base.V2[base.F2[f]].mean(axis=0, keepdims=True))
            if loc.distance[0] <= tol.ROUNDING_REL * max(float(np.ptp(g0.V2)), tol.TINY):
                out[p.name] = int(flab[loc.face[0]])
    return out


def carry_plan(adj: Adjustment, plan: PiecePlan) -> tuple[PiecePlan, list[CarriedPiece | None]]:
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

    Returns
    -------
    plan : PiecePlan
        ``plan`` with the parts' pieces added and ``panel_names`` filled in.
    pieces : list of CarriedPiece or None
        One per piece of the returned plan; ``None`` where the piece's panel was removed
        whole.
    """
    new_plan, carried, _ = _carry(adj, plan)
    return new_plan, carried


def _carry(
    adj: Adjustment, plan: PiecePlan
) -> tuple[PiecePlan, list[CarriedPiece | None], list[int]]:
    """:func:`carry_plan`, and per planned piece the index of its (first) carried piece."""
    g0 = adj.original if adj.original is not None else adj.state.base
    base = adj.state.base
    orig = plan.panels
    source = source_panels(adj, orig)
    parts: dict[int, list[Panel]] = {}
    for p in adj.state.panels:  # a loop over panels
        if p.name in source:
            parts.setdefault(source[p.name], []).append(p)
    areas = (np.abs(signed_areas_2d(g0.V2, g0.F2)), np.abs(signed_areas_2d(base.V2, base.F2)))
    first: list[int] = []
    pieces: list[Piece] = []
    matches: list[PieceMatch] = []
    from_file: list[bool] = []
    names: list[str] = []
    sources: list[int] = []
    out: list[CarriedPiece | None] = []
    covered: set[str] = set()
    planned_sources = plan.sources or (-1,) * len(plan.pieces)
    for piece, m, ff, src in zip(
        plan.pieces, plan.matches, plan.from_file, planned_sources, strict=True
    ):  # a loop over pieces
        p0 = orig[m.panel]
        now = parts.get(m.panel, [])
        first.append(len(out))
        group = _carry_parts(adj, piece, m, p0, now, areas=areas) if now else [None]
        for k, cp in enumerate(group):  # the parts of one panel (one unless a cut split it)
            pieces.append(replace(piece, name=cp.piece.name) if k else piece)
            matches.append(m)
            from_file.append(ff)
            names.append(now[k].name if now else p0.name)
            sources.append(src)
        covered.update(p.name for p in now)
        out += group
    rest = [p for p in adj.state.panels if p.name not in covered]
    for p, pc in zip(rest, _drawn(adj, rest), strict=True):  # a loop over panels
        pieces.append(pc)
        matches.append(PieceMatch(len(pieces) - 1, -1, "mesh", np.eye(2), np.zeros(2), 0.0))
        from_file.append(False)
        names.append(p.name)
        sources.append(-1)
        out.append(CarriedPiece(piece=pc, outline_from="mesh", dropped=0))
    matches = [replace(mm, piece=i) for i, mm in enumerate(matches)]
    new_plan = replace(
        plan,
        pieces=tuple(pieces),
        matches=tuple(matches),
        from_file=tuple(from_file),
        panel_names=tuple(names),
        sources=tuple(sources),
    )
    return new_plan, out, first


def _carry_parts(
    adj: Adjustment,
    piece: Piece,
    m: PieceMatch,
    p0: Panel,
    now: list[Panel],
    *,
    areas: tuple[np.ndarray, np.ndarray],
) -> list[CarriedPiece]:
    """One planned piece carried onto each adjusted panel its panel ``p0`` became.

    The first part keeps the piece's name, the others take the panel's suffix; a mark is
    dropped only when no part keeps it. ``areas`` are the triangle areas of the input
    pattern and of the pattern the marks are located in.
    """
    g0 = adj.original if adj.original is not None else adj.state.base
    base = adj.state.base
    a0, ab = areas
    s0 = float(a0[p0.faces].sum())
    reach = 0.0
    group = []
    for k, p in enumerate(now):  # the parts of one panel (one unless a cut split it)
        sb = float(ab[p.faces].sum())
        unchanged = (
            len(now) == 1
            and len(p.faces) == len(p0.faces)
            and abs(sb - s0) <= tol.ROUNDING_REL * s0
        )
        if not unchanged and not reach:
            loc = locate_points(g0.V2, g0.F2, m.to_panel(piece_curve(piece)), faces=p0.faces)
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
    if len(group) > 1 and all(c.kept is not None for c in group):
        # a mark is dropped only when no part keeps it
        lost = ~np.logical_or.reduce([c.kept for c in group])
        group = [replace(c, dropped=int(lost.sum()) if k == 0 else 0) for k, c in enumerate(group)]
    return group


def _drawn(adj: Adjustment, rest: list[Panel]) -> list[Piece]:
    """Pieces drawn from the adjusted mesh for the panels ``rest`` no planned piece became."""
    if not rest:
        return []
    g = adj.garment
    grain = grain_directions(g.V2, g.F2, g.V3, g.F3, list(adj.state.panels), frame=g.frame)
    return mesh_pieces(g.V2, g.F2, rest, F3=g.F3, V3=g.V3, grain=grain)


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
    _, carried, first = _carry(adj, plan)
    return [carried[k] for k in first]
