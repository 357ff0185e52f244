"""Fuzzing campaign for what a catalogue reads back (issue 43): N seeded mutants, outside
pytest.

One small ``batch --html`` output root is made once (two generated garments, their pages,
``_catalogue/catalogue.json``, a ``--log``, a manifest). Each case copies it and mutates one
file kind: ``catalogue`` (``_catalogue/catalogue.json``), ``report`` (a garment's
``report.json``), ``stamp`` (its ``batch.json``), ``log`` (the ``--log``, read by ``ptailor
report OUT --log``) or ``manifest`` (a JSON Lines manifest, read as ``batch --manifest``
reads it, every cell checked by the command's own option types). A mutation replaces a value
at a random place of the JSON with an extreme (null, a string, a 400-digit integer, 1e308,
NaN, a deep list, markup, a bool, an object...), deletes a key, or works on the text (cut,
random bytes, deep nesting). Then ``ptailor report OUT`` runs in process (or the manifest
is read), with a time limit.

Counted: ``crash`` (an exit other than 0 and 2, a traceback), ``hang`` (over the limit),
``partial`` (exit 0 and ``OUT/index.html`` links a file that is not there; exit 2 and
anything in OUT changed), ``lost`` (a file a garment folder's marker lists is gone, or a
file outside OUT changed), ``unclear`` (exit 2 whose message is not one line naming the
file).

    python bench/fuzz_catalogue.py --cases 1200 --seed 1 [--timeout 20] [--json out.json]

The mutator (:func:`mutate_json`) and :func:`check_case` are shared with
``tests/test_fuzz_catalogue.py``.
"""

from __future__ import annotations

import argparse
import hashlib
import importlib.util
import json
import random
import shutil
import signal
import sys
import tempfile
import time
from collections import Counter
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

_spec = importlib.util.spec_from_file_location(
    "fuzz_obj", Path(__file__).resolve().parent / "fuzz_obj.py"
)
fuzz_obj = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(fuzz_obj)  # its signature(): one way of naming a traceback

RECIPE = "steps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.1}]\n"
KINDS = ("catalogue", "report", "stamp", "log", "manifest")
EXTREMES = [
    None, True, False, "", "x", "<script>alert(1)</script>", "../../etc", 10**400, -(10**20),
    1e308, -1e308, float("nan"), float("inf"), 0, -1, 1.5, [], {}, [1, "a", None],
    {"a": {"b": [None]}}, "9" * 400, "\u00e9\u0000\u202e", "\ud800", ["x"] * 50,
]  # fmt: skip


def build(root: Path) -> Path:
    """The pristine site: OUT (batch --html of two garments), batch.jsonl, manifest.jsonl."""
    from click.testing import CliRunner

    from ptailor.cli.main import cli
    from ptailor.formats.obj import write_garment
    from ptailor.samples import cone_skirt, cylinder

    (root / "g").mkdir(parents=True)
    write_garment(root / "g" / "a_tube.obj", cylinder(circumference=40.0, n_around=10, n_along=3))
    write_garment(root / "g" / "b_skirt.obj", cone_skirt(n_around=10, n_along=3))
    (root / "r.yaml").write_text(RECIPE)
    args = ["batch", str(root / "r.yaml"), str(root / "g"), "-o", str(root / "OUT"), "--html",
            "-j", "1", "--log", str(root / "batch.jsonl")]  # fmt: skip
    res = CliRunner().invoke(cli, args)
    assert res.exit_code == 0, res.output
    rows = [
        {"garment": "g/a_tube.obj", "name": "tube", "pattern_units": "cm", "up": "y"},
        {"garment": "g/b_skirt.obj", "size": "", "front": "z"},
    ]
    (root / "manifest.jsonl").write_text("".join(json.dumps(r) + "\n" for r in rows))
    return root


# --------------------------------------------------------------------------- mutating


def _places(value, path=()):
    """Every place in a JSON value: paths of keys and indices."""
    yield path
    if isinstance(value, dict):
        for k, v in value.items():
            yield from _places(v, (*path, k))
    elif isinstance(value, list):
        for k, v in enumerate(value[:20]):
            yield from _places(v, (*path, k))


def _set(value, path, new, *, delete: bool = False):
    if not path:
        return new
    parent = value
    for k in path[:-1]:
        parent = parent[k]
    if delete and isinstance(parent, dict):
        del parent[path[-1]]
    else:
        parent[path[-1]] = new
    return value


