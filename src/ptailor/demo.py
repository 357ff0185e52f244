"""The demo's generated garments and bundled recipes."""

from __future__ import annotations

from importlib import resources

DEFAULT_RECIPES = {
    "lantern_sleeve": "wider-sleeves",
    "cone_skirt": "fuller-skirt",
    "cylinder": "wider-sleeves",
}


def bundled_recipe(name: str) -> str:
    """Text of a recipe shipped in ``ptailor/recipes`` (the project's ``recipes/``)."""
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

    from ptailor.formats.obj import write_obj
    from ptailor.method.flatten import panel_labels
    from ptailor.model.garment import panels
    from ptailor.samples import SAMPLES

    g = SAMPLES[name]()
    plist = panels(g)
    with tempfile.TemporaryDirectory() as td:
        p = Path(td) / "s.obj"
        write_obj(
            p,
            V3=g.V3,
            F3=g.F3,
            V2=g.V2,
            F2=g.F2,
            face_panel=panel_labels(plist, g.n_faces),
            panel_names=[q.name for q in plist],
            header=[f"ptailor generated sample: {name}", "units: cm"],
        )
        return p.read_text()
