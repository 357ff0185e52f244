"""Benchmark of ``ptailor adjust`` on a generated lantern sleeve, with libigl's ARAP alongside.

Measures, as medians over ``--repeat`` runs on ``sample_for_triangles(--triangles)``, with the
drape scaled 1.2 around the y axis (x and z times 1.2):

1. ``ptailor.method.flatten.flatten`` alone (every panel as-similar-as-possible), its
   iteration count, and where its time goes: targets, stitch set-up (operators, matrix),
   ``stitch.factor`` (sparse LU), the local/global iterations (including back-substitution),
   the final rigid fit. The split comes from wrapping the module-level functions at run time;
   ``src/`` is not touched. A second row forces 30 iterations (so the per-iteration cost
   compares with libigl's 30): the zero-energy and relative-change stops are switched off
   for that row only.
2. libigl's ARAP parametrisation of the same mesh: ``arap_precomputation`` (dim 2, the
   default energy = per-triangle "elements" for dim 2) and ``arap_solve`` with
   ``max_iter = 30``. libigl needs one mesh, so the drape is re-indexed like the pattern:
   ``V = V3_edit[to3]`` with ``to3`` mapping each pattern vertex to its drape vertex through
   the F2 -> F3 corner correspondence, ``F = F2``, initial guess the original pattern.
   One vertex is pinned *per panel* (the sleeve has two disconnected panels; with a single
   pin libigl's Cholesky fails on the unconstrained panel).
3. The whole ``ptailor adjust garment.obj recipe.yaml -o OUT`` as a subprocess (start-up
   included), with and without ``--no-baseline``, and the report's ``timing_s`` split.
4. ``ptailor --help`` as a subprocess (median of ``--help-repeat``).

Prints a table, writes ``bench/results/adjust.json``. ``--profile`` also runs the adjust
command once in-process under cProfile and prints the hottest functions.

Run: ``python bench/bench_adjust.py [--triangles 100000] [--repeat 5] [--profile]``
"""

from __future__ import annotations

import argparse
import contextlib
import cProfile
import datetime as dt
import io
import json
import pstats
import shutil
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from ptailor.formats.obj import write_garment
from ptailor.method import flatten as flatten_mod
from ptailor.method.flatten import central_vertices, flatten
from ptailor.method.solver import problem as stitch_mod
from ptailor.model.garment import Garment, panels, vertex_labels
from ptailor.samples import sample_for_triangles
from timing import LIBIGL_ITERATIONS, libigl_arap, machine, median, ptailor_command, run_cli

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results" / "adjust.json"
SCALE = 1.2
RECIPE = (
    "units: cm\nsteps:\n  - {op: scale, region: all, direction: around, axis: auto, factor: 1.2}\n"
)
TARGETS = {"flatten_vs_libigl": 1.0, "adjust_s": 4.0, "help_s": 0.3}


def edited_drape(g: Garment) -> np.ndarray:
    """The drape scaled ``SCALE`` around the y axis (x and z)."""
    return g.V3 * np.array([SCALE, 1.0, SCALE])


# ---------------------------------------------------------------------------------------
# 1. ptailor's flatten
# ---------------------------------------------------------------------------------------


@contextlib.contextmanager
def instrumented(marks: dict[str, float], counts: dict[str, int]):
    """Wrap flatten's and stitch's module-level helpers to time them (src/ untouched)."""
    saved = {
        (flatten_mod, "intrinsic_targets"): flatten_mod.intrinsic_targets,
        (flatten_mod, "stitch"): flatten_mod.stitch,
        (flatten_mod, "rigid_fit_groups"): flatten_mod.rigid_fit_groups,
        (stitch_mod, "factor"): stitch_mod.factor,
    }

    def timed(key: str, fn):
        def wrapper(*args, **kwargs):
            marks[key + ".start"] = time.perf_counter()
            out = fn(*args, **kwargs)
            marks[key + ".end"] = time.perf_counter()
            return out

        return wrapper

    def factor(A, **kwargs):
        marks["factor.start"] = time.perf_counter()
        solve = saved[(stitch_mod, "factor")](A, **kwargs)
        marks["factor.end"] = time.perf_counter()

        def counted_solve(b):
            t = time.perf_counter()
            x = solve(b)
            marks["solves"] = marks.get("solves", 0.0) + time.perf_counter() - t
            counts["solves"] = counts.get("solves", 0) + 1
            return x

        return counted_solve

    flatten_mod.intrinsic_targets = timed("targets", saved[(flatten_mod, "intrinsic_targets")])
    flatten_mod.stitch = timed("stitch", saved[(flatten_mod, "stitch")])
    flatten_mod.rigid_fit_groups = timed("rigid_fit", saved[(flatten_mod, "rigid_fit_groups")])
    stitch_mod.factor = factor
    try:
        yield
    finally:
        for (mod, name), fn in saved.items():
            setattr(mod, name, fn)


