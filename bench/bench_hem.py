"""How far ``shorten`` and ``extend`` move a hem, measured in the output pattern.

    python bench/bench_hem.py [--by 5] [--opening hem] [--measure pattern drape]
                              [--garments tee6 tshirt longsleeve dress cone_skirt ...]

For every garment, operation and measure: one in-process ``adjust`` (flattening included,
no baseline), then the distance of the new edge from the old one in the adjusted pattern
``adj.result.V2`` (what a user cuts), per panel the opening runs along: min / median / max
over the new edge's pattern vertices, from the old edge's pattern segments carried into the
output's frame by each panel's rigid fit (input -> output; ``fit`` is the largest distance
a vertex of the panel moved beyond that rigid motion: what the flattening changed). Also
the step record's drape amount (surface distance) and the seconds of the whole ``adjust``.

Real garments come from ``../shared/garments`` (or ``$PTAILOR_SHARED/garments``) and are
skipped when absent; their pattern units are the tests' (tee6: ``cm`` for its 1/300 m
units, the DiffAvatar atlases ``auto``). Generated samples (``ptailor.samples``) are in cm.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from garments import REAL, SHARED
from ptailor.edits.extend import opening_edges
from ptailor.geometry.segments import nearest_segment_distance
from ptailor.model.frame import Frame
from ptailor.model.garment import Garment, panels
from ptailor.model.openings import openings
from ptailor.pipeline import adjustment
from ptailor.recipe import parse_recipe
from ptailor.samples import SAMPLES

ROOT = Path(__file__).resolve().parents[1]


def load(key: str) -> Garment | None:
    """A real garment or a generated sample; None when a real one is absent."""
    if key in SAMPLES:
        return SAMPLES[key]()
    from ptailor.formats.garment import load_garment

    path = SHARED / "garments" / REAL[key][0]
    if not path.is_file():
        return None
    return load_garment(path, pattern_units=REAL[key][1]).garment


def rigid_fit(X: np.ndarray, Y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rotation ``R`` (2, 2) and shift ``t`` (2,) minimising ``|X R^T + t - Y|``."""
    cx, cy = X.mean(0), Y.mean(0)
    U, _, Vt = np.linalg.svd((X - cx).T @ (Y - cy))
    D = np.diag([1.0, np.sign(np.linalg.det(U @ Vt))])
    R = (U @ D @ Vt).T
    return R, cy - cx @ R.T


def _edges_by_panel(g: Garment, V3: np.ndarray, name: str) -> tuple[dict, dict] | None:
    """The opening's pattern edges per panel name, and the panels by name (None: no such)."""
    loop = next((o.loop for o in openings(V3, g.F3, frame=Frame()) if o.name == name), None)
    if loop is None:
        return None
    oe = opening_edges(g.F3, g.F2, loop)
    plist = panels(g)
    flab = np.empty(g.n_faces, dtype=np.int64)
    for p in plist:  # a loop over panels
        flab[p.faces] = p.index
    out: dict[str, list] = {}
    for p in plist:
        sel = flab[oe.face] == p.index
        if sel.any():
            out[p.name] = [oe.a2[sel], oe.b2[sel]]
    return out, {p.name: p for p in plist}


def output_distances(g0: Garment, adj, name: str) -> dict | None:
    """Per input panel: new edge's distances from the old one in the output, and the fit.

    None when the adjusted garment has no opening of that name any more (the step merged
    it with another: a shortened neckline that cut through the straps).
    """
    old, _ = _edges_by_panel(g0, g0.V3, name)
    st = adj.state
    found = _edges_by_panel(st.base, st.V3, name)
    if found is None:
        return None
    new, new_panels = found
    X = adj.result.V2
    out = {}
    for pname, (a0, b0) in old.items():  # a loop over panels
        mine = [q for q in new if q == pname or q.rsplit("_", 1)[0] == pname]
        if not mine:
            out[pname] = None  # the whole panel was removed
            continue
        d_all, fit = [], 0.0
        for q in mine:
            verts = new_panels[q].vertices
            R, t = rigid_fit(st.base.V2[verts], X[verts])
            fit = max(fit, float(np.abs(st.base.V2[verts] @ R.T + t - X[verts]).max()))
            A, B = g0.V2[a0] @ R.T + t, g0.V2[b0] @ R.T + t
            pts = np.unique(np.concatenate(new[q]))
            d_all.append(nearest_segment_distance(X[pts], A, B))
        out[pname] = (np.concatenate(d_all), fit)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--by", type=float, default=5.0)
    ap.add_argument("--opening", default="hem")
    ap.add_argument("--measure", nargs="+", default=["pattern", "drape"])
    ap.add_argument("--ops", nargs="+", default=["shorten", "extend"])
    ap.add_argument(
        "--garments",
        nargs="+",
        default=[*REAL, "cone_skirt", "bodice", "cylinder", "lantern_sleeve"],
    )
    args = ap.parse_args()
    print(f"{args.opening} by {args.by:g}; distances in the output pattern, per panel")
    print(
        f"{'garment':<14} {'op':<8} {'measure':<8} {'panel':<10} "
        f"{'min':>8} {'median':>8} {'max':>8} {'fit':>9}  {'drape min/med/max':>26} {'s':>6}"
    )
    for key in args.garments:  # a loop over garments
        g = load(key)
        if g is None:
            print(f"{key:<14} (absent: {SHARED / 'garments'})")
            continue
        for op in args.ops:
            for measure in args.measure:
                text = (
                    f"steps: [{{op: {op}, opening: {args.opening}, by: {args.by}, "
                    f"measure: {measure}}}]"
                )
                t0 = time.perf_counter()
                try:
                    adj = adjustment(g, parse_recipe(text), baseline=False)
                except Exception as exc:  # report and go on with the next one
                    print(f"{key:<14} {op:<8} {measure:<8} FAILED: {exc}")
                    continue
                sec = time.perf_counter() - t0
                drape = adj.state.log[-1]["amount"]["drape"]
                dtxt = f"{drape['min']:.3f}/{drape['median']:.3f}/{drape['max']:.3f}"
                dist = output_distances(g, adj, args.opening)
                if dist is None:
                    print(f"{key:<14} {op:<8} {measure:<8} (no {args.opening} left to measure)")
                    continue
                for pname, res in dist.items():
                    if res is None:
                        print(f"{key:<14} {op:<8} {measure:<8} {pname:<10} (removed)")
                        continue
                    d, fit = res
                    print(
                        f"{key:<14} {op:<8} {measure:<8} {pname:<10} {d.min():8.4f} "
                        f"{np.median(d):8.4f} {d.max():8.4f} {fit:9.2e}  {dtxt:>26} {sec:6.2f}"
                    )


if __name__ == "__main__":
    main()
