"""The explicit sharing of symbolic analyses (SymbolicCache passed as ``symbolic=``) and
the ARAP deformation's precompute/solve halves."""

from __future__ import annotations

import numpy as np

from ptailor.method.deform import arap_deform, arap_precompute, arap_solve
from ptailor.method.flatten import flatten
from ptailor.method.solver import SymbolicCache, factor
from ptailor.samples import lantern_sleeve
from tests.test_linear import spd  # (the shared analysis with a cache: test_linear)


def test_without_a_cache_nothing_is_shared():
    A = spd(30, 1)
    b = np.ones(30)
    np.testing.assert_allclose(A @ factor(A)(b), b, atol=1e-10)
    cache = SymbolicCache()
    factor(A)
    assert len(cache) == 0


def test_flatten_with_a_cache_gives_the_same_pattern():
    g = lantern_sleeve()
    V3 = g.V3 * np.array([1.1, 1.0, 1.1])
    cache = SymbolicCache()
    shared = flatten(g, V3, symbolic=cache)
    again = flatten(g, V3, method="uniform", seams="free", symbolic=cache)
    assert len(cache) > 0
    np.testing.assert_array_equal(shared.V2, flatten(g, V3).V2)
    np.testing.assert_array_equal(again.V2, flatten(g, V3, method="uniform", seams="free").V2)


def test_arap_precompute_and_solve_compose_to_arap_deform():
    nu, nv = 16, 10
    t = np.linspace(0.0, 2 * np.pi, nu, endpoint=False)
    z = np.linspace(0.0, 2.0, nv)
    V = np.stack([np.tile(np.cos(t), nv), np.tile(np.sin(t), nv), np.repeat(z, nu)], axis=1)
    i, j = np.meshgrid(np.arange(nu), np.arange(nv - 1), indexing="ij")
    a = (j * nu + i).ravel()
    b = (j * nu + (i + 1) % nu).ravel()
    F = np.concatenate([np.stack([a, b, a + nu], 1), np.stack([b, b + nu, a + nu], 1)])
    handles = np.r_[np.arange(nu), np.arange((nv - 1) * nu, nv * nu)]
    pre = arap_precompute(V, F, handles)
    for s in (1.2, 0.9):
        Q = V[handles] * np.array([s, s, 1.0])
        np.testing.assert_array_equal(arap_solve(pre, Q), arap_deform(V, F, handles, Q))
