"""The stitching's Newton step: its Hessian, its constrained solve, and the crawl it cures."""

from __future__ import annotations

import numpy as np
import pytest

from ptailor.geometry.triangles import edge_matrices
from ptailor.method.ease import SeamEase
from ptailor.method.solver import stitch
from ptailor.method.solver.problem import PanelIndex, Problem
from ptailor.method.solver.small_systems import bordered_solver


def strip(nx: int = 60, ny: int = 2, length: float = 48.0, width: float = 1.6, y0: float = 0.0):
    """A long, narrow grid of triangles, ``(V, F)``."""
    x, y = np.meshgrid(
        np.linspace(0, length, nx + 1), np.linspace(y0, y0 + width, ny + 1), indexing="ij"
    )
    V = np.c_[x.ravel(), y.ravel()]
    idx = np.arange(len(V)).reshape(nx + 1, ny + 1)
    a, b = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel()
    c, d = idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    return V, np.r_[np.c_[a, b, c], np.c_[a, c, d]]


def bending_targets(V: np.ndarray, F: np.ndarray, radius: float) -> np.ndarray:
    """Targets that stretch the strip along its length by ``1 + y / radius``: what bends
    it into an annulus of that radius (each triangle's target keeps its own frame, so the
    solver has to find the rotations)."""
    T = edge_matrices(V, F)
    T[:, 0, :] *= (1.0 + V[F, 1].mean(1) / radius)[:, None]
    return T


