"""``ptailor validate``."""

from __future__ import annotations

import click


@click.command()
@click.argument(
    "recipes", nargs=-1, required=True, type=click.Path(dir_okay=False, allow_dash=True)
)
@click.option("--json", "as_json", is_flag=True, help="Print the problems as JSON on stdout.")
@click.option("-q", "--quiet", is_flag=True, help="Print only the problems.")
def validate(recipes, as_json, quiet) -> None:
    """Check RECIPES against the recipe schema and the operations' own rules.

    Every problem of every recipe is printed as FILE:LINE: WHERE: PROBLEM, and the exit
    status is 0 when all are valid, 2 otherwise. '-' reads a recipe from stdin. No garment
    is read: this is the check to run in CI on every recipe change.
    """
    import json
    import sys

    from ptailor.errors import PtailorError
    from ptailor.recipe import Problem, read_recipe_text, recipe_problems

    problems: list[Problem] = []
    for path in recipes:  # a loop over files
        source = "<stdin>" if path == "-" else path
        try:
            # the size limit is checked before anything is parsed
            text = read_recipe_text(path)
        except PtailorError as exc:
            problems.append(Problem(source, None, exc.message))
            continue
        problems += recipe_problems(text, source=source)
    if as_json:
        records = [{"file": p.source, "line": p.line, "message": p.message} for p in problems]
        click.echo(json.dumps(records, indent=2))
    else:
        for p in problems:
            click.echo(str(p))
    bad = len({p.source for p in problems})
    if not quiet:
        n = len(recipes)
        if problems:
            click.echo(f"{len(problems)} problem(s) in {bad} of {n} recipe(s)", err=True)
        else:
            click.echo(f"{n} recipe(s) valid", err=True)
    if problems:
        sys.exit(2)
