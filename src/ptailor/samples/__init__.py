"""Procedurally generated garments for the demo, the tests and the benchmarks.

Every sample is a pure, deterministic function of its keyword-only options and returns a
:class:`ptailor.model.Garment` in centimetres. Conventions: y is up, z is front; pattern
(2D) triangles are counter-clockwise unless asked otherwise; seam vertices are one vertex in
the drape ``V3`` and one vertex per panel in the pattern ``V2``. Panels are quad grids, each
quad split into two triangles along alternating diagonals (a checkerboard).

The samples are *exact at their resolution*: a drape ring of ``n`` vertices is a regular
polygon whose perimeter is the requested circumference, and every pattern triangle is
congruent to its drape triangle (or stretched by exactly the stated factor), so intrinsic
scales are known in closed form.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ptailor.model.garment import Garment

__all__ = [
    "SAMPLES",
    "cone_skirt",
    "cylinder",
    "lantern_sleeve",
    "sample_for_triangles",
    "tseam_tube",
]

#: Gap between pattern panels laid out side by side, in cm.
PANEL_GAP = 5.0

_AXES = {"x": -1, "y": 0, "z": 1}


# ---------------------------------------------------------------------------------------
# private helpers
# ---------------------------------------------------------------------------------------


def _grid_faces(idx3: np.ndarray, idx2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
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


def _polygon_radius(circumference: float, n: int) -> float:
    """Circumradius of the regular ``n``-gon of perimeter ``circumference``."""
    return circumference / (2.0 * n * np.sin(np.pi / n))


def _rings(radii: np.ndarray, heights: np.ndarray, phi: np.ndarray) -> np.ndarray:
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


def _tube_indices(ring0: int, n_rows: int, n_around: int, v2_offset: int) -> tuple:
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


def _grid_2d(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Pattern vertices of a rectangular grid, row-major: ``(len(y) * len(x), 2)``."""
    X, Y = np.meshgrid(np.asarray(x, np.float64), np.asarray(y, np.float64))
    return np.stack([X, Y], axis=-1).reshape(-1, 2)


