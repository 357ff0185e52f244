"""The paper's evidence on real garments: the re-drape check per shared garment and edit.

    python bench/bench_evidence.py [--shared ../shared] [--jobs 2] [--only tee6 ...]
                                   [--edits "loosen 2" ...] [--levels 0 2] [--keep DIR]

For each garment of ``../shared`` (tee6, tshirt, longsleeve_initial, dress_initial) and each
edit that applies to it (one sleeve 1.1 around, loosen 2 cm, a 1.2 gather of one armhole;
the dress: its skirt 1.1 around instead of the sleeve edits), runs
``ptailor adjust GARMENT RECIPE --verify --body auto`` as a subprocess (``--jobs`` at a
time) and reads ``report.json``: for ours, the uniform baseline and the original pattern,
the worst panel's stretch p95, displacement mean and p95 from the edited drape, and the
same minus the original's re-drape (what the pattern changes, not what any re-drape
moves), settled, steps, seconds and CPU seconds; the null test's numbers and the verdict;
and each command's CPU seconds (imports, body fit, adjustment and the three re-drapes: the
check's CPU budget). ``--levels 2`` runs each garment subdivided to 16x the triangles
(``bench/subdivide.py``; the check simulates on its 8,000-triangle copy). The demo's
lantern sleeve on its arm is the first row
(``ptailor demo``'s recipe, its arm cylinder as the body).

Prints a Markdown table and writes ``bench/results/evidence.json``.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from timing import run_measured

ROOT = Path(__file__).resolve().parents[1]

SLEEVE = (
    "units: cm\nsteps: [{op: scale, region: {panels: [sleeve_left]}, direction: around, "
    "axis: auto, factor: 1.1}]\n"
)
LOOSEN = "units: cm\nsteps: [{op: loosen, region: all, by: 2}]\n"
GATHER = (
    "units: cm\nsteps: [{op: scale_seam, seam: armhole_left, part: sleeve_left, factor: 1.2}]\n"
)
#: tee6's sleeves are front and back panels: its left armhole gathered on the front one
GATHER_TEE6 = (
    "units: cm\nsteps: [{op: scale_seam, seam: [front, sleeve_left_front], "
    "part: sleeve_left_front, factor: 1.2}]\n"
)
SKIRT = (
    "units: cm\nsteps: [{op: scale, region: {panels: [skirt]}, direction: around, "
    "axis: auto, factor: 1.1}]\n"
)

#: garment -> (path under shared, unit options, edits)
GARMENTS = {
    "tee6": (
        "garments/gpg_tee6/tee6_sim.obj",
        ["--pattern-units", "0.3333cm", "--drape-units", "0.3333cm"],
        {"sleeve 1.1": SLEEVE, "loosen 2": LOOSEN, "gather 1.2": GATHER_TEE6},
    ),
    "tshirt": (
        "garments/diffavatar/tshirt.obj",
        ["--pattern-units", "auto"],
        {"sleeve 1.1": SLEEVE, "loosen 2": LOOSEN, "gather 1.2": GATHER},
    ),
    "longsleeve": (
        "garments/diffavatar/longsleeve_initial.obj",
        ["--pattern-units", "auto"],
        {"sleeve 1.1": SLEEVE, "loosen 2": LOOSEN, "gather 1.2": GATHER},
    ),
    "dress": (
        "garments/diffavatar/dress_initial.obj",
        ["--pattern-units", "auto"],
        {"skirt 1.1": SKIRT, "loosen 2": LOOSEN},
    ),
}
KINDS = ("ours", "baseline", "original")


def worst(section: dict, kind: str) -> dict:
    """The worst panel's numbers of one re-drape (stretch p95 and displacement by the
    panel with the largest stretch p95 / displacement p95)."""
    panels = section[kind]["panels"]
    return {
        "stretch_p95": max(p["stretch"]["p95"] for p in panels.values()),
        "disp_mean": max(p["displacement"]["mean"] for p in panels.values()),
        "disp_p95": max(p["displacement"]["p95"] for p in panels.values()),
        "settled": bool(section[kind]["settled"]),
        "steps": int(section[kind]["steps"]),
        "seconds": round(float(section[kind]["seconds"]), 1),
        "cpu_s": round(float(section[kind].get("cpu_seconds", float("nan"))), 1),
        "speed_p95": section[kind].get("speed_p95"),
    }


def relative(section: dict, kind: str) -> dict:
    """Displacement minus the original's re-drape, per panel, worst panel: how much more
    this pattern's re-drape moves than the original pattern's does."""
    ref = section["original"]["panels"]
    panels = section[kind]["panels"]
    return {
        "disp_mean_minus_original": round(
            max(
                p["displacement"]["mean"] - ref[n]["displacement"]["mean"]
                for n, p in panels.items()
            ),
            3,
        ),
        "disp_p95_minus_original": round(
            max(
                p["displacement"]["p95"] - ref[n]["displacement"]["p95"] for n, p in panels.items()
            ),
            3,
        ),
    }


def timed(cmd: list[str]) -> tuple[int, str, float, float]:
    """Run ``cmd``: its exit status, stderr, and wall and CPU seconds of that command alone
    (:func:`timing.run_measured`; nan when it failed)."""
    with tempfile.TemporaryFile("w+") as err:
        try:
            wall, cpu, _ = run_measured(cmd, stdout=subprocess.DEVNULL, stderr=err)
            rc = 0
        except subprocess.CalledProcessError as e:
            rc, wall, cpu = e.returncode, float("nan"), float("nan")
        err.seek(0)
        return rc, err.read(), wall, cpu


def garment_path(shared: Path, work: Path, garment: str, levels: int) -> Path:
    """The garment's OBJ, subdivided ``levels`` times (4 ** levels the triangles; written
    once into ``work`` by ``bench/subdivide.py``)."""
    path = shared / GARMENTS[garment][0]
    if levels == 0:
        return path
    out = work / f"{garment}-{4**levels}x.obj"
    if not out.exists():
        subprocess.run([sys.executable, str(ROOT / "bench/subdivide.py"), str(path), str(out),
                        "--levels", str(levels)], check=True)  # fmt: skip
    return out


def run_one(shared: Path, work: Path, garment: str, edit: str, levels: int = 0) -> dict:
    _, units, edits = GARMENTS[garment]
    tag = f"{garment}-{4**levels}x-{edit.replace(' ', '_')}"
    recipe = work / f"{tag}.yaml"
    recipe.write_text(edits[edit])
    out = work / tag
    obj = garment_path(shared, work, garment, levels)
    cmd = [sys.executable, "-m", "ptailor", "adjust", str(obj), str(recipe), *units,
           "--verify", "--body", "auto", "-o", str(out), "-q"]  # fmt: skip
    rc, err, wall, cpu = timed(cmd)
    row = {"garment": garment if levels == 0 else f"{garment} {4**levels}x", "edit": edit,
           "wall_s": round(wall, 1), "cpu_s": round(cpu, 1), "rc": rc}  # fmt: skip
    if rc != 0:
        row["error"] = err.strip().splitlines()[-1:] or [""]
        return row
    rep = json.loads((out / "report.json").read_text())
    sec = rep["verify"]
    row["body_fit"] = rep.get("body_fit")
    row["triangles"] = sec.get("triangles")
    for k in KINDS:
        row[k] = worst(sec, k) | (relative(sec, k) if k != "original" else {})
    return row | judged(sec)


def judged(section: dict) -> dict:
    """The null test's numbers and the verdict (issue 46; absent from older reports)."""
    null, ver = section.get("null"), section.get("verdict")
    if not null or not ver:
        return {}
    return {
        "null": {k: round(null[k], 2) for k in ("mean", "p95", "max")} | {"holds": null["holds"]},
        "verdict": ver["result"],
    }


