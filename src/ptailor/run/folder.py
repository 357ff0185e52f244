"""Writing an output folder: all or nothing, never over an input, never over user files.

An output folder is written into a hidden staging folder beside it and moved into place
when complete. Every output folder holds a marker, :data:`MARKER` (JSON: the ptailor
version and the files written); an existing folder is replaced only when it is empty, or
holds that marker and nothing else than the files it lists (or is an output of a ptailor
from before the marker: :func:`legacy_files`). A symbolic link given as the output folder
is followed: the folder it points to is replaced under the same rules and the link kept;
a link to nothing is refused. The inputs are never inside what gets replaced.

The staging folders' names, their locks and the clean-up after a killed writer are
:mod:`ptailor.run.staging`'s.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import signal
import threading
from collections.abc import Iterable, Mapping
from contextlib import contextmanager
from pathlib import Path

from ptailor import tolerances as tol
from ptailor.errors import PtailorError
from ptailor.run.staging import hold, new_staging_dir, old_staging_dir, remove_stale_staging

#: the marker file every output folder gets (hidden; lists the files ptailor wrote there)
MARKER = ".ptailor"
#: the files a ptailor from before the marker wrote into an output folder
LEGACY_NAMES = frozenset(
    {"report.json", "garment.obj", "pattern.dxf", "pattern.svg", "preview.png", "batch.json"}
)
#: the longest file name most file systems take (bytes)
NAME_MAX = 255


# --------------------------------------------------------------------------- the folder


def _missing_parents(out: Path) -> list[Path]:
    """The folders above ``out`` that do not exist yet, deepest first."""
    out = Path(os.path.abspath(out))
    missing = []
    for d in out.parents:
        if d.exists() or d.is_symlink():
            break
        missing.append(d)
    return missing


def _remove_empty(folders: list[Path]) -> None:
    """Remove ``folders`` (deepest first) while they are empty: what a failed run made."""
    for d in folders:
        try:
            d.rmdir()
        except OSError:
            return


def _real(out: Path, shown: str) -> Path:
    """The folder that is written for ``out``: symbolic links followed (a link to nothing
    refused), the name's length checked."""
    if len(os.fsencode(out.name)) > NAME_MAX:
        raise PtailorError(
            f"output folder name is too long ({len(os.fsencode(out.name))} bytes; a file "
            f"name holds at most {NAME_MAX})",
            path=shown,
        )
    real = Path(os.path.realpath(out))
    if out.is_symlink() and not real.exists():
        raise PtailorError(
            f"output folder is a symbolic link to {os.readlink(out)}, which does not exist "
            "(ptailor does not create a link's target: create it, or give another folder)",
            path=shown,
        )
    if not real.name:  # "/"
        raise PtailorError("the root folder cannot be an output folder", path=shown)
    return real


def _os_error(exc: OSError, shown: str, what: str = "cannot write the output folder"):
    reason = exc.strerror or type(exc).__name__
    return PtailorError(f"{what} ({reason})", path=shown)


# --------------------------------------------------------------------------- markers


def read_marker(folder: Path) -> list[str] | None:
    """The files the folder's marker lists, or None when it has none ptailor could have
    written (missing, not a plain file, not ptailor's JSON)."""
    p = folder / MARKER
    try:
        if not p.is_file() or p.is_symlink() or p.stat().st_size > tol.OUTPUT_MARKER_MAX_BYTES:
            return None
        data = json.loads(p.read_text())
    except (OSError, ValueError):
        return None
    if not isinstance(data, dict) or data.get("written_by") != "ptailor":
        return None
    files = data.get("files")
    if not isinstance(files, list):
        return None
    if not all(isinstance(f, str) and f and "/" not in f and f not in (".", "..") for f in files):
        return None
    return files


def marker_text(files: Iterable[str]) -> str:
    """The marker's JSON for an output folder holding ``files``."""
    from ptailor import __version__

    data = {"written_by": "ptailor", "version": __version__, "files": sorted(files)}
    return json.dumps(data, indent=2) + "\n"


def legacy_files(folder: Path) -> set[str] | None:
    """The files of an output written by a ptailor from before the marker, or None.

    Accepted only when ``report.json`` is a ptailor report (its ``outputs``, ``inputs``,
    ``panels`` and ``solver``) and every file is one of :data:`LEGACY_NAMES` that the
    report lists (``batch.json`` a ptailor stamp).
    """
    rp = folder / "report.json"
    try:
        if rp.is_symlink() or not rp.is_file() or rp.stat().st_size > tol.LEGACY_REPORT_MAX_BYTES:
            return None
        rep = json.loads(rp.read_text())
    except (OSError, ValueError):
        return None
    if not isinstance(rep, dict) or not all(k in rep for k in ("inputs", "panels", "solver")):
        return None
    outputs = rep.get("outputs")
    if not isinstance(outputs, list) or "report.json" not in outputs:
        return None
    names = {n for n in outputs if isinstance(n, str) and n in LEGACY_NAMES}
    with contextlib.suppress(OSError, ValueError):
        stamp = json.loads((folder / "batch.json").read_text())
        if isinstance(stamp, dict) and "key" in stamp and "ptailor_version" in stamp:
            names.add("batch.json")
    return names


