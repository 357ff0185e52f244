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


def cylinder(nu: int, nv: int, radius: float = 1.0, height: float = 3.0):
    """Open cylinder around z: ``nu`` vertices per ring, ``nv`` rows, ``2 nu nv`` triangles."""
    th = 2.0 * np.pi * np.arange(nu) / nu
    z = np.linspace(0.0, height, nv + 1)
    V = np.column_stack(
        [
            np.tile(radius * np.cos(th), nv + 1),
            np.tile(radius * np.sin(th), nv + 1),
            np.repeat(z, nu),
        ]
    )
    col, row = np.meshgrid(np.arange(nu), np.arange(nv))
    a = row * nu + col
    b = row * nu + (col + 1) % nu
    F = np.concatenate([np.stack([a, b, b + nu], -1), np.stack([a, b + nu, a + nu], -1)])
    return V, F.reshape(-1, 3)


def main() -> None:
    V, F = cylinder(250, 200)
    z = V[:, 2]
    handles = np.flatnonzero((z <= z.max() / 3.0 + 1e-9) | (z >= z.max() - 1e-9))
    Q = V[handles].copy()
    Q[z[handles] < z.max() / 2.0, :2] *= 1.2
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
