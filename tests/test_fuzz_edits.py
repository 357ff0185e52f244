"""Property-based fuzzing of extreme-edit recipes (issue 12).

The cases come from ``bench/fuzz_edits.py`` (the campaign's generator), drawn here by
Hypothesis: factors from subnormal to 1e300, axes with huge, tiny or zero components,
``by`` from 1e-12 to 1e300, extreme flatten weights and ``max_iter``, regions selecting
nothing or everything, cut planes and sketches anywhere; half of them past the recipe
validator (``raw``), so the edits and the method must hold on their own. The contract:
exit 0 with every written number finite, or a one-line ``PtailorError`` with nothing left
behind, and no RuntimeWarning printed. The ``ci`` profile runs 60 seeded cases;
``PTAILOR_FUZZ=long`` runs 2,000.
"""

from __future__ import annotations

import importlib.util
import warnings
from pathlib import Path

import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import given  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def _load_bench():
    spec = importlib.util.spec_from_file_location("fuzz_edits", ROOT / "bench" / "fuzz_edits.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


fz = _load_bench()


class HypothesisSource:
    """The generator's ``pick``/``unit`` drawn from Hypothesis (so cases shrink)."""

    def __init__(self, data) -> None:
        self.data = data

    def pick(self, seq):
        return self.data.draw(st.sampled_from(list(seq)))

    def unit(self) -> float:
        return self.data.draw(st.floats(0.0, 1.0, allow_nan=False))


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    return fz.garment_files(tmp_path_factory.mktemp("fuzz_edits"))


@pytest.fixture(scope="module")
def work(tmp_path_factory):
    return tmp_path_factory.mktemp("fuzz_edits_out")


@pytest.mark.slow
@given(data=st.data())
def test_extreme_edits_exit_cleanly_and_never_write_nan(files, work, data):
    case = fz.draw_case(HypothesisSource(data))
    formats = data.draw(st.sampled_from([("obj",), ("obj", "dxf"), ("obj", "dxf", "svg", "png")]))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        outcome, detail = fz.run_case(case, files, work, formats=formats)
    assert outcome in ("ok", "exit2"), f"{outcome}: {detail}\n{case}"
    printed = [w for w in caught if issubclass(w.category, RuntimeWarning)]
    assert not printed, f"{printed[0].category.__name__}: {printed[0].message}\n{case}"


def test_generator_is_seeded_and_covers_the_extremes():
    cases = [fz.draw_case(fz.RandomSource(i)) for i in range(300)]
    assert cases == [fz.draw_case(fz.RandomSource(i)) for i in range(300)]
    ops = {s["op"] for c in cases for s in c["steps"]}
    assert ops >= {"scale", "scale_seam", "extend", "shorten", "loosen", "cut"}
    numbers = [
        s.get("factor", s.get("by"))
        for c in cases
        for s in c["steps"]
        if "factor" in s or "by" in s
    ]
    assert min(numbers) < 1e-300 and max(numbers) > 1e300
    assert any(c["raw"] for c in cases) and not all(c["raw"] for c in cases)
