"""Golden outputs: each case of tests/golden/cases.py run again and compared, file by file,
with what tests/golden/CASE.npz holds (tolerances in tests/golden/compare.py).

Refresh on purpose, after a change meant to move results, with
``python -m pytest tests/test_golden.py --refresh-golden`` and say why in the commit.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from tests.conftest import GARMENTS, ROOT
from tests.golden.cases import CASES, RECIPES, Case
from tests.golden.compare import differences, store

HERE = Path(__file__).resolve().parent / "golden"
#: the DXF's creation date of every golden output: 2026-12-02, the day they were written
#: (without it the date of the day is written: the outputs changed at midnight)
SOURCE_DATE_EPOCH = "1796169600"


def _garment(case: Case, tmp: Path) -> tuple[Path, tuple[str, ...]]:
    """The case's garment file (and the options it needs), made or found."""
    from ptailor.cli.main import cli
    from ptailor.samples.obj_text import sample_obj_text

    kind, _, what = case.garment.partition(":")
    if kind == "shared":
        p = GARMENTS / what
        if not p.is_file():
            pytest.skip(f"{p} not available (../shared is absent)")
        return p, ()
    sample = tmp / f"{what}.obj"
    sample.write_text(sample_obj_text(what))
    if kind == "sample":
        return sample, ()
    assert kind == "dxf-of", case.garment
    first = tmp / "identity"
    r = CliRunner().invoke(
        cli, ["adjust", str(sample), str(RECIPES / "identity.yaml"), "-o", str(first)]
    )
    assert r.exit_code == 0, r.output
    return first / "pattern.dxf", ("--drape", str(sample))


#: the real garments' runs take seconds each: slow; so are three generated ones whose edits
#: the quick loop's own tests cover (a seam line's scale, an extend, the identity: 0.6-0.9 s
#: each); the demo, the DXF input, the cut and the loosen stay in the quick loop
SLOW_GENERATED = frozenset({"skirt-fuller", "bodice-lengthen", "cylinder-identity"})
_PARAMS = [
    pytest.param(
        c,
        id=c.name,
        marks=[pytest.mark.slow]
        if c.garment.startswith("shared:") or c.name in SLOW_GENERATED
        else [],
    )
    for c in CASES
]


@pytest.mark.parametrize("case", _PARAMS)
def test_golden(
    case: Case, tmp_path: Path, request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch
) -> None:
    from ptailor.cli.main import cli

    monkeypatch.setenv("SOURCE_DATE_EPOCH", SOURCE_DATE_EPOCH)
    garment, extra = _garment(case, tmp_path)
    out = tmp_path / "out"
    args = ["adjust", str(garment), str(RECIPES / case.recipe), "-o", str(out), *extra]
    args += [a.replace("{SHARED}", str(GARMENTS)) for a in case.args]
    r = CliRunner().invoke(cli, args)
    assert r.exit_code == 0, r.output
    places = {"RUN": tmp_path, "SHARED": GARMENTS, "ROOT": ROOT}
    path = HERE / f"{case.name}.npz"
    if request.config.getoption("--refresh-golden"):
        np.savez_compressed(path, **store(out, places))
        return
    assert path.is_file(), f"no golden expectation {path.name}: run with --refresh-golden"
    with np.load(path) as expected:
        problems = differences(out, places, dict(expected))
    assert not problems, "\n".join(problems)
