"""Property-based fuzzing of the DXF reader (issue 12): mutants of small valid DXF
patterns (ptailor's own ``pattern.dxf`` from ``ptailor demo``, and the shared fixtures when
present) keep the contract of ``ptailor inspect`` and ``ptailor adjust``: exit 0 or exit 2
with one line naming the file, no traceback, nothing written on exit 2, no NaN or inf
written on exit 0.

The Hypothesis profile comes from tests/conftest.py: ``ci`` (seeded, 60 examples per
property) by default, ``PTAILOR_FUZZ=long`` for 2,000. ``bench/fuzz_dxf.py`` runs a longer
campaign outside pytest with time limits per case.
"""

from __future__ import annotations

import importlib.util
import re
import shutil
from pathlib import Path

import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import given  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from ptailor.cli.main import cli  # noqa: E402

from .conftest import SHARED  # noqa: E402

# one mutation vocabulary for these properties and the campaign (bench/fuzz_dxf.py)
_spec = importlib.util.spec_from_file_location(
    "fuzz_dxf", Path(__file__).resolve().parents[1] / "bench" / "fuzz_dxf.py"
)
_bench = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_bench)

EXTREMES = _bench.EXTREMES
ENTITY_NAMES = _bench.ENTITY_NAMES
#: group codes worth hitting with extreme values: coordinates, radius/height, angle,
#: flags, text, layer, name
HOT_CODES = {"10", "20", "11", "21", "40", "41", "42", "50", "66", "70", "1", "8", "2"}

pos = st.floats(0.0, 1.0, exclude_max=True)
value = st.sampled_from(EXTREMES) | st.text(max_size=12)
MUTATION = st.one_of(
    st.tuples(st.just("hot"), pos, value),
    st.tuples(st.just("value"), pos, value),
    st.tuples(st.just("layer"), pos, st.sampled_from(["1", "2", "4", "6", "7", "8", "13", "14"])),
    st.tuples(st.just("drop"), pos, st.integers(1, 40)),
    st.tuples(st.just("dup"), pos, st.integers(1, 40)),
    st.tuples(st.just("swap"), pos, pos),
    st.tuples(st.just("name"), pos, st.sampled_from(ENTITY_NAMES)),
    st.tuples(st.just("trunc"), pos, st.just(0)),
    st.tuples(st.just("bytes"), pos, st.binary(min_size=1, max_size=16)),
)
MUTATIONS = st.lists(MUTATION, min_size=1, max_size=3)


def _set_value_of(lines: list[str], codes: set[str], at: float, arg: str) -> None:
    """Set the value of the pair at fraction ``at`` among those with a group code in ``codes``."""
    idx = [i for i in range(0, len(lines) - 1, 2) if lines[i].strip() in codes]
    if idx:
        lines[idx[int(at * len(idx))] + 1] = arg


