"""The null test, the verdict and the settle test of the re-drape check, without the engine:
report sections and positions made up for each case."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from ptailor.verify.engine import Settings
from ptailor.verify.settle import Settle
from ptailor.verify.summary import summary_lines
from ptailor.verify.verdict import null_test, verdict


def redrape(stretch: dict[str, float], d: tuple[float, float, float], *, settled=True) -> dict:
    """A re-drape's report: per panel stretch p95, the whole drape's displacement
    ``(mean, p95, max)`` (every panel's too)."""
    disp = dict(zip(("mean", "p95", "max"), d, strict=True))
    return {
        "panels": {
            n: {"stretch": {"p95": s}, "displacement": dict(disp)} for n, s in stretch.items()
        },
        "displacement": disp,
        "settled": settled,
    }


def section(ours, baseline, original) -> dict:
    return {"ours": ours, "baseline": baseline, "original": original}


# --------------------------------------------------------------------------- the null test


@pytest.mark.parametrize(
    ("d", "holds"),
    [
        ((0.4, 1.2, 3.0), True),
        ((1.0, 2.5, 9.0), True),  # on the limits
        ((1.1, 2.0, 3.0), False),  # the mean beyond
        ((0.5, 2.6, 3.0), False),  # the p95 beyond
        ((float("nan"),) * 3, False),
    ],
)
def test_the_null_test_holds_within_its_limits(d, holds):
    null = null_test(redrape({"front": 1.02}, d), cm_per_unit=1.0)
    assert null["holds"] is holds
    assert null["limits"] == {"mean": 1.0, "p95": 2.5}
    assert ("within" in null["why"]) is holds


def test_the_null_test_limits_are_lengths_in_the_report_units():
    """In mm (0.1 cm per unit) the default limits are 10 and 25 mm; limits are given in cm."""
    R = redrape({"front": 1.0, "sleeve": 1.0}, (8.0, 20.0, 40.0))
    R["panels"]["sleeve"]["displacement"] = {"mean": 9.0, "p95": 30.0, "max": 40.0}
    null = null_test(R, cm_per_unit=0.1)
    assert null["holds"] and null["limits"] == pytest.approx({"mean": 10.0, "p95": 25.0})
    tight = null_test(R, cm_per_unit=0.1, mean_cm=0.5, p95_cm=5.0)
    assert not tight["holds"] and tight["limits"] == pytest.approx({"mean": 5.0, "p95": 50.0})
    assert "mean 0.80 cm" in tight["why"] and "most in sleeve (p95 3.00 cm)" in tight["why"]
    assert tight["panels"]["sleeve"]["p95"] == 30.0


# --------------------------------------------------------------------------- the verdict


def test_a_body_that_does_not_fit_gives_no_ranking():
    null_R = redrape({"front": 1.05}, (6.8, 8.8, 12.0))
    sec = section(redrape({"front": 1.0}, (1, 2, 3)), redrape({"front": 1.3}, (5, 6, 7)), null_R)
    null = null_test(null_R, cm_per_unit=1.0)
    v = verdict(sec, null, cm_per_unit=1.0)
    assert v["holds"] is False and v["result"] == "inconclusive" and "ranking" not in v
    assert "does not fit" in v["reason"] and "mean 6.80 cm, p95 8.80 cm" in v["reason"]


def test_an_unsettled_null_redrape_gives_no_ranking():
    null_R = redrape({"front": 1.0}, (0.2, 0.5, 1.0), settled=False)
    sec = section(redrape({"front": 1.0}, (1, 2, 3)), redrape({"front": 1.3}, (5, 6, 7)), null_R)
    v = verdict(sec, null_test(null_R, cm_per_unit=1.0), cm_per_unit=1.0)
    assert v["result"] == "inconclusive" and "did not settle" in v["reason"]


@pytest.mark.parametrize(
    ("ours", "baseline", "result", "ranking"),
    [
        # (stretch p95, displacement p95): lower is better on both
        ((1.01, 1.0), (1.20, 1.0), "ours", ["ours", "baseline"]),  # stretch wins, disp ties
        ((1.01, 1.0), (1.01, 3.0), "ours", ["ours", "baseline"]),  # disp wins, stretch ties
        ((1.20, 3.0), (1.01, 1.0), "baseline", ["baseline", "ours"]),
        ((1.01, 1.1), (1.012, 1.0), "tie", ["ours", "baseline"]),  # within the ties
        ((1.01, 3.0), (1.20, 1.0), "mixed", ["ours", "baseline"]),  # ranked by stretch
    ],
)
def test_the_verdict_ranks_on_stretch_and_displacement(ours, baseline, result, ranking):
    null_R = redrape({"front": 1.0, "sleeve": 1.0}, (0.2, 0.5, 1.0))
    sec = section(
        redrape({"front": 1.0, "sleeve": ours[0]}, (0.5, ours[1], 4.0)),
        redrape({"front": 1.0, "sleeve": baseline[0]}, (0.5, baseline[1], 4.0)),
        null_R,
    )
    v = verdict(sec, null_test(null_R, cm_per_unit=1.0), cm_per_unit=1.0)
    assert v["holds"] is True and v["result"] == result and v["ranking"] == ranking
    assert v["measures"]["ours"]["stretch_excess"] == pytest.approx(ours[0] - 1.0)
    assert v["measures"]["baseline"]["displacement_p95"] == baseline[1]
    assert v["unsettled"] == []


def test_stretch_is_measured_above_the_null_redrapes_own_per_panel():
    """A panel the simulation stretches anyway (the null's cuff at 1.10) is not held
    against a pattern: ours' cuff at 1.10 is no excess, the baseline's front at 1.05 is."""
    null_R = redrape({"front": 1.0, "cuff": 1.10}, (0.2, 0.5, 1.0))
    sec = section(
        redrape({"front": 1.0, "cuff": 1.10}, (0.5, 1.0, 2.0)),
        redrape({"front": 1.05, "cuff": 1.10}, (0.5, 1.0, 2.0), settled=False),
        null_R,
    )
    v = verdict(sec, null_test(null_R, cm_per_unit=1.0), cm_per_unit=1.0)
    assert v["measures"]["ours"]["stretch_excess"] == pytest.approx(0.0)
    assert v["measures"]["baseline"]["stretch_excess"] == pytest.approx(0.05)
    assert v["result"] == "ours" and v["unsettled"] == ["baseline"]
    assert v["reason"].endswith("not settled: baseline")


def test_the_displacement_tie_is_a_length():
    """0.2 cm: in mm (0.1 cm per unit) displacements 1.5 mm apart tie, 3 mm apart do not."""
    null_R = redrape({"front": 1.0}, (0.2, 0.5, 1.0))

    def result(d_ours, d_base):
        sec = section(redrape({"front": 1.0}, (0, d_ours, 0)),
                      redrape({"front": 1.0}, (0, d_base, 0)), null_R)  # fmt: skip
        return verdict(sec, null_test(null_R, cm_per_unit=0.1), cm_per_unit=0.1)["result"]

    assert result(10.0, 11.5) == "tie" and result(10.0, 13.0) == "ours"


# --------------------------------------------------------------------------- settled


def _settle(**kw) -> Settle:
    s = replace(Settings(), check_every=10, settle_checks=2, settle_window=30, **kw)
    return Settle(s, np.array([True, True, False]))


def test_settled_needs_slow_vertices_that_stayed_put_over_the_window():
    st = _settle()
    q = np.zeros((3, 3))
    slow = np.full((3, 3), 1e-4)  # 0.17 mm/s
    assert st.window_steps == 30
    assert [st.check(q, slow) for _ in range(3)] == [False, False, False]  # no window yet
    assert st.check(q, slow) is True
    rec = st.record(settled=True, steps=40, units_m=0.01)
    assert rec["move_p95"] == 0.0 and rec["move_limit"] == pytest.approx(0.1)  # cm
    assert rec["why"].startswith("settled at step 40: speed p95 0.173 mm/s < 2")


def test_a_creeping_drape_is_not_settled_though_slow_at_each_check():
    """1.5 mm per check (10 steps) while the checks read 0.17 mm/s: 4.5 mm over the window."""
    st = _settle()
    slow = np.full((3, 3), 1e-4)
    got = [st.check(np.full((3, 3), 1.5e-3 * i), slow) for i in range(6)]
    assert not any(got)
    assert st.move_p95 == pytest.approx(math.sqrt(3) * 4.5e-3)
    rec = st.record(settled=False, steps=60, units_m=0.01)
    assert "not settled at the cap (60 steps)" in rec["why"]
    assert "moved p95 7.79 mm over the last 30 steps >= 1" in rec["why"]
    assert rec["move_p95"] == pytest.approx(0.779, abs=1e-3)


def test_a_fast_drape_says_how_many_checks_were_slow():
    st = _settle()
    st.check(np.zeros((3, 3)), np.full((3, 3), 0.01))
    rec = st.record(settled=False, steps=10, units_m=1.0)
    assert "speed p95 17.3 mm/s >= 2 (slow on 0 of 2 checks)" in rec["why"]
    assert "fewer than 30 steps: no displacement window" in rec["why"]
    assert rec["move_p95"] is None


def test_the_window_test_can_be_turned_off():
    st = _settle(settle_move=0.0)
    creep = [st.check(np.full((3, 3), 0.01 * i), np.full((3, 3), 1e-4)) for i in range(2)]
    assert creep == [False, True] and st.window_steps == 0
    assert "window_steps" not in st.record(settled=True, steps=20, units_m=1.0)


# --------------------------------------------------------------------------- the summary


def test_the_summary_says_the_null_test_the_verdict_and_why_not_settled():
    null_R = redrape({"front": 1.0}, (0.3, 0.8, 1.0))
    sec = section(redrape({"front": 1.0}, (0.4, 1.0, 2.0)),
                  redrape({"front": 1.2}, (0.5, 1.5, 2.0), settled=False), null_R)  # fmt: skip
    sec["baseline"]["settle"] = {"move_p95": 0.42, "window_steps": 100}
    sec["null"] = null_test(null_R, cm_per_unit=1.0)
    sec["verdict"] = verdict(sec, sec["null"], cm_per_unit=1.0)
    lines = summary_lines({"verify": {**sec, "cpu_seconds": 12.5}, "units": "cm"})
    assert "(12.5 s CPU)" in lines[0]
    assert "(step cap; moved p95 0.42 cm in its last 100 steps)" in lines[2]
    assert lines[-2].startswith("  null test: ") and lines[-2].endswith(": holds")
    assert lines[-1].startswith("  verdict: ours: ours rests closer")
    old = summary_lines({"verify": section(*[redrape({"a": 1.0}, (0, 0, 0))] * 3)})
    assert len(old) == 4 and not any("verdict" in line for line in old)  # an older report
