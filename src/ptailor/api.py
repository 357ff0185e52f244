"""The Python API: ptailor as a library ([docs/api.md](../../docs/api.md)).

Four functions, re-exported by the package (``ptailor.load_garment`` ...) without importing
anything at ``import ptailor``::

    g = ptailor.load_garment("garment.obj", pattern_units="cm", drape_units="cm")
    a = ptailor.adjust(g, "recipe.yaml")       # a path, YAML text, a dict or a Recipe
    a.garment.V2, a.report["panels"]            # the adjusted garment, report.json's dict
    ptailor.write(a, "out/", formats=("obj", "dxf"))
    V2 = ptailor.flatten(g, V3_edit)            # the pattern of a drape edited elsewhere

They are the command line's run (:mod:`ptailor.run`), step for step: the same reading,
adjustment, report and all-or-nothing output folder, so a garment adjusted here and written
is the one ``ptailor adjust`` writes. Nothing is printed and nothing exits: every problem of
the input raises :class:`~ptailor.errors.PtailorError` (a recipe's :class:`RecipeError`,
a numeric failure's :class:`NumericError` are kinds of it).
"""

from __future__ import annotations

import tempfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from ptailor.errors import PtailorError, RecipeError
from ptailor.formats.garment import LoadedGarment
from ptailor.model.garment import Garment
from ptailor.pipeline import Adjustment, adjustment
from ptailor.recipe import Recipe, load_recipe, parse_recipe, validate
from ptailor.run.edited import NO_RECIPE, check_edited_recipe
from ptailor.run.folder import check_output_dir
from ptailor.run.garment import Staged, stage, staged_folder
from ptailor.run.inputs import load_input, read_inputs
from ptailor.run.library_warnings import capture_library_warnings
from ptailor.run.options import RunOptions
from ptailor.run.outputs import DEFAULT_FORMATS
from ptailor.run.spec import spec_input

#: what :func:`adjust` takes as a recipe: a file's path, YAML text, a mapping, a Recipe
RecipeLike = str | Path | Mapping[str, Any] | Recipe


@dataclass(frozen=True)
class GarmentFile:
    """A garment read from its files (:func:`load_garment`).

    Attributes
    ----------
    loaded : LoadedGarment
        The garment in its computation unit, with its file units, its intake's record and,
        for a DXF, its pieces.
    path : str
        The garment file (OBJ, or DXF with ``drape``).
    drape : str or None
        The drape OBJ of a pattern-only garment or a DXF.
    options : RunOptions
        How it was read (units, weld, axes, size): the run's options.
    """

    loaded: LoadedGarment
    path: str
    drape: str | None
    options: RunOptions

    @property
    def garment(self) -> Garment:
        """The garment: ``V3`` (n3, 3), ``F3`` (m, 3), ``V2`` (n2, 2), ``F2`` (m, 3), in
        ``units``, worn in ``frame``."""
        return self.loaded.garment


@dataclass(frozen=True)
class Adjusted:
    """One adjustment (:func:`adjust`), ready to be written (:func:`write`).

    Attributes
    ----------
    garment : Garment
        The edited drape and the adjusted pattern (``garment.V2``, (n2, 2)), in the input's
        computation unit.
    report : dict
        The report as ``report.json`` holds it (written with no other file: its ``outputs``
        is ``["report.json"]``; :func:`write` returns the written one).
    adjustment : Adjustment
        The pipeline's record: the edit state, the flatten result, the uniform baseline.
    source : GarmentFile
        The garment adjusted.
    staged : Staged
        What :func:`write` writes from.
    """

    garment: Garment
    report: dict
    adjustment: Adjustment
    source: GarmentFile
    staged: Staged


