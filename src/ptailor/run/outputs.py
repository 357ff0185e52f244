"""What each output format of a run writes, through the formats' dispatch tables.

One function per output format makes the file's content from the adjustment (the garment
OBJ's arrays, the DXF's pieces, the previews' sheet) and hands it to the writer that
:func:`ptailor.formats.writer_for` finds for the file's name.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ptailor.formats import PATTERN_WRITERS, SHEET_WRITERS, extension, writer_for
from ptailor.formats.garment import LoadedGarment
from ptailor.formats.sheet import preview_sheet
from ptailor.model.boundary import boundary_loops
from ptailor.model.garment import panel_labels
from ptailor.model.pieces import PatternFile, Piece
from ptailor.model.structure import structure
from ptailor.pieces import CarriedPiece, PieceAllowance, PiecePlan
from ptailor.pieces.grade import GradedNest
from ptailor.pipeline import Adjustment

#: output format -> the file it writes
FILE_NAMES = {
    "obj": "garment.obj",
    "dxf": "pattern.dxf",
    "svg": "pattern.svg",
    "png": "preview.png",
    "pdf": "pattern.pdf",
    "cut": "pattern_cut.svg",
}
#: formats drawn from the pieces whose file's extension is a preview's (``.svg``)
CUT_FORMATS = ("cut",)
#: the output formats, in the order they are written
FORMATS = tuple(FILE_NAMES)
#: what a run writes unless told (the cutting sheet is asked for: ``--formats ...,pdf``)
DEFAULT_FORMATS = ("obj", "dxf", "svg", "png")


def needs_pieces(formats: tuple[str, ...]) -> bool:
    """True when one of ``formats`` writes a CAD pattern (its pieces must be planned)."""
    return any(
        f in CUT_FORMATS or extension(FILE_NAMES[f]) in PATTERN_WRITERS
        for f in formats
        if f in FILE_NAMES
    )


@dataclass(frozen=True)
class OutputContext:
    """What the output writers share besides the adjustment.

    Attributes
    ----------
    loaded : LoadedGarment
        The input, with its file units.
    pieces : list of CarriedPiece or None
        The adjusted pieces (computation units), ``None`` for panels removed whole.
    plan : PiecePlan or None
        None when no pattern file is read or written.
    errors : (m,) float array
        Intrinsic-scale error per adjusted triangle.
    seam_allowance : float or None
        Computation units: the default allowance (``--seam-allowance`` without a name).
    allowances : list of PieceAllowance or None
        Per piece (aligned with ``pieces``), its allowance per outline edge and its runs,
        when any allowance is asked (:func:`cut_allowances`); empty otherwise. The
        written pieces' outline is then the sew line (:meth:`cut_pieces`).
    title : str
        The previews' heading.
    sheet : dict or None
        What both previews draw (:func:`sheet`, its layout included), computed once when
        either is written.
    show_measures : bool
        The previews draw the adjusted garment's points of measure (``--show-measures``).
    nest : GradedNest or None
        ``--sizes``: every chosen size's pieces (``pattern.dxf`` is then the graded nest,
        and each size is written alone too).
    paper : str
        The cutting sheet's paper (``--paper``: ``A4``, ``Letter``, ``A3``, ``A0``,
        ``roll:WIDTH``).
    """

    loaded: LoadedGarment
    pieces: list[CarriedPiece | None]
    plan: PiecePlan | None
    errors: np.ndarray
    seam_allowance: float | None = None
    allowances: list[PieceAllowance | None] = field(default_factory=list)
    title: str = ""
    sheet: dict | None = None
    show_measures: bool = False
    nest: GradedNest | None = None
    paper: str = "A4"

    def cut_pieces(self) -> list[Piece | None]:
        """The pieces as cut (computation units, aligned with ``pieces``): with a seam
        allowance asked, the outline is the cut line (a simple polygon, each edge offset by
        its own allowance) and the adjusted outline the sew line; else the pieces."""
        from ptailor.pieces import with_seam_allowance

        out: list[Piece | None] = []
        for i, cp in enumerate(self.pieces):  # a loop over pieces
            a = self.allowances[i] if i < len(self.allowances) else None
            pc = None if cp is None else cp.piece
            if pc is not None and a is not None:
                pc = with_seam_allowance(pc, self.seam_allowance or 0.0, edges=a.edges)
            out.append(pc)
        return out


def cut_allowances(
    adj: Adjustment,
    plan: PiecePlan | None,
    carried: list[CarriedPiece | None],
    default: float | None,
    named: tuple[tuple[str, float], ...],
) -> list[PieceAllowance | None]:
    """Each carried piece's seam allowance per outline edge
    (:func:`~ptailor.pieces.allowance.piece_allowances`); empty when none is asked."""
    from ptailor.pieces import piece_allowances

    if plan is None or not (default or named):
        return []
    return piece_allowances(adj, plan, carried, default=default or 0.0, named=dict(named))


def allowance_text(default: float | None, named: tuple[tuple[str, float], ...], units: str) -> str:
    """The previews' title's part on the allowance (``, seam allowance 1 cm, hem 3``)."""
    if not (default or named):
        return ""
    parts = ([f"{default:g} {units}"] if default else []) + [f"{n} {d:g}" for n, d in named]
    return ", seam allowance " + ", ".join(parts)


def output_obj(tmp: Path, adj: Adjustment, ctx: OutputContext) -> str:
    """``garment.obj``: edited drape and adjusted pattern, in the input files' units."""
    loaded = ctx.loaded
    g = adj.garment
    header = [
        "ptailor adjusted garment: v = edited drape, vt = adjusted pattern",
        f"v: {loaded.drape_scale:.9g} {g.units} per unit; "
        f"vt: {loaded.pattern_scale:.9g} {g.units} per unit"
        + (" (estimated)" if loaded.pattern_units_estimated else ""),
        *filter(None, [g.frame.header()]),
    ]
    name = FILE_NAMES["obj"]
    writer_for(name)(
        tmp / name,
        V3=g.V3 / loaded.drape_scale,
        F3=g.F3,
        V2=g.V2 / loaded.pattern_scale,
        F2=g.F2,
        face_panel=panel_labels(adj.state.panels, g.n_faces),
        panel_names=[p.name for p in adj.state.panels],
        header=header,
    )
    return name


