"""Production resolution: the shared garments at 1x, 4x and 16x triangles, six edits each.

    python bench/bench_resolution.py [--garments tee6,tshirt,longsleeve,dress]
                                     [--levels 0,1,2] [--edits loosen,sleeve,gather]
                                     [--no-symmetric] [--full-adjust] [--out FILE]

Every garment of ``../shared/garments`` (or ``$PTAILOR_SHARED/garments``) is subdivided by
``bench/subdivide.py`` (each triangle split in four at its edge midpoints, drape and pattern
alike: the same garment) 0, 1 and 2 times. Each edit (the torso loosened by 2 cm, one
sleeve 1.1 around or the dress's skirt, a 1.2 gather at an armhole or the dress's waist;
each also with ``symmetric: true``) runs as the lean command ``ptailor adjust GARMENT RECIPE
-o OUT --no-baseline --formats obj --json`` in a subprocess. Recorded per run, from what
the run wrote:

- the solver's iterations, ``converged``, its warnings (``report.json``);
- the flatten's seconds (``timing_s.flatten``) and the whole command's wall and CPU seconds;
- the worst seam mismatch in cm (``report.json``'s seams: ``|L_a - r L_b|`` against the
  target ratio), and how far the report's seam lengths are from those a reader measures
  in ``garment.obj``'s ``vt``;
- libigl's ARAP (precomputation + 30 iterations, one pin per panel) on the same edited
  drape (``garment.obj``'s ``v``) in this process, and the ratios flatten / libigl and
  command / libigl (CPU time);
- at 4x and 16x: the largest distance, in cm, between the adjusted pattern at the 1x
  vertices (subdivision keeps them first, in order) and the 1x run's pattern.

``--full-adjust`` also runs the default command (baseline and every output) for the first
edit of each garment and resolution. Prints a table and writes ``bench/results/
resolution.json`` (git-ignored).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np

from subdivide import subdivide_obj
from timing import libigl_arap, machine, one_blas_thread_env, ptailor_command, run_measured

HERE = Path(__file__).resolve().parent
SHARED = Path(os.environ.get("PTAILOR_SHARED", HERE.parent.parent / "shared"))
RESULTS = HERE / "results" / "resolution.json"

#: garment -> (file under shared/garments, --pattern-units, --drape-units, panel names)
GARMENTS = {
    "tee6": ("gpg_tee6/tee6_sim.obj", "0.3333cm", "0.3333cm",
             {"torso": ["front", "back"], "sleeve": ["sleeve_left_front", "sleeve_left_back"],
              "gather": ["front", "sleeve_left_front"]}),
    "tshirt": ("diffavatar/tshirt.obj", "auto", "cm",
               {"torso": ["front", "back"], "sleeve": ["sleeve_left"],
                "gather": ["front", "sleeve_left"]}),
    "longsleeve": ("diffavatar/longsleeve_initial.obj", "auto", "cm",
                   {"torso": ["front", "back"], "sleeve": ["sleeve_left"],
                    "gather": ["front", "sleeve_left"]}),
    "dress": ("diffavatar/dress_initial.obj", "auto", "cm",
              {"torso": ["bodice_front", "bodice_front_left", "bodice_front_right",
                         "bodice_back_left", "bodice_back_right", "bodice_back_left_side",
                         "bodice_back_right_side"],
               "sleeve": ["skirt_front", "skirt_back_left", "skirt_back_right"],
               "gather": ["bodice_front", "skirt_front"]}),
}  # fmt: skip


def recipe(edit: str, names: dict, *, symmetric: bool) -> str:
    """The recipe text of one edit on one garment."""
    sym = "true" if symmetric else "false"
    if edit == "loosen":
        step = f"{{op: loosen, region: {{panels: {names['torso']}}}, by: 2, symmetric: {sym}}}"
    elif edit == "sleeve":
        step = (
            f"{{op: scale, region: {{panels: {names['sleeve']}}}, direction: around, "
            f"axis: auto, factor: 1.1, symmetric: {sym}}}"
        )
    else:
        a, part = names["gather"]
        step = (
            f"{{op: scale_seam, seam: [{a}, {part}], part: {part}, direction: around, "
            f"factor: 1.2, symmetric: {sym}}}"
        )
    return f"units: cm\nsteps:\n  - {step}\n"  # fmt: skip


def worst_seam(report: dict, g) -> tuple[float, float]:
    """The largest ``|mismatch|`` of the report's seams (cm), and the largest difference
    between the report's seam lengths after and those of the written garment ``g``'s pattern
    (cm): what the report claims, and whether a reader of ``garment.obj`` sees the same."""
    from ptailor.model.garment import panel_labels, panels
    from ptailor.model.seams import seams

    worst = max((abs(s["mismatch"]) for s in report.get("seams", [])), default=0.0)
    plist = panels(g)
    found = seams(g.F3, g.F2, panel_labels(plist, len(g.F2)))
    names = [p.name for p in plist]

    def keyed(items):  # seams grouped by their two panels, then by their lengths
        groups: dict = {}
        for pair, lengths in items:
            groups.setdefault(tuple(sorted(pair)), []).append(sorted(lengths))
        return {k: sorted(v) for k, v in groups.items()}

    written = keyed(([names[i] for i in s.panels], s.lengths(g.V2)) for s in found)
    claimed = keyed((s["panels"], s["length_after"]) for s in report.get("seams", []))
    if written.keys() != claimed.keys():
        return worst, float("inf")
    diff = max(
        (abs(a - b) for k in written for w, c in zip(written[k], claimed[k], strict=True)
         for a, b in zip(w, c, strict=True)),
        default=0.0,
    )  # fmt: skip
    return worst, diff


def run_case(src: Path, rec: Path, out: Path, units: tuple[str, str], *, lean: bool) -> dict:
    """One ``ptailor adjust`` subprocess; its report, wall/CPU seconds and peak RSS."""
    if out.exists():
        shutil.rmtree(out)
    cmd = [*ptailor_command(), "adjust", str(src), str(rec), "-o", str(out), "-q",
           "--pattern-units", units[0], "--drape-units", units[1]]  # fmt: skip
    if lean:
        cmd += ["--no-baseline", "--formats", "obj"]
    with open(out.parent / "stdout.txt", "w") as fh:
        wall, cpu, rss = run_measured(cmd, stdout=fh, env=one_blas_thread_env())
    report = json.loads((out / "report.json").read_text())
    return {"wall_s": wall, "cpu_s": cpu, "rss_mb": rss, "report": report}


def written_garment(path: Path):
    """A written ``garment.obj`` read in the units its header states."""
    import re

    from ptailor.formats.garment import load_garment

    with path.open() as fh:
        head = fh.readline() + fh.readline()
    m = re.search(r"v: ([0-9.eE+-]+) cm per unit; vt: ([0-9.eE+-]+) cm per unit", head)
    pu, du = (f"{m.group(2)}cm", f"{m.group(1)}cm") if m else ("cm", "cm")
    return load_garment(path, pattern_units=pu, drape_units=du).garment


def libigl_case(g, e) -> dict:
    """libigl's ARAP on the run's edited drape (``e``, the written garment), on the input
    garment ``g``'s mesh, one pin per panel."""
    from ptailor.method.flatten import central_vertices
    from ptailor.model.garment import panels, vertex_labels

    plist = panels(g)
    pins = central_vertices(g.V2, vertex_labels(plist, len(g.V2)), len(plist))
    r = libigl_arap(e.V3, g.F3, g.V2, g.F2, pins, 1)
    r.pop("U", None)
    return r


