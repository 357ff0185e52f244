"""The skip-unchanged stamp: ``batch.json`` in each garment's output folder.

Its ``key`` hashes the garment's contents (with its drape), the canonical recipe, the run's
options (:meth:`ptailor.run.options.RunOptions.stamped`) and the ptailor version, never the
garment's path: a folder whose stamp has the key a new run would write is up to date.
"""

from __future__ import annotations

import json
from pathlib import Path

from ptailor import __version__
from ptailor.digest import file_sha256, text_sha256

#: the stamp file written into each garment's output folder
STAMP = "batch.json"


def recipe_digest(recipe) -> str:
    """SHA-256 of the validated recipe as sorted JSON (every default filled in, no source).

    Comments, formatting, key order and spelled-out defaults do not change it.
    """
    data = recipe.to_dict()
    return text_sha256(json.dumps(data, sort_keys=True, separators=(",", ":"), default=str))


def inputs_digest(
    garment: str | Path,
    drape: str | Path | None = None,
    spec: str | Path | None = None,
    edited: str | Path | None = None,
) -> str:
    """SHA-256 of a garment file, or of a CAD pattern's file with its drape's, and with the
    specification's (``--spec``) and the edited drape's (``edited_drape``) when read.

    Raises
    ------
    OSError
        A file cannot be read.
    """
    digest = file_sha256(garment)
    if drape is not None:  # a CAD pattern: its drape is an input too
        digest = text_sha256(f"{digest}:{file_sha256(drape)}")
    if spec is not None:  # so is a specification
        digest = text_sha256(f"{digest}:spec:{file_sha256(spec)}")
    if edited is not None:  # and a drape edited elsewhere
        digest = text_sha256(f"{digest}:edited:{file_sha256(edited)}")
    return digest


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
    return {
        "key": text_sha256(json.dumps(keyed, sort_keys=True)),
        "ptailor_version": __version__,
        "garment": {"path": garment, "sha256": garment_sha},
        "recipe": {"sha256": recipe_sha},
        "options": options,
    }


def up_to_date(folder: Path, stamp: dict) -> dict | None:
    """The folder's report when its stamp has ``stamp``'s key and its outputs are all there
    (a report with a field of the wrong type is not one ptailor wrote: the garment re-runs).
    """
    from ptailor.batch.readback import REPORT_FIELDS, STAMP_FIELDS, read_checked

    old, _ = read_checked(folder / STAMP, STAMP_FIELDS)
    if not isinstance(old, dict) or old.get("key") != stamp["key"]:
        return None
    report, problems = read_checked(folder / "report.json", REPORT_FIELDS)
    outputs = report.get("outputs") if isinstance(report, dict) and not problems else None
    if not isinstance(outputs, list) or not all((folder / n).is_file() for n in outputs):
        return None
    return report
