"""``--sizes``: a graded CAD pattern's sizes read with the drape's size, adjusted as it was
(:func:`ptailor.pieces.grade.grade_nest`) and written as a graded nest and one file each."""

from __future__ import annotations

from ptailor.errors import PtailorError
from ptailor.formats import is_pattern_file, sizes_reader_for
from ptailor.formats.garment import LoadedGarment
from ptailor.model.pieces import PatternFile
from ptailor.pieces.grade import GradedNest
from ptailor.run.options import RunOptions, sizes_list
from ptailor.run.outputs import size_file_names


def check_sizes_input(garment: str, options: RunOptions, *, shown: str) -> None:
    """``--sizes`` takes a CAD pattern (a graded nest): refuse any other garment before
    anything is read (exit 2)."""
    if options.sizes is not None and not is_pattern_file(garment):
        raise PtailorError(
            "--sizes applies to a graded DXF pattern (a nest of sizes), not to this garment",
            path=shown,
        )


def read_sizes(
    garment: str, loaded: LoadedGarment, options: RunOptions, *, shown: str
) -> tuple[PatternFile, ...] | None:
    """The sizes ``--sizes`` asks for, read in the unit the drape's size was read in; None
    without ``--sizes``.

    Raises
    ------
    PtailorError
        A pattern of one size (or none named), or a size the file lacks (exit 2).
    """
    if options.sizes is None:
        return None
    pf = loaded.pattern
    if pf is None:
        raise PtailorError("--sizes applies to a graded DXF pattern only", path=shown)
    if len(pf.sizes) < 2:
        held = f"one size, {pf.sizes[0]}" if pf.sizes else "no named size"
        raise PtailorError(f"--sizes: the pattern is not graded (it holds {held})", path=shown)
    names = sizes_list(options.sizes)
    asked = None if [n.casefold() for n in names] == ["all"] else tuple(names)
    try:
        read = sizes_reader_for(garment)(garment, sizes=asked, units=pf.units)
    except PtailorError as exc:
        raise PtailorError(f"--sizes: {exc.message}", path=exc.path or shown) from None
    return tuple({p.size: p for p in read}.values())  # a size asked twice, once


def grading_section(nest: GradedNest, pattern: PatternFile, options: RunOptions) -> dict:
    """The report's ``pattern.grading``: the base size, the sizes and their files (when
    DXF is written), and per size and piece how it was graded
    (:class:`~ptailor.pieces.grade.GradedNest`'s records, lengths in the pattern file's
    unit)."""
    files = size_file_names(nest.sizes) if "dxf" in options.formats else {}
    return {
        "base_size": nest.base,
        "sizes": list(nest.sizes),
        "files": files,
        "units": pattern.units,
        "pieces": list(nest.records),
    }
