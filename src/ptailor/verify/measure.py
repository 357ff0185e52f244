"""Measures of a re-drape: principal stretches, per-panel statistics, the pinned opening."""

from __future__ import annotations

import numpy as np

from ptailor.geometry.closed_forms import inv2
from ptailor.geometry.triangles import edge_matrices
from ptailor.model.boundary import boundary_loops
from ptailor.model.frame import Frame

__all__ = ["panel_stats", "pattern_vertex_values", "principal_stretches", "top_opening"]


def principal_stretches(V: np.ndarray, F: np.ndarray, rest: np.ndarray) -> np.ndarray:
    """Principal stretches of each triangle of a drape against its rest shape.

    Parameters
    ----------
    V : (n, 3) float array
        The drape.
    F : (m, 3) int array
    rest : (m, 2, 2) float array
        Rest edge matrices (columns ``p1 - p0``, ``p2 - p0``), mirrored or not.

    Returns
    -------
    (m, 2) float array
        Singular values of ``J = E3(V, F) rest^-1``, largest first: above 1 stretched,
        below 1 compressed (a degenerate rest gives nan).

    Examples
    --------
    >>> V = np.array([[0.0, 0, 0], [2, 0, 0], [0, 0.5, 0]])
    >>> principal_stretches(V, np.array([[0, 1, 2]]), np.eye(2)[None])
    array([[2. , 0.5]])
    """
    with np.errstate(all="ignore"):
        J = edge_matrices(np.asarray(V, dtype=float), F) @ inv2(np.asarray(rest, dtype=float))
        ok = np.all(np.isfinite(J), axis=(1, 2))
        out = np.full((len(J), 2), np.nan)
        if np.any(ok):
            out[ok] = np.linalg.svd(J[ok], compute_uv=False)
    return out


def _stats(values: np.ndarray, qs: dict[str, float]) -> dict[str, float]:
    """``{name: percentile}`` of the finite ``values`` (nan for none); ``max`` is q 100."""
    v = values[np.isfinite(values)]
    if len(v) == 0:
        return {k: float("nan") for k in qs}
    p = np.percentile(v, list(qs.values()))
    return {k: float(x) for k, x in zip(qs, p, strict=True)}


def panel_stats(
    stretch: np.ndarray,
    displacement: np.ndarray,
    face_panel: np.ndarray,
    vertex_panel: np.ndarray,
    names: list[str],
) -> dict[str, dict]:
    """Per-panel statistics of a re-drape.

    Parameters
    ----------
    stretch : (m, 2) float array
        :func:`principal_stretches` per triangle.
    displacement : (n,) float array
        Distance of each vertex from the start drape, in the units wanted in the report
        (the caller scales); per pattern vertex so that a seam counts in both panels.
    face_panel : (m,) int array
        Panel index per triangle (-1: none).
    vertex_panel : (n,) int array
        Panel index per vertex of ``displacement`` (-1: none).
    names : list of str
        Panel names, by index.

    Returns
    -------
    dict
        ``{NAME: {"stretch": {"p50", "p95", "max"}, "compression": {"p5"},
        "displacement": {"mean", "p95", "max"}}}`` of floats (nan where a panel has no
        finite value): stretch from the largest principal stretch, compression from the
        smallest.

    Examples
    --------
    >>> s = np.array([[1.0, 0.9], [1.2, 1.0]])
    >>> d = np.array([0.0, 1.0, 2.0])
    >>> r = panel_stats(s, d, np.array([0, 0]), np.array([0, 0, 0]), ["cuff"])
    >>> r["cuff"]["stretch"]["max"], r["cuff"]["displacement"]["mean"]
    (1.2, 1.0)
    """
    stretch = np.asarray(stretch, dtype=float)
    displacement = np.asarray(displacement, dtype=float)
    out: dict[str, dict] = {}
    for k, name in enumerate(names):
        s = stretch[np.asarray(face_panel) == k]
        d = displacement[np.asarray(vertex_panel) == k]
        dd = d[np.isfinite(d)]
        disp = _stats(d, {"p95": 95.0, "max": 100.0})
        out[name] = {
            "stretch": _stats(s[:, 0], {"p50": 50.0, "p95": 95.0, "max": 100.0}),
            "compression": _stats(s[:, 1], {"p5": 5.0}),
            "displacement": {
                "mean": float(dd.mean()) if len(dd) else float("nan"),
                **disp,
            },
        }
    return out


def pattern_vertex_values(
    values: np.ndarray, F3: np.ndarray, F2: np.ndarray, n2: int
) -> np.ndarray:
    """Per-drape-vertex values carried to the pattern vertices (each seam side gets one).

    Parameters
    ----------
    values : (n3,) array
    F3, F2 : (m, 3) int arrays
        Corresponding drape and pattern triangles.
    n2 : int
        Number of pattern vertices.

    Returns
    -------
    (n2,) float array
        ``values`` of the drape vertex each pattern vertex is sewn to; nan for unused ones.

    Examples
    --------
    >>> pattern_vertex_values(np.array([5.0, 6, 7]), np.array([[0, 1, 2]]),
    ...                       np.array([[1, 2, 3]]), 4).tolist()
    [nan, 5.0, 6.0, 7.0]
    """
    to3 = np.full(n2, -1)
    to3[np.asarray(F2).ravel()] = np.asarray(F3).ravel()
    out = np.full(n2, np.nan)
    used = to3 >= 0
    out[used] = np.asarray(values, dtype=float)[to3[used]]
    return out


def top_opening(V3: np.ndarray, F3: np.ndarray, *, frame: Frame) -> np.ndarray:
    """The drape's top opening: the boundary loop with the highest mean height.

    Parameters
    ----------
    V3 : (n, 3) float array
    F3 : (m, 3) int array
    frame : Frame
        The wearer's axes (heights along its up).

    Returns
    -------
    (k,) int array
        Vertex indices of that loop (the neckline, a waist, a sleeve's top); empty for a
        closed surface.

    Examples
    --------
    >>> from ptailor.samples import cylinder
    >>> g = cylinder()
    >>> bool(g.V3[top_opening(g.V3, g.F3, frame=g.frame), 1].min() == g.V3[:, 1].max())
    True
    """
    loops = boundary_loops(np.asarray(F3))
    if not loops:
        return np.zeros(0, dtype=int)
    h = np.asarray(V3, dtype=float) @ frame.matrix()[1]
    heights = [float(h[lp].mean()) for lp in loops]
    return np.asarray(loops[int(np.argmax(heights))], dtype=int)
