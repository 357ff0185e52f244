"""The stitching solver: per-triangle targets glued into panels, seams kept exactly.

The one entry is :func:`stitch` (its record, :class:`StitchInfo`); the sparse
factorisation it runs on, :func:`factor`, and the :class:`SymbolicCache` that shares its
analyses across a garment's factorisations are the package's other public names (the ARAP
deformation and the edits factor their own matrices through them), with the count of a
run's factorisations (:func:`counting`, :func:`counted`, :func:`counted_so_far`,
:class:`FactorCount`) and the reuse of an edit's factors (:func:`reusing`). Code outside
the package imports these from here, never from its modules.

The modules, from the entry down:

- ``entry``: :func:`stitch` and :class:`StitchInfo`;
- ``iteration``: the local/global iterations, Anderson acceleration and its energy
  safeguard, Newton steps where they crawl (``Iterate``, ``iterate``);
- ``problem``: the stitching energy of one pattern, its factored matrix and steps
  (``Problem``, with ``PanelIndex`` and ``panel_sizes``);
- ``newton``: the Newton step (``NewtonModel``, a part of ``Problem``);
- ``seams``: the constrained seam step (``SeamConstraints``, a part of ``Problem``;
  ``SplitSolve``, ``Solved``, ``SeamStep``);
- ``count``: the factorisation count (every factorisation below notes itself there);
- ``linear``: :func:`factor`; ``cholesky`` (per-block CHOLMOD, SuperLU); ``symbolic`` (the
  analyses, :class:`SymbolicCache`, CHOLMOD's options under one lock); ``seam_factor``
  (``SeamFactor``, the seam-last factorisation); ``seam_block`` (``SeamBlock``, the seam
  block of ``A^-1``); ``small_systems`` (the seam step's small dense systems).

The modules import each other's public names only (no name with a leading underscore
crosses a module: ``tests/test_layers.py`` checks it), and a cache is kept by the object
that fills it (the problem's rotations of the last iterate, a :class:`SymbolicCache`'s
analyses): no module resets another's.
"""

from ptailor.method.solver.count import (
    FactorCount,
    counted,
    counted_so_far,
    counting,
    reusing,
)
from ptailor.method.solver.entry import StitchInfo, stitch
from ptailor.method.solver.linear import factor
from ptailor.method.solver.symbolic import SymbolicCache

__all__ = [
    "FactorCount",
    "StitchInfo",
    "SymbolicCache",
    "counted",
    "counted_so_far",
    "counting",
    "factor",
    "reusing",
    "stitch",
]
