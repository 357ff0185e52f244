"""Catalogues: one recipe over many garments, one output folder each (``ptailor batch``).

The library side, without click: expanding garment arguments, naming output folders,
the skip-unchanged stamp, quality gates, the per-garment job (run in-process, in a pool of
worker processes or on a Dask cluster) and the JSON-lines records.

Each garment is one :class:`Job`; :func:`run_job` turns it into a record (a dict, see
:data:`RECORD_KEYS`) and never raises for a bad garment: a :class:`PtailorError` is a
failed record, a broken quality gate too (and no folder is written, through
:func:`ptailor.job.run_adjust`'s ``check``), any other exception an internal-error record.
"""

from __future__ import annotations

import contextlib
import glob
import json
import os
import re
import shutil
import signal
import threading
import time
import uuid
from collections.abc import Callable, Iterable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import IO, Any

from ptailor import __version__, tolerances
from ptailor.digest import file_sha256, text_sha256
from ptailor.errors import PtailorError

#: the stamp file written into each garment's output folder
STAMP = "batch.json"
#: a record's keys, in the order they are written
RECORD_KEYS = (
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
    "warnings",
)
#: record statuses; ``ok`` and ``skipped`` are successes
STATUSES = ("ok", "skipped", "failed", "interrupted")
_GLOB_CHARS = re.compile(r"[*?\[]")


# --------------------------------------------------------------------------- arguments


def expand_garments(
    specs: Sequence[str],
    *,
    stdin: IO[str] | None = None,
    exclude_under: str | Path | None = None,
    warn: Callable[[str], None] | None = None,
) -> list[str]:
    """The garment paths that ``specs`` name, in order, each once.

    Parameters
    ----------
    specs : list of str
        Paths; globs (``*``, ``?``, ``[``, ``**`` recursive; expanded sorted, unless the
        argument is an existing file); folders (every ``*.obj`` and ``*.dxf`` below,
        sorted); ``-``: the paths listed on ``stdin``, one per line (blank lines ignored, no
        expansion). An OBJ that is the drape of a listed DXF (``X.obj`` beside ``X.dxf``)
        is left out: the pair is one garment.
    stdin : text stream, optional
        Read for ``-``.
    exclude_under : path, optional
        The output root: files below it found by a glob or a folder are left out (they are
        earlier outputs), paths given literally are kept.
    warn : callable, optional
        Called with a message for each glob or folder that finds no garment.

    Returns
    -------
    list of str
        As given (not resolved); a path named twice is kept the first time only. A literal
        path that does not exist is kept: it fails as a garment.

    Raises
    ------
    PtailorError
        ``-`` given twice or without ``stdin``.
    """
    out_root = Path(exclude_under).resolve() if exclude_under is not None else None

    def outside(p: str) -> bool:
        return out_root is None or out_root not in Path(p).resolve().parents

    paths: list[str] = []
    read_stdin = False
    for spec in specs:
        if spec == "-":
            if read_stdin or stdin is None:
                raise PtailorError("'-' (garment paths on stdin) can be given once")
            read_stdin = True
            paths += [ln.strip() for ln in stdin.read().splitlines() if ln.strip()]
        elif Path(spec).is_dir() or (_GLOB_CHARS.search(spec) and not Path(spec).is_file()):
            if Path(spec).is_dir():
                root = os.path.join(glob.escape(spec), "**")
                found = [
                    f
                    for pat in ("*.obj", "*.OBJ", "*.dxf", "*.DXF")
                    for f in glob.glob(os.path.join(root, pat), recursive=True)
                ]
            else:
                found = glob.glob(spec, recursive=True)
            found = [p for p in sorted(found) if Path(p).is_file() and outside(p)]
            if not found and warn is not None:
                warn(f"{spec}: no garments found")
            paths += found
        else:
            paths.append(spec)
    paths = _without_drapes(paths)
    seen: set[str] = set()
    unique = []
    for p in paths:
        key = os.path.realpath(p)
        if key not in seen:
            seen.add(key)
            unique.append(p)
    return unique


def drape_for(garment: str | Path) -> str | None:
    """The drape OBJ a DXF pattern is paired with: the file beside it with the same stem
    (``X.dxf`` -> ``X.obj``); None for an OBJ garment (it holds its own drape)."""
    p = Path(garment)
    if p.suffix.lower() != ".dxf":
        return None
    for ext in (".obj", ".OBJ"):
        if p.with_suffix(ext).is_file():
            return str(p.with_suffix(ext))
    return str(p.with_suffix(".obj"))  # missing: the garment fails naming it


