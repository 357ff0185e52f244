"""Typed recipe steps: one frozen dataclass per operation, built once by the recipe rules.

Edits read a step's attributes (never a mapping's keys), and only the attributes their step
type and :class:`~ptailor.edits.EditOptions` have: checked here over the AST of every module
under ``edits/``, the check that would have caught ``extend`` reading
``options.clearance`` (a field :class:`EditOptions` never had).
"""

from __future__ import annotations

import ast
import dataclasses
from pathlib import Path

import pytest

import ptailor.edits as edits
from ptailor.catalogue.rows import recipe_text
from ptailor.edits import (
    OPERATIONS,
    CutStep,
    EditOptions,
    ExtendStep,
    LoosenStep,
    ScaleSeamStep,
    ScaleStep,
    ShortenStep,
    Step,
    TightenStep,
)
from ptailor.edits.registry import COMMON_FIELDS
from ptailor.recipe import Recipe, parse_recipe

EDITS = Path(edits.__file__).parent
OPTION_FIELDS = {f.name for f in dataclasses.fields(EditOptions)}


def step_types() -> dict[str, type[Step]]:
    """Every step type by class name (the names annotations use)."""
    return {t.__name__: t for t in (Step, *(op.step for op in OPERATIONS.values()))}


def test_every_operation_has_its_own_step_type():
    assert set(OPERATIONS) == {
        "cut", "extend", "loosen", "scale", "scale_seam", "shorten", "tighten",
    }  # fmt: skip
    for name, op in OPERATIONS.items():
        assert op.step.op == name and op.name == name
        assert dataclasses.is_dataclass(op.step) and op.step.__dataclass_params__.frozen
        # every field is a recipe parameter (checked), or a key every step has
        for f in dataclasses.fields(op.step):
            assert "check" in f.metadata or f.name in COMMON_FIELDS, f"{name}.{f.name}"


def test_the_recipe_builds_typed_steps_with_the_fields_defaults():
    r = parse_recipe(
        "steps:\n"
        "  - {op: shorten, opening: hem, by: 5}\n"
        "  - {op: scale, factor: 1.1}\n"
        "  - {op: tighten, by: 1}\n"
        "  - {op: scale_seam, seam: [cuff, sleeve], part: sleeve, factor: 1.2}\n"
    )
    shorten, scale, tighten, seam = r.steps
    assert isinstance(r.steps, tuple)
    assert shorten == ShortenStep(opening="hem", by=5)
    assert shorten.measure == "drape"  # the field's default, given nowhere else
    assert scale == ScaleStep(factor=1.1)
    assert (scale.region, scale.direction, scale.axis) == ("all", "uniform", "auto")
    assert type(tighten) is TightenStep and tighten.op == "tighten"
    assert tighten.region is None and tighten.offset_region == "all"
    assert seam.fix == [] and seam.fix is not ScaleSeamStep(seam="x", part="x", factor=1).fix


def test_parameter_defaults_are_the_fields_defaults():
    """The rules and the JSON Schema read each parameter's default off its field."""
    for op in OPERATIONS.values():
        made = {f.name: f for f in dataclasses.fields(op.step)}
        for key, prm in op.params.items():
            f = made[key]
            if prm.required:
                assert f.default is dataclasses.MISSING
                assert f.default_factory is dataclasses.MISSING
            elif f.default_factory is not dataclasses.MISSING:
                assert prm.default == f.default_factory()
            else:
                assert prm.default == f.default
    assert OPERATIONS["cut"].params["view"].default == "front"
    assert OPERATIONS["extend"].params["measure"].default == "drape"
    assert OPERATIONS["shorten"].params["opening"].required
    # by or measure + to: the whole-step check asks for one (test_asks.py)
    assert not OPERATIONS["shorten"].params["by"].required


def test_steps_are_frozen():
    step = ShortenStep(opening="hem", by=5)
    with pytest.raises(dataclasses.FrozenInstanceError):
        step.by = 6  # type: ignore[misc]


def test_to_dict_is_the_validated_mapping():
    r = parse_recipe(
        "symmetric: true\nsteps:\n"
        "  - {op: cut, view: front, sketch: [[10, 0], [10, 60]], remove: right}\n"
        "  - {op: loosen, by: 2}\n"
        "  - {op: extend, opening: {loop: 1}, by: 3, measure: pattern}\n"
    )
    cut, loosen, extend = (s.to_dict() for s in r.steps)
    assert list(cut) == [
        "op", "plane", "view", "sketch", "remove", "layers", "origin", "symmetric",
    ]  # fmt: skip
    assert cut["symmetric"] is True and cut["sketch"] == [[10, 0], [10, 60]]
    assert loosen == {
        "op": "loosen", "region": None, "by": 2, "view": None, "silhouette": None,
        "symmetric": True,
    }  # fmt: skip
    assert extend == {
        "op": "extend", "opening": {"loop": 1}, "by": 3, "clearance": None,
        "measure": "pattern", "symmetric": True,
    }  # fmt: skip
    # the mapping gives the same step back
    for step in r.steps:
        d = step.to_dict()
        assert OPERATIONS[d.pop("op")].step(**d) == step


