"""Garment and pattern readers and writers, in dispatch tables keyed by file extension.

Four kinds of file, one table each for reading and writing:

- meshes (``.obj``): :data:`READERS` give a :class:`ptailor.formats.obj.ObjMesh`,
  :data:`WRITERS` take the garment's arrays as keywords;
- patterns (``.dxf``): :data:`PATTERN_READERS` give a
  :class:`ptailor.model.pieces.PatternFile`, :data:`PATTERN_WRITERS` take one;
- sheets (``.svg``, ``.png``): :data:`SHEET_WRITERS` draw a pattern before and after an
  adjustment (the keywords of :func:`ptailor.formats.svg.pattern_svg`);
- cutting sheets (``.pdf``): a pattern writer too (:data:`PATTERN_WRITERS`), drawing a
  :class:`ptailor.model.pieces.PatternFile` 1:1 on tiled pages
  (:func:`ptailor.formats.pdf.write_pdf`).

Callers look a file up by its name (:func:`reader_for`, :func:`writer_for`,
:func:`is_pattern_file`), never by testing an extension themselves.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from ptailor.errors import PtailorError

#: extension -> reader(path, **options) returning a :class:`ptailor.formats.obj.ObjMesh`
READERS: dict[str, Callable[..., Any]] = {}
#: extension -> writer(path, **content)
WRITERS: dict[str, Callable[..., Any]] = {}
#: extension -> pattern reader(path, *, size=None, units=None) returning a
#: :class:`ptailor.model.pieces.PatternFile`
PATTERN_READERS: dict[str, Callable[..., Any]] = {}
#: extension -> graded pattern reader(path, *, sizes=None, units=None) returning one
#: :class:`ptailor.model.pieces.PatternFile` per size (a graded nest, parsed once)
SIZES_READERS: dict[str, Callable[..., Any]] = {}
#: extension -> pattern writer(path, pattern, **options)
PATTERN_WRITERS: dict[str, Callable[..., Any]] = {}
#: extension -> sheet writer(path, outlines_before, outlines_after, names, **options)
SHEET_WRITERS: dict[str, Callable[..., Any]] = {}


def extension(path: str | Path) -> str:
    """A file's extension, lower case, without the dot (``"A.DXF"`` -> ``"dxf"``)."""
    return Path(path).suffix.lower().lstrip(".")


def _lookup(table: dict[str, Callable[..., Any]], path: str | Path, what: str):
    ext = extension(path)
    if ext not in table:
        known = ", ".join(sorted(table))
        raise PtailorError(f"cannot read '.{ext}' {what} (known: {known})", path=str(path))
    return table[ext]


def reader_for(path: str | Path) -> Callable[..., Any]:
    """The mesh reader registered for ``path``'s extension; a clear error otherwise."""
    return _lookup(READERS, path, "files")


def is_pattern_file(path: str | Path) -> bool:
    """True when ``path`` names a CAD pattern file (its extension has a pattern reader)."""
    return extension(path) in PATTERN_READERS


def pattern_reader_for(path: str | Path) -> Callable[..., Any]:
    """The pattern reader registered for ``path``'s extension; a clear error otherwise."""
    return _lookup(PATTERN_READERS, path, "patterns")


def sizes_reader_for(path: str | Path) -> Callable[..., Any]:
    """The graded (every size) pattern reader registered for ``path``'s extension."""
    return _lookup(SIZES_READERS, path, "graded patterns")


def writer_for(path: str | Path) -> Callable[..., Any]:
    """The writer registered for ``path``'s extension, whichever its kind (mesh, pattern
    or sheet: see the module's tables for what each takes)."""
    ext = extension(path)
    for table in (WRITERS, PATTERN_WRITERS, SHEET_WRITERS):
        if ext in table:
            return table[ext]
    known = ", ".join(sorted({*WRITERS, *PATTERN_WRITERS, *SHEET_WRITERS}))
    raise PtailorError(f"cannot write '.{ext}' files (known: {known})", path=str(path))


def write_svg(path: str | Path, *args: Any, **options: Any) -> None:
    """Write :func:`ptailor.formats.svg.pattern_svg`'s document to ``path``."""
    from ptailor.formats.svg import pattern_svg

    Path(path).write_text(pattern_svg(*args, **options))


def _register() -> None:
    from ptailor.formats import dxf, obj, pdf, png

    READERS["obj"] = obj.read_obj
    WRITERS["obj"] = obj.write_obj
    PATTERN_READERS["dxf"] = dxf.read_dxf
    SIZES_READERS["dxf"] = dxf.read_dxf_sizes
    PATTERN_WRITERS["dxf"] = dxf.write_dxf
    PATTERN_WRITERS["pdf"] = pdf.write_pdf
    SHEET_WRITERS["svg"] = write_svg
    SHEET_WRITERS["png"] = png.pattern_png


_register()