def _without_drapes(paths: list[str]) -> list[str]:
    """Drop the OBJs that are a listed DXF's drape (a folder holding ``X.dxf`` and
    ``X.obj`` is one garment, the DXF pattern with its drape)."""
    drapes = {os.path.realpath(d) for d in map(drape_for, paths) if d is not None}
    return [p for p in paths if os.path.realpath(p) not in drapes]


def output_names(paths: Sequence[str]) -> list[tuple[str, str | None]]:
    """One folder name per garment: the file's stem, made unique in input order.

    The first garment with a stem gets it; later ones get ``stem-2``, ``stem-3``, ...
    (skipping names that are some other garment's stem).

    Returns
    -------
    list of (name, note)
        ``note`` says why a name is not the stem (``None`` when it is).
    """
    stems = [Path(p).stem or "garment" for p in paths]
    taken = set(stems)
    used: set[str] = set()
    first: dict[str, str] = {}
    out = []
    for p, stem in zip(paths, stems, strict=True):
        if stem not in used:
            used.add(stem)
            first[stem] = p
            out.append((stem, None))
            continue
        k = 2
        while f"{stem}-{k}" in used or f"{stem}-{k}" in taken:
            k += 1
        name = f"{stem}-{k}"
        used.add(name)
        out.append((name, f"stem {stem!r} is shared with {first[stem]}: folder {name}"))
    return out


# --------------------------------------------------------------------------- stamp


def recipe_digest(recipe) -> str:
    """SHA-256 of the validated recipe as sorted JSON (every default filled in, no source).

    Comments, formatting, key order and spelled-out defaults do not change it.
    """
    data = asdict(recipe)
    data.pop("source", None)
    text = json.dumps(data, sort_keys=True, separators=(",", ":"), default=str)
    return text_sha256(text)


def make_stamp(garment: str, garment_sha: str, recipe_sha: str, options: dict) -> dict:
    """The ``batch.json`` stamp; its ``key`` decides whether a folder is up to date.

    ``key`` is the SHA-256 of the garment's contents, the canonical recipe, the options
    that change the outputs and the ptailor version (not the garment's path).
    """
    keyed = {
        "ptailor_version": __version__,
        "garment_sha256": garment_sha,
        "recipe_sha256": recipe_sha,
        "options": options,
    }
    key = text_sha256(json.dumps(keyed, sort_keys=True))
    return {
        "key": key,
        "ptailor_version": __version__,
        "garment": {"path": garment, "sha256": garment_sha},
        "recipe": {"sha256": recipe_sha},
        "options": options,
    }


def up_to_date(folder: Path, stamp: dict) -> dict | None:
    """The folder's report when its stamp has ``stamp``'s key and its outputs are all there."""
    try:
        old = json.loads((folder / STAMP).read_text())
        if not isinstance(old, dict) or old.get("key") != stamp["key"]:
            return None
        report = json.loads((folder / "report.json").read_text())
    except (OSError, ValueError):
        return None
    outputs = report.get("outputs") if isinstance(report, dict) else None
    if not isinstance(outputs, list) or not all((folder / n).is_file() for n in outputs):
        return None
    return report


# --------------------------------------------------------------------------- gates


@dataclass(frozen=True)
class Gates:
    """Quality gates: a garment whose report breaks one fails and gets no folder.

    Attributes
    ----------
    max_area_change : float, optional
        Fraction: a panel with ``|area_after / area_before - 1|`` above it fails.
    max_boundary_deviation : float, optional
        In the report's units: a panel whose ``boundary_deviation`` is above it fails.
    max_intrinsic_error : float, optional
        A panel whose ``intrinsic_scale_error.p95`` is above it fails (the 95th percentile
        over the panel's triangles, so a few triangles at a seam do not decide).
    max_seam_mismatch : float, optional
        In the report's units: a seam whose ``|mismatch|`` (its two sides' length difference
        at the target ratio) is above it fails.
    fail_on_flips : bool
        A panel with ``flipped_triangles > 0`` fails.
    """

    max_area_change: float | None = None
    max_boundary_deviation: float | None = None
    max_intrinsic_error: float | None = None
    max_seam_mismatch: float | None = None
    fail_on_flips: bool = False


