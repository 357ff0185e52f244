"""Reading a recipe's YAML with bounded work: the safe loader, one linear pass over
its events (depth, aliases, expanded size) and duplicate keys.
"""

from __future__ import annotations

import re
from typing import Any

from ptailor import tolerances as tol
from ptailor.edits.checks import (
    show,
)


class YamlLimitError(Exception):
    """A recipe's YAML over one of the reader's limits (a problem with its line)."""

    def __init__(self, line: int | None, message: str) -> None:
        super().__init__(message)
        self.line = line
        self.message = message


def _loader_class():
    """The recipe loader: libyaml's safe loader when available (linear, fast), with the
    constructors that can raise or run away (long ints, bad dates, explicit tags on the
    wrong scalars) turned into YAML errors with their line. Only safe tags are known:
    ``!!python/object`` and every other unknown tag stays an error."""
    import yaml

    base = getattr(yaml, "CSafeLoader", None) or yaml.SafeLoader

    class RecipeLoader(base):  # type: ignore[misc, valid-type]
        def construct_object(self, node, deep=False):
            try:
                return super().construct_object(node, deep=deep)
            except yaml.YAMLError:
                raise
            except (ValueError, TypeError, OverflowError, ArithmeticError) as exc:
                raise yaml.constructor.ConstructorError(
                    None,
                    None,
                    f"cannot read the value {show(node.value)} ({exc})",
                    node.start_mark,
                ) from None

        def construct_yaml_int(self, node):
            value = str(node.value)
            if len(value) > tol.RECIPE_MAX_NUMBER_CHARS:
                raise yaml.constructor.ConstructorError(
                    None,
                    None,
                    f"a number of {len(value)} characters (at most "
                    f"{tol.RECIPE_MAX_NUMBER_CHARS}: ptailor.tolerances.RECIPE_MAX_NUMBER_CHARS)",
                    node.start_mark,
                )
            return super().construct_yaml_int(node)

        def construct_yaml_float(self, node):
            value = str(node.value)
            if ":" in value and len(value) > tol.RECIPE_MAX_NUMBER_CHARS:
                raise yaml.constructor.ConstructorError(
                    None, None, f"a number of {len(value)} characters", node.start_mark
                )
            return super().construct_yaml_float(node)

    # YAML 1.2 (and JSON, and the schema's editors) read only true and false as booleans;
    # YAML 1.1 also yes, no, on, off: a recipe's `on: pattern` keeps its key `on`.
    bool_tag = "tag:yaml.org,2002:bool"
    RecipeLoader.yaml_implicit_resolvers = {
        first: [(tag, rx) for tag, rx in resolvers if tag != bool_tag]
        for first, resolvers in base.yaml_implicit_resolvers.items()
    }
    RecipeLoader.add_implicit_resolver(
        bool_tag, re.compile(r"^(?:true|True|TRUE|false|False|FALSE)$"), list("tTfF")
    )
    # YAML 1.2 (and JSON, and the schema's editors) read 1e5 as a number; YAML 1.1 as a
    # string: a recipe's 1e-3 or 1e300 is a number here, and checked as one.
    RecipeLoader.add_implicit_resolver(
        "tag:yaml.org,2002:float",
        re.compile(r"^[-+]?(?:[0-9][0-9_]*)(?:\.[0-9_]*)?[eE][-+]?[0-9]+$"),
        list("-+0123456789"),
    )
    RecipeLoader.add_constructor("tag:yaml.org,2002:int", RecipeLoader.construct_yaml_int)
    RecipeLoader.add_constructor("tag:yaml.org,2002:float", RecipeLoader.construct_yaml_float)
    return RecipeLoader


_LOADER = None


def recipe_loader():
    """The YAML loader class recipes are read with (built once)."""
    global _LOADER
    if _LOADER is None:
        _LOADER = _loader_class()
    return _LOADER


def check_events(text: str) -> None:
    """One linear pass over the YAML events, before anything is composed: nesting depth,
    the number of aliases, and the document's size with every alias expanded.

    Raises
    ------
    YamlLimitError
        Over :data:`~ptailor.tolerances.RECIPE_MAX_DEPTH`,
        :data:`~ptailor.tolerances.RECIPE_MAX_ALIASES` or
        :data:`~ptailor.tolerances.RECIPE_MAX_NODES`.
    yaml.YAMLError
        A syntax error.
    """
    import yaml

    ev = yaml.events
    count = _EventCount()
    loader = recipe_loader()(text)
    try:
        while loader.check_event():
            e = loader.get_event()
            if isinstance(e, ev.AliasEvent):
                count.alias(e)
            elif isinstance(e, ev.ScalarEvent):
                count.scalar(e)
            elif isinstance(e, (ev.SequenceStartEvent, ev.MappingStartEvent)):
                count.start(e)
            elif isinstance(e, (ev.SequenceEndEvent, ev.MappingEndEvent)):
                count.end()
    finally:
        loader.dispose()


