"""The drape as an edit leaves it: checked (:func:`check_drape`), or edited elsewhere.

A drape edited in another tool (Blender, Maya, CLO, Marvelous Designer, a re-simulation on
another body) is an edit like a recipe's steps: the same vertices and triangles, moved.
:func:`edited_state` makes it the :class:`~ptailor.edits.state.EditState` the flattening
reads, so that the pattern follows it by the method, as it follows a recipe's steps.
"""

from __future__ import annotations

import numpy as np

from ptailor import tolerances as tol
from ptailor.edits import tolerances as edit_tol
from ptailor.edits.state import EditState
from ptailor.errors import NumericError, PtailorError
from ptailor.geometry.labels import used_indices
from ptailor.geometry.rotations import max_trace_rotations
from ptailor.geometry.triangles import triangle_areas
from ptailor.model.garment import Garment, Panel, panel_labels
from ptailor.model.structure import structure


def check_drape(state: EditState, where: str) -> None:
    """Refuse a step that leaves the drape non-finite or collapses its triangles.

    A triangle whose area falls below ``tol.EDIT_COLLAPSE_REL`` of its area on the
    original drape (``state.base.V3``) is collapsed: the stitching would be singular.
    """
    g = state.base
    V = state.V3
    used = used_indices(g.F3, len(V))  # (np.unique's sort: 16 ms at 100k; this 1 ms)
    if not np.all(np.isfinite(V[used])):
        raise NumericError(f"{where}: the edited drape has non-finite coordinates")
    if not len(g.F3):
        return
    with np.errstate(all="ignore"):
        a0 = triangle_areas(g.V3, g.F3, robust=True)
        a1 = triangle_areas(V, g.F3, robust=True)
        bad = (a0 > 0) & ~(a1 >= tol.EDIT_COLLAPSE_REL * a0)
    if np.any(bad):
        flab = panel_labels(state.panels, g.n_faces)
        names = sorted({state.panels[i].name for i in flab[bad] if i >= 0})
        worst = float(np.min(a1[bad] / a0[bad])) if np.any(bad) else 0.0
        raise PtailorError(
            f"{where}: collapses {int(bad.sum())} drape triangle(s) of panel(s) "
            f"{', '.join(names[:5]) or '?'} (area down to {worst:.3g} of the original, below "
            f"{tol.EDIT_COLLAPSE_REL:g}): the pattern cannot follow"
        )


def similar_panels(
    V3: np.ndarray, V3_edit: np.ndarray, F3: np.ndarray, plist: list[Panel]
) -> np.ndarray:
    """Panels the edit moved by a similarity (rotation, uniform scale, translation) or not at
    all: with ``boundary: auto`` they keep their outline shape, as a recipe's uniform scale
    of whole panels does (:attr:`EditState.even`).

    A panel is similar when the best similarity's residual, root mean square over its
    triangles' corners, is below ``EDITED_SIMILAR_REL`` of the panel's radius (its corners'
    root mean square distance from their centroid): a drape written with nine significant
    digits and read back stays similar where it was.

    Parameters
    ----------
    V3, V3_edit : (n3, 3) float arrays
        The drape before and after the edit.
    F3 : (m, 3) int array
    plist : list of Panel

    Returns
    -------
    (n_panels,) bool array
    """
    k = len(plist)
    flab = panel_labels(plist, len(F3))
    on = flab >= 0
    lab = np.repeat(flab[on], 3)
    X = V3[F3[on]].reshape(-1, 3)
    Y = V3_edit[F3[on]].reshape(-1, 3)
    count = np.maximum(np.bincount(lab, minlength=k), 1).astype(float)

    def centred(P: np.ndarray) -> np.ndarray:
        c = np.stack([np.bincount(lab, P[:, j], k) for j in range(3)], 1) / count[:, None]
        return P - c[lab]

    Xc, Yc = centred(X), centred(Y)
    S = np.stack(
        [np.bincount(lab, Xc[:, i] * Yc[:, j], k) for i in range(3) for j in range(3)], 1
    ).reshape(k, 3, 3)  # sum over a panel's corners of Xc Yc^T
    sxx = np.bincount(lab, np.einsum("ij,ij->i", Xc, Xc), k)
    syy = np.bincount(lab, np.einsum("ij,ij->i", Yc, Yc), k)
    _, trace = max_trace_rotations(S)  # max over rotations R of sum Yc . R Xc
    with np.errstate(all="ignore"):
        # min over s, R of sum |Yc - s R Xc|^2 = syy - trace^2 / sxx (s = trace / sxx)
        residual = np.maximum(syy - np.maximum(trace, 0.0) ** 2 / sxx, 0.0)
        rel = np.sqrt(residual / sxx)
    return (sxx > 0) & (rel <= edit_tol.EDITED_SIMILAR_REL)


def edited_state(
    garment: Garment, V3_edit: np.ndarray, *, where: str = "edited drape"
) -> EditState:
    """The edit state of a drape edited elsewhere: ``garment`` the original, ``V3_edit`` its
    drape moved (same vertices, same triangles ``garment.F3``).

    Panels the edit moved by a similarity are ``even`` (:func:`similar_panels`); no outline
    is freed, no panel frozen and no seam gathers: what a recipe step says on purpose (a new
    hem, a gathered seam) a drape alone cannot. The log holds one record, ``{"op":
    "edited_drape", "vertices", "faces", "moved_max", "moved_rms", "similar_panels"}``
    (distances in the garment's units).

    Parameters
    ----------
    garment : Garment
    V3_edit : (n3, 3) float array
    where : str
        Named in errors.

    Returns
    -------
    EditState

    Raises
    ------
    PtailorError
        A shape other than ``garment.V3``'s; non-finite coordinates or collapsed triangles
        (:func:`check_drape`).
    """
    V = np.asarray(V3_edit, dtype=np.float64)
    if V.shape != garment.V3.shape:
        raise PtailorError(
            f"{where}: {V.shape[0] if V.ndim else 0} vertices of shape {V.shape}, the garment's "
            f"drape has {garment.V3.shape[0]} ({garment.V3.shape})"
        )
    plist = structure(garment).panels
    used = used_indices(garment.F3, len(V))
    state = EditState(
        base=garment, V3=np.ascontiguousarray(V), panels=plist, even=np.ones(len(plist), bool)
    )
    check_drape(state, where)
    moved = np.linalg.norm(V[used] - garment.V3[used], axis=1)
    even = similar_panels(garment.V3, V, garment.F3, plist)
    record = {
        "op": "edited_drape",
        "vertices": len(V),
        "faces": len(garment.F3),
        "moved_max": round(float(moved.max(initial=0.0)), 6),
        "moved_rms": round(float(np.sqrt(np.mean(moved**2))) if len(moved) else 0.0, 6),
        "similar_panels": [p.name for p in plist if even[p.index]],
    }
    return EditState(base=garment, V3=state.V3, panels=plist, even=even, log=(record,))