def _entries(folder: Path) -> dict[str, bool]:
    """Name -> is a plain file (not a link, folder, ...)."""
    with os.scandir(folder) as it:
        return {e.name: e.is_file(follow_symlinks=False) for e in it}


def check_replaceable(folder: Path, shown: str) -> None:
    """Raise unless ``folder`` (existing) may be replaced whole: empty, or ptailor's only.

    Raises
    ------
    PtailorError
        The folder holds files ptailor did not write (they are named), or cannot be read.
    """
    try:
        entries = _entries(folder)
    except OSError as exc:
        raise _os_error(exc, shown, "cannot read the output folder") from None
    if not entries:
        return
    listed = read_marker(folder) if MARKER in entries else None
    if listed is not None:
        allowed, how = {*listed, MARKER}, "its .ptailor marker lists"
    elif MARKER in entries:
        allowed, how = set(), "ptailor writes"
    else:
        legacy = legacy_files(folder)
        allowed, how = (legacy or set()), "ptailor writes"
    foreign = sorted(n for n, plain in entries.items() if n not in allowed or not plain)
    if not foreign:
        return
    shown_names = ", ".join(foreign[:3]) + (
        f" and {len(foreign) - 3} more" if len(foreign) > 3 else ""
    )
    if listed is None and MARKER not in entries and legacy_files(folder) is None:
        raise PtailorError(
            f"output folder exists and is not an earlier ptailor output (it holds {shown_names});"
            " choose another folder, or empty it",
            path=shown,
        )
    raise PtailorError(
        f"output folder holds files other than those {how} ({shown_names}); move them "
        "or choose another folder",
        path=shown,
    )


def check_output_dir(out: str | Path, inputs: Iterable[str | Path | None] = ()) -> Path:
    """Refuse an output folder that holds an input or files ptailor did not write.

    An existing folder is accepted when it is empty or an earlier ptailor output
    (:func:`check_replaceable`); a symbolic link is followed (one to nothing refused).
    ``inputs`` that are no files (``-``, ``<stdin>``, None) are ignored.

    Raises
    ------
    PtailorError
    """
    shown = str(out)
    out = Path(out)
    try:
        real = _real(out, shown)
        if real.exists() and not real.is_dir():
            raise PtailorError("output exists and is not a folder", path=shown)
        for p in inputs:
            if p is None or str(p) in ("", "-") or not os.path.lexists(p):
                continue
            rp = Path(os.path.realpath(p))
            if rp == real or real in rp.parents:
                raise PtailorError(
                    f"output folder holds the input {p}, which replacing it would delete; "
                    "choose another output folder",
                    path=shown,
                )
        if real.is_dir():
            check_replaceable(real, shown)
    except OSError as exc:
        raise _os_error(exc, shown, "cannot use the output folder") from None
    return out


# --------------------------------------------------------------------------- staging


