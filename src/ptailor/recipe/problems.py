"""A recipe's problems, each with its line: the YAML reader's and the operations' rules',
and the entry points that read a recipe (:func:`parse_recipe`, :func:`load_recipe`).

The rules (:func:`ptailor.recipe.rules.validate`) are the one authority at run time. The
published JSON Schema (:mod:`ptailor.recipe.schema`, for editors) is generated from the same
checks; tests/test_validate.py holds that it never refuses a recipe the rules accept.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from ptailor import tolerances as tol
from ptailor.errors import PtailorError, RecipeError
from ptailor.recipe.loader import YamlLimitError, check_events, duplicate_keys, recipe_loader
from ptailor.recipe.rules import validate
from ptailor.recipe.spec import Recipe


def one_line(message: str, limit: int = 400) -> str:
    """``message`` on one printable line of at most ``limit`` characters."""
    out = "".join(
        c if c.isprintable() else c.encode("unicode_escape").decode("ascii") for c in message
    )
    return out if len(out) <= limit else out[: limit - 3] + "..."


@dataclass(frozen=True)
class Problem:
    """One problem in a recipe file.

    Attributes
    ----------
    source : str
        The recipe's path (``<stdin>`` for standard input).
    line : int or None
        1-based line of the offending key or value; None when the problem is the whole
        document.
    message : str
        What is wrong, starting with where (``steps[2].factor: must be > 0, got -1``).
    """

    source: str
    line: int | None
    message: str

    def __post_init__(self) -> None:
        object.__setattr__(self, "message", one_line(self.message))

    def __str__(self) -> str:
        return (
            f"{self.source}:{self.line}: {self.message}"
            if self.line
            else (f"{self.source}: {self.message}")
        )


class RecipeProblemsError(RecipeError):
    """A recipe's problems, each shown as ``FILE:LINE: WHERE: PROBLEM`` on one line.

    ``problems`` holds the messages (``steps[2].by: ...``), ``located`` the
    :class:`Problem` records with their lines.
    """

    def __init__(self, located: list[Problem], *, path: str | None = None) -> None:
        super().__init__([p.message for p in located], path=path)
        self.located = list(located)

    def __str__(self) -> str:
        return "; ".join(str(p) for p in self.located)


def parse_recipe(text: str, *, source: str = "<string>") -> Recipe:
    """Parse and validate recipe text: the same checks as ``ptailor validate``.

    Raises
    ------
    RecipeError
        Listing every problem (:func:`recipe_problems`: the YAML reader's limits and the
        operations' rules), each with its line.
    """
    probs, data = _problems_and_data(text, source=source)
    if probs:
        raise RecipeProblemsError(probs, path=source)
    recipe, rule_msgs = validate(data)
    if rule_msgs or recipe is None:  # pragma: no cover - recipe_problems saw them
        raise RecipeError(rule_msgs, path=source)
    return replace(recipe, source=source)


def read_recipe_text(path: str | Path) -> str:
    """A recipe file's text (``-``: standard input), refusing one over the size limit.

    The size is checked before anything is parsed: at most
    :data:`ptailor.tolerances.RECIPE_MAX_BYTES` plus one bytes are read.

    Raises
    ------
    PtailorError
        A missing, unreadable, too large or non-UTF-8 file.
    """
    import sys

    limit = tol.RECIPE_MAX_BYTES
    name = "<stdin>" if str(path) == "-" else str(path)
    try:
        if str(path) == "-":
            stream = getattr(sys.stdin, "buffer", None)
            raw = stream.read(limit + 1) if stream is not None else None
            if raw is None:
                txt = sys.stdin.read(limit + 1)
                raw = txt.encode("utf-8", "surrogatepass")
        else:
            with open(path, "rb") as fh:
                raw = fh.read(limit + 1)
    except FileNotFoundError:
        raise PtailorError("no such file", path=name) from None
    except OSError as exc:
        raise PtailorError(f"cannot read recipe ({exc.strerror or exc})", path=name) from None
    if len(raw) > limit:
        raise PtailorError(
            f"recipe larger than {limit} bytes (ptailor.tolerances.RECIPE_MAX_BYTES); "
            "recipes are short YAML files",
            path=name,
        )
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise PtailorError(f"not UTF-8 text (byte {exc.start}: {exc.reason})", path=name) from None
    return text.removeprefix("\ufeff")


def load_recipe(path: str | Path) -> Recipe:
    """Read and validate a recipe file (``-`` reads standard input)."""
    name = "<stdin>" if str(path) == "-" else str(path)
    return parse_recipe(read_recipe_text(path), source=name)


_WHERE = re.compile(r"^((?:[A-Za-z_]\w*)(?:\.[A-Za-z_]\w*|\[\d+\])*)(?=: )")
_TOKEN = re.compile(r"\.?([A-Za-z_]\w*)|\[(\d+)\]")
_UNKNOWN = re.compile(r"unknown (?:key|measure) '([^']+)'")


def _path_of(message: str) -> tuple[list, str | None]:
    """``steps[2].factor: ...`` -> ``(["steps", 1, "factor"], None)``; unknown keys' names."""
    path: list = []
    m = _WHERE.match(message)
    if m:
        for name, idx in _TOKEN.findall(m.group(1)):
            path.append(name if name else int(idx) - (1 if path == ["steps"] else 0))
    unknown = _UNKNOWN.search(message)
    return path, unknown.group(1) if unknown else None


def _line_of(node: Any, path: list, key: str | None, index: dict | None = None) -> int | None:
    """Line of the YAML node at ``path`` (or of ``key`` under it), as deep as it exists.

    ``index`` caches each mapping's keys (so many problems cost linear time).
    """
    import yaml

    if node is None:
        return None
    if index is None:
        index = {}
    line = node.start_mark.line + 1
    for step in [*path, *([key] if key is not None else [])]:
        if isinstance(node, yaml.MappingNode):
            keys = index.get(id(node))
            if keys is None:
                keys = {}
                for k, v in node.value:
                    keys.setdefault(str(getattr(k, "value", None)), (k, v))
                index[id(node)] = keys
            hit = keys.get(str(step))
            if hit is None:
                break
            k, node = hit
            line = (k if step == key else node).start_mark.line + 1
        elif isinstance(node, yaml.SequenceNode) and isinstance(step, int):
            if not 0 <= step < len(node.value):
                break
            node = node.value[step]
            line = node.start_mark.line + 1
        else:
            break
    return line


def _problems_and_data(text: str, *, source: str) -> tuple[list[Problem], Any]:
    """Every problem of a recipe's text (each with its line) and the document read."""
    probs, root, data = _read_document(text, source=source)
    if probs:
        return probs, None
    _, rule_msgs = validate(data)
    index: dict = {}
    found = []
    for msg in rule_msgs:
        path, key = _path_of(msg)
        found.append(Problem(source, _line_of(root, path, key, index), msg))
    return sorted(found, key=lambda p: p.line or 0), data


def _read_document(text: str, *, source: str) -> tuple[list[Problem], Any, Any]:
    """A recipe's text read as YAML with bounded work: ``(problems, root node, document)``,
    the problems (size, text, limits, syntax, duplicate keys) empty when it was read."""
    import yaml

    try:
        n = len(text.encode("utf-8"))
    except UnicodeEncodeError:
        return [Problem(source, None, "not valid text (unpaired surrogates)")], None, None
    if n > tol.RECIPE_MAX_BYTES:
        msg = (
            f"recipe larger than {tol.RECIPE_MAX_BYTES} bytes "
            "(ptailor.tolerances.RECIPE_MAX_BYTES); recipes are short YAML files"
        )
        return [Problem(source, None, msg)], None, None
    text = text.removeprefix("\ufeff")
    try:
        check_events(text)
        loader = recipe_loader()(text)
        try:
            root = loader.get_single_node()
            dups = duplicate_keys(root)
            if dups:
                return [Problem(source, ln, msg) for ln, msg in dups], None, None
            data = loader.construct_document(root) if root is not None else None
        finally:
            loader.dispose()
    except YamlLimitError as exc:
        return [Problem(source, exc.line, f"YAML: {exc.message}")], None, None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        line = mark.line + 1 if mark else None
        return [Problem(source, line, f"YAML syntax error: {problem}")], None, None
    return [], root, data


def recipe_problems(text: str, *, source: str = "<string>") -> list[Problem]:
    """Every problem of a recipe's text, each with its line: the reader's and the rules'.
    ``ptailor validate`` and every command reading a recipe use this one path.

    The YAML is read with bounded work (:data:`~ptailor.tolerances.RECIPE_MAX_BYTES`,
    ``RECIPE_MAX_DEPTH``, ``RECIPE_MAX_ALIASES``, ``RECIPE_MAX_NODES``), by the safe
    loader only; then the operations' own rules (:func:`validate`), the one authority.

    Parameters
    ----------
    text : str
    source : str
        Shown with each problem.

    Returns
    -------
    list of Problem
        Sorted by line; empty for a valid recipe. Each message is one line.
    """
    return _problems_and_data(text, source=source)[0]
