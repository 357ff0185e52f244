"""Building blocks of the generated garments: quad grids split into triangles, rings of
drape vertices, tube panels closed by a seam, and the assembly of panels into a
:class:`~ptailor.model.Garment`.
"""

from __future__ import annotations

import numpy as np

from ptailor.model.garment import Garment

#: Gap between pattern panels laid out side by side, in cm.
PANEL_GAP = 5.0

AXES = {"x": -1, "y": 0, "z": 1}


def quad_faces(idx3: np.ndarray, idx2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Triangulate a quad grid, alternating the diagonal in a checkerboard.

    Parameters
    ----------
    idx3, idx2 : (R + 1, C + 1) int arrays
        Drape and pattern vertex index of each grid node; row ``i`` is below row ``i + 1``
        and column ``j`` left of column ``j + 1`` in the pattern.

    Returns
    -------
    F3, F2 : (2 R C, 3) int arrays
        Quads in row-major order, two triangles each, counter-clockwise in a pattern where
        columns increase along +x and rows along +y.
    """

    def split(idx: np.ndarray) -> np.ndarray:
        a, b = idx[:-1, :-1], idx[:-1, 1:]
        c, d = idx[1:, 1:], idx[1:, :-1]
        R, C = a.shape
        even = ((np.arange(R)[:, None] + np.arange(C)[None, :]) % 2 == 0)[..., None]
        # even quads: diagonal a-c; odd quads: diagonal b-d
        t0 = np.where(even, np.stack([a, b, c], -1), np.stack([a, b, d], -1))
        t1 = np.where(even, np.stack([a, c, d], -1), np.stack([b, c, d], -1))
        return np.stack([t0, t1], axis=2).reshape(-1, 3).astype(np.int64)

    return split(np.asarray(idx3)), split(np.asarray(idx2))


def polygon_radius(circumference: float, n: int) -> float:
    """Circumradius of the regular ``n``-gon of perimeter ``circumference``."""
    return circumference / (2.0 * n * np.sin(np.pi / n))


def rings(radii: np.ndarray, heights: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """Drape vertices on horizontal rings.

    Parameters
    ----------
    radii, heights : (R,) float arrays
        Radius and y of each ring.
    phi : (n,) float array
        Angle of each vertex on a ring, 0 at the front (+z), increasing towards +x.

    Returns
    -------
    (R * n, 3) float array
        Ring-major: vertex ``j`` of ring ``i`` is row ``i * n + j``.
    """
    r = np.asarray(radii, dtype=np.float64)[:, None]
    y = np.broadcast_to(np.asarray(heights, dtype=np.float64)[:, None], (r.shape[0], phi.size))
    return np.stack([r * np.sin(phi), y, r * np.cos(phi)], axis=-1).reshape(-1, 3)


def prism(circumference: float, heights: np.ndarray, n: int) -> np.ndarray:
    """Drape vertices of a tube: rings of the regular ``n``-gon of perimeter
    ``circumference`` at ``heights``, vertex 0 at the back (-z), so a tube panel's seam
    with itself lies at the back.

    Returns
    -------
    (len(heights) * n, 3) float array
        Ring-major, as :func:`rings`.
    """
    radius = polygon_radius(circumference, n)
    phi = np.pi + 2.0 * np.pi * np.arange(n) / n
    return rings(np.full(heights.shape, radius), heights, phi)


def tube_indices(ring0: int, n_rows: int, n_around: int, v2_offset: int) -> tuple:
    """Grid node indices of a tube panel closed by a seam with itself.

    Parameters
    ----------
    ring0 : int
        Drape ring of the panel's bottom row (rings hold ``n_around`` vertices each).
    n_rows : int
        Number of quad rows.
    n_around : int
        Number of quad columns (drape vertices per ring).
    v2_offset : int
        Index of the panel's first pattern vertex.

    Returns
    -------
    idx3, idx2 : (n_rows + 1, n_around + 1) int arrays
        The last column's drape indices repeat the first column's (the seam).
    """
    rows = np.arange(n_rows + 1)[:, None]
    cols = np.arange(n_around + 1)[None, :]
    idx3 = (ring0 + rows) * n_around + cols % n_around
    idx2 = v2_offset + rows * (n_around + 1) + cols
    return idx3, idx2


def points_2d(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Pattern vertices of a rectangular grid, row-major: ``(len(y) * len(x), 2)``."""
    X, Y = np.meshgrid(np.asarray(x, np.float64), np.asarray(y, np.float64))
    return np.stack([X, Y], axis=-1).reshape(-1, 2)


def check_positive(**values: float) -> None:
    """Raise ``ValueError`` naming the first of ``values`` that is not a positive finite number."""
    for name, value in values.items():
        if not (np.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be a positive finite number, got {value!r}")


def check_count(name: str, value: int, minimum: int) -> None:
    """Raise ``ValueError`` unless ``value`` is an integer >= ``minimum``."""
    if int(value) != value or value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")


def assemble(
    V3: np.ndarray,
    F3s: list[np.ndarray],
    V2s: list[np.ndarray],
    F2s: list[np.ndarray],
    names: tuple[str, ...],
) -> Garment:
    """Assemble panels (each with local pattern indices already offset) into a Garment."""
    F3 = np.concatenate(F3s).astype(np.int64)
    F2 = np.concatenate(F2s).astype(np.int64)
    face_group = np.concatenate([np.full(len(f), k, dtype=np.int64) for k, f in enumerate(F3s)])
    return Garment(
        V3=np.ascontiguousarray(V3, dtype=np.float64),
        F3=F3,
        V2=np.ascontiguousarray(np.concatenate(V2s), dtype=np.float64),
        F2=F2,
        face_group=face_group,
        group_names=names,
        units="cm",
    )


def assemble_grids(
    V3: np.ndarray,
    grids: list[tuple[np.ndarray, np.ndarray]],
    V2s: list[np.ndarray],
    names: tuple[str, ...],
) -> Garment:
    """:func:`assemble` panels given as quad grids: ``(idx3, idx2)`` per panel, as
    :func:`quad_faces` takes them (pattern indices already offset)."""
    faces = [quad_faces(idx3, idx2) for idx3, idx2 in grids]
    return assemble(V3, [f[0] for f in faces], V2s, [f[1] for f in faces], names)


def split_pattern(
    V2: np.ndarray, F2: np.ndarray, labels: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Cut a pattern into pieces along the edges between differently labelled triangles.

    Every pattern vertex used by triangles of several labels is duplicated, one copy per
    label, so each label's triangles become a piece of their own (the drape, untouched,
    keeps them sewn: the new edges are seams).

    Parameters
    ----------
    V2 : (n, 2) float array
    F2 : (m, 3) int array
    labels : (m,) int array
        The new piece of each triangle.

    Returns
    -------
    V2 : (k, 2) float array
        The pattern vertices, one per (vertex, label) pair used.
    F2 : (m, 3) int array
    source : (k,) int array
        Each new vertex's vertex in the input.
    """
    F2 = np.asarray(F2, dtype=np.int64)
    lab = np.repeat(np.asarray(labels, dtype=np.int64), 3)
    key = F2.ravel() * (int(lab.max(initial=0)) + 1) + lab
    uniq, inv = np.unique(key, return_inverse=True)
    source = uniq // (int(lab.max(initial=0)) + 1)
    return np.asarray(V2, dtype=np.float64)[source], inv.reshape(F2.shape), source
