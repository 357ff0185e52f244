"""Length units."""

from __future__ import annotations

#: centimetres per unit
CM_PER: dict[str, float] = {"mm": 0.1, "cm": 1.0, "m": 100.0, "in": 2.54}
UNITS = tuple(CM_PER)


def factor(src: str, dst: str) -> float:
    """Multiply a length in ``src`` units by this to get ``dst`` units."""
    return CM_PER[src] / CM_PER[dst]
