"""Fuzzing campaign for specification JSON (issue 43): N seeded mutations of a valid
specification, each read and matched to its garment as ``adjust --spec`` does.

The base is the generated cone skirt and its GarmentCode specification
(``tests/test_spec.py``'s ``sample_spec``: arcs, straight edges, two stitches, design
parameters added). A case applies one to three mutations to the JSON tree (a value made a
huge or infinite number, a bool, a string, a list, an object, null; a key dropped; a loop
re-rooted; stitches repeated, reversed or made self-stitches; ``units_in_meter`` dropped
or extreme; ``curvature_coords`` odd; a parameter's influence of the wrong type) or to its
text (a 400- or 5000-digit integer, deep nesting, a repeated key, a cut, random bytes).
Each runs ``read_specification``, ``spec_unit`` and ``match_specification`` under a
per-case time limit (SIGALRM). Counted: success, exit 2 (a ``PtailorError``), tracebacks
(by signature: exception type and innermost ptailor frame), hangs, and unclear refusals
(a message that does not name the file or spans lines).

    python bench/fuzz_spec.py --cases 1000 --seed 43 [--timeout 10] [--json out.json]
"""

from __future__ import annotations

import argparse
import copy
import json
import random
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


def base_case(folder: Path):
    """``(garment, its panels, its seams, the specification's JSON)``: the cone skirt."""
    from tests.test_spec import sample_spec

    from ptailor.model.structure import structure
    from ptailor.samples import cone_skirt

    g = cone_skirt(n_around=48, n_along=16)
    d = json.loads(sample_spec(g, folder / "base.json").read_text())
    names = list(d["pattern"]["panels"])
    d["parameters"] = {
        "length": {
            "influence": [{"panel": n, "edge_list": [{"id": 0, "direction": "both"}]}
                          for n in names],
            "type": "length",
            "value": 1,
        }
    }  # fmt: skip
    st = structure(g)
    return g, st.panels, st.seams, d


ODD = [1e300, -1e300, float("inf"), True, None, "x", [], [1, 2], {"a": 1}, 0, -1, 1e-300, 7]


def _nodes(x, path=()):
    """Every (path, value) of a JSON tree."""
    yield path, x
    if isinstance(x, dict):
        for k, v in x.items():
            yield from _nodes(v, (*path, k))
    elif isinstance(x, list):
        for i, v in enumerate(x):
            yield from _nodes(v, (*path, i))


def _set(d, path, value):
    for k in path[:-1]:
        d = d[k]
    d[path[-1]] = value


def _drop(d, path):
    for k in path[:-1]:
        d = d[k]
    del d[path[-1]]


def _reroot(d: dict, rng: random.Random) -> None:
    pat = d.get("pattern")
    if not isinstance(pat, dict) or not isinstance(pat.get("panels"), dict) or not pat["panels"]:
        return
    name = rng.choice(list(pat["panels"]))
    p = pat["panels"][name]
    if not (isinstance(p, dict) and isinstance(p.get("edges"), list) and p["edges"]):
        return
    r, n = rng.randrange(len(p["edges"])), len(p["edges"])
    p["edges"] = p["edges"][r:] + p["edges"][:r]
    sides = [x for s in pat.get("stitches") or [] if isinstance(s, list) for x in s]
    for side in sides:  # the stitches renumbered with it
        if (
            isinstance(side, dict)
            and side.get("panel") == name
            and isinstance(side.get("edge"), int)
        ):
            side["edge"] = (side["edge"] - r) % n


def _stitches(d: dict, rng: random.Random) -> None:
    st = d["pattern"].get("stitches") if isinstance(d.get("pattern"), dict) else None
    if not isinstance(st, list) or not st:
        return
    s = rng.choice(st)
    how = rng.choice(["repeat", "reverse", "self", "many"])
    if how == "repeat":
        st.append(copy.deepcopy(s))
    elif how == "reverse":
        st.append(list(reversed(copy.deepcopy(s))))
    elif how == "self" and isinstance(s, list) and len(s) == 2:
        s[1] = copy.deepcopy(s[0])
    else:
        st += [copy.deepcopy(s)] * 10_000


def _units(d: dict, rng: random.Random) -> None:
    props = d.setdefault("properties", {})
    if not isinstance(props, dict):
        return
    if rng.random() < 0.5:
        props.pop("units_in_meter", None)
    else:
        props["units_in_meter"] = rng.choice([1e-300, 1e300, 300, 1, 1000, -5, 0])


def _coords(d: dict, rng: random.Random) -> None:
    if isinstance(d.setdefault("properties", {}), dict):
        d["properties"]["curvature_coords"] = rng.choice(
            ["absolute", "Absolute", "abs", 1, None, "relative"]
        )


