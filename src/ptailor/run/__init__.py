"""The run of one garment: from files to an output folder (``adjust``, ``demo``, batch).

Modules, read top down:

- :mod:`~ptailor.run.garment`: :func:`run_garment`, the run itself (:func:`staged_run`: the
  same, its report judged before the folder is put in place);
- :mod:`~ptailor.run.inputs`: the recipe, the garment, the body, the pieces' plan;
- :mod:`~ptailor.run.checks`: guards (options, seam allowance, finite results) and warnings;
- :mod:`~ptailor.run.sections`: the report sections the run adds (units, pattern pieces);
- :mod:`~ptailor.run.outputs`: what each output format writes, through the formats' tables;
- :mod:`~ptailor.run.options`: :class:`RunOptions`, the frozen options of one run.
"""

from __future__ import annotations

from ptailor.run.garment import run_garment, staged_run
from ptailor.run.options import RunOptions
from ptailor.run.outputs import FORMATS, OutputContext, write_outputs

__all__ = ["FORMATS", "OutputContext", "RunOptions", "run_garment", "staged_run", "write_outputs"]
