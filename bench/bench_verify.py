"""Re-drape speed: seconds per solver step of ``ptailor.verify.engine.redrape``.

A cylinder sample (``ptailor.samples.cylinder``, 30 cm around, 20 cm long; its pattern is its
own rest) is hung by its top ring and stepped without the settle test, twice (``--short`` and
``--long`` steps): the difference over the extra steps is the time per step, free of the
model build; the build (plus the short run) is reported too. Medians of ``--repeat`` runs,
with cloth-cloth contact on (the default) and off. ``--compile`` also times the first call
with an empty warp kernel cache, in a subprocess (what a fresh machine pays once).

Run: ``pip install -e '.[sim]'`` then ``python bench/bench_verify.py [--triangles 5000 20000]``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from ptailor.model.frame import Frame

ROOT = Path(__file__).resolve().parents[1]


def tube(n_triangles: int):
    """A cylinder sample with about ``n_triangles`` triangles, its rest and its top ring."""
    from ptailor.geometry.triangles import edge_matrices
    from ptailor.samples import cylinder
    from ptailor.verify.measure import top_opening

    n_along = max(round(np.sqrt(n_triangles / 2 / 1.5)), 2)
    n_around = max(round(n_triangles / 2 / n_along), 3)
    g = cylinder(circumference=30.0, height=20.0, n_around=n_around, n_along=n_along)
    rest = edge_matrices(g.V2, g.F2)
    return g, rest, top_opening(g.V3, g.F3, frame=Frame())


def run_seconds(g, rest, pinned, settings) -> float:
    from ptailor.verify.engine import redrape

    t0 = time.perf_counter()
    redrape(g.V3, g.F3, rest, units_m=0.01, pinned=pinned, settings=settings)
    return time.perf_counter() - t0


def per_step(n_triangles: int, *, short: int, long: int, repeat: int, self_collision: bool):
    from ptailor.verify.engine import Settings

    g, rest, pinned = tube(n_triangles)
    base = replace(Settings(), settle_speed=0.0, self_collision=self_collision)
    a = [run_seconds(g, rest, pinned, replace(base, max_steps=short)) for _ in range(repeat)]
    b = [run_seconds(g, rest, pinned, replace(base, max_steps=long)) for _ in range(repeat)]
    step = (statistics.median(b) - statistics.median(a)) / (long - short)
    return {"triangles": len(g.F3), "self_collision": self_collision,
            "s_per_step": step, "build_plus_short_s": statistics.median(a)}  # fmt: skip


def first_compile_seconds() -> float:
    """Wall time of one small re-drape in a fresh process with an empty kernel cache."""
    here = str(Path(__file__).parent)
    code = (
        f"import time, sys; sys.path.insert(0, {here!r}); import bench_verify as b;"
        "from ptailor.verify.engine import Settings;"
        "g, r, p = b.tube(500); t = time.perf_counter();"
        "b.run_seconds(g, r, p, Settings(max_steps=5)); print(time.perf_counter() - t)"
    )
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "WARP_CACHE_PATH": cache}
        out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                             text=True, check=True)  # fmt: skip
    return float(out.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--triangles", type=int, nargs="+", default=[5000, 20000])
    ap.add_argument("--short", type=int, default=20)
    ap.add_argument("--long", type=int, default=120)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--compile", action="store_true", help="also time a first compile")
    args = ap.parse_args()
    from ptailor.verify.engine import engine_available

    if not engine_available():
        sys.exit("bench_verify: the cloth engine is not installed: pip install -e '.[sim]'")
    rows = []
    for n in args.triangles:
        for sc in (True, False):
            r = per_step(n, short=args.short, long=args.long, repeat=args.repeat,
                         self_collision=sc)  # fmt: skip
            rows.append(r)
            print(f"{r['triangles']:>7} triangles  cloth-cloth {'on ' if sc else 'off'}  "
                  f"{1000 * r['s_per_step']:7.1f} ms/step  build + {args.short} steps "
                  f"{r['build_plus_short_s']:6.2f} s", flush=True)  # fmt: skip
    result = {"rows": rows}
    if args.compile:
        result["first_compile_s"] = first_compile_seconds()
        print(f"first call with an empty kernel cache: {result['first_compile_s']:.1f} s")
    out = ROOT / "bench" / "results" / "verify.json"
    out.parent.mkdir(exist_ok=True)
    out.write_text(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
