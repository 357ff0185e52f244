"""Edge curves of a parametric pattern: evaluation and least-squares fitting.

A pattern specification (GarmentCode, Garment-Pattern-Generator) draws each panel edge
from its start point ``P0`` to its end point ``P1`` as one of:

- ``straight``: the segment;
- ``quadratic``: a quadratic Bezier curve with one control point ``c``;
- ``cubic``: a cubic Bezier curve with two control points ``c1, c2``;
- ``circle``: a circular arc ``(radius, large_arc, right)``, SVG's arc flags.

Bezier control points are *relative*, in the edge's own frame: ``(u, v)`` is the point
``P0 + u (P1 - P0) + v perp(P1 - P0)`` with ``perp(x, y) = (-y, x)``, so they do not change
when the edge is moved, turned or scaled. An arc's flags follow GarmentCode's drawing: an
SVG arc in the y-down drawing frame (the panel's ``y`` negated) with ``sweep = not right``;
``radius`` is absolute (pattern units) and grows to half the chord when it is shorter.
"""

from __future__ import annotations

import numpy as np

from ptailor import tolerances as tol

__all__ = [
    "CURVE_KINDS",
    "arc_center",
    "chord_deviation",
    "curve_points",
    "fit_curve",
    "to_absolute",
    "to_relative",
]

#: edge curve kinds and the shape of their parameters
CURVE_KINDS = {"straight": (0,), "quadratic": (1, 2), "cubic": (2, 2), "circle": (3,)}


