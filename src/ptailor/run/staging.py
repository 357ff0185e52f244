"""The staging folders an output folder is written in: their names, the lock a writer
holds on one, and the clean-up of those a killed writer left.

An output folder ``NAME`` is written into ``.NAME.XXXXXXXX.tmp`` beside it
(:func:`new_staging_dir`) and moved into place when complete; the folder it replaces is
moved aside to ``.NAME.old-.NAME.XXXXXXXX.tmp`` meanwhile (:func:`old_staging_dir`). Both
names are recognised again (:func:`staging_pattern`): to remove what a killed writer left
(:func:`remove_staging`, :func:`remove_stale_staging`) and to keep them out of messages
(:func:`hide_staging`). Writing and replacing the folder itself is
:mod:`ptailor.run.folder`'s.
"""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import tempfile
from pathlib import Path

from ptailor import tolerances

#: see :data:`ptailor.tolerances.STAGING_NAME_BYTES`
STAGING_NAME_BYTES = tolerances.STAGING_NAME_BYTES


def staging_stem(name: str) -> str:
    """The part of an output folder's name its staging folders carry (``.STEM.*.tmp``)."""
    raw = os.fsencode(name)
    if len(raw) <= STAGING_NAME_BYTES:
        return name
    cut = raw[: STAGING_NAME_BYTES - 9].decode("utf-8", "ignore")
    return f"{cut}~{hashlib.sha256(raw).hexdigest()[:8]}"


def new_staging_dir(out: Path) -> Path:
    """Create the staging folder ``out`` is written into: ``.STEM.XXXXXXXX.tmp`` beside it
    (read back by :func:`staging_pattern`)."""
    stem = staging_stem(out.name)
    return Path(tempfile.mkdtemp(prefix=f".{stem}.", suffix=".tmp", dir=out.parent))


def old_staging_dir(out: Path, tmp: Path) -> Path:
    """Where the previous ``out`` is moved aside while ``tmp`` replaces it:
    ``.STEM.old-.STEM.XXXXXXXX.tmp`` (read back by :func:`staging_pattern`)."""
    return out.with_name(f".{staging_stem(out.name)}.old-{tmp.name}")


def staging_pattern(name: str) -> re.Pattern:
    """Matches the staging folders of an output folder named ``name``: group 1 is set for
    ``.NAME.old-...`` (the previous output, moved aside while being replaced)."""
    s = re.escape(staging_stem(name))
    return re.compile(f"^\\.{s}\\.(old-\\.{s}\\.)?[a-z0-9_]{{8}}\\.tmp$")


def _staging_folders(out: Path) -> list[tuple[Path, bool]]:
    """The staging folders beside ``out`` (not links), each with whether it is the previous
    output moved aside (``.NAME.old-...tmp``)."""
    if not out.parent.is_dir():
        return []
    pat = staging_pattern(out.name)
    found = []
    for p in sorted(out.parent.iterdir()):
        m = pat.match(p.name)
        if m and p.is_dir() and not p.is_symlink():
            found.append((p, bool(m.group(1))))
    return found


def _put_back_or_remove(p: Path, *, old: bool, out: Path) -> None:
    """Move the previous output ``p`` back when ``out`` is missing, else remove ``p``."""
    if old and not out.exists():
        p.rename(out)
    else:
        shutil.rmtree(p, ignore_errors=True)


def remove_staging(out: str | Path) -> list[str]:
    """Remove the staging folders a killed writer of ``out`` left beside it.

    ``.NAME.XXXXXXXX.tmp`` (being written, :func:`ptailor.run.folder.staged_dir`) is removed;
    ``.NAME.old-...tmp`` (the previous output, moved aside for the replacement) is moved back
    when ``out`` is missing, else removed. Returns the names handled.
    """
    out = Path(out)
    handled = []
    for p, old in _staging_folders(out):
        _put_back_or_remove(p, old=old, out=out)
        handled.append(p.name)
    return handled


def hold(folder: Path) -> int | None:
    """Lock ``folder`` for this process (an advisory ``flock``, released by the kernel
    however the process ends); the descriptor to close when done, None where locks are not
    available."""
    try:
        import fcntl
    except ImportError:  # not POSIX
        return None
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return None
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        os.close(fd)
        return None
    return fd


def _held(folder: Path) -> bool:
    """Whether a live process holds ``folder`` (:func:`hold`); True where it cannot be
    told (no locks, or the folder cannot be opened): only a folder known to be free is
    removed."""
    fd = hold(folder)
    if fd is None:
        return True
    os.close(fd)  # (closing releases the probe's lock)
    return False


def remove_stale_staging(out: str | Path) -> list[str]:
    """Remove the staging folders of ``out`` that no live process holds: a writer killed
    with SIGKILL (which no handler sees) left them, and :func:`remove_staging` removes
    them only for a batch's garments whose workers are known to be gone. A folder being
    written holds a lock (:func:`hold`); the previous output moved aside
    (``.NAME.old-.NAME.XXXXXXXX.tmp``) is held through the staging folder named in it, and
    is moved back when ``out`` is missing. Returns the names handled."""
    out = Path(out)
    handled = []
    for p, old in _staging_folders(out):
        writer = p.with_name(p.name.split(".old-", 1)[1]) if old else p
        if writer.is_dir() and _held(writer):
            continue
        _put_back_or_remove(p, old=old, out=out)
        handled.append(p.name)
    return handled


_ANY_STAGING = re.compile(r"(?:^|(?<=/))\.([^/]+?)\.(?:old-\.[^/]+?\.)?[a-z0-9_]{8}\.tmp(?=/|$)")


def hide_staging(text: str) -> str:
    """``text`` with staging folder names replaced by the output folder's (messages)."""
    return _ANY_STAGING.sub(lambda m: m.group(1), text)
