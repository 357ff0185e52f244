"""Refitting a specification edge to its carried points.

Each curved edge's parameters are refitted to its carried samples by least squares in the
edge's own frame; a straight edge whose carried samples leave the chord by more than
:data:`~ptailor.tolerances.SPEC_BEND_CM` gets a curve.
"""

from __future__ import annotations

import numpy as np

from ptailor import tolerances as tol
from ptailor.geometry.curves import chord_deviation, curve_points, fit_curve
from ptailor.geometry.segments import segment_feet
from ptailor.model.specification import SpecPanel

__all__ = [
    "chord_params",
    "fit_edge",
    "param_at",
    "sample_params",
    "straight_or_bent",
]


def sample_params() -> np.ndarray:
    """The parameters ``(SPEC_REFIT_SAMPLES - 1,)`` of an edge's carried samples (its ends
    left out)."""
    return np.linspace(0.0, 1.0, tol.SPEC_REFIT_SAMPLES + 1)[1:-1]


def fit_edge(
    P0: np.ndarray, P1: np.ndarray, kind: str, t: np.ndarray, Z: np.ndarray, *, start=None
) -> tuple[str, np.ndarray, float, float]:
    """``(kind, params, refit error, chord deviation)`` of the edge of ``kind`` through
    points ``Z`` at parameters ``t`` (``start``: the input's parameters, an arc's first
    guess); the refit error is the points' largest distance from the fitted curve."""
    dev = chord_deviation(P0, P1, Z)
    if kind == "straight":
        return "straight", np.zeros(0), dev, dev
    params = fit_curve(P0, P1, kind, t, Z, start=start, reparametrize=tol.SPEC_REPARAMETRIZE)
    curve = curve_points(P0, P1, kind, params, np.linspace(0.0, 1.0, 513))
    err = float(np.max(_polyline_distance(Z, curve))) if len(Z) else 0.0
    return kind, params, err, dev


def _polyline_distance(X: np.ndarray, P: np.ndarray) -> np.ndarray:
    """Distance from points ``X`` to the open polyline ``P``."""
    d, _ = segment_feet(X[:, None, :], P[None, :-1], P[None, 1:])
    return d.min(axis=1)


def straight_or_bent(P0, P1, Z, t, bend: float) -> tuple[str, np.ndarray, float, float]:
    """A straight edge through carried points ``Z``: a quadratic when they bend."""
    dev = chord_deviation(P0, P1, Z)
    if dev <= bend or len(Z) < 3:
        return "straight", np.zeros(0), dev, dev
    kind, params, err, _ = fit_edge(P0, P1, "quadratic", t, Z)
    return kind, params, err, dev


def chord_params(P: np.ndarray) -> np.ndarray:
    """Chord-length parameters ``(n,)`` in ``[0, 1]`` of the polyline ``P``."""
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(P, axis=0), axis=1))])
    return s / max(float(s[-1]), tol.TINY)


def param_at(sp: SpecPanel, e: int, X: np.ndarray) -> float:
    """The parameter of the point of input edge ``e`` nearest ``X`` (input frame)."""
    t = np.linspace(0.0, 1.0, 4097)
    return float(t[int(np.argmin(np.linalg.norm(sp.edge_points(e, t) - X, axis=1)))])
