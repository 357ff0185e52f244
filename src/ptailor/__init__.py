"""ptailor: scale-preserving 2D sewing-pattern adjustment driven by 3D garment edits.

The packages, bottom up (a module imports only its own layer or lower ones):

- :mod:`ptailor.errors`, :mod:`ptailor.tolerances`, :mod:`ptailor.digest`: the base;
- :mod:`ptailor.geometry`: pure array helpers over ``(V, F)`` meshes;
- :mod:`ptailor.model`: the garment (drape + pattern), panels, seams, openings, units;
- :mod:`ptailor.formats`: readers and writers in dispatch tables keyed by extension;
  :mod:`ptailor.method`: intrinsic scale targets and the ARAP/ASAP stitching solver;
- :mod:`ptailor.edits`, :mod:`ptailor.recipe`, :mod:`ptailor.schema`: recipe operations,
  one module each, registered by name, and the recipes that list them;
- :mod:`ptailor.pipeline`: one adjustment, ``adjustment(garment, recipe) -> Adjustment``;
- :mod:`ptailor.pieces`, :mod:`ptailor.report`, :mod:`ptailor.summary`: CAD pieces
  through an adjustment, distortion metrics and the report;
- :mod:`ptailor.run`: the run of one garment, files in and an output folder out;
  :mod:`ptailor.output`: all-or-nothing output folders; :mod:`ptailor.samples`,
  :mod:`ptailor.demo`: generated garments and bundled recipes;
- :mod:`ptailor.batch`: one recipe over a catalogue of garments;
- :mod:`ptailor.cli`: the thin click layer, one module per command.
"""

__version__ = "0.1.0"
