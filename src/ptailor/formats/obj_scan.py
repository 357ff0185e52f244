"""The fast path of the OBJ reader: a well-formed file scanned in bulk.

Every line is classified by its first bytes (``v``, ``vt``, ``f``, ``g``/``o``, anything
else ignored, as :func:`ptailor.formats.obj.read_obj` does) and the bodies of each record
kind are gathered into one buffer and converted in bulk. Nothing is raised here: whatever
the scan does not recognise as well-formed (a byte outside a number's alphabet, a ragged
record, a token that is not one number, a corner whose ``/`` count differs from the first
corner's, fewer than three corners, an index beyond 2**62, a lone carriage return, no ``v``
or no ``f``) makes :func:`scan` return None, and the reader then parses the file record by
record, with its exact error messages. When the scan succeeds its arrays are the ones the
record-by-record parser gives, and the reader's checks run on them unchanged.

Numbers: each record kind's text is converted by one ``np.fromstring`` call, which
converts coordinates as Python's ``float`` does (correctly rounded) and raises at the first
text it cannot convert. Every token converts to at least one number or raises, so when the
count of numbers equals the count of tokens each token is exactly one number. Coordinates
may hold digits, ``.``, ``e``/``E`` and signs only (no ``nan``, ``inf`` or ``1_0``: the
record parser names or reads those); face fields digits with at most a leading ``-``
before a digit (numpy's integer conversion reads a lone ``-`` as 0 and skips blanks after
a sign), so each field is at most one number.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

_SPACE, _TAB, _CR, _LF = 32, 9, 13, 10
_SLASH, _MINUS = 47, 45
_RUNS = 256  # record kinds in at most this many runs of lines are gathered by slicing
_INDEX_MAX = 1 << 62  # np.fromstring clamps an integer beyond int64: refuse far below


# byte classes of a section: 0 foreign, 1 blank (space, tab, CR, LF), then per alphabet
_FOREIGN, _BLANK, _DIGIT, _POINT, _EXP, _SIGN = range(6)


def _table(classes: dict[bytes, int]) -> np.ndarray:
    t = np.zeros(256, dtype=np.uint8)
    t[[_SPACE, _TAB, _CR, _LF]] = _BLANK
    t[np.frombuffer(b"0123456789", dtype=np.uint8)] = _DIGIT
    for chars, c in classes.items():
        t[np.frombuffer(chars, dtype=np.uint8)] = c
    return t


_FLOAT_CHARS = _table({b".": _POINT, b"eE": _EXP, b"+-": _SIGN})
_INDEX_CHARS = _table({b"-": _SIGN, b"/": _POINT})
#: the pairs of neighbouring classes a decimal number's text may hold (prev * 6 + next)
_PAIR_OK = np.zeros(36, dtype=bool)
for _p, _n in (
    (_BLANK, _BLANK), (_BLANK, _DIGIT), (_BLANK, _POINT), (_BLANK, _SIGN),
    (_DIGIT, _BLANK), (_DIGIT, _DIGIT), (_DIGIT, _POINT), (_DIGIT, _EXP),
    (_POINT, _BLANK), (_POINT, _DIGIT), (_POINT, _EXP),
    (_EXP, _DIGIT), (_EXP, _SIGN), (_SIGN, _DIGIT), (_SIGN, _POINT),
):  # fmt: skip
    _PAIR_OK[_p * 6 + _n] = True


@dataclass(frozen=True)
class Scan:
    """What :func:`scan` found.

    Attributes
    ----------
    v : (nv, c) float array
        The ``v`` records' numbers (every record has the same count ``c``).
    vt : (nt, c) float array or None
        The ``vt`` records' numbers; None when the file has none.
    nums : (k, s + 1) int array
        Each face corner's fields (``v[/vt[/vn]]``, ``v//vn`` read as ``v/0/vn``), file order.
    corners_per : (nf,) int array
        Corners of each ``f`` record (>= 3).
    slashes : int
        ``/`` per corner (0, 1 or 2).
    face_line_group : (nf,) int array
        Index into ``group_lines`` of the last ``g``/``o`` record before each ``f`` record
        (-1: none).
    group_lines : list of str
        The names of the ``g``/``o`` records in file order (decoded and stripped).
    """

    v: np.ndarray
    vt: np.ndarray | None
    nums: np.ndarray
    corners_per: np.ndarray
    slashes: int
    face_line_group: np.ndarray
    group_lines: list[str]


@dataclass(frozen=True)
class _Section:
    """The bodies of one record kind in one buffer (tags blanked, each line ending in \\n)."""

    buf: np.ndarray  # (b,) uint8
    cls: np.ndarray  # (b,) uint8 byte classes
    tok: np.ndarray  # (t,) first byte of each token
    end: np.ndarray  # (t,) last byte of each token
    per_line: np.ndarray  # (r,) tokens of each record


def _section(a: np.ndarray, starts: np.ndarray, lengths: np.ndarray, rows, tag: int, table):
    """The records ``rows`` (a mask over the lines) as a :class:`_Section`, or None when a
    byte outside ``table``'s alphabet occurs."""
    n = len(a)
    idx = np.flatnonzero(rows)
    brk = np.flatnonzero(np.diff(idx) > 1)
    if brk.size < _RUNS:  # runs of lines (the usual layout): slices of the file
        first_line = idx[np.concatenate([[0], brk + 1])].tolist()
        last_line = idx[np.concatenate([brk, [len(idx) - 1]])].tolist()
        sec = np.concatenate(
            [
                a[starts[i] : starts[j] + lengths[j] + 1]
                for i, j in zip(first_line, last_line, strict=True)
            ]
        )
    else:
        sec = a[np.repeat(rows, lengths + 1)[:n]]  # the +1: each line's \n
    lens = lengths[rows] + 1
    if rows[-1] and int(starts[-1] + lengths[-1]) == n:  # last line without \n
        sec = np.append(sec, np.uint8(_LF))
    first = np.cumsum(lens) - lens
    for j in range(tag):
        sec[first + j] = _SPACE
    cls = table[sec]
    if not cls.all():
        return None
    ws = cls == _BLANK
    edge = ws[1:] != ws[:-1]  # token starts and ends (sec starts and ends with blanks)
    del ws
    pos = np.flatnonzero(edge)
    del edge
    tok, end = pos[0::2] + 1, pos[1::2]
    per_line = np.diff(np.append(np.searchsorted(tok, first), len(tok)))
    return _Section(sec, cls, tok, end, per_line)


