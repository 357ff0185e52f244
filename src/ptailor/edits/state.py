"""The garment as a recipe's steps go (:class:`EditState`), and a run's settings."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ptailor.model.frame import Frame
from ptailor.model.garment import Garment, Panel


@dataclass(frozen=True)
class EditState:
    """The garment as the recipe's steps go.

    Attributes
    ----------
    base : Garment
        The original drape and pattern (on the current topology).
    V3 : (n3, 3) float array
        The edited drape so far.
    panels : list of Panel
        ``panels(base)``.
    even : (n_panels,) bool array
        Panels every step so far moved by one affine map (or not at all): with
        ``boundary: auto`` they keep their outline shape (as-similar-as-possible).
    log : tuple of dict
        One record per applied step, for the report.
    outline_free : (n2,) bool array or None
        Pattern vertices of ``base`` whose outline is free even on ``even`` panels (an edge
        a step created, such as an extended hem); None for none.
    frozen : frozenset of str
        Names of panels whose pattern is kept: their drape's change goes into their
        intrinsic scale (a cuff that gathers more when the sleeve above it widens).
    gathers : tuple of (str, str, float)
        ``(part, other, f)``: the seams between panels ``part`` and ``other`` change their
        length ratio on purpose, the side on ``part`` ``f`` times longer relative to the
        side on ``other`` (``scale_seam``'s gather); the flattening keeps that new ratio.
    gather_bands : tuple of (str, tuple of str, float, float)
        ``(part, others, f, band)``: gathers whose extra length the pattern of ``part``
        takes in a band ``band`` wide (drape units) along its seam line with ``others``, the
        drape kept (:mod:`ptailor.method.gather`).
    """

    base: Garment
    V3: np.ndarray
    panels: list[Panel]
    even: np.ndarray
    log: tuple[dict, ...] = field(default_factory=tuple)
    outline_free: np.ndarray | None = None
    frozen: frozenset[str] = frozenset()
    gathers: tuple[tuple[str, str, float], ...] = ()
    gather_bands: tuple[tuple[str, tuple[str, ...], float, float], ...] = ()

    @property
    def frame(self) -> Frame:
        """The garment's frame (``base.frame``): the wearer's axes of every step."""
        return self.base.frame

    @property
    def structure(self):
        """``structure(base)``."""
        from ptailor.model.structure import structure

        return structure(self.base)


@dataclass(frozen=True)
class EditOptions:
    """Garment-independent settings of a run.

    Attributes
    ----------
    body : trimesh.Trimesh or None
        A watertight body in the computation unit: extended rows are pushed out of it.
    symbolic : SymbolicCache or None
        Symbolic analyses the step's factorisations share (:mod:`ptailor.method.solver`):
        a mirrored step's two applications factor matrices of one pattern.
    """

    body: Any = None
    symbolic: Any = None
