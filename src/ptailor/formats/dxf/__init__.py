"""AAMA/ASTM D6673 DXF pattern files: read pieces with their marks, write them back.

A piece is a block INSERTed in modelspace (or, in files without blocks, a closed boundary
drawn straight into modelspace). Layers follow ASTM D6673: 1 boundary (cut line) and piece
text, 2 turn points, 3 curve points, 4 and 80-83 notches, 5 grade reference, 6 mirror line,
7 grain line, 8 internal lines, 11 internal cutouts, 13 drill holes, 14 sew line,
15 annotation text, 84 and up quality-validation curves (ignored).

The writer produces DXF R12 in the flavour Gerber AccuMark imports (no TABLES section, see
:mod:`ezdxf.addons.gerber_D6673`): one block per piece, INSERTed at the origin.

Modules, read bottom up:

- :mod:`~ptailor.formats.dxf.astm`: the standard's layer codes, units and ``Quantity:`` text;
- :mod:`~ptailor.formats.dxf.document`: opening a file with ezdxf, quietly, failing closed;
- :mod:`~ptailor.formats.dxf.entities`: entities to marks (points, chained segments);
- :mod:`~ptailor.formats.dxf.assembly`: piece candidates and their assembly into pieces;
- :mod:`~ptailor.formats.dxf.grading`: marks carried from the sample size to graded sizes;
- :mod:`~ptailor.formats.dxf.units`: the file's unit, and the drape ``vt`` unit against it;
- :mod:`~ptailor.formats.dxf.reader`: :func:`read_dxf`, :func:`read_dxf_sizes` (a graded
  nest's sizes);
- :mod:`~ptailor.formats.dxf.writer`: :func:`write_dxf`, :func:`dxf_plan`, the layout.
"""

from __future__ import annotations

from ptailor.formats.dxf.astm import (
    CM_PER_UNIT,
    LAYOUTS,
    NOTCH_LAYERS,
    parse_quantity,
    quantity_text,
)
from ptailor.formats.dxf.document import printable_text
from ptailor.formats.dxf.reader import read_dxf, read_dxf_sizes
from ptailor.formats.dxf.units import CM_PER_UNIT_ALL, VT_UNIT_SLACK, reconcile_units
from ptailor.formats.dxf.writer import (
    DxfEntity,
    DxfPlan,
    dxf_plan,
    layout_nest,
    layout_pieces,
    piece_bounds,
    write_dxf,
)

__all__ = [
    "CM_PER_UNIT",
    "CM_PER_UNIT_ALL",
    "LAYOUTS",
    "NOTCH_LAYERS",
    "VT_UNIT_SLACK",
    "DxfEntity",
    "DxfPlan",
    "dxf_plan",
    "layout_nest",
    "layout_pieces",
    "parse_quantity",
    "piece_bounds",
    "printable_text",
    "quantity_text",
    "read_dxf",
    "read_dxf_sizes",
    "reconcile_units",
    "write_dxf",
]
