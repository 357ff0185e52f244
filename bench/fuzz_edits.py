"""Fuzz campaign: extreme-edit recipes on small generated garments (issue 12).

Each case draws a small garment and a recipe of one or two steps with extreme parameters
(factors from subnormal to 1e300, axes with huge, tiny or zero components, ``by`` from
1e-12 to 1e300, extreme flatten weights and ``max_iter``, regions selecting nothing or
everything), then runs ``ptailor.run.garment.run_garment`` in-process. Half the cases go through
the recipe validator (the real path); the other half ("raw") skip it, so that the method
and the edits themselves are fuzzed past the validator's bounds.

The contract checked: exit 0 with every written number finite, or a ``PtailorError``
(exit 2) that leaves nothing behind. Anything else is a traceback, counted by signature
(exception type and the innermost ptailor frame).

    python bench/fuzz_edits.py -n 2000 --seed 12 --timeout 20

The generator (:func:`draw_case`) takes any ``pick``/``number`` source, so
``tests/test_fuzz_edits.py`` drives the same cases from Hypothesis.
"""

from __future__ import annotations

import argparse
import json
import math
import random
import re
import signal
import sys
import tempfile
import time
import traceback
from collections import Counter
from dataclasses import replace
from pathlib import Path

#: the garments: sample name -> small keyword arguments (a few hundred triangles)
GARMENTS = {
    "lantern_sleeve": {"n_around": 16, "n_sleeve": 8, "n_cuff": 3},
    "cone_skirt": {"n_around": 16, "n_along": 8},
    "bodice": {"n_around": 16, "n_along": 8},
    "cylinder": {"n_around": 12, "n_along": 6},
}
#: panel names per garment (for regions and seams), and openings
PANELS = {
    "lantern_sleeve": ["sleeve", "cuff"],
    "cone_skirt": ["front", "back"],
    "bodice": ["front", "back"],
    "cylinder": ["panel"],
}
OPENINGS = ["hem", "waist", "neckline", "cuff", "armhole", "nope", {"loop": 0}, {"loop": 7}]

#: extreme magnitudes: subnormal, tiny, ordinary, huge
MAGNITUDES = [
    5e-324,
    1e-320,
    1e-300,
    1e-12,
    1e-9,
    1e-6,
    1e-3,
    0.1,
    0.5,
    0.9,
    1.0,
    1.2,
    2.0,
    5.0,
    50.0,
    100.0,
    1e3,
    99999.0,
    1e6,
    1e12,
    1e300,
    1e308,
]


class RandomSource:
    """Draws from ``random.Random`` (the campaign)."""

    def __init__(self, seed: int) -> None:
        self.r = random.Random(seed)

    def pick(self, seq):
        return seq[self.r.randrange(len(seq))]

    def unit(self) -> float:
        return self.r.random()


def magnitude(src) -> float:
    """A positive number: a listed extreme, a plausible one, or log-uniform in 1e+-300."""
    kind = src.pick(["listed", "plausible", "plausible", "log"])
    if kind == "listed":
        return float(src.pick(MAGNITUDES))
    if kind == "plausible":
        return float(0.05 + 10.0 * src.unit())
    return float(10.0 ** (-300.0 + 600.0 * src.unit()))


def signed(src) -> float:
    return src.pick([1.0, -1.0]) * magnitude(src) if src.pick([True, True, False]) else 0.0


def vector(src) -> list[float]:
    return [signed(src) for _ in range(3)]


def region(src, garment: str):
    kind = src.pick(["all", "all", "panels", "box", "box"])
    if kind == "all":
        return "all"
    if kind == "panels":
        return {"panels": [src.pick(PANELS[garment] + ["nothing"])]}
    a, b = vector(src), vector(src)
    if src.pick([True, False]):  # a plausible box: the lower or upper part of the garment
        y = 40.0 * src.unit()
        a, b = [-1e3, -1e3, -1e3], [1e3, 1e3, 1e3]
        (a if src.pick([True, False]) else b)[1] = y
    lo = [min(x, y) for x, y in zip(a, b, strict=True)]
    hi = [max(x, y) for x, y in zip(a, b, strict=True)]
    return {"box": {"min": lo, "max": hi}}


