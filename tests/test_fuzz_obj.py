"""Property-based fuzzing of the OBJ reader and of ``adjust`` / ``inspect`` on mutated OBJs.

The contract (issue 12): exit 0, or exit 2 with one line naming the file and nothing
written; on exit 0 no NaN or infinity in garment.obj, report.json or pattern.svg. The
mutator is the campaign's (``bench/fuzz_obj.py``), driven by a Hypothesis-controlled
``random.Random``. Seeded and short by default (the ``ci`` profile of ``conftest.py``);
``PTAILOR_FUZZ=long`` runs the long profile.
"""

from __future__ import annotations

import importlib.util
import random
import tempfile
from functools import cache
from pathlib import Path

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from ptailor.errors import PtailorError  # noqa: E402
from ptailor.formats.obj import read_obj  # noqa: E402

_spec = importlib.util.spec_from_file_location(
    "fuzz_obj", Path(__file__).resolve().parents[1] / "bench" / "fuzz_obj.py"
)
fuzz = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(fuzz)


@cache
def base() -> bytes:
    return fuzz.base_obj()


def _mutant(rnd: random.Random) -> bytes:
    return fuzz.mutate(base(), rnd)


@pytest.mark.slow
@settings()
@given(st.randoms(use_true_random=False))
def test_reader_fails_closed(rnd):
    """read_obj gives finite, in-range arrays or a PtailorError naming the file."""
    data = _mutant(rnd)
    with tempfile.TemporaryDirectory() as td:
        p = Path(td) / "m.obj"
        p.write_bytes(data)
        try:
            m = read_obj(p)
        except PtailorError as exc:
            assert str(p) in str(exc) and "\n" not in str(exc)
            return
    assert np.all(np.isfinite(m.v)) and np.all(np.isfinite(m.vt))
    assert m.fv.min() >= 0 and m.fv.max() < len(m.v)
    if m.fvt is not None:
        assert m.fvt.min() >= 0 and m.fvt.max() < len(m.vt)
    assert len(m.face_group) == len(m.fv)
    assert all(len(n) <= 200 for n in m.group_names)


@pytest.mark.slow
@settings()
@given(st.randoms(use_true_random=False))
def test_adjust_and_inspect_keep_the_contract(rnd):
    data = _mutant(rnd)
    with tempfile.TemporaryDirectory() as td:
        res = fuzz.check_case(data, Path(td))
    breaches = [r for r in res if not r[0].startswith("exit")]
    assert not breaches, breaches


@pytest.mark.slow
@settings()
@given(
    st.sampled_from(["v", "vt", "f"]),
    st.sampled_from(fuzz.EXTREMES),
    st.integers(min_value=1, max_value=3),
)
def test_one_extreme_everywhere(tag, value, column):
    """Every record of one kind gets the same extreme in one column."""
    lines = base().split(b"\n")
    t = tag.encode() + b" "

    def sub(ln: bytes) -> bytes:
        parts = ln.split(b" ")
        if not ln.startswith(t) or len(parts) <= column:
            return ln
        parts[column] = value.encode()
        return b" ".join(parts)

    data = b"\n".join(sub(ln) for ln in lines)
    with tempfile.TemporaryDirectory() as td:
        res = fuzz.check_case(data, Path(td), inspect=False)
    breaches = [r for r in res if not r[0].startswith("exit")]
    assert not breaches, breaches


def test_base_sample_adjusts():
    with tempfile.TemporaryDirectory() as td:
        res = fuzz.check_case(base(), Path(td))
    assert res == [("exit0", "adjust"), ("exit0", "inspect")]


@settings()
@given(st.randoms(use_true_random=False), st.sampled_from([b"v", b"vt"]))
def test_a_short_record_anywhere_is_refused_naming_it(rnd, tag):
    """Issue 22: one ``v`` without z cut every record to its length (the whole drape lost
    z, exit 0). Any one ``v`` or ``vt`` record short of a value is a PtailorError naming
    the record."""
    lines = base().split(b"\n")
    rows = [k for k, ln in enumerate(lines) if ln.startswith(tag + b" ")]
    k = rows[rnd.randrange(len(rows))]
    lines[k] = b" ".join(lines[k].split()[: rnd.randint(1, 2 if tag == b"v" else 1)])
    with tempfile.TemporaryDirectory() as td:
        p = Path(td) / "m.obj"
        p.write_bytes(b"\n".join(lines))
        with pytest.raises(PtailorError, match=rf"'{tag.decode()}' record {rows.index(k) + 1} has"):
            read_obj(p)
