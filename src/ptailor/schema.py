"""The recipe format as JSON Schema: :mod:`ptailor.recipe.schema`, runnable.

``python -m ptailor.schema > recipes/schema.json`` writes the published schema (a test
keeps the two equal).
"""

from __future__ import annotations

from ptailor.recipe.schema import SCHEMA_ID, recipe_schema, schema_text

__all__ = ["SCHEMA_ID", "recipe_schema", "schema_text"]

if __name__ == "__main__":
    print(schema_text(), end="")
