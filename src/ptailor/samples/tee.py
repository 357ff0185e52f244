"""A flat tee: a T-shaped front and back sewn along their outline, the sleeves set in.

Not a drape off a simulator but a garment of the shape the naming rules must read: a torso
with a neckline, a hem and two sleeves out to the sides (T-pose), the sleeves one piece
(folded over the top of the arm) or two (front and back halves sewn along the top of the
arm), or none (a kimono tee, the sleeves cut with the body).
"""

from __future__ import annotations

import numpy as np

from ptailor.model.garment import Garment
from ptailor.samples.grid import check_positive

__all__ = ["flat_tee"]

_PIECES = ("front", "back", "sleeve_left_front", "sleeve_left_back", "sleeve_right_front",
           "sleeve_right_back")  # fmt: skip


def flat_tee(
    *,
    width: float = 48.0,
    length: float = 66.0,
    sleeve: float = 20.0,
    sleeve_width: float = 18.0,
    neck: float = 18.0,
    depth: float = 10.0,
    cell: float = 2.0,
    sleeves: str = "two",
) -> Garment:
    """A T-shaped tee in T-pose, y up, z front, centimetres.

    The front and back are the T (the body ``width`` x ``length``, the sleeves ``sleeve``
    long and ``sleeve_width`` deep at the top) on a grid of ``cell``: sewn along the sides,
    the underarms, the tops of the sleeves and the shoulders, open at the neck (``neck``
    wide), the hem and the cuffs. Each layer bulges ``depth`` off the seams (a pillow: the
    pattern is the flat T, the drape a little longer across).

    Parameters
    ----------
    width, length, sleeve, sleeve_width, neck, depth, cell : float
    sleeves : str
        ``two`` (each sleeve a front and a back piece, sewn along the top of the arm),
        ``one`` (each sleeve one piece, folded over the top of the arm, its underarm the
        seam) or ``none`` (the sleeves cut with the front and back).

    Returns
    -------
    Garment
        No panel names (an export without groups): ptailor names the panels from the drape.
    """
    check_positive(width=width, length=length, sleeve=sleeve, sleeve_width=sleeve_width,
                   neck=neck, depth=depth, cell=cell)  # fmt: skip
    if sleeves not in ("one", "two", "none"):
        raise ValueError(f"sleeves must be one, two or none, got {sleeves!r}")
    nx_b, ny = round(width / (2 * cell)), round(length / cell)
    nx_s, ny_s, nn = round(sleeve / cell), round(sleeve_width / cell), round(neck / (2 * cell))
    nx = nx_b + nx_s  # half-width in cells
    ci, cj = _t_cells(nx=nx, nx_b=nx_b, ny=ny, ny_s=ny_s)
    side = np.where(ci >= 0, 0, 1)  # 0: the wearer's left (+x)
    limb = ~((ci >= -nx_b) & (ci < nx_b))
    corners = _cell_corners(ci, cj, nx=nx, ny=ny)
    seam_v = _seam_vertices(corners, nx=nx, ny=ny, nn=nn)
    n_grid = len(seam_v)
    gi, gj = np.arange(n_grid) // (ny + 1) - nx, np.arange(n_grid) % (ny + 1)
    X, Y = gi * cell, gj * cell
    V3, layer_v = _pillow_drape(X, Y, seam_v, depth=depth, cell=cell)
    # triangles: front counter-clockwise seen from the front, back reversed
    quads = np.concatenate([corners[:, [0, 1, 2]], corners[:, [0, 2, 3]]])
    cell_of = np.concatenate([np.arange(len(ci))] * 2)
    F_front = layer_v[0][quads]
    F_back = layer_v[1][quads][:, ::-1]
    F3 = np.concatenate([F_front, F_back])
    layer = np.repeat([0, 1], len(quads))
    cells = np.concatenate([cell_of, cell_of])
    is_limb = limb[cells] & (sleeves != "none")
    piece = _face_pieces(layer, side[cells], is_limb, one_piece=sleeves == "one")
    corner_grid = np.concatenate([quads, quads[:, ::-1]])
    V2, F2 = _flat_pattern(
        corner_grid,
        piece,
        layer,
        (gj == ny)[corner_grid] & is_limb[:, None],
        one_piece=sleeves == "one",
        X=X,
        Y=Y,
        length=length,
        span=2.0 * (nx + 2) * cell,  # the pieces side by side
    )
    used, F3 = np.unique(F3, return_inverse=True)  # the drape's vertices the triangles use
    V3, F3 = V3[used], F3.reshape(-1, 3)
    return Garment(
        V3=V3,
        F3=F3.astype(np.int64),
        V2=V2,
        F2=F2.astype(np.int64),
        face_group=np.full(len(F3), -1, dtype=np.int64),
        group_names=(),
    )


