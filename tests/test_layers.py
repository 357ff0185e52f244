"""The package's architecture, checked over the AST of every module in ``src/ptailor``.

Layers, bottom up; a module may import its own layer or lower ones, never a higher one, and
no import cycle exists between modules, counting imports inside functions (``import`` statements
anywhere in a file, ``TYPE_CHECKING`` blocks included). A package's ``__init__`` may import its
own submodules (to register or re-export them); they then import each other directly, never the
package back.

A closed package (``CLOSED``: the stitching solver) has one front door: its modules import no
name with a leading underscore from another module, and code outside it imports only what its
``__init__`` exports, never its modules.
"""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

SRC = Path(__file__).resolve().parents[1] / "src"

#: bottom up; a name stands for the module or package and everything below it (``ptailor.method``:
#: its ``solver`` package too)
LAYERS: tuple[tuple[str, ...], ...] = (
    ("ptailor", "ptailor.errors", "ptailor.tolerances", "ptailor.digest"),
    ("ptailor.geometry",),
    ("ptailor.model",),
    ("ptailor.measures",),
    ("ptailor.formats", "ptailor.method"),
    ("ptailor.edits", "ptailor.recipe"),
    ("ptailor.pipeline",),
    ("ptailor.pieces", "ptailor.report", "ptailor.spec", "ptailor.verify"),
    ("ptailor.run", "ptailor.samples"),
    ("ptailor.batch",),
    ("ptailor.catalogue",),
    ("ptailor.cli", "ptailor.api", "ptailor.__main__"),
)

#: pairs in one layer that must not import each other
APART = (("ptailor.formats", "ptailor.method"),)

#: packages whose modules import no private name from another module, imported from outside
#: only through their ``__init__``
CLOSED = ("ptailor.method.solver",)


