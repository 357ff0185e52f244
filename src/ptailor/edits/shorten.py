"""``shorten``: remove a strip of given width along an opening, measured on the surface."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ptailor.edits import EditOptions, EditState, Param, register
from ptailor.edits.checks import number
from ptailor.edits.opening import find_opening, opening_spec
from ptailor.edits.surgery import split_keep
from ptailor.errors import PtailorError
from ptailor.report.outline import edge_offsets


@register(
    "shorten",
    {
        "opening": Param(opening_spec, required=True, doc="hem | neckline | ... | {loop: k}"),
        "by": Param(number(gt=0.0), required=True, doc="width removed, recipe units"),
    },
)
def shorten(state: EditState, step: dict, *, options: EditOptions) -> EditState:
    """Cut the garment on the iso-line of geodesic distance ``by`` from an opening.

    Distances are measured on the edited drape from the opening's curve; every triangle
    the iso-line crosses is split exactly on it and the strip is removed, in 3D and 2D.
    """
    from ptailor.method.geodesic import geodesic_distance

    name, loop = find_opening(state, step["opening"], options=options)
    by = float(step["by"])
    d = geodesic_distance(state.V3, state.base.F3, loop, limit=1.5 * by)
    used = np.unique(state.base.F3)
    if not np.any(d[used] > by):
        raise PtailorError(
            f"shorten {name} by {by:g}: the garment is nowhere farther than that from its {name}"
        )
    res = split_keep(state, d - by)
    rec = {
        "op": "shorten",
        "opening": name,
        "by": by,
        "removed_triangles": res.removed_triangles,
        "split_triangles": res.split_triangles,
        "new_edge_vertices": len(res.new_vertices3),
        "achieved": edge_offsets(state, res, loop),
    }
    return replace(res.state, log=(*state.log, rec))
