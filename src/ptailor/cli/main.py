"""``ptailor``: the command group. Library errors map to exit status 2, here and only here."""

from __future__ import annotations

import click

from ptailor import __version__
from ptailor.cli.adjust import adjust
from ptailor.cli.batch import batch
from ptailor.cli.demo import demo
from ptailor.cli.inspect import inspect
from ptailor.cli.validate import validate


class _Group(click.Group):
    def invoke(self, ctx: click.Context):
        from ptailor.errors import PtailorError

        try:
            return super().invoke(ctx)
        except PtailorError as exc:
            click.echo(f"ptailor: error: {exc}", err=True)
            ctx.exit(2)


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="ptailor")
def cli() -> None:
    """Adjust sewing patterns after garments are edited in 3D.

    ptailor keeps what the designer built into a pattern (elastic cuffs, gathers, straight
    edges, matching seams) while the drape is scaled, shortened, extended or cut, following
    Qi & Igarashi's PerfectTailor (scale-preserving flattening).
    """


cli.add_command(adjust)
cli.add_command(inspect)
cli.add_command(demo)
cli.add_command(batch)
cli.add_command(validate)
