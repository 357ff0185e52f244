"""The test suite's own bookkeeping: the slow list names tests that exist."""

from __future__ import annotations

import ast
from pathlib import Path

from tests.conftest import SLOW

TESTS = Path(__file__).resolve().parent


def test_every_slow_test_named_exists():
    missing = []
    for module, names in SLOW.items():
        path = TESTS / f"{module}.py"
        if not path.exists():
            missing.append(f"{module}.py")
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        defined = {n.name for n in ast.walk(tree) if isinstance(n, ast.FunctionDef)}
        missing += [f"{module}::{n}" for n in sorted(names - defined)]
    assert missing == []