def modules() -> dict[str, Path]:
    """Every module of the package by dotted name."""
    out = {}
    for p in sorted((SRC / "ptailor").rglob("*.py")):
        parts = list(p.relative_to(SRC).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = p
    return out


def _resolve(name: str, mods: dict[str, Path]) -> str | None:
    while name and name not in mods:
        name = name.rpartition(".")[0]
    return name or None


def imports(mods: dict[str, Path]) -> dict[str, set[str]]:
    """``{module: {ptailor modules it imports}}``, from every import statement in its file."""
    graph: dict[str, set[str]] = {}
    for m, p in mods.items():
        package = m if p.name == "__init__.py" else m.rpartition(".")[0]
        targets: set[str] = set()
        for node in ast.walk(ast.parse(p.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package.split(".")[: len(package.split(".")) - node.level + 1]
                    stem = ".".join(base + ([node.module] if node.module else []))
                else:
                    stem = node.module or ""
                names = [f"{stem}.{a.name}" for a in node.names]
            else:
                continue
            for n in names:
                if n == "ptailor" or n.startswith("ptailor."):
                    t = _resolve(n, mods)
                    if t and t != m:
                        targets.add(t)
        graph[m] = targets
    return graph


def private_imports(m: str, tree: ast.AST, mods: dict[str, Path]) -> list[str]:
    """``"module imports name from other"`` for each name with a leading underscore that
    module ``m`` imports from another ptailor module (``from x import _y``; a module of the
    package, ``_x``, counts too)."""
    package = m if mods[m].name == "__init__.py" else m.rpartition(".")[0]
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                stem = ".".join(base + ([node.module] if node.module else []))
            else:
                stem = node.module or ""
            pairs = [(stem, a.name) for a in node.names]
        elif isinstance(node, ast.Import):
            pairs = [tuple(a.name.rsplit(".", 1)) for a in node.names if "." in a.name]
        else:
            continue
        for stem, name in pairs:
            ours = (stem == "ptailor" or stem.startswith("ptailor.")) and stem != m
            if ours and name.startswith("_") and not name.startswith("__"):
                out.append(f"{m} imports {name} from {stem}")
    return out


def layer_of(m: str) -> tuple[int, str]:
    best = (-1, "")
    for i, names in enumerate(LAYERS):
        for n in names:
            if (m == n or m.startswith(n + ".")) and len(n) > len(best[1]):
                best = (i, n)
    return best


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module, each sorted."""
    names = sorted(set(graph) | {b for bs in graph.values() for b in bs})
    at = {n: i for i, n in enumerate(names)}
    rows = [at[a] for a, bs in graph.items() for _ in bs]
    cols = [at[b] for bs in graph.values() for b in bs]
    adjacency = coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(len(names),) * 2)
    _, label = connected_components(adjacency, directed=True, connection="strong")
    groups = [[names[i] for i in np.flatnonzero(label == k)] for k in np.unique(label)]
    return sorted(g for g in groups if len(g) > 1)


MODULES = modules()
#: every module's syntax tree, parsed once for the tests that read them all
TREES = {m: ast.parse(p.read_text(encoding="utf-8")) for m, p in MODULES.items()}
GRAPH = imports(MODULES)


def test_every_module_has_a_layer():
    assert [m for m in MODULES if layer_of(m)[0] < 0] == []


def test_no_module_imports_a_higher_layer():
    up = [
        f"{a} ({layer_of(a)[1]}) imports {b} ({layer_of(b)[1]})"
        for a, bs in sorted(GRAPH.items())
        for b in sorted(bs)
        if layer_of(b)[0] > layer_of(a)[0]
    ]
    assert up == []


@pytest.mark.parametrize(("x", "y"), APART)
def test_apart_packages_do_not_import_each_other(x, y):
    crossing = [
        f"{a} imports {b}"
        for a, bs in sorted(GRAPH.items())
        for b in sorted(bs)
        if {layer_of(a)[1], layer_of(b)[1]} == {x, y}
    ]
    assert crossing == []


def test_no_import_cycles():
    assert cycles(GRAPH) == []


def test_cycle_finder_finds_a_planted_cycle():
    g = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}, "p": {"p.x"}, "p.x": set()}
    assert cycles(g) == [["a", "b", "c"]]
    assert cycles({**g, "p.x": {"p"}}) == [["a", "b", "c"], ["p", "p.x"]]


def inside(m: str, package: str) -> bool:
    return m == package or m.startswith(package + ".")


@pytest.mark.parametrize("package", CLOSED)
def test_closed_packages_import_no_private_names(package):
    assert [m for m in MODULES if inside(m, package)]  # the package exists
    found = [
        hit
        for m, p in MODULES.items()
        if inside(m, package)
        for hit in private_imports(m, TREES[m], MODULES)
    ]
    assert found == []


def test_no_module_imports_another_modules_private_names():
    """A name one module shares with another is public (documented, no underscore): the
    house rule the closed packages started, now for every module."""
    found = [hit for m, p in MODULES.items() for hit in private_imports(m, TREES[m], MODULES)]
    assert found == []


@pytest.mark.parametrize("package", CLOSED)
def test_closed_packages_are_imported_through_their_init(package):
    through = [
        f"{a} imports {b}"
        for a, bs in sorted(GRAPH.items())
        if not inside(a, package)
        for b in sorted(bs)
        if inside(b, package) and b != package
    ]
    assert through == []


def test_private_imports_finds_planted_ones():
    mods = {"ptailor.p.a": Path("a.py"), "ptailor.p": Path("__init__.py")}
    src = (
        "from ptailor.p.b import _x, y\n"
        "from .c import _z as z\n"
        "from ptailor.p.a import _own\n"  # its own names: not another module's
        "from __future__ import annotations\n"
        "import ptailor.p._d\n"
        "def f():\n    from ptailor import _e\n"
    )
    assert private_imports("ptailor.p.a", ast.parse(src), mods) == [
        "ptailor.p.a imports _x from ptailor.p.b",
        "ptailor.p.a imports _z from ptailor.p.c",
        "ptailor.p.a imports _d from ptailor.p",
        "ptailor.p.a imports _e from ptailor",
    ]
