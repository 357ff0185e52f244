"""A batch's inputs: the garments its arguments name, their drapes, their output folders."""

from __future__ import annotations

import glob
import os
import re
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import IO

from ptailor.errors import PtailorError
from ptailor.formats import PATTERN_READERS, READERS, is_pattern_file

_GLOB_CHARS = re.compile(r"[*?\[]")
#: a batch catalogue's page and its own folder in OUT (``batch --html``, ``ptailor report``)
CATALOGUE_PAGE = "index.html"
CATALOGUE_DIR = "_catalogue"
#: where a catalogue's batch keeps what its quality gates rejected: ``OUT/_rejected/NAME``
REJECTED_DIR = "_rejected"
#: names a garment's folder never takes: they are the catalogue's
RESERVED_NAMES = frozenset({CATALOGUE_PAGE, CATALOGUE_DIR, REJECTED_DIR})


def expand_garments(
    specs: Sequence[str],
    *,
    stdin: IO[str] | None = None,
    exclude_under: str | Path | None = None,
    warn: Callable[[str], None] | None = None,
) -> list[str]:
    """The garment paths that ``specs`` name, in order, each once.

    Parameters
    ----------
    specs : list of str
        Paths; globs (``*``, ``?``, ``[``, ``**`` recursive; expanded sorted, unless the
        argument is an existing file); folders (every ``*.obj`` and ``*.dxf`` below,
        sorted); ``-``: the paths listed on ``stdin``, one per line (blank lines ignored, no
        expansion). An OBJ that is the drape of a listed DXF (``X.obj`` beside ``X.dxf``)
        is left out: the pair is one garment.
    stdin : text stream, optional
        Read for ``-``.
    exclude_under : path, optional
        The output root: files below it found by a glob or a folder are left out (they are
        earlier outputs), paths given literally are kept.
    warn : callable, optional
        Called with a message for each glob or folder that finds no garment.

    Returns
    -------
    list of str
        As given (not resolved); a path named twice is kept the first time only. A literal
        path that does not exist is kept: it fails as a garment.

    Raises
    ------
    PtailorError
        ``-`` given twice or without ``stdin``.
    """
    out_root = Path(exclude_under).resolve() if exclude_under is not None else None

    def outside(p: str) -> bool:
        return out_root is None or out_root not in Path(p).resolve().parents

    paths: list[str] = []
    read_stdin = False
    for spec in specs:
        if spec == "-":
            if read_stdin or stdin is None:
                raise PtailorError("'-' (garment paths on stdin) can be given once")
            read_stdin = True
            paths += [ln.strip() for ln in stdin.read().splitlines() if ln.strip()]
        elif Path(spec).is_dir() or (_GLOB_CHARS.search(spec) and not Path(spec).is_file()):
            found = [p for p in _found(spec) if outside(p)]
            if not found and warn is not None:
                warn(f"{spec}: no garments found")
            paths += found
        else:
            paths.append(spec)
    paths = _without_drapes(paths)
    seen: set[str] = set()
    unique = []
    for p in paths:
        key = os.path.realpath(p)
        if key not in seen:
            seen.add(key)
            unique.append(p)
    return unique


def _found(spec: str) -> list[str]:
    """The files a folder (every garment file below it) or a glob names, sorted."""
    if Path(spec).is_dir():
        root = os.path.join(glob.escape(spec), "**")
        found = [
            f
            for ext in sorted({*READERS, *PATTERN_READERS})
            for pat in (f"*.{ext}", f"*.{ext.upper()}")
            for f in glob.glob(os.path.join(root, pat), recursive=True)
        ]
    else:
        found = glob.glob(spec, recursive=True)
    return [p for p in sorted(found) if Path(p).is_file()]


def drape_for(garment: str | Path) -> str | None:
    """The drape OBJ a DXF pattern is paired with: the file beside it with the same stem
    (``X.dxf`` -> ``X.obj``); None for an OBJ garment (it holds its own drape)."""
    p = Path(garment)
    if not is_pattern_file(p):
        return None
    for ext in (".obj", ".OBJ"):
        if p.with_suffix(ext).is_file():
            return str(p.with_suffix(ext))
    return str(p.with_suffix(".obj"))  # missing: the garment fails naming it


def _without_drapes(paths: list[str]) -> list[str]:
    """Drop the OBJs that are a listed DXF's drape (a folder holding ``X.dxf`` and
    ``X.obj`` is one garment, the DXF pattern with its drape)."""
    drapes = {os.path.realpath(d) for d in map(drape_for, paths) if d is not None}
    return [p for p in paths if os.path.realpath(p) not in drapes]


def output_names(
    paths: Sequence[str], names: Sequence[str | None] | None = None
) -> list[tuple[str, str | None]]:
    """One folder name per garment: the file's stem, made unique in input order.

    The first garment with a stem gets it; later ones get ``stem-2``, ``stem-3``, ...
    (skipping names that are some other garment's stem or given name).

    Parameters
    ----------
    paths : list of str
        The garments.
    names : list of (str or None), optional
        Names given (a manifest's ``name`` column; distinct, checked by the caller), None
        where the stem decides.

    Returns
    -------
    list of (name, note)
        ``note`` says why a name is not the stem (``None`` when it is, or was given). A stem
    in :data:`RESERVED_NAMES` is renamed like a repeated one.
    """
    given = list(names) if names is not None else [None] * len(paths)
    stems = [Path(p).stem or "garment" for p in paths]
    fixed = {n for n in given if n is not None}
    taken = set(stems) | fixed
    used = set(fixed) | RESERVED_NAMES  # a stem "index.html" gets "index.html-2"
    first: dict[str, str] = {}
    out = []
    for p, stem, name in zip(paths, stems, given, strict=True):
        if name is not None:
            out.append((name, None))
            continue
        if stem not in used:
            used.add(stem)
            first[stem] = p
            out.append((stem, None))
            continue
        k = 2
        while f"{stem}-{k}" in used or f"{stem}-{k}" in taken:
            k += 1
        name = f"{stem}-{k}"
        used.add(name)
        why = f"shared with {first[stem]}" if stem in first else "another garment's given name"
        out.append((name, f"stem {stem!r} is {why}: folder {name}"))
    return out
