"""Seam ease under partial edits, on the real garments in ../shared and the generated samples.

For each garment and edit (one sleeve 10 % wider, a ``scale_seam`` gather of 1.2 at an
armhole, loosen the torso by 2, and their symmetric versions) prints every seam's worst
ratio error against its target, the gather achieved, the intrinsic-scale error p95 of the
panels the edit did not touch (no drape edge changed length by 0.1 %), iterations and seconds,
with ``flatten.seams: ease`` (the default) and ``free`` side by side.

    python bench/bench_seams.py [--garments tee6,tshirt,...] [--json out.json]

Sleeves are the panels holding the ``cuff_left`` opening, the torso the panels holding the
``hem``; the gathered seam is the first seam between a sleeve panel and a torso panel.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "garments"
REAL = {
    "tee6": ("gpg_tee6/tee6_sim.obj", "cm"),
    "tshirt": ("diffavatar/tshirt.obj", "auto"),
    "longsleeve": ("diffavatar/longsleeve_initial.obj", "auto"),
    "dress": ("diffavatar/dress_initial.obj", "auto"),
}


def load(key: str):
    from ptailor.formats.garment import load_garment
    from ptailor.samples import SAMPLES

    if key in REAL:
        path = SHARED / REAL[key][0]
        if not path.is_file():
            return None
        return load_garment(path, pattern_units=REAL[key][1]).garment
    return SAMPLES[key]()


def opening_panels(g, name: str) -> list[str]:
    """Panels whose triangles touch an opening's drape vertices."""
    from ptailor.edits import EditState
    from ptailor.edits.opening import find_opening
    from ptailor.model.garment import panels

    plist = panels(g)
    st = EditState(base=g, V3=g.V3, panels=plist, even=np.ones(len(plist), bool))
    try:
        _, loop = find_opening(st, name)
    except Exception:
        return []
    on = np.isin(g.F3, loop).any(axis=1)
    return [p.name for p in plist if on[p.faces].any()]


def strain_max(g, V3_edit, faces) -> float:
    """Largest relative 3D edge-length change over some triangles."""
    F = g.F3[faces]
    E = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    l0 = np.linalg.norm(g.V3[E[:, 1]] - g.V3[E[:, 0]], axis=1)
    l1 = np.linalg.norm(V3_edit[E[:, 1]] - V3_edit[E[:, 0]], axis=1)
    return float(np.abs(l1 / np.maximum(l0, 1e-300) - 1.0).max())


def cases(g) -> dict[str, str]:
    """Recipe text per case name for a garment (empty when it lacks sleeves or a hem)."""
    from ptailor.model.garment import panel_labels, panels
    from ptailor.model.seams import seams

    sleeve = opening_panels(g, "cuff_left")
    torso = opening_panels(g, "hem")
    out: dict[str, str] = {}
    out["all 20% wider around"] = (
        "steps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.2}]"
    )
    out["shorten hem 5"] = "steps: [{op: shorten, opening: hem, by: 5}]"
    out["extend hem 5"] = "steps: [{op: extend, opening: hem, by: 5}]"
    if torso:
        out["loosen torso 1"] = (
            f"steps: [{{op: loosen, region: {{panels: {json.dumps(torso)}}}, by: 1}}]"
        )
        out["loosen torso 2"] = (
            f"steps: [{{op: loosen, region: {{panels: {json.dumps(torso)}}}, by: 2}}]"
        )
    if sleeve:
        out["sleeve 10% wider"] = (
            "steps: [{op: scale, region: {panels: " + json.dumps(sleeve) + "},"
            " direction: around, axis: auto, factor: 1.1}]"
        )
        plist = panels(g)
        names = [p.name for p in plist]
        for s in seams(g.F3, g.F2, panel_labels(plist, g.n_faces)):
            a, b = names[s.panels[0]], names[s.panels[1]]
            if (a in sleeve) != (b in sleeve) and (a in torso or b in torso):
                part, other = (a, b) if a in sleeve else (b, a)
                out["gather 1.2 at armhole"] = (
                    f"steps: [{{op: scale_seam, seam: [{part}, {other}], part: {part},"
                    " factor: 1.2}]"
                )
                break
    for k in [k for k in out if k.startswith(("loosen torso 2", "sleeve", "gather"))]:
        out[k + " (symmetric)"] = out[k].replace("}]", ", symmetric: true}]")
    return out


