"""Benchmark ``ptailor batch``: throughput and the overhead of the batch machinery.

    python bench/bench_batch.py [--garments 100] [--jobs 2] [--no-reference] [--shell]
                                [--keep DIR]

Writes ``--garments`` lantern sleeves (``ptailor.samples.sample_for_triangles(n)``, n drawn
from 5,000 to 30,000 triangles with a seeded RNG) once to a temporary folder, then runs
``ptailor batch RECIPE '*.obj' -o OUT -j JOBS -q --log L`` as a subprocess with the one-step
recipe below (all outputs, baseline included) and reports garments per minute and the
overhead of the batch machinery (interpreter start-up, imports, worker start-up and
warm-up, dispatch, result collection, idle workers at the end):

- **against in-worker time**: ``overhead = 1 - sum(record seconds) / (wall x workers)``,
  where a record's ``seconds`` is the whole job in its worker (hashing, stamp check and
  ``run_garment``);
- **against in-process time** (unless ``--no-reference``): ``run_garment`` on every garment
  one after the other in one process (imports paid before timing, one BLAS thread like a
  worker), ``overhead = 1 - (sum / workers) / wall``. This one also counts the slowdown of
  two adjustments sharing the machine (memory bandwidth, caches), not the machinery's;
- **CPU time**: the CPU time of the batch's processes (``RUSAGE_CHILDREN``) against the
  in-process runs' CPU time (less sensitive to other load on the machine).

``--shell`` also times ``cli/adjust-parallel`` (one ``ptailor adjust`` process per garment,
``--jobs`` at a time) on the same garments, for comparison.

Target (issue 6): overhead under 10 % of the total. Writes ``bench/results/batch.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from ptailor.formats.obj import write_garment
from ptailor.samples import sample_for_triangles

RECIPE = "steps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.2}]\n"
#: in a subprocess (one BLAS thread, like a worker): run_garment on every garment in turn,
#: after one untimed run (imports, first calls); prints [wall seconds, CPU seconds]
REFERENCE = """
import json, sys, time
from pathlib import Path
from ptailor.run.garment import run_garment
from ptailor.recipe import load_recipe
recipe, cat, out, n = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3]), int(sys.argv[4])
rec = load_recipe(recipe)
run_garment(str(cat / "g000.obj"), rec, out / "warm")
wall = cpu = 0.0
for k in range(n):
    t0, c0 = time.perf_counter(), time.process_time()
    run_garment(str(cat / f"g{k:03d}.obj"), rec, out / f"g{k:03d}")
    wall += time.perf_counter() - t0
    cpu += time.process_time() - c0
