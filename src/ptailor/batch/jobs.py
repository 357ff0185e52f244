"""One garment of a batch: :class:`GarmentJob`, and :func:`run_job` turning it into a record.

:func:`run_job` never raises for a bad garment: a :class:`~ptailor.errors.PtailorError` is a
failed record, a broken quality gate too (no folder is written: the gates judge the report
that :func:`ptailor.run.garment.staged_run` yields before it puts the folder in place), any
other exception an internal-error record. In a worker process (:func:`enter_worker`) a
garment past its ``timeout`` is stopped by SIGALRM, or its worker killed by a watchdog when
a signal cannot reach it.
"""

from __future__ import annotations

import json
import os
import signal
import threading
import time
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from ptailor import tolerances
from ptailor.batch.gates import GateFailedError, Gates, broken_gates, gate_failures
from ptailor.batch.inputs import REJECTED_DIR, drape_for, output_names
from ptailor.batch.manifest import ManifestRow, as_rows
from ptailor.batch.records import RECORD_KEYS, key_numbers
from ptailor.batch.stamp import STAMP, inputs_digest, make_stamp, recipe_digest, up_to_date
from ptailor.errors import OUT_OF_MEMORY, PtailorError, internal_error
from ptailor.run.options import RunOptions
from ptailor.run.spec import spec_input