def draw_step(src, garment: str) -> dict:
    """One recipe step with extreme parameters (keys as in a recipe)."""
    op = src.pick(["scale", "scale", "scale_seam", "extend", "shorten", "loosen", "cut"])
    if op == "scale":
        return {
            "op": "scale",
            "region": region(src, garment),
            "direction": src.pick(["around", "along", "uniform"]),
            "axis": src.pick(["auto", vector(src), [1.0e308] * 3, [5e-324, 0.0, 0.0]]),
            "factor": magnitude(src),
        }
    if op == "scale_seam":
        names = PANELS[garment] + ["nothing"]
        a, b = src.pick(names), src.pick(names)
        return {
            "op": "scale_seam",
            "seam": [a, b],
            "part": a,
            "direction": src.pick(["around", "along"]),
            "factor": magnitude(src),
        }
    if op in ("extend", "shorten"):
        st = {"op": op, "opening": src.pick(OPENINGS), "by": magnitude(src)}
        if src.pick([True, False]):
            st["measure"] = src.pick(["drape", "pattern"])
        return st
    if op == "loosen":
        return {"op": "loosen", "region": region(src, garment), "by": magnitude(src)}
    # cut
    if src.pick([True, False]):
        return {"op": "cut", "plane": {"point": vector(src), "normal": vector(src)}}
    k = src.pick([2, 3, 4])
    pts = [
        [signed(src) if src.pick([True, False]) else 40.0 * src.unit() - 20.0 for _ in (0, 1)]
        for _ in range(k)
    ]
    return {
        "op": "cut",
        "view": src.pick(["front", "back", "left", "top", vector(src)]),
        "sketch": pts,
        "remove": src.pick(["above", "below", "left", "right"]),
        "layers": src.pick(["both", "near"]),
    }


def draw_flatten(src) -> dict:
    fl: dict = {}
    if src.pick([True, False, False, False, False]):
        fl["w_pin"] = magnitude(src)
    if src.pick([True, False, False, False, False]):
        fl["w_asap"] = magnitude(src)
    if src.pick([True, False, False]):
        fl["max_iter"] = src.pick([1, 2, 3, 50, 100, 500, 10000])
    if src.pick([True, False, False]):
        fl["seams"] = src.pick(["ease", "keep", "free"])
    if src.pick([True, False, False]):
        fl["boundary"] = src.pick(["auto", "similar", "free"])
    if src.pick([True, False, False, False]):
        fl["method"] = "uniform"
    if src.pick([True, False, False, False]):
        fl["intrinsic"] = "paper"
    return fl


def draw_case(src) -> dict:
    """A case: ``{"garment", "steps", "flatten", "raw", "seam_allowance"}``."""
    garment = src.pick(sorted(GARMENTS))
    steps = [draw_step(src, garment) for _ in range(src.pick([1, 1, 2]))]
    for st in steps:
        if src.pick([True, False, False, False]):
            st["symmetric"] = True
    return {
        "garment": garment,
        "steps": steps,
        "flatten": draw_flatten(src),
        "raw": src.pick([True, False]),
        "seam_allowance": src.pick([None, None, None, 1.0, magnitude(src)]),
    }


def garment_files(folder: Path) -> dict[str, Path]:
    """Write each small garment once as an OBJ (v = drape, vt = pattern)."""
    from ptailor import samples
    from ptailor.formats.obj import write_garment

    out = {}
    for name, kw in GARMENTS.items():
        p = folder / f"{name}.obj"
        write_garment(p, getattr(samples, name)(**kw), header=[f"fuzz {name}", "units: cm"])
        out[name] = p
    return out


