"""Writing every output format imports neither matplotlib nor ezdxf (a second of imports
between them): the PNG is drawn with Pillow, the DXF text formatted by ptailor."""

from __future__ import annotations

import subprocess
import sys


def test_writing_all_formats_imports_neither_matplotlib_nor_ezdxf(tmp_path):
    code = (
        "import sys\n"
        "from click.testing import CliRunner\n"
        "from ptailor.cli.main import cli\n"
        f"r = CliRunner().invoke(cli, ['demo', {str(tmp_path / 'out')!r}])\n"
        "assert r.exit_code == 0, r.output\n"
        "heavy = sorted(m for m in ('matplotlib', 'ezdxf') if m in sys.modules)\n"
        "assert not heavy, heavy\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)
    for name in ("garment.obj", "pattern.dxf", "pattern.svg", "preview.png"):
        assert (tmp_path / "out" / name).is_file()