@dataclass(frozen=True)
class GarmentJob:
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
        :func:`~ptailor.batch.stamp.recipe_digest` of it.
    options : RunOptions
        How the garment is read, adjusted and written; also stamped.
    gates : Gates
    force : bool
        Redo even when the folder's stamp matches.
    drape_abs : str or None
        For a CAD pattern: its drape OBJ (:func:`~ptailor.batch.inputs.drape_for`, or a
        manifest's ``drape``), read and stamped with it; ``drape`` is the path as shown.
    timeout : float or None
        Seconds the garment may take in its worker process (``failure: timeout`` past it).
    rejected_abs : str or None
        Where the garment's outputs go when a quality gate rejects them (``batch --html``:
        ``OUT/_rejected/NAME``, for the catalogue to show); None: nowhere.
    debug : bool
        Print an internal error's traceback on stderr (``ptailor --debug``; the record
        has its one line either way).
    """

    index: int
    garment: str
    garment_abs: str
    out: str
    out_abs: str
    note: str | None
    recipe: Any
    recipe_sha: str
    options: RunOptions = field(default_factory=RunOptions)
    gates: Gates = field(default_factory=Gates)
    force: bool = False
    drape_abs: str | None = None
    timeout: float | None = None
    drape: str | None = None
    rejected_abs: str | None = None
    debug: bool = False

    def record(self, status: str, **values: Any) -> dict:
        """A record for this garment with every key of :data:`RECORD_KEYS`."""
        rec = dict.fromkeys(RECORD_KEYS)
        rec.update(
            index=self.index + 1, garment=self.garment, out=self.out, status=status, note=self.note
        )
        rec.update(values)
        return rec

    def shown(self, text: str) -> str:
        """A message with the absolute paths written as given."""
        text = text.replace(self.out_abs, self.out).replace(self.garment_abs, self.garment)
        if self.drape_abs is not None and self.drape is not None:
            text = text.replace(self.drape_abs, self.drape)
        return text

    def failed(self, exc: BaseException) -> dict:
        """The record of a job whose worker raised ``exc`` (an internal error)."""
        if isinstance(exc, KeyboardInterrupt):
            return self.record("failed", failure="internal", reason="interrupted in its worker")
        reason = f"internal error: {type(exc).__name__}: {exc}"
        return self.record("failed", failure="internal", reason=self.shown(reason))

    def timed_out(self) -> dict:
        """The record of a job stopped at its timeout."""
        reason = f"timeout: not done in {self.timeout:g} s (--timeout)"
        return self.record("failed", failure="timeout", reason=reason)


def make_jobs(
    garments: Sequence[str | ManifestRow],
    out: str | Path,
    recipe,
    *,
    options: RunOptions | None = None,
    gates: Gates | None = None,
    force: bool = False,
    timeout: float | None = None,
    keep_rejected: bool = False,
    debug: bool = False,
) -> list[GarmentJob]:
    """One :class:`GarmentJob` per garment, output folders named by
    :func:`~ptailor.batch.inputs.output_names`.

    Parameters
    ----------
    garments : list of (str or ManifestRow)
        Paths, or a manifest's rows (:func:`~ptailor.batch.manifest.read_manifest`): a
        row's drape, name and options override the defaults (its options go into the
        garment's stamp like the command line's).
    out : str or Path
        The output root.
    recipe : Recipe
        Validated.
    options : RunOptions, optional
        Every garment's options (the command line's).
    gates, force, timeout
        As :class:`GarmentJob`'s.
    keep_rejected : bool
        Keep what the gates reject in ``OUT/_rejected/NAME`` (:data:`REJECTED_DIR`).
    debug : bool
        Internal errors' tracebacks on stderr (:class:`GarmentJob`'s ``debug``).

    Returns
    -------
    list of GarmentJob
    """
    rows = as_rows(garments)
    paths = [r.garment for r in rows]
    names = output_names(paths, [r.name for r in rows])
    base = options or RunOptions()
    digest = recipe_digest(recipe)
    out_abs = Path(out).resolve()
    jobs = []
    for i, (row, (name, note)) in enumerate(zip(rows, names, strict=True)):
        drape = row.drape if row.drape is not None else drape_for(row.garment)
        jobs.append(
            GarmentJob(
                index=i,
                garment=row.garment,
                garment_abs=os.path.abspath(row.garment),
                out=os.path.join(str(out), name),
                out_abs=str(out_abs / name),
                note=note,
                recipe=recipe,
                recipe_sha=digest,
                options=replace(base, **row.options) if row.options else base,
                gates=gates or Gates(),
                force=force,
                drape_abs=None if drape is None else os.path.abspath(drape),
                timeout=timeout,
                drape=drape,
                rejected_abs=str(out_abs / REJECTED_DIR / name) if keep_rejected else None,
                debug=debug,
            )
        )
    return jobs


# --------------------------------------------------------------------------- stamp


def job_stamp(job: GarmentJob) -> dict:
    """The stamp the job's folder gets (hashes the garment file).

    Raises
    ------
    OSError
        The garment cannot be read.
    """
    spec = spec_input(job.garment_abs, job.options.spec)
    digest = inputs_digest(job.garment_abs, job.drape_abs, spec, job.options.edited_drape)
    return make_stamp(job.garment, digest, job.recipe_sha, job.options.stamped())


def _unchanged(job: GarmentJob, stamp: dict) -> dict | None:
    """The record of a job whose folder is up to date (skipped, or failed by a gate)."""
    report = up_to_date(Path(job.out_abs), stamp)
    if report is None:
        return None
    probs = gate_failures(report, job.gates)
    if probs:
        reason = "gate: " + "; ".join(probs) + " (the folder from an earlier run is kept)"
        return job.record(
            "failed",
            failure="gate",
            reason=reason,
            failed_gates=broken_gates(report, job.gates),
            **key_numbers(report),
        )
    return job.record("skipped", reason="unchanged", **key_numbers(report))


def check_unchanged(job: GarmentJob) -> dict | None:
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


def finished_meanwhile(job: GarmentJob) -> dict | None:
    """The ``ok`` record of a job whose worker was interrupted after its folder was
    complete (the folder swapped in with this run's stamp, the result not yet handed back),
    else None. Not with ``--force``: an up-to-date folder is then an earlier run's.

    Returns
    -------
    dict or None
        The record from the folder's report (its key numbers), ``reason`` saying so; a
        gate's ``failed`` record where the kept folder fails one.
    """
    if job.force or not (Path(job.out_abs) / STAMP).is_file():
        return None
    try:
        rec = _unchanged(job, job_stamp(job))
    except OSError:
        return None
    if rec is None or rec["status"] != "skipped":
        return rec
    return {**rec, "status": "ok", "reason": "finished as the batch was interrupted"}


# --------------------------------------------------------------------------- worker state

#: set in worker processes by :func:`enter_worker`
_STOP = None
_TIMED_OUT = None
_IN_JOB = False
#: a garment past its ``--timeout`` that does not stop (stuck in native code) has its
#: worker killed this much later: max(this, a quarter of the timeout) seconds
TIMEOUT_GRACE_S = tolerances.TIMEOUT_GRACE_S
WORKER_PARENT_POLL_S = tolerances.WORKER_PARENT_POLL_S


class JobTimeoutError(BaseException):
    """Raised in a worker when its garment runs past ``--timeout`` (a BaseException, so that
    no ``except Exception`` swallows it; staging folders are removed on the way out)."""


def _on_alarm(signum, frame) -> None:
    if _IN_JOB:
        raise JobTimeoutError


def _on_sigint(signum, frame) -> None:
    """In a worker: interrupt the garment being adjusted (its staging folder is removed),
    ignore the signal between garments (the parent decides what happens next)."""
    global _IN_JOB
    if _IN_JOB:
        _IN_JOB = False  # a second signal during the clean-up is ignored
        raise KeyboardInterrupt


def enter_worker(stop, timed_out=None) -> None:
    """Make this process a worker: the shared stop flag and timed-out flags, SIGINT,
    SIGTERM and SIGALRM handling."""
    global _STOP, _TIMED_OUT
    _STOP = stop
    _TIMED_OUT = timed_out
    signal.signal(signal.SIGINT, _on_sigint)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)  # terminate() ends a worker at once
    signal.signal(signal.SIGALRM, _on_alarm)
    _watch_parent()


def _watch_parent(period: float = WORKER_PARENT_POLL_S) -> None:
    """End this worker when the batch that started it is gone: ``kill -9`` of ``ptailor
    batch`` once left its workers alive and idle, holding its stdout and stderr (a
    ``ptailor batch ... | tee`` never ended). A daemon thread polls the parent's pid; the
    garment the worker was on keeps its staging folder, which the next run on that output
    removes (:func:`ptailor.run.staging.remove_stale_staging`)."""
    parent = os.getppid()

    def watch() -> None:
        while True:
            time.sleep(period)
            if os.getppid() != parent:
                os._exit(1)

    threading.Thread(target=watch, name="ptailor-parent-watch", daemon=True).start()


def _watchdog(job: GarmentJob, finished: threading.Event) -> None:
    """Kill this worker when the garment neither finished nor stopped at its timeout."""
    if finished.wait(job.timeout + max(TIMEOUT_GRACE_S, 0.25 * job.timeout)):
        return
    if _TIMED_OUT is not None:
        _TIMED_OUT[job.index] = 1
    os.kill(os.getpid(), signal.SIGKILL)


# --------------------------------------------------------------------------- running


def run_job(job: GarmentJob) -> dict:
    """Adjust one garment into its folder (or skip it); return its record. Never raises for
    a bad garment (only ``KeyboardInterrupt`` / ``SystemExit`` pass).

    With ``job.timeout`` in a worker process (:func:`enter_worker`), SIGALRM stops the
    garment at its timeout (``failure: timeout``); a watchdog thread kills the worker when
    the garment is stuck where a signal cannot reach it (the parent records the timeout).
    Library warnings go to the garment's report, not to the terminal.
    """
    from ptailor.run.library_warnings import capture_library_warnings

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
        rec = job.timed_out()
    finally:
        _IN_JOB = False
        if timed:
            signal.setitimer(signal.ITIMER_REAL, 0)
        finished.set()
    rec["seconds"] = round(time.perf_counter() - t0, 4)
    return rec


def _stamp_or_record(job: GarmentJob) -> tuple[dict | None, dict | None]:
    """``(stamp, None)``, or ``(None, record)`` when the garment cannot be read."""
    try:
        return job_stamp(job), None
    except FileNotFoundError as exc:
        missing = job.garment if not Path(job.garment_abs).is_file() else exc.filename
        reason = job.shown(f"{missing}: no such file")
        return None, job.record("failed", failure="input", reason=reason)
    except OSError as exc:
        reason = f"{job.garment}: cannot read ({exc.strerror or exc})"
        return None, job.record("failed", failure="input", reason=reason)


def _run_job(job: GarmentJob) -> dict:
    from ptailor.run.folder import check_output_dir
    from ptailor.run.garment import staged_run  # (looked up per call: tests replace it)

    stamp, rec = _stamp_or_record(job)
    if rec is None and not job.force:
        rec = _unchanged(job, stamp)
    if rec is not None:
        return rec
    shown = (
        {"garment": job.garment}
        if job.drape_abs is None
        else {"pattern": job.garment, "drape": job.drape or drape_for(job.garment)}
    )
    try:
        check_output_dir(job.out_abs, [job.recipe.source])  # the recipe is never replaced
        with staged_run(
            job.garment_abs,
            job.recipe,
            job.out_abs,
            options=job.options,
            drape=job.drape_abs,
            display_inputs=shown,
            extra_files={STAMP: json.dumps(stamp, indent=2) + "\n"},
            divert=(GateFailedError, job.rejected_abs) if job.rejected_abs else None,
        ) as report:  # the gates judge the report before the folder is put in place
            probs = gate_failures(report, job.gates)
            if probs:
                raise GateFailedError(probs, report)
    except GateFailedError as exc:
        reason = "gate: " + "; ".join(exc.problems)
        return job.record(
            "failed",
            failure="gate",
            reason=reason,
            failed_gates=broken_gates(exc.report, job.gates),
            **key_numbers(exc.report),
        )
    except PtailorError as exc:  # bad input, a numeric failure (NumericError) too
        return job.record("failed", failure="input", reason=job.shown(str(exc)))
    except MemoryError:  # as the CLI's exit 2: not a bug
        return job.record("failed", failure="input", reason=f"{job.garment}: {OUT_OF_MEMORY}")
    except Exception as exc:  # no known kind, a bug: one garment's failure, the others go on
        if job.debug:
            import sys
            import traceback

            tb = "".join(traceback.format_exception(exc))
            sys.stderr.write(f"ptailor: {job.garment}: internal error:\n{job.shown(tb)}")
        return job.record("failed", failure="internal", reason=job.shown(internal_error(exc)))
    return job.record("ok", **key_numbers(report))