def _t_cells(*, nx: int, nx_b: int, ny: int, ny_s: int) -> tuple[np.ndarray, np.ndarray]:
    """The grid cells of the T: ``(i, j)`` with ``i`` in ``[-nx, nx)``, ``j`` in
    ``[0, ny)``, in the body (``-nx_b <= i < nx_b``) or in a sleeve (the top ``ny_s`` rows).

    Returns
    -------
    ci, cj : (c,) int arrays
    """
    ci, cj = np.meshgrid(np.arange(-nx, nx), np.arange(ny), indexing="ij")
    ci, cj = ci.ravel(), cj.ravel()
    in_body = (ci >= -nx_b) & (ci < nx_b)
    keep = in_body | (cj >= ny - ny_s)
    return ci[keep], cj[keep]


def _cell_corners(ci: np.ndarray, cj: np.ndarray, *, nx: int, ny: int) -> np.ndarray:
    """The grid vertex ids of each cell's corners, counter-clockwise from the lower left.

    Parameters
    ----------
    ci, cj : (c,) int arrays
        The cells (:func:`_t_cells`); grid vertex ``(i, j)`` is ``(i + nx) (ny + 1) + j``.

    Returns
    -------
    (c, 4) int array
    """

    def vid(i: np.ndarray, j: np.ndarray) -> np.ndarray:  # grid vertex ids
        return (i + nx) * (ny + 1) + j

    return np.stack([vid(ci, cj), vid(ci + 1, cj), vid(ci + 1, cj + 1), vid(ci, cj + 1)], 1)


def _seam_vertices(corners: np.ndarray, *, nx: int, ny: int, nn: int) -> np.ndarray:
    """Which grid vertices are sewn: on the T's boundary but not on an opening (the hem,
    the cuffs, the neckline ``nn`` cells either side of the centre).

    Parameters
    ----------
    corners : (c, 4) int array
        :func:`_cell_corners`.
    nx, ny, nn : int
        Half-width and height of the grid, half-width of the neckline, in cells.

    Returns
    -------
    ((2 nx + 1) (ny + 1),) bool array
    """
    # boundary edges of the T and which of them are openings
    e = np.concatenate(
        [corners[:, [0, 1]], corners[:, [1, 2]], corners[:, [2, 3]], corners[:, [3, 0]]]
    )
    key = np.sort(e, axis=1)
    uniq, count = np.unique(key, axis=0, return_counts=True)
    bnd = uniq[count == 1]
    gx = bnd // (ny + 1) - nx  # grid i of both ends
    gy = bnd % (ny + 1)
    hem = (gy == 0).all(1)
    cuff = (np.abs(gx) == nx).all(1)
    neckline = (gy == ny).all(1) & (np.abs(gx) <= nn).all(1)
    seam_v = np.zeros((2 * nx + 1) * (ny + 1), dtype=bool)
    seam_v[bnd[~(hem | cuff | neckline)].ravel()] = True
    return seam_v


