"""One point of measure's value on one garment."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ptailor.measures.lines import MaterialLine


@dataclass(frozen=True)
class Measure:
    """One point of measure of one garment, in the garment's units.

    Attributes
    ----------
    name, kind : str
        See :data:`ptailor.measures.table.MEASURES`.
    drape, pattern : float
        The line's length in the drape and in the pattern (a depth: the drop).
    line : MaterialLine
        The line itself (what a picture draws).
    height : float or None
        A horizontal girth's level: the coordinate along the up axis, in the drape's
        coordinates.
    point, axis : (3,) float arrays or None
        A limb girth's plane: a point and the limb's axis (the plane's normal).
    """

    name: str
    kind: str
    drape: float
    pattern: float
    line: MaterialLine
    height: float | None = None
    point: np.ndarray | None = field(default=None, repr=False)
    axis: np.ndarray | None = field(default=None, repr=False)
