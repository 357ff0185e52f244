"""Pattern pieces through an adjustment: match CAD pieces to panels, carry their marks.

A CAD system's piece (outline, turn points, notches, grain line, internal lines, drill
holes) is matched to the panel of the triangulated pattern it outlines, carried through
the adjustment with its marks, and written back; panels no piece outlines get a piece
drawn from the mesh.

Modules
-------
match
    Which panel each CAD piece outlines, by position or by a rigid shape fit.
draw
    Pieces drawn from the mesh: outline, turn points, notches, grain line.
carry
    One piece's outline and marks carried to the adjusted pattern.
plan
    The pieces a run writes, planned on the input garment and carried through.
allowance
    Seam allowances by seam and opening: what each piece edge sews, its allowance.
"""

from ptailor.pieces.allowance import (
    PieceAllowance,
    allowance_names,
    check_allowance_names,
    piece_allowances,
)
from ptailor.pieces.carry import CarriedPiece, carry_piece, scale_piece, with_seam_allowance
from ptailor.pieces.draw import grain_directions, mesh_pieces
from ptailor.pieces.match import PieceMatch, match_pieces
from ptailor.pieces.plan import PiecePlan, adjusted_pieces, carry_plan, piece_plan, unfolded

__all__ = [
    "CarriedPiece",
    "PieceAllowance",
    "PieceMatch",
    "PiecePlan",
    "adjusted_pieces",
    "allowance_names",
    "carry_piece",
    "carry_plan",
    "check_allowance_names",
    "grain_directions",
    "match_pieces",
    "mesh_pieces",
    "piece_allowances",
    "piece_plan",
    "scale_piece",
    "unfolded",
    "with_seam_allowance",
]
