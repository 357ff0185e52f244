"""What one run reads: the recipe, the garment (and its drape), the body, the pieces' plan,
the specification, the edited drape: :func:`read_inputs`, all checked before any work."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ptailor.edits import EditOptions
from ptailor.formats.garment import LoadedGarment, load_garment
from ptailor.pieces import PiecePlan
from ptailor.recipe import Recipe, load_recipe, resolve_frame
from ptailor.report.expect import measures_before
from ptailor.run.checks import (
    check_body_placement,
    check_engine,
    check_seam_allowance,
    check_size_against_body,
)
from ptailor.run.edited import read_edited_drape
from ptailor.run.graded import read_sizes
from ptailor.run.options import RunOptions
from ptailor.run.outputs import needs_pieces
from ptailor.run.spec import matched_specification, read_run_specification, spec_unit, spec_units
from ptailor.spec.match import SpecMatching


def checked_recipe(recipe: Recipe | str, options: RunOptions) -> Recipe:
    """The recipe (read when given as a path, ``-`` for stdin) with the options checked
    against it; raises before any garment is read."""
    if not isinstance(recipe, Recipe):
        recipe = load_recipe(recipe)
    if options.edited_drape is not None:
        from ptailor.run.edited import check_edited_recipe

        check_edited_recipe(recipe)
    if options.verify:
        check_engine()
    return recipe


def load_body(path: str, *, units: str, to: str):
    """Read a ``--body`` mesh (:func:`ptailor.edits.body.read_body`)."""
    from ptailor.edits.body import read_body

    return read_body(path, units=units, to=to)


def edit_options(recipe: Recipe, options: RunOptions) -> EditOptions:
    """The edits' options: the body (``--body auto`` is fitted once the garment is read:
    :func:`fitted_body`)."""
    body = options.body if options.body != "auto" else None
    return EditOptions(
        body=load_body(body, units=options.body_units, to=recipe.units) if body else None,
    )


def fitted_body(garment, *, path: str | None = None):
    """``--body auto``: the mean body fitted to a garment's drape
    (:func:`ptailor.verify.fit.fit_body`), as a trimesh in the garment's frame and units,
    and the fit's record.

    Raises
    ------
    PtailorError
        A drape the body cannot be fitted to (exit 2).
    """
    import trimesh

    from ptailor.model.structure import structure
    from ptailor.model.units import CM_PER
    from ptailor.verify.fit import fit_body
    from ptailor.verify.legs import trouser_axes
    from ptailor.verify.pose import sleeve_axes

    fit = fit_body(
        garment.V3,
        garment.F3,
        openings=structure(garment).openings,
        frame=garment.frame,
        cm_per_unit=CM_PER.get(garment.units, 1.0),
        path=path,
        sleeves=sleeve_axes(garment),
        trousers=trouser_axes(garment),
    )
    return trimesh.Trimesh(fit.V, fit.F, process=False), fit.record()


def load_input(
    garment: str, drape: str | None, recipe: Recipe, options: RunOptions
) -> LoadedGarment:
    """The garment in the recipe's units and its frame (the options' axes, else the
    recipe's: :func:`ptailor.recipe.resolve_frame`) (:func:`ptailor.formats.garment.
    load_garment`)."""
    return load_garment(
        garment,
        drape=drape,
        units=recipe.units,
        pattern_units=options.pattern_units,
        drape_units=options.drape_units,
        weld=options.weld,
        size=options.size,
        dxf_units=options.dxf_units,
        frame=resolve_frame(options.up, options.front, recipe, default=None),
    )


def plan_pieces(loaded: LoadedGarment, options: RunOptions) -> PiecePlan | None:
    """The pieces, matched (a CAD pattern's, failing early) or drawn from the mesh, when a
    pattern file is read or written; else None."""
    from ptailor.pieces import piece_plan

    if loaded.pattern is None and not needs_pieces(options.formats):
        return None
    # the panels: the garment's cached structure, the one the adjustment reads too
    return piece_plan(loaded.garment, pattern=loaded.pattern)


@dataclass(frozen=True)
class RunInputs:
    """What a run read and checked before the adjustment: the garment, the edits' options
    (with ``--body auto``'s fitted body), the pieces' plan, the matched specification, the
    garment's measures as read, the edited drape (``--edited-drape``)."""

    loaded: LoadedGarment
    edits: EditOptions
    plan: PiecePlan | None
    body_fit: dict | None = None  # --body auto: the fit's record
    spec_match: SpecMatching | None = None  # --spec: the specification matched
    spec_note: tuple[str, ...] = ()  # --spec auto without a specification: what was looked for
    measures_before: list[dict] = field(default_factory=list)  # the garment's, as read (cm)
    edited: np.ndarray | None = None  # --edited-drape: the drape edited elsewhere
    graded: tuple | None = None  # --sizes: the sizes of a graded nest, as read


def read_inputs(
    garment: str | LoadedGarment,
    drape: str | None,
    recipe: Recipe,
    options: RunOptions,
    *,
    spec_file: str | None,
    shown: str,
) -> RunInputs:
    """Read the garment (unless ``garment`` is one read already), its specification and
    body; check them against each other (a specification of another garment, a body
    elsewhere) before any work."""
    edits = edit_options(recipe, options)
    spec = read_run_specification(spec_file, options.spec_units) if spec_file else None
    if isinstance(garment, LoadedGarment):
        loaded = garment
    else:
        loaded = load_input(garment, drape, recipe, options)
    path = garment if isinstance(garment, str) else shown
    graded = read_sizes(path, loaded, options, shown=shown)
    spec_match = None
    spec_note: tuple[str, ...] = ()
    if options.spec == "auto" and spec is None:
        spec_note = (
            f"--spec auto: no specification beside {Path(shown).name} (looked for "
            "STEM_specification.json, its shorter prefixes, specification.json)",
        )
    if spec is not None:  # matched before any work: a specification of another garment fails
        spec = spec_unit(loaded, spec)
        loaded = spec_units(loaded, spec)
        spec_match = matched_specification(loaded, spec)
    # the garment's measures; a measure the recipe expects and the garment lacks fails here
    before = measures_before(loaded.garment, recipe, shown=shown)
    body_fit = None
    if options.body == "auto":
        body, body_fit = fitted_body(loaded.garment, path=shown)
        edits = replace(edits, body=body)
    elif edits.body is not None:
        if options.drape_units is None:
            check_size_against_body(loaded.garment, edits.body, path=shown)
        check_body_placement(loaded.garment, edits.body, path=options.body)
    plan = plan_pieces(loaded, options)
    if options.seam_allowance or options.seam_allowances:
        named = options.seam_allowances
        check_seam_allowance(loaded.garment, options.seam_allowance, named, path=shown)
    edited = read_edited_drape(options.edited_drape, loaded) if options.edited_drape else None
    return RunInputs(loaded, edits, plan, body_fit, spec_match, spec_note, before, edited, graded)
