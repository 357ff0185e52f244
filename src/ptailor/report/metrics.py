"""Per-panel and per-triangle quality measures of an adjusted pattern. All vectorised."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor import tolerances as tol
from ptailor.geometry.closed_forms import inv2, sqrt_spd2
from ptailor.geometry.labels import used_indices
from ptailor.geometry.rotations import closest_rotations
from ptailor.geometry.triangles import edge_matrices, signed_areas_2d
from ptailor.method.intrinsic import intrinsic_targets
from ptailor.model.boundary import boundary_edges


def _by_label(lab: np.ndarray, vals: np.ndarray, n: int) -> np.ndarray:
    return np.bincount(lab, vals, minlength=n)


def panel_areas(V2: np.ndarray, F2: np.ndarray, flab: np.ndarray, n: int) -> np.ndarray:
    """Pattern area of each panel, ``(n,)``."""
    return _by_label(flab, np.abs(signed_areas_2d(V2, F2)), n)


def panel_sizes(V2: np.ndarray, vlab: np.ndarray, n: int) -> np.ndarray:
    """Bounding-box width and height of each panel, ``(n, 2)``."""
    used = vlab >= 0
    lab, P = vlab[used], V2[used]
    lo = np.full((n, 2), np.inf)
    hi = np.full((n, 2), -np.inf)
    if len(lab):  # per label: runs of one stable sort (ufunc.at is 5x slower)
        order = np.argsort(lab, kind="stable")
        sl, Ps = lab[order], P[order]
        starts = np.flatnonzero(np.r_[True, sl[1:] != sl[:-1]])
        lo[sl[starts]] = np.minimum.reduceat(Ps, starts, axis=0)
        hi[sl[starts]] = np.maximum.reduceat(Ps, starts, axis=0)
    return np.where(np.isfinite(hi - lo), hi - lo, 0.0)


def boundary_deviation(
    V2_before: np.ndarray, V2_after: np.ndarray, F2: np.ndarray, vlab: np.ndarray, n: int
) -> np.ndarray:
    """Largest outline distance after the best similarity fit, per panel.

    Fits ``after`` onto ``before`` over each panel's boundary vertices by rotation,
    translation and uniform scale (Umeyama), and returns the largest distance between
    corresponding boundary vertices, in ``after``'s size (the fit's scale is undone).

    Parameters
    ----------
    V2_before, V2_after : (n2, 2) float arrays
    F2 : (m, 3) int array
    vlab : (n2,) int array
        Panel per vertex.
    n : int
        Number of panels.

    Returns
    -------
    (n,) float array
    """
    b = used_indices(boundary_edges(F2), len(V2_before))
    lab = vlab[b]
    X, Y = V2_after[b], V2_before[b]
    cnt = np.maximum(np.bincount(lab, minlength=n), 1).astype(float)
    cx = np.stack([_by_label(lab, X[:, c], n) for c in range(2)], 1) / cnt[:, None]
    cy = np.stack([_by_label(lab, Y[:, c], n) for c in range(2)], 1) / cnt[:, None]
    a, t = X - cx[lab], Y - cy[lab]
    dot = _by_label(lab, (a * t).sum(1), n)
    crs = _by_label(lab, a[:, 0] * t[:, 1] - a[:, 1] * t[:, 0], n)
    saa = np.maximum(_by_label(lab, (a * a).sum(1), n), tol.TINY)
    s = np.hypot(dot, crs) / saa  # similarity scale taking after onto before
    ang = np.arctan2(crs, dot)
    c, si = np.cos(ang)[lab], np.sin(ang)[lab]
    fit = s[lab, None] * np.stack([c * a[:, 0] - si * a[:, 1], si * a[:, 0] + c * a[:, 1]], 1)
    d = np.linalg.norm(fit - t, axis=1) / s[lab]
    out = np.zeros(n)
    np.maximum.at(out, lab, d)
    return out


@dataclass(frozen=True)
class ScaleReference:
    """What :func:`intrinsic_scale_error` measures a new pattern against: the same for
    every pattern of one edited garment (the adjusted one and the uniform baseline).

    Attributes
    ----------
    U0 : (m, 2, 2) float array
        The stretch each triangle should have: of its target onto its edited drape triangle
        (with no target given, of the original pattern triangle onto the original drape).
    E3e : (m, 3, 2) float array
        Edge matrices of the edited drape.
    target : (m, 2, 2) float array
        The polar scale-preserving targets.
    """

    U0: np.ndarray
    E3e: np.ndarray
    target: np.ndarray


def scale_reference(
    V2: np.ndarray,
    F2: np.ndarray,
    V3: np.ndarray,
    V3_edit: np.ndarray,
    F3: np.ndarray,
    *,
    target: np.ndarray | None = None,
) -> ScaleReference:
    """The :class:`ScaleReference` of a garment (arguments as in
    :func:`intrinsic_scale_error`)."""
    E2 = edge_matrices(V2, F2)
    E3, E3e = edge_matrices(V3, F3), edge_matrices(V3_edit, F3)
    J0 = E3 @ inv2(E2)
    U0 = sqrt_spd2(np.swapaxes(J0, 1, 2) @ J0)
    if target is None:
        return ScaleReference(
            U0=U0, E3e=E3e, target=intrinsic_targets(V2, F2, V3, V3_edit, F3, intrinsic="polar")
        )
    # the scale the edit asks for: the target's onto the edited drape (U0 itself where the
    # target keeps the intrinsic scale; a kept cuff's drape stretch and a gather's spread
    # are asked, not errors)
    Jt = E3e @ inv2(target)
    return ScaleReference(U0=sqrt_spd2(np.swapaxes(Jt, 1, 2) @ Jt), E3e=E3e, target=target)


def intrinsic_scale_error(
    V2: np.ndarray,
    V2_new: np.ndarray,
    F2: np.ndarray,
    V3: np.ndarray,
    V3_edit: np.ndarray,
    F3: np.ndarray,
    *,
    target: np.ndarray | None = None,
    reference: ScaleReference | None = None,
) -> np.ndarray:
    """Per-triangle relative change of the intrinsic scale, frame-free.

    ``|M_new - M|_F / |M|_F`` where ``M = sqrt(J0^T J0)`` is the stretch of the original
    pattern triangle onto the original drape triangle and ``M_new`` the stretch of the new
    pattern triangle onto the edited drape triangle, brought into the original pattern's
    frame by the rotation that best aligns the new triangle with its scale-preserving
    target. Zero exactly when the new triangle is a rotated copy of that target.

    Parameters
    ----------
    V2, V2_new : (n2, 2) float arrays
        Original and new pattern (mirrored panels flipped consistently in both).
    F2 : (m, 3) int array
    V3, V3_edit : (n3, 3) float arrays
    F3 : (m, 3) int array
    target : (m, 2, 2) float array, optional
        The polar targets, when the caller has them (they are recomputed otherwise).
    reference : ScaleReference, optional
        :func:`scale_reference` of these arguments, when the caller measures several new
        patterns of one garment (``V2``, ``V3``, ``V3_edit`` and ``target`` are then not
        read).

    Returns
    -------
    (m,) float array
    """
    if reference is None:
        reference = scale_reference(V2, F2, V3, V3_edit, F3, target=target)
    E2n = edge_matrices(V2_new, F2)
    S = closest_rotations(E2n @ inv2(reference.target))
    Jn = reference.E3e @ inv2(E2n) @ S
    Mn = sqrt_spd2(np.swapaxes(Jn, 1, 2) @ Jn)
    U0 = reference.U0
    num = np.linalg.norm(Mn - U0, axis=(1, 2))
    return num / np.linalg.norm(U0, axis=(1, 2))


def flipped(V2_new: np.ndarray, F2: np.ndarray, orientation: np.ndarray) -> np.ndarray:
    """``(m,)`` bool: triangles whose signed area is not of their panel's sign.

    Parameters
    ----------
    V2_new : (n2, 2) float array
    F2 : (m, 3) int array
    orientation : (m,) float array
        +1 for triangles of counter-clockwise panels, -1 for mirrored ones.
    """
    return signed_areas_2d(V2_new, F2) * orientation <= 0


def summary_stats(x: np.ndarray, lab: np.ndarray, n: int) -> dict[str, np.ndarray]:
    """Mean, 95th percentile and max of ``x`` per label (sorted once, no loop over items)."""
    order = np.lexsort((x, lab))
    xs, ls = x[order], lab[order]
    start = np.searchsorted(ls, np.arange(n))
    stop = np.searchsorted(ls, np.arange(n), side="right")
    cnt = np.maximum(stop - start, 1)
    mean = np.bincount(lab, x, minlength=n) / cnt
    p95_idx = np.clip(start + np.ceil(0.95 * (cnt - 1)).astype(int), 0, max(len(xs) - 1, 0))
    mx_idx = np.clip(stop - 1, 0, max(len(xs) - 1, 0))
    empty = stop == start
    p95 = np.where(empty, 0.0, xs[p95_idx] if len(xs) else 0.0)
    mx = np.where(empty, 0.0, xs[mx_idx] if len(xs) else 0.0)
    return {"mean": mean, "p95": p95, "max": mx}
