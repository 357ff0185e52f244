"""``python -m ptailor``."""

from ptailor.cli.main import cli

cli(prog_name="ptailor")
