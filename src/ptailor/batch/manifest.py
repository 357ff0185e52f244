"""A batch manifest: one garment a row, each with its own options (``batch --manifest``).

A manifest is CSV with a header row, or JSON Lines (one object a line): a ``.jsonl``,
``.ndjson`` or ``.json`` file, or one whose first character is ``{``. Its columns
(:data:`MANIFEST_COLUMNS`): ``garment`` (required: the OBJ or DXF; relative paths are
resolved against the manifest's folder), ``drape`` (the drape OBJ of a pattern-only
garment; default: for ``X.dxf`` the ``X.obj`` beside it), ``spec`` (the garment's
GarmentCode / Garment-Pattern-Generator specification JSON, resolved like ``garment``, or
``auto``: the one beside it), ``edited_drape`` (the garment's drape edited elsewhere, resolved
like ``garment``: the edit, in place of the recipe's steps; :mod:`ptailor.run.edited`),
``name`` (the output folder;
default: the garment file's stem, made unique) and the options of :data:`OPTION_COLUMNS`,
which override the command line's for that garment. A cell that is empty (or a key that is
absent or ``null``) falls back to the command line.

The whole manifest is checked before anything runs (:func:`read_manifest`): columns, the
garment and drape files, the options, the output names. Rows are numbered as the file's
lines (the CSV header is row 1).
"""

from __future__ import annotations

import csv
import io
import json
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ptailor import tolerances as tol
from ptailor.batch.inputs import RESERVED_NAMES, drape_for
from ptailor.errors import PtailorError
from ptailor.formats import is_pattern_file

#: the options a row may set: :class:`~ptailor.run.options.RunOptions` fields, named as
#: the command line's options (``pattern_units`` is ``--pattern-units``)
OPTION_COLUMNS = ("pattern_units", "drape_units", "dxf_units", "size", "up", "front")
#: every column a manifest may have
MANIFEST_COLUMNS = ("garment", "drape", "spec", "edited_drape", "name", *OPTION_COLUMNS)
#: unit options, and whether each also takes ``auto`` (a [0, 1] atlas)
UNIT_OPTIONS = {"pattern_units": True, "drape_units": False}
#: suffixes read as JSON Lines (any other file is CSV unless it starts with ``{``)
JSON_LINES_SUFFIXES = (".jsonl", ".ndjson", ".json")
#: the longest output folder name, in UTF-8 bytes (a file name's limit)
NAME_MAX_BYTES = 255

#: ``check(column, text)``: an option cell's value, or :class:`PtailorError` saying why not
Check = Callable[[str, str], Any]


@dataclass(frozen=True)
class ManifestRow:
    """One garment of a batch with what its manifest row says about it.

    Attributes
    ----------
    garment : str
        The garment file as it is read and shown (resolved against the manifest's folder).
    row : int or None
        Its row (line) in the manifest; None for a garment not from a manifest.
    drape : str or None
        The drape OBJ (resolved like ``garment``); None: the default
        (:func:`~ptailor.batch.inputs.drape_for`).
    name : str or None
        The output folder's name; None: the garment's stem, made unique.
    options : mapping
        :class:`~ptailor.run.options.RunOptions` fields this garment overrides.
    """

    garment: str
    row: int | None = None
    drape: str | None = None
    name: str | None = None
    options: Mapping[str, Any] = field(default_factory=dict)


def as_rows(garments: Sequence[str | ManifestRow]) -> list[ManifestRow]:
    """Garments as :class:`ManifestRow` (a path is a row with no options of its own)."""
    return [g if isinstance(g, ManifestRow) else ManifestRow(garment=g) for g in garments]


def check_units(name: str, value: str | None) -> str | None:
    """A manifest's unit cell (``pattern_units`` or ``drape_units``, :data:`UNIT_OPTIONS`)
    checked with the parser that reads the garments and the command line's units
    (:func:`ptailor.formats.garment.parse_units`).

    Parameters
    ----------
    name : str
        The column (the option's field name), named in the message.
    value : str or None
        ``cm``, ``0.3333cm``, ...; for the pattern also ``auto``; None: not given.

    Returns
    -------
    str or None
        ``value``.

    Raises
    ------
    PtailorError
        An unknown unit or one outside the sane range (exit 2).
    """
    from ptailor.formats.garment import parse_units

    if value is not None and not (UNIT_OPTIONS[name] and value == "auto"):
        parse_units(value, what=name)
    return value


