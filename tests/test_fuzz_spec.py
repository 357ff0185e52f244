"""Property-based fuzzing of specification JSON (issue 43): read and matched to its garment.

The contract: a mutated specification is read and matched, or refused with a
``PtailorError`` of one line naming the file; never another exception, never a hang. The
mutator is the campaign's (``bench/fuzz_spec.py``), driven by a Hypothesis-controlled
``random.Random``. Seeded and short by default (the ``ci`` profile of ``conftest.py``);
``PTAILOR_FUZZ=long`` runs the long profile.
"""

from __future__ import annotations

import importlib.util
import random
import tempfile
from functools import cache
from pathlib import Path

import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

_spec = importlib.util.spec_from_file_location(
    "fuzz_spec", Path(__file__).resolve().parents[1] / "bench" / "fuzz_spec.py"
)
fuzz = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(fuzz)


@cache
def base():
    return fuzz.base_case(Path(tempfile.mkdtemp()))


@pytest.mark.slow
@settings()
@given(st.randoms(use_true_random=False))
def test_specifications_fail_closed(rnd: random.Random):
    """Read and matched, or a one-line PtailorError naming the file."""
    g, panels, seams, d = base()
    text = fuzz.case_text(d, rnd)
    with tempfile.TemporaryDirectory() as td:
        path = Path(td) / "s_specification.json"
        outcome, detail = fuzz.run_case(text, path, g, panels, seams, timeout=20.0)
    assert outcome in ("ok", "exit2"), (outcome, detail)


@pytest.mark.slow
def test_the_base_specification_matches():
    g, panels, seams, d = base()
    import json

    with tempfile.TemporaryDirectory() as td:
        path = Path(td) / "s_specification.json"
        assert fuzz.run_case(json.dumps(d), path, g, panels, seams, timeout=20.0) == ("ok", None)
