"""A batch's records: one dict per garment (:data:`RECORD_KEYS`), passed on in input order,
written as JSON lines, and summed up in the end-of-batch table."""

from __future__ import annotations

import json
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path

from ptailor.batch.gates import (
    area_change,
    number,
    p95,
    seam_mismatch,
    verify_number,
    verify_panels,
)

#: a record's keys, in the order they are written
RECORD_KEYS = (
    "index",
    "garment",
    "out",
    "status",
    "failure",
    "reason",
    "seconds",
    "note",
    "panels",
    "max_area_change",
    "max_boundary_deviation",
    "max_intrinsic_error_p95",
    "max_seam_mismatch",
    "flipped_triangles",
    "verify_stretch_p95",
    "verify_displacement_p95",
    "spec_fit_max",
    "warnings",
    "failed_gates",
)
#: record statuses; ``ok`` and ``skipped`` are successes
STATUSES = ("ok", "skipped", "failed", "interrupted")


def key_numbers(report: dict) -> dict:
    """A record's numbers from a report: maxima over panels, flips and warnings summed
    (None where the report lacks them: a record shows, it does not judge)."""
    panels = report.get("panels", [])

    def biggest(vals: Iterable[float | None]) -> float | None:
        vs = [v for v in vals if v is not None]
        return round(max(vs), 6) if vs else None

    return {
        "panels": len(panels),
        "max_area_change": biggest(area_change(p) for p in panels),
        "max_boundary_deviation": biggest(number(p.get("boundary_deviation")) for p in panels),
        "max_intrinsic_error_p95": biggest(p95(p) for p in panels),
        "max_seam_mismatch": biggest(seam_mismatch(s) for s in report.get("seams", [])),
        "flipped_triangles": sum(int(p.get("flipped_triangles") or 0) for p in panels),
        **verify_numbers(report),
        "spec_fit_max": number((report.get("spec") or {}).get("fit_max")),
        "warnings": len(report.get("warnings", [])),
    }


def verify_numbers(report: dict) -> dict:
    """A record's re-drape numbers: the adjusted pattern's worst panel stretch p95 and
    displacement p95 (None without the check)."""
    panels = verify_panels(report) or {}
    out = {}
    for measure in ("stretch", "displacement"):
        vs = [v for p in panels.values() if (v := verify_number(p, measure)) is not None]
        out[f"verify_{measure}_p95"] = round(max(vs), 6) if vs else None
    return out


def is_record(line: str) -> bool:
    """Whether ``line`` is one of :func:`record_line`'s (a JSON object with a garment and a
    known status)."""
    try:
        r = json.loads(line)
    except ValueError:
        return False
    return isinstance(r, dict) and "garment" in r and r.get("status") in STATUSES


def log_problem(path: str | Path, inputs: Iterable[str | Path]) -> str | None:
    """Why a batch may not write its log to ``path``, or None where it may: the file is
    absent, empty, or a log of ptailor's records (which the run replaces). An input of the
    run (a garment, the drape beside a DXF, the recipe) or any other file is refused, so
    that ``--log garment.obj`` cannot destroy the garment.

    Parameters
    ----------
    path : str or Path
        The log.
    inputs : iterable of str or Path
        The run's input files.

    Returns
    -------
    str or None
        The problem, for an error message naming ``path``.
    """
    import os

    p = Path(path)
    if not p.exists():
        return None
    for q in inputs:
        try:
            if os.path.samefile(p, q):
                return "is an input of this run; name another file for the log"
        except OSError:
            continue
    if not p.is_file():
        return "is not a regular file"
    try:
        with p.open(encoding="utf-8", errors="strict") as fh:
            for line in fh:
                if line.strip() and not is_record(line):
                    return (
                        "exists and is not a ptailor batch log (a line that is not a record); "
                        "the log is only created or replaced where it is one: remove the file "
                        "or name another"
                    )
    except UnicodeDecodeError:
        return "exists and is not a ptailor batch log (not text); remove it or name another"
    except OSError as exc:
        return f"cannot be read ({exc.strerror or exc})"
    return None


