"""Cone samples: a developable cone skirt (front and back halves of a frustum, each
pattern its exact development) and the bodice (the same cone upside down).
"""

from __future__ import annotations

import numpy as np

from ptailor.model.garment import Garment
from ptailor.samples import grid


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
    grid.check_positive(waist_radius=waist_radius, hem_radius=hem_radius, length=length)
    grid.check_count("n_around", n_around, 4)
    grid.check_count("n_along", n_along, 1)
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
    V3 = grid.rings(radii, drop * t, -0.5 * np.pi + 2.0 * np.pi * np.arange(n) / n)

    panel2 = _half_development(radii, t, d=d, length=length, n=n)
    width = panel2[:, 0].max()
    V2_front = panel2
    V2_back = panel2 + np.array([width + grid.PANEL_GAP, 0.0])

    rows = np.arange(na + 1)[:, None]
    cols = np.arange(h + 1)[None, :]
    local2 = rows * (h + 1) + cols
    front3 = rows * n + cols
    back3 = rows * n + (cols + h) % n
    grids = [(front3, local2), (back3, local2 + len(V2_front))]
    return grid.assemble_grids(V3, grids, [V2_front, V2_back], ("front", "back"))


def _half_development(
    radii: np.ndarray, t: np.ndarray, *, d: float, length: float, n: int
) -> np.ndarray:
    """The exact development of half a frustum of a regular ``n``-gon pyramid.

    Parameters
    ----------
    radii : (R,) float array
        The rings' radii, ring 0 the hem.
    t : (R,) float array
        Each ring's share of the slant ``length`` from the hem (0 to 1).
    d : float
        Hem radius less waist radius.
    length : float
        Slant length from waist to hem.
    n : int
        Columns around the whole frustum (``n / 2 + 1`` vertices a ring in the half).

    Returns
    -------
    (R (n / 2 + 1), 2) float array
        Row-major (ring by ring), its bounding box starting at the origin.
    """
    h = n // 2
    # development about the apex; written with sinc-type factors so the equal-radii
    # (cylinder) limit needs no special case and stays accurate near it
    sin_half = np.sin(np.pi / n)
    sigma = sin_half * d / length  # sin(alpha / 2), alpha = angle between columns
    alpha = 2.0 * np.arcsin(sigma)
    asinc = np.arcsin(sigma) / sigma if sigma != 0.0 else 1.0
    arc = (2.0 * radii * sin_half * asinc)[:, None]  # (R, 1): angle / curvature
    s = (length * t)[:, None]  # slant distance from the hem
    k = (np.arange(h + 1) - 0.5 * h)[None, :]  # column, centred
    theta = k * alpha
    x = k * arc * np.sinc(theta / np.pi)
    y = s + k * arc * np.sin(0.5 * theta) * np.sinc(0.5 * theta / np.pi)
    panel2 = np.stack([x, y], axis=-1).reshape(-1, 2)
    return panel2 - panel2.min(axis=0)


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


def unnamed_skirt(**options: float) -> Garment:
    """:func:`cone_skirt` without panel names, as an export that carries no groups names
    it: ptailor names its panels from the drape (``skirt_front``, ``skirt_back``), so a
    recipe for skirts (``{panels: [skirt]}``) is tested on it as on a real dress.

    Parameters
    ----------
    **options
        :func:`cone_skirt`'s keyword-only options.
    """
    import dataclasses

    return dataclasses.replace(cone_skirt(**options), group_names=())


def gored_skirt(*, gores: int = 4, **options: float) -> Garment:
    """:func:`cone_skirt` cut into ``gores`` panels of equal angle around the body, without
    panel names (a skirt of 2, 4 or 6 gores as an export with no groups).

    The gore seams are at the angles ``2 pi k / gores`` from the wearer's left (the first on
    the left side), so an even count has side seams at +-x and, from 4 up, a centre-front
    and centre-back seam; each pattern piece is its part of the developed halves.

    Parameters
    ----------
    gores : int
        Panels: an even number, at least 2 (the cone skirt's front and back halves are cut
        further).
    **options
        :func:`cone_skirt`'s keyword-only options.
    """
    import dataclasses

    from ptailor.samples.grid import check_count, split_pattern

    check_count("gores", gores, 2)
    if gores % 2:
        raise ValueError(f"gores must be even (the front and back halves are cut), got {gores}")
    g = cone_skirt(**options)
    c = g.V3[g.F3].mean(axis=1)
    angle = np.mod(np.arctan2(c[:, 2], c[:, 0]), 2.0 * np.pi)
    lab = np.minimum((angle / (2.0 * np.pi / gores)).astype(np.int64), gores - 1)
    V2, F2, _ = split_pattern(g.V2, g.F2, lab)
    return dataclasses.replace(
        g, V2=V2, F2=F2, face_group=np.full(g.n_faces, -1, dtype=np.int64), group_names=()
    )


def halved_bodice(**options: float) -> Garment:
    """:func:`bodice` with its front cut in halves at the centre front (a tank top's
    ``front_left`` and ``front_right``) and no panel names.

    Parameters
    ----------
    **options
        :func:`bodice`'s keyword-only options.
    """
    import dataclasses

    from ptailor.samples.grid import split_pattern

    g = bodice(**options)
    c = g.V3[g.F3].mean(axis=1)
    lab = np.where(c[:, 2] < 0, 0, np.where(c[:, 0] >= 0, 1, 2))  # back, front left, right
    V2, F2, _ = split_pattern(g.V2, g.F2, lab)
    return dataclasses.replace(
        g, V2=V2, F2=F2, face_group=np.full(g.n_faces, -1, dtype=np.int64), group_names=()
    )
