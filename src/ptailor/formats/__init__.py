"""Garment and pattern readers and writers, in dispatch tables keyed by file extension."""

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
#: extension -> pattern writer(path, pattern, **options)
PATTERN_WRITERS: dict[str, Callable[..., Any]] = {}


def reader_for(path: str | Path) -> Callable[..., Any]:
    """The reader registered for ``path``'s extension; a clear error otherwise."""
    ext = Path(path).suffix.lower().lstrip(".")
    if ext not in READERS:
        known = ", ".join(sorted(READERS))
        raise PtailorError(f"cannot read '.{ext}' files (known: {known})", path=str(path))
    return READERS[ext]


def _register() -> None:
    from ptailor.formats import dxf, obj

    READERS["obj"] = obj.read_obj
    WRITERS["obj"] = obj.write_obj
    PATTERN_READERS["dxf"] = dxf.read_dxf
    PATTERN_WRITERS["dxf"] = dxf.write_dxf


_register()