def _frame(P0: np.ndarray, P1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    e = np.asarray(P1, dtype=float) - np.asarray(P0, dtype=float)
    return e, np.array([-e[1], e[0]])


def to_absolute(P0: np.ndarray, P1: np.ndarray, C: np.ndarray) -> np.ndarray:
    """Relative control points ``C`` ``(k, 2)`` of the edge ``P0 -> P1`` as points ``(k, 2)``."""
    e, n = _frame(P0, P1)
    C = np.asarray(C, dtype=float).reshape(-1, 2)
    return np.asarray(P0, dtype=float) + C[:, :1] * e + C[:, 1:] * n


def to_relative(P0: np.ndarray, P1: np.ndarray, X: np.ndarray) -> np.ndarray:
    """Points ``X`` ``(k, 2)`` in the frame of the edge ``P0 -> P1`` (inverse of
    :func:`to_absolute`)."""
    e, n = _frame(P0, P1)
    L2 = max(float(e @ e), tol.TINY)
    d = np.asarray(X, dtype=float).reshape(-1, 2) - np.asarray(P0, dtype=float)
    return np.stack([d @ e / L2, d @ n / L2], axis=1)


def _bernstein(t: np.ndarray, degree: int) -> np.ndarray:
    """Bernstein basis ``(len(t), degree + 1)``."""
    from math import comb

    t = np.asarray(t, dtype=float)[:, None]
    k = np.arange(degree + 1)[None, :]
    return np.array([comb(degree, i) for i in range(degree + 1)]) * t**k * (1 - t) ** (degree - k)


def arc_center(
    P0: np.ndarray, P1: np.ndarray, radius: float, large_arc: bool, right: bool
) -> tuple[np.ndarray, float, float, float]:
    """An arc edge's centre, radius (grown to half the chord), start angle and sweep angle.

    Angles are in the panel's frame (``y`` up); the arc is
    ``centre + r (cos a, sin a)`` for ``a`` from ``start`` to ``start + sweep``.
    """
    # SVG's centre parametrisation (SVG 1.1, F.6.5) in the y-down drawing frame
    a = np.array([P0[0], -P0[1]], dtype=float)
    b = np.array([P1[0], -P1[1]], dtype=float)
    sweep_flag = not right
    h = (a - b) / 2.0
    d2 = float(h @ h)
    r = max(abs(float(radius)), np.sqrt(d2))
    coef = np.sqrt(max(r * r - d2, 0.0) / max(d2, tol.TINY))
    if bool(large_arc) == sweep_flag:
        coef = -coef
    c = coef * np.array([h[1], -h[0]]) + (a + b) / 2.0
    t0 = np.arctan2(a[1] - c[1], a[0] - c[0])
    t1 = np.arctan2(b[1] - c[1], b[0] - c[0])
    dt = (t1 - t0) % (2 * np.pi)  # in [0, 2 pi)
    if not sweep_flag and dt > 0:
        dt -= 2 * np.pi
    # back to y up: angles negate
    return np.array([c[0], -c[1]]), float(r), float(-t0), float(-dt)


def curve_points(
    P0: np.ndarray, P1: np.ndarray, kind: str, params: np.ndarray, t: np.ndarray
) -> np.ndarray:
    """Points of an edge curve at parameters ``t`` in ``[0, 1]``.

    Parameters
    ----------
    P0, P1 : (2,) float array
        The edge's start and end.
    kind : str
        One of :data:`CURVE_KINDS`.
    params : float array
        ``quadratic``: ``(1, 2)`` relative control point; ``cubic``: ``(2, 2)``;
        ``circle``: ``(radius, large_arc, right)``; ``straight``: ignored.
    t : (k,) float array

    Returns
    -------
    (k, 2) float array
        Bezier curves at their own parameter, arcs at uniform angle.
    """
    P0 = np.asarray(P0, dtype=float)
    P1 = np.asarray(P1, dtype=float)
    t = np.asarray(t, dtype=float)
    if kind == "straight":
        return P0 + t[:, None] * (P1 - P0)
    if kind in ("quadratic", "cubic"):
        ctrl = np.vstack([P0, to_absolute(P0, P1, params), P1])
        return _bernstein(t, len(ctrl) - 1) @ ctrl
    if kind == "circle":
        radius, large_arc, right = (float(x) for x in np.asarray(params).ravel()[:3])
        c, r, a0, da = arc_center(P0, P1, radius, bool(large_arc), bool(right))
        a = a0 + t * da
        X = c + r * np.stack([np.cos(a), np.sin(a)], axis=1)
        X[t == 0.0] = P0  # exact ends
        X[t == 1.0] = P1
        return X
    raise ValueError(f"unknown edge curve kind {kind!r}")


def chord_deviation(P0: np.ndarray, P1: np.ndarray, X: np.ndarray) -> float:
    """Largest distance of points ``X`` ``(k, 2)`` from the segment ``P0 P1``."""
    from ptailor.geometry.segments import segment_feet

    if len(X) == 0:
        return 0.0
    P0 = np.broadcast_to(np.asarray(P0, dtype=float), X.shape)
    P1 = np.broadcast_to(np.asarray(P1, dtype=float), X.shape)
    d, _ = segment_feet(X, P0, P1)
    return float(np.max(d))


def fit_curve(
    P0: np.ndarray,
    P1: np.ndarray,
    kind: str,
    t: np.ndarray,
    X: np.ndarray,
    *,
    start: np.ndarray | None = None,
    reparametrize: int = 0,
) -> np.ndarray:
    """The parameters of the edge curve from ``P0`` to ``P1`` closest to points ``X``.

    Parameters
    ----------
    P0, P1 : (2,) float array
        Fixed ends.
    kind : str
        ``quadratic`` or ``cubic`` (least squares of ``curve(t_i) - X_i``, linear in the
        control points), or ``circle`` (least squares of the points' distances to the arc's
        circle over the centre's offset along the chord's bisector; ``start`` gives the
        flags' first guess); ``straight`` returns an empty array.
    t : (k,) float array
        The parameter each point belongs to (Bezier curves); ignored for arcs.
    X : (k, 2) float array
    reparametrize : int
        Bezier curves: after the first fit, this many rounds of moving each point's
        parameter to its foot on the curve (Newton steps) and fitting again: a geometric
        fit. Points already on the curve at their parameters stay there.

    Returns
    -------
    float array
        The parameters :func:`curve_points` takes, Bezier control points relative.
    """
    P0 = np.asarray(P0, dtype=float)
    P1 = np.asarray(P1, dtype=float)
    X = np.asarray(X, dtype=float).reshape(-1, 2)
    if kind == "straight":
        return np.zeros(0)
    if kind in ("quadratic", "cubic"):
        deg = 2 if kind == "quadratic" else 3
        t = np.asarray(t, dtype=float)
        best = (np.inf, None)
        for _ in range(reparametrize + 1):
            B = _bernstein(t, deg)
            rhs = X - np.outer(B[:, 0], P0) - np.outer(B[:, -1], P1)
            ctrl, *_ = np.linalg.lstsq(B[:, 1:-1], rhs, rcond=None)
            full = np.vstack([P0, ctrl, P1])
            t = _feet(full, X, t)
            err = float(np.sum((_bernstein(t, deg) @ full - X) ** 2))
            if err < best[0]:  # the rounds need not improve: keep the closest fit
                best = (err, ctrl)
        return to_relative(P0, P1, best[1])
    if kind == "circle":
        return _fit_arc(P0, P1, X, start)
    raise ValueError(f"unknown edge curve kind {kind!r}")


def _feet(
    ctrl: np.ndarray, X: np.ndarray, t: np.ndarray, steps: int = tol.CURVE_FOOT_STEPS
) -> np.ndarray:
    """Parameters of the feet of points ``X`` on the Bezier curve ``ctrl``, by Newton
    steps on ``|B(t) - X|^2`` from ``t`` (kept in ``[0, 1]``)."""
    deg = len(ctrl) - 1
    # start from the nearer of t and the nearest of 257 samples (Newton finds local feet)
    ts = np.linspace(0.0, 1.0, 257)
    S = _bernstein(ts, deg) @ ctrl
    near = ts[np.argmin(((X[:, None, :] - S[None]) ** 2).sum(-1), axis=1)]
    keep = ((_bernstein(t, deg) @ ctrl - X) ** 2).sum(1) <= (
        (_bernstein(near, deg) @ ctrl - X) ** 2
    ).sum(1)
    t = np.where(keep, t, near)
    d1 = deg * np.diff(ctrl, axis=0)
    d2 = (deg - 1) * np.diff(d1, axis=0) if deg > 1 else np.zeros((1, 2))
    for _ in range(steps):
        r = _bernstein(t, deg) @ ctrl - X
        g1 = _bernstein(t, deg - 1) @ d1
        g2 = _bernstein(t, deg - 2) @ d2 if deg > 1 else np.zeros_like(g1)
        num = np.sum(r * g1, axis=1)
        gn = np.sum(g1 * g1, axis=1)  # Gauss-Newton: where the full Newton step is not a descent
        den = gn + np.sum(r * g2, axis=1)
        den = np.where(den > tol.CURVE_NEWTON_CURVATURE_REL * np.maximum(gn, tol.TINY), den, gn)
        step = np.where(den > tol.TINY, num / np.where(den > tol.TINY, den, 1.0), 0.0)
        t = np.clip(t - step, 0.0, 1.0)
    return t


def _fit_arc(P0: np.ndarray, P1: np.ndarray, X: np.ndarray, start: np.ndarray | None):
    """:func:`fit_curve` for an arc: the centre ``m + s n`` on the chord's bisector."""
    from scipy.optimize import least_squares

    m = (P0 + P1) / 2.0
    e, n = _frame(P0, P1)
    L = max(float(np.linalg.norm(e)), tol.TINY)
    n = n / L

    def resid(s):
        c = m + s[0] * n
        return np.linalg.norm(X - c, axis=1) - np.linalg.norm(P0 - c)

    if start is not None:
        c0, *_ = arc_center(P0, P1, *np.asarray(start, dtype=float).ravel()[:3])
        s0 = float((c0 - m) @ n)
    else:
        s0 = 0.0
    fit_tol = tol.CURVE_ARC_FIT_TOL
    s = float(
        least_squares(resid, [s0], x_scale=[L], xtol=fit_tol, ftol=fit_tol, gtol=fit_tol).x[0]
    )
    c = m + s * n
    r = float(np.linalg.norm(P0 - c))
    # the flags: the arc passes the points' side of the chord
    side = float(np.mean((X - m) @ n)) if len(X) else 1.0
    best = None
    for large in (0, 1):
        for right in (0, 1):
            cc, _, _, _ = arc_center(
                P0, P1, r * (1 + tol.CURVE_ARC_RADIUS_GROW_REL), bool(large), bool(right)
            )
            pts = curve_points(P0, P1, "circle", np.array([r, large, right]), np.array([0.5]))
            score = np.linalg.norm(cc - c) + (0.0 if (pts[0] - m) @ n * side > 0 else tol.HUGE)
            if best is None or score < best[0]:
                best = (score, large, right)
    return np.array([r, float(best[1]), float(best[2])])
