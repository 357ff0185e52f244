"""JSON that ptailor reads, within limits: the one reader of every JSON file it reads back.

Python's :func:`json.loads` has no limits of its own: a deeply nested file raises
``RecursionError``, an integer of 400 digits becomes an int that ``float()`` cannot take
(``OverflowError``), one of more than 4,300 digits a ``ValueError`` that is no
``JSONDecodeError``, and a repeated key silently keeps the last value. Here a file is
refused before it is parsed when it is larger than ``tol.JSON_MAX_BYTES`` or nests deeper
than ``tol.JSON_MAX_DEPTH`` (counted over the text without its strings, in numpy), and while
it is parsed when an integer literal is longer than ``tol.JSON_MAX_INT_CHARS`` or an object
repeats a key. Every refusal is a :class:`~ptailor.errors.PtailorError` naming the file.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import numpy as np

from ptailor import tolerances as tol
from ptailor.errors import PtailorError

__all__ = ["json_depth", "parse_json", "read_json"]

#: a JSON string literal (its escapes included)
_STRING = re.compile(rb'"(?:[^"\\]|\\.)*"', re.DOTALL)


class _LimitError(ValueError):
    """A limit crossed inside the parser (raised from its hooks)."""


def json_depth(text: str | bytes) -> int:
    """How deep arrays and objects nest in ``text`` (0: a bare value), strings skipped.

    Counted without parsing (brackets outside strings, a cumulative sum), so a text far
    too deep for Python's recursive parser is measured in linear time.
    """
    raw = text.encode("utf-8", "surrogatepass") if isinstance(text, str) else text
    b = np.frombuffer(_STRING.sub(b'""', raw), dtype=np.uint8)
    step = np.isin(b, (ord("["), ord("{"))).astype(np.int64)
    step -= np.isin(b, (ord("]"), ord("}")))
    return int(np.cumsum(step).max(initial=0))


def _int(s: str) -> int:
    if len(s) > tol.JSON_MAX_INT_CHARS:
        raise _LimitError(
            f"an integer of {len(s)} digits (at most {tol.JSON_MAX_INT_CHARS}): {s[:20]}..."
        )
    return int(s)


def _pairs(pairs: list[tuple[str, Any]]) -> dict:
    out: dict = {}
    for key, value in pairs:  # an object's members
        if key in out:
            raise _LimitError(f"the key {key!r} appears twice in one object")
        out[key] = value
    return out


def parse_json(text: str, *, path: str | Path, what: str) -> Any:
    """``text`` parsed as JSON within the limits.

    Parameters
    ----------
    text : str
    path : str or Path
        The file the text came from (errors name it).
    what : str
        What the file is (``specification``, ``catalogue``): errors say ``not a JSON
        {what}``.

    Returns
    -------
    Any
        The value; objects are dicts (no key repeated), integers ints of at most
        ``tol.JSON_MAX_INT_CHARS`` digits, other numbers floats (``1e400`` is ``inf``: the
        caller bounds its numbers).

    Raises
    ------
    PtailorError
        Not JSON, too deep, an integer too long or a key repeated.
    """
    depth = json_depth(text)
    if depth > tol.JSON_MAX_DEPTH:
        raise PtailorError(
            f"not a JSON {what}: nested {depth} deep (at most {tol.JSON_MAX_DEPTH})",
            path=str(path),
        )
    try:
        return json.loads(text, parse_int=_int, object_pairs_hook=_pairs)
    except (ValueError, RecursionError) as e:  # JSONDecodeError and _LimitError are ValueErrors
        raise PtailorError(f"not a JSON {what}: {e}", path=str(path)) from None


def read_json(path: str | Path, *, what: str, max_bytes: int | None = None) -> Any:
    """The JSON file at ``path``, read and parsed within the limits (:func:`parse_json`).

    Parameters
    ----------
    path : str or Path
    what : str
        What the file is, for the messages.
    max_bytes : int, optional
        Largest file read (default ``tol.JSON_MAX_BYTES``).

    Raises
    ------
    PtailorError
        The file cannot be read, is too large, is not UTF-8, or :func:`parse_json` refuses it.
    """
    limit = tol.JSON_MAX_BYTES if max_bytes is None else max_bytes
    try:
        with open(path, "rb") as f:
            data = f.read(limit + 1)
    except OSError as e:
        raise PtailorError(f"cannot read the {what}: {e.strerror}", path=str(path)) from None
    if len(data) > limit:
        raise PtailorError(f"the {what} is larger than {limit} bytes: not read", path=str(path))
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        raise PtailorError(f"not a JSON {what}: not UTF-8 ({e.reason})", path=str(path)) from None
    return parse_json(text, path=path, what=what)