@contextmanager
def deferred_signals():
    """Hold SIGINT, SIGTERM and SIGALRM back (main thread only) while a folder is swapped:
    the first is delivered when the block ends."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    got: list[int] = []
    old = {}
    for s in (signal.SIGINT, signal.SIGTERM, signal.SIGALRM):  # (alarm: batch --timeout)
        with contextlib.suppress(ValueError, OSError):
            old[s] = signal.signal(s, lambda n, f: got.append(n))
    try:
        yield
    finally:
        for s, h in old.items():
            signal.signal(s, h)
        if got:
            signal.raise_signal(got[0])


def _default_mode() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return 0o777 & ~mask


def _commit(tmp: Path, real: Path, shown: str, done: list | None = None) -> None:
    """Put ``tmp`` in place as ``real`` (``done`` gets ``shown`` once it is: a signal held
    meanwhile is delivered after, and says the folder is complete)."""
    done = [] if done is None else done
    names = [p.name for p in tmp.iterdir()]
    (tmp / MARKER).write_text(marker_text(names))
    with deferred_signals():
        if real.exists():
            check_replaceable(real, shown)  # again: the folder may have changed meanwhile
            tmp.chmod(real.stat().st_mode & 0o7777)
            old = old_staging_dir(real, tmp)
            real.rename(old)
            try:
                tmp.rename(real)
            except BaseException:
                old.rename(real)
                raise
            done.append(shown)
            shutil.rmtree(old, ignore_errors=True)
        else:
            tmp.chmod(_default_mode())
            tmp.rename(real)
            done.append(shown)


@contextmanager
def staged_dir(out: str | Path, *, divert: tuple[type[BaseException], str | Path] | None = None):
    """Yield a temporary folder beside ``out``; on success it replaces ``out`` atomically.

    On any exception (``KeyboardInterrupt`` and the SIGTERM the CLI turns into one too)
    the temporary folder is removed and ``out`` is left as it was; an ``OSError`` becomes
    a :class:`PtailorError` naming ``out`` (never the staging folder). A symbolic link
    ``out`` is followed (:func:`check_output_dir`); the marker is written last.

    ``divert``: ``(exception type, folder)``: an exception of that type puts the staged
    folder at ``folder`` instead (replacing it whole under the same rules; ``out`` is left
    as it was) before it goes on: a batch keeps a garment its quality gates rejected there,
    for review. Where that cannot be written the folder is removed, as for any exception.
    """
    shown = str(out)
    out = Path(out)
    real = _real(out, shown)
    tmp = None
    lock = None
    made = _missing_parents(real)  # removed again if the run fails (a full disk)
    done: list[str] = []
    try:
        with deferred_signals():  # a signal as mkdtemp returns must not orphan the folder
            real.parent.mkdir(parents=True, exist_ok=True)
            remove_stale_staging(real)
            tmp = new_staging_dir(real)
            lock = hold(tmp)
        yield tmp
        _commit(tmp, real, shown, done)
    except BaseException as exc:
        if done and isinstance(exc, KeyboardInterrupt):  # a signal held while it was put
            exc.output_complete = shown  # in place: the folder is complete (the CLI says)
            raise
        if tmp is None:
            _remove_empty(made)
            if isinstance(exc, OSError):
                raise _os_error(exc, shown, "cannot create the output folder") from None
            raise
        if divert is not None and isinstance(exc, divert[0]) and _diverted(tmp, divert[1]):
            raise
        with deferred_signals():
            shutil.rmtree(tmp, ignore_errors=True)
            if not real.exists():
                _remove_empty(made)
        if isinstance(exc, OSError):
            raise _os_error(exc, shown) from None
        if isinstance(exc, PtailorError) and str(tmp) in str(exc):
            raise PtailorError(str(exc).replace(str(tmp), shown)) from None
        raise
    finally:
        if lock is not None:
            os.close(lock)


def _diverted(tmp: Path, folder: str | Path) -> bool:
    """Put the staged folder ``tmp`` at ``folder`` (see :func:`staged_dir`'s ``divert``);
    False where it cannot be (the caller removes it)."""
    shown = str(folder)
    try:
        real = _real(Path(folder), shown)
        if real.exists():
            check_replaceable(real, shown)
        real.parent.mkdir(parents=True, exist_ok=True)
        if real.parent.stat().st_dev != tmp.stat().st_dev:
            return False  # (a rename cannot cross file systems)
        _commit(tmp, real, shown)
    except (OSError, PtailorError):
        return False
    return True


def write_json(path: Path, data: Mapping) -> None:
    """Write ``data`` as indented JSON (insertion order) with a trailing newline."""
    path.write_text(json.dumps(data, indent=2) + "\n")


def add_files(folder: str | Path, files: Mapping[str, bytes]) -> None:
    """Write ``files`` (name -> bytes) into an existing output folder and list them in its
    marker, so that a later run may still replace the folder whole.

    Each file is written beside its final name and moved into place (a reader never sees
    half a file); the marker is rewritten last, the same way. Used for what a catalogue
    adds to a garment's folder after the run (its page and thumbnail).

    Raises
    ------
    PtailorError
        The folder has no ptailor marker (its files are not known to be ptailor's), or a
        name is not a plain file name.
    """
    folder = Path(folder)
    listed = read_marker(folder)
    if listed is None:
        raise PtailorError("not a ptailor output folder (no .ptailor marker)", path=str(folder))
    for name in files:
        if not name or "/" in name or name in (".", "..", MARKER):
            raise PtailorError(f"not a file name an output folder can hold: {name!r}")
    try:
        for name, data in files.items():
            replace_file(folder / name, data)
        replace_file(folder / MARKER, marker_text({*listed, *files}).encode())
    except OSError as exc:
        raise _os_error(exc, str(folder)) from None


def replace_file(path: Path, data: bytes) -> None:
    """``path`` holds ``data``: written to a hidden file beside it, then moved into place
    (a reader never sees half a file; the hidden file is removed if the write fails)."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        tmp.write_bytes(data)
        os.replace(tmp, path)
    finally:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()