def problem(V, F, T, ease=None) -> Problem:
    return Problem(
        V, F, T, pins=np.array([len(V) // 2]), vertex_panel=None, asap_faces=None,
        asap_exclude=None, ease=ease, panel_weight=None, w_pin=1e3, w_asap=0.0,
    )  # fmt: skip


def test_projected_hessian_is_the_energys_second_derivative_where_nothing_is_compressed():
    V, F = strip(12, 3, 10.0, 3.0)
    rng = np.random.default_rng(0)
    pb = problem(V, F, edge_matrices(V, F))
    X = 1.1 * V + 0.01 * rng.standard_normal(V.shape)  # every triangle stretched: r > 2
    J, _, _ = pb.rotations(X)
    m = pb.m
    assert np.hypot(J[:m, 0] + J[m:, 1], J[:m, 1] - J[m:, 0]).min() > 2.0
    for _ in range(3):
        P = rng.standard_normal(V.shape)
        h = 1e-4
        e = [pb.energy(X + t * h * P) / 2 for t in (-1.0, 0.0, 1.0)]
        fd = (e[0] - 2 * e[1] + e[2]) / h**2
        pb.rotations(X)
        quad = float((P * pb.hessian(X, P, None)).sum())
        assert quad == pytest.approx(fd, rel=1e-5)


def test_projected_hessian_is_positive_semi_definite_where_triangles_are_compressed():
    V, F = strip(12, 3, 10.0, 3.0)
    rng = np.random.default_rng(1)
    pb = problem(V, F, edge_matrices(V, F))
    X = 0.7 * V + 0.05 * rng.standard_normal(V.shape)  # compressed: the twist is negative
    quads = [float((P * pb.hessian(X, P, None)).sum()) for P in rng.standard_normal((20, *V.shape))]
    assert min(quads) >= 0.0
    # the unprojected twist (alpha = 1/r) would be indefinite here: the projection matters
    J, _, _ = pb.rotations(X)
    m = pb.m
    assert np.hypot(J[:m, 0] + J[m:, 1], J[:m, 1] - J[m:, 0]).max() < 2.0


def test_bordered_solver_solves_the_kkt_system_for_every_right_hand_side():
    rng = np.random.default_rng(2)
    k, t = 9, 2
    G = rng.standard_normal((k, k))
    M = G @ G.T + 0.1 * np.eye(k)
    B = np.zeros((k, t))
    B[:4, 0] = rng.standard_normal(4)  # disjoint supports, one curve per column
    B[5:8, 1] = rng.standard_normal(3)
    K = np.block([[M, B], [B.T, np.zeros((t, t))]])
    solve = bordered_solver(M, B)
    for _ in range(3):
        r = rng.standard_normal(k)
        want = np.linalg.solve(K, np.r_[r, np.zeros(t)])[:k]
        np.testing.assert_allclose(solve(r), want, rtol=1e-9, atol=1e-12)
    assert bordered_solver(np.full((k, k), np.nan), B) is None


@pytest.mark.slow
@pytest.mark.parametrize("radius", [60.0, 200.0])
def test_newton_steps_bend_a_slender_strip_that_local_global_steps_crawl_on(radius):
    V, F = strip()
    T = bending_targets(V, F, radius)
    pins = np.array([len(V) // 2])
    ref, _ = stitch(V, F, T, pins=pins, max_iter=2000, step_tol=1e-12)
    X, info = stitch(V, F, T, pins=pins, max_iter=300)
    X0, info0 = stitch(V, F, T, pins=pins, max_iter=300, newton_cg=0)
    assert info.converged and info.newton_steps >= 1
    assert not info0.converged  # Anderson-accelerated local/global alone: the cap
    size = np.ptp(V, axis=0).max()

    def off(Y):  # rigid motion removed: the pin holds one vertex, the strip may turn
        return float(PanelIndex(np.zeros(len(V), int), 1).rigid_misfit(Y, ref)[0])

    # converged means near the answer, not merely that the last step was small
    assert off(X) < 1e-5 * size
    assert off(X0) > 1e-3 * size


@pytest.mark.slow
def test_newton_steps_keep_the_seams_exact():
    """Two strips sewn along their length, bent: the Newton steps' iterates meet the
    linearised seams, so the run ends converged with every seam pair at its ratio. (A third
    of the crawl test's strip, bent through the same angle: the Newton steps still run.)"""
    nx, ny = 20, 2
    Va, Fa = strip(nx, ny, 16.0, 0.8, 0.0)
    Vb, Fb = strip(nx, ny, 16.0, 0.8, 0.8)
    V = np.r_[Va, Vb]
    F = np.r_[Fa, Fb + len(Va)]
    T = bending_targets(V, F, 20.0)
    top = np.arange(nx + 1) * (ny + 1) + ny  # strip a's top row, in x order
    bottom = len(Va) + np.arange(nx + 1) * (ny + 1)  # strip b's bottom row
    ea = np.c_[top[1:], top[:-1]]  # a's boundary runs against x, b's along it
    eb = np.c_[bottom[:-1], bottom[1:]]
    ease = SeamEase(ea=ea, eb=eb, row=np.arange(nx), ratio=np.ones(nx))
    vlab = np.r_[np.zeros(len(Va), int), np.ones(len(Vb), int)]
    pins = np.array([len(Va) // 2, len(Va) + len(Vb) // 2])
    X, info = stitch(V, F, T, pins=pins, vertex_panel=vlab, ease=ease, max_iter=300)
    assert info.converged and info.newton_steps >= 1
    assert info.seam_violation <= 1e-9
    la, lb = ease.lengths(X)
    np.testing.assert_allclose(lb, la, rtol=1e-9)


@pytest.mark.slow
def test_the_split_factor_and_two_solves_give_one_answer(monkeypatch):
    """The constrained steps through the factor that orders the seam unknowns last (one
    forward and one back-substitution) and through two plain solves (as without CHOLMOD)
    reach the same pattern, Newton steps included (the strips of the test above)."""
    import ptailor.method.solver.problem as st

    Va, Fa = strip(20, 2, 16.0, 0.8, 0.0)
    Vb, Fb = strip(20, 2, 16.0, 0.8, 0.8)
    V = np.r_[Va, Vb]
    F = np.r_[Fa, Fb + len(Va)]
    T = bending_targets(V, F, 20.0)
    top = np.arange(21) * 3 + 2
    bottom = len(Va) + np.arange(21) * 3
    ease = SeamEase(
        ea=np.c_[top[1:], top[:-1]], eb=np.c_[bottom[:-1], bottom[1:]],
        row=np.arange(20), ratio=np.full(20, 1.02),
    )  # fmt: skip
    kw = dict(
        pins=np.array([len(Va) // 2, len(Va) + len(Vb) // 2]),
        vertex_panel=np.r_[np.zeros(len(Va), int), np.ones(len(Vb), int)],
        ease=ease, max_iter=300,
    )  # fmt: skip
    made = []
    split = st.split_solver
    monkeypatch.setattr(st, "split_solver", lambda *a: made.append(split(*a)) or made[-1])
    X1, info1 = stitch(V, F, T, **kw)
    assert made and made[0] is not None
    monkeypatch.setattr(st, "split_solver", lambda *a: None)
    X2, info2 = stitch(V, F, T, **kw)
    assert info1.converged and info2.converged and info1.newton_steps >= 1
    assert info1.iterations == info2.iterations
    np.testing.assert_allclose(X1, X2, atol=1e-9 * 16.0)
