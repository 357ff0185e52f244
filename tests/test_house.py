"""The house's size rules, held by a test: every source file at most 500 lines and every
function at most 80 (docstring included), so a file or a function that grows past them is
split along a seam of its own in the change that grows it."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "ptailor"
#: the most lines a source file may have
FILE_LINES = 500
#: the most lines a function may span (``def`` to its last line)
FUNCTION_LINES = 80

FILES = sorted(SRC.rglob("*.py"))


def long_functions(tree: ast.AST, limit: int) -> list[tuple[str, int]]:
    """``(name, lines)`` of every function (methods and nested ones too) longer than
    ``limit`` lines."""
    return [
        (n.name, n.end_lineno - n.lineno + 1)
        for n in ast.walk(tree)
        if isinstance(n, ast.FunctionDef | ast.AsyncFunctionDef)
        and n.end_lineno - n.lineno + 1 > limit
    ]


def test_the_rules_see_what_they_judge():
    assert len(FILES) > 100
    tree = ast.parse("def f():\n" + "    x = 1\n" * 90 + "def g():\n    pass\n")
    assert long_functions(tree, FUNCTION_LINES) == [("f", 91)]


@pytest.mark.parametrize("path", FILES, ids=[str(p.relative_to(SRC)) for p in FILES])
def test_files_and_functions_stay_small(path):
    text = path.read_text(encoding="utf-8")
    assert text.count("\n") <= FILE_LINES, f"{path.name}: {text.count(chr(10))} lines"
    assert long_functions(ast.parse(text), FUNCTION_LINES) == []
