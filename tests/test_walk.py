"""Walking one garment from the CLI to the written files reads top to bottom.

A profile hook records, for every ptailor function called while ``ptailor demo`` and
``ptailor adjust`` run in-process, the chain of ptailor modules on the call stack. Along every
chain the layers (``test_layers.LAYERS``) never go up, and a module is visited once on the way
down: once the chain has left a module for another, it does not come back to it. Callbacks (a
lambda or a nested function handed down, as ``Piece.map_points(fn)`` takes) are the caller's
code running on the callee's behalf and are not counted as visits.
"""

from __future__ import annotations

import inspect
import itertools
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from ptailor.cli.main import cli
from tests.test_layers import layer_of

ROOT = Path(__file__).resolve().parents[1]


def chains(args: list[str]) -> set[tuple[str, ...]]:
    """The distinct chains of ptailor modules seen on the call stack while running ``args``."""
    seen: set[tuple[str, ...]] = set()

    def hook(frame, event, arg):
        if event != "call":
            return
        chain = []
        f = frame
        while f is not None:
            name = f.f_globals.get("__name__", "")
            code = f.f_code  # a lambda, or a function nested in another (co_qualname: 3.11+)
            callback = code.co_name == "<lambda>" or bool(code.co_flags & inspect.CO_NESTED)
            if name.startswith("ptailor.") and not callback and (not chain or chain[-1] != name):
                chain.append(name)
            f = f.f_back
        if chain:
            seen.add(tuple(reversed(chain)))

    sys.setprofile(hook)
    try:
        result = CliRunner().invoke(cli, args, catch_exceptions=False)
    finally:
        sys.setprofile(None)
    assert result.exit_code == 0, result.output
    return seen


def problems(seen: set[tuple[str, ...]]) -> list[str]:
    out = set()
    for chain in seen:
        for a, b in itertools.pairwise(chain):
            if layer_of(b)[0] > layer_of(a)[0]:
                out.add(f"up: {a} -> {b}")
        for i, m in enumerate(chain):
            if m in chain[i + 1 :]:
                out.add("revisit: " + " -> ".join(chain[chain.index(m) :]))
                break
    return sorted(out)


def test_problems_name_a_climb_and_a_revisit():
    down = (
        "ptailor.cli.adjust",
        "ptailor.run.garment",
        "ptailor.pipeline",
        "ptailor.model.garment",
    )
    assert problems({down}) == []
    climb = ("ptailor.cli.adjust", "ptailor.model.garment", "ptailor.pipeline")
    assert problems({climb}) == ["up: ptailor.model.garment -> ptailor.pipeline"]
    back = ("ptailor.edits", "ptailor.edits.cut", "ptailor.edits")
    assert problems({back}) == ["revisit: ptailor.edits -> ptailor.edits.cut -> ptailor.edits"]


@pytest.mark.slow
def test_demo_a_dxf_adjustment_and_a_batch_walk_down(tmp_path):
    demo = tmp_path / "demo"
    assert problems(chains(["demo", str(demo)])) == []
    recipe = str(ROOT / "recipes" / "wider-around.yaml")
    dxf = ["adjust", str(demo / "pattern.dxf"), recipe, "--drape", str(demo / "garment.obj")]
    assert problems(chains([*dxf, "-o", str(tmp_path / "dxf")])) == []
    batch = ["batch", recipe, str(demo / "sample.obj"), "-o", str(tmp_path / "batch"), "-j", "1"]
    assert problems(chains(batch)) == []