def lantern_row() -> dict:
    """The lantern sleeve widened 1.2 around on its arm (the tests' arm cylinder)."""
    import numpy as np
    import trimesh

    from ptailor import samples
    from ptailor.pipeline import adjustment
    from ptailor.recipe import load_recipe
    from ptailor.verify.check import verify_section

    g = samples.lantern_sleeve()
    adj = adjustment(g, load_recipe(ROOT / "src/ptailor/recipes/wider-around.yaml"))
    arm = trimesh.creation.cylinder(radius=4.6, segment=[[0, -6, 0], [0, 54, 0]], sections=48)
    t0 = time.perf_counter()
    sec, _ = verify_section(adj, body=(np.asarray(arm.vertices), np.asarray(arm.faces)),
                            units_m=0.01, to_units=1.0)  # fmt: skip
    wall = round(time.perf_counter() - t0, 1)
    row = {"garment": "lantern", "edit": "1.2 around", "wall_s": wall, "rc": 0,
           "triangles": g.n_faces}  # fmt: skip
    for k in KINDS:
        row[k] = worst(sec, k) | (relative(sec, k) if k != "original" else {})
    return row | judged(sec)


def table(rows: list[dict]) -> str:
    head = ("| garment | edit | pattern | stretch p95 | disp. mean | disp. p95 | mean - orig. "
            "| p95 - orig. | settled | steps | s | CPU s |")  # fmt: skip
    lines = [head, "|" + "---|" * 12]
    for r in rows:
        if r["rc"] != 0:
            lines.append(
                f"| {r['garment']} | {r['edit']} | exit {r['rc']}: {r.get('error')} |" + " |" * 9
            )
            continue
        for k in KINDS:
            x = r[k]
            lines.append(
                f"| {r['garment']} | {r['edit']} | {k} | {x['stretch_p95']:.3f} "
                f"| {x['disp_mean']:.2f} "
                f"| {x['disp_p95']:.2f} | {x.get('disp_mean_minus_original', 0):+.2f} "
                f"| {x.get('disp_p95_minus_original', 0):+.2f} | {'yes' if x['settled'] else 'no'} "
                f"| {x['steps']} | {x['seconds']} | {x.get('cpu_s', '')} |"
            )
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--shared", default=str(ROOT.parent / "shared"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--only", nargs="*", default=None)
    ap.add_argument("--no-lantern", action="store_true")
    ap.add_argument("--keep", default=None)
    ap.add_argument(
        "--levels",
        type=int,
        nargs="*",
        default=[0],
        help="subdivision levels to run each garment at (1: 4x, 2: 16x)",
    )
    ap.add_argument("--edits", nargs="*", default=None, help="only these edits")
    a = ap.parse_args()
    shared = Path(a.shared)
    work = Path(a.keep) if a.keep else Path(tempfile.mkdtemp(prefix="ptailor-evidence-"))
    work.mkdir(parents=True, exist_ok=True)
    jobs = [
        (g, e, lv)
        for g, (_, _, edits) in GARMENTS.items()
        if not a.only or g in a.only
        for lv in a.levels
        for e in edits
        if not a.edits or e in a.edits
    ]
    for g, lv in {(g, lv) for g, _, lv in jobs}:  # subdivided once, before the jobs
        garment_path(shared, work, g, lv)
    rows = [] if a.no_lantern else [lantern_row()]
    with ThreadPoolExecutor(a.jobs) as pool:
        rows += list(pool.map(lambda gel: run_one(shared, work, *gel), jobs))
    print(table(rows))
    for r in rows:  # the whole check's CPU, one line per command
        if "cpu_s" in r:
            drapes = " + ".join(f"{r[k]['cpu_s']}" for k in KINDS if k in r)
            print(f"{r['garment']} {r['edit']}: the command {r['cpu_s']} s CPU "
                  f"({r['wall_s']} s wall), its re-drapes {drapes} s")  # fmt: skip
    for r in rows:  # the null test and the verdict, one line per check
        if "null" in r:
            n = r["null"]
            ok = "holds" if n["holds"] else "fails"
            print(f"{r['garment']} {r['edit']}: null mean {n['mean']} p95 {n['p95']} max "
                  f"{n['max']} ({ok}), verdict {r['verdict']}")  # fmt: skip
    res = ROOT / "bench/results"
    res.mkdir(exist_ok=True)
    (res / "evidence.json").write_text(json.dumps(rows, indent=1) + "\n")


if __name__ == "__main__":
    main()
