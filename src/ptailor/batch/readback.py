"""Reading back what ptailor wrote: one place for every file a batch or a catalogue reads
again (a garment folder's ``report.json`` and ``batch.json``, ``_catalogue/catalogue.json``,
a ``--log``'s records).

Each file is read with a size and a nesting limit (:func:`load_json`: a deeply nested file
is refused, never a ``RecursionError``) and checked against a small schema of the fields
ptailor uses (:func:`checked`): a field of the wrong type (``"warnings": null``, a string
where a number goes, a 400-digit integer) is dropped and named in a problem, never a
traceback later. What to do with the problems is the caller's: a catalogue names the file
in a warning and goes on, a ``--log`` given by the user is exit 2, a batch re-runs a
garment whose stored report is not one ptailor wrote.

Schemas are plain data: a type (``str``, ``bool``, ``dict``, ``list``), :data:`NUM` (a
finite number within :data:`~ptailor.tolerances.READBACK_NUMBER_MAX`, or null), :data:`INT`
(an integer, or null), ``[item]`` (a list of items: a bad item is dropped), ``{key:
schema}`` (an object: its listed keys checked, others kept), :class:`Each` (an object of
names to one schema), :class:`Null` (the schema, or null), :class:`OneOf` (one of a few
strings).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ptailor import tolerances as tol
from ptailor.errors import PtailorError
from ptailor.formats.json_input import json_depth, parse_json

#: a number (int or float, not bool), finite and within READBACK_NUMBER_MAX, or null
NUM = "number"
#: an integer (not bool) within READBACK_NUMBER_MAX, or null
INT = "integer"
#: a plain file name: not empty, ``.`` or ``..``, no ``/`` or NUL, at most 255 bytes
FILE_NAME = "file name"


@dataclass(frozen=True)
class Each:
    """An object whose every value matches ``item`` (a name -> record mapping)."""

    item: Any


@dataclass(frozen=True)
class Null:
    """``schema``, or null."""

    schema: Any


@dataclass(frozen=True)
class OneOf:
    """One of ``values`` (strings)."""

    values: tuple[str, ...]


class ReadBackError(Exception):
    """A file ptailor reads back cannot be read, is too large, too deep or not JSON."""


_BAD = object()  # a value that does not match its schema (dropped)


# --------------------------------------------------------------------------- reading


def nesting_depth(text: str) -> int:
    """How deep ``text``'s arrays and objects nest (strings' brackets not counted): the
    specification reader's count (:func:`ptailor.formats.json_input.json_depth`)."""
    return json_depth(text)


def load_text(path: str | Path, *, max_bytes: int = tol.READBACK_MAX_BYTES) -> str:
    """A file's text, within ``max_bytes`` and its nesting within
    :data:`~ptailor.tolerances.READBACK_MAX_DEPTH`.

    Raises
    ------
    ReadBackError
        The file cannot be read, is larger than ``max_bytes``, is not UTF-8 text or nests
        too deep (the message says which).
    """
    p = Path(path)
    try:
        size = p.stat().st_size
        if size > max_bytes:
            raise ReadBackError(f"larger than {max_bytes} bytes ({size})")
        text = p.read_bytes().decode("utf-8")
    except OSError as exc:
        raise ReadBackError(f"cannot be read ({exc.strerror or exc})") from None
    except UnicodeDecodeError:
        raise ReadBackError("not UTF-8 text") from None
    depth = nesting_depth(text)
    if depth > tol.READBACK_MAX_DEPTH:
        raise ReadBackError(f"nested {depth} deep (at most {tol.READBACK_MAX_DEPTH})")
    return text


def parse(text: str) -> Any:
    """``text`` parsed with the specification reader's limits
    (:func:`ptailor.formats.json_input.parse_json`: long integers, repeated keys, depth),
    every failure a :class:`ReadBackError`."""
    try:
        return parse_json(text, path="", what="file")
    except PtailorError as exc:
        raise ReadBackError(exc.message.replace("not a JSON file", "not JSON")) from None


