"""Pattern pieces as CAD systems exchange them: outline plus construction marks.

A :class:`Piece` is what one AAMA/ASTM DXF block holds: the cut outline, its turn points,
notches, a grain line, internal lines, drill holes and the piece text. A
:class:`PatternFile` is a whole file: pieces of one size, the sizes it grades to, its
units and style text. Coordinates are in ``PatternFile.units`` (``mm``, ``cm``, ``in``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np


def _empty_points() -> np.ndarray:
    return np.zeros((0, 2))


@dataclass(frozen=True)
class Piece:
    """One pattern piece.

    Attributes
    ----------
    name : str
        Piece name (``Piece Name:`` text; the block name without the size otherwise).
    outline : (k, 2) float array
        The closed boundary (cut line), first point not repeated.
    turn : (k,) bool array
        Outline points that are turn points (corners, layer 2); the others are curve points.
    notches : (m, 2) float array
        Notch positions on (or next to) the outline (layer 4).
    notch_angles : (m,) float array
        Notch directions in degrees, as written (0 when the file gives none).
    grain : (2, 2) float array or None
        Grain line ends (layer 7).
    internal : tuple of (j, 2) float arrays
        Internal lines (layer 8): open polylines.
    drills : (h, 2) float array
        Drill holes (layer 13).
    sew : (k, 2) float array or None
        Sew line (layer 14), closed, when the file has one.
    mirror : (2, 2) float array or None
        Mirror (fold) line ends (layer 6): the piece is half of one cut on the fold.
    quantity : int
        How many to cut in all.
    quantity_split : (2,) tuple of int or None
        ASTM D6673's ``Quantity: a,b``: ``a`` cut as drawn and ``b`` mirrored (face up /
        face down, left / right), ``quantity == a + b``; None for a plain ``Quantity: n``.
    size : str
        The size this piece is drawn in (``""`` when the file names none).
    annotations : tuple of str
        Other text of the piece (``Annotation:``, category, ...), kept as written.
    """

    name: str
    outline: np.ndarray
    turn: np.ndarray | None = None
    notches: np.ndarray = field(default_factory=_empty_points)
    notch_angles: np.ndarray = field(default_factory=lambda: np.zeros(0))
    grain: np.ndarray | None = None
    internal: tuple[np.ndarray, ...] = ()
    drills: np.ndarray = field(default_factory=_empty_points)
    sew: np.ndarray | None = None
    mirror: np.ndarray | None = None
    quantity: int = 1
    size: str = ""
    annotations: tuple[str, ...] = ()
    quantity_split: tuple[int, int] | None = None

    def __post_init__(self) -> None:
        if self.turn is None:
            object.__setattr__(self, "turn", np.zeros(len(self.outline), dtype=bool))

    def map_points(self, fn: Callable[[np.ndarray], np.ndarray]) -> Piece:
        """A new piece with ``fn`` applied to every coordinate array (``(k, 2)`` -> ``(k, 2)``).

        The one place that knows which fields hold coordinates: changes of units, layouts
        and rigid maps go through it.
        """

        def f(a: np.ndarray | None) -> np.ndarray | None:
            return None if a is None else fn(np.asarray(a, dtype=np.float64).reshape(-1, 2))

        return replace(
            self,
            outline=f(self.outline),
            notches=f(self.notches),
            grain=f(self.grain),
            internal=tuple(f(a) for a in self.internal),
            drills=f(self.drills),
            sew=f(self.sew),
            mirror=f(self.mirror),
        )

    @property
    def extent(self) -> np.ndarray:
        """Width and height of the outline's bounding box, ``(2,)``."""
        return np.ptp(self.outline, axis=0) if len(self.outline) else np.zeros(2)

    @property
    def area(self) -> float:
        """Unsigned area inside the outline (shoelace)."""
        x, y = self.outline[:, 0], self.outline[:, 1]
        return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


@dataclass(frozen=True)
class PatternFile:
    """The pieces of one size of a pattern file, and what the file says about itself.

    Attributes
    ----------
    pieces : tuple of Piece
        Pieces of the chosen size, in file order.
    units : str
        ``mm``, ``cm`` or ``in``: the unit of every coordinate.
    units_note : str
        Where ``units`` came from (``"Units: ENGLISH" in the file``, an estimate, an
        override), for the report.
    style : str
        ``Style Name:`` text (``""`` when absent).
    sizes : tuple of str
        Every size the file holds, in file order.
    size : str
        The size ``pieces`` are in.
    sample_size : str
        ``Sample Size:`` text (``""`` when absent).
    path : str
        The file read.
    units_text : str
        The units word as the file writes it (``"ENGLISH"``, ``"METRIC"``), ``""`` when
        the file has none.
    warnings : tuple of str
        What the reader noticed (a size lacking marks the sample size has, ...).
    """

    pieces: tuple[Piece, ...]
    units: str
    units_note: str = ""
    style: str = ""
    sizes: tuple[str, ...] = ()
    size: str = ""
    sample_size: str = ""
    path: str = ""
    units_text: str = ""
    warnings: tuple[str, ...] = ()
