"""``loosen``'s offset form: a region moved along its smoothed outward normals, falling off to
zero at its border."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ptailor.edits import tolerances as edit_tol
from ptailor.edits.loosen.normals import (
    normal_smoother,
    outward_normals,
    turned_faces,
    unit_rows,
)
from ptailor.errors import LimitError
from ptailor.geometry.triangles import triangle_normals
from ptailor.method.geodesic import geodesic_distance
from ptailor.model.frame import Frame
from ptailor.model.garment import Panel, panel_labels


def falloff_weights(V: np.ndarray, F3: np.ndarray, faces: np.ndarray, *, band: float) -> np.ndarray:
    """Offset weights of a region's vertices: 0 on its border, rising smoothly to 1.

    The border is the region's vertices that also belong to triangles outside it (the
    garment's own open edges are not a border). The weight is ``smoothstep(d / band)``
    with ``d`` the geodesic distance within the region from its border.

    Parameters
    ----------
    V : (n, 3) float array
    F3 : (m, 3) int array
    faces : (k,) int array
        The region's triangles.
    band : float, keyword-only
        Width of the falloff.

    Returns
    -------
    (n,) float array
        Weights in ``[0, 1]``; 1 everywhere when the region has no border (it is the whole
        garment or whole connected pieces of it), 0 at vertices outside the region.
    """
    n = len(V)
    inside = np.zeros(len(F3), dtype=bool)
    inside[faces] = True
    in_region = np.zeros(n, dtype=bool)
    in_region[F3[faces]] = True
    on_outside = np.zeros(n, dtype=bool)
    on_outside[F3[~inside]] = True
    border = np.flatnonzero(in_region & on_outside)
    w = in_region.astype(float)
    if border.size == 0:
        return w
    d = geodesic_distance(V, F3[faces], border, limit=band)
    t = np.clip(d / band, 0.0, 1.0)
    return np.where(in_region, t * t * (3.0 - 2.0 * t), 0.0)


def where_faces(
    V: np.ndarray, F3: np.ndarray, plist: list[Panel], mask: np.ndarray, *, frame: Frame
) -> str:
    """Where some triangles are, in words: their panels and their heights.

    Parameters
    ----------
    V : (n, 3) float array
    F3 : (m, 3) int array
    plist : list of Panel
    mask : (m,) bool array
        The triangles (at least one).
    frame : Frame, keyword-only
        The garment's frame: heights are the centroids' coordinates along its up.

    Returns
    -------
    str
        ``"panel 'front', 'back', height 12.0 to 31.5"``: the (up to three) panels holding
        most of them, most first.
    """
    fp = panel_labels(plist, len(F3))[mask]
    count = np.bincount(fp[fp >= 0], minlength=len(plist))
    worst = np.argsort(-count, kind="stable")[: min(3, int((count > 0).sum()))]
    height = V[F3[mask]].mean(axis=1) @ frame.matrix()[1]
    names = ", ".join(f"'{plist[i].name}'" for i in worst) or "(none)"
    lo, hi = float(height.min()), float(height.max())
    at = f"{lo:.1f}" if hi - lo < 0.05 else f"{lo:.1f} to {hi:.1f}"
    return f"panel {names}, height {at}"


def offset_error(
    V: np.ndarray,
    F3: np.ndarray,
    plist: list[Panel],
    mask: np.ndarray,
    *,
    by: float,
    sigma: float,
    frame: Frame,
    washed_out: bool,
) -> LimitError:
    """The error for an offset that cannot be made, naming the panels and heights.

    Parameters
    ----------
    V : (n, 3) float array
        Drape before the offset.
    F3 : (m, 3) int array
    plist : list of Panel
    mask : (m,) bool array
        The triangles to name: turned over, or those whose smoothed normals no longer
        follow their surface.
    by : float, keyword-only
        Signed offset.
    sigma : float, keyword-only
        The widest smoothing tried.
    frame : Frame, keyword-only
    washed_out : bool, keyword-only
        True when the smoothing an offset of this size needs is wider than the panels
        (their smoothed normals no longer point out of them), False when triangles turn
        over even at the widest smoothing.
    """
    verb = "loosening" if by > 0 else "tightening"
    where = where_faces(V, F3, plist, mask, frame=frame)
    if washed_out:
        return LimitError(
            f"{verb} by {abs(by):g} needs the normals smoothed over about {sigma:.3g},"
            f" more than the garment allows ({where}: the smoothed normals no longer point"
            " out of the surface); use a smaller 'by'"
        )
    return LimitError(
        f"{verb} by {abs(by):g} turns part of the region inside out ({where}): the surface"
        f" there curves more tightly than {abs(by):g}, even smoothed over {sigma:.3g};"
        " use a smaller 'by'"
    )


def offset_region(
    V: np.ndarray,
    F3: np.ndarray,
    F2: np.ndarray,
    plist: list[Panel],
    faces: np.ndarray,
    *,
    by: float,
    frame: Frame,
    pairs: np.ndarray | None = None,
    symbolic=None,
) -> tuple[np.ndarray, float]:
    """Offset a region along its smoothed outward normals.

    Every vertex moves by ``by w n_s``: ``w`` its falloff weight (:func:`falloff_weights`,
    band ``LOOSEN_FALLOFF_BY |by|``) and ``n_s`` the outward normals (:func:`outward_normals`)
    diffused over the whole drape (:func:`normal_smoother`: ``LOOSEN_SMOOTH_STEPS`` steps of total
    width ``sigma = LOOSEN_SMOOTH_BY |by|``), normalised. Both widths are lengths of the edit, not
    of the mesh, so the same garment at any resolution gets the same offset.

    Why smoothed: a simulated drape's wrinkles and folds curve far more tightly (radius
    well below 1 cm) than any useful ease, and offsetting them along their own normals
    folds them over. A smooth displacement field carries them along unchanged instead
    (detail preservation, after Nealen et al.): the surface under the wrinkles is offset
    by ``by``, which adds ``2 pi by`` around a closed region (the wrinkled cloth itself
    gains a little less, about the mean cosine of its wrinkles' slopes: 0.92 to 1.0 of it
    measured on simulated tees, shirts and a dress). On a tube the diffused
    normals are exactly the radial ones, so a cylinder offset by ``by`` gains exactly
    ``2 pi by`` of circumference.

    When the offset still turns a region triangle over, the field is diffused further
    (four times as long: twice ``sigma``), up to ``LOOSEN_SMOOTH_LEVELS`` widths and as long as
    the smoothed normals still follow every panel that moves (area-weighted mean cosine to
    the raw normals at least ``LOOSEN_NORMAL_AGREEMENT``: wider smoothing than a thin sleeve
    washes its normals out), before the offset is refused.

    The rest of the garment does not move: the weight is 0 on the region's border, so the
    displacement is continuous there (an as-rigid-as-possible solve for the rest would
    only pull the rings next to the border in).

    Parameters
    ----------
    V : (n, 3) float array
        Drape.
    F3, F2 : (m, 3) int arrays
    plist : list of Panel
    faces : (k,) int array
        The region's triangles.
    by : float, keyword-only
        Signed offset: positive outward (loosen), negative inward (tighten).
    frame : Frame, keyword-only
        The garment's frame, for the error message's heights.
    pairs : (k, 2) int array, optional, keyword-only
        :func:`ptailor.model.seams.seam_halfedges` of ``F3, F2`` when known (the garment's
        structure holds them, and the flatten after the edit uses the same); computed
        otherwise.

    Returns
    -------
    V_new : (n, 3) float array
        The edited drape.
    sigma : float
        Width of the normal smoothing that was used (recorded in the step's log).

    Raises
    ------
    LimitError
        When the offset turns a triangle over even at the widest smoothing (tightening by
        more than the surface's radius, loosening into a tight concave fold), or needs a
        smoothing wider than a panel, naming the panels and the heights where it happens.
    """
    w = falloff_weights(V, F3, faces, band=edit_tol.LOOSEN_FALLOFF_BY * abs(by))
    N0 = outward_normals(V, F3, F2, plist, pairs=pairs)
    live = _LiveFaces.of(V, F3, plist, faces, w)
    return _smoothed_offset(V, F3, plist, faces, w, N0, live, by=by, frame=frame, symbolic=symbolic)


class _LiveFaces(NamedTuple):
    """A region's triangles that move, their panels and areas: the smoothed normals must
    still follow each panel's surface (area-weighted mean cosine to the raw normals).

    Attributes
    ----------
    live : (k,) bool array
        Region triangles with a vertex of positive weight.
    panel : (k,) int array
        Panel of each region triangle (-1: none).
    weight : (k,) float array
        Twice the area of each live triangle in a panel, else 0.
    total : (p,) float array
        ``weight`` summed per panel.
    """

    live: np.ndarray
    panel: np.ndarray
    weight: np.ndarray
    total: np.ndarray

    @classmethod
    def of(
        cls, V: np.ndarray, F3: np.ndarray, plist: list[Panel], faces: np.ndarray, w: np.ndarray
    ) -> _LiveFaces:
        """The live faces of the region ``faces`` under the falloff weights ``w`` ``(n,)``."""
        T = F3[faces]
        live = (w[T] > 0.0).any(axis=1)
        fp = panel_labels(plist, len(F3))[faces]
        area = np.linalg.norm(triangle_normals(V, T, unit=False), axis=1)  # twice the areas
        wt = np.where(live & (fp >= 0), area, 0.0)
        total = np.bincount(np.maximum(fp, 0), weights=wt, minlength=len(plist))
        return cls(live, fp, wt, total)

    def lost(self, cos: np.ndarray) -> np.ndarray:
        """Panels ``(p,)`` bool the smoothing washed out, from each region triangle's mean
        cosine ``cos`` ``(k,)`` of smoothed to raw normals (below ``LOOSEN_NORMAL_AGREEMENT``)."""
        fp = np.maximum(self.panel, 0)
        agree = np.bincount(fp, weights=self.weight * cos, minlength=len(self.total))
        return agree < edit_tol.LOOSEN_NORMAL_AGREEMENT * self.total


def _smoothed_offset(
    V: np.ndarray,
    F3: np.ndarray,
    plist: list[Panel],
    faces: np.ndarray,
    w: np.ndarray,
    N0: np.ndarray,
    live: _LiveFaces,
    *,
    by: float,
    frame: Frame,
    symbolic=None,
) -> tuple[np.ndarray, float]:
    """The offset of :func:`offset_region` along normals smoothed level after level.

    The raw outward normals ``N0`` ``(n, 3)`` are diffused ``LOOSEN_SMOOTH_STEPS`` steps of width
    ``sigma = LOOSEN_SMOOTH_BY |by|``; while the offset ``by w n_s`` turns a region triangle over,
    four times as long (twice ``sigma``), up to ``LOOSEN_SMOOTH_LEVELS`` widths and as long as no
    panel that moves is washed out (:meth:`_LiveFaces.lost`). Returns the edited drape and
    the width used; raises :func:`offset_error` otherwise.
    """
    T = F3[faces]
    moving = np.flatnonzero(w > 0.0)
    sigma = edit_tol.LOOSEN_SMOOTH_BY * abs(by)
    step = normal_smoother(
        V, F3, tau=sigma * sigma / (2.0 * edit_tol.LOOSEN_SMOOTH_STEPS), symbolic=symbolic
    )
    N, done, turned = N0, 0, np.zeros(len(T), dtype=bool)
    for level in range(edit_tol.LOOSEN_SMOOTH_LEVELS):  # a loop over smoothing levels
        for _ in range(edit_tol.LOOSEN_SMOOTH_STEPS * 4**level - done):  # over diffusion steps
            N = step(N)
        done = edit_tol.LOOSEN_SMOOTH_STEPS * 4**level
        Nu = unit_rows(N)
        lost = live.lost(np.einsum("ij,ij->i", Nu, N0)[T].mean(axis=1))
        if lost.any() and level == 0:
            fp = live.panel
            bad = np.zeros(len(F3), dtype=bool)
            bad[faces[live.live & lost[np.maximum(fp, 0)] & (fp >= 0)]] = True
            raise offset_error(V, F3, plist, bad, by=by, sigma=sigma, frame=frame, washed_out=True)
        if lost.any():
            break
        V_new = V.copy()
        V_new[moving] += (by * w[moving])[:, None] * Nu[moving]
        turned = turned_faces(V, V_new, T)
        if not turned.any():
            return V_new, sigma * 2.0**level
    bad = np.zeros(len(F3), dtype=bool)
    bad[faces[turned]] = True
    tried = sigma * 2.0 ** (level - int(lost.any()))
    raise offset_error(V, F3, plist, bad, by=by, sigma=tried, frame=frame, washed_out=False)
