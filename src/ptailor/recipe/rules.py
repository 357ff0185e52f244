"""The recipe rules: a parsed document checked key by key against the operations'
registry (:data:`ptailor.edits.OPERATIONS`), every problem collected.
"""

from __future__ import annotations

from typing import Any

from ptailor import tolerances as tol
from ptailor.edits import OPERATIONS, Step
from ptailor.edits.checks import (
    boolean,
    choice,
    direction_problem,
    is_number,
    show,
    vector3,
)
from ptailor.model.units import CM_PER, UNITS
from ptailor.recipe import spec
from ptailor.recipe.expect import expect_problems


def validate(data: Any) -> tuple[spec.Recipe | None, list[str]]:
    """Check a parsed recipe; collect every problem.

    Parameters
    ----------
    data : object
        The YAML document.

    Returns
    -------
    recipe : Recipe or None
        None when there are problems.
    problems : list of str
    """
    if data is None:
        data = {}
    if not isinstance(data, dict):
        return None, ["the recipe must be a mapping with 'steps' (and optionally units, flatten)"]
    probs = _top_level_problems(data)
    units = data.get("units", "cm")
    symmetric = data.get("symmetric", False)
    steps, step_probs = _steps(data.get("steps", []), units=units, symmetric=symmetric)
    flatten, flatten_probs = _flatten(data.get("flatten"))
    expect, expect_probs = expect_problems(data.get("expect"), units=units)
    probs += step_probs + flatten_probs + expect_probs
    if probs:
        return None, probs
    return spec.Recipe(
        units=units,
        steps=steps,
        flatten=flatten,
        up=data.get("up"),
        front=data.get("front"),
        symmetric=symmetric,
        expect=expect,
    ), []


def _top_level_problems(data: dict) -> list[str]:
    """The problems of a recipe's top-level keys: unknown keys, format, units, axes and
    ``symmetric`` (``steps``, ``flatten`` and ``expect`` have their own checks)."""
    probs = [
        f"unknown key {show(k)} (known: {', '.join(spec.TOP_KEYS)})"
        for k in data
        if k not in spec.TOP_KEYS
    ]
    fmt = data.get("format", 1)
    if isinstance(fmt, bool) or fmt != 1:
        probs.append(f"format: only format 1 is known, got {show(fmt)}")
    probs += choice(*UNITS)(data.get("units", "cm"), "units")
    for k in ("up", "front"):
        if k in data:
            probs += choice(*spec.AXIS_NAMES)(data[k], k)
    bad_axes = spec.axes_problem(data.get("up"), data.get("front"))
    if bad_axes:
        # on the key the recipe set (front when it set both, or only front)
        key = "front" if "front" in data else "up"
        probs.append(f"{key}: " + bad_axes.removeprefix(f"{key} "))
    probs += boolean(data.get("symmetric", False), "symmetric")
    return probs


def _steps(steps_in: Any, *, units: Any, symmetric: Any) -> tuple[list[Step], list[str]]:
    """The typed steps (every parameter filled in), and their problems (``steps[i]...``)."""
    if steps_in is None:
        steps_in = []
    probs: list[str] = []
    if not isinstance(steps_in, list):
        probs.append("steps: expected a list of steps")
        steps_in = []
    if len(steps_in) > tol.RECIPE_MAX_STEPS:
        probs.append(
            f"steps: {len(steps_in)} steps, more than {tol.RECIPE_MAX_STEPS} "
            "(ptailor.tolerances.RECIPE_MAX_STEPS)"
        )
        steps_in = []
    steps: list[Step] = []
    for i, st in enumerate(steps_in, start=1):
        step, step_probs = _step(st, f"steps[{i}]", units=units, symmetric=symmetric)
        probs += step_probs
        if step is not None:
            steps.append(step)
    return steps, probs


def _step(st: Any, where: str, *, units: Any, symmetric: Any) -> tuple[Step | None, list[str]]:
    """One step, typed (:class:`ptailor.edits.Step`; its defaults are its fields'), or None
    where it has problems: unknown keys, missing or bad parameters, then sizes and the op's
    own check (each only when nothing before it was wrong)."""
    if not isinstance(st, dict) or "op" not in st:
        return None, [f"{where}: expected a mapping with 'op'"]
    op = OPERATIONS.get(st["op"]) if isinstance(st["op"], str) else None
    if op is None:
        return None, [f"{where}.op: unknown op {show(st['op'])} (known: {', '.join(OPERATIONS)})"]
    params = op.params
    known = [*params, *(k for k in spec.STEP_KEYS if k not in params)]
    probs = [
        f"{where}: unknown key {show(k)} for {op.name} (known: {', '.join(known)})"
        for k in st
        if k != "op" and k not in known
    ]
    given: dict[str, Any] = {}
    for k, prm in params.items():
        if k in st:
            probs += prm.check(st[k], f"{where}.{k}")
            given[k] = st[k]
        elif prm.required:
            probs.append(f"{where}: {op.name} needs {k!r}")
    # symmetric: every op's, defaulting to the recipe's (an op's own symmetric param, such
    # as cut's, takes the same resolved value and mirrors itself)
    if "symmetric" in st and "symmetric" not in params:
        probs += boolean(st["symmetric"], f"{where}.symmetric")
    if "optional" in st:  # skipped on a garment without what it names
        probs += boolean(st["optional"], f"{where}.optional")
    if probs:
        return None, probs
    given["symmetric"] = st.get("symmetric", symmetric is True)
    given["optional"] = st.get("optional", False)
    step = op.step(**given)
    probs += _sizes(step, where, units)
    if op.check is not None and not probs:
        probs += op.check(step, where)
    return (None if probs else step), probs


def _flatten(fl_in: Any) -> tuple[dict, list[str]]:
    """The flatten settings with their defaults filled in, and their problems."""
    if fl_in is None:  # absent or null; 0, false, '' and [] are not mappings
        fl_in = {}
    probs: list[str] = []
    if not isinstance(fl_in, dict):
        probs.append("flatten: expected a mapping")
        fl_in = {}
    probs += [
        f"flatten: unknown key {show(k)} (known: {', '.join(spec.FLATTEN_PARAMS)})"
        for k in fl_in
        if k not in spec.FLATTEN_PARAMS
    ]
    flatten: dict = {}
    for k, (check, default) in spec.FLATTEN_PARAMS.items():
        if k in fl_in:
            probs += check(fl_in[k], f"flatten.{k}")
        flatten[k] = fl_in.get(k, default)
    return flatten, probs


def _sizes(step: Step, where: str, units: Any) -> list[str]:
    """Lengths within :data:`~ptailor.tolerances.RECIPE_MAX_LENGTH_CM`; directions usable."""
    probs = []
    cm = CM_PER.get(units, 1.0) if isinstance(units, str) else 1.0
    limit = tol.RECIPE_MAX_LENGTH_CM / cm
    for k in spec.LENGTH_PARAMS.get(step.op, ()):
        x = getattr(step, k)
        if is_number(x) and abs(x) > limit:
            probs.append(
                f"{where}.{k}: {x} is longer than {limit:g} {units} "
                f"({tol.RECIPE_MAX_LENGTH_CM:g} cm; ptailor.tolerances.RECIPE_MAX_LENGTH_CM)"
            )
    for first, *rest in spec.DIRECTION_PARAMS.get(step.op, ()):
        x: Any = getattr(step, first)
        for k in rest:
            x = x.get(k) if isinstance(x, dict) else None
        if isinstance(x, list) and not vector3(x, where):
            bad = direction_problem(x, f"{where}." + ".".join([first, *rest]))
            if bad:
                probs.append(bad)
    return probs
