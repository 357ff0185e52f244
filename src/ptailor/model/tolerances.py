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

# --- polylines (ptailor.model.polyline, ptailor.model.offset) ---
#: Consecutive outline points closer than this fraction of the outline's extent (relative)
#: are one point: rounding, not a segment.
POLYLINE_DUPLICATE_REL = 1e-12
#: A seam-allowance corner whose two edges' unit directions have a cross product at most
#: this (unitless: the sine of the turn) is straight (ptailor.model.offset): no mitre point
#: (the offset lines are parallel), and a wedge joins its two strips (a turn of a few ulps
#: either way would leave them touching along a line only, a slit in GEOS's union).
MITER_PARALLEL = 1e-12
#: A cut line's points closer than this fraction of its diagonal (relative) to the line
#: through their neighbours are dropped (Douglas-Peucker, topology kept): the collinear
#: points a union of strips leaves, far below a plotter's step (1e-9 of 1 m: 1 nm).
OFFSET_SIMPLIFY_REL = 1e-9
#: The grid a per-edge cut line's union is computed on, as a fraction of the outline's
#: diagonal (relative; rounded down to a power of ten): GEOS's floating-point union of many
#: thin strips can lose one (measured on a 16x garment); on a grid it is exact. 1e-9 of
#: 1 m is 1 nm, far below any drawing.
OFFSET_GRID_REL = 1e-9
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
#: A loop's end within this fraction of the garment's width (relative: rounding, which grows
#: with the distance from the origin) of the centre line touches it: the loop is on the side
#: it reaches into, a loop within it on both ends is centred (a strip sewn on the centre
#: front once changed its side with the garment's position).
OPENING_ON_LINE = 1e-9

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

# --- names from geometry (ptailor.model.names: roles, seam_names) ---
#: A strip is at least this long for its width (unitless: the rectangle with the panel's
#: pattern's area and outline length). The edits' own strip test is ptailor.edits.tolerances'.
NAMES_STRIP_ASPECT = 3.5
#: A strip's long side lies along an opening when this fraction of its length touches it.
NAMES_STRIP_TOUCH = 0.4
#: A pattern panel's width is read from its boundary sampled at its vertices and this many
#: points between them on every edge (a count: a one-triangle strip's width to 1/5 of an edge).
NAMES_EDGE_SAMPLES = 4
#: The widest width is sought among the triangles at least this fraction (unitless) of the
#: panel's farthest along the mesh's edges from its boundary (edge paths on a triangle mesh are
#: at most a few percent longer than straight lines; 0.8 leaves room for 25 %).
NAMES_WIDTH_CANDIDATES = 0.8
#: A panel straddles the centre line when its shorter reach across it is this fraction of
#: its longer one.
NAMES_CENTRED = 1.0 / 3.0
#: A panel lies in the centre plane when it reaches no further across it than this fraction
#: of the garment's width (relative: rounding of coordinates far from the origin).
NAMES_ON_LINE = 1e-9
#: A panel is named as going around the body (a tube) only when it holds at least this
#: share of its tier's body area: a tee's front whose side seams sit far back still shares
#: the tier with its back, and is the front.
NAMES_WRAP_SHARE = 0.8
#: A seam is vertical when the up component of its principal direction is at least this
#: (a cosine: 37 degrees from up) ...
NAMES_VERTICAL = 0.8
#: ... level when at most this (a cosine: 53 degrees); in between (a diagonal seam, where a
#: mirror pair could fall on both sides of one threshold) it is neither.
NAMES_LEVEL = 0.6
#: A front/back seam in this top fraction of its tier, not vertical, is a shoulder seam.
NAMES_SHOULDER = 0.75
#: A seam between two fronts (backs) is a centre seam when its midpoint is this close to the
#: centre line (fraction of the tier's half-width).
NAMES_CENTRE_SEAM = 0.15
#: Seams of one name are split at their median along an axis (the middle one of an odd count
#: ``middle``: the bare name is the stem of the others, their seam line's name) when the
#: widest gap between them is less than this times the next.
NAMES_EVEN_GAPS = 1.5
#: A seam's mirror image lies this near its mirrored midpoint (fraction of the distance
#: between the two midpoints, twice the distance from the centre line).
NAMES_MIRROR_NEAR = 0.25
