"""Fuzzing campaign for the OBJ reader (issue 12): N seeded mutants, outside pytest.

Each case mutates a small generated garment OBJ (a lantern sleeve of 96 triangles, as
``ptailor.formats.obj.write_garment`` writes it) with one to three mutations (numbers
replaced by extremes, lines dropped / duplicated / swapped / moved, tokens truncated,
random bytes, a BOM, CRLF or CR line ends, long names, duplicated faces, unreferenced
records) and runs ``ptailor adjust FILE RECIPE -o OUT`` (every format) and
``ptailor inspect FILE`` in process through click's CliRunner, in a forked child with a time
limit. Counted: exit codes, tracebacks (by signature: exception type and innermost ptailor
frame), hangs, exit-2 messages that are not one line naming the file, output left behind on
exit 2, NaN/inf text written on exit 0.

    python bench/fuzz_obj.py --cases 4000 --seed 1 [--timeout 30] [--json out.json]

The mutator (:func:`mutate`) is shared with ``tests/test_fuzz_obj.py``.
"""

from __future__ import annotations

import argparse
import json
import os
import random
import re
import signal
import sys
import tempfile
import time
import traceback
from collections import Counter
from functools import partial
from pathlib import Path

RECIPE = "steps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.2}]\n"

EXTREMES = [
    "nan", "NaN", "-nan", "inf", "-inf", "Infinity", "1e300", "-1e300", "1e308", "1.8e308",
    "5e-324", "1e-300", "-0", "-0.0", "0", "1e6", "1000001", "99999999999999999999",
    "-99999999999999999999", "9223372036854775807", "-9223372036854775808",
    "9223372036854775808", "2147483648", "-1", "-2", "1.5", "", "x", "1e", "0x10", "1,5",
    "--1", "1" * 400,
]  # fmt: skip
RECORDS = [
    "v nan nan nan", "v 1e300 0 0", "v 0 0", "v 1", "v", "vt 0.5", "vt", "vt nan 0",
    "vn 0 0 1", "f 1", "f 1 2", "f 1/1/1/1 2/2 3/3", "f 1//1 2//2 3//3", "f 0 0 0",
    "f 1/1 2/2 3/3", "f -1/-1 -2/-2 -3/-3", "g", "o", "g " + "n" * 300, "o \u00e9\u00e8",
    "s off", "usemtl x", "mtllib a.mtl", "l 1 2", "p 1", "#", "\\", "f 1/1 1/1 1/1",
]  # fmt: skip
_NUM = re.compile(rb"-?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def base_obj() -> bytes:
    """The unmutated sample: a small lantern sleeve (two panels) in cm."""
    from ptailor.formats.obj import write_garment
    from ptailor.samples import lantern_sleeve

    g = lantern_sleeve(n_around=8, n_sleeve=4, n_cuff=2)
    with tempfile.TemporaryDirectory() as td:
        p = Path(td) / "s.obj"
        write_garment(p, g, header=["ptailor fuzz sample", "units: cm"])
        return p.read_bytes()


def _replace_number(lines: list[bytes], rng: random.Random) -> None:
    i = rng.randrange(len(lines))
    nums = list(_NUM.finditer(lines[i]))
    if not nums:
        return
    m = rng.choice(nums)
    lines[i] = lines[i][: m.start()] + rng.choice(EXTREMES).encode() + lines[i][m.end() :]


# The mutations: each takes the lines, two line indices drawn for it (``i``, ``j``) and the
# random source, and returns the mutated lines (the list may be changed in place).


def _number_to_extreme(lines: list[bytes], i: int, j: int, rng: random.Random) -> list[bytes]:
    _replace_number(lines, rng)
    return lines


def _drop_line(lines: list[bytes], i: int, j: int, rng: random.Random) -> list[bytes]:
    del lines[i]
    return lines


def _duplicate_line(lines: list[bytes], i: int, j: int, rng: random.Random) -> list[bytes]:
    lines.insert(i, lines[j])
    return lines


def _swap_lines(lines: list[bytes], i: int, j: int, rng: random.Random) -> list[bytes]:
    lines[i], lines[j] = lines[j], lines[i]
    return lines


def _line_to_start(lines: list[bytes], i: int, j: int, rng: random.Random) -> list[bytes]:
    """A record moved to the start (vt before the v, f before the vt ...)."""
    lines.insert(0, lines.pop(i))
    return lines


def _truncate_line(lines: list[bytes], i: int, j: int, rng: random.Random) -> list[bytes]:
    lines[i] = lines[i][: rng.randrange(len(lines[i]) + 1)]
    return lines


def _random_bytes(lines: list[bytes], i: int, j: int, rng: random.Random) -> list[bytes]:
    """Random bytes inside a line."""
    k = rng.randrange(len(lines[i]) + 1)
    junk = bytes(rng.randrange(256) for _ in range(rng.randint(1, 8)))
    lines[i] = lines[i][:k] + junk + lines[i][k:]
    return lines


def _bom(lines: list[bytes], i: int, j: int, rng: random.Random) -> list[bytes]:
    lines[0] = b"\xef\xbb\xbf" + lines[0]
    return lines


def _old_line_ends(lines: list[bytes], i: int, j: int, rng: random.Random) -> list[bytes]:
    """CRLF line ends (70%) or CR alone."""
    return [ln + b"\r" for ln in lines] if rng.random() < 0.7 else [b"\r".join(lines)]


def _long_group_name(lines: list[bytes], i: int, j: int, rng: random.Random) -> list[bytes]:
    size = rng.choice([50, 201, 5000, 70_000])
    lines.insert(i, b"g " + b"N" * size)
    return lines


def _duplicate_faces(lines: list[bytes], i: int, j: int, rng: random.Random) -> list[bytes]:
    """Duplicated faces: one or all."""
    faces = [ln for ln in lines if ln.startswith(b"f ")]
    if faces:
        lines += faces if rng.random() < 0.5 else [rng.choice(faces)]
    return lines


def _extra_record(lines: list[bytes], i: int, j: int, rng: random.Random) -> list[bytes]:
    """An extra record anywhere."""
    lines.insert(i, rng.choice(RECORDS).encode())
    return lines


def _extreme_in_every_record(lines: list[bytes], i: int, j: int, rng: random.Random) -> list[bytes]:
    """A number in every record of one kind becomes one extreme."""
    tag = rng.choice([b"v ", b"vt ", b"f "])
    x = rng.choice(EXTREMES).encode()
    k = rng.randrange(1, 4)
    return [
        b" ".join([*ln.split(b" ")[:k], x, *ln.split(b" ")[k + 1 :]]) if ln.startswith(tag) else ln
        for ln in lines
    ]


def _drop_run(lines: list[bytes], i: int, j: int, rng: random.Random) -> list[bytes]:
    """Drop a run of lines."""
    del lines[i : i + rng.randint(2, 40)]
    return lines


def _drop_value(lines: list[bytes], i: int, j: int, rng: random.Random) -> list[bytes]:
    """Drop the last value of a 'v' or 'vt' record (a drape without z: issue 22)."""
    rows = [k for k, ln in enumerate(lines) if ln.startswith((b"v ", b"vt "))]
    if rows:
        k = rows[i % len(rows)]
        lines[k] = b" ".join(lines[k].split()[:-1])
    return lines


_SHORT = re.compile(rb"^(?:v(?:[ \t]+\S+){0,2}|vt(?:[ \t]+\S+)?)[ \t]*\r?$", re.M)


def short_record(data: bytes) -> bool:
    """The file holds a 'v' with fewer than 3 values or a 'vt' with fewer than 2."""
    return _SHORT.search(data) is not None


#: mutation by the number drawn for it (``rng.randrange(17)``); the commonest, three
#: numbers of seventeen: a number becomes an extreme
MUTATIONS = (
    _number_to_extreme,
    _number_to_extreme,
    _number_to_extreme,
    _drop_line,
    _duplicate_line,
    _swap_lines,
    _line_to_start,
    _truncate_line,
    _random_bytes,
    _bom,
    _old_line_ends,
    _long_group_name,
    _duplicate_faces,
    _extra_record,
    _extreme_in_every_record,
    _drop_run,
    _drop_value,
)


def mutate(data: bytes, rng: random.Random) -> bytes:
    """One to three random mutations of an OBJ's bytes (deterministic given ``rng``)."""
    lines = data.split(b"\n")
    for _ in range(rng.randint(1, 3)):
        op = rng.randrange(len(MUTATIONS))
        if not lines:
            lines = [b""]
        n = len(lines)
        i, j = rng.randrange(n), rng.randrange(n)
        lines = MUTATIONS[op](lines, i, j, rng)
    return b"\n".join(lines)


_NONFINITE = re.compile(r"(?i)\bnan\b|\binf(inity)?\b")


def nonfinite_written(out: Path) -> list[str]:
    """Output files holding NaN or infinity as text."""
    bad = []
    for name in ("garment.obj", "report.json", "pattern.svg"):
        f = out / name
        if f.exists() and _NONFINITE.search(f.read_text(errors="replace")):
            bad.append(name)
    return bad


def signature(exc: BaseException) -> str:
    """Exception type and the innermost ptailor frame (file:line function)."""
    frames = traceback.extract_tb(exc.__traceback__)
    own = [f for f in frames if "ptailor" in f.filename] or frames
    f = own[-1] if own else None
    where = f"{Path(f.filename).name}:{f.lineno} {f.name}" if f else "?"
    return f"{type(exc).__name__} at {where}: {str(exc)[:80]}"


def check_case(data: bytes, work: Path, *, inspect: bool = True) -> list[tuple[str, str]]:
    """Run ``adjust`` (and ``inspect``) on one mutant in process; the contract's breaches.

    Returns
    -------
    list of (kind, detail)
        kind is ``exit0``/``exit2`` (outcomes, not breaches) or ``traceback``,
        ``left_output``, ``message``, ``nonfinite``.
    """
    from click.testing import CliRunner

    from ptailor.cli.main import cli

    src = work / "m.obj"
    src.write_bytes(data)
    recipe = work / "r.yaml"
    recipe.write_text(RECIPE)
    out = work / "out"
    results = []
    runs = [["adjust", str(src), str(recipe), "-o", str(out), "--formats", "obj,dxf,svg,png"]]
    if inspect:
        runs.append(["inspect", str(src)])
    for args in runs:
        r = CliRunner().invoke(cli, args)
        cmd = args[0]
        if r.exit_code not in (0, 2):
            exc = r.exception
            results.append(("traceback", f"{cmd}: " + (signature(exc) if exc else "?")))
            continue
        results.append((f"exit{r.exit_code}", cmd))
        if r.exit_code == 2:
            lines = [ln for ln in r.output.splitlines() if ln.strip()]
            if len(lines) != 1 or str(src) not in lines[0]:
                results.append(("message", f"{cmd}: {r.output.strip()[:160]!r}"))
            if cmd == "adjust" and out.exists():
                results.append(("left_output", cmd))
        elif cmd == "adjust":
            bad = nonfinite_written(out)
            if bad:
                results.append(("nonfinite", ",".join(bad)))
            if short_record(data):  # a wrong garment, exit 0: cut to the shortest record
                results.append(("wrong", "a short 'v' or 'vt' record was accepted"))
    return results


def run_forked(check, timeout: float) -> tuple[list, float]:
    """``check(work)`` (a fresh temporary folder; it returns the breaches as ``(kind,
    detail)`` pairs) in a forked child, killed as a hang after ``timeout`` seconds; the
    breaches and the seconds taken. Shared by the other fuzzers (``fuzz_body.py``)."""
    rfd, wfd = os.pipe()
    t0 = time.perf_counter()
    pid = os.fork()
    if pid == 0:  # child
        os.close(rfd)
        code = 0
        try:
            with tempfile.TemporaryDirectory() as td:
                res = check(Path(td))
            os.write(wfd, json.dumps(res).encode())
        except BaseException as exc:  # reported to the parent
            os.write(wfd, json.dumps([["traceback", "harness: " + signature(exc)]]).encode())
            code = 1
        finally:
            os.close(wfd)
            os._exit(code)
    os.close(wfd)
    deadline = t0 + timeout
    while True:
        done, _ = os.waitpid(pid, os.WNOHANG)
        if done:
            break
        if time.perf_counter() > deadline:
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
            os.close(rfd)
            return [["hang", f"> {timeout:g} s"]], time.perf_counter() - t0
        time.sleep(0.005)
    chunks = []
    while chunk := os.read(rfd, 1 << 16):
        chunks.append(chunk)
    os.close(rfd)
    try:
        res = json.loads(b"".join(chunks) or b"[]")
    except ValueError:
        res = [["traceback", "harness: child died without a result"]]
    return res, time.perf_counter() - t0


def _run_forked(data: bytes, timeout: float) -> tuple[list, float]:
    """check_case of one mutant in a forked child (:func:`run_forked`)."""
    return run_forked(partial(check_case, data), timeout)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", type=int, default=4000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=30.0, help="per case, seconds")
    ap.add_argument("--json", type=Path, default=None, help="write the counts here")
    ap.add_argument("--keep", type=Path, default=None, help="save breaching mutants here")
    args = ap.parse_args(argv)

    base = base_obj()
    with tempfile.TemporaryDirectory() as td:  # every lazy import once, before the forks
        check_case(base, Path(td))
    outcomes: Counter = Counter()
    breaches: Counter = Counter()
    examples: dict[str, int] = {}
    slowest = 0.0
    t_start = time.perf_counter()
    for case in range(args.cases):
        data = mutate(base, random.Random(args.seed * 1_000_003 + case))
        res, dt = _run_forked(data, args.timeout)
        slowest = max(slowest, dt)
        for kind, detail in res:
            if kind.startswith("exit"):
                outcomes[f"{detail} {kind}"] += 1
            else:
                key = f"{kind}: {detail}"
                breaches[key] += 1
                examples.setdefault(key, case)
                if args.keep:
                    args.keep.mkdir(parents=True, exist_ok=True)
                    (args.keep / f"case{case}.obj").write_bytes(data)
        if (case + 1) % 250 == 0:
            print(f"  {case + 1} cases, {sum(breaches.values())} breaches", file=sys.stderr)
    total = time.perf_counter() - t_start
    kinds = Counter(k.split(":")[0] for k in breaches.elements())
    summary = {
        "cases": args.cases,
        "seed": args.seed,
        "timeout_s": args.timeout,
        "seconds": round(total, 1),
        "slowest_case_s": round(slowest, 2),
        "outcomes": dict(sorted(outcomes.items())),
        "tracebacks": kinds.get("traceback", 0),
        "hangs": kinds.get("hang", 0),
        "nonfinite_written": kinds.get("nonfinite", 0),
        "left_output": kinds.get("left_output", 0),
        "bad_messages": kinds.get("message", 0),
        "wrong": kinds.get("wrong", 0),
        "breaches": {k: [v, examples[k]] for k, v in breaches.most_common()},
    }
    print(json.dumps(summary, indent=2))
    if args.json:
        args.json.write_text(json.dumps(summary, indent=2))
    return 1 if breaches else 0


if __name__ == "__main__":
    sys.exit(main())