def _line(e: Any) -> int | None:
    """An event's 1-based line (None when it has no mark)."""
    return e.start_mark.line + 1 if e.start_mark is not None else None


class _EventCount:
    """The running counts of :func:`check_events`: the open collections (each as its
    expanded size so far and its anchor), each closed anchor's expanded size, the aliases
    and the values seen with every alias expanded."""

    def __init__(self) -> None:
        self.stack: list[list] = []  # [expanded size, anchor] of each open collection
        self.sizes: dict[str, int] = {}  # anchor -> expanded size of its (closed) node
        self.aliases = 0
        self.total = 0

    def bump(self, n: int, e: Any) -> None:
        """Count ``n`` values at event ``e``, in its collection and in the document."""
        if self.stack:
            self.stack[-1][0] += n
        self.total += n
        if self.total > tol.RECIPE_MAX_NODES:
            raise YamlLimitError(
                _line(e),
                f"the document holds more than {tol.RECIPE_MAX_NODES} values with its "
                "aliases expanded (ptailor.tolerances.RECIPE_MAX_NODES)",
            )

    def alias(self, e: Any) -> None:
        """An alias: counted, and its anchor's node counted again in full."""
        self.aliases += 1
        if self.aliases > tol.RECIPE_MAX_ALIASES:
            raise YamlLimitError(
                _line(e),
                f"more than {tol.RECIPE_MAX_ALIASES} YAML aliases "
                "(ptailor.tolerances.RECIPE_MAX_ALIASES)",
            )
        if e.anchor not in self.sizes:
            if any(a == e.anchor for _, a in self.stack):
                raise YamlLimitError(
                    _line(e), f"the alias *{e.anchor} refers to a node that contains it"
                )
            raise YamlLimitError(_line(e), f"the alias *{e.anchor} has no anchor before it")
        self.bump(self.sizes[e.anchor], e)  # the expanded copy counts in full

    def scalar(self, e: Any) -> None:
        """A scalar: one value."""
        if e.anchor is not None:
            self.sizes[e.anchor] = 1
        self.bump(1, e)

    def start(self, e: Any) -> None:
        """A sequence or mapping opens: one value in its parent, one level deeper."""
        if len(self.stack) >= tol.RECIPE_MAX_DEPTH:
            raise YamlLimitError(
                _line(e),
                f"nested more than {tol.RECIPE_MAX_DEPTH} deep "
                "(ptailor.tolerances.RECIPE_MAX_DEPTH)",
            )
        self.bump(1, e)  # the collection itself, counted in its parent
        self.stack.append([1, e.anchor])

    def end(self) -> None:
        """A sequence or mapping closes: its size is its anchor's and joins its parent's."""
        n, anchor = self.stack.pop()
        if anchor is not None:
            self.sizes[anchor] = n
        if self.stack:
            self.stack[-1][0] += n - 1  # its contents (itself was counted at its start)


def duplicate_keys(root: Any) -> list[tuple[int, str]]:
    """``(line, message)`` for each key written twice in one mapping (YAML keeps the last
    silently; a recipe with ``by`` twice is ambiguous). Each node is visited once."""
    import yaml

    out = []
    seen: set[int] = set()
    todo = [root]
    while todo:
        node = todo.pop()
        if node is None or id(node) in seen:
            continue
        seen.add(id(node))
        if isinstance(node, yaml.MappingNode):
            first: dict[tuple, int] = {}
            for k, v in node.value:
                if isinstance(k, yaml.ScalarNode) and k.value != "<<":
                    ln = k.start_mark.line + 1
                    key = (k.tag, k.value)
                    if key in first:
                        out.append(
                            (ln, f"duplicate key {show(k.value)} (first on line {first[key]})")
                        )
                    else:
                        first[key] = ln
                todo += [k, v]
        elif isinstance(node, yaml.SequenceNode):
            todo += node.value
    return out