def measure(g, text: str, seams_mode: str) -> dict:
    from ptailor.errors import PtailorError
    from ptailor.pipeline import adjustment
    from ptailor.recipe import parse_recipe
    from ptailor.report.build import build_report

    recipe = parse_recipe(text + f"\nflatten: {{seams: {seams_mode}}}")
    t0 = time.perf_counter()
    try:
        adj = adjustment(g, recipe, baseline=False)
    except PtailorError as e:
        return {"error": str(e)}
    secs = time.perf_counter() - t0
    rep = build_report(adj, inputs={}, units_note={}, warnings=[], timing_s={})
    rel = [abs(s["ratio_after"] / s["ratio_target"] - 1.0) for s in rep["seams"]]
    gathered = [s for s in rep["seams"] if abs(s["ratio_target"] / s["ratio_before"] - 1) > 1e-6]
    st = adj.state
    untouched = [
        p["intrinsic_scale_error"]["p95"]
        for p, pl in zip(rep["panels"], st.panels, strict=True)
        if pl.faces.size and strain_max(st.base, st.V3, pl.faces) < 1e-3
    ]
    return {
        "max_ratio_err": max(rel, default=0.0),
        "max_mismatch": max((abs(s["mismatch"]) for s in rep["seams"]), default=0.0),
        "gather": [
            max(s["ratio_after"] / s["ratio_before"], s["ratio_before"] / s["ratio_after"])
            for s in gathered
        ],
        "untouched_p95": max(untouched, default=None),
        "all_p95": max(p["intrinsic_scale_error"]["p95"] for p in rep["panels"]),
        "iterations": adj.result.info.iterations,
        "converged": adj.result.info.converged,
        "seconds": secs,
    }


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--garments", default="tee6,tshirt,longsleeve,dress,bodice,lantern_sleeve")
    ap.add_argument("--json", default=None)
    args = ap.parse_args()
    rows = []
    for key in args.garments.split(","):
        g = load(key)
        if g is None:
            print(f"{key}: not available", file=sys.stderr)
            continue
        for name, text in cases(g).items():
            for mode in ("ease", "free"):
                r = {"garment": key, "case": name, "seams": mode, **measure(g, text, mode)}
                rows.append(r)
                if "error" in r:
                    print(f"{key:11} {name:32} {mode:4}  ERROR {r['error']}")
                    continue
                up = r["untouched_p95"]
                print(
                    f"{key:11} {name:32} {mode:4} ratio err {100 * r['max_ratio_err']:8.4f} %"
                    f"  mismatch {r['max_mismatch']:7.3f}"
                    f"  gather {','.join(f'{x:.4f}' for x in r['gather']) or '-':>13}"
                    f"  untouched p95 {'-' if up is None else f'{100 * up:.3f} %':>8}"
                    f"  all p95 {100 * r['all_p95']:7.3f} %"
                    f"  it {r['iterations']:3d}{'' if r['converged'] else '!'}"
                    f"  {r['seconds']:6.2f} s",
                    flush=True,
                )
    ok = [r for r in rows if "error" not in r and r["seams"] == "ease"]
    if ok:
        its = [r["iterations"] for r in ok]
        print(
            f"ease: worst ratio error {100 * max(r['max_ratio_err'] for r in ok):.4f} %,"
            f" iterations median {statistics.median(its)}, max {max(its)},"
            f" not converged {sum(not r['converged'] for r in ok)} of {len(ok)}"
        )
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