class GateFailedError(Exception):
    """A report broke a quality gate (raised from ``run_adjust``'s ``check``)."""

    def __init__(self, problems: list[str], report: dict) -> None:
        self.problems = problems
        self.report = report
        super().__init__("; ".join(problems))


def _num(x: Any) -> float | None:
    return float(x) if isinstance(x, int | float) and not isinstance(x, bool) else None


def area_change(panel: dict) -> float | None:
    """``|area_after / area_before - 1|`` of a report panel, or None."""
    a0, a1 = _num(panel.get("area_before")), _num(panel.get("area_after"))
    if a0 is None or a1 is None or a0 <= 0:
        return None
    return abs(a1 / a0 - 1.0)


def _p95(panel: dict) -> float | None:
    err = panel.get("intrinsic_scale_error")
    return _num(err.get("p95")) if isinstance(err, dict) else None


def gate_failures(report: dict, gates: Gates) -> list[str]:
    """Every gate the report breaks, one line per panel and gate."""
    probs = []
    units_rec = report.get("units")
    units = units_rec.get("computation", "") if isinstance(units_rec, dict) else units_rec or ""
    for p in report.get("panels", []):  # a loop over panels
        name = p.get("name", "?")
        da = area_change(p)
        if gates.max_area_change is not None and da is not None and da > gates.max_area_change:
            probs.append(
                f"{name}: area change {100 * da:.3g} % > {100 * gates.max_area_change:.3g} %"
            )
        dev = _num(p.get("boundary_deviation"))
        lim = gates.max_boundary_deviation
        if lim is not None and dev is not None and dev > lim:
            probs.append(f"{name}: boundary deviation {dev:.4g} > {lim:.4g} {units}".rstrip())
        err = _p95(p)
        lim = gates.max_intrinsic_error
        if lim is not None and err is not None and err > lim:
            probs.append(f"{name}: intrinsic-scale error p95 {err:.4g} > {lim:.4g}")
        flips = int(p.get("flipped_triangles") or 0)
        if gates.fail_on_flips and flips > 0:
            probs.append(f"{name}: {flips} flipped triangle{'s' if flips != 1 else ''}")
    lim = gates.max_seam_mismatch
    if lim is not None:
        for s in report.get("seams", []):  # a loop over seams
            mis = seam_mismatch(s)
            if mis is None or mis > lim:
                shown = "missing" if mis is None else f"{mis:.4g} > {lim:.4g} {units}".rstrip()
                probs.append(f"seam {' / '.join(s.get('panels', ['?']))}: mismatch {shown}")
    return probs


def seam_mismatch(seam: dict) -> float | None:
    """``|mismatch|`` of a report seam, or None when the report lacks it."""
    mis = _num(seam.get("mismatch"))
    return None if mis is None else abs(mis)


def key_numbers(report: dict) -> dict:
    """A record's numbers from a report: maxima over panels, flips and warnings summed."""
    panels = report.get("panels", [])

    def biggest(vals: Iterable[float | None]) -> float | None:
        vs = [v for v in vals if v is not None]
        return round(max(vs), 6) if vs else None

    return {
        "panels": len(panels),
        "max_area_change": biggest(area_change(p) for p in panels),
        "max_boundary_deviation": biggest(_num(p.get("boundary_deviation")) for p in panels),
        "max_intrinsic_error_p95": biggest(_p95(p) for p in panels),
        "max_seam_mismatch": biggest(seam_mismatch(s) for s in report.get("seams", [])),
        "flipped_triangles": sum(int(p.get("flipped_triangles") or 0) for p in panels),
        "warnings": len(report.get("warnings", [])),
    }


# --------------------------------------------------------------------------- jobs


