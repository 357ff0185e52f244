"""Specifications at production resolution: matching, carrying and checking on tee6 at 1x,
16x and 64x triangles.

    python bench/bench_spec.py [--levels 0,2,3] [--repeat 3] [--out FILE]

tee6 (``../shared/garments/gpg_tee6``, or ``$PTAILOR_SHARED``) is subdivided by
``bench/subdivide.py`` (each level splits every triangle in four: the same garment). Per
level and recipe (identity, one sleeve 1.1 around, shorten the hem by 5 on the pattern),
recorded: the median seconds of matching the specification to the garment
(:func:`ptailor.run.spec.matched_specification`) and of writing and checking the adjusted
specification (:func:`ptailor.run.spec.spec_outputs`), beside the adjustment's own seconds;
the written specification's largest vertex distance from the 1x one (cm); and the check's
``fit_max``. Prints a table and writes ``bench/results/spec.json`` (git-ignored).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from subdivide import subdivide_obj
from timing import machine, median

RECIPES = {
    "identity": "units: cm\nsteps: []\n",
    "sleeve 1.1": "units: cm\nsteps:\n  - op: scale\n    region: {panels: [sleeve_left]}\n"
    "    direction: around\n    axis: auto\n    factor: 1.1\n",
    "shorten 5": "units: cm\nsteps:\n  - op: shorten\n    opening: hem\n    by: 5\n"
    "    measure: pattern\n",
}


def _timed(fn, repeat: int):
    """``fn()``'s result and its median seconds over ``repeat`` calls."""
    out, times = None, []
    for _ in range(repeat):  # a loop over repeats
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return out, median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--levels", default="0,2,3")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--out", default=str(Path(__file__).parent / "results" / "spec.json"))
    args = ap.parse_args()
    from ptailor.formats.garment import load_garment
    from ptailor.formats.spec_json import read_specification
    from ptailor.pipeline import adjustment
    from ptailor.recipe import parse_recipe
    from ptailor.run.spec import matched_specification, spec_outputs

    shared = Path(os.environ.get("PTAILOR_SHARED", Path(__file__).parents[2] / "shared"))
    src = shared / "garments" / "gpg_tee6" / "tee6_sim.obj"
    spec = read_specification(src.with_name("tee6_specification.json"))
    rows, first = [], {}
    with tempfile.TemporaryDirectory() as tmp:
        for level in (int(x) for x in args.levels.split(",")):  # a loop over resolutions
            path = Path(tmp) / f"tee6_x{4**level}.obj"
            if level:
                subdivide_obj(src, path, levels=level)
            else:
                path = src
            loaded = load_garment(path, pattern_units="0.3333cm", drape_units="0.3333cm")
            n = loaded.garment.n_faces
            matching, t_match = _timed(
                lambda loaded=loaded: matched_specification(loaded, spec), args.repeat
            )
            for name, text in RECIPES.items():  # a loop over recipes
                recipe = parse_recipe(text, source=f"{name}.yaml")
                t = time.perf_counter()
                adj = adjustment(loaded.garment, recipe, baseline=False)
                t_adj = time.perf_counter() - t
                out = Path(tmp) / f"out_{level}_{name}"
                out.mkdir()
                (_, section, _), t_out = _timed(
                    lambda out=out, adj=adj, m=matching: spec_outputs(out, adj, m), args.repeat
                )
                written = json.loads((out / "specification.json").read_text())
                V = np.vstack(
                    [np.array(p["vertices"]) for p in written["pattern"]["panels"].values()]
                )
                first.setdefault(name, V)
                same = first[name].shape == V.shape
                drift = float(np.abs(V - first[name]).max()) / 3.0 if same else float("nan")
                rows.append(
                    {
                        "triangles": n,
                        "recipe": name,
                        "match_s": round(t_match, 3),
                        "spec_out_s": round(t_out, 3),
                        "adjust_s": round(t_adj, 3),
                        "fit_max_cm": section["fit_max"],
                        "vs_1x_cm": round(drift, 4),
                    }
                )
                r = rows[-1]
                print(
                    f"{n:>7} {name:<11} match {r['match_s']:6.2f} s  spec out "
                    f"{r['spec_out_s']:6.2f} s  adjust {r['adjust_s']:6.2f} s  fit "
                    f"{r['fit_max_cm']:.3f} cm  vs 1x {r['vs_1x_cm']:.4f} cm",
                    flush=True,
                )
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps({"machine": machine(), "rows": rows}, indent=2))
    print(f"wrote {args.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
