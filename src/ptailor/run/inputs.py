"""What one run reads: the recipe, the garment (and its drape), the body, the pieces' plan."""

from __future__ import annotations

from ptailor.edits import EditOptions
from ptailor.formats.garment import LoadedGarment, load_garment
from ptailor.pieces import PiecePlan
from ptailor.recipe import Recipe, load_recipe, resolve_frame
from ptailor.run.checks import check_engine
from ptailor.run.options import RunOptions
from ptailor.run.outputs import needs_pieces


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

    fit = fit_body(
        garment.V3,
        garment.F3,
        openings=structure(garment).openings,
        frame=garment.frame,
        cm_per_unit=CM_PER.get(garment.units, 1.0),
        path=path,
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
