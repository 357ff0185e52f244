"""A region that holds a trunk and its sleeves, split so each scales about its own axis.

``scale`` with ``axis: auto`` takes each connected part of its region about its own axis; a
whole shirt is one connected part whose normals avoid no one direction (no tube), and its
longest extent (across a T-pose's arms) is no axis of its body or its sleeves: a shirt made
20 % wider around came out +11.6 % at the chest and one sleeve 19 % longer. Split by the
garment's parts of the body (:mod:`ptailor.edits.parts`), the trunk scales about its own
axis and centroid, and each sleeve about its own axis, carried where the trunk's map takes
the sleeve's armhole (so the sleeve stays sewn on, its armhole ring moved as the trunk's).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ptailor.edits.parts import LIMB_ROLES
from ptailor.model.garment import Garment
from ptailor.model.structure import structure

__all__ = ["Piece", "limb_pieces"]


class Piece(NamedTuple):
    """One piece of a region to scale about its own axis.

    Attributes
    ----------
    faces : (k,) int array
        Its triangles.
    trunk : bool
        The trunk (True), or a limb carried by the trunk's map at its joint.
    joint : (j,) int array
        A limb's drape vertices shared with the trunk (empty for the trunk).
    """

    faces: np.ndarray
    trunk: bool
    joint: np.ndarray


def limb_pieces(garment: Garment, faces: np.ndarray) -> list[Piece]:
    """The region ``faces`` split into its trunk and its limbs (a sleeve with its cuff, one
    per side), trunk first; the whole region as one trunk where it holds no limb or nothing
    but limbs, or a limb shares no vertex with the trunk.

    Parameters
    ----------
    garment : Garment
    faces : (k,) int array
        A connected part of a region.

    Returns
    -------
    list of Piece
    """
    whole = [Piece(faces, True, np.zeros(0, dtype=np.int64))]
    st = structure(garment)
    lab, _ = st.panel_components
    lay = st.layout
    role = np.asarray(lay.role, dtype=object)
    side = np.asarray(lay.side, dtype=object)
    fp = lab[faces]
    limb = (fp >= 0) & np.isin(role[np.maximum(fp, 0)], LIMB_ROLES)
    if not limb.any() or limb.all():
        return whole
    trunk = faces[~limb]
    in_trunk = np.zeros(len(garment.V3), dtype=bool)
    in_trunk[garment.F3[trunk]] = True
    pieces = [whole[0]._replace(faces=trunk)]
    for s in np.unique(side[np.maximum(fp[limb], 0)]):  # a loop over the sides (two)
        mine = faces[limb & (side[np.maximum(fp, 0)] == s)]
        verts = np.unique(garment.F3[mine])
        joint = verts[in_trunk[verts]]
        if joint.size == 0:
            return whole
        pieces.append(Piece(mine, False, joint))
    return pieces