def make_recipe(case: dict):
    """The case's Recipe: validated (the real path), or filled with defaults but unchecked.

    Returns ``(recipe, None)`` or ``(None, PtailorError)`` when the validator refuses it.
    """
    from ptailor.errors import PtailorError
    from ptailor.recipe import parse_recipe

    raw = case["raw"]
    doc = {"units": "cm", "steps": case["steps"], "flatten": case["flatten"]}
    try:
        # raw: the validator sees every number clamped (monotone, so boxes stay ordered)
        # and checks the structure; the extreme numbers are then put back
        recipe = parse_recipe(yaml_flow(_benign(doc) if raw else doc), source="fuzz.yaml")
    except PtailorError as exc:
        return None, exc
    if not raw:
        return recipe, None
    steps = [
        replace(full, **{k: v for k, v in st.items() if k != "op"})
        for full, st in zip(recipe.steps, case["steps"], strict=True)
    ]
    try:  # a Recipe checks its flatten settings itself: an extreme weight is refused here
        return replace(recipe, steps=steps, flatten={**recipe.flatten, **case["flatten"]}), None
    except PtailorError as exc:
        return None, exc


def yaml_flow(x) -> str:
    """A recipe as one line of flow YAML, floats written so YAML 1.1 reads them as floats."""
    if isinstance(x, dict):
        return "{" + ", ".join(f"{k}: {yaml_flow(v)}" for k, v in x.items()) + "}"
    if isinstance(x, list):
        return "[" + ", ".join(yaml_flow(v) for v in x) + "]"
    if isinstance(x, bool) or x is None:
        return json.dumps(x)
    if isinstance(x, float):
        return f"{x:.17e}"
    return json.dumps(x)


def _benign(x):
    """Numbers clamped into [1e-3, 1e3] in magnitude (zero stays zero); ints kept."""
    if isinstance(x, dict):
        return {k: _benign(v) for k, v in x.items()}
    if isinstance(x, list):
        return [_benign(v) for v in x]
    if isinstance(x, float) and x != 0.0:
        return math.copysign(min(max(abs(x), 1e-3), 1e3), x)
    return x


def nan_on_disk(out: Path) -> list[str]:
    """Files in ``out`` holding a NaN or an infinity (garment.obj, report.json, pattern.dxf)."""
    bad = []
    for p in sorted(out.glob("*")):
        if p.suffix not in (".obj", ".json", ".dxf", ".svg"):
            continue
        t = p.read_text(errors="replace")
        if p.suffix == ".json":
            found: list = []
            json.loads(t, parse_constant=found.append)
            hit = bool(found)
        else:
            hit = re.search(r"(?<![A-Za-z_])(nan|inf|infinity)(?![A-Za-z_])", t, re.I) is not None
        if hit:
            bad.append(p.name)
    return bad


#: RuntimeWarnings that escaped a case (they would print), one entry per case
WARNED: list[str] = []


class CaseTimeoutError(Exception):
    pass


def _alarm(signum, frame):
    raise CaseTimeoutError


def signature(exc: BaseException) -> str:
    """Exception type and the innermost ptailor frame."""
    tb = traceback.extract_tb(exc.__traceback__)
    mine = [f for f in tb if "ptailor" in f.filename]
    f = (mine or tb)[-1]
    return f"{type(exc).__name__} @ {Path(f.filename).name}:{f.name}:{f.lineno}"


def run_case(case: dict, files: dict[str, Path], work: Path, *, formats=None, timeout=0):
    """Run one case; return ``(outcome, detail)``.

    outcome: ``ok``, ``exit2``, ``traceback``, ``nan`` (non-finite written), ``left``
    (exit 2 left output behind) or ``timeout``.
    """
    from ptailor.errors import PtailorError
    from ptailor.run import FORMATS, RunOptions, run_garment

    out = work / "out"
    if out.exists():
        import shutil

        shutil.rmtree(out)
    recipe, err = make_recipe(case)
    if err is not None:
        return "exit2", f"validate: {err}"
    if timeout:
        signal.signal(signal.SIGALRM, _alarm)
        signal.alarm(int(timeout))
    import warnings

    caught = warnings.catch_warnings(record=True)
    escaped = caught.__enter__()
    warnings.simplefilter("always")
    try:
        options = RunOptions(
            formats=tuple(formats or FORMATS), seam_allowance=case["seam_allowance"]
        )
        report = run_garment(str(files[case["garment"]]), recipe, out, options=options)
    except PtailorError as exc:
        return _refused(exc, out)
    except CaseTimeoutError:
        return "timeout", ""
    except Exception as exc:  # the contract's violation: count it by signature
        return "traceback", f"{signature(exc)}: {str(exc)[:160]}"
    finally:
        if timeout:
            signal.alarm(0)
        caught.__exit__(None, None, None)
        shown = [w for w in escaped if issubclass(w.category, RuntimeWarning)]
        if shown:
            WARNED.append(f"{shown[0].category.__name__}: {str(shown[0].message)[:60]}")
    return _written(out, report)


