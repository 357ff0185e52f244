"""Points of measure as JSON: lengths in centimetres, whatever the garment's units."""

from __future__ import annotations

from collections.abc import Sequence

from ptailor.measures.measure import Measure
from ptailor.model.units import factor


def _cm(x: float, k: float) -> float:
    return round(float(x) * k, 4)


def measure_dicts(measures: Sequence[Measure], units: str) -> list[dict]:
    """Each measure as ``{"name", "kind", "drape", "pattern"}`` in cm, with ``height`` (a
    horizontal girth's level along up, in the drape's coordinates) or ``point`` and ``axis``
    (a limb girth's plane) where it has them.

    Parameters
    ----------
    measures : sequence of Measure
        In the garment's units.
    units : str
        The garment's units (``Garment.units``).

    Returns
    -------
    list of dict
    """
    k = factor(units, "cm")
    out = []
    for m in measures:
        d: dict = {
            "name": m.name,
            "kind": m.kind,
            "drape": _cm(m.drape, k),
            "pattern": _cm(m.pattern, k),
        }
        if m.height is not None:
            d["height"] = _cm(m.height, k)
        if m.point is not None and m.axis is not None:
            d["point"] = [_cm(x, k) for x in m.point]
            d["axis"] = [round(float(x), 6) for x in m.axis]
        out.append(d)
    return out


def measures_by_name(dicts: Sequence[dict]) -> dict[str, dict]:
    """``{name: dict}`` of :func:`measure_dicts`'s output."""
    return {d["name"]: d for d in dicts}
