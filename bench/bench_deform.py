"""Benchmark of :func:`ptailor.method.deform.arap_deform`.

A cylinder of about 100,000 triangles; its bottom third is scaled by 1.2 around the axis
(those vertices are the handles, with the top ring held fixed) and the rest follows with
10 as-rigid-as-possible iterations. Prints the median wall time over 5 runs.

Run: ``python bench/bench_deform.py``
"""

from __future__ import annotations

import statistics
import time

import numpy as np

from ptailor.method.deform import arap_deform
from ptailor.samples import cylinder


def main() -> None:
    g = cylinder(n_around=250, n_along=200)  # 100,000 triangles, axis y
    V, F = g.V3, g.F3
    y = V[:, 1]
    handles = np.flatnonzero((y <= y.max() / 3.0 + 1e-9) | (y >= y.max() - 1e-9))
    Q = V[handles].copy()
    low = y[handles] < y.max() / 2.0
    Q[low, 0] *= 1.2
    Q[low, 2] *= 1.2
    times = []
    for _ in range(5):
        t0 = time.perf_counter()
        arap_deform(V, F, handles, Q, iterations=10, tol=0.0)
        times.append(time.perf_counter() - t0)
    print(
        f"arap_deform: {len(V)} vertices, {len(F)} triangles, {len(handles)} handles, "
        f"10 iterations: median {statistics.median(times):.3f} s over 5 runs "
        f"(min {min(times):.3f} s)"
    )


if __name__ == "__main__":
    main()
