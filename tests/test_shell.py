"""The shell pipelines in cli/."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from ptailor.demo import sample_obj_text

CLI = Path(__file__).resolve().parents[1] / "cli"


@pytest.mark.skipif(shutil.which("xargs") is None, reason="needs xargs")
def test_adjust_each_runs_every_garment_and_reports_failures(tmp_path):
    good = []
    for k in range(3):
        p = tmp_path / f"g{k}.obj"
        p.write_text(sample_obj_text("lantern_sleeve"))
        good.append(p)
    bad = tmp_path / "broken.obj"
    bad.write_text("not a garment\n")
    rec = tmp_path / "r.yaml"
    rec.write_text("steps: [{op: scale, factor: 1.1}]\n")
    out = tmp_path / "out"
    env = dict(os.environ, JOBS="2", PTAILOR=f"{sys.executable} -m ptailor")
    paths = "\n".join(str(p) for p in [*good, bad]) + "\n"
    r = subprocess.run(
        [str(CLI / "adjust-each"), str(rec), str(out)],
        input=paths,
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )
    assert r.returncode == 1, r.stderr
    assert sorted(p.name for p in out.iterdir()) == ["g0", "g1", "g2"]
    for k in range(3):
        rep = json.loads((out / f"g{k}" / "report.json").read_text())
        assert rep["panels"][0]["area_after"] > rep["panels"][0]["area_before"]
    assert "broken.obj" in r.stderr and "not an OBJ" in r.stderr
