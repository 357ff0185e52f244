"""Benchmark the catalogue page (``batch --html``, ``ptailor report``) over a large batch.

    python bench/bench_catalogue.py [--garments 200] [--repeat 5]

Adjusts three generated garments (``sample_for_triangles``: 5,000, 10,000 and 20,000
triangles) once with ``ptailor batch``, copies their folders to ``--garments`` folders (a
catalogue of that many garments, a tenth of them failed records without a folder), then
times :func:`ptailor.catalogue.write_catalogue` over it:

- **first**: thumbnails made from every preview (Pillow) and every page written;
- **again**: thumbnails current (written once), the pages rewritten.

Medians over ``--repeat`` runs; also the index page's size. Writes
``bench/results/catalogue.json``.
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from ptailor.catalogue import write_catalogue
from ptailor.catalogue.thumbnails import THUMBNAIL
from ptailor.formats.obj import write_garment
from ptailor.samples import sample_for_triangles
from timing import machine, median

RECIPE = "steps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.2}]\n"


def _catalogue(root: Path, n: int) -> tuple[Path, list[dict]]:
    """``n`` garment folders under ``root / "out"`` and their records."""
    cat, seed = root / "cat", root / "seed"
    cat.mkdir()
    for k, tris in enumerate((5_000, 10_000, 20_000)):
        write_garment(cat / f"g{k}.obj", sample_for_triangles(tris))
    (root / "r.yaml").write_text(RECIPE)
    log = root / "seed.jsonl"
    cmd = [sys.executable, "-m", "ptailor", "batch", str(root / "r.yaml"), str(cat),
           "-o", str(seed), "-q", "--log", str(log)]  # fmt: skip
    subprocess.run(cmd, check=True)
    seeds = [json.loads(line) for line in log.read_text().splitlines()]
    out, records = root / "out", []
    out.mkdir()
    for i in range(n):
        rec = dict(seeds[i % 3], index=i + 1, garment=f"cat/garment{i:04d}.obj")
        rec["out"] = str(out / f"garment{i:04d}")
        if i % 10 == 9:  # a failed one: a record, no folder
            rec.update(status="failed", failure="gate", reason="gate: sleeve: area change",
                       failed_gates=["--max-area-change"])  # fmt: skip
        else:
            shutil.copytree(seed / f"g{i % 3}", rec["out"])
        records.append(rec)
    return out, records


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--garments", type=int, default=200)
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        out, records = _catalogue(Path(tmp), args.garments)
        first, again = [], []
        for _ in range(args.repeat):
            for t in out.glob(f"*/{THUMBNAIL}"):
                t.unlink()
            t0 = time.perf_counter()
            write_catalogue(out, records)
            first.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            write_catalogue(out, records)
            again.append(time.perf_counter() - t0)
        size = (out / "index.html").stat().st_size
    n = args.garments
    result = {
        "machine": machine(),
        "garments": n,
        "repeat": args.repeat,
        "first_s": median(first),
        "again_s": median(again),
        "first_ms_per_garment": 1000 * median(first) / n,
        "again_ms_per_garment": 1000 * median(again) / n,
        "index_bytes": size,
    }
    per_first, per_again = result["first_ms_per_garment"], result["again_ms_per_garment"]
    print(
        f"{n} garments: first {median(first):.2f} s ({per_first:.1f} ms a garment, thumbnails "
        f"made), again {median(again):.2f} s ({per_again:.1f} ms a garment); "
        f"index.html {size / 1e3:.0f} kB"
    )
    results = Path(__file__).resolve().parent / "results"
    results.mkdir(exist_ok=True)
    (results / "catalogue.json").write_text(json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
