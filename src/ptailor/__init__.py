"""ptailor: scale-preserving 2D sewing-pattern adjustment driven by 3D garment edits.

The packages, bottom up (a module imports only its own layer or lower ones; docs/architecture.md
says what each owns):

- :mod:`ptailor.errors`, :mod:`ptailor.tolerances`, :mod:`ptailor.digest`: the base;
- :mod:`ptailor.geometry`: pure array helpers over ``(V, F)`` meshes, mesh topology;
- :mod:`ptailor.model`: the garment (drape + pattern), panels, seams, openings, units;
- :mod:`ptailor.formats`: readers and writers in dispatch tables keyed by extension;
  :mod:`ptailor.method`: intrinsic scale targets and the ARAP/ASAP stitching solver;
- :mod:`ptailor.edits`, :mod:`ptailor.recipe`: recipe operations, one module each,
  registered by name, and the recipes that list them (with their JSON Schema);
- :mod:`ptailor.pipeline`: one adjustment, ``adjustment(garment, recipe) -> Adjustment``;
- :mod:`ptailor.pieces`, :mod:`ptailor.report`, :mod:`ptailor.spec`, :mod:`ptailor.verify`:
  CAD pieces and specifications through an adjustment, distortion metrics, the report and
  ``inspect``'s summary, the re-drape check;
- :mod:`ptailor.run`: the run of one garment, files in and an all-or-nothing output folder
  out; :mod:`ptailor.samples`: generated garments;
- :mod:`ptailor.batch`: one recipe over a catalogue of garments;
- :mod:`ptailor.cli`: the thin click layer, one module per command.
"""

__version__ = "0.1.0"