def _influence(d: dict, rng: random.Random) -> None:
    par = d.get("parameters", {}).get("length") if isinstance(d.get("parameters"), dict) else None
    if isinstance(par, dict) and isinstance(par.get("influence"), list) and par["influence"]:
        par["influence"][0] = rng.choice(
            [{"panel": {"a": 1}}, {"panel": ["front"]}, 5, {"panel": "front", "edge_list": 3}]
        )


def _value(d: dict, rng: random.Random) -> None:
    nodes = [p for p, _ in _nodes(d) if p]
    if nodes:
        _set(d, rng.choice(nodes), rng.choice(ODD))


def _drop_node(d: dict, rng: random.Random) -> None:
    nodes = [p for p, _ in _nodes(d) if p]
    if nodes:
        _drop(d, rng.choice(nodes))


MUTATIONS = [_value, _value, _drop_node, _reroot, _stitches, _units, _coords, _influence]


def mutate_tree(d: dict, rng: random.Random) -> dict:
    d = copy.deepcopy(d)
    rng.choice(MUTATIONS)(d, rng)
    return d


def mutate_text(text: str, rng: random.Random) -> str:
    if rng.random() < 0.6:  # most cases: the tree's mutations only
        return text
    how = rng.choice(["bigint", "hugeint", "deep", "repeat_key", "cut", "bytes"])
    if how == "bigint":
        return text.replace("100", "9" * 400, 1)
    if how == "hugeint":
        return text.replace("100", "9" * 5000, 1)
    if how == "deep":
        n = rng.choice([100, 1000, 100_000])
        return text.replace('"pattern": {', '"deep": ' + "[" * n + "]" * n + ', "pattern": {', 1)
    if how == "repeat_key":
        return text.replace('"pattern": {', '"pattern": {"panels": {}, ', 1)
    if how == "cut":
        return text[: rng.randrange(len(text))]
    i = rng.randrange(len(text))
    return text[:i] + "".join(chr(rng.randrange(32, 0x3000)) for _ in range(4)) + text[i:]


def case_text(base: dict, rng: random.Random) -> str:
    d = base
    for _ in range(rng.randint(1, 3)):  # one to three tree mutations
        d = mutate_tree(d, rng)
    try:
        text = json.dumps(d, allow_nan=True)
    except (TypeError, ValueError):
        text = json.dumps(base)
    return mutate_text(text, rng)


def run_case(text: str, path: Path, g, panels, seams, timeout: float) -> tuple[str, str | None]:
    """``(outcome, detail)``: ok, exit2, traceback, hang or unclear."""
    from ptailor.errors import PtailorError
    from ptailor.formats.garment import LoadedGarment  # noqa: F401  (the run's type)
    from ptailor.formats.spec_json import read_specification
    from ptailor.spec.match import match_specification

    path.write_text(text, encoding="utf-8", errors="surrogatepass")
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, timeout)
    try:
        spec = read_specification(path)
        if spec.units_source == "absent":
            from types import SimpleNamespace

            from ptailor.run.spec import spec_unit

            spec = spec_unit(SimpleNamespace(garment=g), spec)
        match_specification(g, spec, panels, seams=seams)
        return "ok", None
    except HangError:
        return "hang", None
    except PtailorError as exc:
        msg = str(exc)
        if str(path) not in msg or "\n" in msg:
            return "unclear", msg[:120]
        return "exit2", msg.split(": ", 2)[-1][:60]
    except Exception as exc:  # (what the campaign counts)
        return "traceback", signature(exc, exc.__traceback__)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=43)
    ap.add_argument("--timeout", type=float, default=10.0)
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args(argv)
    signal.signal(signal.SIGALRM, _alarm)
    rng = random.Random(args.seed)
    outcomes: Counter = Counter()
    details: dict[str, Counter] = {"traceback": Counter(), "unclear": Counter(),
                                   "exit2": Counter()}  # fmt: skip
    slowest = 0.0
    with tempfile.TemporaryDirectory() as td:
        g, panels, seams, base = base_case(Path(td))
        path = Path(td) / "case_specification.json"
        t0 = time.perf_counter()
        for _ in range(args.cases):  # a loop over cases
            text = case_text(base, rng)
            t = time.perf_counter()
            outcome, detail = run_case(text, path, g, panels, seams, args.timeout)
            slowest = max(slowest, time.perf_counter() - t)
            outcomes[outcome] += 1
            if detail is not None and outcome in details:
                details[outcome][detail] += 1
        total = time.perf_counter() - t0
    result = {
        "cases": args.cases,
        "seed": args.seed,
        "outcomes": dict(outcomes),
        "tracebacks": dict(details["traceback"]),
        "unclear": dict(details["unclear"]),
        "exit2_top": dict(details["exit2"].most_common(12)),
        "seconds": round(total, 1),
        "slowest_case_s": round(slowest, 2),
    }
    print(json.dumps(result, indent=2))
    if args.json:
        args.json.write_text(json.dumps(result, indent=2))
    return 1 if outcomes["traceback"] or outcomes["hang"] or outcomes["unclear"] else 0


if __name__ == "__main__":
    sys.exit(main())