def markdown_table(rows: list[dict]) -> str:
    """The results as a markdown table: garment x resolution x edit -> iterations (Newton
    steps among them), seconds, ratios to libigl, worst seam, a zigzag warning, agreement
    with 1x."""
    head = (
        "| garment | x | triangles | edit | iterations | Newton | converged | flatten s "
        "| libigl s | flatten / libigl | lean / libigl | worst seam cm | zigzag | vs 1x mm |\n"
        "|---|---:|---:|---|---:|---:|---|---:|---:|---:|---:|---:|---|---:|"
    )
    out = [head]
    for r in rows:
        agree = "" if r["agree_1x_cm"] is None else f"{10 * r['agree_1x_cm']:.2f}"
        newton = "" if r.get("newton_steps") is None else str(r["newton_steps"])
        zig = "**yes**" if any("zigzags" in w for w in r.get("warnings", ())) else ""
        out.append(
            f"| {r['garment']} | {r['x']} | {r['triangles']:,} | {r['edit']} | "
            f"{r['iterations']} | {newton} | {'yes' if r['converged'] else '**no**'} | "
            f"{r['flatten_s']:.2f} | {r['libigl_s']:.2f} | {r['flatten_over_libigl']:.2f} | "
            f"{r['lean_over_libigl']:.2f} | {r['worst_seam_cm']:.1e} | {zig} | {agree} |"
        )
    return "\n".join(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--garments", default=",".join(GARMENTS))
    ap.add_argument("--levels", default="0,1,2")
    ap.add_argument("--edits", default="loosen,sleeve,gather")
    ap.add_argument("--no-symmetric", action="store_true")
    ap.add_argument("--full-adjust", action="store_true")
    ap.add_argument("--out", default=str(RESULTS))
    ap.add_argument(
        "--table", metavar="RESULTS", help="print a results file as a table, run nothing"
    )
    a = ap.parse_args()
    if a.table:
        print(markdown_table(json.loads(Path(a.table).read_text())["rows"]))
        return
    if not (SHARED / "garments").is_dir():
        sys.exit(f"bench_resolution: no garments under {SHARED} (set PTAILOR_SHARED)")
    from ptailor.formats.garment import load_garment

    levels = [int(x) for x in a.levels.split(",")]
    rows: list[dict] = []
    with tempfile.TemporaryDirectory(prefix="ptailor-res-") as tmp:
        tmp = Path(tmp)
        for gname in a.garments.split(","):
            rel, pu, du, names = GARMENTS[gname]
            base: dict[str, np.ndarray] = {}
            for lev in levels:
                src = SHARED / "garments" / rel
                if lev:
                    src = tmp / f"{gname}_x{4**lev}.obj"
                    subdivide_obj(SHARED / "garments" / rel, src, levels=lev)
                g_in = load_garment(src, pattern_units=pu, drape_units=du).garment
                for edit in a.edits.split(","):
                    for sym in [False] if a.no_symmetric else [False, True]:
                        key = f"{edit}{'_sym' if sym else ''}"
                        rec = tmp / f"{key}_{gname}.yaml"
                        rec.write_text(recipe(edit, names, symmetric=sym))
                        out = tmp / "out"
                        r = run_case(src, rec, out, (pu, du), lean=True)
                        rep = r["report"]
                        e = written_garment(out / "garment.obj")
                        vt, n_tri = e.V2, len(e.F2)
                        agree = None
                        if lev == 0:
                            base[key] = vt
                        elif key in base:
                            n1 = len(base[key])
                            agree = float(np.linalg.norm(vt[:n1] - base[key], axis=1).max())
                        seam_worst, seam_check = worst_seam(rep, e)
                        igl = libigl_case(g_in, e)
                        full = None
                        if a.full_adjust and edit == a.edits.split(",")[0] and not sym:
                            f = run_case(src, rec, tmp / "full", (pu, du), lean=False)
                            full = {
                                "wall_s": f["wall_s"],
                                "cpu_s": f["cpu_s"],
                                "rss_mb": f["rss_mb"],
                                "timing_s": f["report"]["timing_s"],
                            }
                        sol = rep["solver"]
                        row = {
                            "garment": gname, "x": 4**lev, "edit": key,
                            "triangles": n_tri,
                            "iterations": sol["iterations"], "converged": sol["converged"],
                            "newton_steps": sol.get("newton_steps"),
                            "seam_violation": sol.get("seam_violation"),
                            "worst_seam_cm": seam_worst, "report_vs_obj_cm": seam_check,
                            "warnings": rep["warnings"],
                            "flatten_s": rep["timing_s"]["flatten"], "timing_s": rep["timing_s"],
                            "wall_s": r["wall_s"], "cpu_s": r["cpu_s"], "rss_mb": r["rss_mb"],
                            "libigl_s": igl.get("cpu_median_s"), "libigl": igl,
                            "agree_1x_cm": agree, "full": full,
                        }  # fmt: skip
                        li = row["libigl_s"] or float("nan")
                        row["flatten_over_libigl"] = row["flatten_s"] / li
                        row["lean_over_libigl"] = row["cpu_s"] / li
                        if full:
                            row["full_over_libigl"] = full["cpu_s"] / li
                        rows.append(row)
                        print(
                            f"{gname:10s} {4**lev:3d}x {key:11s} it {sol['iterations']:3d} "
                            f"{'conv' if sol['converged'] else 'NOT '} seam "
                            f"{row['worst_seam_cm']:.1e} cm  flatten {row['flatten_s']:6.2f}s "
                            f"libigl {li:5.2f}s ratio {row['flatten_over_libigl']:4.2f} "
                            f"lean {row['lean_over_libigl']:4.2f}"
                            + (f" full {row['full_over_libigl']:4.2f}" if full else "")
                            + (f" 1x-agree {agree * 10:.3f} mm" if agree is not None else "")
                            + (f" WARN {rep['warnings']}" if rep["warnings"] else ""),
                            flush=True,
                        )
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(json.dumps({"machine": machine(), "rows": rows}, indent=1))
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
