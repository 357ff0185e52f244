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
- :mod:`ptailor.cli`: the thin click layer, one module per command; :mod:`ptailor.api`: the
  Python API, re-exported here (docs/api.md).

The API (:mod:`ptailor.api`), loaded on first use so that ``import ptailor`` stays cheap::

    g = ptailor.load_garment("garment.obj", pattern_units="cm", drape_units="cm")
    a = ptailor.adjust(g, "recipe.yaml")       # a.garment, a.report
    ptailor.write(a, "out/", formats=("obj", "dxf"))
    V2 = ptailor.flatten(g, V3_edit)

Errors of the input raise :class:`PtailorError`.
"""

from __future__ import annotations

import importlib
from typing import Any

__version__ = "0.1.0"

#: the names the package lends, by module, looked up on first use (PEP 562): ``import
#: ptailor`` imports none of them, and no import statement goes up the layers
#: (:mod:`ptailor.errors` imports the version from here; tests/test_api.py)
LENT = {
    "PtailorError": "ptailor.errors",
    **dict.fromkeys(
        ("load_garment", "adjust", "write", "flatten", "as_recipe", "GarmentFile", "Adjusted"),
        "ptailor.api",
    ),
}

__all__ = ["__version__", *LENT]


def __getattr__(name: str) -> Any:
    """``ptailor.adjust``, ``ptailor.PtailorError`` and the rest of :data:`LENT`."""
    if name in LENT:
        return getattr(importlib.import_module(LENT[name]), name)
    raise AttributeError(f"module 'ptailor' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *LENT})
