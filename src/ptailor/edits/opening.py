"""Finding a recipe's opening (``hem``, ``{loop: 2}``) on the current drape, and its edges."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ptailor import tolerances as tol
from ptailor.edits.checks import show, with_schema
from ptailor.edits.state import EditState
from ptailor.errors import AbsentError, PtailorError
from ptailor.geometry.topology import half_edges
from ptailor.model.openings import Opening, openings
from ptailor.model.structure import structure

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


def drape_openings(state: EditState) -> list[Opening]:
    """The openings of the edited drape ``state.V3``.

    While the drape is still the garment's own (a recipe's first step), they are the
    garment's, computed once for it (:func:`ptailor.model.structure.structure`).
    """
    g = state.base
    if state.V3 is g.V3 or np.array_equal(state.V3, g.V3):
        return structure(g).openings
    return openings(state.V3, g.F3, frame=g.frame, F2=g.F2)


def find_opening(state: EditState, spec: Any) -> tuple[str, np.ndarray]:
    """The drape loop a recipe names.

    Parameters
    ----------
    state : EditState
        Openings are found on the edited drape ``state.V3``.
    spec : str or dict
        A name from :func:`ptailor.model.openings.openings`, or ``{"loop": k}`` for the k-th
        boundary loop (longest first, as ``ptailor inspect`` lists them), named under
        the garment's frame.

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
    ops = drape_openings(state)
    if isinstance(spec, dict):
        k = spec["loop"]
        if k >= len(ops):
            raise AbsentError(f"no opening {{loop: {k}}}: this garment has {len(ops)} loops")
        return ops[k].name, ops[k].loop
    for o in ops:
        if o.name == spec:
            return o.name, o.loop
    names = ", ".join(o.name for o in ops) or "none"
    raise AbsentError(f"no opening named {spec!r} on this garment (it has: {names})")


@dataclass(frozen=True)
class OpeningEdges:
    """The boundary edges of one opening, with their triangles.

    Attributes
    ----------
    a3, b3 : (k,) int arrays
        Drape ends of edge ``i``: ``loop[i]`` and ``loop[i + 1]`` (half-edge order, so the
        triangle is on the left of ``a3 -> b3``).
    a2, b2 : (k,) int arrays
        The same ends in the pattern (the triangle's pattern corners).
    face : (k,) int array
        The triangle of each edge.
    opposite : (k,) int array
        Drape vertex of that triangle opposite the edge.
    """

    a3: np.ndarray
    b3: np.ndarray
    a2: np.ndarray
    b2: np.ndarray
    face: np.ndarray
    opposite: np.ndarray


def opening_edges(F3: np.ndarray, F2: np.ndarray, loop: np.ndarray) -> OpeningEdges:
    """Triangles and pattern edges along an ordered boundary loop.

    Parameters
    ----------
    F3, F2 : (m, 3) int arrays
        Drape and pattern triangles.
    loop : (k,) int array
        Ordered drape vertices of a boundary loop, in either direction.

    Returns
    -------
    OpeningEdges

    Raises
    ------
    PtailorError
        When consecutive loop vertices are not a boundary edge of ``F3``.
    """
    loop = np.asarray(loop, dtype=np.int64)
    h3 = half_edges(F3)
    n = int(max(F3.max(initial=0), loop.max(initial=0))) + 1
    keys = h3[:, 0] * n + h3[:, 1]
    order = np.argsort(keys, kind="stable")
    sorted_keys = keys[order]

    def lookup(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        q = a * n + b
        pos = np.minimum(np.searchsorted(sorted_keys, q), len(sorted_keys) - 1)
        return np.where(sorted_keys[pos] == q, order[pos], -1)

    a, b = loop, np.roll(loop, -1)
    he = lookup(a, b)
    if np.any(he < 0):  # the loop was given against its half-edges: walk it the other way
        loop = loop[::-1]
        a, b = loop, np.roll(loop, -1)
        he = lookup(a, b)
    if len(loop) < 3 or np.any(he < 0) or np.any(lookup(b, a) >= 0):
        raise PtailorError("the opening is not a boundary loop of the drape")
    f, c = he // 3, he % 3
    return OpeningEdges(
        a3=a,
        b3=b,
        a2=F2[f, c],
        b2=F2[f, (c + 1) % 3],
        face=f,
        opposite=F3[f, (c + 2) % 3],
    )
