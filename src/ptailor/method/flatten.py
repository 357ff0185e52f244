"""Scale-preserving flattening of a whole garment: targets, stitching, placement."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal

import numpy as np

from ptailor import tolerances as tol
from ptailor.geometry.rotations import rigid_fit_groups
from ptailor.geometry.triangles import edge_lengths, edge_matrices
from ptailor.method import tolerances as method_tol
from ptailor.method.ease import SeamEase, seam_ease
from ptailor.method.gather import GatherBand, stretch_targets
from ptailor.method.intrinsic import Intrinsic, intrinsic_targets
from ptailor.method.solver import StitchInfo, SymbolicCache, stitch
from ptailor.model.garment import Garment, Panel, panel_labels, vertex_labels
from ptailor.model.structure import structure

Method = Literal["scale-preserving", "uniform"]
Seams = Literal["ease", "free"]


@dataclass(frozen=True)
class FlattenResult:
    """Adjusted pattern positions and solver state.

    Attributes
    ----------
    V2 : (n2, 2) float array
        The adjusted pattern, each panel placed by a rigid best fit onto its original.
    targets : (m, 2, 2) float array
        The per-triangle target edge matrices the solver glued (in each panel's original
        frame, mirrored panels flipped).
    info : StitchInfo
    asap_panels : (n_panels,) bool array or None
        Panels that kept their outline shape.
    """

    V2: np.ndarray
    targets: np.ndarray
    info: StitchInfo
    asap_panels: np.ndarray | None = None


def mirror_mask(panel_list: list[Panel], n: int) -> np.ndarray:
    """``(n,)`` bool: pattern vertices of mirrored (clockwise) panels."""
    mask = np.zeros(n, dtype=bool)
    for p in panel_list:
        if p.mirrored:
            mask[p.vertices] = True
    return mask


def central_vertices(V2: np.ndarray, vlab: np.ndarray, n_panels: int) -> np.ndarray:
    """Per panel, the vertex nearest to the panel's vertex centroid, ``(n_panels,)`` int."""
    used = np.flatnonzero(vlab >= 0)
    lab = vlab[used]
    cnt = np.bincount(lab, minlength=n_panels).astype(float)
    cen = np.stack([np.bincount(lab, V2[used, c], n_panels) for c in range(2)], 1)
    cen /= np.maximum(cnt, 1)[:, None]
    d = np.linalg.norm(V2[used] - cen[lab], axis=1)
    order = np.lexsort((d, lab))
    first = np.searchsorted(lab[order], np.arange(n_panels))
    return used[order[first]]


def panel_strain(
    V3: np.ndarray, V3_edit: np.ndarray, F3: np.ndarray, face_panel: np.ndarray, n_panels: int
) -> np.ndarray:
    """Per panel, the largest relative length change of a drape edge, ``(n_panels,)`` float.

    Parameters
    ----------
    V3, V3_edit : (n3, 3) float arrays
        The drape before and after the edits.
    F3 : (m, 3) int array
    face_panel : (m,) int array
    n_panels : int
    """
    l0, l1 = edge_lengths(V3, F3), edge_lengths(V3_edit, F3)
    strain = (np.abs(l1 - l0) / np.maximum(l0, tol.TINY)).max(axis=1)
    out = np.zeros(n_panels)
    np.maximum.at(out, face_panel, strain)
    return out


def check_targets(targets: np.ndarray, E2: np.ndarray, plist: list[Panel], m: int) -> None:
    """Refuse non-finite or collapsed target triangles before anything is factored.

    A target whose area is below ``tol.EDIT_COLLAPSE_REL`` of its pattern triangle's (or
    not finite) would make the stitching matrix singular or overflow.

    Raises
    ------
    NumericError
        Naming the panels (the pipeline names the step).
    """
    from ptailor.errors import NumericError
    from ptailor.geometry.closed_forms import det2

    with np.errstate(all="ignore"):
        a0 = np.abs(det2(E2))
        a1 = np.abs(det2(targets))
        ok = np.all(np.isfinite(targets), axis=(1, 2)) & (
            (a0 == 0) | (a1 >= tol.EDIT_COLLAPSE_REL * a0)
        )
    if np.all(ok):
        return
    lab = panel_labels(plist, m)
    names = sorted({plist[i].name for i in lab[~ok] if i >= 0})
    raise NumericError(
        f"{int((~ok).sum())} target triangle(s) of panel(s) {', '.join(names[:5])} "
        "are degenerate or not finite (the edit collapses or blows up the drape there)"
    )


