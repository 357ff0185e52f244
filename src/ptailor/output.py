"""Writing an output folder: all or nothing, never over an input."""

from __future__ import annotations

import json
import shutil
import tempfile
from collections.abc import Callable
from contextlib import contextmanager
from pathlib import Path

from ptailor.errors import PtailorError


def check_output_dir(out: str | Path, inputs: list[str]) -> Path:
    """Refuse an output folder that holds an input or unrelated files.

    An existing folder is accepted when it is empty or holds a previous ptailor output
    (a ``report.json``), which is then replaced whole.

    Raises
    ------
    PtailorError
    """
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise PtailorError("output exists and is not a folder", path=str(out))
    res = out.resolve()
    for p in inputs:
        rp = Path(p).resolve()
        if res == rp or res in rp.parents:
            raise PtailorError(f"output folder would hold the input {p}", path=str(out))
    if out.is_dir() and any(out.iterdir()) and not (out / "report.json").is_file():
        raise PtailorError(
            "output folder exists, is not empty and holds no earlier ptailor output", path=str(out)
        )
    return out


@contextmanager
def staged_dir(out: str | Path):
    """Yield a temporary folder beside ``out``; on success it replaces ``out`` atomically.

    On any exception the temporary folder is removed and ``out`` is left as it was.
    """
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".tmp", dir=out.parent))
    try:
        yield tmp
        old = None
        if out.exists():
            old = out.with_name(f".{out.name}.old-{tmp.name}")
            out.rename(old)
        tmp.rename(out)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


def write_json(path: Path, data: dict) -> None:
    """Write JSON with sorted-insertion order and a trailing newline."""
    path.write_text(json.dumps(data, indent=2) + "\n")


Writer = Callable[[Path], None]