@dataclass(frozen=True)
class Job:
    """One garment of a batch (picklable: it travels to worker processes and Dask).

    Attributes
    ----------
    index : int
        Position in the input order.
    garment : str
        The path as given (shown in records and in ``report.json``).
    garment_abs : str
        The absolute path that is read.
    out : str
        The output folder as shown (``OUT/name``); ``out_abs`` is written.
    note : str or None
        Why the folder name is not the garment's stem.
    recipe : Recipe
        Validated.
    recipe_sha : str
        :func:`recipe_digest` of it.
    adjust_options : dict
        Keyword arguments of :func:`ptailor.job.run_adjust` (pattern_units, drape_units,
        up, front, baseline, formats, seam_allowance); also stamped.
    gates : Gates
    force : bool
        Redo even when the folder's stamp matches.
    drape_abs : str or None
        For a DXF pattern: its drape OBJ (:func:`drape_for`), read and stamped with it.
    timeout : float or None
        Seconds the garment may take in its worker process (``failure: timeout`` past it).
    """

    index: int
    garment: str
    garment_abs: str
    out: str
    out_abs: str
    note: str | None
    recipe: Any
    recipe_sha: str
    adjust_options: dict = field(default_factory=dict)
    gates: Gates = Gates()
    force: bool = False
    drape_abs: str | None = None
    timeout: float | None = None

    def record(self, status: str, **values: Any) -> dict:
        """A record for this garment with every key of :data:`RECORD_KEYS`."""
        rec = dict.fromkeys(RECORD_KEYS)
        rec.update(garment=self.garment, out=self.out, status=status, note=self.note)
        rec.update(values)
        return rec


def make_jobs(
    garments: Sequence[str],
    out: str | Path,
    recipe,
    *,
    adjust_options: dict | None = None,
    gates: Gates | None = None,
    force: bool = False,
    timeout: float | None = None,
) -> list[Job]:
    """One :class:`Job` per garment, output folders named by :func:`output_names`."""
    digest = recipe_digest(recipe)
    out_abs = Path(out).resolve()
    jobs = []
    for i, (g, (name, note)) in enumerate(zip(garments, output_names(garments), strict=True)):
        jobs.append(
            Job(
                index=i,
                garment=g,
                garment_abs=os.path.abspath(g),
                out=os.path.join(str(out), name),
                out_abs=str(out_abs / name),
                note=note,
                recipe=recipe,
                recipe_sha=digest,
                adjust_options=dict(adjust_options or {}),
                gates=gates or Gates(),
                force=force,
                drape_abs=None if (d := drape_for(g)) is None else os.path.abspath(d),
                timeout=timeout,
            )
        )
    return jobs


#: set in worker processes by :func:`init_worker`
_STOP = None
_TIMED_OUT = None
_IN_JOB = False
#: a garment past its ``--timeout`` that does not stop (stuck in native code) has its
#: worker killed this much later: max(this, a quarter of the timeout) seconds
TIMEOUT_GRACE_S = tolerances.TIMEOUT_GRACE_S


class JobTimeoutError(BaseException):
    """Raised in a worker when its garment runs past ``--timeout`` (a BaseException, so that
    no ``except Exception`` swallows it; staging folders are removed on the way out)."""


def _on_alarm(signum, frame) -> None:
    if _IN_JOB:
        raise JobTimeoutError


def _timeout_record(job: Job) -> dict:
    return job.record(
        "failed",
        failure="timeout",
        reason=f"timeout: not done in {job.timeout:g} s (--timeout)",
    )


def _watchdog(job: Job, finished: threading.Event) -> None:
    """Kill this worker when the garment neither finished nor stopped at its timeout."""
    if finished.wait(job.timeout + max(TIMEOUT_GRACE_S, 0.25 * job.timeout)):
        return
    if _TIMED_OUT is not None:
        _TIMED_OUT[job.index] = 1
    os.kill(os.getpid(), signal.SIGKILL)


def run_job(job: Job) -> dict:
    """Adjust one garment into its folder (or skip it); return its record. Never raises for
    a bad garment (only ``KeyboardInterrupt`` / ``SystemExit`` pass).

    With ``job.timeout`` in a worker process (:func:`init_worker`), SIGALRM stops the
    garment at its timeout (``failure: timeout``); a watchdog thread kills the worker when
    the garment is stuck where a signal cannot reach it (the parent records the timeout).
    Library warnings go to the garment's report, not to the terminal.
    """
    from ptailor.output import capture_library_warnings

    global _IN_JOB
    if _STOP is not None and _STOP.is_set():
        return job.record("interrupted", reason="interrupted before it started")
    t0 = time.perf_counter()
    timed = (
        job.timeout is not None
        and _TIMED_OUT is not None
        and threading.current_thread() is threading.main_thread()
    )
    finished = threading.Event()
    _IN_JOB = True
    try:
        if timed:
            threading.Thread(target=_watchdog, args=(job, finished), daemon=True).start()
            signal.setitimer(signal.ITIMER_REAL, job.timeout)
        with capture_library_warnings():
            rec = _run_job(job)
    except JobTimeoutError:
        rec = _timeout_record(job)
    finally:
        _IN_JOB = False
        if timed:
            signal.setitimer(signal.ITIMER_REAL, 0)
        finished.set()
    rec["seconds"] = round(time.perf_counter() - t0, 4)
    return rec