def bench_flatten(g: Garment, V3e: np.ndarray, repeat: int) -> dict:
    plist = panels(g)
    asap = np.ones(len(plist), dtype=bool)
    total, iters = [], []
    for _ in range(repeat):
        t0 = time.perf_counter()
        res = flatten(g, V3e, asap_panels=asap)
        total.append(time.perf_counter() - t0)
        iters.append(res.info.iterations)

    split: dict[str, list[float]] = {}
    n_solves = []
    for _ in range(repeat):
        marks: dict[str, float] = {}
        counts: dict[str, int] = {}
        with instrumented(marks, counts):
            t0 = time.perf_counter()
            flatten(g, V3e, asap_panels=asap)
            t1 = time.perf_counter()
        parts = {
            "targets": marks["targets.end"] - marks["targets.start"],
            "stitch_setup": marks["factor.start"] - marks["stitch.start"],
            "factor": marks["factor.end"] - marks["factor.start"],
            "iterations": marks["stitch.end"] - marks["factor.end"],
            "solves_in_iterations": marks["solves"],
            "rigid_fit": marks["rigid_fit.end"] - marks["rigid_fit.start"],
            "instrumented_total": t1 - t0,
        }
        parts["other"] = parts["instrumented_total"] - (
            parts["targets"]
            + parts["stitch_setup"]
            + parts["factor"]
            + parts["iterations"]
            + parts["rigid_fit"]
        )
        for k, v in parts.items():
            split.setdefault(k, []).append(v)
        n_solves.append(counts["solves"])

    forced, forced_iters = [], []
    for _ in range(repeat):  # plain iterations (no Anderson), no early stop, like libigl's
        t0 = time.perf_counter()
        res = flatten(
            g, V3e, asap_panels=asap, max_iter=LIBIGL_ITERATIONS, step_tol=-1.0, history=0
        )
        forced.append(time.perf_counter() - t0)
        forced_iters.append(res.info.iterations)

    return {
        "median_s": median(total),
        "min_s": min(total),
        "iterations": iters[0],
        "iterations_all_runs": iters,
        "linear_solves": n_solves[0],
        "split_median_s": {k: median(v) for k, v in split.items()},
        "forced_30": {"median_s": median(forced), "iterations": forced_iters[0]},
    }


# ---------------------------------------------------------------------------------------
# 2. libigl's ARAP parametrisation
# ---------------------------------------------------------------------------------------


def bench_libigl(g: Garment, V3e: np.ndarray, repeat: int) -> dict:
    plist = panels(g)
    pins = central_vertices(g.V2, vertex_labels(plist, len(g.V2)), len(plist))
    res = libigl_arap(V3e, g.F3, g.V2, g.F2, pins, repeat)
    if "error" in res:
        return res
    U = res.pop("U")
    res["panel_widths_cm"] = {
        p.name: {
            "pattern": float(np.ptp(g.V2[p.vertices, 0])),
            "libigl": float(np.ptp(U[p.vertices, 0])),
        }
        for p in plist
    }
    return res


# ---------------------------------------------------------------------------------------
# 3, 4. the command line
# ---------------------------------------------------------------------------------------


def write_inputs(g: Garment, folder: Path) -> tuple[Path, Path]:
    garment = folder / "garment.obj"
    write_garment(garment, g, header=["ptailor benchmark: lantern sleeve", "units: cm"])
    recipe = folder / "recipe.yaml"
    recipe.write_text(RECIPE)
    return garment, recipe


def bench_cli(garment: Path, recipe: Path, folder: Path, repeat: int, extra: list[str]) -> dict:
    wall, split = [], {}
    for i in range(repeat):
        out = folder / f"out-{'-'.join(extra) or 'default'}-{i}"
        wall.append(run_cli(["adjust", str(garment), str(recipe), "-o", str(out), "-q", *extra]))
        timing = json.loads((out / "report.json").read_text())["timing_s"]
        timing["untimed"] = wall[-1] - sum(timing.values())
        for k, v in timing.items():
            split.setdefault(k, []).append(v)
        shutil.rmtree(out)
    return {
        "median_s": median(wall),
        "min_s": min(wall),
        "timing_s_median": {k: median(v) for k, v in split.items()},
    }


def profile_adjust(garment: Path, recipe: Path, folder: Path, top: int = 30) -> str:
    """cProfile one in-process ``ptailor adjust``; the hottest functions by cumulative time."""
    from ptailor.cli.main import cli

    out = folder / "out-profile"
    prof = cProfile.Profile()
    prof.enable()
    with contextlib.suppress(SystemExit):
        cli.main(["adjust", str(garment), str(recipe), "-o", str(out), "-q"], "ptailor")
    prof.disable()
    buf = io.StringIO()
    pstats.Stats(prof, stream=buf).sort_stats("cumulative").print_stats(top)
    shutil.rmtree(out, ignore_errors=True)
    return buf.getvalue()


# ---------------------------------------------------------------------------------------
# report
# ---------------------------------------------------------------------------------------


def verdict(value: float, limit: float) -> str:
    return "ok" if value <= limit else "MISSED"


