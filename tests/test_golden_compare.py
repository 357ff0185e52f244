"""The golden comparison itself: it must fail where outputs moved and hold where they did not."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.golden.compare import differences, store, text_parts


def _folder(tmp: Path, obj: str, report: str) -> Path:
    out = tmp / "out"
    out.mkdir(exist_ok=True)
    (out / "garment.obj").write_text(obj)
    (out / "report.json").write_text(report)
    return out


OBJ = "# ptailor\nv 1.000000 2.5 -3\nvt 0.125 0.250\nf 1/1 2/2 3/3\n"
REPORT = '{"a": 12.345, "timing_s": {"load": 0.5}, "name": "tee6", "path": "/x/y"}'


@pytest.fixture
def expected(tmp_path):
    places = {"RUN": tmp_path}
    return dict(store(_folder(tmp_path, OBJ, REPORT), places)), places


def test_the_same_output_holds(tmp_path, expected):
    want, places = expected
    assert differences(_folder(tmp_path, OBJ, REPORT), places, want) == []


def test_timings_and_paths_do_not_count(tmp_path, expected):
    want, places = expected
    report = '{"a": 12.345, "timing_s": {"load": 9.0}, "name": "tee6", "path": "/elsewhere"}'
    assert differences(_folder(tmp_path, OBJ, report), places, want) == []


def test_a_number_within_tolerance_or_one_last_digit_holds(tmp_path, expected):
    want, places = expected
    obj = OBJ.replace("2.5 ", "2.5000004 ").replace("0.125", "0.126")
    assert differences(_folder(tmp_path, obj, REPORT), places, want) == []


@pytest.mark.parametrize(
    "old, new",
    [("2.5 ", "2.52 "), ("0.125", "0.128"), ("f 1/1 2/2 3/3", "f 1/1 3/3 2/2"), ("v ", "vn ")],
)
def test_a_moved_number_or_changed_text_fails(tmp_path, expected, old, new):
    want, places = expected
    problems = differences(_folder(tmp_path, OBJ.replace(old, new), REPORT), places, want)
    assert len(problems) == 1 and problems[0].startswith("garment.obj: ")


def test_a_changed_report_value_and_a_missing_file_fail(tmp_path, expected):
    want, places = expected
    out = _folder(tmp_path, OBJ, REPORT.replace("12.345", "12.4").replace("tee6", "tee7"))
    assert [p.split(":")[0] for p in differences(out, places, want)] == ["report.json"]
    (out / "garment.obj").unlink()
    assert differences(out, places, want)[0].startswith("files: ")


def test_words_and_hashes_are_text():
    parts = text_parts(
        b"tee6 c298f5df27fa840d83cc20887ce262373f35ce7e42e06d07a355babd8a79350d 1e-05"
    )
    assert parts.skeleton.startswith(b"tee6 c298f5") and parts.skeleton.endswith(b" #")
    np.testing.assert_array_equal(parts.numbers, [1e-05])