def _shown(job: Job, text: str) -> str:
    """A message with the absolute paths written as given."""
    return text.replace(job.out_abs, job.out).replace(job.garment_abs, job.garment)


def job_stamp(job: Job) -> dict:
    """The stamp the job's folder gets (hashes the garment file).

    Raises
    ------
    OSError
        The garment cannot be read.
    """
    opts = {**job.adjust_options}
    opts["formats"] = sorted(opts.get("formats", ()))
    digest = file_sha256(job.garment_abs)
    if job.drape_abs is not None:  # a DXF pattern: its drape is an input too
        digest = text_sha256(f"{digest}:{file_sha256(job.drape_abs)}")
    return make_stamp(job.garment, digest, job.recipe_sha, opts)


def _unchanged(job: Job, stamp: dict) -> dict | None:
    """The record of a job whose folder is up to date (skipped, or failed by a gate)."""
    report = up_to_date(Path(job.out_abs), stamp)
    if report is None:
        return None
    probs = gate_failures(report, job.gates)
    if probs:
        reason = "gate: " + "; ".join(probs) + " (the folder from an earlier run is kept)"
        return job.record("failed", failure="gate", reason=reason, **key_numbers(report))
    return job.record("skipped", reason="unchanged", **key_numbers(report))


def check_unchanged(job: Job) -> dict | None:
    """:func:`run_job`'s record when the job's folder is up to date, else None (cheap: the
    parent runs it first so that an up-to-date catalogue starts no workers)."""
    if job.force or not (Path(job.out_abs) / STAMP).is_file():
        return None  # (no hashing when there is no stamp to compare with)
    t0 = time.perf_counter()
    try:
        rec = _unchanged(job, job_stamp(job))
    except OSError:
        return None
    if rec is not None:
        rec["seconds"] = round(time.perf_counter() - t0, 4)
    return rec


def _run_job(job: Job) -> dict:
    from ptailor.job import run_adjust
    from ptailor.output import check_output_dir

    try:
        stamp = job_stamp(job)
    except FileNotFoundError as exc:
        missing = job.garment if not Path(job.garment_abs).is_file() else exc.filename
        return job.record("failed", failure="input", reason=_shown(job, f"{missing}: no such file"))
    except OSError as exc:
        reason = f"{job.garment}: cannot read ({exc.strerror or exc})"
        return job.record("failed", failure="input", reason=reason)
    if not job.force:
        rec = _unchanged(job, stamp)
        if rec is not None:
            return rec

    def check(report: dict) -> None:
        probs = gate_failures(report, job.gates)
        if probs:
            raise GateFailedError(probs, report)

    try:
        check_output_dir(job.out_abs, [job.recipe.source])  # the recipe is never replaced
        report = run_adjust(
            job.garment_abs,
            job.recipe,
            job.out_abs,
            **job.adjust_options,
            drape=job.drape_abs,
            display_inputs=(
                {"garment": job.garment}
                if job.drape_abs is None
                else {"pattern": job.garment, "drape": drape_for(job.garment)}
            ),
            extra_files={STAMP: json.dumps(stamp, indent=2) + "\n"},
            check=check,
        )
    except GateFailedError as exc:
        reason = "gate: " + "; ".join(exc.problems)
        return job.record("failed", failure="gate", reason=reason, **key_numbers(exc.report))
    except PtailorError as exc:
        return job.record("failed", failure="input", reason=_shown(job, str(exc)))
    except Exception as exc:  # per-garment isolation: report and go on
        reason = _shown(job, f"internal error: {type(exc).__name__}: {exc}")
        return job.record("failed", failure="internal", reason=reason)
    return job.record("ok", **key_numbers(report))


# --------------------------------------------------------------------------- workers


def _on_sigint(signum, frame) -> None:
    """In a worker: interrupt the garment being adjusted (its staging folder is removed),
    ignore the signal between garments (the parent decides what happens next)."""
    global _IN_JOB
    if _IN_JOB:
        _IN_JOB = False  # a second signal during the clean-up is ignored
        raise KeyboardInterrupt


