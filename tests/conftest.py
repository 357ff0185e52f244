"""Shared fixtures: generated garments and the real ones in ../shared (skipped when absent)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from ptailor.cli.main import one_blas_thread

# One BLAS thread, as every ptailor command sets before numpy loads (unless the user chose):
# the tests then run the code as the command runs it. A second OpenBLAS thread busy-waits for
# work that rarely comes; on a loaded 2-core machine that made the quick loop's CPU time 6x
# for tests/test_newton.py (38 s against 6 s).
one_blas_thread()

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("PTAILOR_SHARED", ROOT.parent / "shared"))
GARMENTS = SHARED / "garments"

#: real garments: path relative to shared/garments, pattern units
REAL = {
    "tee6": ("gpg_tee6/tee6_sim.obj", "cm"),
    "tshirt": ("diffavatar/tshirt.obj", "auto"),
    "longsleeve": ("diffavatar/longsleeve_initial.obj", "auto"),
    "dress": ("diffavatar/dress_initial.obj", "auto"),
}


def real_path(key: str) -> Path:
    """Path of a shared garment, skipping the test when it is absent."""
    p = GARMENTS / REAL[key][0]
    if not p.is_file():
        pytest.skip(f"{p} not available (../shared is absent)")
    return p


#: why a test that draws the re-drape picture skips on the lean install
PICTURE_NEEDS_MATPLOTLIB = (
    "verify.png is drawn with matplotlib, which only the sim extra installs "
    "(pip install -e '.[test,sim]'); the lean install cannot run the re-drape check at all"
)


def needs_matplotlib() -> None:
    """Skip, saying why, where matplotlib (the sim extra's, for ``verify.png``) is absent."""
    pytest.importorskip("matplotlib", reason=PICTURE_NEEDS_MATPLOTLIB)


@pytest.fixture(params=sorted(REAL))
def real_garment(request):
    """(key, LoadedGarment) for each real garment."""
    from ptailor.formats.garment import load_garment

    p = real_path(request.param)
    return request.param, load_garment(p, pattern_units=REAL[request.param][1])


# The quick loop: `pytest -m "not slow"` takes under 60 s of CPU (user + sys) on 2 cores, on
# the lean install ('.[test]': no cloth engine, no matplotlib; .ci/run runs it so first);
# plain `pytest` (what CI runs) runs everything. A test that takes 0.6 s or more (a parameter
# alone, `pytest --durations=0` on a loaded 2-core machine), or a real garment's (../shared)
# 0.3 s or more, is made cheaper (a smaller mesh, a lower iteration cap for a negative
# control) or else marked `@pytest.mark.slow` where it is defined.


# Property-based fuzzing (Hypothesis): short and seeded in CI, longer on demand:
#   PTAILOR_FUZZ=long python -m pytest tests/test_fuzz_*.py
try:
    from hypothesis import HealthCheck, settings

    _fuzz_common = {
        "deadline": None,
        "derandomize": True,  # seeded: the same cases every run
        "suppress_health_check": [HealthCheck.too_slow, HealthCheck.data_too_large],
        "database": None,
    }
    settings.register_profile("ci", max_examples=60, **_fuzz_common)
    settings.register_profile("long", max_examples=2000, **_fuzz_common)
    settings.load_profile(os.environ.get("PTAILOR_FUZZ", "ci"))
except ImportError:  # hypothesis comes with the test extra
    pass


def pytest_addoption(parser):
    """``--refresh-golden``: rewrite tests/golden/*.npz from this run (tests/test_golden.py)."""
    parser.addoption(
        "--refresh-golden",
        action="store_true",
        help="rewrite the golden expectations of tests/test_golden.py from this run",
    )
