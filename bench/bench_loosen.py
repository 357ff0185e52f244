"""Loosen / tighten (offset form) on the real, simulated drapes of ../shared.

For each garment, region (the torso panels, or a box band around the waist) and offset
``d``, this runs ``ptailor adjust GARMENT RECIPE -o OUT`` as a subprocess (exit status,
flipped triangles from ``report.json``) and the same adjustment in-process, and measures
the girth of the torso at a few heights:

- the material curve: the drape's horizontal cross-section at height ``y`` through the
  region's triangles, carried by barycentric coordinates into the edited drape and into the
  original and adjusted patterns;
- ``3D gain``: its length after minus before in the drape, over the expected ``2 pi d``;
- ``pattern gain``: its length after minus before in the pattern, over the expected
  ``2 pi d / s`` with ``s`` the curve's intrinsic scale (3D over 2D length, before).

Heights are chosen where the offset is at full strength (falloff weight 1 along the whole
curve, printed as ``w_min``). Usage, from the repository root::

    python bench/bench_loosen.py [--shared ../shared] [--d 1 2 5] [--op loosen]

``--op tighten`` measures tightening (the gains are then negative, and still compared with
``-2 pi d``). Garments missing from ``--shared`` are skipped.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[1]

#: garment: (path under garments/, pattern units, drape units, torso panels,
#: heights measured for the panels region, box band (y min, y max))
GARMENTS = {
    "tee6": (
        "gpg_tee6/tee6_sim.obj",
        "0.3333cm",
        "0.3333cm",
        ["front", "back"],
        [-20.0, -12.0, -5.0],
        (-23.0, 9.0),
    ),
    "tshirt": (
        "diffavatar/tshirt.obj",
        "auto",
        "cm",
        ["panel_2", "panel_3"],
        [108.0, 114.0, 120.0],
        (105.0, 131.0),
    ),
    "longsleeve": (
        "diffavatar/longsleeve_initial.obj",
        "auto",
        "cm",
        ["panel_0", "panel_1"],
        [80.0, 86.0, 92.0],
        (77.0, 102.0),
    ),
    "dress": (
        "diffavatar/dress_initial.obj",
        "auto",
        "cm",
        [f"panel_{i}" for i in (0, 1, 2, 3, 6, 7, 8, 9, 10, 11, 12)],  # all but the straps
        [90.0, 100.0, 106.0],
        (82.0, 108.0),
    ),
}


def cross_section(V: np.ndarray, F: np.ndarray, faces: np.ndarray, y: float):
    """The material curve at height ``y`` through some triangles.

    Parameters
    ----------
    V : (n, 3) float array
    F : (m, 3) int array
    faces : (k,) int array
    y : float

    Returns
    -------
    tri : (s,) int array
        Triangle of each segment.
    bary : (s, 2, 3) float array
        Barycentric coordinates of the segment's two ends in its triangle.
    """
    T = F[faces]
    hgt = V[T][:, :, 1] - y
    hgt = np.where(hgt == 0.0, 1e-12, hgt)  # a corner on the plane counts as above
    neg = hgt < 0.0
    cut = neg.any(axis=1) & ~neg.all(axis=1)
    tri, hgt, neg = faces[cut], hgt[cut], neg[cut]
    # the two crossed edges of each triangle: the ones whose ends differ in sign
    a = np.array([0, 1, 2])
    b = np.array([1, 2, 0])
    crossed = neg[:, a] != neg[:, b]  # (s, 3), two True per row
    k = np.argsort(~crossed, axis=1, kind="stable")[:, :2]  # indices of the two edges
    ea, eb = a[k], b[k]  # (s, 2)
    r = np.arange(len(tri))[:, None]
    t = hgt[r, ea] / (hgt[r, ea] - hgt[r, eb])
    bary = np.zeros((len(tri), 2, 3))
    s2 = np.arange(2)[None, :]
    bary[r, s2, ea] = 1.0 - t
    bary[r, s2, eb] = t
    return tri, bary


def curve_length(X: np.ndarray, F: np.ndarray, tri: np.ndarray, bary: np.ndarray) -> float:
    """Length of a material curve (:func:`cross_section`) on positions ``X`` via ``F``."""
    P = np.einsum("skc,scd->skd", bary, X[F[tri]])
    return float(np.linalg.norm(P[:, 0] - P[:, 1], axis=1).sum())


def recipe_text(op: str, region: dict, d: float) -> str:
    return yaml.safe_dump({"units": "cm", "steps": [{"op": op, "region": region, "by": d}]})


def run_cli(path: Path, text: str, pu: str, du: str) -> tuple[int, int | None, float, str]:
    """``ptailor adjust``: exit status, flipped triangles (report), seconds, stderr tail."""
    with tempfile.TemporaryDirectory() as tmp:
        rec = Path(tmp) / "recipe.yaml"
        rec.write_text(text)
        out = Path(tmp) / "out"
        cmd = [sys.executable, "-m", "ptailor", "adjust", str(path), str(rec), "-o", str(out)]
        cmd += ["--pattern-units", pu, "--drape-units", du, "--formats", "obj", "-q"]
        t0 = time.perf_counter()
        p = subprocess.run(cmd, capture_output=True, text=True, env=os.environ.copy())
        secs = time.perf_counter() - t0
        flips = None
        if p.returncode == 0:
            rep = json.loads((out / "report.json").read_text())
            flips = sum(int(q["flipped_triangles"]) for q in rep["panels"])
        last = p.stderr.strip().splitlines()[-1:]
        return p.returncode, flips, secs, last[0] if last else ""


def measure(key: str, region_kind: str, d: float, op: str, shared: Path, cli: bool) -> dict:
    from ptailor.edits import EditOptions
    from ptailor.edits.loosen import falloff_weights
    from ptailor.edits.region import region_faces
    from ptailor.edits.tolerances import LOOSEN_FALLOFF_BY as FALLOFF_BY
    from ptailor.errors import PtailorError
    from ptailor.formats.garment import load_garment
    from ptailor.model.garment import panels
    from ptailor.pipeline import adjustment, apply_steps
    from ptailor.recipe import parse_recipe

    rel, pu, du, torso, heights, (y0, y1) = GARMENTS[key]
    path = shared / "garments" / rel
    g = load_garment(path, pattern_units=pu, drape_units=du).garment
    if region_kind == "panels":
        region: dict = {"panels": torso}
    else:
        region = {"box": {"min": [-1e3, y0, -1e3], "max": [1e3, y1, 1e3]}}
        heights = [0.5 * (y0 + y1)]
    text = recipe_text(op, region, d)
    row = {"garment": key, "region": region_kind, "d": d}
    if cli:
        rc, flips, secs, err = run_cli(path, text, pu, du)
        row.update(exit=rc, flips=flips, cli_s=round(secs, 2), error=err if rc else "")
    recipe = parse_recipe(text)
    t0 = time.perf_counter()
    try:
        state = apply_steps(g, recipe, options=EditOptions())
    except PtailorError as e:
        row.update(edit_s=round(time.perf_counter() - t0, 3), error=str(e))
        return row
    row["edit_s"] = round(time.perf_counter() - t0, 3)
    adj = adjustment(g, recipe)
    pl = panels(g)
    faces = region_faces(region, g, g.V3, pl)
    # the band the edit used (edits.loosen.offset_region: from by only)
    w = falloff_weights(g.V3, g.F3, faces, band=FALLOFF_BY * abs(d))
    sign = 1.0 if op == "loosen" else -1.0
    g3, g2, wmin = [], [], []
    for y in heights:
        tri, bary = cross_section(g.V3, g.F3, faces, y)
        l3, l3n = curve_length(g.V3, g.F3, tri, bary), curve_length(state.V3, g.F3, tri, bary)
        l2, l2n = curve_length(g.V2, g.F2, tri, bary), curve_length(adj.result.V2, g.F2, tri, bary)
        s = l3 / l2
        g3.append((l3n - l3) / (sign * 2.0 * np.pi * d))
        g2.append((l2n - l2) / (sign * 2.0 * np.pi * d / s))
        wmin.append(float(w[g.F3[tri]].min()))
    row.update(gain3d=g3, gain2d=g2, w_min=min(wmin), s=round(s, 3))
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--shared", type=Path, default=ROOT.parent / "shared")
    ap.add_argument("--d", type=float, nargs="+", default=[1.0, 2.0, 5.0])
    ap.add_argument("--op", choices=["loosen", "tighten"], default="loosen")
    ap.add_argument("--garments", nargs="+", default=list(GARMENTS))
    ap.add_argument("--no-cli", action="store_true", help="skip the ptailor adjust subprocess")
    args = ap.parse_args()
    head = (
        f"{'garment':11s} {'region':6s} {'d':>4s} {'exit':>4s} {'flips':>5s} {'w_min':>5s}"
        f" {'3D gain / 2 pi d':>22s} {'pattern gain / (2 pi d / s)':>28s}"
        f" {'edit s':>6s} {'cli s':>6s}"
    )
    print(head)
    for key in args.garments:
        if not (args.shared / "garments" / GARMENTS[key][0]).is_file():
            print(f"{key:11s} skipped: {args.shared / 'garments' / GARMENTS[key][0]} absent")
            continue
        for kind in ("panels", "box"):
            for d in args.d:
                r = measure(key, kind, d, args.op, args.shared, not args.no_cli)
                if "gain3d" not in r:
                    print(f"{key:11s} {kind:6s} {d:4g} {r.get('exit', '-')!s:>4s}  {r['error']}")
                    continue

                def fmt(v: list[float]) -> str:
                    return " ".join(f"{x:.3f}" for x in v)

                print(
                    f"{key:11s} {kind:6s} {d:4g} {r.get('exit', '-')!s:>4s}"
                    f" {r.get('flips', '-')!s:>5s} {r['w_min']:5.2f} {fmt(r['gain3d']):>22s}"
                    f" {fmt(r['gain2d']):>28s} {r['edit_s']:6.2f} {r.get('cli_s', '-')!s:>6s}"
                )


if __name__ == "__main__":
    main()
