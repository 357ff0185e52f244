"""The README's two commands: the test command is exactly what CI (``.ci/run``) runs."""

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
