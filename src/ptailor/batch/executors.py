"""Where a batch's garments run: in this process, in a pool of worker processes, or on a
Dask cluster, behind one interface (:class:`Executor`), and :func:`run_batch` over them.

An executor runs jobs and calls ``done(job, record)`` as each finishes; ``run`` returns True
when ``KeyboardInterrupt`` stopped it (the garments in progress are interrupted, their
staging folders removed; the rest are not started).
"""

from __future__ import annotations

import contextlib
import os
import signal
import time
import uuid
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Protocol, runtime_checkable

from ptailor import tolerances as tol
from ptailor.batch.jobs import (
    GarmentJob,
    check_unchanged,
    enter_worker,
    finished_meanwhile,
    run_job,
)
from ptailor.batch.records import BatchResult, InOrder
from ptailor.errors import PtailorError
from ptailor.run.staging import remove_staging

#: ``done(job, record)``: called as each job finishes
Done = Callable[[GarmentJob, dict], None]


@runtime_checkable
class Executor(Protocol):
    """Runs jobs somewhere; ``where`` says where (the summary shows it)."""

    where: str

    def run(self, jobs: Sequence[GarmentJob], done: Done) -> bool:
        """Run every job, calling ``done`` with its record; True when interrupted."""
        ...


def warm_up() -> None:
    """Import everything an adjustment needs and run a tiny one (worker start-up cost)."""
    import tempfile

    from ptailor.formats.obj import write_garment
    from ptailor.recipe import parse_recipe
    from ptailor.run.garment import run_garment
    from ptailor.samples import lantern_sleeve

    # only a warm-up: the real jobs report their own errors
    with contextlib.suppress(Exception), tempfile.TemporaryDirectory(prefix="ptailor-") as td:
        g = Path(td) / "g.obj"
        write_garment(g, lantern_sleeve(n_around=6, n_sleeve=2, n_cuff=1))
        rec = parse_recipe("steps: [{op: scale, factor: 1.1}]")
        run_garment(str(g), rec, Path(td) / "out")


def init_worker(stop, timed_out=None) -> None:
    """Pool initializer: SIGINT and SIGALRM handling, the shared stop flag and timed-out
    flags (:func:`~ptailor.batch.jobs.enter_worker`), imports paid once."""
    enter_worker(stop, timed_out)
    warm_up()


def largest_first(jobs: Sequence[GarmentJob]) -> list[GarmentJob]:
    """Dispatch order for workers: the largest garment files first, so that no worker is
    left with a big garment while the others idle at the end (records keep input order)."""

    def size(job: GarmentJob) -> int:
        try:
            return os.path.getsize(job.garment_abs)
        except OSError:
            return 0

    return sorted(jobs, key=lambda j: (-size(j), j.index))


# --------------------------------------------------------------------------- in-process


class InProcess:
    """Every job in this process, one after the other."""

    where = "in-process"

    def run(self, jobs: Sequence[GarmentJob], done: Done) -> bool:
        for job in jobs:
            try:
                rec = run_job(job)
            except KeyboardInterrupt:
                return True
            done(job, rec)
        return False


# --------------------------------------------------------------------------- process pool


class ProcessPool:
    """Jobs in a pool of ``n`` worker processes.

    A worker that dies (killed, out of memory, a crash in a native library) breaks the
    pool: the garments not finished go to a new pool, and one still unfinished after
    :data:`ptailor.tolerances.BATCH_POOL_STRIKES` broken pools runs alone, so that a garment
    that kills its worker fails by itself ("its worker process died") and the others finish.
    """

    def __init__(self, n: int) -> None:
        self.n = n
        self.where = f"{n} worker process{'es' if n > 1 else ''}"

    def run(self, jobs: Sequence[GarmentJob], done: Done) -> bool:
        import multiprocessing as mp

        strikes = dict.fromkeys((j.index for j in jobs), 0)
        # set by a worker's watchdog before it kills its worker for a garment past --timeout
        timed_out = mp.get_context().Array("b", max(j.index for j in jobs) + 1, lock=False)

        def done_again(job: GarmentJob, rec: dict) -> None:
            # up-to-date jobs never reach a pool (the parent skips them first), so a retried
            # job found up to date was written in this run, by the pool that broke before its
            # result came back: it is done, not skipped
            if rec["status"] == "skipped" and strikes[job.index]:
                rec = {**rec, "status": "ok", "reason": None}
            done(job, rec)

        todo = list(jobs)
        while todo:
            shared = [j for j in todo if strikes[j.index] < tol.BATCH_POOL_STRIKES]
            rounds = ([shared] if shared else []) + [[j] for j in todo if j not in shared]
            todo = []
            for part in rounds:
                interrupted, unfinished = _pool_round(
                    part, min(self.n, len(part)), done_again, timed_out
                )
                if interrupted:
                    return True
                todo += _strike(unfinished, strikes, timed_out, done)
        return False


def _strike(unfinished: list[GarmentJob], strikes: dict, timed_out, done: Done) -> list:
    """The jobs a broken pool left to run again; the others are done (timed out, or failed
    after too many broken pools)."""
    killer = any(timed_out[j.index] for j in unfinished)
    again = []
    for job in unfinished:
        if timed_out[job.index]:
            done(job, job.timed_out())
            continue
        if not killer:  # a worker killed for a timeout is no strike for the others
            strikes[job.index] += 1
        if strikes[job.index] > tol.BATCH_POOL_STRIKES:
            reason = "internal error: its worker process died (killed, or out of memory?)"
            done(job, job.record("failed", failure="internal", reason=reason))
        else:
            again.append(job)
    return again