def load_garment(
    path: str | Path,
    *,
    drape: str | Path | None = None,
    pattern_units: str | None = None,
    drape_units: str | None = None,
    up: str | None = None,
    front: str | None = None,
    units: str = "cm",
    weld: str | float = "auto",
    size: str | None = None,
    dxf_units: str | None = None,
) -> GarmentFile:
    """Read, repair and check a garment, as ``ptailor adjust`` reads it.

    Parameters
    ----------
    path : str or Path
        An OBJ with ``v`` = drape and ``vt`` = pattern; a pattern-only OBJ or a DXF with
        ``drape``.
    drape : str or Path, optional
        The drape OBJ of a pattern-only garment (``--drape``).
    pattern_units, drape_units : str, optional
        The files' units (``mm``, ``cm``, ``m``, ``in``, ``0.3333cm``; the pattern also
        ``auto``); None: ``cm`` if the garment is then of human size (``--pattern-units``,
        ``--drape-units``).
    up, front : str, optional
        The wearer's axes (``y``, ``-z``, ...); default: the file's, else y up and z front.
    units : str
        The computation unit (a recipe's ``units``).
    weld : str or float
        ``auto``, ``off`` or a distance (``--weld``).
    size, dxf_units : str, optional
        A DXF's size and unit.

    Returns
    -------
    GarmentFile

    Raises
    ------
    PtailorError
        A file that cannot be read or used, naming it.
    """
    options = RunOptions(
        pattern_units=pattern_units, drape_units=drape_units, weld=weld, up=up, front=front,
        size=size, dxf_units=dxf_units,
    )  # fmt: skip
    d = None if drape is None else str(drape)
    loaded = load_input(str(path), d, Recipe(units=units), options)
    return GarmentFile(loaded=loaded, path=str(path), drape=d, options=options)


def as_recipe(recipe: RecipeLike) -> Recipe:
    """A validated recipe from a path (a one-line string naming an existing file or ending
    in ``.yaml``/``.yml``, or a Path), YAML text (any other string), a mapping (the YAML's
    document) or a :class:`~ptailor.recipe.Recipe`.

    Raises
    ------
    RecipeError
        Every problem of the recipe.
    PtailorError
        Anything else (a missing file, another type).
    """
    if isinstance(recipe, Recipe):
        return recipe
    if isinstance(recipe, Mapping):
        rec, problems = validate(dict(recipe))
        if problems or rec is None:
            raise RecipeError(problems, path="<dict>")
        return replace(rec, source="<dict>")
    if isinstance(recipe, Path):
        return load_recipe(recipe)
    if isinstance(recipe, str):
        named = recipe.strip().endswith((".yaml", ".yml")) or Path(recipe).is_file()
        if "\n" not in recipe and named:
            return load_recipe(recipe.strip())
        return parse_recipe(recipe)
    raise PtailorError(f"a recipe is a path, YAML text or a dict, not {type(recipe).__name__}")


def adjust(
    garment: GarmentFile,
    recipe: RecipeLike | None = None,
    *,
    edited_drape: np.ndarray | str | Path | None = None,
    method: str | None = None,
    intrinsic: str | None = None,
    baseline: bool = True,
) -> Adjusted:
    """Edit a garment's drape by a recipe (or take a drape edited elsewhere) and adjust its
    pattern: ``ptailor adjust``'s run, without writing.

    Parameters
    ----------
    garment : GarmentFile
        From :func:`load_garment` (read again in the recipe's ``units`` and axes when they
        differ from those it was read in).
    recipe : path, str, dict or Recipe, optional
        :func:`as_recipe`'s; optional with ``edited_drape`` (the default settings).
    edited_drape : (n3, 3) float array, or str or Path, optional
        The drape edited elsewhere, in place of the recipe's steps (which must be none):
        an array in the garment's units and vertex order (``garment.garment.V3``'s), or an
        OBJ read as ``--edited-drape`` reads it.
    method, intrinsic : str, optional
        Override the recipe's flatten settings (``--method``, ``--intrinsic``).
    baseline : bool
        Also flatten uniformly, for the report's comparison.

    Returns
    -------
    Adjusted

    Raises
    ------
    PtailorError
        Bad input: the recipe, an edited drape of another shape, a step the garment cannot
        take, a numeric failure.
    """
    if recipe is None and edited_drape is None:
        raise PtailorError("adjust needs a recipe or an edited_drape")
    rec = NO_RECIPE if recipe is None else as_recipe(recipe)
    array = edited_drape if isinstance(edited_drape, np.ndarray) else None
    path = None if edited_drape is None or array is not None else str(edited_drape)
    options = replace(
        garment.options, method=method, intrinsic=intrinsic, baseline=baseline, edited_drape=path
    )
    if edited_drape is not None:
        check_edited_recipe(rec)
    # the garment as read, unless the recipe asks for other units or axes
    again = rec.units != garment.garment.units or (
        (rec.up or rec.front) and not (options.up or options.front)
    )
    source = garment.path if again else garment.loaded
    spec = spec_input(garment.path, options.spec)
    with capture_library_warnings() as library, one_blas_thread():
        inputs = read_inputs(
            source, garment.drape, rec, options, spec_file=spec, shown=garment.path
        )
        if array is not None:
            inputs = replace(inputs, edited=np.asarray(array, dtype=np.float64))
        staged = stage(inputs, rec, options, shown=garment.path, library=library)
        report = _report(staged, garment)
    adj = staged.adj
    return Adjusted(garment=adj.garment, report=report, adjustment=adj, source=garment,
                    staged=staged)  # fmt: skip