def print_table(res: dict) -> None:
    fl, ig, cli = res["flatten"], res["libigl"], res["cli"]
    g = res["garment"]
    print(
        f"lantern sleeve: {g['triangles']} triangles, {g['drape_vertices']} drape / "
        f"{g['pattern_vertices']} pattern vertices; medians of {res['repeat']} runs"
    )
    rows = [
        ("ptailor flatten", fl["median_s"], f"{fl['iterations']} iteration(s)"),
    ]
    for k, v in fl["split_median_s"].items():
        if k != "instrumented_total":
            note = "panels(), labels, pins, mirroring" if k == "other" else ""
            rows.append((f"  {k}", v, note))
    rows.append(
        (
            "ptailor flatten, 30 forced iter.",
            fl["forced_30"]["median_s"],
            f"{fl['forced_30']['iterations']} iteration(s)",
        )
    )
    if "error" in ig:
        rows.append(("libigl ARAP", float("nan"), ig["error"]))
    else:
        rows += [
            ("libigl ARAP (pre + 30 solves)", ig["median_s"], f"{ig['pins']} pins"),
            ("  arap_precomputation", ig["precomputation_median_s"], ""),
            ("  arap_solve, max_iter 30", ig["solve_30_median_s"], ""),
        ]
    for name, key in (("ptailor adjust", "default"), ("ptailor adjust --no-baseline", "nb")):
        rows.append((name, cli[key]["median_s"], "subprocess, start-up included"))
        for k, v in cli[key]["timing_s_median"].items():
            note = "start-up, imports, recipe, report, json" if k == "untimed" else ""
            rows.append((f"  timing_s.{k}" if k != "untimed" else "  untimed", v, note))
    rows.append(("ptailor --help", res["help"]["median_s"], f"median of {res['help']['runs']}"))
    width = max(len(r[0]) for r in rows)
    for name, secs, note in rows:
        print(f"{name:<{width}}  {secs:8.3f} s  {note}")
    print()
    for name, (value, limit) in res["targets"].items():
        print(f"target {name}: {value:.3f} (limit {limit}) {verdict(value, limit)}")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--triangles", type=int, default=100_000)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--help-repeat", type=int, default=10)
    ap.add_argument("--profile", action="store_true", help="cProfile one in-process adjust")
    ap.add_argument("--out", type=Path, default=RESULTS)
    args = ap.parse_args(argv)

    g = sample_for_triangles(args.triangles)
    V3e = edited_drape(g)
    res: dict = {
        "date": dt.datetime.now().astimezone().isoformat(timespec="seconds"),
        "machine": machine(),
        "repeat": args.repeat,
        "garment": {
            "sample": f"sample_for_triangles({args.triangles})",
            "triangles": int(g.n_faces),
            "drape_vertices": len(g.V3),
            "pattern_vertices": len(g.V2),
            "edit": f"scale {SCALE} around y (x, z times {SCALE})",
        },
    }
    res["flatten"] = bench_flatten(g, V3e, args.repeat)
    res["libigl"] = bench_libigl(g, V3e, args.repeat)
    with tempfile.TemporaryDirectory(prefix="ptailor-bench-") as td:
        folder = Path(td)
        garment, recipe = write_inputs(g, folder)
        res["cli"] = {
            "command": ptailor_command(),
            "default": bench_cli(garment, recipe, folder, args.repeat, []),
            "nb": bench_cli(garment, recipe, folder, args.repeat, ["--no-baseline"]),
        }
        helps = [run_cli(["--help"]) for _ in range(args.help_repeat)]
        res["help"] = {"median_s": median(helps), "runs": args.help_repeat}
        profile = profile_adjust(garment, recipe, folder) if args.profile else None

    targets = {
        "adjust_s": (res["cli"]["default"]["median_s"], TARGETS["adjust_s"]),
        "adjust_no_baseline_s": (res["cli"]["nb"]["median_s"], TARGETS["adjust_s"]),
        "help_s": (res["help"]["median_s"], TARGETS["help_s"]),
    }
    if "error" not in res["libigl"]:
        ratio = res["flatten"]["median_s"] / res["libigl"]["median_s"]
        res["flatten_over_libigl"] = ratio
        res["flatten_forced_30_over_libigl"] = (
            res["flatten"]["forced_30"]["median_s"] / res["libigl"]["median_s"]
        )
        targets = {"flatten_vs_libigl": (ratio, TARGETS["flatten_vs_libigl"]), **targets}
    res["targets"] = {k: list(v) for k, v in targets.items()}

    print_table(res)
    if "flatten_over_libigl" in res:
        print(
            f"ratio ptailor flatten / libigl ARAP: {res['flatten_over_libigl']:.2f} "
            f"(with 30 forced iterations: {res['flatten_forced_30_over_libigl']:.2f})"
        )
    if profile:
        print("\ncProfile of one in-process `ptailor adjust` (by cumulative time):")
        print(profile)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(res, indent=2) + "\n")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
