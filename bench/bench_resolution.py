"""Production resolution: the shared garments at 1x, 4x and 16x triangles, six edits each.

    python bench/bench_resolution.py [--garments tee6,tshirt,longsleeve,dress]
                                     [--levels 0,1,2] [--edits loosen,sleeve,gather]
                                     [--no-symmetric] [--full-adjust] [--quick] [--out FILE]
                                     [--garment PATH ... [--pattern-units U]
                                      [--drape-units U] [--up AXIS] [--front AXIS]]

``--garment PATH`` (repeatable) runs on those garments instead of the shared ones, with
``ptailor adjust``'s unit and axis options for them (``bench/garments.py``); the panels the
edits act on come from ``ptailor inspect``: the sleeve the left sleeve (its panels named
``sleeve...left...``, else the first ``sleeve...``, else the smallest panel), the torso the
other panels, the gather the longest seam between a torso panel and a sleeve panel (else
between any two panels). An edit a garment cannot take is reported and the rest go on.
``--quick``: 1x and 4x, no ``symmetric: true`` runs.

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
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from garments import GarmentOptions, add_garment_options, inspect
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


@dataclass(frozen=True)
class Case:
    """A garment to run: its name, file, options for ptailor and the panels of the edits."""

    name: str
    path: Path
    opts: GarmentOptions
    names: dict


def shared_cases(keys: list[str]) -> list[Case]:
    """The shared garments ``keys`` (:data:`GARMENTS`)."""
    if not (SHARED / "garments").is_dir():
        sys.exit(f"bench_resolution: no garments under {SHARED} (set PTAILOR_SHARED)")
    out = []
    for key in keys:
        rel, pu, du, names = GARMENTS[key]
        out.append(Case(key, SHARED / "garments" / rel, GarmentOptions(pu, du), names))
    return out


def placed_names(info: dict) -> dict:
    """The panels of the three edits, from ``ptailor inspect``'s JSON of a garment."""
    area = {p["name"]: float(p["area"]) for p in info["panels"]}
    sleeves = [n for n in area if "sleeve" in n]
    sleeve = [n for n in sleeves if "left" in n] or sleeves[:1] or [min(area, key=area.get)]
    torso = [n for n in area if n not in sleeves and n not in sleeve] or [max(area, key=area.get)]
    between = [s for s in info["seams"] if len(set(s["panels"])) == 2]
    across = [s for s in between if {*s["panels"]} & {*torso} and {*s["panels"]} & {*sleeve}]
    gather = max(across or between, key=lambda s: max(s["lengths"]), default=None)
    if gather is None:
        pair = [torso[0], sleeve[0]]
    else:
        pair = sorted(gather["panels"], key=lambda n: n not in torso)  # the torso's first
    return {"torso": torso, "sleeve": sleeve, "gather": pair}


def given_cases(paths: list[Path], opts: GarmentOptions) -> list[Case]:
    """``--garment`` files, their edits placed from ``ptailor inspect``."""
    out = []
    for path in paths:
        names = placed_names(inspect(path, opts))
        print(f"{path.stem}: {names}", flush=True)
        out.append(Case(path.stem, path, opts, names))
    return out


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


def run_case(src: Path, rec: Path, out: Path, opts: GarmentOptions, *, lean: bool) -> dict:
    """One ``ptailor adjust`` subprocess; its report, wall/CPU seconds and peak RSS, or
    ``{"error": its message}``."""
    if out.exists():
        shutil.rmtree(out)
    cmd = [*ptailor_command(), "adjust", str(src), str(rec), "-o", str(out), "-q", *opts.cli()]
    if lean:
        cmd += ["--no-baseline", "--formats", "obj"]
    err = out.parent / "stderr.txt"
    with open(out.parent / "stdout.txt", "w") as fh, open(err, "w") as eh:
        try:
            wall, cpu, rss = run_measured(cmd, stdout=fh, stderr=eh, env=one_blas_thread_env())
        except subprocess.CalledProcessError as exc:
            return {"error": err.read_text().strip() or f"exit {exc.returncode}"}
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
        if "error" in r:
            out.append(f"| {r['garment']} | {r['x']} | | {r['edit']} | failed: {r['error']} |")
            continue
        agree = "" if r["agree_1x_cm"] is None else f"{10 * r['agree_1x_cm']:.2f}"
        newton = "" if r.get("newton_steps") is None else str(r["newton_steps"])
        zig = "**yes**" if any("zigzags" in w for w in r.get("warnings", ())) else ""
        out.append(
            f"| {r['garment']} | {r['x']} | {r['triangles']:,} | {r['edit']} | "
            f"{r['iterations']} | {newton} | {'yes' if r['converged'] else '**no**'} | "
            f"{r['flatten_s']:.2f} | {r['libigl_s'] or float('nan'):.2f} | "
            f"{r['flatten_over_libigl']:.2f} | "
            f"{r['lean_over_libigl']:.2f} | {r['worst_seam_cm']:.1e} | {zig} | {agree} |"
        )
    return "\n".join(out)