def read_manifest(path: str | Path, *, check: Check) -> list[ManifestRow]:
    """The garments of a manifest, every row checked before any garment is read.

    Parameters
    ----------
    path : str or Path
        The manifest (CSV with a header row, or JSON Lines); blank rows are ignored.
    check : callable
        ``check(column, text)`` for each non-empty cell of :data:`OPTION_COLUMNS`: its
        value (what the command line's option would hold), or :class:`PtailorError` saying
        what is wrong (the command line checks a cell as it checks its own option).

    Returns
    -------
    list of ManifestRow
        In the manifest's order, paths resolved against its folder.

    Raises
    ------
    PtailorError
        Naming the manifest, and each problem's row: the file cannot be read, an unknown
        or repeated column, a row without a garment, a garment or drape file that does not
        exist, a bad option value, an output name that is not a plain folder name or is
        another row's, no garments at all.
    """
    path = str(path)
    text = _read_text(path)
    parsed, problems = _rows(path, text)
    base = os.path.dirname(path)
    rows = []
    for n, cells in parsed:
        row, probs = _row(n, cells, base, check)
        problems += probs
        if row is not None:
            rows.append(row)
    problems += _name_problems(rows)
    if problems:
        shown = [f"row {n}: {msg}" for n, msg in sorted(problems, key=lambda p: p[0])]
        if len(shown) > tol.MANIFEST_PROBLEMS_SHOWN:
            more = len(shown) - tol.MANIFEST_PROBLEMS_SHOWN
            shown = [*shown[: tol.MANIFEST_PROBLEMS_SHOWN], f"and {more} more"]
        head = "" if len(problems) == 1 else f"{len(problems)} problems: "
        raise PtailorError(head + "; ".join(shown), path=path)
    if not rows:
        raise PtailorError("no garments (the manifest has no rows)", path=path)
    return rows


# --------------------------------------------------------------------------- reading

#: (row number, problem)
Problem = tuple[int, str]


def _read_text(path: str) -> str:
    """The manifest's text (UTF-8, a BOM allowed)."""
    p = Path(path)
    if not p.exists():
        raise PtailorError("no such file (--manifest)", path=path)
    if not p.is_file():
        raise PtailorError("not a file (--manifest)", path=path)
    try:
        if p.stat().st_size > tol.MANIFEST_MAX_BYTES:
            raise PtailorError(
                f"not a manifest: larger than {tol.MANIFEST_MAX_BYTES} bytes", path=path
            )
        return p.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError:
        raise PtailorError("not a manifest: not UTF-8 text", path=path) from None
    except OSError as exc:
        raise PtailorError(f"cannot read ({exc.strerror or exc})", path=path) from None


def _rows(path: str, text: str) -> tuple[list[tuple[int, dict]], list[Problem]]:
    """``[(row, {column: cell})]`` and the problems of the file's layout."""
    if path.lower().endswith(JSON_LINES_SUFFIXES) or text.lstrip().startswith("{"):
        return _json_rows(text)
    return _csv_rows(text)


def _csv_rows(text: str) -> tuple[list[tuple[int, dict]], list[Problem]]:
    reader = csv.reader(io.StringIO(text, newline=""))
    header: list[str] | None = None
    rows: list[tuple[int, dict]] = []
    problems: list[Problem] = []
    start = 1
    try:
        for record in reader:
            n, start = start, reader.line_num + 1
            cells = [c.strip() for c in record]
            if not any(cells):
                continue  # a blank row
            if header is None:
                header = [c.lower() for c in cells]
                problems += [(n, p) for p in _column_problems(header)]
                if "garment" not in header:
                    problems.append((n, "no garment column (the header must name one)"))
                    return [], problems
                continue
            if any(cells[len(header) :]):
                problems.append((n, f"{len(cells)} cells, the header has {len(header)} columns"))
            rows.append((n, dict(zip(header, cells, strict=False))))
    except csv.Error as exc:
        problems.append((start, f"not CSV ({exc})"))
    return rows, problems


def _json_rows(text: str) -> tuple[list[tuple[int, dict]], list[Problem]]:
    rows: list[tuple[int, dict]] = []
    problems: list[Problem] = []
    for n, line in enumerate(text.split("\n"), start=1):  # (not splitlines: U+2028 in a value)
        if not line.strip():
            continue
        try:
            obj = json.loads(line, object_pairs_hook=_pairs)
        except (ValueError, RecursionError) as exc:  # (nested too deep: RecursionError)
            problems.append((n, f"not a JSON object ({str(exc)[:120]})"))
            continue
        if not isinstance(obj, _Pairs):
            problems.append((n, "not a JSON object"))
            continue
        keys = [str(k).strip().lower() for k, _ in obj]
        probs = _column_problems(keys)
        cells = {}
        for key, (_, value) in zip(keys, obj, strict=True):
            if value is None:
                continue
            if isinstance(value, bool) or not isinstance(value, str | int | float):
                kind = (
                    "an object" if isinstance(value, _Pairs)
                    else "a list" if isinstance(value, list) else json.dumps(value)
                )  # fmt: skip
                probs.append(f"{key}: must be a string, not {kind}")
                continue
            cells[key] = str(value).strip()
        problems += [(n, p) for p in probs]
        rows.append((n, cells))
    return rows, problems


