"""``ptailor demo``.

Light at import (every command imports it through :mod:`ptailor.cli.main`): the choices are
names here; :data:`DEFAULT_RECIPES` names every generated sample of
:data:`ptailor.samples.SAMPLES` (a test holds the two equal) with the bundled recipe the demo
runs on it by default.
"""

from __future__ import annotations

import click

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


@click.command()
@click.argument("out", type=click.Path(file_okay=False))
@click.option(
    "--sample",
    default="lantern_sleeve",
    show_default=True,
    type=click.Choice(SAMPLE_NAMES),
    help="Which generated garment to use.",
)
@click.option(
    "--recipe", "recipe_name", default=None, help="Bundled recipe name (default: the sample's own)."
)
def demo(out, sample, recipe_name) -> None:
    """Generate a sample garment, adjust it with a bundled recipe, write everything to OUT.

    The default sample is the paper's lantern sleeve: a sleeve gathered into an elastic cuff
    whose 3D circumference is 0.7 of its pattern width. The bundled recipe makes it 20 %
    wider around; ptailor's cuff pattern grows by 20 %, uniform flattening shrinks it to
    0.7 of that.
    """
    import tempfile
    from pathlib import Path

    from ptailor.recipe import parse_recipe
    from ptailor.recipe.bundled import bundled_recipe
    from ptailor.report.build import summary_lines
    from ptailor.run.garment import run_garment
    from ptailor.samples.obj_text import sample_obj_text

    rname = recipe_name or DEFAULT_RECIPES[sample]
    rtext = bundled_recipe(rname)
    recipe = parse_recipe(rtext, source=f"recipes/{rname}.yaml")
    obj = sample_obj_text(sample)
    with tempfile.TemporaryDirectory() as td:
        src = Path(td) / "sample.obj"
        src.write_text(obj)
        report = run_garment(
            str(src),
            recipe,
            out,
            display_inputs={"garment": str(Path(out) / "sample.obj")},
            extra_files={"sample.obj": obj, "recipe.yaml": rtext},
        )
    click.echo(f"sample: {sample}, recipe: recipes/{rname}.yaml")
    for line in summary_lines(report):
        click.echo(line)
    click.echo("ours against uniform flattening (width x height):")
    for p in report["panels"]:
        a, b = p["size_after"], p["baseline_size_after"]
        click.echo(
            f"  {p['name']:<10} ours {a[0]:6.2f} x {a[1]:6.2f}   uniform {b[0]:6.2f} x {b[1]:6.2f}"
            f"   ({a[0] / max(b[0], 1e-12):.3f}x wider)"
        )
    files = ", ".join(["sample.obj", "recipe.yaml", *report["outputs"]])
    click.echo(f"wrote {Path(out)}/ ({files})")