def _pillow_drape(
    X: np.ndarray, Y: np.ndarray, seam_v: np.ndarray, *, depth: float, cell: float
) -> tuple[np.ndarray, np.ndarray]:
    """The drape of the two layers, each bulging ``depth`` off the seams (a pillow).

    Parameters
    ----------
    X, Y : (g,) float arrays
        The grid vertices' positions.
    seam_v : (g,) bool array
        :func:`_seam_vertices`.
    depth, cell : float

    Returns
    -------
    V3 : (2 g, 3) float array
        The front layer's grid vertices (z >= 0), then the back's.
    layer_v : (2, g) int array
        Each layer's drape vertex of a grid vertex: the seam ones shared by the layers (the
        front's).
    """
    # drape vertices: one per (layer, grid vertex), the seam ones shared by the layers
    n_grid = len(seam_v)
    layer_v = np.stack(
        [np.arange(n_grid), np.where(seam_v, np.arange(n_grid), n_grid + np.arange(n_grid))]
    )
    # the bulge: smooth in the distance to the nearest seam vertex (a pillow)
    sx, sy = X[seam_v], Y[seam_v]
    d = np.sqrt(((X[:, None] - sx[None]) ** 2 + (Y[:, None] - sy[None]) ** 2).min(axis=1))
    z = depth * np.sin(0.5 * np.pi * np.minimum(d / (4.0 * cell), 1.0))
    V3 = np.zeros((2 * n_grid, 3))
    V3[:n_grid] = np.stack([X, Y, z], 1)
    V3[n_grid:] = np.stack([X, Y, -z], 1)
    return V3, layer_v


def _face_pieces(
    layer: np.ndarray, side: np.ndarray, is_limb: np.ndarray, *, one_piece: bool
) -> np.ndarray:
    """Each triangle's piece: 0 the front, 1 the back, ``2 + 2 side + layer`` a sleeve's
    half (``2 + 2 side`` for a one-piece sleeve), as in :data:`_PIECES`.

    Parameters
    ----------
    layer, side : (f,) int arrays
        0 the front layer / the wearer's left, 1 the back / the right.
    is_limb : (f,) bool array
        The triangle is cut as a sleeve.
    """
    piece = np.where(~is_limb, layer, 2 + 2 * side + layer)
    if one_piece:
        piece = np.where(is_limb, 2 + 2 * side, piece)
    return piece


def _flat_pattern(
    corner_grid: np.ndarray,
    piece: np.ndarray,
    layer: np.ndarray,
    arm_top: np.ndarray,
    *,
    one_piece: bool,
    X: np.ndarray,
    Y: np.ndarray,
    length: float,
    span: float,
) -> tuple[np.ndarray, np.ndarray]:
    """The pattern: one vertex per (piece, layer, grid vertex), the pieces ``span`` apart.

    Parameters
    ----------
    corner_grid : (f, 3) int array
        Each triangle's grid vertices, counter-clockwise in the pattern.
    piece, layer : (f,) int arrays
        :func:`_face_pieces` and the layer (0 front, 1 back).
    arm_top : (f, 3) bool array
        The corner lies on the top of a sleeve.
    one_piece : bool
        The sleeves are one piece each, folded over the top of the arm.
    X, Y : (g,) float arrays
        The grid vertices' positions.
    length : float
        The tee's length (a one-piece sleeve's back half goes above it, mirrored).
    span : float

    Returns
    -------
    V2 : (v, 2) float array
    F2 : (f, 3) int array
    """
    # pattern vertices: one per (piece, layer, grid vertex); a one-piece sleeve's two layers
    # share the top of the arm (the fold)
    n_grid = len(X)
    lay_key = np.where(arm_top & one_piece, 0, layer[:, None])
    key = (piece[:, None] * 2 + lay_key) * n_grid + corner_grid
    uk, inv = np.unique(key.ravel(), return_inverse=True)
    F2 = inv.reshape(-1, 3)
    k_piece, k_layer, k_grid = uk // (2 * n_grid), (uk // n_grid) % 2, uk % n_grid
    px, py = X[k_grid], Y[k_grid]
    folded = (k_layer == 1) & (k_piece >= 2) & one_piece
    U = np.where(k_layer == 1, -px, px)  # the back seen from behind: counter-clockwise
    U = np.where(folded, px, U)
    Vv = np.where(folded, 2.0 * length - py, py)  # a one-piece sleeve's back half above
    # lay the pieces side by side
    U = U + span * k_piece
    return np.stack([U, Vv], 1), F2
