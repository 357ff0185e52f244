"""The null test alone: the original pattern re-draped from the original drape on a body.

    python bench/bench_null.py tee6 [dress ...] [--shared ../shared] [--max-steps N]
                               [--set friction=0.5 friction_slip=1e-4 ...]

For each shared garment, its own pattern sewn on its own drape with ``--body auto`` (the
fitted mean body) and settled with the engine: how far it lands from where it started
(mean, p95, max, cm; :func:`ptailor.verify.verdict.null_test`), whether it settled and why
(:mod:`ptailor.verify.settle`), steps, wall and CPU seconds. One re-drape per garment (a
third of a check): what ``--set`` (any :class:`ptailor.verify.engine.Settings` field) does
to the null test and to settling, measured without the other two. Prints one line per
garment and writes ``bench/results/null.json``.
"""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import fields, replace
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: garment -> (path under shared, pattern units, drape units)
GARMENTS = {
    "tee6": ("garments/gpg_tee6/tee6_sim.obj", "0.3333cm", "0.3333cm"),
    "tshirt": ("garments/diffavatar/tshirt.obj", "auto", None),
    "longsleeve": ("garments/diffavatar/longsleeve_initial.obj", "auto", None),
    "dress": ("garments/diffavatar/dress_initial.obj", "auto", None),
}


def settings_from(pairs: list[str], max_steps: int | None):
    """The engine's settings with ``NAME=VALUE`` overrides (numbers, or comma tuples)."""
    from ptailor.verify.engine import Settings

    s = Settings() if max_steps is None else Settings(max_steps=max_steps)
    kinds = {f.name: f.type for f in fields(Settings)}
    over = {}
    for pair in pairs:  # a loop over a few options
        name, _, value = pair.partition("=")
        if name not in kinds:
            raise SystemExit(f"bench_null: no setting {name!r} (known: {', '.join(kinds)})")
        cur = getattr(s, name)
        if isinstance(cur, tuple):
            over[name] = tuple(float(v) for v in value.split(","))
        elif isinstance(cur, bool) or cur is None:
            over[name] = value.lower() in ("1", "true", "yes")
        else:
            over[name] = type(cur)(float(value))
    return replace(s, **over)


def null_one(shared: Path, name: str, settings) -> dict:
    """The null re-drape of one garment: its record."""
    import numpy as np

    from ptailor.formats.garment import load_garment
    from ptailor.model.structure import structure
    from ptailor.model.units import CM_PER
    from ptailor.run.inputs import fitted_body
    from ptailor.run.verify import body_arrays, to_y_up
    from ptailor.verify.check import verify_patterns
    from ptailor.verify.verdict import null_test

    path, pu, du = GARMENTS[name]
    g = load_garment(str(shared / path), units="cm", pattern_units=pu, drape_units=du).garment
    body, fit = fitted_body(g, path=path)
    st = structure(g)
    R = to_y_up(g.frame)
    V, F = body_arrays(body)
    t0 = time.perf_counter()
    sec, _, _ = verify_patterns(
        g.V3 @ R.T, g.F3, g.F2, {"original": g.V2}, g.V2, g.V3 @ R.T,
        panel_names=[p.name for p in st.panels], face_panel=np.asarray(st.face_panel),
        vertex_panel=np.asarray(st.vertex_panel), body=(V @ R.T, F),
        frame=type(g.frame)(R @ g.frame.up, R @ g.frame.front),
        units_m=CM_PER["cm"] / 100.0, to_units=1.0, settings=settings,
    )  # fmt: skip
    wall = time.perf_counter() - t0
    r = sec["original"]
    null = null_test(r, cm_per_unit=1.0)
    return {
        "garment": name,
        "triangles": sec["triangles"],
        "null_cm": {k: round(null[k], 2) for k in ("mean", "p95", "max")},
        "holds": null["holds"],
        "settled": r["settled"],
        "why": r["settle"]["why"],
        "steps": r["steps"],
        "wall_s": round(wall, 1),
        "cpu_s": r.get("cpu_seconds"),
        "worst_panel": max(null["panels"], key=lambda n: null["panels"][n]["p95"]),
        "body_fit": fit,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("garments", nargs="+", choices=list(GARMENTS))
    ap.add_argument("--shared", default=str(ROOT.parent / "shared"))
    ap.add_argument("--max-steps", type=int, default=None)
    ap.add_argument("--set", nargs="*", default=[], metavar="NAME=VALUE")
    a = ap.parse_args()
    s = settings_from(a.set, a.max_steps)
    rows = []
    for name in a.garments:  # one garment at a time: one simulation at a time
        row = null_one(Path(a.shared), name, s) | {"set": a.set}
        rows.append(row)
        n = row["null_cm"]
        print(f"{name}: null mean {n['mean']:.2f} p95 {n['p95']:.2f} max {n['max']:.2f} cm "
              f"({'holds' if row['holds'] else 'fails'}; most {row['worst_panel']}), "
              f"{row['why']}; {row['steps']} steps, {row['wall_s']} s wall, "
              f"{row['cpu_s']} s CPU", flush=True)  # fmt: skip
    res = ROOT / "bench" / "results"
    res.mkdir(exist_ok=True)
    (res / "null.json").write_text(json.dumps(rows, indent=1, default=str) + "\n")


if __name__ == "__main__":
    main()