def _fromstring(buf, dtype: type) -> np.ndarray | None:
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            return np.fromstring(buf, dtype=dtype, sep=" ")
    except (ValueError, DeprecationWarning):
        return None


def _floats(a, starts, lengths, rows, tag: int) -> np.ndarray | None:
    """The records ``rows`` as an (k, c) float array; None unless each has the same c >= 1
    tokens, each one decimal number."""
    s = _section(a, starts, lengths, rows, tag, _FLOAT_CHARS)
    if s is None:
        return None
    c = int(s.per_line[0])
    if c == 0 or np.any(s.per_line != c):
        return None
    vals = _decimals(s)
    return None if vals is None else vals.reshape(len(s.per_line), c)


def _one_each(owner: np.ndarray) -> bool:
    """Whether the sorted token indices ``owner`` hold no token twice."""
    return owner.size < 2 or bool(np.all(owner[1:] != owner[:-1]))


def _decimals(s: _Section) -> np.ndarray | None:
    """Each token of ``s`` as a float, or None when one is no decimal number
    ``[+-]?(d+.?d*|.d+)([eE][+-]?d+)?``.

    The text is checked by its pairs of neighbouring byte classes plus: a point next to a
    digit, a sign before a point only at a token's start, at most one point and one
    exponent per token, the point before it; then one ``np.fromstring`` converts it all
    (correctly rounded, as Python's ``float``).
    """
    buf, cls, tok, end = s.buf, s.cls, s.tok, s.end
    if not _PAIR_OK[cls[:-1] * np.uint8(6) + cls[1:]].all():
        return None
    points = np.flatnonzero(cls == _POINT)
    if points.size:
        near = (cls[points - 1] == _DIGIT) | (cls[points + 1] == _DIGIT)
        signed = cls[points - 1] == _SIGN  # "-.5": the sign must start the token
        if not near.all() or np.any(signed & (cls[np.maximum(points - 2, 0)] != _BLANK)):
            return None
    exps = np.flatnonzero(cls == _EXP)
    p_tok = np.searchsorted(tok, points, side="right") - 1
    e_tok = np.searchsorted(tok, exps, side="right") - 1
    if not (_one_each(p_tok) and _one_each(e_tok)):
        return None
    mant_end = end.copy()  # the mantissa's last byte
    mant_end[e_tok] = exps - 1
    if np.any(points > mant_end[p_tok]):
        return None
    vals = _fromstring(buf, np.float64)
    return vals if vals is not None and vals.size == len(tok) else None


