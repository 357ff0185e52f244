"""Whether drape and pattern are in the units they were said to be in.

Each triangle edge's pattern length over its drape length is near 1 on any garment read in
the right units (elastic and gathered parts measure about 0.7-1.4); a median far from 1 is a
unit mistake (a drape in mm read as cm), refused with :class:`UnitMismatchError`.
"""

from __future__ import annotations

import numpy as np

from ptailor.errors import PtailorError
from ptailor.geometry.labels import component_labels
from ptailor.geometry.topology import edge_keys, half_edges
from ptailor.geometry.triangles import edge_lengths, signed_areas_2d, triangle_areas
from ptailor.model import tolerances as model_tol

__all__ = [
    "UNIT_RATIO_RANGE",
    "UnitMismatchError",
    "check_units",
    "pattern_scale_estimate",
    "unit_ratios",
]

#: see :data:`ptailor.model.tolerances.UNIT_RATIO_RANGE`
UNIT_RATIO_RANGE = model_tol.UNIT_RATIO_RANGE


class UnitMismatchError(PtailorError):
    """Drape and pattern are not in the units they were said to be in (exit 2)."""


def unit_ratios(
    V3: np.ndarray, F3: np.ndarray, V2: np.ndarray, F2: np.ndarray, *, lengths3=None
) -> tuple[float, np.ndarray]:
    """Median pattern/drape edge length ratio, of the garment and of each panel.

    Parameters
    ----------
    V3 : (n3, 3) float array
    F3 : (m, 3) int array
    V2 : (n2, 2) float array
    F2 : (m, 3) int array
        Panels are its connected components (:func:`ptailor.geometry.component_labels` order).
    lengths3 : (m, 3) float array, optional
        ``edge_lengths(V3, F3)`` when already computed (:attr:`IntakeResult.lengths3`).

    Returns
    -------
    ratio : float
        Median over every triangle edge of its 2D length over its 3D length (1 when both
        are in the same unit; elastic parts measure about 0.7-1.4); NaN without edges.
    per_panel : (p,) float array
        The same median per panel.
    """
    l3 = (edge_lengths(V3, F3) if lengths3 is None else lengths3).ravel()
    l2 = edge_lengths(V2, F2).ravel()
    lab = np.repeat(component_labels(F2, len(V2)), 3)
    ok = (l3 > 0) & (l2 > 0) & np.isfinite(l2 / np.where(l3 > 0, l3, 1.0))
    r, lab = l2[ok] / l3[ok], lab[ok]
    n_p = int(lab.max()) + 1 if lab.size else 0
    if not r.size:
        return float("nan"), np.full(n_p, np.nan)
    # per-panel medians: the ratios grouped by panel, each run's middle two values
    order = np.argsort(lab, kind="stable") if n_p <= 64 else np.lexsort((r, lab))
    rs, count = r[order], np.bincount(lab, minlength=n_p)
    start = np.cumsum(count) - count
    lo, hi = start + (count - 1) // 2, start + count // 2
    for p in np.flatnonzero(count).tolist() if n_p <= 64 else []:  # select, not sort
        a, b = start[p], start[p] + count[p]
        rs[a:b] = np.partition(rs[a:b], [lo[p] - a, hi[p] - a])
    per = np.where(
        count > 0, 0.5 * (rs[np.minimum(lo, len(rs) - 1)] + rs[np.minimum(hi, len(rs) - 1)]), np.nan
    )
    return float(np.median(r)), per


def check_units(
    ratio: float,
    *,
    path: str | None,
    pattern_units: str,
    drape_units: str,
    pattern_option: str = "--pattern-units",
) -> None:
    """Raise :class:`UnitMismatchError` when ``ratio`` (:func:`unit_ratios`) is outside
    :data:`UNIT_RATIO_RANGE`.

    Parameters
    ----------
    ratio : float
        Median pattern/drape edge length ratio, both read in their stated units.
    path : str or None
        The file named in the message.
    pattern_units, drape_units : str
        The units as given.
    pattern_option : str
        The option that sets the pattern's unit (``--dxf-units`` for a DXF pattern).
    """
    lo, hi = UNIT_RATIO_RANGE
    if np.isfinite(ratio) and not lo <= ratio <= hi:
        raise UnitMismatchError(
            f"pattern and drape disagree in scale: median pattern/drape edge length ratio "
            f"{ratio:.3g} (outside [{lo:g}, {hi:g}]) reading the pattern in {pattern_units} "
            f"and the drape in {drape_units}: check {pattern_option} and --drape-units "
            "(or --pattern-units auto)",
            path=path,
        )


def pattern_scale_estimate(V3: np.ndarray, F3: np.ndarray, V2: np.ndarray, F2: np.ndarray) -> float:
    """The scale that puts a pattern in the drape's unit (``--pattern-units auto``).

    The median, over the pattern's interior triangles (no corner on a panel's outline), of
    each triangle's ``sqrt(drape area / pattern area)``: a box mesh's seam triangles, stretched
    across the gaps between its placed panels (a third to two thirds of its 3D area), and
    stretched hems and cuffs do not count. Without interior triangles, the whole garment's
    area ratio.

    Parameters
    ----------
    V3 : (n3, 3) float array
    F3 : (m, 3) int array
    V2 : (n2, 2) float array
    F2 : (m, 3) int array

    Returns
    -------
    float
        NaN when the pattern has no area.

    Examples
    --------
    >>> V2 = np.array([[0.0, 0], [1, 0], [0, 1]])
    >>> V3 = np.c_[3.0 * V2, np.zeros(3)]
    >>> float(pattern_scale_estimate(V3, np.array([[0, 1, 2]]), V2, np.array([[0, 1, 2]])))
    3.0
    """
    a3 = triangle_areas(V3, F3)
    a2 = np.abs(signed_areas_2d(V2, F2))
    keys = edge_keys(half_edges(F2), n=len(V2))
    uniq, count = np.unique(keys, return_counts=True)
    outline = np.zeros(len(V2), dtype=bool)
    outline[half_edges(F2)[np.isin(keys, uniq[count == 1])].ravel()] = True
    inner = ~outline[F2].any(axis=1) & (a2 > 0) & (a3 > 0)
    if inner.any():
        return float(np.median(np.sqrt(a3[inner] / a2[inner])))
    total = float(a2.sum())
    return float(np.sqrt(a3.sum() / total)) if total > 0 else float("nan")