def _same(A: np.ndarray, B: np.ndarray) -> bool:
    return A is B or (A.shape == B.shape and np.array_equal(A, B))


def _loop_finder(adj: Adjustment, ctx: OutputContext):
    """``loops(name, F2, faces)``: a panel's boundary loops, ``boundary_loops(F2[faces])``.

    Taken from the structure the run already cached (the input garment's in the run's axes:
    the plan drew its pieces from those loops) when it holds a panel of that name with the
    same triangles; computed otherwise.
    """
    lg = ctx.loaded.garment
    st = structure(lg)
    at = {p.name: i for i, p in enumerate(st.panels)}

    def loops(name: str, F2: np.ndarray, faces: np.ndarray) -> list[np.ndarray]:
        i = at.get(name)
        if i is not None and _same(F2, lg.F2) and _same(st.panels[i].faces, faces):
            return st.panel_loops(i)
        return boundary_loops(F2[faces])

    return loops


def sheet(adj: Adjustment, ctx: OutputContext, *, caller: str = "pattern_svg") -> dict:
    """The arguments both previews take: outlines before and after, triangles, errors, and
    their checked inputs and layout (``layout``, :func:`ptailor.formats.sheet.preview_sheet`,
    computed once for both; ``caller`` names the writer in its errors); with
    ``ctx.show_measures`` the adjusted garment's points of measure (``measures``)."""
    g = adj.garment
    g0 = adj.original if adj.original is not None else adj.state.base
    s0 = structure(g0)  # the input's panels, as the adjustment found them
    at = {p.name: i for i, p in enumerate(s0.panels)}
    loops = _loop_finder(adj, ctx)
    before = [
        [g0.V2[lp] for lp in loops(p.name, g0.F2, s0.panels[at[p.name]].faces)]
        if p.name in at
        else []
        for p in adj.state.panels
    ]
    tris = []
    errs = []
    for p in adj.state.panels:  # a loop over panels
        tris.append((g.V2, g.F2[p.faces]))  # the whole pattern's vertices, as the writers allow
        errs.append(ctx.errors[p.faces])
    out = {
        "outlines_before": before,
        "outlines_after": [
            [g.V2[lp] for lp in loops(p.name, g.F2, p.faces)] for p in adj.state.panels
        ],
        "names": [p.name for p in adj.state.panels],
        "units": g.units,
        "title": ctx.title,
        "triangles": tris,
        "errors": errs,
    }
    if ctx.show_measures:
        out["measures"] = _measure_lines(adj)
    out["layout"] = preview_sheet(
        out["outlines_before"], out["outlines_after"], out["names"], tris, errs,
        units=g.units, title=ctx.title, caller=caller,
    )  # fmt: skip
    return out


