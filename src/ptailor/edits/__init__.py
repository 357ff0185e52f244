"""Recipe operations: one module per edit, registered by name.

Each operation is an :class:`Operation` (:mod:`ptailor.edits.registry`): a typed step (a
frozen :class:`Step` dataclass: its parameters, their checks and defaults), built by the
recipe rules when the recipe is validated (before any garment is read), and a pure function
applying the step::

    apply(state: EditState, step: Step, *, options: EditOptions) -> EditState

The steps: :class:`ScaleStep`, :class:`ScaleSeamStep`, :class:`ShortenStep`,
:class:`ExtendStep`, :class:`CutStep`, :class:`LoosenStep` and :class:`TightenStep`.

Importing this package registers every operation in :data:`OPERATIONS`.

Modules, read top down:

- the operations, one entry point each: :mod:`~ptailor.edits.cut`,
  :mod:`~ptailor.edits.shorten`, :mod:`~ptailor.edits.extend` (a package: ``rows`` the plan
  and triangles, ``drape`` and ``pattern`` the two ways of growing them, ``chain`` offset
  chains), :mod:`~ptailor.edits.loosen` (``loosen`` and ``tighten``; a package: ``normals``,
  ``offset``, ``silhouette``, ``girth``), :mod:`~ptailor.edits.scale`,
  :mod:`~ptailor.edits.scale_seam`;
  :mod:`~ptailor.edits.mirror` applies any of them symmetrically;
- what they share: :mod:`~ptailor.edits.surgery` (split on a level set),
  :mod:`~ptailor.edits.corners` (a cut's sketch embedded in the mesh),
  :mod:`~ptailor.edits.crumbs` (pieces a cut leaves too small, dropped),
  :mod:`~ptailor.edits.sketch_lines` (sides of a sketched polyline),
  :mod:`~ptailor.edits.pattern_distance` (distances in the pattern),
  :mod:`~ptailor.edits.opening` (openings and their edges), :mod:`~ptailor.edits.region`
  (regions and axes), :mod:`~ptailor.edits.parts` (regions by part of the body, from the
  garment's structure), :mod:`~ptailor.edits.coverage` (the share of a girth a region
  holds), :mod:`~ptailor.edits.body` (keeping cloth outside a body),
  :mod:`~ptailor.edits.achieved` (what an edit achieved, for the report),
  :mod:`~ptailor.edits.asks` (steps asked in points of measure: the parameter that gives
  the asked value, the record of asked and achieved);
- the registry: :mod:`~ptailor.edits.registry` (:class:`Step`, :func:`checked`,
  :class:`Param`, :class:`Operation`, :func:`register`), :mod:`~ptailor.edits.state`
  (:class:`EditState`, :class:`EditOptions`), :mod:`~ptailor.edits.checks` (parameter checks),
  :mod:`~ptailor.edits.limits` (sizes checked at apply time).
"""

from __future__ import annotations

from ptailor.edits.cut import CutStep
from ptailor.edits.extend import ExtendStep
from ptailor.edits.loosen import LoosenStep, TightenStep
from ptailor.edits.registry import OPERATIONS, Check, Operation, Param, Step, checked, register
from ptailor.edits.scale import ScaleStep
from ptailor.edits.scale_seam import ScaleSeamStep
from ptailor.edits.shorten import ShortenStep
from ptailor.edits.state import EditOptions, EditState

__all__ = [
    "OPERATIONS",
    "Check",
    "CutStep",
    "EditOptions",
    "EditState",
    "ExtendStep",
    "LoosenStep",
    "Operation",
    "Param",
    "ScaleSeamStep",
    "ScaleStep",
    "ShortenStep",
    "Step",
    "TightenStep",
    "checked",
    "register",
]