def test_the_recipe_yaml_the_catalogue_writes_is_unchanged():
    """Byte for byte what the catalogue wrote when steps were mappings: values as written
    (ints stay ints), a mapping shared by a YAML alias written twice, not as an anchor."""
    r = parse_recipe(
        "steps:\n"
        "  - {op: scale, region: &s {panels: [sleeve]}, factor: 2}\n"
        "  - {op: shorten, opening: hem, by: 2, symmetric: true}\n"
        "  - {op: scale, region: *s, factor: 1.5}\n"
    )
    assert recipe_text(r) == (
        "units: cm\nsteps:\n"
        "- op: scale\n  region:\n    panels:\n    - sleeve\n  direction: uniform\n"
        "  axis: auto\n  factor: 2\n  symmetric: false\n"
        "- op: shorten\n  opening: hem\n  by: 2\n  measure: drape\n  symmetric: true\n"
        "- op: scale\n  region:\n    panels:\n    - sleeve\n  direction: uniform\n"
        "  axis: auto\n  factor: 1.5\n  symmetric: false\n"
        "flatten:\n  method: scale-preserving\n  intrinsic: polar\n  boundary: auto\n"
        "  seams: ease\n  w_pin: 1000.0\n  w_asap: 1000.0\n  max_iter: 100\n"
        "up: null\nfront: null\nsymmetric: false\n"
    )


def test_a_recipe_built_in_python_holds_a_tuple_of_steps():
    r = Recipe(
        steps=[ScaleStep(factor=1.1), CutStep(plane={"point": [0, 0, 0], "normal": [0, 1, 0]})]
    )
    assert isinstance(r.steps, tuple) and r.to_dict()["steps"][1]["op"] == "cut"


def test_a_step_type_checks_its_form_on_the_typed_step():
    """Whole-step checks (cut's one tool, loosen's one form) take the typed step."""
    assert OPERATIONS["cut"].check(CutStep(), "steps[1]") == [
        "steps[1]: cut needs exactly one of 'plane' or 'sketch'"
    ]
    assert OPERATIONS["tighten"].check(TightenStep(by=1.0, view="front"), "s") == [
        "s: 'view' goes with 'silhouette', not with 'by'"
    ]
    assert OPERATIONS["loosen"].check(LoosenStep(silhouette=[[0, 0], [0, 1]]), "s") == []
    assert ExtendStep(opening="hem", by=1, clearance=0.3).clearance_for(10.0) == 0.3


# ---------------------------------------------------------------------------------------
# edits read typed steps and the options' fields only (over the AST)
# ---------------------------------------------------------------------------------------


def _annotated(fn: ast.FunctionDef | ast.AsyncFunctionDef) -> dict[str, str]:
    """A function's parameters annotated with a step type or EditOptions: name -> type."""
    args = [*fn.args.posonlyargs, *fn.args.args, *fn.args.kwonlyargs]
    out = {}
    for a in args:
        ann = a.annotation
        text = ann.value if isinstance(ann, ast.Constant) else ast.unparse(ann) if ann else ""
        if text == "EditOptions" or text in step_types():
            out[a.arg] = text
    return out


def _allowed(type_name: str) -> set[str]:
    """What a parameter of that type may be read for (a plain ``Step``: what any step type
    has, as code narrows it with ``isinstance``)."""
    if type_name == "EditOptions":
        return OPTION_FIELDS
    types = list(step_types().values()) if type_name == "Step" else [step_types()[type_name]]
    return {
        n
        for t in types
        for n in [*(f.name for f in dataclasses.fields(t)), *dir(t)]
        if not n.startswith("__")
    }


def _misreads(path: Path) -> list[str]:
    """Every read of a step or options parameter that its type does not have: an unknown
    attribute (``.get`` included), a subscript, or ``getattr(...)`` (which hides a missing
    one)."""
    bad = []
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for fn in ast.walk(tree):
        if not isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        typed = _annotated(fn)
        for node in ast.walk(fn):
            where = f"{path.name}:{getattr(node, 'lineno', '?')}"
            if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name):
                t = typed.get(node.value.id)
                if t and node.attr not in _allowed(t):
                    bad.append(f"{where}: {node.value.id}.{node.attr} ({t} has no {node.attr!r})")
            elif isinstance(node, ast.Subscript) and isinstance(node.value, ast.Name):
                if node.value.id in typed:
                    bad.append(f"{where}: {node.value.id}[...] on a {typed[node.value.id]}")
            elif (
                isinstance(node, ast.Call)
                and isinstance(node.func, ast.Name)
                and node.func.id == "getattr"
                and node.args
                and isinstance(node.args[0], ast.Name)
                and node.args[0].id in typed
            ):
                bad.append(f"{where}: getattr({node.args[0].id}, ...) on a typed parameter")
    return bad


def test_edits_read_only_what_steps_and_options_have():
    paths = sorted(EDITS.rglob("*.py"))
    assert len(paths) > 20
    bad = [msg for p in paths for msg in _misreads(p)]
    assert bad == []


def test_the_ast_check_sees_a_missing_option_and_a_step_read_as_a_mapping(tmp_path):
    probe = tmp_path / "probe.py"
    probe.write_text(
        "def f(step: ShortenStep, *, options: EditOptions):\n"
        "    c = getattr(options, 'clearance', None)\n"
        "    return step.get('measure') or step['by'] or options.clearance or step.measure\n"
    )
    bad = _misreads(probe)
    assert len(bad) == 4, bad  # getattr, step.get, step[...], options.clearance
    assert any("options.clearance" in b for b in bad)
    assert any("step.get" in b for b in bad)
