"""Catalogues: one recipe over many garments, one output folder each (``ptailor batch``).

The library side, without click. Modules, in the order a batch goes through them:

- :mod:`~ptailor.batch.inputs`: the garments the arguments name, their drapes, folder names;
- :mod:`~ptailor.batch.manifest`: or the garments a manifest names, each with its own options;
- :mod:`~ptailor.batch.stamp`: the ``batch.json`` stamp that lets unchanged garments skip;
- :mod:`~ptailor.batch.gates`: quality gates, reading the report strictly;
- :mod:`~ptailor.batch.jobs`: :class:`GarmentJob` and :func:`run_job`, one garment to a record;
- :mod:`~ptailor.batch.executors`: in-process, process pool and Dask behind one
  :class:`Executor` interface, and :func:`run_batch`;
- :mod:`~ptailor.batch.records`: record keys, JSON lines and the end-of-batch summary.
"""

from __future__ import annotations

from ptailor.batch.executors import Executor, executor_for, run_batch
from ptailor.batch.gates import GateFailedError, Gates, area_change, gate_failures, seam_mismatch
from ptailor.batch.inputs import drape_for, expand_garments, output_names
from ptailor.batch.jobs import GarmentJob, check_unchanged, job_stamp, make_jobs, run_job
from ptailor.batch.manifest import ManifestRow, read_manifest
from ptailor.batch.records import (
    RECORD_KEYS,
    STATUSES,
    BatchResult,
    key_numbers,
    record_line,
    summary_lines,
)
from ptailor.batch.stamp import STAMP, make_stamp, recipe_digest, up_to_date
from ptailor.run.staging import remove_staging

__all__ = [
    "RECORD_KEYS",
    "STAMP",
    "STATUSES",
    "BatchResult",
    "Executor",
    "GarmentJob",
    "GateFailedError",
    "Gates",
    "ManifestRow",
    "area_change",
    "check_unchanged",
    "drape_for",
    "executor_for",
    "expand_garments",
    "gate_failures",
    "job_stamp",
    "key_numbers",
    "make_jobs",
    "make_stamp",
    "output_names",
    "read_manifest",
    "recipe_digest",
    "record_line",
    "remove_staging",
    "run_batch",
    "run_job",
    "seam_mismatch",
    "summary_lines",
    "up_to_date",
]
