"""Benchmark of :func:`ptailor.method.geodesic.geodesic_distance`.

The default lantern sleeve refined to about 100,000 triangles
(``ptailor.samples.sample_for_triangles(100_000)``, drape ``V3``, ``F3``); the sources are
the bottom boundary ring (the cuff's hem). Prints the median wall time over 5 runs with
``limit=5`` (a 5 cm band, as when shortening near a hem) and with no limit (the whole
sleeve), and the largest error against the exact distance, the height above the hem.

Run: ``python bench/bench_geodesic.py``
"""

from __future__ import annotations

import statistics
import time

import numpy as np

from ptailor.method.geodesic import geodesic_distance
from ptailor.model.boundary import boundary_loops
from ptailor.samples import sample_for_triangles

REPEAT = 5


def main() -> None:
    g = sample_for_triangles(100_000)
    V, F = g.V3, g.F3
    loops = boundary_loops(F)
    hem = min(loops, key=lambda loop: float(V[loop, 1].mean()))
    print(f"{len(V)} vertices, {len(F)} triangles, {len(hem)} sources (the bottom ring)")
    exact = V[:, 1] - V[hem, 1].min()
    for limit in (5.0, np.inf):
        times = []
        for _ in range(REPEAT):
            t0 = time.perf_counter()
            d = geodesic_distance(V, F, hem, limit=limit)
            times.append(time.perf_counter() - t0)
        below = d < limit
        err = float(np.max(np.abs(d[below] - exact[below])))
        print(
            f"limit={limit:g}: median {statistics.median(times):.3f} s over {REPEAT} runs "
            f"(min {min(times):.3f} s); {int(below.sum())} vertices below the limit, "
            f"max error {err:.1e} cm"
        )


if __name__ == "__main__":
    main()