def warm_up() -> None:
    """Import everything an adjustment needs and run a tiny one (worker start-up cost)."""
    import tempfile

    from ptailor.formats.obj import write_garment
    from ptailor.job import run_adjust
    from ptailor.recipe import parse_recipe
    from ptailor.samples import lantern_sleeve

    # only a warm-up: the real jobs report their own errors
    with contextlib.suppress(Exception), tempfile.TemporaryDirectory(prefix="ptailor-") as td:
        g = Path(td) / "g.obj"
        write_garment(g, lantern_sleeve(n_around=6, n_sleeve=2, n_cuff=1))
        rec = parse_recipe("steps: [{op: scale, factor: 1.1}]")
        run_adjust(str(g), rec, Path(td) / "out")


def init_worker(stop, timed_out=None) -> None:
    """Pool initializer: SIGINT and SIGALRM handling, the shared stop flag and timed-out
    flags, imports paid once."""
    global _STOP, _TIMED_OUT
    _STOP = stop
    _TIMED_OUT = timed_out
    signal.signal(signal.SIGINT, _on_sigint)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)  # terminate() ends a worker at once
    signal.signal(signal.SIGALRM, _on_alarm)
    warm_up()


# --------------------------------------------------------------------------- running


@dataclass
class BatchResult:
    """Records in input order (unfinished garments have status ``interrupted``)."""

    records: list[dict]
    interrupted: bool = False
    seconds: float = 0.0
    where: str = ""

    def count(self, status: str) -> int:
        return sum(r["status"] == status for r in self.records)

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


def _failed_future(job: Job, exc: BaseException) -> dict:
    if isinstance(exc, KeyboardInterrupt):
        return job.record("failed", failure="internal", reason="interrupted in its worker")
    reason = f"internal error: {type(exc).__name__}: {exc}"
    return job.record("failed", failure="internal", reason=_shown(job, reason))


def run_batch(
    jobs: Sequence[Job],
    *,
    workers: int = 1,
    scheduler: str | None = None,
    on_record: Callable[[dict], None] | None = None,
    on_done: Callable[[dict], None] | None = None,
) -> BatchResult:
    """Run every job; in-process (``workers == 1``), in a process pool, or on Dask.

    Parameters
    ----------
    jobs : list of Job
    workers : int
        Worker processes (ignored with ``scheduler``).
    scheduler : str, optional
        A Dask distributed scheduler address.
    on_record : callable, optional
        Called with each record in input order, as soon as possible.
    on_done : callable, optional
        Called with each record as it completes (progress).

    Returns
    -------
    BatchResult
        With ``interrupted`` set when ``KeyboardInterrupt`` stopped it: the garments in
        progress were interrupted (their staging folders removed), the rest not started.

    Raises
    ------
    PtailorError
        Dask is not installed or the scheduler cannot be reached.
    """
    t0 = time.perf_counter()
    records: list[dict | None] = [None] * len(jobs)
    order = InOrder(len(jobs), on_record or (lambda r: None))

    def done(job: Job, rec: dict) -> None:
        records[job.index] = rec
        if on_done is not None:
            on_done(rec)
        order.add(job.index, rec)

    todo = []
    interrupted = False
    try:
        for job in jobs:
            rec = check_unchanged(job)
            if rec is None:
                todo.append(job)
            else:
                done(job, rec)
    except KeyboardInterrupt:
        interrupted = True
        todo = []
    if scheduler is not None:
        where = f"Dask scheduler {scheduler}"
        if todo:
            interrupted = _run_dask(todo, scheduler, done)
    elif (workers <= 1 or len(todo) <= 1) and not any(j.timeout for j in todo):
        where = "in-process"
        if todo:
            interrupted = _run_here(todo, done)
    else:
        n = max(1, min(workers, len(todo)))
        where = f"{n} worker process{'es' if n > 1 else ''}"
        interrupted = _run_pool(todo, n, done)
    final = []
    for j, r in zip(jobs, records, strict=True):
        if r is None or r["status"] == "interrupted":
            r = j.record("interrupted", reason=(r or {}).get("reason") or "interrupted")
        final.append(r)
    if scheduler is None:  # the workers are gone: what a killed one left is garbage
        for j, r in zip(jobs, final, strict=True):
            if r["status"] == "interrupted" or r["failure"] in ("internal", "timeout"):
                remove_staging(j.out_abs)
    order.finish(final)
    return BatchResult(
        records=final,
        interrupted=interrupted,
        seconds=time.perf_counter() - t0,
        where=where,
    )


