"""Writing every output format does not import matplotlib (about half a second): the PNG
is drawn with Pillow; matplotlib is only for the re-drape picture (the sim extra)."""

from __future__ import annotations

import subprocess
import sys

import pytest


@pytest.mark.slow
def test_writing_all_formats_does_not_import_matplotlib(tmp_path):
    code = (
        "import sys\n"
        "from click.testing import CliRunner\n"
        "from ptailor.cli.main import cli\n"
        f"r = CliRunner().invoke(cli, ['demo', {str(tmp_path / 'out')!r}])\n"
        "assert r.exit_code == 0, r.output\n"
        "assert 'matplotlib' not in sys.modules\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)
    for name in ("garment.obj", "pattern.dxf", "pattern.svg", "preview.png"):
        assert (tmp_path / "out" / name).is_file()
