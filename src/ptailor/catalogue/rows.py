"""A catalogue's rows: one per garment, from a batch's records and the folders under OUT.

The rows of the last run come first, in its input order (skipped garments too: their
records carry the numbers of their stored report); then every garment folder under OUT
that the run did not name (written by an earlier run on other garments), built from its
``report.json`` and ``batch.json`` with status ``earlier``.
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from ptailor import tolerances as tol
from ptailor.batch.inputs import CATALOGUE_DIR, CATALOGUE_PAGE, REJECTED_DIR, RESERVED_NAMES
from ptailor.batch.readback import (
    RECORD_FIELDS,
    REPORT_FIELDS,
    SAVED_FIELDS,
    STAMP_FIELDS,
    ReadBackError,
    checked,
    is_file_name,
    load_text,
    read_checked,
)
from ptailor.batch.records import RECORD_KEYS, is_record, key_numbers
from ptailor.batch.stamp import STAMP
from ptailor.errors import PtailorError
from ptailor.run.folder import read_marker

#: the catalogue's page in OUT (and each garment's page in its folder)
INDEX = CATALOGUE_PAGE
#: the last run's records and summary, in :data:`CATALOGUE_DIR`
SAVED = "catalogue.json"
#: a catalogue row's statuses: a record's, and ``earlier`` for a folder the run did not name
ROW_STATUSES = ("failed", "interrupted", "ok", "skipped", "earlier")


@dataclass(frozen=True)
class Summary:
    """What the catalogue's head says about the run.

    Attributes
    ----------
    seconds : float or None
        The run's wall time (None: not known, as from a log).
    ran : int or None
        Garments run (not skipped): the rate's numerator.
    where : str
        Where they ran (``2 worker processes``).
    source : str
        Where the rows came from (``this run``, ``the log batch.jsonl``, ...).
    recipe : str
        The recipe file the run applied (empty: not known).
    recipe_text : str
        The recipe as validated, every default filled in (YAML; empty: not known).
    """

    seconds: float | None = None
    ran: int | None = None
    where: str = ""
    source: str = "this run"
    recipe: str = ""
    recipe_text: str = ""

    @property
    def rate(self) -> float | None:
        """Garments per minute over the garments run."""
        if not self.seconds or not self.ran:
            return None
        return 60.0 * self.ran / self.seconds


@dataclass(frozen=True)
class Row:
    """One garment of the catalogue.

    Attributes
    ----------
    record : dict
        The batch record (:data:`~ptailor.batch.records.RECORD_KEYS`).
    name : str
        Its output folder's name under OUT.
    folder : Path or None
        The folder, where the garment has one (a failed garment has none).
    report : dict or None
        Its ``report.json``.
    rejected : bool
        The folder is what the quality gates rejected (``OUT/_rejected/NAME``).
    """

    record: dict
    name: str
    folder: Path | None = None
    report: dict | None = field(default=None, repr=False)
    rejected: bool = False

    @property
    def status(self) -> str:
        return str(self.record.get("status"))

    @property
    def parts(self) -> tuple[str, ...]:
        """The folder's path under OUT, as parts (a relative link's)."""
        return (REJECTED_DIR, self.name) if self.rejected else (self.name,)

    @property
    def earlier_folder(self) -> bool:
        """The folder is not this record's run's output (an earlier run's, kept)."""
        return (
            self.folder is not None
            and not self.rejected
            and self.status not in ("ok", "skipped", "earlier")
        )


def _said(path: Path, problems: list[str], warn: Callable[[str], None] | None) -> None:
    """One warning naming the file and its first problems (fields ignored)."""
    if problems and warn is not None:
        more = f" and {len(problems) - 3} more" if len(problems) > 3 else ""
        warn(f"{path}: {'; '.join(problems[:3])}{more} (ignored)")


def read_report(folder: Path, *, warn: Callable[[str], None] | None = None) -> dict | None:
    """A garment folder's ``report.json``, every field type-checked (a wrong one dropped
    and named in a warning), or None when it is no JSON object (also warned)."""
    path = folder / "report.json"
    report, problems = read_checked(path, REPORT_FIELDS)
    _said(path, problems, warn)
    return report


def read_log(path: str | Path) -> list[dict]:
    """The records of a batch log (``--log``), in input order.

    Raises
    ------
    PtailorError
        The file cannot be read, or holds a line that is not a record (or a record with a
        field of the wrong type: its line and field named).
    """
    try:
        lines = load_text(path, max_bytes=tol.READBACK_LOG_MAX_BYTES).splitlines()
    except ReadBackError as exc:
        raise PtailorError(f"cannot read the batch log: {exc}", path=str(path)) from None
    recs = []
    for k, line in enumerate(lines, 1):
        if not line.strip():
            continue
        if not is_record(line):
            raise PtailorError(f"line {k} is not a ptailor batch record", path=str(path))
        rec, problems = checked(json.loads(line), RECORD_FIELDS, where=f"line {k}:")
        if problems or rec.get("index") is None:
            why = problems[0] if problems else f"line {k}: no index"
            raise PtailorError(f"{why} (not a ptailor batch record)", path=str(path))
        recs.append(rec)
    by_index = sorted(recs, key=lambda r: r["index"])
    seen, out = set(), []
    for r in reversed(by_index):  # a log written as garments finished, then in order
        if r["index"] not in seen:
            seen.add(r["index"])
            out.append(r)
    return out[::-1]


def saved_records(
    out: Path, *, warn: Callable[[str], None] | None = None
) -> tuple[list[dict], Summary] | None:
    """The records and summary the last ``batch --html`` saved in OUT, or None; a field of
    the wrong type is dropped (a record without its garment), named in a warning."""
    path = out / CATALOGUE_DIR / SAVED
    if not path.is_file() or path.is_symlink():
        return None
    data, problems = read_checked(path, SAVED_FIELDS)
    recs = []
    for k, r in enumerate((data or {}).get("records") or []):
        rec, more = checked(r, RECORD_FIELDS, where=f"records[{k}]")
        problems += more
        if rec is not None and isinstance(rec.get("garment"), str):
            recs.append(rec)
    _said(path, problems, warn)
    if data is None or "records" not in data:
        return None
    s = data.get("summary") or {}
    summary = Summary(
        seconds=s.get("seconds"), ran=s.get("ran"), where=str(s.get("where") or ""),
        source="the last batch run's records", recipe=str(s.get("recipe") or ""),
        recipe_text=str(s.get("recipe_text") or ""),
    )  # fmt: skip
    return recs, summary


def recipe_text(recipe) -> str:
    """A validated recipe as YAML, every default filled in (what the run applied)."""
    import yaml

    return yaml.safe_dump(recipe.to_dict(), sort_keys=False, default_flow_style=False, width=88)


def saved_text(records: list[dict], summary: Summary) -> str:
    """:data:`SAVED`'s JSON: the run's records and its summary."""
    data = {
        "written_by": "ptailor",
        "summary": {
            "seconds": summary.seconds,
            "ran": summary.ran,
            "where": summary.where,
            "recipe": summary.recipe,
            "recipe_text": summary.recipe_text,
        },
        "records": [{k: r.get(k) for k in RECORD_KEYS} for r in records],
    }
    return json.dumps(data, indent=1) + "\n"


def garment_folders(out: Path, *, warn: Callable[[str], None] | None = None) -> list[Path]:
    """The garment folders under OUT: ptailor output folders (a marker) with a
    ``report.json``, sorted by name (hidden staging folders left out; a symbolic link is
    left out with a warning: the catalogue writes only into OUT's own folders)."""
    try:
        entries = sorted(os.scandir(out), key=lambda e: e.name)
    except OSError:
        return []
    found = []
    for e in entries:
        if e.name.startswith(".") or e.name in RESERVED_NAMES:
            continue
        p = Path(e.path)
        if e.is_symlink():
            if warn is not None and p.is_dir() and read_marker(p) is not None:
                warn(f"{p}: a symbolic link, not a folder of OUT's own: left out of the catalogue")
            continue
        if e.is_dir() and read_marker(p) is not None and (p / "report.json").is_file():
            found.append(p)
    return found


def _folder_record(folder: Path, report: dict, index: int) -> dict:
    """A record for a folder no record of the run names (``earlier``)."""
    stamp, _ = read_checked(folder / STAMP, STAMP_FIELDS)
    garment = ((stamp or {}).get("garment") or {}).get("path")
    if garment is None:
        inputs = report.get("inputs") or {}
        first = next(iter(inputs.values()), None) or {}
        garment = first.get("path")
    rec = dict.fromkeys(RECORD_KEYS)
    rec.update(
        index=index, garment=garment or folder.name, out=str(folder), status="earlier",
        note="not in the last run: written by an earlier one",
    )  # fmt: skip
    rec.update(key_numbers(report))
    return rec


def _output(folder: Path, warn: Callable[[str], None] | None = None) -> dict | None:
    """The report of a ptailor output folder (a marker and a ``report.json``; not a
    symbolic link), else None."""
    if folder.is_symlink() or not folder.is_dir() or read_marker(folder) is None:
        return None
    return read_report(folder, warn=warn)


def _record_row(out: Path, r: dict, warn) -> Row:
    """The row of a record: its folder, or for a gate's failure what the gates rejected
    (``OUT/_rejected/NAME``), else an earlier run's folder kept."""
    name = Path(str(r.get("out") or r.get("garment") or "garment")).name
    if not is_file_name(name) or name in RESERVED_NAMES:  # (a name no folder of OUT has)
        return Row(r, name)
    if r.get("failure") == "gate":
        report = _output(out / REJECTED_DIR / name, warn)
        if report is not None:
            return Row(r, name, out / REJECTED_DIR / name, report, rejected=True)
    if (out / name).is_symlink() and warn is not None:
        warn(f"{out / name}: a symbolic link, not a folder of OUT's own: no page for it")
    report = _output(out / name, warn)
    return Row(r, name, out / name if report is not None else None, report)


def catalogue_rows(
    out: str | Path, records: list[dict], *, warn: Callable[[str], None] | None = None
) -> list[Row]:
    """The catalogue's rows: ``records`` in their order, then the garment folders under
    ``out`` that no record names (status ``earlier``).

    Parameters
    ----------
    out : str or Path
        The batch's output root.
    records : list of dict
        A batch's records (a record's folder is ``out / basename(record["out"])``; a gate's
        failure shows what the gates rejected, ``out / "_rejected" / basename``, if kept).
    warn : callable, optional
        Told of a garment folder whose ``report.json`` has fields of the wrong type (they
        are ignored) or is no report (the folder is left out), or that is a symbolic link
        (left out).

    Returns
    -------
    list of Row
    """
    out = Path(out)
    rows = [_record_row(out, r, warn) for r in records]
    named = {row.name for row in rows}
    for folder in garment_folders(out, warn=warn):
        if folder.name in named:
            continue
        report = read_report(folder, warn=warn)
        if report is not None:
            rec = _folder_record(folder, report, len(rows) + 1)
            rows.append(Row(rec, folder.name, folder, report))
    return rows


def stale_rejected(out: str | Path, records: list[dict]) -> list[Path]:
    """Rejected folders (``OUT/_rejected/NAME``) of garments whose record is no longer a
    gate's failure (they pass now, or failed otherwise): to be removed."""
    out = Path(out)
    stale = []
    for r in records:
        name = Path(str(r.get("out") or "")).name
        if not is_file_name(name):
            continue
        folder = out / REJECTED_DIR / name
        if r.get("failure") != "gate" and _output(folder) is not None:
            stale.append(folder)
    return stale