def largest_first(jobs: Sequence[Job]) -> list[Job]:
    """Dispatch order for workers: the largest garment files first, so that no worker is
    left with a big garment while the others idle at the end (records keep input order)."""

    def size(job: Job) -> int:
        try:
            return os.path.getsize(job.garment_abs)
        except OSError:
            return 0

    return sorted(jobs, key=lambda j: (-size(j), j.index))


def _run_here(jobs: Sequence[Job], done) -> bool:
    for job in jobs:
        try:
            rec = run_job(job)
        except KeyboardInterrupt:
            return True
        done(job, rec)
    return False


#: a garment still unfinished after this many broken pools runs in a worker of its own
_STRIKES = 2


def _run_pool(jobs: Sequence[Job], n: int, done) -> bool:
    """Run jobs in a pool of ``n`` worker processes; True when interrupted.

    A worker that dies (killed, out of memory, a crash in a native library) breaks the
    pool: the garments not finished go to a new pool, and one still unfinished after
    :data:`_STRIKES` broken pools runs alone, so that a garment that kills its worker fails
    by itself ("its worker process died") and the others finish.
    """
    import multiprocessing as mp

    strikes = dict.fromkeys((j.index for j in jobs), 0)
    # set by a worker's watchdog before it kills its worker for a garment past --timeout
    timed_out = mp.get_context().Array("b", max(j.index for j in jobs) + 1, lock=False)

    def done_again(job: Job, rec: dict) -> None:
        # up-to-date jobs never reach a pool (the parent skips them first), so a retried
        # job found up to date was written in this run, by the pool that broke before its
        # result came back: it is done, not skipped
        if rec["status"] == "skipped" and strikes[job.index]:
            rec = {**rec, "status": "ok", "reason": None}
        done(job, rec)

    todo = list(jobs)
    while todo:
        shared = [j for j in todo if strikes[j.index] < _STRIKES]
        rounds = ([shared] if shared else []) + [[j] for j in todo if j not in shared]
        todo = []
        for part in rounds:
            interrupted, unfinished = _pool_round(part, min(n, len(part)), done_again, timed_out)
            if interrupted:
                return True
            killer = any(timed_out[j.index] for j in unfinished)
            for job in unfinished:
                if timed_out[job.index]:
                    done(job, _timeout_record(job))
                    continue
                if not killer:  # a worker killed for a timeout is no strike for the others
                    strikes[job.index] += 1
                if strikes[job.index] > _STRIKES:
                    reason = "internal error: its worker process died (killed, or out of memory?)"
                    done(job, job.record("failed", failure="internal", reason=reason))
                else:
                    todo.append(job)
    return False


def _pool_round(jobs: Sequence[Job], n: int, done, timed_out=None) -> tuple[bool, list[Job]]:
    """One pool over ``jobs``: (interrupted, the jobs left unfinished by a broken pool)."""
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor, as_completed
    from concurrent.futures.process import BrokenProcessPool

    ctx = mp.get_context()
    stop = ctx.Event()
    ex = ProcessPoolExecutor(
        max_workers=n, mp_context=ctx, initializer=init_worker, initargs=(stop, timed_out)
    )
    futures = {}
    unfinished = []
    try:
        for job in largest_first(jobs):
            futures[ex.submit(run_job, job)] = job
        for fut in as_completed(futures):
            job = futures[fut]
            exc = fut.exception()
            if isinstance(exc, BrokenProcessPool):
                unfinished.append(job)
            else:
                done(job, _failed_future(job, exc) if exc is not None else fut.result())
    except KeyboardInterrupt:
        stop.set()
        for fut in futures:
            fut.cancel()
        children = list(mp.active_children())
        for p in children:  # interrupt the garments in progress (when the signal was ours only)
            if p.pid is not None:
                with contextlib.suppress(ProcessLookupError):
                    os.kill(p.pid, signal.SIGINT)
        try:
            ex.shutdown(wait=True, cancel_futures=True)
        except KeyboardInterrupt:  # a second Ctrl-C: stop waiting
            for p in children:
                p.terminate()
            ex.shutdown(wait=True, cancel_futures=True)
        for fut, job in futures.items():
            if fut.done() and not fut.cancelled() and fut.exception() is None:
                rec = fut.result()
                if rec["status"] != "interrupted":
                    done(job, rec)
        return True, []
    except BrokenProcessPool:  # submit() on a pool that broke meanwhile
        unfinished = [j for f, j in futures.items() if not f.done() or f.exception()]
        unfinished += [j for j in jobs if j not in futures.values()]
    finally:
        ex.shutdown(wait=True, cancel_futures=True)
    for job in unfinished:  # what a killed worker was writing
        remove_staging(job.out_abs)
    return False, sorted(unfinished, key=lambda j: j.index)


