"""Property-based fuzzing of what a catalogue reads back (issue 43): ``catalogue.json``, a
garment's ``report.json`` and ``batch.json``, a ``--log`` and a manifest, mutated.

The contract: ``ptailor report OUT`` (``--log`` for a log) exits 0 with every link of its
pages resolving, or 2 with one line naming the file and OUT unchanged; a manifest is read
or refused with one line naming it; never a traceback, no file a marker lists lost, nothing
outside OUT touched. The mutator and the judge are the campaign's
(``bench/fuzz_catalogue.py``), driven by a Hypothesis-controlled ``random.Random``. Seeded
and short by default (the ``ci`` profile of ``conftest.py``); ``PTAILOR_FUZZ=long`` runs the
long profile.
"""

from __future__ import annotations

import importlib.util
import random
import shutil
import tempfile
from pathlib import Path

import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from ptailor.batch.readback import REPORT_FIELDS, checked  # noqa: E402

_spec = importlib.util.spec_from_file_location(
    "fuzz_catalogue", Path(__file__).resolve().parents[1] / "bench" / "fuzz_catalogue.py"
)
fuzz = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(fuzz)


@pytest.fixture(scope="module")
def pristine(tmp_path_factory) -> Path:
    return fuzz.build(tmp_path_factory.mktemp("fuzzcat") / "site")


def _case(pristine: Path, kind: str, rnd: random.Random) -> list:
    with tempfile.TemporaryDirectory() as td:
        site = Path(td) / "site"
        shutil.copytree(pristine, site, symlinks=True)
        path = fuzz.target(site, kind, rnd)
        text = fuzz.mutate_json(path.read_text(), rnd, lines=kind in ("log", "manifest"))
        return fuzz.check_case(site, kind, text)


@pytest.mark.slow
@pytest.mark.parametrize("kind", fuzz.KINDS)
@settings()
@given(rnd=st.randoms(use_true_random=False))
def test_a_mutated_file_read_back_fails_closed(pristine, kind, rnd):
    breaches = [r for r in _case(pristine, kind, rnd) if not r[0].startswith("exit")]
    assert breaches == []


@pytest.mark.slow
@settings()
@given(rnd=st.randoms(use_true_random=False))
def test_the_checked_report_has_only_the_types_it_promises(rnd):
    """Whatever a report holds, what ``checked`` keeps reads without a type error: the
    record's numbers and a garment page's lists."""
    import json

    from ptailor.batch.records import key_numbers

    base = {
        "panels": [{"name": "front", "area_before": 10.0, "area_after": 11.0,
                    "flipped_triangles": 0, "intrinsic_scale_error": {"p95": 0.1}}],
        "seams": [{"name": "side", "panels": ["front", "back"], "mismatch": 0.1}],
        "warnings": ["w"],
        "steps": [{"op": "scale"}],
        "spec": {"fit_max": 0.2},
    }  # fmt: skip
    text = fuzz.mutate_json(json.dumps(base), rnd)
    try:
        data = json.loads(text)
    except (ValueError, RecursionError):
        return
    report, _ = checked(data, REPORT_FIELDS)
    if report is None:
        assert not isinstance(data, dict)
        return
    numbers = key_numbers(report)
    assert isinstance(numbers["panels"], int) and isinstance(numbers["warnings"], int)
    assert all(isinstance(w, str) for w in report.get("warnings", []))
