"""Writing a catalogue into a batch's output root.

``OUT/index.html`` (one row per garment), ``OUT/_catalogue/`` (style sheet, script, the
run's records) and, in each garment's folder, ``index.html`` and ``thumbnail.png``, listed
in the folder's marker so that a later run may still replace the folder whole. Static and
self-contained: relative links only, nothing from outside the folder.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Callable
from importlib import resources
from pathlib import Path

from ptailor import __version__
from ptailor.catalogue.pages import GENERATOR, environment, garment_view, index_view
from ptailor.catalogue.rows import (
    CATALOGUE_DIR,
    INDEX,
    REJECTED_DIR,
    SAVED,
    Row,
    Summary,
    catalogue_rows,
    saved_text,
    stale_rejected,
)
from ptailor.catalogue.thumbnails import PREVIEW, THUMBNAIL, thumbnails
from ptailor.errors import PtailorError
from ptailor.run.folder import (
    add_files,
    check_output_dir,
    check_replaceable,
    read_marker,
    replace_file,
    staged_dir,
)

#: the catalogue's static files, copied into :data:`CATALOGUE_DIR`
STATIC = ("catalogue.css", "catalogue.js")


def is_catalogue_page(path: Path) -> bool:
    """Whether ``path`` is a page ptailor's catalogue wrote (its generator tag)."""
    try:
        with open(path, encoding="utf-8", errors="replace") as fh:
            head = fh.read(2048)
    except OSError:
        return False
    return f'<meta name="generator" content="{GENERATOR} ' in head


def check_catalogue_target(out: str | Path) -> None:
    """Refuse, before anything runs, an OUT whose ``index.html`` or ``_catalogue`` is not
    ptailor's catalogue (they would be replaced).

    Raises
    ------
    PtailorError
    """
    out = Path(out)
    page = out / INDEX
    if os.path.lexists(page) and (page.is_symlink() or not is_catalogue_page(page)):
        raise PtailorError(
            "exists and is not a ptailor catalogue page; move it or choose another output root",
            path=str(page),
        )
    folder = out / CATALOGUE_DIR
    if folder.is_symlink():
        raise PtailorError(
            "is a symbolic link (the catalogue writes only into OUT's own folders); "
            "remove it or choose another output root",
            path=str(folder),
        )
    if os.path.lexists(folder):
        check_output_dir(folder)
    rejected = out / REJECTED_DIR
    if os.path.lexists(rejected):
        foreign = [] if rejected.is_dir() and not rejected.is_symlink() else [rejected]
        if not foreign:
            foreign = [
                p for p in rejected.iterdir()
                if not p.name.startswith(".") and (not p.is_dir() or read_marker(p) is None)
            ]  # fmt: skip
        if foreign:
            raise PtailorError(
                "holds what ptailor did not write (a batch keeps rejected garments there); "
                "move it or choose another output root",
                path=str(foreign[0]),
            )


def _garment_files(row: Row, thumbnail, *, title: str, env, warn) -> None:
    """The garment's page, and its thumbnail when one was made, into its folder."""
    assert row.folder is not None
    files: dict[str, bytes] = {}
    if row.folder.is_symlink() or row.folder.parent.is_symlink():  # (never outside OUT)
        warn(f"{row.folder}: a symbolic link, not a folder of OUT's own: no page written")
        return
    if isinstance(thumbnail, OSError):
        warn(f"{row.folder / PREVIEW}: no thumbnail ({thumbnail})")
    elif thumbnail is not None:
        files[THUMBNAIL] = thumbnail
    view = garment_view(row, title=title, version=__version__)
    files[INDEX] = env.get_template("garment.html").render(view).encode("utf-8", "replace")
    try:
        add_files(row.folder, files)
    except PtailorError as exc:
        warn(f"no page for {row.name}: {exc}")


def _remove_output(folder: Path, warn) -> None:
    """Remove a ptailor output folder (only one that holds nothing else)."""
    import shutil

    try:
        if folder.is_symlink():
            raise PtailorError("a symbolic link, not a folder of OUT's own")
        check_replaceable(folder, str(folder))
        shutil.rmtree(folder)
        with contextlib.suppress(OSError):
            folder.parent.rmdir()  # (only when empty)
    except (OSError, PtailorError) as exc:
        warn(f"{folder}: left in place ({exc})")


