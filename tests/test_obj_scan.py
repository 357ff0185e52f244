"""The OBJ reader's bulk scan (formats/obj_scan.py) against its record-by-record parser.

Whatever the scan accepts must give the arrays the record parser gives, bit for bit; what
it does not accept falls back to that parser, so every error message stays the same.
"""

from __future__ import annotations

import importlib.util
import random
from pathlib import Path

import numpy as np
import pytest

from ptailor.errors import PtailorError
from ptailor.formats import obj as obj_mod
from ptailor.formats.obj_scan import scan

_spec = importlib.util.spec_from_file_location(
    "fuzz_obj", Path(__file__).resolve().parents[1] / "bench" / "fuzz_obj.py"
)
fuzz = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(fuzz)
base_obj, mutate = fuzz.base_obj, fuzz.mutate

QUAD = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 2 0.1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt .5 2\n"


def _outcome(fn, raw: bytes):
    try:
        return fn(raw)
    except PtailorError as exc:
        return ("error", exc.message)


def _old(raw: bytes):
    """The record-by-record parser alone."""
    text, _ = obj_mod._check_text(raw, "m.obj")
    return obj_mod._parse_records(text, "m.obj", obj_mod._header(text))


def _both(raw: bytes):
    """(record parser's outcome, reader's outcome, whether the scan took the file)."""
    with np.errstate(all="ignore"):
        old = _outcome(_old, raw)
        new = _outcome(lambda r: obj_mod._parse(r, "m.obj"), raw)
    try:
        text, ends = obj_mod._check_text(raw, "m.obj")
        fast = scan(text, ends) is not None
    except PtailorError:
        fast = False
    return old, new, fast


def _same(a, b) -> bool:
    if isinstance(a, tuple) or isinstance(b, tuple):
        return a == b
    for name in ("v", "vt", "fv", "fvt", "face_group"):
        x, y = getattr(a, name), getattr(b, name)
        if (x is None) != (y is None):
            return False
        if x is not None and (x.dtype != y.dtype or x.shape != y.shape):
            return False
        if x is not None and x.tobytes() != y.tobytes():  # bit for bit: signed zeros too
            return False
    return a.group_names == b.group_names and a.header == b.header


CASES = {
    "sample": base_obj(),
    "crlf": base_obj().replace(b"\n", b"\r\n"),
    "no final newline": base_obj().rstrip(b"\n"),
    "tabs": base_obj().replace(b" ", b"\t"),
    "usemtl and o": base_obj().replace(b"\ng ", b"\nusemtl m\no "),
    "quads and groups": QUAD + b"g a\nf 1/1 2/2 3/3 4/4\ng b\nf 3/3 5/5 4/4\n",
    "v only corners": QUAD + b"f 1 2 3 4\nf 3 5 4\n",
    "v//vn": QUAD + b"vn 0 0 1\nf 1//1 2//1 3//1\n",
    "v/vt/vn": QUAD + b"vn 0 0 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\n",
    "negative": QUAD + b"f -5/-5 -4/-4 -3/-3\n",
    "empty group names": QUAD + b"o\nf 1/1 2/2 3/3\ng   \nf 3/3 4/4 1/1\n",
    "utf-8 names": QUAD + b"g \xc3\xa9 \nf 1/1 2/2 3/3\ng x\xffy\nf 1/1 2/2 3/3\n",
    "faces first": b"f 1/1 2/2 3/3\n" + QUAD,
    "number forms": QUAD.replace(b"v 1 1 0", b"v 1. .1 -0") + b"f 1 2 3\n",
    "exponents": QUAD.replace(b"v 1 1 0", b"v 1E+02 -2.5e-3 +7e0") + b"f 1 2 3\n",
    "long digits": QUAD.replace(b"v 1 1 0", b"v 0.1234567890123456789 1e-30 3") + b"f 1 2 3\n",
    "overflow": QUAD.replace(b"v 1 1 0", b"v 1e-400 1e400 -0.0") + b"f 1 2 3\n",
    "underscore": QUAD.replace(b"v 1 1 0", b"v 1_0 1 0") + b"f 1 2 3\n",
    "nan": QUAD.replace(b"v 1 1 0", b"v nan 1 0") + b"f 1 2 3\n",
    "ragged v": QUAD.replace(b"v 1 1 0", b"v 1 1 0 1") + b"f 1 2 3\n",
    "comment after": QUAD + b"f 1/1 2/2 3/3 # c\n",
    "lone minus": QUAD + b"f 1/1 2/2 3/-\n",
    "sign inside": QUAD + b"f 1-2/1 2/2 3/3 /4\n",
    "plus index": QUAD + b"f 1/+1 2/2 3/3\n",
    "trailing slash": QUAD + b"f 1/1/ 2/2/ 3/3/\n",
    "mixed slashes": QUAD + b"f 1/2/3 4 5/6\n",
    "huge index": QUAD + b"f 99999999999999999999 2 3\n",
    "two corners": QUAD + b"f 1 2 3\nf 4 5\n",
    "lone cr": QUAD + b"g a\rb\nf 1/1 2/2 3/3\n",
}


@pytest.mark.parametrize("name", list(CASES))
def test_scan_matches_record_parser(name):
    old, new, _ = _both(CASES[name])
    assert _same(old, new), (old, new)


def test_scan_takes_well_formed_files_and_leaves_the_rest():
    for name in ("sample", "crlf", "quads and groups", "v//vn", "negative", "exponents"):
        assert _both(CASES[name])[2], name
    for name in ("nan", "underscore", "ragged v", "lone minus", "sign inside", "lone cr"):
        assert not _both(CASES[name])[2], name


def test_scan_reads_numbers_as_float_does():
    rng = random.Random(3)
    toks = []
    for _ in range(3000):
        k = rng.randrange(4)
        x = rng.uniform(-1, 1) * 10 ** rng.uniform(-30, 30)
        toks.append(format(x, (".9g", ".17g", ".6f", ".18e")[k]))
    lines = [" ".join(["v", *toks[i : i + 3]]) for i in range(0, len(toks), 3)]
    raw = ("\n".join(lines) + "\nf 1 2 3\n").encode()
    ends = np.flatnonzero(np.frombuffer(raw, dtype=np.uint8) == 10)
    got = scan(raw, ends)
    assert got is not None
    assert got.v.ravel().tobytes() == np.array([float(t) for t in toks]).tobytes()


@pytest.mark.slow
def test_scan_matches_record_parser_on_mutants():
    base = base_obj()
    taken = 0
    for case in range(1500):
        raw = mutate(base, random.Random(7 * 1_000_003 + case))
        old, new, fast = _both(raw)
        assert _same(old, new), (case, old, new)
        taken += fast
    assert taken > 500  # the mutants the scan reads itself