def _refused(exc: Exception, out: Path) -> tuple[str, str]:
    """Outcome of a refusal: ``left`` (output behind), a multi-line ``traceback``, or ``exit2``."""
    if out.exists():
        return "left", str(exc)
    msg = str(exc)
    if "\n" in msg:
        return "traceback", f"multi-line message: {msg[:200]}"
    return "exit2", msg


def _written(out: Path, report: dict) -> tuple[str, str]:
    """Outcome of a run that succeeded: ``nan`` (a non-finite number written) or ``ok``."""
    bad = nan_on_disk(out)
    if bad:
        return "nan", ", ".join(bad)
    if not _finite_report(report):
        return "nan", "report (in memory)"
    return "ok", ""


def _finite_report(obj) -> bool:
    if isinstance(obj, dict):
        return all(_finite_report(v) for v in obj.values())
    if isinstance(obj, (list, tuple)):
        return all(_finite_report(v) for v in obj)
    if isinstance(obj, float):
        return math.isfinite(obj)
    return True


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=2000, help="cases")
    ap.add_argument("--seed", type=int, default=12)
    ap.add_argument("--timeout", type=float, default=20.0, help="seconds per case")
    ap.add_argument("--slow", type=float, default=5.0, help="a case slower than this is slow")
    ap.add_argument("--formats", default="obj,dxf,svg,png")
    ap.add_argument("--log", help="JSON lines: one record per case")
    args = ap.parse_args(argv)
    work = Path(tempfile.mkdtemp(prefix="fuzz_edits."))
    files = garment_files(work)
    counts: Counter = Counter()
    sigs: Counter = Counter()
    exits: Counter = Counter()
    examples: dict[str, dict] = {}
    slow = []
    log = open(args.log, "w") if args.log else None  # noqa: SIM115
    t_all = time.perf_counter()
    for i in range(args.n):
        case = draw_case(RandomSource(args.seed * 1_000_003 + i))
        t0 = time.perf_counter()
        outcome, detail = run_case(
            case, files, work, formats=args.formats.split(","), timeout=args.timeout
        )
        dt = time.perf_counter() - t0
        counts[outcome] += 1
        if outcome in ("traceback", "nan", "left", "timeout"):
            key = f"{outcome}: {detail.split(':')[0] if outcome == 'traceback' else detail[:80]}"
            sigs[key] += 1
            examples.setdefault(key, {"case": i, "detail": detail, **case})
        if outcome == "exit2":
            exits[re.sub(r"[-+]?\d[\d.]*(e[-+]?\d+)?", "#", detail.split(": ", 2)[-1])[:70]] += 1
        if dt > args.slow:
            slow.append((round(dt, 1), i))
        if log:
            rec = {"i": i, "outcome": outcome, "s": round(dt, 3), "detail": detail[:300]}
            log.write(json.dumps(rec, default=str) + "\n")
        if (i + 1) % 100 == 0:
            print(f"{i + 1}/{args.n} {dict(counts)}", file=sys.stderr, flush=True)
    total = time.perf_counter() - t_all
    print(f"seed {args.seed}, {args.n} cases, {total:.0f} s")
    print("outcomes:", dict(counts))
    print(f"slow (> {args.slow:g} s): {len(slow)}", sorted(slow, reverse=True)[:10])
    for key, c in sigs.most_common():
        print(f"  {c:5d}  {key}")
        print(f"         e.g. {json.dumps(examples[key], default=str)[:600]}")
    print(f"cases printing a RuntimeWarning: {len(WARNED)}", Counter(WARNED).most_common(5))
    print("most common exit-2 messages:")
    for key, c in exits.most_common(12):
        print(f"  {c:5d}  {key}")
    bad = sum(counts[k] for k in ("traceback", "nan", "left", "timeout"))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
