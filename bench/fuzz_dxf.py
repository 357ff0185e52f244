"""Fuzzing campaign for the DXF reader (issue 12): N seeded mutants, outside pytest.

Each case mutates a small valid DXF (ptailor's own ``pattern.dxf`` from ``ptailor demo``,
and ``../shared/dxf/*.dxf`` when present) and runs ``ptailor inspect FILE.dxf`` and, for
mutants of the demo pattern, ``ptailor adjust FILE.dxf RECIPE --drape garment.obj``, each
in a forked child with a time limit. Counted: exit codes, tracebacks (by signature: the
exception type and the innermost ptailor frame), hangs, exit-2 messages that are not one
line naming the file, output left behind on exit 2, NaN/inf text written on exit 0.

    python bench/fuzz_dxf.py --cases 2000 --seed 12 [--timeout 60] [--json out.json]

Seed 12, 2,000 cases (2026-11-30, after the issue-12 reader changes; 1,099 s on 2 shared
cores): exit codes inspect/adjust 0/0 330, 0/2 16, inspect-only 0 273, 2 1,381; no
traceback, no hang (60 s limit), no exit-2 message that was not one line naming the file,
no output left on exit 2, no NaN or inf written.
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
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("PTAILOR_SHARED", ROOT.parent / "shared"))

EXTREMES = [
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e300",
    "-1e300",
    "1e308",
    "1.8e308",
    "5e-324",
    "-0",
    "99999999999999999999",
    "-99999999999999999999",
    "2147483648",
    "",
    " ",
    "x",
    "garbage",
    "1e",
    "0x10",
    "\x00",
    "1,5",
    "--1",
    "100000000",
    "1" * 400,
    "0.0abc",
]
ENTITY_NAMES = [
    "LINE",
    "POLYLINE",
    "LWPOLYLINE",
    "VERTEX",
    "SEQEND",
    "POINT",
    "TEXT",
    "MTEXT",
    "INSERT",
    "BLOCK",
    "ENDBLK",
    "CIRCLE",
    "ARC",
    "SPLINE",
    "ELLIPSE",
    "HATCH",
    "3DFACE",
    "FOO",
    "SECTION",
    "ENDSEC",
    "EOF",
    "",
]


def mutate(data: bytes, rng: random.Random) -> bytes:
    """One to three random mutations of a DXF's bytes."""
    lines = data.decode("latin-1").splitlines()
    for _ in range(rng.randint(1, 3)):
        if not lines:
            break
        op = rng.choice(
            ["value", "value", "value", "drop", "dup", "swap", "name", "trunc", "bytes", "layer"]
        )
        n = len(lines)
        pair = rng.randrange(max(n // 2, 1)) * 2  # the group code line of a pair
        if op == "value" and pair + 1 < n:
            lines[pair + 1] = rng.choice(EXTREMES)
        elif op == "layer" and pair + 1 < n:
            lines[pair + 1] = rng.choice(["1", "2", "4", "6", "7", "8", "13", "14", "15", "99"])
        elif op == "drop":
            k = rng.choice([1, 2, 2, 2 * rng.randint(1, 20)])
            del lines[pair : pair + k]
        elif op == "dup":
            k = 2 * rng.randint(1, 30)
            lines[pair:pair] = lines[pair : pair + k] * rng.randint(1, 3)
        elif op == "swap":
            other = rng.randrange(max(n // 2, 1)) * 2
            a, b = lines[pair : pair + 2], lines[other : other + 2]
            lines[pair : pair + 2], lines[other : other + 2] = b, a
        elif op == "name":
            zeros = [i for i in range(0, n - 1, 2) if lines[i].strip() == "0"]
            if zeros:
                lines[rng.choice(zeros) + 1] = rng.choice(ENTITY_NAMES)
        elif op == "trunc":
            del lines[rng.randrange(n) :]
        elif op == "bytes":
            text = "\n".join(lines)
            at = rng.randrange(len(text) + 1)
            junk = "".join(chr(rng.randrange(256)) for _ in range(rng.randint(1, 16)))
            text = text[:at] + junk + text[at + rng.randint(0, 16) :]
            lines = text.split("\n")
    return ("\n".join(lines) + "\n").encode("latin-1")


_BAD_NUMBER = re.compile(rb"(?i)(?<![a-z])(nan|inf(inity)?)(?![a-z])")


def signature(exc: BaseException) -> str:
    """The exception type and the innermost ptailor frame (file:function)."""
    tb = traceback.extract_tb(exc.__traceback__)
    mine = [f for f in tb if "ptailor" in f.filename]
    where = mine[-1] if mine else (tb[-1] if tb else None)
    loc = f"{Path(where.filename).name}:{where.name}" if where else "?"
    return f"{type(exc).__name__} at {loc}"


def run_case(path: Path, demo: Path | None, out: Path) -> dict:
    """inspect (and adjust with the demo's drape): the contract checks, in this process."""
    from click.testing import CliRunner

    from ptailor.cli.main import cli

    res: dict = {"problems": [], "codes": []}
    cmds = [["inspect", str(path)]]
    if demo is not None:
        cmds.append(
            [
                "adjust",
                str(path),
                str(demo / "recipe.yaml"),
                "--drape",
                str(demo / "garment.obj"),
                "-o",
                str(out),
            ]
        )
    for args in cmds:
        r = CliRunner().invoke(cli, args)
        code = r.exit_code
        res["codes"].append(code)
        if r.exception is not None and not isinstance(r.exception, SystemExit):
            res["problems"].append(("traceback", signature(r.exception)))
            continue
        text = r.output.strip()
        if code == 2:
            res.setdefault("messages", []).append(
                f"{args[0]}: " + re.sub(r"-?\d[\d.e+-]*", "N", text.replace(str(path), "FILE"))[:90]
            )
            if len(text.splitlines()) != 1 or str(path) not in text:
                res["problems"].append(("message", f"{args[0]}: {text[:200]!r}"))
            if args[0] == "adjust" and out.exists():
                res["problems"].append(("left output", args[0]))
        elif code == 0 and args[0] == "adjust":
            for f in out.iterdir():
                if f.suffix in (".obj", ".dxf", ".json", ".svg") and _BAD_NUMBER.search(
                    f.read_bytes()
                ):
                    res["problems"].append(("nan written", f.name))
        elif code != 0:
            res["problems"].append(("exit", f"{args[0]}: {code}: {text[:200]!r}"))
        if code != 0:
            break  # adjust only after a readable inspect
    return res


def in_child(fn, timeout: float) -> dict:
    """``fn()`` in a forked child, killed after ``timeout`` seconds."""
    rfd, wfd = os.pipe()
    pid = os.fork()
    if pid == 0:  # child
        os.close(rfd)
        try:
            data = json.dumps(fn()).encode()
        except BaseException as exc:  # the harness itself must report
            data = json.dumps({"problems": [("harness", signature(exc))], "codes": []}).encode()
        with os.fdopen(wfd, "wb") as f:
            f.write(data)
        os._exit(0)
    os.close(wfd)
    t0 = time.monotonic()
    chunks = []
    os.set_blocking(rfd, False)
    while True:
        try:
            b = os.read(rfd, 65536)
            if b:
                chunks.append(b)
            else:
                break
        except BlockingIOError:
            if time.monotonic() - t0 > timeout:
                os.kill(pid, signal.SIGKILL)
                os.waitpid(pid, 0)
                os.close(rfd)
                return {"problems": [("hang", f">{timeout:.0f}s")], "codes": [], "t": timeout}
            time.sleep(0.01)
    os.close(rfd)
    os.waitpid(pid, 0)
    res = json.loads(b"".join(chunks) or b'{"problems": [["harness", "no result"]], "codes": []}')
    res["t"] = time.monotonic() - t0
    return res


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", type=int, default=200)
    ap.add_argument("--seed", type=int, default=12)
    ap.add_argument("--timeout", type=float, default=60.0)
    ap.add_argument("--json", type=Path, help="write the counts and every problem case here")
    ap.add_argument("--keep", type=Path, help="copy the files of problem cases here")
    a = ap.parse_args(argv)

    from click.testing import CliRunner

    import ptailor.cli.main  # noqa: F401 - imported once, before forking
    from ptailor.cli.main import cli

    work = Path(tempfile.mkdtemp(prefix="fuzz_dxf_"))
    demo = work / "demo"
    r = CliRunner().invoke(cli, ["demo", str(demo)])
    assert r.exit_code == 0, r.output
    seeds: list[tuple[Path, Path | None]] = [(demo / "pattern.dxf", demo)]
    for p in sorted((SHARED / "dxf").glob("*")) if (SHARED / "dxf").is_dir() else []:
        if p.suffix.lower() == ".dxf":
            seeds.append((p, None))
    rng = random.Random(a.seed)
    codes: Counter = Counter()
    kinds: Counter = Counter()
    sigs: Counter = Counter()
    messages: Counter = Counter()
    cases = []
    t0 = time.monotonic()
    for i in range(a.cases):
        # two in three cases mutate the demo pattern (inspect + adjust), the rest a fixture
        src, drape = seeds[0] if rng.random() < 2 / 3 or len(seeds) == 1 else rng.choice(seeds[1:])
        case = work / f"case{i:05d}.dxf"
        case.write_bytes(mutate(src.read_bytes(), rng))
        res = in_child(lambda c=case, d=drape, i=i: run_case(c, d, work / f"out{i:05d}"), a.timeout)
        codes[tuple(res["codes"]) or ("hang",)] += 1
        for msg in res.get("messages", []):
            messages[msg] += 1
        for kind, what in res["problems"]:
            kinds[kind] += 1
            sigs[f"{kind}: {what}"] += 1
        if res["problems"]:
            cases.append({"case": i, "seed_file": src.name, "problems": res["problems"]})
            if a.keep:
                a.keep.mkdir(parents=True, exist_ok=True)
                (a.keep / case.name).write_bytes(case.read_bytes())
        case.unlink()
        if (i + 1) % 100 == 0:
            print(
                f"{i + 1} cases, {time.monotonic() - t0:.0f}s, problems {dict(kinds)}",
                file=sys.stderr,
                flush=True,
            )
    summary = {
        "cases": a.cases,
        "seed": a.seed,
        "seconds": round(time.monotonic() - t0, 1),
        "exit_codes": {"/".join(map(str, k)): v for k, v in sorted(codes.items(), key=str)},
        "problems": dict(kinds),
        "signatures": dict(sigs.most_common()),
        "exit_2_messages": dict(messages.most_common(40)),
    }
    print(json.dumps(summary, indent=2))
    if a.json:
        a.json.write_text(json.dumps({**summary, "cases_with_problems": cases}, indent=2))
    return 1 if kinds else 0


if __name__ == "__main__":
    sys.exit(main())
