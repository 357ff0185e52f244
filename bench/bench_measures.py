"""Benchmark of :func:`ptailor.measures.garment_measures`: the points of measure of a garment
(cached structure excluded: every run computes it once anyway), at 1x, 16x and 64x the
triangles of the generated tee (``ptailor.samples.flat_tee``) and, when ../shared is there, of
the DiffAvatar tshirt. Prints the median wall time over 5 runs and its ratio to the garment's
structure (panels, layout, seams), which every ``adjust`` computes.

Run: ``python bench/bench_measures.py``
"""

from __future__ import annotations

import time
from pathlib import Path

from ptailor.formats.garment import load_garment
from ptailor.measures import garment_measures
from ptailor.model.structure import structure
from ptailor.samples import flat_tee
from subdivide import subdivide_garment
from timing import median_time

REPEAT = 5
TSHIRT = Path(__file__).resolve().parents[2] / "shared/garments/diffavatar/tshirt.obj"


def _subdivided(g, levels: int):
    import dataclasses

    if levels == 0:
        return g
    V3, F3, V2, F2, parent = subdivide_garment(g.V3, g.F3, g.V2, g.F2, levels=levels)
    return dataclasses.replace(g, V3=V3, F3=F3, V2=V2, F2=F2, face_group=g.face_group[parent])


def main() -> None:
    garments = {"flat_tee": flat_tee()}
    if TSHIRT.exists():
        garments["tshirt"] = load_garment(TSHIRT, pattern_units="auto", drape_units="cm").garment
    print(f"{'garment':10s} {'triangles':>9s} {'structure s':>11s} {'measures s':>10s} ratio")
    for name, g0 in garments.items():
        for levels in (0, 2, 3):
            g = _subdivided(g0, levels)
            t = time.perf_counter()
            st = structure(g)
            st.layout, st.seams  # noqa: B018 - computed once per garment by every adjust
            t_st = time.perf_counter() - t
            t_m = median_time(lambda g=g: garment_measures(g), REPEAT)
            print(f"{name:10s} {len(g.F3):9d} {t_st:11.3f} {t_m:10.3f} {t_m / t_st:5.2f}")


if __name__ == "__main__":
    main()