def _check_positive(**values: float) -> None:
    for name, value in values.items():
        if not (np.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be a positive finite number, got {value!r}")


def _check_count(name: str, value: int, minimum: int) -> None:
    if int(value) != value or value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")


def _garment(
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


# ---------------------------------------------------------------------------------------
# samples
# ---------------------------------------------------------------------------------------


def lantern_sleeve(
    *,
    circumference: float = 28.0,
    sleeve_length: float = 40.0,
    cuff_height: float = 8.0,
    cuff_ratio: float = 0.7,
    n_around: int = 48,
    n_sleeve: int = 40,
    n_cuff: int = 8,
    axis: str = "y",
) -> Garment:
    """The paper's lantern sleeve: a straight tube with an elastic cuff.

    The drape is a prism over a regular ``n_around``-gon of perimeter ``circumference``
    (so its radius is ``circumference / (2 n sin(pi / n))``, within ``pi^2 / (6 n^2)`` of
    ``circumference / 2 pi``). The cuff spans ``0 <= y <= cuff_height``, the sleeve
    ``cuff_height <= y <= cuff_height + sleeve_length``; they share the seam ring in the
    drape. Each panel is closed by a vertical seam with itself at the back (``z < 0``).

    The sleeve pattern is a ``circumference x sleeve_length`` rectangle, congruent triangle
    by triangle to the drape. The cuff pattern is ``circumference / cuff_ratio`` wide and
    ``cuff_height`` high: its drape is ``cuff_ratio`` times its pattern around and equal
    along. The cuff is laid out at the origin and the sleeve :data:`PANEL_GAP` to its right,
    both with their bottom edge on ``y = 0``; pattern x runs around, y up.

    Parameters
    ----------
    circumference : float
        Drape circumference (perimeter of the ring polygon), cm.
    sleeve_length, cuff_height : float
        Heights of the two panels, cm.
    cuff_ratio : float
        Drape / pattern length ratio around the cuff (< 1: elastic, gathered).
    n_around : int
        Quads around (drape vertices per ring), >= 3.
    n_sleeve, n_cuff : int
        Quad rows of each panel, >= 1.
    axis : {"x", "y", "z"}
        Direction of the tube's axis; ``"x"`` and ``"z"`` cyclically permute the drape's
        coordinates of the ``"y"`` sleeve (a rotation).

    Returns
    -------
    Garment
        ``2 n_around (n_sleeve + n_cuff)`` triangles, sleeve first; groups
        ``("sleeve", "cuff")``; ``V3`` has ``n_around (n_sleeve + n_cuff + 1)`` vertices,
        ``V2`` has ``(n_around + 1) (n_sleeve + n_cuff + 2)``. Its drape boundary loops are
        the armhole (top of the sleeve) and the cuff's bottom edge.
    """
    _check_positive(
        circumference=circumference,
        sleeve_length=sleeve_length,
        cuff_height=cuff_height,
        cuff_ratio=cuff_ratio,
    )
    _check_count("n_around", n_around, 3)
    _check_count("n_sleeve", n_sleeve, 1)
    _check_count("n_cuff", n_cuff, 1)
    if axis not in _AXES:
        raise ValueError(f"axis must be one of 'x', 'y', 'z', got {axis!r}")
    n, ns, nc = int(n_around), int(n_sleeve), int(n_cuff)

    # drape: rings 0..nc are the cuff, rings nc..nc+ns the sleeve (ring nc is the seam)
    radius = _polygon_radius(circumference, n)
    heights = np.concatenate(
        [
            cuff_height * np.arange(nc + 1) / nc,
            cuff_height + sleeve_length * np.arange(1, ns + 1) / ns,
        ]
    )
    phi = np.pi + 2.0 * np.pi * np.arange(n) / n
    V3 = _rings(np.full(heights.shape, radius), heights, phi)
    V3 = np.roll(V3, _AXES[axis], axis=1)

    # pattern: sleeve vertices first, then cuff
    cols = np.arange(n + 1) / n
    cuff_width = circumference / cuff_ratio
    V2_cuff = _grid_2d(cuff_width * cols, cuff_height * np.arange(nc + 1) / nc)
    V2_sleeve = _grid_2d(
        cuff_width + PANEL_GAP + circumference * cols, sleeve_length * np.arange(ns + 1) / ns
    )
    s3, s2 = _tube_indices(nc, ns, n, 0)
    c3, c2 = _tube_indices(0, nc, n, len(V2_sleeve))
    F3_s, F2_s = _grid_faces(s3, s2)
    F3_c, F2_c = _grid_faces(c3, c2)
    return _garment(V3, [F3_s, F3_c], [V2_sleeve, V2_cuff], [F2_s, F2_c], ("sleeve", "cuff"))


def cylinder(
    *,
    circumference: float = 30.0,
    height: float = 20.0,
    stretch: float = 1.0,
    n_around: int = 40,
    n_along: int = 16,
    mirrored: bool = False,
) -> Garment:
    """One tube panel closed by a seam with itself.

    The drape is a prism over a regular ``n_around``-gon of perimeter ``circumference``,
    y from 0 to ``height``, seam at the back (``z < 0``). The pattern is a
    ``circumference / stretch x height`` rectangle with its lower-left corner at the origin,
    so each drape triangle is ``stretch`` times its pattern triangle around and equal along.

    Parameters
    ----------
    circumference, height : float
        Drape circumference (polygon perimeter) and height, cm.
    stretch : float
        Drape / pattern length ratio around.
    n_around, n_along : int
        Quads around (>= 3) and along (>= 1).
    mirrored : bool
        Mirror the pattern in x (same drape, same faces), so every pattern triangle is
        clockwise: a mirrored panel.

    Returns
    -------
    Garment
        ``2 n_around n_along`` triangles in one group ``("tube",)``; ``V3`` has
        ``n_around (n_along + 1)`` vertices, ``V2`` has ``(n_around + 1) (n_along + 1)``.
    """
    _check_positive(circumference=circumference, height=height, stretch=stretch)
    _check_count("n_around", n_around, 3)
    _check_count("n_along", n_along, 1)
    n, na = int(n_around), int(n_along)
    radius = _polygon_radius(circumference, n)
    heights = height * np.arange(na + 1) / na
    phi = np.pi + 2.0 * np.pi * np.arange(n) / n
    V3 = _rings(np.full(heights.shape, radius), heights, phi)
    width = circumference / stretch
    x = width * np.arange(n + 1) / n
    if mirrored:
        x = width - x
    V2 = _grid_2d(x, heights)
    idx3, idx2 = _tube_indices(0, na, n, 0)
    F3, F2 = _grid_faces(idx3, idx2)
    return _garment(V3, [F3], [V2], [F2], ("tube",))


def cone_skirt(
    *,
    waist_radius: float = 12.0,
    hem_radius: float = 30.0,
    length: float = 60.0,
    n_around: int = 64,
    n_along: int = 30,
) -> Garment:
    """A developable cone skirt: front and back halves of a frustum, side seams at x = +-r.

    The drape is the frustum of a regular ``n_around``-gon pyramid (vertices on circles of
    the given radii), hem at ``y = 0`` and waist at ``y = sqrt(length^2 - (hem_radius -
    waist_radius)^2)``. The front panel is the ``z >= 0`` half, the back panel the ``z <= 0``
    half; they share the side-seam vertices at ``x = +-r`` in the drape.

    Each pattern is the exact development of its half of the polygonal frustum: the
    vertices of a ring lie on a circle about the development's apex, consecutive ones a
    fixed angle apart so that every chord equals the drape chord, and rows are
    ``length / n_along`` apart along the rays. Every pattern triangle is congruent to its
    drape triangle; a panel spans the angle ``n_around * arcsin(sin(pi / n_around) * (hem -
    waist) / length)`` (``pi * (hem - waist) / length`` in the limit), which is an annular
    sector for a cone and a rectangle when the radii are equal. The front panel's
    bounding box starts at the origin and the back lies :data:`PANEL_GAP` to its right.

    Parameters
    ----------
    waist_radius, hem_radius : float
        Radii of the waist (top) and hem (bottom) rings, cm.
    length : float
        Slant length from waist to hem along the surface, cm; larger than
        ``|hem_radius - waist_radius|``.
    n_around : int
        Quads around the whole skirt, even, >= 4 (``n_around / 2`` per panel).
    n_along : int
        Quad rows, >= 1.

    Returns
    -------
    Garment
        ``2 n_around n_along`` triangles, front first; groups ``("front", "back")``;
        ``V3`` has ``n_around (n_along + 1)`` vertices, ``V2`` has
        ``2 (n_around / 2 + 1) (n_along + 1)``.
    """
    _check_positive(waist_radius=waist_radius, hem_radius=hem_radius, length=length)
    _check_count("n_around", n_around, 4)
    _check_count("n_along", n_along, 1)
    if n_around % 2:
        raise ValueError(f"n_around must be even (two halves), got {n_around!r}")
    d = hem_radius - waist_radius
    if not length > abs(d):
        raise ValueError(
            f"length ({length!r}) must exceed |hem_radius - waist_radius| ({abs(d)!r})"
        )
    n, na, h = int(n_around), int(n_along), int(n_around) // 2
    t = np.arange(na + 1) / na
    radii = hem_radius - d * t  # ring 0 is the hem
    drop = np.sqrt(length * length - d * d)
    V3 = _rings(radii, drop * t, -0.5 * np.pi + 2.0 * np.pi * np.arange(n) / n)

    # development about the apex; written with sinc-type factors so the equal-radii
    # (cylinder) limit needs no special case and stays accurate near it
    sin_half = np.sin(np.pi / n)
    sigma = sin_half * d / length  # sin(alpha / 2), alpha = angle between columns
    alpha = 2.0 * np.arcsin(sigma)
    asinc = np.arcsin(sigma) / sigma if sigma != 0.0 else 1.0
    arc = (2.0 * radii * sin_half * asinc)[:, None]  # (na + 1, 1): angle / curvature
    s = (length * t)[:, None]  # slant distance from the hem
    k = (np.arange(h + 1) - 0.5 * h)[None, :]  # column, centred
    theta = k * alpha
    x = k * arc * np.sinc(theta / np.pi)
    y = s + k * arc * np.sin(0.5 * theta) * np.sinc(0.5 * theta / np.pi)
    panel2 = np.stack([x, y], axis=-1).reshape(-1, 2)
    panel2 = panel2 - panel2.min(axis=0)
    width = panel2[:, 0].max()
    V2_front = panel2
    V2_back = panel2 + np.array([width + PANEL_GAP, 0.0])

    rows = np.arange(na + 1)[:, None]
    cols = np.arange(h + 1)[None, :]
    local2 = rows * (h + 1) + cols
    front3 = rows * n + cols
    back3 = rows * n + (cols + h) % n
    F3_f, F2_f = _grid_faces(front3, local2)
    F3_b, F2_b = _grid_faces(back3, local2 + len(V2_front))
    return _garment(V3, [F3_f, F3_b], [V2_front, V2_back], [F2_f, F2_b], ("front", "back"))


def sample_for_triangles(n_triangles: int) -> Garment:
    """A default lantern sleeve refined to about ``n_triangles`` triangles.

    Keeps the default sleeve's balance of about as many quads around as rows (48 : 48) and
    its cuff at about a sixth of the rows, and picks the resolution whose triangle count
    ``2 n_around (n_sleeve + n_cuff)`` is closest to the request; within 5 % for any
    request of 100 triangles or more.

    Parameters
    ----------
    n_triangles : int
        Requested number of triangles, >= 12 (the coarsest sleeve).

    Returns
    -------
    Garment
        See :func:`lantern_sleeve`.
    """
    _check_count("n_triangles", n_triangles, 12)
    n_tri = int(n_triangles)
    # the default sleeve has 48 quads around per 48 rows (40 sleeve + 8 cuff)
    ideal = np.sqrt(n_tri / 2.0)
    cand = np.arange(max(3, int(0.7 * ideal)), max(4, int(1.4 * ideal) + 2))
    rows = np.maximum(2, np.rint(n_tri / (2.0 * cand))).astype(np.int64)
    err = np.abs(2 * cand * rows - n_tri)
    best = np.lexsort((np.abs(cand - ideal), err))[0]
    n_around, n_rows = int(cand[best]), int(rows[best])
    n_cuff = max(1, round(n_rows / 6))
    return lantern_sleeve(n_around=n_around, n_sleeve=n_rows - n_cuff, n_cuff=n_cuff)


def bodice(
    *,
    bust_radius: float = 15.0,
    waist_radius: float = 12.5,
    length: float = 40.0,
    n_around: int = 64,
    n_along: int = 24,
) -> Garment:
    """A plain sleeveless bodice: front and back halves of a tube narrowing to the waist.

    :func:`cone_skirt` upside down: the bust ring (``bust_radius``) at the top, the waist
    (``waist_radius``) at ``y = 0``, side seams at ``x = +-r``, each pattern panel the exact
    development of its half. The top opening is the neckline-to-be (a recipe cuts it
    deeper); the waist opening is the lowest, which ``ptailor inspect`` names ``hem``.

    Returns
    -------
    Garment
        Panels ``front`` and ``back``, in cm.
    """
    return cone_skirt(
        waist_radius=bust_radius,
        hem_radius=waist_radius,
        length=length,
        n_around=n_around,
        n_along=n_along,
    )


def tseam_tube(
    *,
    circumference: float = 60.0,
    height: float = 40.0,
    n_around: int = 24,
    n_along: int = 16,
    rows: tuple[int, int] = (4, 12),
    strip_width: float = 3.0,
    n_strip: int = 2,
) -> Garment:
    """A tube with a strip sewn onto its front along a line of interior edges (a T-seam).

    The tube is :func:`cylinder` (seam at the back). The strip is a ``strip_width`` wide
    rectangle whose one long edge is sewn onto the tube's front column of vertical grid
    edges from grid row ``rows[0]`` to ``rows[1]`` (a placket, a pleat, a ruffle); it stands
    out radially as a fin and its other long edge and both short ends are free. Each
    drape edge of the sewn line is then used by three faces: two of the tube (one pattern
    edge, inside the panel) and one of the strip. Both sides of the T-seam are
    ``height (rows[1] - rows[0]) / n_along`` long, and every pattern triangle is congruent
    to its drape triangle.

    Parameters
    ----------
    circumference, height : float
        The tube's circumference and height, cm.
    n_around, n_along : int
        Tube quads around (even, >= 4) and along (>= 2).
    rows : (int, int)
        First and last grid row of the sewn line, ``0 <= rows[0] < rows[1] <= n_along``; a
        line touching row 0 or ``n_along`` ends on the tube's hem or top.
    strip_width : float
        Width of the strip, cm.
    n_strip : int
        Strip quads across its width (>= 1).

    Returns
    -------
    Garment
        Panels ``("tube", "strip")`` in cm; the strip's pattern lies right of the tube's.
    """
    _check_positive(circumference=circumference, height=height, strip_width=strip_width)
    _check_count("n_around", n_around, 4)
    _check_count("n_along", n_along, 2)
    _check_count("n_strip", n_strip, 1)
    if int(n_around) % 2:
        raise ValueError(f"n_around must be even (the front column), got {n_around!r}")
    r0, r1 = (int(r) for r in rows)
    if not 0 <= r0 < r1 <= int(n_along):
        raise ValueError(f"rows must satisfy 0 <= rows[0] < rows[1] <= n_along, got {rows!r}")
    tube = cylinder(circumference=circumference, height=height, n_around=n_around, n_along=n_along)
    n, na, ns = int(n_around), int(n_along), int(n_strip)
    j0 = n // 2  # the front column: phi = 2 pi, +z
    heights = height * np.arange(r0, r1 + 1) / na
    radius = _polygon_radius(circumference, n)
    off = strip_width * np.arange(1, ns + 1) / ns
    # new drape vertices of the strip: radially out from the front column, row-major
    Vs = np.stack(
        [
            np.zeros((len(heights), ns)),
            np.broadcast_to(heights[:, None], (len(heights), ns)),
            radius + np.broadcast_to(off[None, :], (len(heights), ns)),
        ],
        axis=-1,
    ).reshape(-1, 3)
    n3 = len(tube.V3)
    line3 = (r0 + np.arange(r1 - r0 + 1)) * n + j0
    idx3 = np.concatenate(
        [line3[:, None], n3 + np.arange(len(Vs)).reshape(len(heights), ns)], axis=1
    )
    x0 = circumference + PANEL_GAP
    V2s = _grid_2d(x0 + strip_width * np.arange(ns + 1) / ns, heights)
    idx2 = len(tube.V2) + np.arange(len(V2s)).reshape(len(heights), ns + 1)
    F3s, F2s = _grid_faces(idx3, idx2)
    return _garment(
        np.concatenate([tube.V3, Vs]),
        [tube.F3, F3s],
        [tube.V2, V2s],
        [tube.F2, F2s],
        ("tube", "strip"),
    )


#: Samples by name, for the demo and the CLI.
SAMPLES: dict[str, Callable[..., Garment]] = {
    "lantern_sleeve": lantern_sleeve,
    "cylinder": cylinder,
    "cone_skirt": cone_skirt,
    "bodice": bodice,
}
