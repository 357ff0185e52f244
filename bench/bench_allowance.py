"""Seam allowances: is every cut line simple, before (the hand mitre offset) and after (GEOS).

    python bench/bench_allowance.py [--levels 0 2] [--cm 1 2.5 5]

For every shared garment (``../shared/garments`` or ``$PTAILOR_SHARED/garments``; skipped
when absent), at each subdivision level (0: as read, 2: 16x the triangles, bench/subdivide.py)
and each allowance: the pieces drawn from the mesh (``piece_plan``), each offset by
``with_seam_allowance`` (GEOS) and by the hand mitre offset it replaced (each point moved
along its mitre, bevelled beyond 4 allowances; kept here only to show what it did). A cut
line that is not a simple ring is counted, with the area of the loops it closes off (mm2,
by shapely's polygonize of its noded ring). Also: the per-edge path (runs of 3 edges at
the allowance and 4 at 3 allowances), whether every cut polygon is valid, the nearest any sew line
point comes to its cut line over the smallest allowance (1: no slit or loop reaches in) and
the CPU seconds of the GEOS offsets (uniform and per-edge together).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import shapely

from garments import REAL, SHARED

ROOT = Path(__file__).resolve().parents[1]


def hand_offset(P: np.ndarray, d: float, limit: float = 4.0) -> np.ndarray:
    """The replaced offset (ptailor before GEOS): each point along its mitre, bevelled."""
    sign = 1.0 if shapely.Polygon(P).exterior.is_ccw else -1.0
    e = np.roll(P, -1, axis=0) - P
    n = sign * np.stack([e[:, 1], -e[:, 0]], axis=1) / np.linalg.norm(e, axis=1)[:, None]
    n_in = np.roll(n, 1, axis=0)
    m = n_in + n
    denom = 1.0 + (n_in * n).sum(axis=1)
    miter = np.where(denom[:, None] > 1e-12, d * m / np.maximum(denom, 1e-12)[:, None], 0.0)
    bevel = (denom <= 2.0 / limit**2) | (np.linalg.norm(miter, axis=1) > limit * abs(d))
    idx = np.repeat(np.arange(len(P)), np.where(bevel, 2, 1))
    first = np.concatenate([[True], idx[1:] != idx[:-1]])
    out = P[idx] + miter[idx]
    bi = bevel[idx]
    out[bi & first] = P[idx][bi & first] + d * n_in[idx][bi & first]
    out[bi & ~first] = P[idx][bi & ~first] + d * n[idx][bi & ~first]
    return out


def loops_mm2(cut: np.ndarray, mm_per_unit: float) -> list[float]:
    """Areas (mm2) of the loops a non-simple cut line closes off besides its main area."""
    ring = shapely.LinearRing(cut)
    if ring.is_simple:
        return []
    faces = sorted(f.area for f in shapely.polygonize([shapely.union_all([ring])]).geoms)
    return [round(a * mm_per_unit**2, 2) for a in faces[:-1]]


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--levels", type=int, nargs="+", default=[0, 2])
    ap.add_argument("--cm", type=float, nargs="+", default=[1.0, 2.5, 5.0])
    args = ap.parse_args()
    sys.path.insert(0, str(ROOT / "bench"))
    from garments import subdivided
    from ptailor.formats.garment import load_garment
    from ptailor.model.units import CM_PER
    from ptailor.pieces import piece_plan, with_seam_allowance

    print(
        "garment     x   cm  pieces  hand: bad  loops mm2                       geos: bad  "
        "per-edge bad  nearest/d  cpu s"
    )
    for key, (rel, units) in REAL.items():
        path = SHARED / "garments" / rel
        if not path.is_file():
            print(f"{key}: {path} absent, skipped")
            continue
        g0 = load_garment(path, pattern_units=units).garment
        for lv in args.levels:
            g = subdivided(g0, lv)
            pieces = piece_plan(g).pieces
            mm = 10.0 * CM_PER[g.units]
            for cm in args.cm:
                d = cm / CM_PER[g.units]
                hand = [loops_mm2(hand_offset(pc.outline, d), mm) for pc in pieces]
                t = time.process_time()
                ours = [with_seam_allowance(pc, d).outline for pc in pieces]
                per = [
                    with_seam_allowance(
                        pc, d, edges=np.where(np.arange(len(pc.outline)) % 7 < 3, d, 3 * d)
                    ).outline
                    for pc in pieces
                ]
                cpu = time.process_time() - t
                bad_hand = [(pc.name, lp) for pc, lp in zip(pieces, hand, strict=True) if lp]
                bad = sum(not shapely.LinearRing(c).is_simple for c in ours)
                bad_per = sum(not shapely.Polygon(c).is_valid for c in per + ours)
                near = min(
                    shapely.distance(shapely.LinearRing(c), shapely.points(pc.outline)).min()
                    for c, pc in zip(ours + per, pieces + pieces, strict=True)
                )
                print(
                    f"{key:10s} {4**lv:2d}x {cm:4g} {len(pieces):6d}  {len(bad_hand):9d}  "
                    f"{str(bad_hand)[:30]:30s} {bad:9d}  {bad_per:12d}  {near / d:9.6f}  {cpu:5.2f}"
                )


if __name__ == "__main__":
    main()