def load_json(path: str | Path, *, max_bytes: int = tol.READBACK_MAX_BYTES) -> Any:
    """A JSON file ptailor wrote, read within the limits (:func:`load_text`).

    Raises
    ------
    ReadBackError
    """
    return parse(load_text(path, max_bytes=max_bytes))


# --------------------------------------------------------------------------- checking


def _number(x: Any, *, integer: bool) -> bool:
    if isinstance(x, bool) or not isinstance(x, int if integer else int | float):
        return False
    try:
        return math.isfinite(float(x)) and abs(float(x)) <= tol.READBACK_NUMBER_MAX
    except OverflowError:  # an integer of 400 digits
        return False


def is_file_name(name: str) -> bool:
    """Whether ``name`` is a plain file name a folder can hold (:data:`FILE_NAME`)."""
    if name in ("", ".", "..") or "/" in name or "\0" in name:
        return False
    return len(name.encode("utf-8", "surrogatepass")) <= tol.READBACK_NAME_MAX_BYTES


def _kind(value: Any, schema: Any) -> str:
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, int | float):
        if schema in (NUM, INT) and not _number(value, integer=False):
            return "a number out of range"
        return "a number"
    return {str: "a string", list: "a list", dict: "an object"}.get(type(value), "a value")


def _want(schema: Any) -> str:
    if schema in (NUM, INT):
        return f"an {schema}" if schema == INT else "a number"
    if schema == FILE_NAME:
        return "a plain file name"
    if isinstance(schema, Null):
        return _want(schema.schema) + " or null"
    if isinstance(schema, OneOf):
        return "one of " + ", ".join(schema.values)
    if isinstance(schema, list):
        return "a list"
    if isinstance(schema, dict | Each) or schema is dict:
        return "an object"
    return {str: "a string", bool: "a boolean", list: "a list"}.get(schema, "a value")


def _check(value: Any, schema: Any, where: str, problems: list[str]) -> Any:
    """``value`` checked against ``schema``: itself, cleaned, or ``_BAD`` (a problem said)."""
    if schema is Any:
        return value
    if isinstance(schema, Null):
        return None if value is None else _check(value, schema.schema, where, problems)
    if schema in (NUM, INT):
        ok = value is None or _number(value, integer=schema == INT)
    elif isinstance(schema, OneOf):
        ok = isinstance(value, str) and value in schema.values
    elif schema == FILE_NAME:
        ok = isinstance(value, str) and is_file_name(value)
    elif isinstance(schema, list):
        ok = isinstance(value, list)
        if ok:
            items = [_check(v, schema[0], f"{where}[{k}]", problems) for k, v in enumerate(value)]
            return [v for v in items if v is not _BAD]
    elif isinstance(schema, dict | Each):
        ok = isinstance(value, dict)
        if ok:
            return _check_object(value, schema, where, problems)
    else:
        ok = isinstance(value, schema) and not (schema is int and isinstance(value, bool))
    if ok:
        return value
    shown = f" {value!r}" if isinstance(value, str) and len(value) < 40 else ""
    problems.append(f"{where} is {_kind(value, schema)}{shown}, not {_want(schema)}")
    return _BAD


def _check_object(value: dict, schema: dict | Each, where: str, problems: list[str]) -> dict:
    out = {}
    for k, v in value.items():
        sub = schema.item if isinstance(schema, Each) else schema.get(k, Any)
        name = f"{where} {k}" if where.endswith(":") else f"{where}.{k}"
        got = _check(v, sub, name, problems)
        if got is not _BAD:
            out[k] = got
    return out


def checked(value: Any, schema: Any, *, where: str = "") -> tuple[Any, list[str]]:
    """``value`` with every field that does not match ``schema`` dropped, and the problems.

    Parameters
    ----------
    value : Any
        What ``json.loads`` returned.
    schema : Any
        The file kind's schema (:data:`REPORT_FIELDS`, :data:`RECORD_FIELDS`,
        :data:`SAVED_FIELDS`, :data:`STAMP_FIELDS`).
    where : str
        The value's name in the problems (``line 3:``; empty: the file's top level).

    Returns
    -------
    value : Any or None
        The value cleaned; None when the top level itself does not match.
    problems : list of str
        ``FIELD is X, not Y``, one per dropped field (or item).
    """
    problems: list[str] = []
    got = _check(value, schema, where or "the file", problems)
    if problems and not where:
        problems = [p.removeprefix("the file.") for p in problems]
    return (None if got is _BAD else got), problems


