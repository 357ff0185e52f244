"""Property-based fuzzing of ``--body`` meshes (issue 43).

The contract: :func:`ptailor.edits.body.read_body` refuses with one line naming the file, or
returns a body (closed, consistently oriented, outward, enclosing a volume) out of which
:func:`~ptailor.edits.body.push_out` moves points. The mutator is the campaign's
(``bench/fuzz_body.py``), driven by a Hypothesis-controlled ``random.Random``; seeded and
short by default (the ``ci`` profile of ``conftest.py``).
"""

from __future__ import annotations

import importlib.util
import tempfile
from pathlib import Path

import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

_spec = importlib.util.spec_from_file_location(
    "fuzz_body", Path(__file__).resolve().parents[1] / "bench" / "fuzz_body.py"
)
fuzz = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(fuzz)


@pytest.mark.slow
@settings()
@given(st.randoms(use_true_random=False))
def test_a_body_is_refused_clearly_or_is_a_body(rnd):
    data = fuzz.mutate_body(rnd)
    with tempfile.TemporaryDirectory() as td:
        res = fuzz.check_case(data, Path(td))
    assert [r for r in res if r[0] != "exit"] == [], res


def test_the_unmutated_sphere_is_accepted_and_pushes_out(tmp_path):
    assert fuzz.check_case(fuzz.obj_bytes(*fuzz.base_body()), tmp_path) == [("exit", "accepted")]


def test_two_nested_pieces_keep_the_outer_one(tmp_path):
    """An eye inside a head is dropped; two crossing shells are refused."""
    from ptailor.edits.body import read_body
    from ptailor.errors import PtailorError

    V, F = fuzz.base_body()
    p = tmp_path / "nested.obj"
    p.write_bytes(fuzz.obj_bytes(fuzz.np.r_[V, 0.2 * V], fuzz.np.r_[F, F + len(V)]))
    assert len(read_body(str(p), units="cm", to="cm").faces) == len(F)
    p = tmp_path / "crossing.obj"
    p.write_bytes(fuzz.obj_bytes(fuzz.np.r_[V, V + 15.0], fuzz.np.r_[F, F + len(V)]))
    with pytest.raises(PtailorError, match="cross each other"):
        read_body(str(p), units="cm", to="cm")