def _swap(lines: list[str], pair: int, arg: float) -> None:
    other = int(arg * max(len(lines) // 2, 1)) * 2
    a, b = lines[pair : pair + 2], lines[other : other + 2]
    if len(a) == len(b):
        lines[pair : pair + 2], lines[other : other + 2] = b, a


def _insert_bytes(lines: list[str], at: float, arg: bytes) -> list[str]:
    text = "\n".join(lines)
    k = int(at * (len(text) + 1))
    text = text[:k] + arg.decode("latin-1") + text[k + len(arg) :]
    return text.split("\n")


def _mutate_once(lines: list[str], op: str, at: float, arg) -> list[str]:
    """``lines`` after one mutation (edited in place, or a new list for ``bytes``)."""
    n = len(lines)
    pair = int(at * max(n // 2, 1)) * 2
    if op == "hot":
        _set_value_of(lines, HOT_CODES, at, arg)
    elif op == "value" and pair + 1 < n:
        lines[pair + 1] = arg
    elif op == "layer" and pair + 1 < n:
        _set_value_of(lines, {"8"}, at, arg)
    elif op == "drop":
        del lines[pair : pair + arg]
    elif op == "dup":
        lines[pair:pair] = lines[pair : pair + arg]
    elif op == "swap":
        _swap(lines, pair, arg)
    elif op == "name":
        _set_value_of(lines, {"0"}, at, arg)
    elif op == "trunc":
        del lines[int(at * n) :]
    elif op == "bytes":
        return _insert_bytes(lines, at, arg)
    return lines


def mutate(data: bytes, mutations: list[tuple]) -> bytes:
    """Apply ``MUTATIONS`` to a DXF's bytes (lines: group code, value, ...)."""
    lines = data.decode("latin-1").splitlines()
    for op, at, arg in mutations:
        if not lines:
            break
        lines = _mutate_once(lines, op, at, arg)
    return ("\n".join(lines) + "\n").encode("latin-1", errors="replace")


#: "nan"/"inf" as a number in a written file (not inside a word such as "infinite")
BAD_NUMBER = re.compile(rb"(?i)(?<![a-z_])(nan|inf|infinity)(?![a-z_])")


@pytest.fixture(scope="module")
def demo(tmp_path_factory) -> Path:
    """``ptailor demo``'s folder: pattern.dxf with its drape garment.obj and recipe.yaml."""
    from click.testing import CliRunner

    out = tmp_path_factory.mktemp("fuzz_dxf") / "demo"
    r = CliRunner().invoke(cli, ["demo", str(out)])
    assert r.exit_code == 0, r.output
    return out


def seeds(demo: Path) -> list[Path]:
    found = [demo / "pattern.dxf"]
    for name in ("clo-pattern.dxf", "WM_SLIM_TANK.DXF"):
        p = SHARED / "dxf" / name
        if p.is_file():
            found.append(p)
    return found


def check(args: list[str], path: Path, out: Path | None = None) -> int:
    """Run the CLI; assert the contract; return the exit code."""
    from click.testing import CliRunner

    r = CliRunner().invoke(cli, args)
    if r.exception is not None and not isinstance(r.exception, SystemExit):
        import traceback

        tb = "".join(traceback.format_exception(r.exception))
        raise AssertionError(f"traceback on {args[0]}:\n{tb}")
    assert r.exit_code in (0, 2), (r.exit_code, r.output)
    text = r.output.strip()
    if r.exit_code == 2:
        assert len(text.splitlines()) == 1, text
        assert str(path) in text, text
        if out is not None:
            assert not out.exists(), f"exit 2 left {out} behind"
    elif out is not None:
        for f in out.iterdir():
            if f.suffix in (".obj", ".dxf", ".json", ".svg"):
                m = BAD_NUMBER.search(f.read_bytes())
                assert m is None, f"{f.name} holds {m.group(0)!r}"
    return r.exit_code


@pytest.mark.slow
@given(which=st.integers(0, 2), mutations=MUTATIONS)
def test_inspect_mutated_dxf_fails_closed(demo, tmp_path_factory, which, mutations):
    src = seeds(demo)
    src = src[which % len(src)]
    d = tmp_path_factory.mktemp("m")
    p = d / f"mutant{src.suffix}"
    p.write_bytes(mutate(src.read_bytes(), mutations))
    check(["inspect", str(p)], p)
    shutil.rmtree(d)


@pytest.mark.slow
@given(mutations=MUTATIONS)
def test_adjust_mutated_dxf_fails_closed(demo, tmp_path_factory, mutations):
    d = tmp_path_factory.mktemp("m")
    p = d / "pattern.dxf"
    p.write_bytes(mutate((demo / "pattern.dxf").read_bytes(), mutations))
    out = d / "out"
    args = ["adjust", str(p), str(demo / "recipe.yaml"), "--drape", str(demo / "garment.obj")]
    check([*args, "-o", str(out)], p, out)
    shutil.rmtree(d)


@pytest.mark.slow
def test_mutate_is_deterministic_and_changes_the_file(demo):
    data = (demo / "pattern.dxf").read_bytes()
    muts = [("hot", 0.5, "nan"), ("drop", 0.1, 2)]
    assert mutate(data, muts) == mutate(data, muts) != data


@pytest.mark.slow  # 60 DXF files written and read: 1 s
@given(
    st.one_of(
        st.text(alphabet=st.characters(codec="ascii", exclude_categories=("Cc",)), max_size=12),
        st.integers(-5, 2000).map(str),
        st.floats(allow_nan=True, allow_infinity=True).map(repr),
        st.tuples(st.integers(-3, 9), st.integers(-3, 9)).map(lambda t: f"{t[0]},{t[1]}"),
    )
)
def test_a_quantity_is_a_count_read_once_or_an_error_naming_the_piece(text):
    """Issue 22: ``Quantity:`` values that are not counts were read as 1 and written back
    twice. Whatever the text: a count (the piece's quantity, no note repeating it), or a
    PtailorError naming the piece."""
    import tempfile

    from ptailor.errors import PtailorError
    from ptailor.formats.dxf import parse_quantity, read_dxf
    from tests.test_bad_dxf import square

    with tempfile.TemporaryDirectory() as td:
        p = square(Path(td), quantity=text)
        try:
            (piece,) = read_dxf(p).pieces
        except PtailorError as exc:
            assert "piece 'FRONT'" in str(exc) or "FRONT" in str(exc) or str(p) in str(exc)
            return
    q = parse_quantity(text.strip())
    if text.strip():  # an empty value is no quantity: the default 1
        assert q is not None and piece.quantity == q[0]
    assert not any("QUANTITY" in a.upper() for a in piece.annotations)
