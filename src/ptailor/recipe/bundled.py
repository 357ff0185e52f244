"""The recipes shipped with ptailor (``ptailor/recipes``, the project's ``recipes/``)."""

from __future__ import annotations


def bundled_recipe(name: str) -> str:
    """Text of a recipe shipped in ``ptailor/recipes`` (the project's ``recipes/``)."""
    from importlib import resources  # (9 ms: not on ``ptailor adjust``'s path)

    from ptailor.errors import PtailorError

    path = resources.files("ptailor") / "recipes" / f"{name}.yaml"
    if not path.is_file():
        known = sorted(
            p.name[:-5]
            for p in (resources.files("ptailor") / "recipes").iterdir()
            if p.name.endswith(".yaml")
        )
        raise PtailorError(f"no bundled recipe {name!r} (known: {', '.join(known)})")
    return path.read_text()
