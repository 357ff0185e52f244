"""Finding a recipe's opening (``hem``, ``{loop: 2}``) on the current drape."""

from __future__ import annotations

from typing import Any

import numpy as np

from ptailor import tolerances as tol
from ptailor.edits import EditOptions, EditState
from ptailor.edits.checks import show, with_schema
from ptailor.errors import PtailorError
from ptailor.model.openings import openings

OPENING_SCHEMA = {
    "anyOf": [
        {"type": "string", "minLength": 1},
        {
            "type": "object",
            "properties": {
                "loop": {"type": "integer", "minimum": 0, "maximum": tol.RECIPE_NUMBER_MAX}
            },
            "required": ["loop"],
            "additionalProperties": False,
        },
    ]
}


@with_schema(OPENING_SCHEMA)
def opening_spec(x: Any, where: str) -> list[str]:
    """Recipe check: an opening name or ``{loop: k}``."""
    if isinstance(x, str) and x:
        return []
    if isinstance(x, dict) and set(x) == {"loop"}:
        k = x["loop"]
        # bool is an int in Python, not in the schema (nor in a recipe): one rule for both
        if isinstance(k, int) and not isinstance(k, bool) and 0 <= k <= tol.RECIPE_NUMBER_MAX:
            return []
        return [f"{where}.loop: expected a loop number 0, 1, 2, ..., got {show(k)}"]
    return [f"{where}: expected an opening name (hem, neckline, ...) or {{loop: k}}, got {show(x)}"]


def find_opening(state: EditState, spec: Any, *, options: EditOptions) -> tuple[str, np.ndarray]:
    """The drape loop a recipe names.

    Parameters
    ----------
    state : EditState
        Openings are found on the edited drape ``state.V3``.
    spec : str or dict
        A name from :func:`ptailor.model.openings.openings`, or ``{"loop": k}`` for the k-th
        boundary loop (longest first, as ``ptailor inspect`` lists them).
    options : EditOptions
        The up and front axes.

    Returns
    -------
    name : str
    loop : (k,) int array
        Ordered drape vertex indices.

    Raises
    ------
    PtailorError
        An unknown name or loop index, listing what this garment has.
    """
    ops = openings(state.V3, state.base.F3, up=options.up, front=options.front, F2=state.base.F2)
    if isinstance(spec, dict):
        k = spec["loop"]
        if k >= len(ops):
            raise PtailorError(f"no opening {{loop: {k}}}: this garment has {len(ops)} loops")
        return ops[k].name, ops[k].loop
    for o in ops:
        if o.name == spec:
            return o.name, o.loop
    names = ", ".join(o.name for o in ops) or "none"
    raise PtailorError(f"no opening named {spec!r} on this garment (it has: {names})")
