"""Reading a DXF pattern file: :func:`read_dxf`, one size's pieces with their marks."""

from __future__ import annotations

from pathlib import Path

from ptailor.errors import PtailorError
from ptailor.formats.dxf.assembly import (
    build_piece,
    check_piece,
    choose_size,
    parse_piece_text,
    piece_candidates,
    sizes_from_block_names,
)
from ptailor.formats.dxf.astm import CM_PER_UNIT
from ptailor.formats.dxf.document import (
    check_counts,
    header_number,
    one_line,
    open_document,
    quiet_ezdxf,
    read_style_text,
    recover_warning,
)
from ptailor.formats.dxf.grading import fill_from_sample
from ptailor.formats.dxf.units import file_units, size_in
from ptailor.model.pieces import PatternFile


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
    with quiet_ezdxf() as log:
        try:
            return _read(spath, size, units, log)
        except PtailorError:
            raise
        except (ArithmeticError, LookupError, TypeError, ValueError, RecursionError) as exc:
            # fail closed: a file this reader's checks did not foresee is refused, not a crash
            raise PtailorError(
                f"not a usable DXF pattern ({type(exc).__name__}: {one_line(exc)})", path=spath
            ) from exc
        except Exception as exc:
            from ezdxf.lldxf.const import DXFError

            if not isinstance(exc, DXFError):
                raise
            raise PtailorError(
                f"not a usable DXF pattern ({type(exc).__name__}: {one_line(exc)})", path=spath
            ) from exc


def _read(spath: str, size: str | None, units: str | None, log: list[str]) -> PatternFile:
    """:func:`read_dxf`'s work, ezdxf's log going to ``log``."""
    doc = open_document(spath, log)
    check_counts(doc, spath)
    msp = doc.modelspace()
    style_text = read_style_text(msp, spath)
    cands = piece_candidates(doc, spath)
    if not cands:
        raise PtailorError(
            "no pattern pieces in the file (no boundary on layer 1 in a block or in modelspace)",
            path=spath,
        )
    for c in cands:
        parse_piece_text(c, spath)
    sizes_from_block_names(cands)

    sizes = tuple(dict.fromkeys(c.size for c in cands if c.size))
    sample = style_text.get("SAMPLE SIZE", "")
    chosen = choose_size(sizes, size, sample, spath)
    chosen_c = [c for c in cands if c.size in (chosen, "")]
    pieces = tuple(build_piece(c, spath) for c in chosen_c)
    warnings: tuple[str, ...] = recover_warning(log)
    if sample and chosen != sample and sample in sizes:
        sample_c = [c for c in cands if c.size == sample]
        sample_p = [build_piece(c, spath) for c in sample_c]
        pieces, filled = fill_from_sample(pieces, chosen_c, sample_p, sample_c, chosen, sample)
        for p in pieces:
            check_piece(p, spath)
        warnings += filled

    units_text = style_text.get("UNITS", "")
    unit, note = file_units(
        units,
        units_text,
        header_number(doc, "$INSUNITS"),
        pieces,
        header_number(doc, "$MEASUREMENT"),
    )
    problem = size_in(pieces, unit) if pieces else None
    if problem is not None:
        warnings += (f"read in {unit} ({note}), {problem}: check the units (--dxf-units)",)
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
