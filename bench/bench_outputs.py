"""Benchmark the pattern outputs against a whole ``adjust`` on a 100,000-triangle garment.

    python bench/bench_outputs.py [--triangles 100000] [--repeat 5]

On ``ptailor.samples.sample_for_triangles`` scaled 1.2 around its axis, times (medians
over the repeats) the in-process ``adjust`` (edit, flatten, baseline), then each output
stage on its result: the piece plan (mesh pieces and notches), carrying the pieces
through the adjustment, writing ``pattern.dxf``, reading it back, ``pattern.svg`` and
``preview.png``, and the ezdxf import. Target (issue 5): DXF writing and reading under
10 % of the ``adjust`` run.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path
from types import SimpleNamespace

from ptailor.model.garment import panels
from ptailor.pieces import adjusted_pieces, piece_plan
from ptailor.pipeline import adjustment
from ptailor.recipe import parse_recipe
from ptailor.report.build import triangle_errors
from ptailor.run.outputs import OutputContext, output_dxf, output_png, output_svg
from ptailor.samples import sample_for_triangles
from timing import median_time

RECIPE = "steps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.2}]"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--triangles", type=int, default=100_000)
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    g = sample_for_triangles(args.triangles)
    rec = parse_recipe(RECIPE)
    print(f"lantern sleeve, {g.n_faces} triangles; medians of {args.repeat} runs")
    t_adjust = median_time(lambda: adjustment(g, rec), args.repeat)
    adj = adjustment(g, rec)
    plan = piece_plan(g, panels(g))
    carried = adjusted_pieces(adj, plan)
    errors = triangle_errors(adj)

    loaded = SimpleNamespace(pattern=None, inputs={"garment": "bench.obj"})  # what they read
    ctx = OutputContext(loaded=loaded, pieces=carried, plan=plan, errors=errors)
    rows = {
        "piece plan": lambda: piece_plan(g, panels(g)),
        "carry pieces": lambda: adjusted_pieces(adj, plan),
    }
    with tempfile.TemporaryDirectory() as td:
        tmp = Path(td)
        output_dxf(tmp, adj, ctx)
        from ptailor.formats.dxf import read_dxf

        rows["write pattern.dxf"] = lambda: output_dxf(tmp, adj, ctx)
        rows["read pattern.dxf"] = lambda: read_dxf(tmp / "pattern.dxf")
        rows["write pattern.svg"] = lambda: output_svg(tmp, adj, ctx)
        rows["write preview.png"] = lambda: output_png(tmp, adj, ctx)
        n_pts = sum(len(c.piece.outline) for c in carried if c is not None)
        size = (tmp / "pattern.dxf").stat().st_size
        print(f"adjust (in-process)    {t_adjust:7.3f} s")
        times = {}
        for name, fn in rows.items():
            times[name] = median_time(fn, args.repeat)
            print(f"{name:<22} {times[name]:7.3f} s  {100 * times[name] / t_adjust:5.1f} %")
        svg_mb = (tmp / "pattern.svg").stat().st_size / 1e6
        # the whole command, as a user runs it: OBJ in, every format out
        from ptailor.formats.obj import write_garment

        write_garment(tmp / "g.obj", g, header=["bench garment, cm"])
        (tmp / "r.yaml").write_text(RECIPE + "\n")
        cmd = ["ptailor", "adjust", str(tmp / "g.obj"), str(tmp / "r.yaml"), "-q"]
        t_cli = median_time(
            lambda: subprocess.run([*cmd, "-o", str(tmp / "cli")], check=True), args.repeat
        )
        print(f"ptailor adjust (CLI)   {t_cli:7.3f} s  (subprocess, all formats)")
    code = "import time; t = time.perf_counter(); import ezdxf; print(time.perf_counter() - t)"
    imp = statistics.median(
        float(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True).stdout)
        for _ in range(args.repeat)
    )
    dxf_share = times["write pattern.dxf"] + times["read pattern.dxf"] + imp
    print(f"import ezdxf           {imp:7.3f} s")
    print(f"outline points {n_pts}, pattern.dxf {size / 1e3:.0f} kB, pattern.svg {svg_mb:.1f} MB")
    flag = "ok" if dxf_share <= 0.1 * t_cli else "OVER 10 %"
    print(
        f"DXF write + read + ezdxf import: {dxf_share:.3f} s = {100 * dxf_share / t_cli:.1f} % "
        f"of the CLI run, {100 * dxf_share / t_adjust:.1f} % of the in-process adjust [{flag}]"
    )


if __name__ == "__main__":
    main()
