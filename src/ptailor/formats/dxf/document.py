"""Opening a DXF with ezdxf, quietly and failing closed, and reading its text.

ezdxf's log goes to a list (recover mode's repairs become one warning); header numbers,
entity counts, TEXT contents and the style text (``Style Name:``, ``Sample Size:``) are
read with checks that refuse a malformed file with a one-line error.
"""

from __future__ import annotations

import contextlib
import io
import logging
import re
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from ptailor import tolerances as _tol
from ptailor.errors import PtailorError


class _Captured(logging.Handler):
    """Collects ezdxf's log records (recover mode's repairs) instead of printing them."""

    def __init__(self) -> None:
        super().__init__(level=logging.DEBUG)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        if record.levelno >= logging.WARNING and len(self.messages) < _tol.DXF_RECOVER_MESSAGES_MAX:
            with contextlib.suppress(Exception):  # a record that cannot be formatted is dropped
                self.messages.append(" ".join(str(record.getMessage()).split())[:200])


@contextlib.contextmanager
def quiet_ezdxf() -> Any:
    """ezdxf's log records captured (yielded), its prints and Python/numpy warnings
    swallowed: nothing reaches stdout or stderr while a DXF is read."""
    log = logging.getLogger("ezdxf")
    handler = _Captured()
    old = log.propagate, log.level
    log.addHandler(handler)
    log.propagate = False
    log.setLevel(logging.WARNING)
    sink = io.StringIO()
    try:
        with (
            contextlib.redirect_stdout(sink),
            contextlib.redirect_stderr(sink),
            warnings.catch_warnings(),
            np.errstate(all="ignore"),
        ):
            warnings.simplefilter("ignore")
            yield handler.messages
    finally:
        log.removeHandler(handler)
        log.propagate, log.level = old[0], old[1]


def recover_warning(messages: list[str]) -> tuple[str, ...]:
    """Recover mode's repairs as one report warning (the first few quoted)."""
    if not messages:
        return ()
    shown = "; ".join(messages[:3])
    more = f" (and {len(messages) - 3} more)" if len(messages) > 3 else ""
    return (f"read in ezdxf's recover mode, {len(messages)} repair(s): {shown}{more}",)


def open_document(spath: str, log: list[str] | None = None) -> Any:
    """The ezdxf document; strict reader first, then recover mode (CLO's group codes).

    Files over ``DXF_MAX_BYTES`` are refused unread; recover mode's repairs go to ``log``.
    """
    import ezdxf
    from ezdxf import recover

    p = Path(spath)
    if not p.is_file():
        raise PtailorError("no such file", path=spath)
    try:
        nbytes = p.stat().st_size
    except OSError as exc:
        raise PtailorError(f"cannot read: {exc.strerror or exc}", path=spath) from exc
    if nbytes > _tol.DXF_MAX_BYTES:
        raise PtailorError(
            f"the file is {nbytes} bytes, over the limit of {_tol.DXF_MAX_BYTES} for a DXF pattern",
            path=spath,
        )
    try:
        doc = ezdxf.readfile(spath)
    except Exception as strict_exc:  # any parse failure: retry leniently
        try:
            doc, _auditor = recover.readfile(spath)
        except Exception as exc:
            raise PtailorError(
                f"not a readable DXF file ({one_line(exc or strict_exc)})", path=spath
            ) from exc
    else:
        if log is not None:
            log.clear()  # the strict reader's notes are not repairs
    return doc


def one_line(exc: BaseException | str) -> str:
    """An exception's text on one line, at most 200 characters."""
    text = " ".join(str(exc).split()) or type(exc).__name__
    return text if len(text) <= 200 else text[:197] + "..."


class BadEntityError(ValueError):
    """An entity this reader cannot use; the message says why (no file or piece named)."""


def entity_xy(v: Any) -> tuple[float, float]:
    """A point's x and y as floats (a missing point or coordinate is a :class:`BadEntityError`)."""
    if v is None:
        raise BadEntityError("has no coordinates")
    try:
        return float(v[0]), float(v[1])
    except (TypeError, IndexError, ValueError) as exc:
        raise BadEntityError("has no x or y coordinate") from exc


