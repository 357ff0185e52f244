"""Points of measure: what a pattern maker measures on a garment, in the drape and in the
pattern (girths, lengths, depths), named from the garment's structure.

>>> from ptailor.samples import cylinder
>>> from ptailor.measures import garment_measures
>>> [(m.name, round(m.drape, 3), round(m.pattern, 3)) for m in garment_measures(cylinder())][:2]
[('waist', 30.0, 30.0), ('hip', 30.0, 30.0)]
"""

from __future__ import annotations

from ptailor.measures.dicts import measure_dicts, measures_by_name
from ptailor.measures.garment import garment_measures
from ptailor.measures.lines import MaterialLine
from ptailor.measures.measure import Measure
from ptailor.measures.table import KINDS, MEASURES, MeasureDefinition

__all__ = [
    "KINDS",
    "MEASURES",
    "MaterialLine",
    "Measure",
    "MeasureDefinition",
    "garment_measures",
    "measure_dicts",
    "measures_by_name",
]