def flatten(
    garment: Garment,
    V3_edit: np.ndarray,
    *,
    method: Method = "scale-preserving",
    intrinsic: Intrinsic = "polar",
    asap_panels: np.ndarray | None = None,
    outline_free: np.ndarray | None = None,
    frozen_panels: np.ndarray | None = None,
    gathers: tuple[GatherBand, ...] = (),
    seams: Seams = "ease",
    seam_factors: dict[tuple[int, int], float] | None = None,
    w_pin: float = method_tol.W_PIN,
    w_asap: float = method_tol.W_ASAP,
    max_iter: int = method_tol.ARAP_MAX_ITER,
    step_tol: float = method_tol.ARAP_STEP_TOL,
    history: int = method_tol.ANDERSON_HISTORY,
    panel_list: list[Panel] | None = None,
    seam_pairs: np.ndarray | None = None,
    progress: Callable[[int, float], None] | None = None,
    symbolic: SymbolicCache | None = None,
) -> FlattenResult:
    """Adjust a garment's pattern to an edited drape.

    Parameters
    ----------
    garment, V3_edit : Garment, (n3, 3) float array
        The original drape and pattern; the edited drape (same triangles as ``F3``).
    method : {"scale-preserving", "uniform"}
        ``uniform`` flattens the edited drape directly (the paper's baseline).
    intrinsic : {"polar", "paper"}
        How scale-preserving targets are formed (ignored for ``uniform``).
    asap_panels : (n_panels,) bool array, optional
        Panels whose outline keeps its shape (as-similar-as-possible); default none.
    outline_free : (n2,) bool array, optional
        Pattern vertices whose outline stays free even on those panels (an edited edge).
    frozen_panels : (n_panels,) bool array, optional
        Panels whose pattern triangles are kept as they were: the change of their drape is
        taken up by their intrinsic scale (the cuff a seam-line scale gathers into); with
        ``seams="ease"`` they are stiffer in the stitching (:func:`_seam_terms`).
    gathers : tuple of GatherBand, optional
        Gathers taken in a band along their seams (:mod:`ptailor.method.gather`).
    seams : {"ease", "free"}
        ``ease``: each seam edge's sides keep their input length ratio, exactly
        (:mod:`ptailor.method.ease`); ``free``: each panel on its own (the paper).
    seam_factors : dict, optional
        ``{(p, q): f}``: the side on ``p`` of the seams of ``p`` and ``q`` ``f`` times
        longer relative to the side on ``q`` (:func:`ptailor.method.ease.seam_ease`).
    w_pin, w_asap, max_iter, step_tol, history
        Solver settings (see :func:`ptailor.method.solver.stitch`).
    panel_list, seam_pairs : list of Panel, (s, 2) int array, optional
        The panels and their ``seam_halfedges`` (those used with ``seams="ease"``), as the
        caller found them; default: ``structure(garment)``'s.
    progress : callable, optional
        ``progress(iteration, residual)`` once per stitching iteration.
    symbolic : SymbolicCache, optional
        Symbolic analyses shared with the caller's other flattens.

    Returns
    -------
    FlattenResult
    """
    plist = panel_list or structure(garment).panels  # (API: default)
    sign = np.where(mirror_mask(plist, len(garment.V2)), -1.0, 1.0)
    V2 = garment.V2 * np.stack([sign, np.ones(len(sign))], 1)  # mirrored panels flipped
    targets = _targets(garment, V2, V3_edit, plist, method, intrinsic, frozen_panels)
    targets, gathered = stretch_targets(V2, garment.F2, targets, gathers)
    vlab = vertex_labels(plist, len(V2))
    ease, weight = _seam_terms(
        garment, V2, V3_edit, plist, seams, seam_factors, seam_pairs, frozen_panels, gathered
    )
    X, info = stitch(
        V2, garment.F2, targets, pins=central_vertices(V2, vlab, len(plist)), vertex_panel=vlab,
        asap_faces=_asap_faces(plist, garment.n_faces, asap_panels), asap_exclude=outline_free,
        ease=ease, panel_weight=weight, w_pin=w_pin, w_asap=w_asap, max_iter=max_iter,
        step_tol=step_tol, history=history, progress=progress, symbolic=symbolic,
    )  # fmt: skip
    X = rigid_fit_groups(X, V2, vlab, len(plist))
    X[:, 0] *= sign
    return FlattenResult(V2=X, targets=targets, info=info, asap_panels=asap_panels)