def _measure_lines(adj: Adjustment) -> list:
    """The adjusted garment's points of measure in its pattern, by the previews' panels."""
    from ptailor.formats.pom import pattern_lines
    from ptailor.measures import garment_measures

    g = adj.garment
    face_panel = np.full(g.n_faces, -1, dtype=np.int64)
    for i, p in enumerate(adj.state.panels):  # a loop over panels
        face_panel[p.faces] = i
    return pattern_lines(garment_measures(g), g.V2, g.F2, face_panel)


def _output_sheet(fmt: str, tmp: Path, adj: Adjustment, ctx: OutputContext) -> str:
    name = FILE_NAMES[fmt]
    writer_for(name)(tmp / name, **(ctx.sheet or sheet(adj, ctx)))
    return name


def output_svg(tmp: Path, adj: Adjustment, ctx: OutputContext) -> str:
    """``pattern.svg``: adjusted outlines over the original ones (dashed), at 1:1."""
    return _output_sheet("svg", tmp, adj, ctx)


def output_png(tmp: Path, adj: Adjustment, ctx: OutputContext) -> str:
    """``preview.png``: the same sheet as the SVG, as a picture."""
    return _output_sheet("png", tmp, adj, ctx)


def size_file_names(sizes: tuple[str, ...]) -> dict[str, str]:
    """Size -> the file of that size alone: ``pattern_SIZE.dxf``, the size's name made
    file-safe (letters, digits, ``.``, ``_``, ``-``) and unique."""
    out: dict[str, str] = {}
    used: set[str] = set()
    for s in sizes:  # a loop over sizes
        base = re.sub(r"[^A-Za-z0-9._-]", "_", s) or "size"
        name, n = f"pattern_{base}.dxf", 1
        while name.casefold() in used:
            n += 1
            name = f"pattern_{base}_{n}.dxf"
        used.add(name.casefold())
        out[s] = name
    return out


def _dxf_pieces(pieces, ctx: OutputContext, k: float) -> list:
    """Another size's pieces (aligned with ``ctx.pieces``) as written: the seam allowance
    added (each edge its base piece's where the outline has as many points, else the
    default), in the pattern file's unit."""
    from ptailor.pieces import scale_piece, with_seam_allowance

    out = []
    for i, pc in enumerate(pieces):  # a loop over pieces
        if pc is None:
            continue
        a = ctx.allowances[i] if i < len(ctx.allowances) else None
        if a is not None and len(a.edges) == len(pc.outline):
            pc = with_seam_allowance(pc, ctx.seam_allowance or 0.0, edges=a.edges)
        elif ctx.seam_allowance:
            pc = with_seam_allowance(pc, ctx.seam_allowance)
        out.append(scale_piece(pc, k))
    return out


def pattern_file(adj: Adjustment, ctx: OutputContext) -> PatternFile:
    """The adjusted pieces in the pattern's units, as ``pattern.dxf`` and ``pattern.pdf``
    write them (a :class:`~ptailor.model.pieces.PatternFile`: with a seam allowance each
    outline is the cut line and ``sew`` the sew line)."""
    from ptailor.model.units import CM_PER
    from ptailor.pieces import scale_piece

    units = ctx.plan.units
    k = CM_PER[adj.garment.units] / CM_PER[units]
    pieces = [scale_piece(pc, k) for pc in ctx.cut_pieces() if pc is not None]
    src = ctx.loaded.pattern
    pf = PatternFile(
        pieces=tuple(pieces),
        units=units,
        style=src.style if src is not None else Path(ctx.loaded.inputs.get("garment", "")).stem,
        sizes=(src.size,) if src is not None and src.size else (),
        size=src.size if src is not None else "",
        sample_size=src.sample_size if src is not None else "",
    )
    if src is not None:
        pf = replace(pf, units_text=src.units_text)
    return pf


