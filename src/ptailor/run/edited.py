"""A drape edited elsewhere (``--edited-drape``, a batch manifest's ``edited_drape``).

The edited OBJ's ``v`` and faces are the garment's drape moved in another tool (Blender,
Maya, CLO, Marvelous Designer, a re-simulation); its ``vt``, normals and groups are ignored.
It is read in the garment drape file's units and numbering, welded as the garment was:

- the drape file's own numbering (the file the garment's drape came from, exported
  again): the same vertex count and the same faces, welded by the garment's weld;
- or the garment's as read (after the weld and the repairs): ptailor's own ``garment.obj``
  of an earlier run, or a drape with nothing to weld.

Anything else is refused in one line naming both files and both counts, before any work.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ptailor.errors import PtailorError
from ptailor.formats import reader_for
from ptailor.formats.garment import LoadedGarment
from ptailor.recipe import Recipe

#: the recipe of an ``--edited-drape`` run given none: the default flatten settings, in cm
NO_RECIPE = Recipe(source="(no recipe: --edited-drape)")


def check_edited_recipe(recipe: Recipe) -> None:
    """Refuse a recipe with steps beside an edited drape: the drape is the edit; a recipe
    with it gives the units, axes, flatten settings and ``expect:`` only.

    Raises
    ------
    PtailorError
        Naming the recipe and its step count (exit 2).
    """
    if recipe.steps:
        n = len(recipe.steps)
        raise PtailorError(
            f"has {n} step{'s' if n != 1 else ''}, but with --edited-drape the edited drape is "
            "the edit: give a recipe without steps (units, axes, flatten settings, expect)",
            path=recipe.source,
        )


def drape_file(loaded: LoadedGarment) -> str:
    """The file the garment's drape was read from (the garment OBJ, or its ``--drape``)."""
    return loaded.inputs.get("drape") or loaded.inputs["garment"]


def read_edited_drape(path: str | Path, loaded: LoadedGarment, *, shown: str | None = None):
    """The edited drape in the garment's units and vertex numbering.

    Parameters
    ----------
    path : str or Path
        An OBJ (any format the readers take) whose ``v`` and faces are the garment's drape.
    loaded : LoadedGarment
        The garment as read, with its drape file's units and weld.
    shown : str, optional
        The garment's drape file as errors name it (default: the path read).

    Returns
    -------
    (n3, 3) float array
        In ``loaded.garment.units``, one row per drape vertex of ``loaded.garment``.

    Raises
    ------
    PtailorError
        Vertex or face counts that match neither numbering, or the same counts with other
        faces: one line naming both files and both counts.
    """
    epath, gpath = str(path), shown or drape_file(loaded)
    mesh = reader_for(epath)(epath)
    v, fv = np.asarray(mesh.v, dtype=np.float64), np.asarray(mesh.fv)
    g = loaded.garment
    if len(v) == len(g.V3) and len(fv) == len(g.F3):  # the garment's numbering, as read
        _same_faces(fv, g.F3, epath, gpath)
        return v * loaded.drape_scale
    raw = reader_for(drape_file(loaded))(drape_file(loaded))
    if loaded.vertex_map is not None and (len(v), len(fv)) == (len(raw.v), len(raw.fv)):
        _same_faces(fv, np.asarray(raw.fv), epath, gpath)  # the file's numbering, welded
        return v[loaded.vertex_map] * loaded.drape_scale
    read = f" ({len(g.V3)} and {len(g.F3)} as read)" if len(g.V3) != len(raw.v) else ""
    raise PtailorError(
        f"{len(v)} vertices and {len(fv)} faces, but the drape of {gpath} has {len(raw.v)} "
        f"vertices and {len(raw.fv)} faces{read}: an edited drape keeps the garment's vertices "
        "and faces",
        path=epath,
    )


def _same_faces(fv: np.ndarray, F: np.ndarray, epath: str, gpath: str) -> None:
    """Refuse faces other than the garment's (same counts, other vertices)."""
    if fv.shape != F.shape or not np.array_equal(fv, F):
        rows = np.flatnonzero(np.any(fv != F, axis=1)) if fv.shape == F.shape else [0]
        raise PtailorError(
            f"{len(fv)} faces as the drape of {gpath} has {len(F)}, but face {int(rows[0]) + 1} "
            f"joins other vertices ({len(rows)} faces differ): an edited drape keeps the "
            "garment's faces, in their order",
            path=epath,
        )
