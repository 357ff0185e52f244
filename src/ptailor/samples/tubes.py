"""Tube samples: the paper's lantern sleeve (a tube with an elastic cuff), a plain
cylinder, a sleeve of a requested triangle count, and a tube with a T-seam strip.
"""

from __future__ import annotations

import numpy as np

from ptailor.model.garment import Garment
from ptailor.samples import grid


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
    grid.check_positive(
        circumference=circumference,
        sleeve_length=sleeve_length,
        cuff_height=cuff_height,
        cuff_ratio=cuff_ratio,
    )
    grid.check_count("n_around", n_around, 3)
    grid.check_count("n_sleeve", n_sleeve, 1)
    grid.check_count("n_cuff", n_cuff, 1)
    if axis not in grid.AXES:
        raise ValueError(f"axis must be one of 'x', 'y', 'z', got {axis!r}")
    n, ns, nc = int(n_around), int(n_sleeve), int(n_cuff)

    # drape: rings 0..nc are the cuff, rings nc..nc+ns the sleeve (ring nc is the seam)
    heights = np.concatenate(
        [
            cuff_height * np.arange(nc + 1) / nc,
            cuff_height + sleeve_length * np.arange(1, ns + 1) / ns,
        ]
    )
    V3 = np.roll(grid.prism(circumference, heights, n), grid.AXES[axis], axis=1)

    V2_sleeve, V2_cuff = _lantern_pattern(
        circumference, sleeve_length, cuff_height, cuff_ratio, n=n, ns=ns, nc=nc
    )
    s3, s2 = grid.tube_indices(nc, ns, n, 0)
    c3, c2 = grid.tube_indices(0, nc, n, len(V2_sleeve))
    grids = [(s3, s2), (c3, c2)]
    return grid.assemble_grids(V3, grids, [V2_sleeve, V2_cuff], ("sleeve", "cuff"))


def _lantern_pattern(
    circumference: float,
    sleeve_length: float,
    cuff_height: float,
    cuff_ratio: float,
    *,
    n: int,
    ns: int,
    nc: int,
) -> tuple[np.ndarray, np.ndarray]:
    """The lantern sleeve's two pattern panels: the cuff (``circumference / cuff_ratio``
    wide) at the origin, the sleeve :data:`PANEL_GAP` to its right.

    Returns
    -------
    V2_sleeve : ((n + 1) (ns + 1), 2) float array
    V2_cuff : ((n + 1) (nc + 1), 2) float array
        Row-major grids, ``n`` columns around, ``ns`` and ``nc`` rows up.
    """
    # pattern: sleeve vertices first, then cuff
    cols = np.arange(n + 1) / n
    cuff_width = circumference / cuff_ratio
    V2_cuff = grid.points_2d(cuff_width * cols, cuff_height * np.arange(nc + 1) / nc)
    V2_sleeve = grid.points_2d(
        cuff_width + grid.PANEL_GAP + circumference * cols, sleeve_length * np.arange(ns + 1) / ns
    )
    return V2_sleeve, V2_cuff


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
    grid.check_positive(circumference=circumference, height=height, stretch=stretch)
    grid.check_count("n_around", n_around, 3)
    grid.check_count("n_along", n_along, 1)
    n, na = int(n_around), int(n_along)
    heights = height * np.arange(na + 1) / na
    V3 = grid.prism(circumference, heights, n)
    width = circumference / stretch
    x = width * np.arange(n + 1) / n
    if mirrored:
        x = width - x
    V2 = grid.points_2d(x, heights)
    return grid.assemble_grids(V3, [grid.tube_indices(0, na, n, 0)], [V2], ("tube",))


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
    grid.check_count("n_triangles", n_triangles, 12)
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
    grid.check_positive(circumference=circumference, height=height, strip_width=strip_width)
    grid.check_count("n_around", n_around, 4)
    grid.check_count("n_along", n_along, 2)
    grid.check_count("n_strip", n_strip, 1)
    if int(n_around) % 2:
        raise ValueError(f"n_around must be even (the front column), got {n_around!r}")
    r0, r1 = (int(r) for r in rows)
    if not 0 <= r0 < r1 <= int(n_along):
        raise ValueError(f"rows must satisfy 0 <= rows[0] < rows[1] <= n_along, got {rows!r}")
    tube = cylinder(circumference=circumference, height=height, n_around=n_around, n_along=n_along)
    n, na, ns = int(n_around), int(n_along), int(n_strip)
    j0 = n // 2  # the front column: phi = 2 pi, +z
    heights = height * np.arange(r0, r1 + 1) / na
    radius = grid.polygon_radius(circumference, n)
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
    x0 = circumference + grid.PANEL_GAP
    V2s = grid.points_2d(x0 + strip_width * np.arange(ns + 1) / ns, heights)
    idx2 = len(tube.V2) + np.arange(len(V2s)).reshape(len(heights), ns + 1)
    F3s, F2s = grid.quad_faces(idx3, idx2)
    return grid.assemble(
        np.concatenate([tube.V3, Vs]),
        [tube.F3, F3s],
        [tube.V2, V2s],
        [tube.F2, F2s],
        ("tube", "strip"),
    )