print(json.dumps([wall, cpu]))
"""
RESULTS = Path(__file__).resolve().parent / "results" / "batch.json"


def write_catalogue(folder: Path, n: int, lo: int, hi: int, seed: int) -> list[int]:
    """``n`` garments g000.obj ... in ``folder``; returns their triangle counts."""
    rng = np.random.default_rng(seed)
    sizes = rng.integers(lo, hi + 1, size=n)
    counts = []
    for k, size in enumerate(sizes):
        g = sample_for_triangles(int(size))
        write_garment(folder / f"g{k:03d}.obj", g)
        counts.append(int(g.n_faces))
    return counts


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--garments", type=int, default=100)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--min-triangles", type=int, default=5000)
    ap.add_argument("--max-triangles", type=int, default=30000)
    ap.add_argument("--seed", type=int, default=6)
    ap.add_argument("--no-reference", action="store_true", help="skip the in-process runs")
    ap.add_argument("--keep", default=None, help="work in this folder and keep it")
    ap.add_argument(
        "--shell", action="store_true", help="also time cli/adjust-parallel (a process each)"
    )
    args = ap.parse_args()

    with tempfile.TemporaryDirectory(prefix="ptailor-bench-batch-") as td:
        root = Path(args.keep) if args.keep else Path(td)
        cat, out = root / "garments", root / "out"
        cat.mkdir(parents=True, exist_ok=True)
        t0 = time.perf_counter()
        counts = write_catalogue(
            cat, args.garments, args.min_triangles, args.max_triangles, args.seed
        )
        print(
            f"{args.garments} lantern sleeves, {min(counts)} to {max(counts)} triangles "
            f"(total {sum(counts)}), written in {time.perf_counter() - t0:.1f} s"
        )
        recipe = root / "recipe.yaml"
        recipe.write_text(RECIPE)
        log = root / "batch.jsonl"
        cmd = [
            sys.executable,
            "-m",
            "ptailor",
            "batch",
            str(recipe),
            str(cat / "*.obj"),
            "-o",
            str(out),
            "-j",
            str(args.jobs),
            "-q",
            "--force",
            "--log",
            str(log),
        ]
        t0 = time.perf_counter()
        ru0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        r = subprocess.run(cmd, capture_output=True, text=True)
        ru1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        wall = time.perf_counter() - t0
        cpu_batch = (ru1.ru_utime - ru0.ru_utime) + (ru1.ru_stime - ru0.ru_stime)
        if r.returncode != 0:
            sys.exit(f"ptailor batch failed ({r.returncode}):\n{r.stderr}")
        recs = [json.loads(ln) for ln in log.read_text().splitlines()]
        assert all(x["status"] == "ok" for x in recs), "every garment should succeed"
        in_worker = sum(x["seconds"] for x in recs)
        n = len(recs)
        capacity = wall * args.jobs
        overhead = 1.0 - in_worker / capacity
        per_garment = (capacity - in_worker) / n
        rate = 60.0 * n / wall
        print(f"ptailor batch -j {args.jobs}: {wall:.1f} s wall, {rate:.1f} garments/min")
        print(
            f"  in-worker jobs: {in_worker:.1f} s summed, {in_worker / n:.3f} s per garment; "
            f"wall x workers {capacity:.1f} s"
        )
        flag = "ok" if overhead < 0.10 else "OVER 10 %"
        print(
            f"  machinery overhead: {100 * overhead:.1f} % of wall x workers "
            f"({per_garment * 1e3:.0f} ms per garment) [target < 10 %: {flag}]"
        )
        result = {
            "date": time.strftime("%Y-%m-%d"),
            "platform": platform.platform(),
            "python": platform.python_version(),
            "cpus": os.cpu_count(),
            "garments": n,
            "triangles": {"min": min(counts), "max": max(counts), "total": sum(counts)},
            "jobs": args.jobs,
            "wall_s": round(wall, 3),
            "garments_per_min": round(rate, 2),
            "in_worker_s": round(in_worker, 3),
            "overhead_vs_in_worker": round(overhead, 4),
        }
        if not args.no_reference:
            env = dict(os.environ)
            for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
                env.setdefault(var, "1")  # as in the batch's worker processes
            r = subprocess.run(
                [sys.executable, "-c", REFERENCE, str(recipe), str(cat), str(root / "ref"), str(n)],
                capture_output=True,
                text=True,
                env=env,
                check=True,
            )
            t_ref, cpu_ref = json.loads(r.stdout)
            ideal = t_ref / args.jobs
            over_ref = 1.0 - ideal / wall
            flag = "ok" if over_ref < 0.10 else "OVER 10 %"
            print(
                f"in-process run_garment, one after the other: {t_ref:.1f} s "
                f"({t_ref / n:.3f} s per garment); / {args.jobs} workers = {ideal:.1f} s"
            )
            print(
                f"  overhead against it: {100 * over_ref:.1f} % of the batch's wall time "
                f"(includes two adjustments sharing the machine) [target < 10 %: {flag}]"
            )
            over_cpu = 1.0 - cpu_ref / cpu_batch
            print(
                f"CPU time: batch (all its processes) {cpu_batch:.1f} s, in-process run_garment "
                f"{cpu_ref:.1f} s: machinery {100 * over_cpu:.1f} % of the batch's CPU time"
            )
            result.update(
                in_process_s=round(t_ref, 3),
                overhead_vs_in_process=round(over_ref, 4),
                cpu_batch_s=round(cpu_batch, 3),
                cpu_in_process_s=round(cpu_ref, 3),
                cpu_overhead=round(over_cpu, 4),
            )
        if args.shell:
            script = Path(__file__).resolve().parents[1] / "cli" / "adjust-parallel"
            env = dict(os.environ, JOBS=str(args.jobs), PTAILOR=f"{sys.executable} -m ptailor")
            listing = "".join(f"{cat / f'g{k:03d}.obj'}\n" for k in range(n))
            t0 = time.perf_counter()
            subprocess.run(
                [str(script), str(recipe), str(root / "shell")],
                input=listing,
                capture_output=True,
                text=True,
                env=env,
                check=True,
            )
            t_shell = time.perf_counter() - t0
            print(
                f"cli/adjust-parallel (one ptailor adjust process per garment, {args.jobs} at a "
                f"time): {t_shell:.1f} s, {60.0 * n / t_shell:.1f} garments/min"
            )
            result.update(shell_s=round(t_shell, 3))
        RESULTS.parent.mkdir(exist_ok=True)
        RESULTS.write_text(json.dumps(result, indent=2) + "\n")
        print(f"wrote {RESULTS}")


if __name__ == "__main__":
    main()
