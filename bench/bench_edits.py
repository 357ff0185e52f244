"""Benchmark the surgery edits (shorten, cut) on a generated 100,000-triangle garment.

    python bench/bench_edits.py [--triangles 100000] [--repeat 5]

Times the edit step alone (``ptailor.adjust.apply_steps``: opening lookup, geodesic
distance, exact split, pattern transfer) and the whole in-process ``adjust`` with the
edit (flatten and baseline included), medians over the repeats. Targets from issues 3
and 4: each surgery edit and each deformation step within 2 s.
"""

from __future__ import annotations

import argparse

from ptailor.edits import EditOptions
from ptailor.pipeline import adjustment, apply_steps
from ptailor.recipe import parse_recipe
from ptailor.samples import sample_for_triangles
from timing import median_time

RECIPES = {
    "shorten hem by 5": "steps: [{op: shorten, opening: hem, by: 5}]",
    "cut plane y = 30": "steps: [{op: cut, plane: {point: [0, 30, 0], normal: [0, 1, 0]}}]",
    "cut sketch (front)": (
        "steps: [{op: cut, view: front, sketch: [[-30, 20], [0, 30], [30, 20]], remove: below}]"
    ),
    "scale cuff 1.3 (ARAP)": (
        "steps: [{op: scale, region: {panels: [cuff]}, direction: around, factor: 1.3}]"
    ),
    "loosen box by 2": (
        "steps: [{op: loosen, region: {box: {min: [-50, 18, -50], max: [50, 38, 50]}}, by: 2}]"
    ),
    "scale_seam 1.3": (
        "steps: [{op: scale_seam, seam: [sleeve, cuff], part: sleeve, factor: 1.3, fix: [waist]}]"
    ),
}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--triangles", type=int, default=100_000)
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    g = sample_for_triangles(args.triangles)
    print(f"lantern sleeve, {g.n_faces} triangles; medians of {args.repeat} runs")
    for name, text in RECIPES.items():
        rec = parse_recipe(text)
        t_edit = median_time(lambda r=rec: apply_steps(g, r, options=EditOptions()), args.repeat)
        t_all = median_time(lambda r=rec: adjustment(g, r), args.repeat)
        flag = "ok" if t_edit <= 2.0 else "OVER 2 s"
        print(f"{name:<22} edit {t_edit:6.3f} s  adjust {t_all:6.3f} s  [{flag}]")


if __name__ == "__main__":
    main()
