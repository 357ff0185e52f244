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
    # cells (i, j): i in [-nx, nx), j in [0, ny); in the body or in a sleeve
    ci, cj = np.meshgrid(np.arange(-nx, nx), np.arange(ny), indexing="ij")
    ci, cj = ci.ravel(), cj.ravel()
    in_body = (ci >= -nx_b) & (ci < nx_b)
    keep = in_body | (cj >= ny - ny_s)
    ci, cj = ci[keep], cj[keep]
    n_cells = len(ci)
    side = np.where(ci >= 0, 0, 1)  # 0: the wearer's left (+x)
    limb = ~((ci >= -nx_b) & (ci < nx_b))

    def vid(i: np.ndarray, j: np.ndarray) -> np.ndarray:  # grid vertex ids
        return (i + nx) * (ny + 1) + j

    corners = np.stack([vid(ci, cj), vid(ci + 1, cj), vid(ci + 1, cj + 1), vid(ci, cj + 1)], 1)
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
    # drape vertices: one per (layer, grid vertex), the seam ones shared by the layers
    n_grid = len(seam_v)
    layer_v = np.stack(
        [np.arange(n_grid), np.where(seam_v, np.arange(n_grid), n_grid + np.arange(n_grid))]
    )
    gi, gj = np.arange(n_grid) // (ny + 1) - nx, np.arange(n_grid) % (ny + 1)
    X, Y = gi * cell, gj * cell
    # the bulge: smooth in the distance to the nearest seam vertex (a pillow)
    sx, sy = X[seam_v], Y[seam_v]
    d = np.sqrt(((X[:, None] - sx[None]) ** 2 + (Y[:, None] - sy[None]) ** 2).min(axis=1))
    z = depth * np.sin(0.5 * np.pi * np.minimum(d / (4.0 * cell), 1.0))
    V3 = np.zeros((2 * n_grid, 3))
    V3[:n_grid] = np.stack([X, Y, z], 1)
    V3[n_grid:] = np.stack([X, Y, -z], 1)
    # triangles: front counter-clockwise seen from the front, back reversed
    quads = np.concatenate([corners[:, [0, 1, 2]], corners[:, [0, 2, 3]]])
    cell_of = np.concatenate([np.arange(n_cells)] * 2)
    F_front = layer_v[0][quads]
    F_back = layer_v[1][quads][:, ::-1]
    F3 = np.concatenate([F_front, F_back])
    layer = np.repeat([0, 1], len(quads))
    cells = np.concatenate([cell_of, cell_of])
    # pieces: body front/back, sleeve pieces by side and layer
    is_limb = limb[cells] & (sleeves != "none")
    piece = np.where(~is_limb, layer, 2 + 2 * side[cells] + layer)
    if sleeves == "one":
        piece = np.where(is_limb, 2 + 2 * side[cells], piece)
    # pattern vertices: one per (piece, layer, grid vertex); a one-piece sleeve's two layers
    # share the top of the arm (the fold)
    corner_grid = np.concatenate([quads, quads[:, ::-1]])
    top = (gj == ny)[corner_grid] & is_limb[:, None]
    lay_key = np.where(top & (sleeves == "one"), 0, layer[:, None])
    key = (piece[:, None] * 2 + lay_key) * n_grid + corner_grid
    uk, inv = np.unique(key.ravel(), return_inverse=True)
    F2 = inv.reshape(-1, 3)
    k_piece, k_layer, k_grid = uk // (2 * n_grid), (uk // n_grid) % 2, uk % n_grid
    px, py = X[k_grid], Y[k_grid]
    folded = (k_layer == 1) & (k_piece >= 2) & (sleeves == "one")
    U = np.where(k_layer == 1, -px, px)  # the back seen from behind: counter-clockwise
    U = np.where(folded, px, U)
    Vv = np.where(folded, 2.0 * length - py, py)  # a one-piece sleeve's back half above
    # lay the pieces side by side
    span = 2.0 * (nx + 2) * cell
    U = U + span * k_piece
    V2 = np.stack([U, Vv], 1)
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
