"""Regions of a garment named in a recipe, and their axes."""

from __future__ import annotations

from typing import Any

import numpy as np

from ptailor import tolerances as tol
from ptailor.edits import tolerances as edit_tol
from ptailor.edits.parts import part_faces
from ptailor.errors import AbsentError, PtailorError
from ptailor.geometry.triangles import triangle_normals
from ptailor.geometry.tube_axis import extent_axis, tube_axis
from ptailor.model.garment import Garment, Panel


def unit_vector(v: Any, what: str = "axis") -> np.ndarray:
    """A 3-vector scaled to unit length without overflow or underflow.

    Dividing by the largest absolute component first keeps ``[1e308, 1e308, 1e308]``
    (whose norm overflows) and ``[5e-324, 0, 0]`` (whose norm underflows) what they mean.

    Raises
    ------
    PtailorError
        A vector with a non-finite or no non-zero component.
    """
    a = np.asarray(v, dtype=float).reshape(-1)
    big = float(np.max(np.abs(a))) if a.size else 0.0
    if not np.all(np.isfinite(a)) or big == 0.0:
        raise PtailorError(f"{what} {list(np.asarray(v).tolist())} has no direction")
    a = a / big
    return a / np.linalg.norm(a)


def region_faces(region: Any, garment: Garment, V3: np.ndarray, plist: list[Panel]) -> np.ndarray:
    """Triangles a recipe region selects.

    Parameters
    ----------
    region : ``"all"`` | ``{"panels": [...]}`` | ``{"part": ...}`` | ``{"box": {"min", "max"}}``
        ``part``: a part of the body (:data:`ptailor.edits.parts.PARTS`), every panel
        around it, from the garment's structure.
    garment : Garment
    V3 : (n3, 3) float array
        Current drape (a box selects triangles whose three corners are inside).
    plist : list of Panel

    Returns
    -------
    (k,) int array
        Ascending triangle indices.

    Raises
    ------
    AbsentError
        Unknown panel names (listing the garment's), a part the garment lacks, or a region
        that selects nothing.
    """
    m = garment.n_faces
    if region == "all":
        return np.arange(m)
    if "panels" in region:
        chosen = panels_named(region["panels"], plist)
        faces = np.unique(np.concatenate([p.faces for p in chosen]))
    elif "part" in region:
        faces = part_faces(region["part"], garment)
    else:
        lo, hi = np.asarray(region["box"]["min"]), np.asarray(region["box"]["max"])
        inside = np.all((lo <= V3) & (hi >= V3), axis=1)
        faces = np.flatnonzero(inside[garment.F3].all(axis=1))
    if faces.size == 0:
        raise AbsentError(f"region {region!r} selects no triangle of the garment")
    return faces


def panels_named(names: list[str], plist: list) -> list:
    """The panels a region's names select: the panel of that name, or where there is none,
    its family, every panel named ``NAME_...`` (``sleeve`` selects ``sleeve_left`` and
    ``sleeve_right_front``; ``front`` a tank top's ``front_left`` and ``front_right``), or
    where there is none, the same on a two-tier garment without its tier (``front`` selects
    a dress's ``bodice_front``, ``bodice_front_left`` and ``skirt_front``), so that one
    recipe serves garments cut differently.

    Raises
    ------
    PtailorError
        A name that selects no panel (listing the garment's).
    """
    by_name = {p.name: p for p in plist}
    out: dict[str, object] = {}
    unknown = []
    for n in names:
        family = [by_name[n]] if n in by_name else [p for p in plist if p.name.startswith(n + "_")]
        if not family:  # a two-tier garment's: front selects bodice_front and skirt_front_left
            family = [p for p in plist if _untiered(p.name) in (n,) or
                      _untiered(p.name).startswith(n + "_")]  # fmt: skip
        if not family:
            unknown.append(n)
        out.update((p.name, p) for p in family)
    if unknown:
        raise AbsentError(
            f"no panel named {', '.join(unknown)} (this garment has: {', '.join(by_name)})"
        )
    return list(out.values())


def _untiered(name: str) -> str:
    """A panel name without its tier (``bodice_front_left`` -> ``front_left``)."""
    for tier in ("bodice_", "skirt_"):
        if name.startswith(tier):
            return name[len(tier) :]
    return name


def body_axis(
    P: np.ndarray, body_vertices: np.ndarray, *, k: int = edit_tol.BODY_AXIS_NEIGHBOURS
) -> np.ndarray:
    """The body's local axis near some garment points.

    The body part nearest to the points (each point's ``k`` nearest body vertices) and its
    direction of largest extent: along the arm for a sleeve, up the torso for a bodice.

    Parameters
    ----------
    P : (p, 3) float array
        Garment points (a region, a seam line).
    body_vertices : (b, 3) float array
    k : int
        Body vertices taken per garment point.

    Returns
    -------
    (3,) float array
        Unit vector, largest component positive.
    """
    from scipy.spatial import cKDTree

    _, idx = cKDTree(body_vertices).query(P, k=min(k, len(body_vertices)))
    ax = extent_axis(body_vertices[np.unique(idx)])
    return ax * np.sign(ax[np.argmax(np.abs(ax))])


def region_axis(
    V3: np.ndarray, F3: np.ndarray, faces: np.ndarray, *, body: Any = None
) -> np.ndarray:
    """The principal axis of a region of the drape (for ``axis: auto``).

    With a ``body`` (a mesh with ``vertices``), the body's local axis at the region
    (:func:`body_axis`).

    For tube-like regions (sleeves, a torso, a skirt) the axis is the direction the surface
    normals avoid: the eigenvector of the smallest eigenvalue of the area-weighted normal
    tensor (:func:`ptailor.geometry.tube_axis.tube_axis`, with the thresholds of
    ``tolerances.GRAIN_TUBE_MIN`` and ``GRAIN_TUBE_RATIO``, as the pieces' grain lines). For
    sheet-like regions (normals all alike) that is ill-defined, and the axis is the
    direction of largest extent of the positions instead.

    Parameters
    ----------
    V3 : (n, 3) float array
    F3 : (m, 3) int array
    faces : (k,) int array

    Returns
    -------
    (3,) float array
        Unit vector, sign chosen so its largest component is positive.
    """
    T = F3[faces]
    if body is not None:
        return body_axis(V3[np.unique(T)], np.asarray(body.vertices, dtype=float))
    ax = tube_axis(V3, T)
    if ax is None:
        ax = extent_axis(V3[np.unique(T)])
    return ax * np.sign(ax[np.argmax(np.abs(ax))])


def region_centroid(V3: np.ndarray, F3: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Area-weighted centroid of a region of the drape, ``(3,)``."""
    T = F3[faces]
    a, b, c = V3[T[:, 0]], V3[T[:, 1]], V3[T[:, 2]]
    w = np.linalg.norm(triangle_normals(V3, T, unit=False), axis=1)  # twice the areas
    return ((a + b + c) / 3.0 * w[:, None]).sum(axis=0) / max(float(w.sum()), tol.TINY)
