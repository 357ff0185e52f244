"""``optional: true`` on a step: a garment without what the step names skips it, and says so
(issue 42, item 10: one recipe for a catalogue of tops with and without sleeves)."""

from __future__ import annotations

import json

import pytest

from ptailor.edits import EditOptions
from ptailor.errors import AbsentError, PtailorError, RecipeError
from ptailor.pipeline import apply_steps
from ptailor.recipe import parse_recipe
from ptailor.recipe.schema import recipe_schema
from ptailor.samples import flat_tee

#: steps that name what a tee without set-in sleeves lacks, each with what its skip says
ABSENT = [
    ("{op: scale, region: {part: sleeves}, direction: around, factor: 1.1}", "no part sleeves"),
    ("{op: scale, region: {panels: [sleeve]}, factor: 1.1}", "no panel named sleeve"),
    ("{op: loosen, region: {box: {min: [90, 0, -5], max: [99, 9, 5]}}, by: 1}", "selects no"),
    ("{op: shorten, opening: armhole_left, by: 2}", "no opening named 'armhole_left'"),
    ("{op: scale_seam, seam: armhole_left, part: front, factor: 1.1}", "no seam or seam line"),
    ("{op: scale, region: all, direction: around, measure: bicep_left, by: 1}",
     "no measure 'bicep_left'"),
]  # fmt: skip


def run(g, *steps: str):
    """The steps on the garment's drape (no flatten)."""
    text = "steps:\n" + "".join(f"  - {s}\n" for s in steps)
    return apply_steps(g, parse_recipe(text), options=EditOptions())


def with_optional(step: str) -> str:
    return step[:-1] + ", optional: true}"


@pytest.mark.parametrize("step, why", ABSENT, ids=[w for _, w in ABSENT])
def test_an_absent_part_fails_a_step_and_skips_an_optional_one(step, why):
    g = flat_tee(sleeves="none")
    with pytest.raises(AbsentError, match=r"^steps\[1\] \(\w+\): .*" + why.replace("(", r"\(")):
        run(g, step)
    st = run(g, with_optional(step), "{op: loosen, region: {part: torso}, by: 0.5}")
    skipped, loosened = st.log
    assert set(skipped) == {"op", "skipped", "warnings"}
    assert why in skipped["skipped"]
    assert skipped["warnings"] == [f"steps[1] ({skipped['op']}) skipped (optional: true): "
                                   + skipped["skipped"]]  # fmt: skip
    assert loosened["op"] == "loosen" and "skipped" not in loosened
    assert (st.V3 != g.V3).any()  # the step after it ran


def test_an_optional_step_on_a_garment_that_has_the_part_runs():
    g = flat_tee()
    step = "{op: scale, region: {part: sleeves}, direction: around, factor: 1.1}"
    a, b = run(g, step), run(g, with_optional(step))
    assert "skipped" not in b.log[-1]
    assert (a.V3 == b.V3).all() and (b.V3 != g.V3).any()


def test_an_optional_step_that_fails_otherwise_still_fails():
    g = flat_tee()
    # the chest exists: asked 200 cm smaller it is no length, a failure of the step itself
    step = "{op: scale, region: all, direction: around, measure: chest, by: -200, optional: true}"
    with pytest.raises(PtailorError, match="so that is no length") as err:
        run(g, step)
    assert not isinstance(err.value, AbsentError)


def test_a_symmetric_optional_step_is_skipped_whole():
    g = flat_tee(sleeves="none")
    st = run(
        g,
        "{op: scale, region: {part: sleeve_left}, direction: around, factor: 1.1,"
        " symmetric: true, optional: true}",
    )
    assert st.log[0]["op"] == "symmetry"
    assert "no part sleeve_left" in st.log[1]["skipped"]
    assert (st.V3 == g.V3).all()


@pytest.mark.parametrize("value", [1, "yes", None, [True]])
def test_optional_is_a_boolean(value):
    text = json.dumps({"steps": [{"op": "scale", "factor": 1.1, "optional": value}]})
    with pytest.raises(RecipeError, match=r"steps\[1\]\.optional: expected true or false"):
        parse_recipe(text)


def test_optional_is_echoed_only_when_true_and_published():
    on = parse_recipe("steps:\n  - {op: scale, factor: 1.1, optional: true}\n").steps[0]
    off = parse_recipe("steps:\n  - {op: scale, factor: 1.1}\n").steps[0]
    assert on.optional is True and on.to_dict()["optional"] is True
    assert off.optional is False and "optional" not in off.to_dict()  # as recipes before it
    for branch in recipe_schema()["properties"]["steps"]["items"]["allOf"]:
        prop = branch["then"]["properties"]["optional"]
        assert prop["type"] == "boolean" and "skip" in prop["description"]


@pytest.mark.slow
def test_adjust_reports_the_skipped_step(tmp_path):
    """The command: exit 0, the report's step record and its warnings say what was skipped."""
    from click.testing import CliRunner

    from ptailor.cli.main import cli
    from ptailor.formats.obj import write_garment

    g = flat_tee(sleeves="none")
    obj = tmp_path / "tank.obj"
    write_garment(obj, g)
    recipe = tmp_path / "catalogue.yaml"
    recipe.write_text(
        "steps:\n  - {op: loosen, region: {part: torso}, girth: 2}\n"
        f"  - {with_optional(ABSENT[0][0])}\n"
    )
    out = tmp_path / "out"
    r = CliRunner().invoke(cli, ["adjust", str(obj), str(recipe), "-o", str(out)])
    assert r.exit_code == 0, r.output
    report = json.loads((out / "report.json").read_text())
    assert "no part sleeves" in report["steps"][1]["skipped"]
    assert any("skipped (optional: true)" in w for w in report["warnings"])
