"""Options shared by several commands, defined once."""

from __future__ import annotations

import click

UNIT_HELP = "mm, cm, m, in, or a scaled unit such as 0.3333cm"


def garment_options(fn):
    """``--drape``, ``--pattern-units``, ``--drape-units``, ``--units``."""
    for opt in reversed(
        [
            click.option(
                "--drape",
                type=click.Path(dir_okay=False),
                default=None,
                help="OBJ holding the drape (v) when GARMENT holds only the pattern.",
            ),
            click.option(
                "--pattern-units",
                default="cm",
                show_default=True,
                help=f"Unit of the pattern coordinates: {UNIT_HELP}, or auto (a [0,1] atlas, "
                "scale estimated from the drape).",
            ),
            click.option(
                "--drape-units",
                default="cm",
                show_default=True,
                help=f"Unit of the drape: {UNIT_HELP}.",
            ),
        ]
    ):
        fn = opt(fn)
    return fn


def axes_options(fn):
    """``--up`` and ``--front``: the garment's axes, for naming openings."""
    for opt in reversed(
        [
            click.option(
                "--up",
                default=None,
                type=click.Choice(AXES),
                help="Up axis [default: the recipe's, else y].",
            ),
            click.option(
                "--front",
                default=None,
                type=click.Choice(AXES),
                help="Front axis [default: the recipe's, else z].",
            ),
        ]
    ):
        fn = opt(fn)
    return fn


AXES = ["x", "y", "z", "-x", "-y", "-z"]


def axis_vector(name: str | None, default: str) -> tuple[float, float, float]:
    """``"-y"`` -> ``(0, -1, 0)``; ``None`` gives ``default``'s vector."""
    from ptailor.recipe import axis_vector as vec

    return vec(name or default)
