"""Fuzzing campaign for the recipe reader and validator (issue 12): N seeded cases.

The cases come from the Hypothesis strategies of ``tests/test_fuzz_recipe.py`` (random
YAML documents with anchors, aliases, tags and odd scalars; mutations of the real recipes in
``recipes/*.yaml``), drawn with a fixed seed, half of each. Each runs ``ptailor validate
FILE`` in process through click's CliRunner under a per-case time limit (SIGALRM), then,
when validate says 0, ``parse_recipe`` (the path ``adjust`` takes). Counted: exit codes,
tracebacks (by signature: exception type and innermost ptailor frame), hangs, and contract
breaks (an exit-2 output that is not one line per problem naming the file, validate and
parse_recipe disagreeing, a non-finite number in a recipe validate accepted), and exit-2
cases where only the JSON Schema (not the operations' rules) saw a problem.

    python bench/fuzz_recipe.py --cases 3000 --seed 12 [--timeout 10] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import signal
import sys
import tempfile
import time
import traceback
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


class HangError(Exception):
    pass


def _alarm(signum, frame):
    raise HangError()


def signature(exc: BaseException, tb) -> str:
    frames = [f for f in traceback.extract_tb(tb) if "ptailor" in f.filename]
    where = f"{Path(frames[-1].filename).name}:{frames[-1].lineno}" if frames else "?"
    return f"{type(exc).__name__} at {where}: {str(exc)[:80]}"


def run_case(text: str, path: Path, timeout: float) -> tuple[str, str | None]:
    """``(outcome, detail)``; outcome is exit0, exit2, traceback, hang or contract."""
    from click.testing import CliRunner

    from ptailor.cli.main import cli

    path.write_text(text, encoding="utf-8")
    signal.setitimer(signal.ITIMER_REAL, timeout)
    try:
        r = CliRunner().invoke(cli, ["validate", str(path)])
        if r.exception is not None and not isinstance(r.exception, SystemExit):
            if isinstance(r.exception, HangError):
                return "hang", None
            return "traceback", signature(r.exception, r.exc_info[2])
        if r.exit_code == 0:
            return _accepted(text)
        if r.exit_code != 2:
            return "contract", f"exit {r.exit_code}"
        return _refused(text, path, r.stdout.splitlines())
    except HangError:
        return "hang", None
    except Exception as exc:
        return "traceback", signature(exc, exc.__traceback__)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)


def _accepted(text: str) -> tuple[str, str | None]:
    """Validate said 0: ``parse_recipe`` must accept the text, with every number finite."""
    from tests.test_fuzz_recipe import all_finite

    from ptailor.errors import RecipeError
    from ptailor.recipe import parse_recipe

    try:
        rec = parse_recipe(text)
    except RecipeError as exc:
        return "contract", f"validate 0 but parse_recipe: {str(exc)[:80]}"
    if not all_finite(rec.to_dict()):
        return "contract", "validate 0 with a non-finite or huge number"
    return "exit0", None


def _refused(text: str, path: Path, lines: list[str]) -> tuple[str, str | None]:
    """Validate said 2: one line per problem naming the file, and ``parse_recipe`` refusing."""
    from ptailor.errors import RecipeError
    from ptailor.recipe import parse_recipe, recipe_problems

    probs = recipe_problems(text, source=str(path))
    if len(lines) != len(probs) or not lines:
        return "contract", f"{len(lines)} lines for {len(probs)} problems"
    if not all(ln.startswith(f"{path}:") for ln in lines):
        return "contract", "a line not naming the file"
    try:
        parse_recipe(text)
        return "contract", "validate 2 but parse_recipe accepted"
    except RecipeError:
        pass
    if any(ln.endswith("(schema)") for ln in lines):
        # the schema caught what the operations' rules did not: they disagree
        return "exit2-schema-only", next(
            ln.split(": ", 1)[1] for ln in lines if ln.endswith("(schema)")
        )
    return "exit2", lines[0].split(": ", 1)[1][:60]


def _collector(strat, k: int, seed: int) -> list[str]:
    from hypothesis import HealthCheck, given, settings
    from hypothesis import seed as hseed

    got: list[str] = []

    @hseed(seed)
    @settings(
        max_examples=k,
        database=None,
        deadline=None,
        derandomize=False,
        suppress_health_check=list(HealthCheck),
    )
    @given(strat)
    def collect(text):
        got.append(text)

    collect()
    return got


def draw_cases(n: int, seed: int) -> list[tuple[str, str]]:
    """``n`` texts, half random documents, half mutated recipes, from a seeded run."""
    from tests.test_fuzz_recipe import mutated_recipe, yaml_doc

    out: list[tuple[str, str]] = []
    for kind, strat, k in (("doc", yaml_doc(), n // 2), ("mutant", mutated_recipe(), n - n // 2)):
        got = _collector(strat, k, seed)

        out += [(kind, t) for t in got[:k]]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", type=int, default=3000)
    ap.add_argument("--seed", type=int, default=12)
    ap.add_argument("--timeout", type=float, default=10.0)
    ap.add_argument("--json", default=None)
    a = ap.parse_args()
    signal.signal(signal.SIGALRM, _alarm)
    t0 = time.perf_counter()
    cases = draw_cases(a.cases, a.seed)
    t_draw = time.perf_counter() - t0
    outcomes: Counter = Counter()
    by_kind: Counter = Counter()
    details: Counter = Counter()
    slowest = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        for i, (kind, text) in enumerate(cases):
            t = time.perf_counter()
            outcome, detail = run_case(text, Path(tmp) / f"case{i}.yaml", a.timeout)
            slowest = max(slowest, time.perf_counter() - t)
            outcomes[outcome] += 1
            by_kind[(kind, outcome)] += 1
            if outcome in ("traceback", "contract", "hang", "exit2-schema-only"):
                details[f"{outcome}: {detail}"] += 1
                (Path(tmp).parent / f"fuzz_recipe_bad_{i}.yaml").write_text(text)
    total = time.perf_counter() - t0
    res = {
        "cases": len(cases),
        "seed": a.seed,
        "outcomes": dict(outcomes),
        "by_kind": {f"{k}/{o}": v for (k, o), v in sorted(by_kind.items())},
        "failures": dict(details.most_common()),
        "slowest_case_s": round(slowest, 3),
        "draw_s": round(t_draw, 1),
        "total_s": round(total, 1),
    }
    print(json.dumps(res, indent=2))
    if a.json:
        Path(a.json).write_text(json.dumps(res, indent=2) + "\n")


if __name__ == "__main__":
    main()