def _corners(a, starts, lengths, rows):
    """The ``f`` records' corners: ``(nums, corners_per, slashes)`` or None."""
    s = _section(a, starts, lengths, rows, 1, _INDEX_CHARS)
    if s is None or np.any(s.per_line < 3):
        return None
    sec, tok = s.buf, s.tok
    minus = np.flatnonzero(s.cls == _SIGN)
    if minus.size:  # a sign only at a field's start, before a digit: one number per field
        before, after = sec[minus - 1], sec[minus + 1]  # sec ends with \n: minus + 1 exists
        if np.any((before != _SPACE) & (before != _TAB) & (before != _SLASH)):
            return None
        if np.any((after < ord("0")) | (after > ord("9"))):
            return None
    slash = np.flatnonzero(s.cls == _POINT)
    k = int(np.count_nonzero(slash <= s.end[0]))
    if k > 2 or len(slash) != k * len(tok):
        return None
    if k:  # slashes k*i .. k*i+k-1 lie in corner i: every corner has k
        sl = slash.reshape(-1, k)
        if np.any(sl[:, 0] < tok) or np.any(sl[:, -1] > s.end):
            return None
    if k and np.any(sec[slash + 1] == _SLASH):  # v//vn: read as v/0/vn
        text = sec.tobytes().replace(b"//", b"/0/").replace(b"/", b" ")
    else:
        sec[slash] = _SPACE
        text = sec
    vals = _fromstring(text, np.int64)
    if vals is None or vals.size != tok.size * (k + 1):
        return None
    if vals.size and (int(vals.max()) > _INDEX_MAX or int(vals.min()) < -_INDEX_MAX):
        return None
    return vals.reshape(-1, k + 1), s.per_line.astype(np.int64), k


def _kinds(a: np.ndarray, starts: np.ndarray, lengths: np.ndarray) -> tuple[np.ndarray, ...]:
    """Masks of the ``v``, ``vt``, ``f`` and ``g``/``o`` lines."""
    n = len(a)

    def at(off: int) -> np.ndarray:
        return np.where(lengths > off, a[np.minimum(starts + off, n - 1)], 0)

    c0, c1, c2 = at(0), at(1), at(2)
    blank1 = (c1 == _SPACE) | (c1 == _TAB)
    v = (c0 == ord("v")) & blank1
    vt = (c0 == ord("v")) & (c1 == ord("t")) & ((c2 == _SPACE) | (c2 == _TAB))
    f = (c0 == ord("f")) & blank1
    g = ((c0 == ord("g")) | (c0 == ord("o"))) & ((lengths == 1) | blank1 | (c1 == _CR))
    return v, vt, f, g


def _bare_records(a: np.ndarray, starts: np.ndarray, lengths: np.ndarray) -> bool:
    """Whether a line is a bare ``v``, ``vt`` or ``f`` (a record of no values, for the
    record parser to name: skipped, it would shift every later index)."""
    n = len(a)

    def at(off: int) -> np.ndarray:
        return np.where(lengths > off, a[np.minimum(starts + off, n - 1)], 0)

    c0, c1 = at(0), at(1)
    cr = c1 == _CR
    v_or_f = ((c0 == ord("v")) | (c0 == ord("f"))) & ((lengths == 1) | (cr & (lengths == 2)))
    vt = (c0 == ord("v")) & (c1 == ord("t"))
    vt &= (lengths == 2) | ((at(2) == _CR) & (lengths == 3))
    return bool(v_or_f.any() or vt.any())


def scan(raw: bytes, ends: np.ndarray) -> Scan | None:
    """Scan a well-formed OBJ in bulk, or return None (see the module's docstring).

    Parameters
    ----------
    raw : bytes
        The file (BOM removed, line ends ``\\n`` or ``\\r\\n``).
    ends : (L-1,) int array
        Positions of the ``\\n`` bytes.

    Returns
    -------
    Scan or None
    """
    n = len(raw)
    if not n or b"\x0b" in raw or b"\x0c" in raw:
        return None
    if b"\r" in raw and raw.count(b"\r") != raw.count(b"\r\n"):
        return None
    a = np.frombuffer(raw, dtype=np.uint8)
    starts = np.concatenate([[0], ends + 1])
    lengths = np.concatenate([ends, [n]]) - starts
    vrows, vtrows, frows, grows = _kinds(a, starts, lengths)
    if not vrows.any() or not frows.any() or _bare_records(a, starts, lengths):
        return None
    v = _floats(a, starts, lengths, vrows, 1)
    if v is None:
        return None
    vt = _floats(a, starts, lengths, vtrows, 2) if vtrows.any() else None
    if vtrows.any() and vt is None:
        return None
    corners = _corners(a, starts, lengths, frows)
    if corners is None:
        return None
    gl = np.flatnonzero(grows)
    names = [
        raw[s + 1 : s + k].decode("utf-8", errors="replace").strip()
        for s, k in zip(starts[gl].tolist(), lengths[gl].tolist(), strict=True)
    ]
    face_line_group = np.searchsorted(gl, np.flatnonzero(frows)) - 1
    return Scan(v, vt, *corners, face_line_group, names)
