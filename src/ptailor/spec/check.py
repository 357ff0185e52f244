"""Checking an adjusted specification against the adjusted mesh it was read from."""

from __future__ import annotations

import numpy as np

from ptailor import tolerances as tol
from ptailor.model.garment import Panel
from ptailor.model.specification import Specification
from ptailor.pieces.draw import outer_loop
from ptailor.pieces.match import ClosedCurve
from ptailor.spec.adjust import AdjustedSpec

__all__ = ["edge_lengths", "spec_fit"]


def spec_fit(
    adjusted: AdjustedSpec, V2: np.ndarray, F2: np.ndarray, panel_list: list[Panel]
) -> list[np.ndarray]:
    """Per panel of the adjusted specification, per edge, the largest distance of the edge
    curve (sampled independently of the fit) from its mesh panel's adjusted outline.

    Parameters
    ----------
    adjusted : AdjustedSpec
    V2 : (n, 2) float array
        The adjusted pattern.
    F2 : (m, 3) int array
    panel_list : list of Panel
        The adjusted garment's panels (``PanelChange.panel`` indexes them).

    Returns
    -------
    list of (e,) float arrays
        Computation units, one array per panel of ``adjusted.spec``.
    """
    t = np.linspace(0.0, 1.0, tol.SPEC_FIT_SAMPLES + 1)
    out = []
    for sp, ch in zip(adjusted.spec.panels, adjusted.changes, strict=True):  # spec panels
        A, b = ch.to_pattern
        p = panel_list[ch.panel]
        curve = ClosedCurve(V2[outer_loop(F2, p.faces, V2)])
        X = np.vstack([sp.edge_points(i, t) for i in range(len(sp.edges))]) @ A.T + b
        d = curve.nearest(X)[0].reshape(len(sp.edges), len(t))
        out.append(d.max(axis=1))
    return out


def edge_lengths(spec: Specification) -> dict[tuple[str, int], float]:
    """``(panel, edge)`` to the edge curve's length (specification units)."""
    return {(sp.name, i): float(v) for sp in spec.panels for i, v in enumerate(sp.edge_lengths())}
