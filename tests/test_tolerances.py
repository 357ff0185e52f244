"""Every tolerance is named in a tolerances module, and geometry never reads a naming rule.

Over the AST of every module in ``src/ptailor``:

- no module but the tolerances modules (:data:`TOLERANCE_MODULES`) defines a module-level
  numeric constant (an UPPER_CASE or _UPPER_CASE name bound to a number, a tuple of
  numbers, or arithmetic of numbers), except the few in :data:`NOT_TOLERANCES`, which
  are not tolerances;
- a tolerances module holds only its docstring and constants, each under a ``#:``
  comment (what it bounds, its unit and why; a constant right after another may share
  it), and no name is defined in two of them;
- ``ptailor.edits`` and ``ptailor.method`` never import ``ptailor.model.names`` nor read a
  naming threshold (``OPENING_*``, ``NAMES_*``) of the model's tolerances: changing a
  naming rule can never move a drape.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src"
PKG = SRC / "ptailor"

#: the modules that name tolerances (``docs/architecture.md`` lists them)
TOLERANCE_MODULES = (
    "ptailor/tolerances.py",
    "ptailor/model/tolerances.py",
    "ptailor/method/tolerances.py",
    "ptailor/edits/tolerances.py",
    "ptailor/verify/tolerances.py",
    "ptailor/measures/tolerances.py",
)

#: module-level numbers that are not tolerances: ``(module, name): why``
NOT_TOLERANCES = {
    **{
        ("ptailor/measures/table.py", name): "where a point of measure is taken (ASTM D5585)"
        for name in (
            "CHEST_BELOW_ARMHOLE_CM",
            "BICEP_BELOW_UNDERARM_CM",
            "HIP_BELOW_WAIST_CM",
            "THIGH_BELOW_CROTCH_CM",
        )
    },
    ("ptailor/digest.py", "_BLOCK"): "bytes read at a time while hashing: never a result",
    ("ptailor/edits/body.py", "_PAIRS_PER_CHUNK"): "memory chunking over points: not a result",
    ("ptailor/edits/pattern_distance.py", "_PAIR_CHUNK"): "memory chunking over points",
    ("ptailor/formats/obj_scan.py", "_RUNS"): "slicing or gathering lines: the same result",
    ("ptailor/formats/obj_scan.py", "_INDEX_MAX"): "the int64 range numpy parses (a fact)",
    ("ptailor/formats/footer.py", "_CHAR"): "a font's character advance (drawing)",
    ("ptailor/formats/png.py", "SUPERSAMPLE"): "antialiasing of a picture (drawing)",
    ("ptailor/formats/pdf.py", "PT"): "points per millimetre (PDF's unit: a fact)",
    ("ptailor/formats/preview.py", "ERROR_EDGES"): "the preview legend's colour bins",
    ("ptailor/verify/picture.py", "STRETCH_RANGE"): "the picture's colour scale",
    ("ptailor/catalogue/thumbnails.py", "THUMBNAIL_SIZE"): "a thumbnail's size (drawing)",
    ("ptailor/run/folder.py", "NAME_MAX"): "the file systems' name limit (a fact)",
    ("ptailor/batch/manifest.py", "NAME_MAX_BYTES"): "the file systems' name limit (a fact)",
    ("ptailor/samples/grid.py", "PANEL_GAP"): "a sample garment's dimension",
}

#: packages that move geometry, and the package of the naming rules they never read
GEOMETRY = ("ptailor.edits", "ptailor.method")
NAMING = "ptailor.model.names"

UPPER = re.compile(r"^_?[A-Z][A-Z0-9_]*$")


def _numeric(node: ast.AST) -> bool:
    """A number, a signed number, arithmetic of numbers, or a tuple of them."""
    if isinstance(node, ast.Constant):
        return isinstance(node.value, int | float) and not isinstance(node.value, bool)
    if isinstance(node, ast.UnaryOp):
        return _numeric(node.operand)
    if isinstance(node, ast.BinOp):
        return _numeric(node.left) and _numeric(node.right)
    if isinstance(node, ast.Tuple | ast.List):
        return bool(node.elts) and all(_numeric(e) for e in node.elts)
    return False


def _assigned(stmt: ast.stmt) -> tuple[list[str], ast.AST | None]:
    """The names a module-level statement binds and the value, for plain assignments."""
    if isinstance(stmt, ast.Assign):
        return [t.id for t in stmt.targets if isinstance(t, ast.Name)], stmt.value
    if isinstance(stmt, ast.AnnAssign) and isinstance(stmt.target, ast.Name):
        return [stmt.target.id], stmt.value
    return [], None


def numeric_constants(tree: ast.Module) -> list[tuple[str, int]]:
    """``(name, line)`` of each module-level UPPER_CASE name bound to a number."""
    out = []
    for stmt in tree.body:
        names, value = _assigned(stmt)
        if value is not None and _numeric(value):
            out += [(n, stmt.lineno) for n in names if UPPER.match(n)]
    return out


def _rel(p: Path) -> str:
    return p.relative_to(SRC).as_posix()


MODULES = sorted(PKG.rglob("*.py"))
TREES = {_rel(p): ast.parse(p.read_text(encoding="utf-8")) for p in MODULES}


def test_the_tolerance_modules_exist():
    assert set(TOLERANCE_MODULES) <= set(TREES)


def test_no_module_but_the_tolerances_defines_a_numeric_constant():
    found = [
        f"{rel}:{line}: {name}"
        for rel, tree in TREES.items()
        if rel not in TOLERANCE_MODULES
        for name, line in numeric_constants(tree)
        if (rel, name) not in NOT_TOLERANCES
    ]
    assert found == [], "name these in a tolerances module (or list why not in NOT_TOLERANCES)"


def test_the_exceptions_are_still_there():
    """An exception whose constant moved or went is struck off the list."""
    present = {(rel, name) for rel, tree in TREES.items() for name, _ in numeric_constants(tree)}
    assert set(NOT_TOLERANCES) - present == set()


def test_the_check_finds_a_planted_constant():
    tree = ast.parse("import x\n_LIMIT = 0.05\nBAND = (1.0, -2e-3)\nlimit = 3\nN = 2 ** 10\n")
    assert numeric_constants(tree) == [("_LIMIT", 2), ("BAND", 3), ("N", 5)]


@pytest.mark.parametrize("rel", TOLERANCE_MODULES)
def test_a_tolerances_module_holds_documented_constants_only(rel):
    tree = TREES[rel]
    lines = (SRC / rel).read_text(encoding="utf-8").splitlines()
    body = tree.body
    assert isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant)  # docstring
    bad = []
    previous = body[0]
    for stmt in body[1:]:
        names, value = _assigned(stmt)
        if not names or value is None or not all(UPPER.match(n) for n in names):
            bad.append(f"line {stmt.lineno}: not a constant")
        elif not _numeric(value):
            bad.append(f"line {stmt.lineno}: {names[0]} is not a number")
        elif not lines[stmt.lineno - 2].lstrip().startswith("#:") and (
            previous is body[0] or previous.end_lineno != stmt.lineno - 1
        ):  # a constant right after another shares its comment
            bad.append(f"line {stmt.lineno}: {names[0]} has no #: comment")
        previous = stmt
    assert bad == []


def test_no_tolerance_is_named_twice():
    seen: dict[str, str] = {}
    twice = []
    for rel in TOLERANCE_MODULES:
        for stmt in TREES[rel].body:
            for name in _assigned(stmt)[0]:
                if name in seen:
                    twice.append(f"{name}: {seen[name]} and {rel}")
                seen[name] = rel
    assert twice == []


def _module(rel: str) -> str:
    parts = list(Path(rel).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def imported_modules(rel: str, tree: ast.AST) -> set[str]:
    """Every ptailor module an import statement anywhere in the file names (``from a
    import b``: ``a`` and ``a.b``)."""
    mod = _module(rel)
    package = mod if rel.endswith("__init__.py") else mod.rpartition(".")[0]
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                stem = ".".join(base + ([node.module] if node.module else []))
            else:
                stem = node.module or ""
            out |= {stem} | {f"{stem}.{a.name}" for a in node.names}
    return {m for m in out if m == "ptailor" or m.startswith("ptailor.")}


def _geometry_modules() -> list[str]:
    return [rel for rel in TREES if _module(rel).startswith(GEOMETRY)]


def test_edits_and_method_never_import_the_naming_rules():
    found = [
        f"{rel} imports {m}"
        for rel in _geometry_modules()
        for m in sorted(imported_modules(rel, TREES[rel]))
        if m == NAMING or m.startswith(NAMING + ".")
    ]
    assert found == []


def test_edits_and_method_read_no_naming_threshold():
    found = [
        f"{rel}:{node.lineno}: {node.attr}"
        for rel in _geometry_modules()
        for node in ast.walk(TREES[rel])
        if isinstance(node, ast.Attribute) and node.attr.startswith(("OPENING_", "NAMES_"))
    ]
    assert found == []


def test_the_import_check_finds_a_planted_import():
    tree = ast.parse("def f():\n    from ptailor.model.names.roles import strip_shape\n")
    assert "ptailor.model.names.roles" in imported_modules("ptailor/edits/follow.py", tree)
    tree = ast.parse("from ..model import names\n")
    assert "ptailor.model.names" in imported_modules("ptailor/edits/follow.py", tree)
