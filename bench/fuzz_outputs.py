"""Seeded fuzzing campaign over output paths and folder states (issue 12).

Each case builds a folder state (an output folder missing, empty, an earlier ptailor
output, one with the user's files, another tool's report.json, links, long names, inputs
inside it, a file in its place, ...), runs ``ptailor adjust`` on a small garment, sometimes
sends SIGTERM or SIGINT at a random time, and asserts the contract:

- exit 0 or 2 (or, when a signal was sent, 128 + it, or death by it where it lands
  before ptailor's handler is installed), never a traceback otherwise;
- exit 2: exactly one line on stderr, naming no staging folder;
- no user file lost or changed (every file the case made that is not part of an earlier
  ptailor output), every symbolic link still a link;
- no staging folder (``.NAME.XXXXXXXX.tmp``) left anywhere;
- exit 0: the output folder holds a marker and a report.

Cases without a signal run in this process (click's test runner), those with one as a
subprocess. Usage::

    python bench/fuzz_outputs.py [--cases 500] [--seed 12] [--keep DIR]

Prints one line per failing case and the totals per state and outcome; exits 1 on any
violation.
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from click.testing import CliRunner

from ptailor.cli.main import cli
from ptailor.formats.obj import write_garment
from ptailor.run.folder import MARKER, read_marker
from ptailor.samples import lantern_sleeve, sample_for_triangles

RECIPE = "steps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.2}]\n"
FAST = ["--formats", "obj,svg", "--no-baseline"]
STAGING = re.compile(r"^\..+\.[a-z0-9_]{8}\.tmp$")
STATES = (
    "missing",
    "missing-deep",
    "empty",
    "ptailor",
    "ptailor+user",
    "ptailor+subfolder",
    "foreign-report",
    "symlink-report",
    "legacy",
    "legacy+user",
    "forged-marker",
    "file",
    "link-empty",
    "link-ptailor",
    "link-foreign",
    "link-dangling",
    "link-loop",
    "parent-is-file",
    "long-200",
    "long-256",
    "long-300",
    "unicode",
    "recipe-inside",
    "garment-inside",
    "drape-inside",
    "link-to-input",
    "out-is-cwd",
    "out-is-input",
    "out-above-input",
)


class Case:
    def __init__(self, root: Path, garment: Path, rng: random.Random, state: str) -> None:
        self.root = root
        self.state = state
        self.rng = rng
        self.garment = garment
        self.recipe = root / "r.yaml"
        self.recipe.write_text(RECIPE)
        self.out: Path = root / "out"
        self.extra: list[str] = []
        self.cwd: Path | None = None
        self.ptailor_files: set[Path] = set()  # what ptailor wrote: may be replaced

    def make_output(self, folder: Path, legacy: bool = False) -> None:
        src = self.root.parent / "_ref"
        shutil.copytree(src, folder)
        if legacy:
            (folder / MARKER).unlink()
        self.ptailor_files |= {p for p in folder.rglob("*")}

    def user(self, path: Path, text: str = "user data") -> None:
        path.write_text(text)

    def build(self) -> None:
        """Make the folder state ``self.state`` (the output folder and what is around it)."""
        builder = BUILDERS.get(self.state) or BUILDERS.get(self.state.split("-")[0] + "-")
        if builder is None:
            raise AssertionError(self.state)
        builder(self)

    # -- the states, one builder each (see BUILDERS) ------------------------------------

    def _missing(self) -> None:
        pass

    def _missing_deep(self) -> None:
        self.out = self.root / "a" / "b" / "out"

    def _empty(self) -> None:
        self.out.mkdir()

    def _ptailor(self) -> None:
        out = self.out
        self.make_output(out)
        if self.state == "ptailor+user":
            self.user(out / self.rng.choice(["notes.txt", "garment.obj.bak", ".hidden"]))
        elif self.state == "ptailor+subfolder":
            (out / "sub").mkdir()
            self.user(out / "sub" / "keep.txt")

    def _foreign_report(self) -> None:
        out = self.out
        out.mkdir()
        self.user(out / "report.json", '{"outputs": ["report.json"]}')
        self.user(out / "data.csv")

    def _symlink_report(self) -> None:
        root, out = self.root, self.out
        self.make_output(root / "elsewhere")
        out.mkdir()
        (out / "report.json").symlink_to(root / "elsewhere" / "report.json")
        self.user(out / "mine.txt")

    def _legacy(self) -> None:
        self.make_output(self.out, legacy=True)
        if self.state == "legacy+user":
            self.user(self.out / "recipe.yaml")

    def _forged_marker(self) -> None:
        out = self.out
        out.mkdir()
        self.user(out / MARKER, "{}")
        self.user(out / "report.json", "{}")

    def _file(self) -> None:
        self.user(self.out)

    def _link(self) -> None:
        """The output folder is a link: to an empty folder, an output, another tool's
        folder, nothing (dangling) or itself (a loop)."""
        s, target = self.state, self.root / "target"
        if s == "link-empty":
            target.mkdir()
        elif s == "link-ptailor":
            self.make_output(target)
        elif s == "link-foreign":
            target.mkdir()
            self.user(target / "drawing.dxf")
        elif s == "link-loop":
            target.symlink_to(self.out)
        self.out.symlink_to(target)

    def _parent_is_file(self) -> None:
        self.user(self.root / "plain")
        self.out = self.root / "plain" / "out"

    def _long(self) -> None:
        self.out = self.root / ("n" * int(self.state.split("-")[1]))

    def _unicode(self) -> None:
        self.out = self.root / "sortie-é-☃-𝄞"

    def _recipe_inside(self) -> None:
        self.make_output(self.out)
        self.recipe = self.out / "r.yaml"
        self.user(self.recipe, RECIPE)

    def _garment_inside(self) -> None:
        self.make_output(self.out)
        g = self.out / "in.obj"
        shutil.copy(self.garment, g)
        self.garment = g

    def _drape_inside(self) -> None:
        self.make_output(self.out)
        d = self.out / "drape.obj"
        shutil.copy(self.garment, d)
        self.extra = ["--drape", str(d)]

    def _link_to_input(self) -> None:
        out = self.out
        self.make_output(out)
        self.user(out / "r.yaml", RECIPE)
        link = self.root / "link.yaml"
        link.symlink_to(out / "r.yaml")
        self.recipe = link

    def _out_is_cwd(self) -> None:
        out = self.out
        self.make_output(out)
        self.user(out / "r.yaml", RECIPE)
        self.cwd = out
        self.out = Path(".")
        self.recipe = Path("r.yaml")

    def _out_is_input(self) -> None:
        self.out = self.recipe

    def _out_above_input(self) -> None:
        self.out = self.root

    def args(self) -> list[str]:
        return ["adjust", str(self.garment), str(self.recipe), "-o", str(self.out), "-q"]


#: the builder of each state; a name ending in ``-`` serves every state it begins
#: (``link-dangling`` is ``link-``: a link to nothing)
BUILDERS = {
    "missing": Case._missing,
    "missing-deep": Case._missing_deep,
    "empty": Case._empty,
    "ptailor": Case._ptailor,
    "ptailor+user": Case._ptailor,
    "ptailor+subfolder": Case._ptailor,
    "foreign-report": Case._foreign_report,
    "symlink-report": Case._symlink_report,
    "legacy": Case._legacy,
    "legacy+user": Case._legacy,
    "forged-marker": Case._forged_marker,
    "file": Case._file,
    "link-": Case._link,
    "link-to-input": Case._link_to_input,
    "parent-is-file": Case._parent_is_file,
    "long-": Case._long,
    "unicode": Case._unicode,
    "recipe-inside": Case._recipe_inside,
    "garment-inside": Case._garment_inside,
    "drape-inside": Case._drape_inside,
    "out-is-cwd": Case._out_is_cwd,
    "out-is-input": Case._out_is_input,
    "out-above-input": Case._out_above_input,
}


def snapshot(root: Path) -> dict[str, object]:
    """Every path under root: bytes for files, the target for links, None for folders."""
    snap: dict[str, object] = {}
    for dirpath, dirs, files in os.walk(root):
        for name in dirs + files:
            p = Path(dirpath) / name
            rel = str(p.relative_to(root))
            if p.is_symlink():
                snap[rel] = ("link", os.readlink(p))
            elif p.is_file():
                snap[rel] = p.read_bytes()
            else:
                snap[rel] = None
    return snap


def staging_under(root: Path) -> list[str]:
    return [
        str(Path(d) / n)
        for d, dirs, files in os.walk(root)
        for n in dirs + files
        if STAGING.match(n)
    ]


def run_case(case: Case, sig: int | None, delay: float) -> tuple[int, str]:
    if sig is None:
        old = os.getcwd()
        try:
            if case.cwd is not None:
                os.chdir(case.cwd)
            r = CliRunner().invoke(cli, case.args() + case.extra + FAST)
        finally:
            os.chdir(old)
        if r.exception is not None and not isinstance(r.exception, SystemExit):
            return 1, f"exception {type(r.exception).__name__}: {r.exception}"
        return r.exit_code, r.stderr
    cmd = [sys.executable, "-m", "ptailor", *case.args(), *case.extra, *FAST]
    proc = subprocess.Popen(
        cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, cwd=case.cwd
    )
    time.sleep(delay)
    if proc.poll() is None:
        proc.send_signal(sig)
    _, err = proc.communicate(timeout=300)
    return proc.returncode, err


def check(case: Case, before: dict, code: int, err: str, sig: int | None) -> list[str]:
    probs = []
    # a signal may also land before ptailor installs its handler (while Python imports)
    # or after the command restored the default one: then the process dies of it (-sig)
    ok_codes = {0, 2} | ({128 + sig, -sig} if sig else set())
    lines = err.strip().splitlines()
    startup = (  # SIGINT while Python starts and imports, before ptailor's handler exists
        sig == signal.SIGINT
        and code == 1
        and lines
        and lines[-1] == "KeyboardInterrupt"
        and "in invoke" not in err  # (imports, not the command: nothing written yet)
    )
    if code not in ok_codes and not startup:
        probs.append(f"exit {code}: {err.strip()[-300:]}")
    if code == 2:
        lines = err.splitlines()
        if len(lines) != 1:
            probs.append(f"{len(lines)} lines on stderr: {lines[:3]}")
        if ".tmp" in err:
            probs.append(f"message names a staging folder: {err.strip()}")
    after = snapshot(case.root)
    replaceable = {str(p.relative_to(case.root)) for p in case.ptailor_files}
    for rel, val in before.items():
        if rel in replaceable:
            continue
        if rel not in after:
            probs.append(f"lost {rel}")
        elif after[rel] != val and val is not None:
            probs.append(f"changed {rel}")
    left = staging_under(case.root)
    if left:
        probs.append(f"staging left: {left}")
    if code == 0:
        real = Path(os.path.realpath(case.cwd / case.out if case.cwd else case.out))
        if read_marker(real) is None or not (real / "report.json").is_file():
            probs.append("exit 0 without a marker and report")
    return probs


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", type=int, default=500)
    ap.add_argument("--seed", type=int, default=12)
    ap.add_argument("--signal-rate", type=float, default=0.1)
    ap.add_argument("--keep", type=Path, default=None, help="work here and keep it")
    a = ap.parse_args(argv)
    rng = random.Random(a.seed)
    work = Path(tempfile.mkdtemp(prefix="ptailor-fuzz-")) if a.keep is None else a.keep
    work.mkdir(parents=True, exist_ok=True)
    small = work / "small.obj"
    write_garment(small, lantern_sleeve(n_around=8, n_sleeve=3, n_cuff=1))
    medium = work / "medium.obj"
    write_garment(medium, sample_for_triangles(8000))
    (work / "r.yaml").write_text(RECIPE)
    r = CliRunner().invoke(
        cli, ["adjust", str(small), str(work / "r.yaml"), "-o", str(work / "_ref"), *FAST]
    )
    assert r.exit_code == 0, r.output
    tally: collections.Counter = collections.Counter()
    failures = 0
    t0 = time.perf_counter()
    for i in range(a.cases):
        state = rng.choice(STATES)
        sig = None
        if rng.random() < a.signal_rate:
            sig = rng.choice([signal.SIGTERM, signal.SIGINT])
        delay = rng.uniform(0.0, 2.5)
        root = work / f"c{i:04d}"
        root.mkdir()
        case = Case(root, medium if sig else small, rng, state)
        case.build()
        before = snapshot(root)
        code, err = run_case(case, sig, delay)
        probs = check(case, before, code, err, sig)
        kind = f"{state}{'+' + signal.Signals(sig).name if sig else ''}"
        tally[(kind, code)] += 1
        if probs:
            failures += 1
            print(f"FAIL case {i} seed {a.seed} {kind}: {'; '.join(probs)}", flush=True)
        elif a.keep is None:
            for p in root.rglob("*"):  # (a read-only or odd tree must still go)
                if p.is_dir() and not p.is_symlink():
                    p.chmod(0o755)
            shutil.rmtree(root)
    secs = time.perf_counter() - t0
    by_code = collections.Counter()
    for (_, code), n in tally.items():
        by_code[code] += n
    print(
        json.dumps(
            {
                "seed": a.seed,
                "cases": a.cases,
                "failing_cases": failures,
                "exit_codes": {str(k): v for k, v in sorted(by_code.items())},
                "signals_sent": sum(n for (k, _), n in tally.items() if "+SIG" in k),
                "seconds": round(secs, 1),
            }
        )
    )
    for (kind, code), n in sorted(tally.items()):
        print(f"  {kind:<28} exit {code:>3}: {n}")
    if a.keep is None and not failures:
        shutil.rmtree(work, ignore_errors=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