def _report(staged: Staged, garment: GarmentFile) -> dict:
    """The report of ``staged`` written with no other file (in a folder thrown away)."""
    quiet = replace(staged, options=replace(staged.options, formats=()))
    with (
        tempfile.TemporaryDirectory(prefix="ptailor-report-") as tmp,
        staged_folder(Path(tmp) / "out", quiet, shown=garment.path, display={}) as report,
    ):
        pass
    return report


def write(
    adjusted: Adjusted, out_dir: str | Path, *, formats: Sequence[str] = DEFAULT_FORMATS
) -> dict:
    """Write an adjustment's output folder, all or nothing, as ``ptailor adjust -o`` does.

    Parameters
    ----------
    adjusted : Adjusted
    out_dir : str or Path
        The folder: made, or replaced whole when it is one ptailor wrote.
    formats : sequence of str
        Of ``obj``, ``dxf``, ``svg``, ``png``, ``pdf``, ``cut`` (``--formats``; the first
        four by default); ``report.json`` always.

    Returns
    -------
    dict
        The report written (``report.json``).

    Raises
    ------
    PtailorError
        An unknown format, or a folder ptailor may not write (one it did not write, one
        that holds an input).
    """
    staged = adjusted.staged
    options = replace(staged.options, formats=tuple(formats))  # (checks them)
    src = adjusted.source
    check_output_dir(out_dir, [src.path, src.drape, options.body, options.edited_drape])
    with capture_library_warnings() as library:  # (the writing's, after the adjustment's)
        library[:0] = staged.library_warnings
        staged = replace(staged, options=options, library_warnings=library)
        with staged_folder(out_dir, staged, shown=src.path, display={}) as rep:
            pass
    return rep


def flatten(
    garment: GarmentFile | Garment,
    V3_edit: np.ndarray,
    *,
    recipe: RecipeLike | None = None,
    method: str | None = None,
) -> np.ndarray:
    """The pattern of a drape edited elsewhere, by the method: the adjusted ``V2``.

    Parameters
    ----------
    garment : GarmentFile or Garment
    V3_edit : (n3, 3) float array
        The garment's drape moved (same vertices, in its units and order).
    recipe : path, str, dict or Recipe, optional
        Flatten settings (its steps must be none); default the defaults.
    method : str, optional
        ``scale-preserving`` (default) or ``uniform``.

    Returns
    -------
    (n2, 2) float array
        The adjusted pattern, each panel placed by a rigid best fit onto its original.

    Raises
    ------
    PtailorError
        A drape of another shape, a collapsed triangle, a numeric failure.
    """
    g = garment.garment if isinstance(garment, GarmentFile) else garment
    rec = NO_RECIPE if recipe is None else as_recipe(recipe)
    check_edited_recipe(rec)
    if method is not None:
        RunOptions(method=method)  # (checks it)
    V = np.asarray(V3_edit, dtype=np.float64)
    with one_blas_thread():
        return adjustment(g, rec, method=method, baseline=False, edited=V).result.V2


def one_blas_thread():
    """A context in which BLAS runs one thread, as every ptailor command runs it
    (:func:`ptailor.cli.main.one_blas_thread` sets it before numpy loads; a library is
    imported after, so threadpoolctl limits the loaded BLAS for the call). The method's
    dense systems are small: a second thread costs CPU for no speed, and several on a
    loaded machine busy-wait (the 88k-triangle tshirt's flatten: 1.9 s of CPU with one
    thread, 6.3 s with OpenBLAS's default on a loaded 2-core machine)."""
    from threadpoolctl import threadpool_limits

    return threadpool_limits(limits=1, user_api="blas")
