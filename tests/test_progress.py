"""The progress line: stage, iteration and residual on a terminal's stderr, nothing else."""

from __future__ import annotations

import io

import numpy as np

from ptailor.cli.progress import ProgressLine, progress_line
from ptailor.pipeline import adjustment
from ptailor.recipe import parse_recipe
from ptailor.samples import bodice

LOOSEN = "steps: [{op: loosen, region: {panels: [front]}, by: 1.5}]"


class Clock:
    def __init__(self) -> None:
        self.t = 0.0

    def __call__(self) -> float:
        return self.t


def test_the_line_waits_throttles_and_is_erased():
    clock, out = Clock(), io.StringIO()
    line = ProgressLine(out, delay=1.0, interval=0.1, clock=clock)
    line("read")
    assert out.getvalue() == ""  # a quick run shows nothing
    clock.t = 1.5
    line("flatten", 3, 2e-5)
    clock.t = 1.55
    line("flatten", 4, 1e-5)  # within the interval: not redrawn
    clock.t = 1.56
    line("write")  # a new stage is drawn at once
    line.close()
    text = out.getvalue()
    assert "ptailor: flatten, iteration 3, residual 2.0e-05" in text
    assert "iteration 4" not in text and "ptailor: write" in text
    assert text.endswith("\r\x1b[K")  # erased


def test_no_line_off_a_terminal_or_when_quiet():
    with progress_line(stream=io.StringIO()) as p:
        assert p is None

    class Tty(io.StringIO):
        def isatty(self) -> bool:
            return True

    with progress_line(stream=Tty()) as p:
        assert isinstance(p, ProgressLine)
    with progress_line(stream=Tty(), quiet=True) as p:
        assert p is None


def test_an_adjustment_reports_its_stages_and_each_iteration_and_is_unchanged_by_it():
    g = bodice()
    calls: list = []
    a = adjustment(g, parse_recipe(LOOSEN), progress=lambda *c: calls.append(c))
    b = adjustment(g, parse_recipe(LOOSEN))
    np.testing.assert_array_equal(a.result.V2, b.result.V2)
    assert calls[0] == ("edit", 0, None)
    ours = [c for c in calls if c[0] == "flatten"]
    assert [c[1] for c in ours] == list(range(1, a.result.info.iterations + 1))
    assert [c[2] for c in ours] == list(a.result.info.history)
    assert [c for c in calls if c[0] == "baseline"]  # the uniform baseline too


def test_adjust_through_the_cli_prints_no_progress_when_stderr_is_not_a_terminal(tmp_path):
    from click.testing import CliRunner

    from ptailor.cli.main import cli
    from ptailor.formats.obj import write_garment

    src = tmp_path / "g.obj"
    write_garment(src, bodice(), header=["units: cm"])
    rec = tmp_path / "r.yaml"
    rec.write_text(LOOSEN + "\n")
    r = CliRunner().invoke(cli, ["adjust", str(src), str(rec), "-o", str(tmp_path / "out")])
    assert r.exit_code == 0, r.output
    assert "\x1b[K" not in r.output and "ptailor: flatten" not in r.output