def record_line(record: dict) -> str:
    """A record as one line of JSON (keys in :data:`RECORD_KEYS` order)."""
    return json.dumps({k: record.get(k) for k in RECORD_KEYS})


@dataclass
class BatchResult:
    """Records in input order (unfinished garments have status ``interrupted``).

    ``ran`` counts the garments that were run (``ok`` or ``failed`` after being adjusted,
    not those found unchanged and judged from their stored report); None: every ``ok``
    and ``failed`` one.
    """

    records: list[dict]
    interrupted: bool = False
    seconds: float = 0.0
    where: str = ""
    ran: int | None = None

    def count(self, status: str) -> int:
        return sum(r["status"] == status for r in self.records)

    @property
    def runs(self) -> int:
        """Garments run (``ran``, else every ``ok`` and ``failed`` one): a rate's count."""
        return self.count("ok") + self.count("failed") if self.ran is None else self.ran

    @property
    def exit_status(self) -> int:
        """130 interrupted, 1 some garment failed, else 0."""
        if self.interrupted:
            return 130
        return 1 if any(r["status"] not in ("ok", "skipped") for r in self.records) else 0


class InOrder:
    """Pass records on in input order as soon as every earlier one has arrived."""

    def __init__(self, n: int, sink: Callable[[dict], None]) -> None:
        self.sink = sink
        self.pending: dict[int, dict] = {}
        self.next = 0
        self.n = n

    def add(self, index: int, record: dict) -> None:
        self.pending[index] = record
        while self.next in self.pending:
            self.sink(self.pending.pop(self.next))
            self.next += 1

    def finish(self, records: list[dict]) -> None:
        """Pass on what is left (after an interruption) from ``records``."""
        for i in range(self.next, self.n):
            self.sink(records[i])
        self.next = self.n


def _count_lines(result: BatchResult) -> list[str]:
    counts = {s: result.count(s) for s in STATUSES}
    gated = sum(r["failure"] == "gate" for r in result.records)
    lines = [
        f"{'garments':<12}{len(result.records):>6}",
        f"{'ok':<12}{counts['ok']:>6}",
        f"{'skipped':<12}{counts['skipped']:>6}   (unchanged since their output was written)",
        f"{'failed':<12}{counts['failed']:>6}"
        + (f"   ({gated} by quality gates)" if gated else ""),
    ]
    if counts["interrupted"]:
        lines.append(f"{'interrupted':<12}{counts['interrupted']:>6}   (not done: run again)")
    lines.append(f"{'time':<12}{result.seconds:>8.1f} s: {_rate(result, counts)}")
    return lines


def _rate(result: BatchResult, counts: dict[str, int]) -> str:
    """``3 done, 1 skipped, 0 failed; 20.5 garments/min over the 3 run (where)``: a rate
    only over the garments run (none when every one was unchanged)."""
    ran = result.runs
    done = f"{counts['ok']} done, {counts['skipped']} skipped, {counts['failed']} failed"
    if ran == 0:
        return f"{done}; none run, so no rate"
    rate = f"{60.0 * ran / result.seconds:.1f}" if result.seconds > 0 else "-"
    return f"{done}; {rate} garments/min over the {ran} run ({result.where})"


def _failed_line(record: dict) -> str:
    """``  GARMENT: reason`` (the reason alone when it names the garment already)."""
    if str(record["reason"]).startswith(f"{record['garment']}:"):
        return f"  {record['reason']}"
    return f"  {record['garment']}: {record['reason']}"


def summary_lines(result: BatchResult) -> list[str]:
    """The end-of-batch table: counts, the failed garments with their reasons, time, rate."""
    lines = _count_lines(result)
    failed = [r for r in result.records if r["status"] == "failed"]
    if failed:
        lines.append("failed:")
        lines += [_failed_line(r) for r in failed]
    return lines
