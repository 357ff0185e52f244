"""Recipes: YAML edit recipes (format 1), validated whole before any garment is read.

Modules, read bottom up:

- :mod:`~ptailor.recipe.spec`: the keys, flatten settings and axes; :class:`Recipe`;
- :mod:`~ptailor.recipe.rules`: :func:`validate`, the operations' rules over a document;
- :mod:`~ptailor.recipe.schema`: the same format as JSON Schema (``recipes/schema.json``);
- :mod:`~ptailor.recipe.loader`: the YAML reader with bounded work;
- :mod:`~ptailor.recipe.problems`: every problem with its line; :func:`parse_recipe`,
  :func:`load_recipe`, :func:`recipe_problems`.
"""

from __future__ import annotations

from ptailor.recipe.loader import recipe_loader
from ptailor.recipe.problems import (
    Problem,
    RecipeProblemsError,
    load_recipe,
    one_line,
    parse_recipe,
    read_recipe_text,
    recipe_problems,
)
from ptailor.recipe.rules import validate
from ptailor.recipe.spec import (
    AXIS_NAMES,
    DEFAULT_FRONT,
    DEFAULT_UP,
    DIRECTION_PARAMS,
    FLATTEN_PARAMS,
    LENGTH_PARAMS,
    STEP_KEYS,
    TOP_KEYS,
    Recipe,
    axes_problem,
    resolve_frame,
)

__all__ = [
    "AXIS_NAMES",
    "DEFAULT_FRONT",
    "DEFAULT_UP",
    "DIRECTION_PARAMS",
    "FLATTEN_PARAMS",
    "LENGTH_PARAMS",
    "STEP_KEYS",
    "TOP_KEYS",
    "Problem",
    "Recipe",
    "RecipeProblemsError",
    "axes_problem",
    "load_recipe",
    "one_line",
    "parse_recipe",
    "read_recipe_text",
    "recipe_loader",
    "recipe_problems",
    "resolve_frame",
    "validate",
]