# --------------------------------------------------------------------------- schemas

_P95 = Null({"p95": NUM})
_PANEL = {
    "name": str,
    "triangles": INT,
    "area_before": NUM,
    "area_after": NUM,
    "boundary_deviation": NUM,
    "intrinsic_scale_error": Null({"mean": NUM, "p95": NUM, "max": NUM}),
    "baseline_intrinsic_scale_error": _P95,
    "flipped_triangles": INT,
    "mirrored": Null(bool),
}
_SEAM = {
    "name": str,
    "panels": [Any],
    "edges": INT,
    "ratio_after": NUM,
    "ratio_target": NUM,
    "mismatch": NUM,
}
_REDRAPE = Null({"panels": Null(Each(Null({"stretch": _P95, "displacement": _P95})))})
_SIDES = Null({"drape": NUM, "pattern": NUM})
_MEASURE = {"name": Any, "kind": Null(str), "drape": NUM, "pattern": NUM}

#: ``report.json``: what a batch's gates and records and a catalogue's pages read
REPORT_FIELDS = {
    "inputs": Null(Each(Null({"path": Null(str)}))),
    "outputs": [FILE_NAME],
    "units": Null(Any),
    "solver": Null(dict),
    "panels": [_PANEL],
    "seams": [_SEAM],
    "steps": [dict],
    "warnings": [str],
    "verify": Null({"ours": _REDRAPE, "baseline": _REDRAPE, "original": _REDRAPE}),
    "spec": Null({"fit_max": NUM}),
    "measures": Null({"before": Null([_MEASURE]), "after": Null([_MEASURE])}),
    "expect": [
        {
            "name": Any,
            "on": Null(str),
            "achieved": _SIDES,
            "target": _SIDES,
            "asked": Null(dict),
        }
    ],
}
#: a record's numbers
_NUMBERS = (
    "seconds",
    "max_area_change",
    "max_boundary_deviation",
    "max_intrinsic_error_p95",
    "max_seam_mismatch",
    "verify_stretch_p95",
    "verify_displacement_p95",
    "spec_fit_max",
)
#: a batch record (a ``--log`` line, one of ``catalogue.json``'s records)
RECORD_FIELDS = {
    "index": INT,
    "garment": str,
    "out": Null(str),
    "status": OneOf(("ok", "skipped", "failed", "interrupted")),
    "failure": Null(str),
    "reason": Null(str),
    "note": Null(str),
    "panels": INT,
    "flipped_triangles": INT,
    "warnings": INT,
    "failed_gates": Null([str]),
    **dict.fromkeys(_NUMBERS, NUM),
}
#: ``_catalogue/catalogue.json``: the last ``batch --html``'s records and summary
SAVED_FIELDS = {
    "summary": Null(
        {
            "seconds": NUM,
            "ran": INT,
            "where": Null(str),
            "recipe": Null(str),
            "recipe_text": Null(str),
        }
    ),
    "records": [dict],
}
#: ``batch.json``: a garment folder's stamp (where the catalogue finds the garment's path)
STAMP_FIELDS = {"key": Null(str), "garment": Null({"path": Null(str), "sha256": Null(str)})}


def read_checked(path: str | Path, schema: Any) -> tuple[Any, list[str]]:
    """A file ptailor wrote, read within the limits and checked against ``schema``.

    Returns
    -------
    value : Any or None
        The cleaned value (:func:`checked`); None when the file cannot be read, is not
        JSON or is not of the schema's kind at its top level.
    problems : list of str
        What was wrong (empty: nothing).
    """
    try:
        data = load_json(path)
    except ReadBackError as exc:
        return None, [str(exc)]
    return checked(data, schema)
