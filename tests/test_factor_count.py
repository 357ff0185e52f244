"""A run's sparse factorisations are counted (report.json's ``solver.factorizations``), an
edit's matrix is factored once however often it is solved, and the uniform baseline's
solve is reported (``baseline.solver``)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from ptailor.method.deform import arap_deform
from ptailor.method.solver import counting, factor, reusing
from ptailor.pipeline import adjustment, solver_warnings
from ptailor.recipe import parse_recipe
from ptailor.report.build import build_report
from tests.conftest import real_path
from tests.test_linear import spd

SLEEVE = """
steps:
  - op: scale
    region: {part: sleeve_left}
    direction: around
    factor: 1.1
    symmetric: SYM
"""


def test_each_factorisation_counts_and_a_matrix_factored_again_is_a_repeat():
    A, B = spd(40, 0), spd(40, 2)
    with counting() as count:
        factor(A, lower=True)
        factor(B, lower=True)
        assert (count.total, count.repeated) == (2, 0)
        factor(A, lower=True)
    assert (count.total, count.repeated) == (3, 1)
    factor(A, lower=True)  # outside the block: not counted
    assert count.total == 3


def test_inside_reusing_a_matrix_factored_again_takes_its_kept_factor():
    A, B = spd(40, 0), spd(40, 2)
    b = np.arange(40.0)
    with counting() as count, reusing():
        sa = factor(A, lower=True)
        sb = factor(B, lower=True)
        again = factor(sp.csc_matrix(A), lower=True)
    assert again is sa and count.total == 2 and count.repeated == 0
    np.testing.assert_allclose(A @ again(b), b, atol=1e-10)  # A symmetric: its lower half read
    np.testing.assert_allclose(B @ sb(b), b, atol=1e-10)


def _plate(n: int = 12):
    """A bent ``n`` x ``n`` grid, its left column held and its right one moved."""
    u, v = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n), indexing="ij")
    V = np.c_[u.ravel(), v.ravel(), 0.2 * np.sin(3 * u.ravel())]
    i = np.arange(n - 1)
    a = (i[:, None] * n + i[None, :]).ravel()
    F = np.r_[np.c_[a, a + n, a + 1], np.c_[a + 1, a + n, a + n + 1]]
    handles = np.r_[np.arange(n), np.arange(n * (n - 1), n * n)]
    return V, F, handles


def test_an_edit_solving_one_matrix_twice_factors_it_once_and_answers_the_same():
    V, F, h = _plate()
    moved = V[h] + np.where(np.arange(len(h))[:, None] >= len(h) // 2, [0.3, 0.0, 0.1], 0.0)
    with counting() as plain:
        want = [arap_deform(V, F, h, moved * s) for s in (1.0, 1.1)]
    with counting() as kept, reusing():
        got = [arap_deform(V, F, h, moved * s) for s in (1.0, 1.1)]
    assert (plain.total, plain.repeated) == (2, 1)
    assert (kept.total, kept.repeated) == (1, 0)
    for w, g in zip(want, got, strict=True):
        np.testing.assert_array_equal(w, g)


@pytest.mark.slow
@pytest.mark.parametrize("symmetric", [False, True])
def test_the_tshirt_run_counts_its_factorisations_and_its_baseline_converges(symmetric):
    from ptailor.formats.garment import load_garment

    loaded = load_garment(real_path("tshirt"), pattern_units="auto")
    g = getattr(loaded, "garment", loaded)
    adj = adjustment(g, parse_recipe(SLEEVE.replace("SYM", str(symmetric).lower())))
    fac = adj.factorizations
    # the edit: per application the deformation and its follow-up with the panels apart
    # held (two matrices); the flatten one factor, each seamed panel's block read out of
    # CHOLMOD once more (cvxopt's getfactor leaves it symbolic); the baseline one factor
    n_panels = len(adj.state.panels)
    assert fac["edit"] <= 2 * (2 if symmetric else 1)
    assert 1 <= fac["flatten"] <= 1 + n_panels
    assert fac["baseline"] == 1
    assert fac["repeated"] <= fac["flatten"] - 1  # only the read-outs factor a matrix again
    rep = build_report(adj, inputs={}, units_note={}, warnings=[], timing_s={})
    assert rep["solver"]["factorizations"] == fac
    base = rep["baseline"]["solver"]
    assert base["converged"] is True and base["iterations"] <= 100
    assert base["factorizations"] == 1
    assert list(rep)[list(rep).index("solver") + 1] == "baseline"


def test_the_baseline_record_exists_and_an_unconverged_baseline_is_a_warning():
    from ptailor.samples import lantern_sleeve

    g = lantern_sleeve()
    text = "steps:\n  - op: scale\n    direction: around\n    factor: 1.2\n"
    adj = adjustment(g, parse_recipe(text))
    rep = build_report(adj, inputs={}, units_note={}, warnings=[], timing_s={})
    base = rep["baseline"]["solver"]
    assert base["converged"] is True and base["iterations"] >= 1
    assert set(base) == {
        "iterations",
        "newton_steps",
        "converged",
        "energy",
        "residual",
        "factorizations",
    }
    assert not any(w.startswith("baseline:") for w in solver_warnings(adj))
    capped = adjustment(g, parse_recipe(text + "flatten:\n  max_iter: 1\n"))
    if capped.baseline.info.converged:  # pragma: no cover - one iteration does not converge it
        pytest.skip("the baseline converged in one iteration")
    warned = [
        w for w in solver_warnings(capped) if w.startswith("baseline: uniform solver stopped")
    ]
    assert len(warned) == 1 and "1-iteration cap" in warned[0]
    none = adjustment(g, parse_recipe(text), baseline=False)
    assert "baseline" not in build_report(none, inputs={}, units_note={}, warnings=[], timing_s={})
