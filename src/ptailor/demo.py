"""The demo's generated garments and bundled recipes.

Light on purpose (no numpy, no ``importlib.resources`` at import: every command imports
it): ``ptailor demo --sample`` takes its choices from :data:`DEFAULT_RECIPES`, which names
every generated sample of :data:`ptailor.samples.SAMPLES` (a test holds the two equal) with
the bundled recipe the demo runs on it by default.
"""

from __future__ import annotations

#: sample -> its default bundled recipe (``recipes/NAME.yaml``); the keys are the samples
#: ``ptailor demo --sample`` offers, in the order it lists them
DEFAULT_RECIPES = {
    "lantern_sleeve": "wider-around",
    "cone_skirt": "v-neck-front",
    "cylinder": "wider-around",
    "bodice": "loosen-waist",
    "skirt": "fuller-skirt",
}
#: the samples ``ptailor demo --sample`` offers
SAMPLE_NAMES = tuple(DEFAULT_RECIPES)


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


def sample_obj_text(name: str) -> str:
    """A generated sample garment as OBJ text (v = drape, vt = pattern, g per panel)."""
    import tempfile
    from pathlib import Path

    from ptailor.formats.obj import write_garment
    from ptailor.samples import SAMPLES

    with tempfile.TemporaryDirectory() as td:
        p = Path(td) / "s.obj"
        write_garment(p, SAMPLES[name](), header=[f"ptailor generated sample: {name}", "units: cm"])
        return p.read_text()