class _Pairs(list):
    """A JSON object as its key-value pairs (so that a repeated key is a problem, not the
    last one silently)."""


def _pairs(pairs: list[tuple[str, Any]]) -> _Pairs:
    return _Pairs(pairs)


def _column_problems(columns: list[str]) -> list[str]:
    """Unknown, unnamed and repeated columns."""
    probs = []
    known = ", ".join(MANIFEST_COLUMNS)
    for c in sorted(set(columns) - set(MANIFEST_COLUMNS), key=columns.index):
        probs.append(f"unknown column {c!r} (known: {known})" if c else "a column without a name")
    for c in sorted({c for c in columns if c and columns.count(c) > 1}, key=columns.index):
        probs.append(f"column {c!r} given twice")
    return probs


# --------------------------------------------------------------------------- checking


def _row(n: int, cells: dict, base: str, check: Check) -> tuple[ManifestRow | None, list]:
    """A row's garment (None when it has none) and its problems."""
    problems: list[Problem] = []
    cells = {k: v for k, v in cells.items() if k in MANIFEST_COLUMNS and v}
    options = {}
    for column in OPTION_COLUMNS:
        if column in cells:
            try:
                options[column] = check(column, cells[column])
            except PtailorError as exc:
                problems.append((n, str(exc)))
    name = cells.get("name")
    if name is not None and (why := _bad_name(name)):
        problems.append((n, f"name {name!r}: {why}"))
    if "garment" not in cells:
        return None, [(n, "no garment (the garment column is required)"), *problems]
    garment = _resolve(base, cells["garment"])
    drape = _resolve(base, cells["drape"]) if "drape" in cells else None
    if not _is_file(garment):
        problems.append((n, f"garment {garment}: {_missing(garment)}"))
    elif drape is not None and not _is_file(drape):
        problems.append((n, f"drape {drape}: {_missing(drape)}"))
    elif drape is None and is_pattern_file(garment) and not _is_file(drape_for(garment)):
        what = f"{drape_for(garment)}, the drape beside the pattern"
        problems.append((n, f"{what}: no such file (or give a drape column)"))
    for column in ("spec", "edited_drape"):  # files the run reads beside the garment
        if column in cells:
            options[column] = path = _file_cell(base, column, cells[column])
            if path != "auto" and not _is_file(path):
                problems.append((n, f"{column} {path}: {_missing(path)}"))
    row = ManifestRow(garment=garment, row=n, drape=drape, name=name, options=options)
    return row, problems


def _file_cell(base: str, column: str, cell: str) -> str:
    """A file column's path (resolved: :func:`_resolve`), or ``auto`` for ``spec``'s."""
    return cell if column == "spec" and cell == "auto" else _resolve(base, cell)


def _resolve(base: str, path: str) -> str:
    """A manifest's path, relative to the manifest's folder."""
    return path if not base or os.path.isabs(path) else os.path.join(base, path)


def _is_file(path: str) -> bool:
    """Whether ``path`` is a file (a name the system refuses, too long or with a NUL: no)."""
    try:
        return Path(path).is_file()
    except (OSError, ValueError):
        return False


def _missing(path: str) -> str:
    try:
        return "not a file" if Path(path).exists() else "no such file"
    except (OSError, ValueError) as exc:
        return f"not a file name ({getattr(exc, 'strerror', None) or exc})"


def _bad_name(name: str) -> str | None:
    """Why ``name`` cannot be an output folder's name (None when it can)."""
    if name in (".", "..") or any(c in name for c in "/\\\0"):
        return "not a plain folder name"
    if name.startswith("."):
        return "a hidden name (ptailor's staging folders start with '.')"
    if len(name.encode("utf-8", "surrogatepass")) > NAME_MAX_BYTES:
        return f"longer than {NAME_MAX_BYTES} bytes"
    return None


def _name_problems(rows: list[ManifestRow]) -> list[Problem]:
    """Output names that two rows give, or that are the catalogue's."""
    first: dict[str, int] = {}
    problems = []
    for r in rows:
        if r.name is None:
            continue
        if r.name in RESERVED_NAMES:
            problems.append((r.row, f"name {r.name!r} is the batch catalogue's; name another"))
        elif r.name in first:
            problems.append((r.row, f"name {r.name!r} is row {first[r.name]}'s too"))
        else:
            first[r.name] = r.row
    return problems
