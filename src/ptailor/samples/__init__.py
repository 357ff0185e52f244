"""Procedurally generated garments for the demo, the tests and the benchmarks.

Every sample is a pure, deterministic function of its keyword-only options and returns a
:class:`ptailor.model.Garment` in centimetres. Conventions: y is up, z is front; pattern
(2D) triangles are counter-clockwise unless asked otherwise; seam vertices are one vertex in
the drape ``V3`` and one vertex per panel in the pattern ``V2``. Panels are quad grids, each
quad split into two triangles along alternating diagonals (a checkerboard).

The samples are *exact at their resolution*: a drape ring of ``n`` vertices is a regular
polygon whose perimeter is the requested circumference, and every pattern triangle is
congruent to its drape triangle (or stretched by exactly the stated factor), so intrinsic
scales are known in closed form.

Modules: :mod:`~ptailor.samples.grid` (the building blocks), :mod:`~ptailor.samples.tubes`
(lantern sleeve, cylinder, T-seam tube), :mod:`~ptailor.samples.cones` (cone skirt, bodice,
the cone skirt without panel names, a gored skirt, a bodice with its front in halves),
:mod:`~ptailor.samples.tee` (a flat tee with one- or two-piece sleeves or none).
:data:`SAMPLES` names the ones ``ptailor demo --sample`` offers; every sample a bundled
recipe names (its ``# sample: NAME`` line) is among them.
"""

from __future__ import annotations

from collections.abc import Callable

from ptailor.model.garment import Garment
from ptailor.samples.cones import bodice, cone_skirt, gored_skirt, halved_bodice, unnamed_skirt
from ptailor.samples.grid import PANEL_GAP
from ptailor.samples.tee import flat_tee
from ptailor.samples.tubes import cylinder, lantern_sleeve, sample_for_triangles, tseam_tube

__all__ = [
    "PANEL_GAP",
    "SAMPLES",
    "bodice",
    "cone_skirt",
    "cylinder",
    "flat_tee",
    "gored_skirt",
    "halved_bodice",
    "lantern_sleeve",
    "sample_for_triangles",
    "tseam_tube",
    "unnamed_skirt",
]

#: Samples by name, for the demo and the CLI.
SAMPLES: dict[str, Callable[..., Garment]] = {
    "lantern_sleeve": lantern_sleeve,
    "cylinder": cylinder,
    "cone_skirt": cone_skirt,
    "bodice": bodice,
    "skirt": unnamed_skirt,
}