def bad_coordinate(pts: np.ndarray, what: str = "vertex") -> str | None:
    """Why ``(n, 2)`` points are unusable: ``"vertex 3 is not a number"``, ``"vertex 0 is
    infinite"``, ``"vertex 2 lies 1e+300 units from the origin (limit 1e+07)"``; None when
    every coordinate is finite and within ``DXF_MAX_COORD``."""
    pts = np.asarray(pts, dtype=float).reshape(-1, 2)
    nan = np.isnan(pts).any(axis=1)
    if nan.any():
        return f"{what} {int(np.flatnonzero(nan)[0])} is not a number"
    inf = np.isinf(pts).any(axis=1)
    if inf.any():
        return f"{what} {int(np.flatnonzero(inf)[0])} is infinite"
    far = np.abs(pts).max(axis=1) > _tol.DXF_MAX_COORD if len(pts) else np.zeros(0, bool)
    if far.any():
        i = int(np.flatnonzero(far)[0])
        return (
            f"{what} {i} lies {float(np.abs(pts[i]).max()):.3g} units from the origin "
            f"(limit {_tol.DXF_MAX_COORD:.3g})"
        )
    return None


def header_number(doc: Any, name: str) -> int | None:
    """An integer header variable, or None when absent or not a sane integer."""
    try:
        v = doc.header.get(name)
    except Exception:  # a header that cannot be read says nothing
        return None
    if isinstance(v, bool) or not isinstance(v, int | float):
        return None
    if not np.isfinite(v) or abs(v) > _tol.DXF_HEADER_CODE_MAX:
        return None
    return int(v)


def check_counts(doc: Any, spath: str) -> None:
    """Refuse more than ``DXF_MAX_ENTITIES`` entities (modelspace and blocks)."""
    try:
        n = len(doc.entitydb)
    except Exception:  # no database size: the file-size limit still holds
        return
    if n > _tol.DXF_MAX_ENTITIES:
        raise PtailorError(
            f"{n} entities, over the limit of {_tol.DXF_MAX_ENTITIES} for a DXF pattern",
            path=spath,
        )


_DXF_UNICODE = re.compile(r"\\U\+([0-9A-Fa-f]{4})")


def printable_text(text: str) -> str:
    """``text`` with what UTF-8 cannot carry (lone surrogates from undecodable bytes)
    replaced by ``?``, so it can be printed and written back."""
    return text.encode("utf-8", "replace").decode("utf-8")


def text_of(e: Any) -> str:
    """An entity's text, ``\\U+XXXX`` escapes decoded (over ``DXF_MAX_TEXT`` characters:
    a :class:`BadEntityError`)."""
    if e.dxftype() == "MTEXT":
        raw = str(getattr(e, "text", ""))
        if len(raw) > _tol.DXF_MTEXT_RAW_FACTOR * _tol.DXF_MAX_TEXT:
            raise BadEntityError(f"has {len(raw)} characters of text (limit {_tol.DXF_MAX_TEXT})")
        t = e.plain_text()
    else:
        t = e.dxf.get("text", "")
    t = printable_text(_DXF_UNICODE.sub(lambda m: chr(int(m.group(1), 16)), str(t)).strip())
    if len(t) > _tol.DXF_MAX_TEXT:
        raise BadEntityError(f"has {len(t)} characters of text (limit {_tol.DXF_MAX_TEXT})")
    return t


def key_value(text: str) -> tuple[str, str]:
    """``"Piece Name: FRONT"`` -> ``("PIECE NAME", "FRONT")``; no colon -> ``("", text)``."""
    key, sep, value = text.partition(":")
    if not sep:
        return "", text
    return " ".join(key.split()).upper(), value.strip()


def describe_entity(e: Any, index: int | None = None) -> str:
    """``"POLYLINE 12 (layer 1)"``: an entity as messages name it (with its place in its
    block or in modelspace)."""
    try:
        kind = str(e.dxftype())
        layer = " ".join(str(e.dxf.get("layer", "0")).split())[:40]
    except Exception:
        return "an entity" if index is None else f"entity {index}"
    where = "" if index is None else f" {index}"
    return f"{kind}{where} (layer {layer or '0'})"


def read_style_text(msp: Any, spath: str = "") -> dict[str, str]:
    """Modelspace ``KEY: value`` texts, keys upper-cased (first occurrence wins)."""
    out: dict[str, str] = {}
    for e in msp.query("TEXT MTEXT"):
        try:
            text = text_of(e)
        except BadEntityError as exc:
            raise PtailorError(f"modelspace: {describe_entity(e)} {exc}", path=spath) from exc
        k, v = key_value(text)
        if k and k not in out:
            out[k] = v
    return out
