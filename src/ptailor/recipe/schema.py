"""The recipe format as JSON Schema, generated from the operations' registry.

``recipes/schema.json`` is this module's output (``python -m ptailor.recipe.schema >
recipes/schema.json``; a test keeps the two equal). Editors that speak JSON Schema (VS Code's
YAML extension, JetBrains, ...) complete and check recipes with it: put
``# yaml-language-server: $schema=schema.json`` (or the file's URL) on a recipe's first line.
"""

from __future__ import annotations

import json
from typing import Any

from ptailor.edits import OPERATIONS
from ptailor.edits.opening import OPENING_SCHEMA
from ptailor.edits.registry import COMMON_DOCS
from ptailor.measures.table import MEASURES
from ptailor.model.units import UNITS
from ptailor.recipe.expect import ON
from ptailor.recipe.spec import AXIS_NAMES, FLATTEN_PARAMS, STEP_KEYS

SCHEMA_ID = "https://ptailor.dev/schema/recipe-1.json"


def _param_schema(param: Any) -> dict:
    fragment = dict(getattr(param.check, "schema", {}))
    if param.doc:
        fragment["description"] = param.doc
    if param.default is not None:
        fragment["default"] = param.default
    return fragment


def recipe_schema() -> dict:
    """JSON Schema (draft 2020-12) of recipe format 1.

    Returns
    -------
    dict
        Top-level keys, one ``if op == name then ...`` branch per registered operation
        (its parameters, which are required, no others), and the flatten settings.
    """
    branches = []
    for name, op in sorted(OPERATIONS.items()):
        props: dict[str, Any] = {"op": {"const": name}}
        for key, prm in op.params.items():
            props[key] = _param_schema(prm)
        for key in STEP_KEYS:
            props.setdefault(key, {"type": "boolean", "description": COMMON_DOCS[key]})
        required = ["op", *(k for k, prm in op.params.items() if prm.required)]
        then = {"properties": props, "required": required, "additionalProperties": False}
        if op.doc:
            then["description"] = op.doc
        branches.append({"if": {"properties": {"op": {"const": name}}}, "then": then})
    flatten = {
        key: dict(getattr(check, "schema", {}), default=default)
        for key, (check, default) in FLATTEN_PARAMS.items()
    }
    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "$id": SCHEMA_ID,
        "title": "ptailor edit recipe (format 1)",
        "description": "3D edits applied to a garment's drape, then how its pattern is adjusted.",
        "type": "object",
        "properties": {
            "format": {"const": 1, "description": "recipe format version"},
            "units": {"enum": list(UNITS), "default": "cm", "description": "length unit"},
            "up": {"enum": list(AXIS_NAMES), "description": "the garment's up axis"},
            "front": {"enum": list(AXIS_NAMES), "description": "the garment's front axis"},
            "symmetric": {
                "type": "boolean",
                "default": False,
                "description": "apply every step with its mirror image across the body's "
                "sagittal plane",
            },
            "steps": {
                "type": ["array", "null"],
                "items": {
                    "type": "object",
                    "properties": {"op": {"enum": sorted(OPERATIONS)}},
                    "required": ["op"],
                    "allOf": branches,
                },
            },
            "flatten": {
                "type": ["object", "null"],
                "properties": flatten,
                "additionalProperties": False,
            },
            "expect": _expect_schema(),
        },
        "additionalProperties": False,
        "$defs": {"opening": OPENING_SCHEMA},
    }


def _expect_schema() -> dict:
    """``expect:``: measure names (:data:`ptailor.measures.MEASURES`) to ``{by or to, tol,
    on, optional}`` (:mod:`ptailor.recipe.expect`)."""
    length_or_percent = {
        "oneOf": [
            {"type": "number"},
            {"type": "string", "pattern": r"^\s*[-+]?[0-9.eE+-]+\s*%\s*$"},
        ]
    }
    one = {
        "type": "object",
        "properties": {
            "by": {**length_or_percent, "description": "change asked: a length in the recipe's "
                   "units, or N% of the measure before"},
            "to": {"type": "number", "exclusiveMinimum": 0,
                   "description": "length asked, in the recipe's units"},
            "tol": {**length_or_percent, "description": "how far the result may be from the "
                    "target: a length, or N% of the target (default 0.5 cm)"},
            "on": {"enum": list(ON), "default": "both",
                   "description": "judged in the drape, the pattern or both"},
            "optional": {"type": "boolean", "default": False,
                         "description": "a garment without the measure skips it (recorded "
                         "as skipped) instead of being refused"},
        },
        "oneOf": [{"required": ["by"]}, {"required": ["to"]}],
        "additionalProperties": False,
    }  # fmt: skip
    return {
        "type": ["object", "null"],
        "description": "points of measure the result must reach (checked after the run: a "
        "miss is exit status 3)",
        "propertyNames": {"enum": list(MEASURES)},
        "additionalProperties": one,
    }


def schema_text() -> str:
    """``recipe_schema()`` as the indented JSON written to ``recipes/schema.json``."""
    return json.dumps(recipe_schema(), indent=2) + "\n"


if __name__ == "__main__":
    print(schema_text(), end="")
