"""ASTM D6673 vocabulary: layer codes, units, tolerances and the ``Quantity:`` text."""

from __future__ import annotations

import re

import numpy as np

from ptailor import tolerances as tol
from ptailor.model.pieces import Piece

#: centimetres per file unit
CM_PER_UNIT: dict[str, float] = {"mm": 0.1, "cm": 1.0, "in": 2.54}
#: $INSUNITS codes the reader understands
INSUNITS = {1: "in", 4: "mm", 5: "cm"}

L_BOUNDARY, L_TURN, L_NOTCH, L_GRAIN, L_INTERNAL = "1", "2", "4", "7", "8"
L_CUTOUT, L_DRILL, L_SEW, L_TEXT = "11", "13", "14", "15"
L_MIRROR = "6"
NOTCH_LAYERS = frozenset({"4", "80", "81", "82", "83"})
LAYOUTS = ("auto", "keep", "row")


_QUANTITY = re.compile(r"^\s*(\d+)\s*(?:[,;/]\s*(\d+)\s*)?$")


def parse_quantity(text: str) -> tuple[int, tuple[int, int] | None] | None:
    """A ``Quantity:`` value: ``"2"`` -> ``(2, None)``; ASTM D6673's ``"a,b"`` (``a`` cut
    as drawn, ``b`` mirrored) -> ``(a + b, (a, b))``; anything else -> None."""
    m = _QUANTITY.match(text)
    if m is None:
        try:  # "2.0"
            f = float(text)
        except ValueError:
            return None
        ok = np.isfinite(f) and f.is_integer() and 0 <= f <= tol.DXF_QUANTITY_READ_MAX
        return (int(f), None) if ok else None
    a = int(m.group(1))
    if m.group(2) is None:
        return a, None
    b = int(m.group(2))
    return a + b, (a, b)


def quantity_text(p: Piece) -> str:
    """``Quantity:`` text of a piece: ``a,b`` when it was read so, else the count."""
    if p.quantity_split is not None and sum(p.quantity_split) == int(p.quantity):
        a, b = p.quantity_split
        return f"Quantity: {int(a)},{int(b)}"
    return f"Quantity: {int(p.quantity)}"