def output_dxf(tmp: Path, adj: Adjustment, ctx: OutputContext) -> str | list[str]:
    """``pattern.dxf``: AAMA/ASTM pieces with their construction marks carried through;
    with ``--sizes`` every chosen size as a graded nest, and ``pattern_SIZE.dxf`` each."""
    name = FILE_NAMES["dxf"]
    pf = pattern_file(adj, ctx)
    if ctx.nest is None:
        writer_for(name)(tmp / name, pf)
        return name
    from ptailor.formats.dxf import layout_nest
    from ptailor.model.units import CM_PER

    k = CM_PER[adj.garment.units] / CM_PER[ctx.plan.units]
    nest = ctx.nest
    files = size_file_names(nest.sizes)
    base = nest.base if nest.base in nest.sizes else nest.sizes[0]
    every = tuple(p for row in nest.pieces for p in _dxf_pieces(row, ctx, k))
    every = layout_nest(every, size=base)  # every size laid as the base size is
    for size in nest.sizes:  # a loop over sizes
        one = replace(pf, pieces=tuple(p for p in every if p.size == size), sizes=(size,))
        writer_for(files[size])(
            tmp / files[size], replace(one, size=size, sample_size=size), layout="keep"
        )
    writer_for(name)(
        tmp / name,
        replace(pf, pieces=every, sizes=nest.sizes, size=base, sample_size=base),
        layout="keep",
    )
    return [name, *files.values()]


def output_pdf(tmp: Path, adj: Adjustment, ctx: OutputContext) -> str:
    """``pattern.pdf``: the cutting sheet, every piece 1:1 with its cut and sew lines,
    notches, grain line, name, size and quantity, on ``ctx.paper``'s pages."""
    name = FILE_NAMES["pdf"]
    writer_for(name)(
        tmp / name, pattern_file(adj, ctx), paper=ctx.paper, title=ctx.title,
        note=_allowance_note(adj, ctx),
    )  # fmt: skip
    return name


def _allowance_note(adj: Adjustment, ctx: OutputContext) -> str:
    """The cutting sheet's word on the seam allowance."""
    if ctx.seam_allowance:
        a = f"{ctx.seam_allowance:g} {adj.garment.units}"
        return f"Seam allowance {a} included: cut solid, sew dashed."
    return "No seam allowance: the solid line is the sew line."


def output_cut(tmp: Path, adj: Adjustment, ctx: OutputContext) -> str:
    """``pattern_cut.svg``: the cutting sheet's content on one sheet, 1:1 in mm (the file
    is an SVG but not the preview: its writer is called by name, not by extension)."""
    from ptailor.formats.cut_svg import write_cut_svg

    name = FILE_NAMES["cut"]
    note = _allowance_note(adj, ctx)
    write_cut_svg(tmp / name, pattern_file(adj, ctx), title=ctx.title, note=note)
    return name


#: output format -> writer(folder, adjustment, context) returning the file name
OUTPUTS = {
    "obj": output_obj, "dxf": output_dxf, "svg": output_svg, "png": output_png,
    "pdf": output_pdf, "cut": output_cut,
}  # fmt: skip


def write_outputs(
    tmp: Path, adj: Adjustment, ctx: OutputContext, formats: tuple[str, ...]
) -> list[str]:
    """Write the adjusted garment in the requested formats into ``tmp``; return file names."""
    sheets = [
        f
        for f in FORMATS
        if f in formats and f not in CUT_FORMATS and extension(FILE_NAMES[f]) in SHEET_WRITERS
    ]
    if ctx.sheet is None and sheets:  # the first writer names itself in the inputs' errors
        ctx = replace(ctx, sheet=sheet(adj, ctx, caller=f"pattern_{sheets[0]}"))
    names = []
    for f in FORMATS:  # a loop over formats
        if f in formats:
            got = OUTPUTS[f](tmp, adj, ctx)
            names += [got] if isinstance(got, str) else got
    return names