def one_run(case: Case, src: Path, rec: Path, tmp: Path, *, full_too: bool) -> dict:
    """The lean run of one recipe on one resolution of a garment (and the default one with
    ``full_too``), with libigl on its edited drape: the row's measured part."""
    from ptailor.formats.garment import load_garment

    r = run_case(src, rec, tmp / "out", case.opts, lean=True)
    if "error" in r:
        return r
    rep = r["report"]
    e = written_garment(tmp / "out" / "garment.obj")
    o = case.opts
    g_in = load_garment(src, pattern_units=o.pattern_units, drape_units=o.drape_units).garment
    seam_worst, seam_check = worst_seam(rep, e)
    igl = libigl_case(g_in, e)
    full = None
    if full_too:
        f = run_case(src, rec, tmp / "full", case.opts, lean=False)
        if "error" not in f:
            full = {k: f[k] for k in ("wall_s", "cpu_s", "rss_mb")}
            full["timing_s"] = f["report"]["timing_s"]
    sol = rep["solver"]
    row = {
        "triangles": len(e.F2), "vt": e.V2,
        "iterations": sol["iterations"], "converged": sol["converged"],
        "newton_steps": sol.get("newton_steps"), "seam_violation": sol.get("seam_violation"),
        "worst_seam_cm": seam_worst, "report_vs_obj_cm": seam_check,
        "warnings": rep["warnings"],
        "flatten_s": rep["timing_s"]["flatten"], "timing_s": rep["timing_s"],
        "wall_s": r["wall_s"], "cpu_s": r["cpu_s"], "rss_mb": r["rss_mb"],
        "libigl_s": igl.get("cpu_median_s"), "libigl": igl, "full": full,
    }  # fmt: skip
    li = row["libigl_s"] or float("nan")
    row["flatten_over_libigl"] = row["flatten_s"] / li
    row["lean_over_libigl"] = row["cpu_s"] / li
    if full:
        row["full_over_libigl"] = full["cpu_s"] / li
    return row


def print_row(row: dict) -> None:
    """One line per run, as it finishes."""
    head = f"{row['garment']:10s} {row['x']:3d}x {row['edit']:11s}"
    if "error" in row:
        print(f"{head} FAILED: {row['error']}", flush=True)
        return
    agree, full = row["agree_1x_cm"], row["full"]
    print(
        f"{head} it {row['iterations']:3d} {'conv' if row['converged'] else 'NOT '} seam "
        f"{row['worst_seam_cm']:.1e} cm  flatten {row['flatten_s']:6.2f}s "
        f"libigl {row['libigl_s'] or float('nan'):5.2f}s ratio {row['flatten_over_libigl']:4.2f} "
        f"lean {row['lean_over_libigl']:4.2f}"
        + (f" full {row['full_over_libigl']:4.2f}" if full else "")
        + (f" 1x-agree {agree * 10:.3f} mm" if agree is not None else "")
        + (f" WARN {row['warnings']}" if row["warnings"] else ""),
        flush=True,
    )


def run_garment(case: Case, a: argparse.Namespace, tmp: Path) -> list[dict]:
    """Every resolution and edit of one garment: the rows."""
    rows = []
    base: dict[str, np.ndarray] = {}  # the 1x patterns, by edit
    edits = a.edits.split(",")
    for lev in [int(x) for x in a.levels.split(",")]:
        src = case.path
        if lev:
            src = tmp / f"{case.name}_x{4**lev}{case.path.suffix}"
            subdivide_obj(case.path, src, levels=lev)
        for edit in edits:
            for sym in [False] if a.no_symmetric else [False, True]:
                key = f"{edit}{'_sym' if sym else ''}"
                rec = tmp / f"{key}_{case.name}.yaml"
                rec.write_text(recipe(edit, case.names, symmetric=sym))
                full_too = a.full_adjust and edit == edits[0] and not sym
                row = {"garment": case.name, "x": 4**lev, "edit": key}
                row.update(one_run(case, src, rec, tmp, full_too=full_too))
                vt = row.pop("vt", None)
                row["agree_1x_cm"] = None
                if vt is not None and lev == 0:
                    base[key] = vt
                elif vt is not None and key in base:
                    n1 = len(base[key])
                    row["agree_1x_cm"] = float(np.linalg.norm(vt[:n1] - base[key], axis=1).max())
                print_row(row)
                rows.append(row)
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--garments", default=",".join(GARMENTS))
    ap.add_argument("--levels", default=None, help="subdivisions [default: 0,1,2; quick: 0,1]")
    ap.add_argument("--edits", default="loosen,sleeve,gather")
    ap.add_argument("--no-symmetric", action="store_true")
    ap.add_argument("--full-adjust", action="store_true")
    ap.add_argument("--quick", action="store_true", help="1x and 4x, no symmetric runs")
    ap.add_argument("--out", default=str(RESULTS))
    ap.add_argument(
        "--table", metavar="RESULTS", help="print a results file as a table, run nothing"
    )
    add_garment_options(ap, many=True)
    a = ap.parse_args()
    if a.table:
        print(markdown_table(json.loads(Path(a.table).read_text())["rows"]))
        return
    a.levels = a.levels or ("0,1" if a.quick else "0,1,2")
    a.no_symmetric = a.no_symmetric or a.quick
    if a.garment:
        cases = given_cases(a.garment, GarmentOptions.from_args(a))
    else:
        cases = shared_cases(a.garments.split(","))
    rows: list[dict] = []
    with tempfile.TemporaryDirectory(prefix="ptailor-res-") as tmp:
        for case in cases:
            rows += run_garment(case, a, Path(tmp))
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(json.dumps({"machine": machine(), "rows": rows}, indent=1))
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
