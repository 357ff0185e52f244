"""Recipe operations: one module per edit, registered by name.

Each operation is an :class:`Operation` (:mod:`ptailor.edits.registry`): a parameter spec,
checked when the recipe is validated (before any garment is read), and a pure function
applying the step::

    apply(state: EditState, step: dict, *, options: EditOptions) -> EditState

Importing this package registers every operation in :data:`OPERATIONS`.
"""

from __future__ import annotations

from ptailor.edits import cut, extend, loosen, scale, scale_seam, shorten  # noqa: F401  (register)
from ptailor.edits.registry import OPERATIONS, Check, Operation, Param, register
from ptailor.edits.state import EditOptions, EditState

__all__ = [
    "OPERATIONS",
    "Check",
    "EditOptions",
    "EditState",
    "Operation",
    "Param",
    "register",
]
