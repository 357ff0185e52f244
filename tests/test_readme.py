"""The README's two commands: the test command is exactly what CI (``.ci/run``) runs, after
the quick loop on the lean install."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _commands() -> list[str]:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    return re.findall(r"```sh\n(.+?)\n```", text)


def test_the_readme_starts_with_the_demo_and_the_test_commands():
    demo, tests = _commands()[:2]
    assert demo.endswith("ptailor demo out/") and "pip install ." in demo
    assert tests.endswith("python -m pytest")


def test_ci_runs_the_readme_test_command_exactly():
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8").strip().splitlines()[-1]
    assert ci == _commands()[1]


def test_ci_runs_the_quick_loop_on_the_lean_install_first():
    """The lean install (``.[test]``: no cloth engine, no matplotlib) is what a developer's
    quick loop runs on; the full suite (``.[test,sim]``) cannot see what breaks there."""
    lines = (ROOT / ".ci" / "run").read_text(encoding="utf-8").strip().splitlines()
    lean = [i for i, line in enumerate(lines) if "'.[test]'" in line and line[0] != "#"]
    assert len(lean) == 1
    assert 'python -m pytest -m "not slow" -q' in lines[lean[0]]
    assert lean[0] < len(lines) - 1  # before the full suite (the last line)