#: the note of a row whose folder a running batch may replace (its page is not linked)
RERUN_NOTE = (
    "a batch started re-running it: its page is linked again when that batch has written "
    "it (if this stays, the batch was stopped: run it again)"
)


def unlink_rerun(out: str | Path, names: set[str], *, warn: Callable[[str], None]) -> None:
    """Before a batch replaces garment folders of OUT: rewrite OUT's catalogue page (only
    where it has one) without links to the folders named ``names`` (their rows say so), so
    that the page never links a garment page the batch has not written yet (a batch killed
    with SIGKILL leaves it so; the batch's end writes the pages, then the page).

    Parameters
    ----------
    out : str or Path
        The batch's output root.
    names : set of str
        The output folders' names the batch may replace (in OUT and in ``_rejected``).
    warn : callable
        Told of a garment folder whose files are not ptailor's (it is left out).
    """
    from dataclasses import replace

    from ptailor.catalogue.rows import saved_records

    out = Path(out)
    page = out / INDEX
    if not is_catalogue_page(page) or page.is_symlink():
        return
    records, summary = saved_records(out, warn=warn) or ([], Summary(source="the garment folders"))
    rows = [
        Row({**row.record, "status": "interrupted", "note": RERUN_NOTE}, row.name)
        if row.name in names else row
        for row in catalogue_rows(out, records, warn=warn)
    ]  # fmt: skip
    summary = replace(summary, source=f"{summary.source}; a batch is running")
    view = index_view(rows, summary, title=f"ptailor catalogue: {out.resolve().name}",
                      version=__version__)  # fmt: skip
    replace_file(
        page, environment().get_template("index.html").render(view).encode("utf-8", "replace")
    )


def write_catalogue(
    out: str | Path,
    records: list[dict],
    summary: Summary | None = None,
    *,
    title: str | None = None,
    warn: Callable[[str], None] | None = None,
) -> Path:
    """Write the catalogue of ``out``: its page, each garment's page and thumbnail.

    Parameters
    ----------
    out : str or Path
        The batch's output root (it exists).
    records : list of dict
        The run's records, in input order; folders under ``out`` that none names are
        added as ``earlier`` rows (:func:`~ptailor.catalogue.rows.catalogue_rows`).
    summary : Summary, optional
        The run's time and rate.
    title : str, optional
        The page's title (default: ``ptailor catalogue: OUT``).
    warn : callable, optional
        Told of a garment folder that could not take its page (the others go on).

    Returns
    -------
    Path
        ``out / "index.html"``.

    Raises
    ------
    PtailorError
        ``out`` is not a folder, or its ``index.html`` / ``_catalogue`` is not ptailor's.
    """
    out = Path(out)
    if not out.is_dir():
        raise PtailorError("not a folder", path=str(out))
    check_catalogue_target(out)
    summary = summary or Summary()
    title = title or f"ptailor catalogue: {out.resolve().name}"
    warn = warn or (lambda msg: None)
    env = environment()
    for folder in stale_rejected(out, records):  # the garment passes now
        _remove_output(folder, warn)
    rows = catalogue_rows(out, records, warn=warn)
    made = thumbnails([row.folder for row in rows if row.folder is not None])
    for row in rows:  # a loop over garments: each writes its own folder
        if row.folder is not None:
            _garment_files(row, made.get(row.folder), title=title, env=env, warn=warn)
    static = resources.files("ptailor.catalogue") / "static"
    with staged_dir(out / CATALOGUE_DIR) as tmp:
        for name in STATIC:
            (tmp / name).write_bytes((static / name).read_bytes())
        (tmp / SAVED).write_text(saved_text(records, summary), encoding="utf-8")
    view = index_view(rows, summary, title=title, version=__version__)
    page = out / INDEX
    try:
        replace_file(page, env.get_template("index.html").render(view).encode("utf-8", "replace"))
    except OSError as exc:
        why = exc.strerror or str(exc)
        raise PtailorError(f"cannot write the catalogue ({why})", path=str(page)) from None
    return page
