"""A generated sample as the OBJ file ``ptailor demo`` and the tests start from."""

from __future__ import annotations


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