def _mutate_value(value, rng: random.Random):
    places = list(_places(value))
    path = rng.choice(places)
    if rng.random() < 0.15 and path:
        return _set(value, path, None, delete=True)
    new = rng.choice(EXTREMES)
    if rng.random() < 0.1:
        new = [new]
        for _ in range(rng.choice([3, 40, 200])):
            new = [new]
    return _set(value, path, json.loads(json.dumps(new)) if new == new else new)


def _mutate_text(text: str, rng: random.Random) -> str:
    how = rng.randrange(4)
    if how == 0:
        return text[: rng.randrange(len(text) + 1)]
    if how == 1:
        k = rng.randrange(len(text) + 1)
        junk = "".join(chr(rng.randrange(1, 0x2FF)) for _ in range(rng.randint(1, 6)))
        return text[:k] + junk + text[k:]
    if how == 2:
        n = rng.choice([40, 5000, 100_000])
        return "[" * n + "]" * n
    return '{"records": ' + "9" * rng.choice([400, 5000]) + "}"


def mutate_json(text: str, rng: random.Random, *, lines: bool = False) -> str:
    """One to three mutations of a JSON document (or of JSON Lines, one line each)."""
    for _ in range(rng.randint(1, 3)):
        if rng.random() < 0.25:
            text = _mutate_text(text, rng)
            continue
        if lines:
            rows = text.splitlines() or ["{}"]
            k = rng.randrange(len(rows))
            try:
                rows[k] = json.dumps(_mutate_value(json.loads(rows[k]), rng))
            except (ValueError, RecursionError):
                rows[k] = _mutate_text(rows[k], rng)
            text = "\n".join(rows) + "\n"
            continue
        try:
            text = json.dumps(_mutate_value(json.loads(text), rng))
        except (ValueError, RecursionError):
            text = _mutate_text(text, rng)
    return text


def target(site: Path, kind: str, rng: random.Random) -> Path:
    """The file a case of ``kind`` mutates."""
    garment = rng.choice(["a_tube", "b_skirt"])
    return {
        "catalogue": site / "OUT" / "_catalogue" / "catalogue.json",
        "report": site / "OUT" / garment / "report.json",
        "stamp": site / "OUT" / garment / "batch.json",
        "log": site / "batch.jsonl",
        "manifest": site / "manifest.jsonl",
    }[kind]


# --------------------------------------------------------------------------- checking


class _Refs(HTMLParser):
    def __init__(self, text: str) -> None:
        super().__init__()
        self.refs: list[str] = []
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        self.refs += [v for k, v in attrs if k in ("href", "src") and v]


def dangling(page: Path) -> list[str]:
    """The page's relative links to files that are not there."""
    bad = []
    for ref in _Refs(page.read_text(encoding="utf-8")).refs:
        parts = urlsplit(ref)
        if parts.scheme or parts.netloc or not (page.parent / unquote(parts.path)).is_file():
            bad.append(ref)
    return bad