def _targets(
    garment: Garment,
    V2: np.ndarray,
    V3_edit: np.ndarray,
    plist: list[Panel],
    method: Method,
    intrinsic: Intrinsic,
    frozen_panels: np.ndarray | None,
) -> np.ndarray:
    """The per-triangle target edge matrices ``(m, 2, 2)`` in the frame of ``V2`` (the
    pattern, mirrored panels flipped), frozen panels' kept as they are, checked
    (:func:`check_targets`)."""
    m = garment.n_faces
    kind: Intrinsic = "uniform" if method == "uniform" else intrinsic
    targets = intrinsic_targets(V2, garment.F2, garment.V3, V3_edit, garment.F3, intrinsic=kind)
    if frozen_panels is not None and np.any(frozen_panels):
        frozen = np.asarray(frozen_panels)[panel_labels(plist, m)]
        targets[frozen] = edge_matrices(V2, garment.F2[frozen])
    check_targets(targets, edge_matrices(V2, garment.F2), plist, m)
    return targets


def _seam_terms(
    garment: Garment,
    V2: np.ndarray,
    V3_edit: np.ndarray,
    plist: list[Panel],
    seams: Seams,
    seam_factors: dict[tuple[int, int], float] | None,
    seam_pairs: np.ndarray | None,
    frozen_panels: np.ndarray | None,
    gathered: np.ndarray,
) -> tuple[SeamEase | None, np.ndarray | None]:
    """With ``seams="ease"``, the seam-ease constraints and the panels' weights
    ``(n_panels,)``: the frozen panels, and the panels whose drape no edge of changed in
    length by ``method_tol.KEPT_STRAIN``, are ``method_tol.KEPT_PANEL_WEIGHT`` times stiffer in the
    stitching, so the panels an edit touched take up what keeping the seams costs (a panel
    with ``gathered`` ``(m,)`` triangles takes up its gather: never kept).
    ``(None, None)`` with ``seams="free"``."""
    if seams != "ease":
        return None, None
    flab = panel_labels(plist, garment.n_faces)
    ease = seam_ease(
        garment.F3, garment.F2, V2, face_panel=flab, factors=seam_factors, pairs=seam_pairs
    )
    kept = panel_strain(garment.V3, V3_edit, garment.F3, flab, len(plist)) < method_tol.KEPT_STRAIN
    if frozen_panels is not None:
        kept |= np.asarray(frozen_panels, dtype=bool)
    kept[np.unique(flab[gathered])] = False
    return ease, np.where(kept, method_tol.KEPT_PANEL_WEIGHT, 1.0)


def _asap_faces(plist: list[Panel], m: int, asap_panels: np.ndarray | None) -> np.ndarray | None:
    """The triangles of the as-similar-as-possible panels, None without any."""
    if asap_panels is None or not np.any(asap_panels):
        return None
    return np.flatnonzero(np.asarray(asap_panels)[panel_labels(plist, m)])
