"""Every tolerance and limit of the garment model (:mod:`ptailor.model`): intake and repair,
the frame, polylines, openings, the sagittal plane, seam lines.

Constants only, each with what it bounds, its unit and why that value (the rules and the
literals that may stay inline: :mod:`ptailor.tolerances`). The naming rules'
(``ptailor.model.names``) are theirs until that package is rewritten; an edit never reads
a naming threshold (:mod:`ptailor.edits.tolerances` has the edits' own).
"""

# --- intake: repair, validation, units (ptailor.model.repair, .validate, .unit_ratio, .size)
#: A triangle whose area is at most this times the squared bounding-box size of the
#: referenced vertices (relative) is degenerate: an area near rounding is no area.
ZERO_AREA_REL = 1e-12
#: ``--weld auto`` (and a weld without a distance) merges drape vertices closer than this
#: fraction of the mean drape edge length (relative). Measured: the shortest edge of the
#: shared garments is 0.24-0.66 of their mean, and no two of their referenced vertices are
#: within 0.1.
WELD_REL = 1e-3
#: Points count as clearly apart (a weld that merges nothing, decided without the exact
#: pairs) only beyond the weld distance grown by this fraction (relative) ...
REPAIR_APART_MARGIN_REL = 1e-6
#: ... plus this fraction of the largest coordinate (relative: a projection's rounding is
#: about 1e-16 of it, so 1e-9 is far above rounding and far below a weld distance).
REPAIR_APART_ROUNDING_REL = 1e-9
#: A garment whose median pattern/drape edge length ratio lies outside these bounds
#: (unitless) has its units wrong (elastic and gathered parts measure about 0.7-1.4).
UNIT_RATIO_RANGE = (0.5, 2.0)
#: Of the units that make a garment of human size, the one that makes it nearest this
#: size (cm: the drape's largest extent, or its largest piece) is proposed first.
UNIT_GUESS_TYPICAL_CM = 70.0

# --- the frame (ptailor.model.frame) ---
#: A frame's front whose part perpendicular to up is shorter than this fraction of its
#: length (unitless) is parallel to up (ptailor.model.frame.Frame): no side can be told.
FRAME_PARALLEL = 1e-9

# --- polylines (ptailor.model.polyline) ---
#: Consecutive outline points closer than this fraction of the outline's extent (relative)
#: are one point: rounding, not a segment.
POLYLINE_DUPLICATE_REL = 1e-12
#: A seam-allowance corner whose two edges turn back on each other (``|m|^2 / 2`` of the
#: summed unit normals at most this, unitless) gets no mitre: the mitre's direction is
#: undefined there (a bevel follows from MITER_LIMIT).
MITER_OPPOSED = 1e-12
#: Outline points closer to a fold line than this fraction of the outline's diagonal
#: (relative) lie on the fold (a piece cut on the fold unfolds about them): the fold line is
#: drawn on the piece's edge, so its points lie on it up to the file's precision.
FOLD_ON_LINE_REL = 1e-3

# --- openings: boundary loops named from geometry (ptailor.model.openings) ---
#: A loop shorter than this fraction of the longest loop (relative) is a mesh defect,
#: never named.
OPENING_MIN_REL_LENGTH = 0.05
#: A loop is "horizontal" when its plane normal's cosine to the up axis is at least this
#: (unitless: within 60 degrees).
OPENING_HORIZONTAL_COS = 0.5
#: A lone tube is a limb when its two loops are at least this many times the longer loop's
#: length apart (unitless).
OPENING_LIMB_LENGTH = 1.0
#: Minimum height of the band below the side loops where the torso is measured (relative to
#: the garment's height).
OPENING_BAND_REL = 0.05

# --- the sagittal plane (ptailor.model.symmetry) ---
#: Fraction of the worst pairs (largest mirror distance) left out of each plane update
#: (relative: asymmetric details do not tilt the plane).
SYMMETRY_TRIM = 0.1
#: Weight of the point-to-point term next to the point-to-plane one in the plane fit
#: (unitless): small enough for fast point-to-plane convergence, enough to pin directions
#: the surface's tangent planes leave free (turning a surface of revolution about its axis).
SYMMETRY_MU = 0.1
#: Levenberg-Marquardt damping of the plane update, relative to the normal matrix diagonal.
SYMMETRY_DAMP = 1e-6
#: Largest turn of the normal per update (radians, about): a careful first step from a
#: poor start.
SYMMETRY_MAX_TURN = 0.2
#: Mirrored vertices within this fraction of the surface's size (relative) of a vertex are
#: on the surface (their distance to it is taken as to the vertex: rounding, about 1e-15 of
#: it).
SYMMETRY_EXACT = 1e-12
#: The plane fit stops when an update moves the normal plus the offset over the surface's
#: size by less than this (unitless: near rounding).
SYMMETRY_STILL = 1e-13
#: ICP iterations of the plane fit at most (a count: a skirt tilted 8 degrees converges in
#: five; the fit stops earlier once the plane no longer moves).
SYMMETRY_ITERATIONS = 20
#: Panels are mirror images when their mirrored centroids are closer than this fraction of
#: the square root of the larger panel's area (relative) ...
SYMMETRY_PANEL_DIST = 0.25
#: ... and their areas differ by less than this fraction of the larger one (relative).
SYMMETRY_PANEL_AREA = 0.2

# --- seam lines (ptailor.model.seam_lines) ---
#: A seam of the scaled part continues a scale_seam's seam line where it leaves their
#: shared end vertex within this many degrees of straight on (ptailor.edits.scale_seam).
SEAM_LINE_TURN_DEG = 60.0