def _pool_round(
    jobs: Sequence[GarmentJob], n: int, done: Done, timed_out=None
) -> tuple[bool, list[GarmentJob]]:
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
                done(job, job.failed(exc) if exc is not None else fut.result())
    except KeyboardInterrupt:
        _interrupt_pool(ex, futures, stop, done)
        return True, []
    except BrokenProcessPool:  # submit() on a pool that broke meanwhile
        unfinished = [j for f, j in futures.items() if not f.done() or f.exception()]
        unfinished += [j for j in jobs if j not in futures.values()]
    finally:
        ex.shutdown(wait=True, cancel_futures=True)
    for job in unfinished:  # what a killed worker was writing
        remove_staging(job.out_abs)
    return False, sorted(unfinished, key=lambda j: j.index)


def _interrupt_pool(ex, futures: dict, stop, done: Done) -> None:
    """Ctrl-C: stop the pool, interrupt the garments in progress, keep what finished."""
    import multiprocessing as mp

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


# --------------------------------------------------------------------------- Dask


class DaskCluster:
    """Jobs on a Dask distributed cluster (its workers must see the same files)."""

    def __init__(self, address: str) -> None:
        self.address = address
        self.where = f"Dask scheduler {address}"

    def run(self, jobs: Sequence[GarmentJob], done: Done) -> bool:
        """Raises :class:`PtailorError` when Dask is missing or the scheduler unreachable."""
        try:
            from dask.distributed import Client
        except ImportError:
            raise PtailorError(
                "--scheduler needs Dask distributed: pip install 'ptailor[dask]'"
            ) from None
        try:
            client = Client(self.address, timeout="20s", set_as_default=False)
        except (OSError, TimeoutError, ValueError) as exc:
            msg = f"cannot connect to the Dask scheduler {self.address} ({exc})"
            raise PtailorError(msg) from None
        futures: dict = {}
        try:
            with contextlib.suppress(Exception):  # only a warm-up
                client.run(warm_up)
            _dask_collect(client, jobs, futures, done)
        except KeyboardInterrupt:
            # a running task cannot be interrupted: it finishes its folder on the worker
            client.cancel(list(futures))
            return True
        finally:
            client.close()
        return False


def _dask_collect(client, jobs: Sequence[GarmentJob], futures: dict, done: Done) -> None:
    """Submit every job (largest first) into ``futures`` and pass each record on."""
    from dask.distributed import as_completed

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
            continue
        try:
            exc = fut.exception()
        except BaseException as e:  # cancelled or lost
            if isinstance(e, KeyboardInterrupt):
                raise
            exc = e
        done(job, job.failed(exc))


# --------------------------------------------------------------------------- running


def executor_for(
    jobs: Sequence[GarmentJob], *, workers: int = 1, scheduler: str | None = None
) -> Executor:
    """Dask with a ``scheduler``; in-process for one worker or one job (unless a job has a
    timeout: only a worker process can be stopped); else a pool of processes."""
    if scheduler is not None:
        return DaskCluster(scheduler)
    if (workers <= 1 or len(jobs) <= 1) and not any(j.timeout for j in jobs):
        return InProcess()
    return ProcessPool(max(1, min(workers, len(jobs))))


def _skip_unchanged(jobs: Sequence[GarmentJob], done: Done) -> tuple[list[GarmentJob], bool]:
    """The jobs whose folders are not up to date (the others are done); True when
    interrupted meanwhile (then none is left to do)."""
    todo = []
    try:
        for job in jobs:
            rec = check_unchanged(job)
            if rec is None:
                todo.append(job)
            else:
                done(job, rec)
    except KeyboardInterrupt:
        return [], True
    return todo, False


def run_batch(
    jobs: Sequence[GarmentJob],
    *,
    workers: int = 1,
    scheduler: str | None = None,
    on_record: Callable[[dict], None] | None = None,
    on_done: Callable[[dict], None] | None = None,
) -> BatchResult:
    """Run every job; in-process (``workers == 1``), in a process pool, or on Dask.

    Parameters
    ----------
    jobs : list of GarmentJob
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

    def done(job: GarmentJob, rec: dict) -> None:
        records[job.index] = rec
        if on_done is not None:
            on_done(rec)
        order.add(job.index, rec)

    todo, interrupted = _skip_unchanged(jobs, done)
    executor = executor_for(todo, workers=workers, scheduler=scheduler)
    if todo:
        interrupted = executor.run(todo, done)
    final = _final_records(jobs, records, cleanup=scheduler is None)
    order.finish(final)
    return BatchResult(
        records=final,
        interrupted=interrupted,
        seconds=time.perf_counter() - t0,
        where=executor.where,
        ran=sum(final[j.index]["status"] in ("ok", "failed") for j in todo),
    )


def _final_records(
    jobs: Sequence[GarmentJob], records: list[dict | None], *, cleanup: bool
) -> list[dict]:
    """Every job's record (``interrupted`` for those not done; ``ok`` for one whose folder
    its worker completed before the interrupt reached it: :func:`finished_meanwhile`); with
    ``cleanup`` (the workers are gone) what an interrupted, crashed or timed-out garment
    left is removed."""
    final = []
    for j, r in zip(jobs, records, strict=True):
        if r is None or r["status"] == "interrupted":
            r = finished_meanwhile(j) or j.record(
                "interrupted", reason=(r or {}).get("reason") or "interrupted"
            )
        final.append(r)
    if cleanup:
        for j, r in zip(jobs, final, strict=True):
            if r["status"] == "interrupted" or r["failure"] in ("internal", "timeout"):
                remove_staging(j.out_abs)
    return final