def _run_dask(jobs: Sequence[Job], address: str, done) -> bool:
    try:
        from dask.distributed import Client, as_completed
    except ImportError:
        raise PtailorError(
            "--scheduler needs Dask distributed: pip install 'ptailor[dask]'"
        ) from None
    try:
        client = Client(address, timeout="20s", set_as_default=False)
    except (OSError, TimeoutError, ValueError) as exc:
        raise PtailorError(f"cannot connect to the Dask scheduler {address} ({exc})") from None
    futures = {}
    try:
        with contextlib.suppress(Exception):  # only a warm-up
            client.run(warm_up)
        token = uuid.uuid4().hex
        order = largest_first(jobs)
        for rank, job in enumerate(order):
            key = f"ptailor-batch-{token}-{job.index}"
            fut = client.submit(run_job, job, pure=False, key=key, priority=len(order) - rank)
            futures[fut] = job
        for fut in as_completed(list(futures), loop=client.loop):
            job = futures[fut]
            if fut.status == "finished":
                done(job, fut.result())
            else:
                try:
                    exc = fut.exception()
                except BaseException as e:  # cancelled or lost
                    if isinstance(e, KeyboardInterrupt):
                        raise
                    exc = e
                done(job, _failed_future(job, exc))
    except KeyboardInterrupt:
        # a running task cannot be interrupted: it finishes its folder on the worker
        client.cancel(list(futures))
        return True
    finally:
        client.close()
    return False


def remove_staging(out: str | Path) -> list[str]:
    """Remove the staging folders a killed writer of ``out`` left beside it.

    ``.NAME.XXXXXXXX.tmp`` (being written) is removed; ``.NAME.old-...tmp`` (the previous
    output, moved aside for the replacement) is moved back when ``out`` is missing, else
    removed. Returns the names handled.
    """
    from ptailor.output import staging_pattern

    out = Path(out)
    if not out.parent.is_dir():
        return []
    pat = staging_pattern(out.name)
    handled = []
    for p in sorted(out.parent.iterdir()):
        m = pat.match(p.name)
        if not m or not p.is_dir():
            continue
        if m.group(1) and not out.exists():
            p.rename(out)
        else:
            shutil.rmtree(p, ignore_errors=True)
        handled.append(p.name)
    return handled


# --------------------------------------------------------------------------- summary


def summary_lines(result: BatchResult) -> list[str]:
    """The end-of-batch table: counts, the failed garments with their reasons, time, rate."""
    recs = result.records
    n = len(recs)
    counts = {s: result.count(s) for s in STATUSES}
    gated = sum(r["failure"] == "gate" for r in recs)
    worked = counts["ok"] + counts["failed"]
    rate = 60.0 * worked / result.seconds if result.seconds > 0 else 0.0
    lines = [
        f"{'garments':<12}{n:>6}",
        f"{'ok':<12}{counts['ok']:>6}",
        f"{'skipped':<12}{counts['skipped']:>6}   (unchanged since their output was written)",
        f"{'failed':<12}{counts['failed']:>6}"
        + (f"   ({gated} by quality gates)" if gated else ""),
    ]
    if counts["interrupted"]:
        lines.append(f"{'interrupted':<12}{counts['interrupted']:>6}   (not done: run again)")
    lines.append(
        f"{'time':<12}{result.seconds:>8.1f} s, {rate:.1f} garments/min adjusted "
        f"(ok + failed; {result.where})"
    )
    failed = [r for r in recs if r["status"] == "failed"]
    if failed:
        lines.append("failed:")
        lines += [
            f"  {r['reason']}"
            if str(r["reason"]).startswith(f"{r['garment']}:")
            else f"  {r['garment']}: {r['reason']}"
            for r in failed
        ]
    return lines


def record_line(record: dict) -> str:
    """A record as one line of JSON (keys in :data:`RECORD_KEYS` order)."""
    return json.dumps({k: record.get(k) for k in RECORD_KEYS})