def snapshot(folder: Path) -> dict[str, str]:
    """Relative path -> SHA-256 of every file under ``folder``."""
    return {
        str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


def _marker_files(out: Path) -> list[str]:
    from ptailor.run.folder import read_marker

    missing = []
    for folder in out.iterdir():
        for name in (read_marker(folder) or []) if folder.is_dir() else []:
            if not (folder / name).is_file():
                missing.append(f"{folder.name}/{name}")
    return missing


def _manifest(site: Path, path: Path) -> tuple[int, str]:
    """Read a manifest as ``batch --manifest`` does: (exit status, message)."""
    from ptailor.batch.manifest import read_manifest
    from ptailor.cli.batch import _cell_check, batch
    from ptailor.errors import PtailorError

    ctx = batch.make_context("batch", [str(site / "r.yaml"), "-o", str(site / "o2"),
                                       "--manifest", str(path)])  # fmt: skip
    try:
        read_manifest(path, check=_cell_check(ctx))
    except PtailorError as exc:
        return 2, f"ptailor: error: {exc}"
    return 0, ""


def check_case(site: Path, kind: str, text: str) -> list[tuple[str, str]]:
    """Write the mutant, run the reader, judge: [(kind of breach or ``exitN``, detail)]."""
    from click.testing import CliRunner

    from ptailor.cli.main import cli

    path = target(site, kind, random.Random(len(text)))
    path.write_text(text, encoding="utf-8", errors="surrogatepass")
    out = site / "OUT"
    before_out, before_rest = snapshot(out), snapshot(site / "g")
    if kind == "manifest":
        exc = None
        try:
            code, msg = _manifest(site, path)
        except Exception as e:  # a crash of the reader
            code, msg, exc = 1, "", e
    else:
        args = ["report", str(out)] + (["--log", str(path)] if kind == "log" else [])
        res = CliRunner().invoke(cli, args)
        code, msg, exc = res.exit_code, res.output, res.exception
    found = [(f"exit{code}", kind)]
    if code not in (0, 2) or (exc is not None and not isinstance(exc, SystemExit)):
        found.append(("crash", f"{kind}: {fuzz_obj.signature(exc) if exc else msg[-160:]}"))
    if "Traceback" in msg or "internal error" in msg:
        found.append(("crash", f"{kind}: {msg.strip()[-160:]}"))
    if code == 2:
        errs = [ln for ln in msg.splitlines() if ln.startswith("ptailor: error:")]
        if len(errs) != 1 or (str(path) not in errs[0] and str(out) not in errs[0]):
            found.append(("unclear", f"{kind}: {msg.strip()[:160]!r}"))
        if kind != "manifest" and snapshot(out) != before_out:
            found.append(("partial", f"{kind}: OUT changed on exit 2"))
    if code == 0 and kind != "manifest":
        bad = dangling(out / "index.html") + [
            f"{p.parent.name}: {r}" for p in out.glob("*/index.html") for r in dangling(p)
        ]
        if bad:
            found.append(("partial", f"{kind}: links to nothing: {bad[:3]}"))
    missing = _marker_files(out)
    if missing or snapshot(site / "g") != before_rest:
        found.append(("lost", f"{kind}: {missing[:3]}"))
    return found


def _alarm(signum, frame):
    raise TimeoutError("case over its time limit")


def run_case(pristine: Path, work: Path, case: int, seed: int, timeout: float) -> list:
    """One seeded case in a fresh copy of the site (a hang: SIGALRM after ``timeout``)."""
    rng = random.Random(seed * 1_000_003 + case)
    kind = KINDS[case % len(KINDS)]
    site = work / f"c{case}"
    shutil.copytree(pristine, site, symlinks=True)
    path = target(site, kind, rng)
    text = mutate_json(path.read_text(), rng, lines=kind in ("log", "manifest"))
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, timeout)
    try:
        return check_case(site, kind, text)
    except TimeoutError:
        return [("hang", f"{kind}: > {timeout:g} s")]
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
        shutil.rmtree(site, ignore_errors=True)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", type=int, default=1200)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=20.0, help="per case, seconds")
    ap.add_argument("--json", type=Path, default=None, help="write the counts here")
    args = ap.parse_args(argv)
    outcomes: Counter = Counter()
    breaches: Counter = Counter()
    examples: dict[str, int] = {}
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as td:
        pristine = build(Path(td) / "site")
        for case in range(args.cases):
            for what, detail in run_case(pristine, Path(td), case, args.seed, args.timeout):
                if what.startswith("exit"):
                    outcomes[f"{detail} {what}"] += 1
                else:
                    breaches[f"{what}: {detail}"] += 1
                    examples.setdefault(f"{what}: {detail}", case)
            if (case + 1) % 200 == 0:
                print(f"  {case + 1} cases, {sum(breaches.values())} breaches", file=sys.stderr)
    kinds = Counter(k.split(":")[0] for k in breaches.elements())
    summary = {
        "cases": args.cases,
        "seed": args.seed,
        "seconds": round(time.perf_counter() - t0, 1),
        "outcomes": dict(sorted(outcomes.items())),
        **{k: kinds.get(k, 0) for k in ("crash", "hang", "partial", "lost", "unclear")},
        "breaches": {k: [v, examples[k]] for k, v in breaches.most_common()},
    }
    print(json.dumps(summary, indent=2))
    if args.json:
        args.json.write_text(json.dumps(summary, indent=2))
    return 1 if breaches else 0


if __name__ == "__main__":
    sys.exit(main())
