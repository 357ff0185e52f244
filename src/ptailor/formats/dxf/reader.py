"""Reading a DXF pattern file: :func:`read_dxf`, one size's pieces with their marks."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

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
    return _guarded(spath, lambda log: _read(spath, size, units, log))


def _guarded(spath: str, work: Callable[[list[str]], Any]) -> Any:
    """``work(log)`` with ezdxf quiet (its log to ``log``), failing closed: a file this
    reader's checks did not foresee is refused (:class:`PtailorError`), not a crash."""
    with quiet_ezdxf() as log:
        try:
            return work(log)
        except PtailorError:
            raise
        except (ArithmeticError, LookupError, TypeError, ValueError, RecursionError) as exc:
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


def read_dxf_sizes(
    path: str | Path, *, sizes: tuple[str, ...] | None = None, units: str | None = None
) -> tuple[PatternFile, ...]:
    """Read several sizes of a graded DXF nest at once (the file parsed once).

    Parameters
    ----------
    path : str or Path
    sizes : tuple of str, optional
        The sizes to read, as :func:`read_dxf`'s ``size`` (any case); default every size
        of the file, in file order.
    units : {"mm", "cm", "in"}, optional
        The unit of the coordinates (:func:`read_dxf`'s); by default decided once, from the
        sample size (else the first), for every size.

    Returns
    -------
    tuple of PatternFile
        One per size asked for, in the order asked.

    Raises
    ------
    PtailorError
        As :func:`read_dxf`; a size the file lacks names the file's sizes.
    """
    spath = str(path)
    if units is not None and units not in CM_PER_UNIT:
        raise PtailorError(f"unknown DXF units {units!r} (known: mm, cm, in)", path=spath)

    def work(log: list[str]) -> tuple[PatternFile, ...]:
        nest = _parse(spath, log)
        base = _one_size(nest, None, units, spath)
        unit = units or base.units
        asked = nest.sizes if sizes is None else sizes
        return tuple(_one_size(nest, s, unit, spath, note=base.units_note) for s in asked)

    return _guarded(spath, work)


@dataclass
class _Nest:
    """A parsed DXF: its document, piece candidates (text read), style text, sizes and the
    sample size, and ezdxf's log."""

    doc: Any
    cands: list
    style: dict[str, str]
    sizes: tuple[str, ...]
    sample: str
    log: list[str]


def _parse(spath: str, log: list[str]) -> _Nest:
    """Open the file and read its piece candidates' text (no piece built yet)."""
    doc = open_document(spath, log)
    check_counts(doc, spath)
    style_text = read_style_text(doc.modelspace(), spath)
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
    return _Nest(doc, cands, style_text, sizes, style_text.get("SAMPLE SIZE", ""), log)


def _read(spath: str, size: str | None, units: str | None, log: list[str]) -> PatternFile:
    """:func:`read_dxf`'s work, ezdxf's log going to ``log``."""
    return _one_size(_parse(spath, log), size, units, spath)


def _one_size(
    nest: _Nest, size: str | None, units: str | None, spath: str, *, note: str | None = None
) -> PatternFile:
    """One size's pieces of a parsed file (``note``: where ``units`` came from, when they
    were decided on another size)."""
    doc, cands, sizes, sample = nest.doc, nest.cands, nest.sizes, nest.sample
    style_text = nest.style
    chosen = choose_size(sizes, size, sample, spath)
    chosen_c = [c for c in cands if c.size in (chosen, "")]
    pieces = tuple(build_piece(c, spath) for c in chosen_c)
    warnings: tuple[str, ...] = recover_warning(nest.log)
    if sample and chosen != sample and sample in sizes:
        sample_c = [c for c in cands if c.size == sample]
        sample_p = [build_piece(c, spath) for c in sample_c]
        pieces, filled = fill_from_sample(pieces, chosen_c, sample_p, sample_c, chosen, sample)
        for p in pieces:
            check_piece(p, spath)
        warnings += filled

    units_text = style_text.get("UNITS", "")
    unit, unit_note = file_units(
        units,
        units_text,
        header_number(doc, "$INSUNITS"),
        pieces,
        header_number(doc, "$MEASUREMENT"),
    )
    if note is not None:
        unit_note = note
    problem = size_in(pieces, unit) if pieces else None
    if problem is not None:
        warnings += (f"read in {unit} ({unit_note}), {problem}: check the units (--dxf-units)",)
    return PatternFile(
        pieces=pieces,
        units=unit,
        units_note=unit_note,
        style=style_text.get("STYLE NAME", ""),
        sizes=sizes,
        size=chosen,
        sample_size=sample,
        path=spath,
        units_text=units_text,
        warnings=warnings,
    )
