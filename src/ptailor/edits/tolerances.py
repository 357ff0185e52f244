"""Every tolerance and limit of the edits (:mod:`ptailor.edits`): how the drape deforms,
where a region splits, when a step warns.

Constants only, each with what it bounds, its unit and why that value (the rules and the
literals that may stay inline: :mod:`ptailor.tolerances`). Geometry has its own constants:
an edit never reads a naming rule's threshold (``ptailor.model.names``), so renaming rules
can never change a deformation (``tests/test_tolerances.py`` checks the imports).
"""

# --- how the rest of a garment follows an edit (ptailor.edits.follow) ---
#: A follow-up deformation in which strips sewn to an edited region grow by similarities
#: iterates up to this many times (a count; the energy's own stop ends it sooner): the
#: default 5 leave a 40 cm cuff 1.6 cm from a similarity of its pattern, 20 to convergence
#: 0.16 cm.
FOLLOW_SIMILAR_ITER = 40
#: A panel sewn to an edited region grows by similarities (a cuff below a widened sleeve, a
#: collar stand on a body) rather than as rigidly as possible when its pattern is a strip:
#: the rectangle with its pattern area and outline length is at least this many times as
#: long as it is wide (unitless). The same value as the naming rules' strip (a collar, a
#: waistband) by choice, not by import: the names may change without moving any drape.
FOLLOW_STRIP_ASPECT = 3.5
#: Singular-value ratio (unitless) below which the vertices of a group of panels apart from
#: the region count as collinear (or a point): its rigid motion is then a translation.
FOLLOW_COLLINEAR_REL = 1e-10

# --- surgery: shorten, cut (ptailor.edits.surgery, .cut, .pattern_distance) ---
#: Field values within this many mean edge lengths of zero snap to zero before splitting,
#: so a cut passing next to a vertex goes through it instead of making a sliver.
SPLIT_SNAP_REL = 1e-3
#: A cut or shorten that removes more than this fraction of a panel's pattern area
#: (relative) says so.
SURGERY_REMOVED_WARN = 0.5
#: A level-set crossing on a pattern edge is found when the field there is within this
#: fraction of the level (relative: near the rounding of the field's value) ...
PATTERN_LEVEL_TOL_REL = 1e-12
#: ... or when its bracket is at most this long (in the edge's parameter, 0 to 1: about 450
#: roundings of 1, below any position that matters) ...
PATTERN_BRACKET_MIN = 1e-13
#: ... or after this many steps (a count; regula falsi with the Illinois rule takes a few).
PATTERN_REFINE_STEPS = 100
#: A cut's corner (a sketch's inner point) within this many mean edge lengths of a vertex
#: (in the view) is that vertex, within it of an edge lies on that edge (the edge is split
#: there); else the triangle holding it is split in three at it. Half the split's snap
#: (``SPLIT_SNAP_REL``), so the split sees every such vertex on the cut.
CUT_CORNER_SNAP_REL = 5e-4
#: A piece a cut leaves whose pattern area is under this many of its panel's median
#: triangles (a count) is dropped, with a warning: a V-neck through a dress's strap left a
#: piece of one triangle (0.04 cm2); a real piece of a panel has many.
CUT_CRUMB_TRIANGLES = 4
#: A cut's view whose direction is within this (unitless: the sine of the angle) of the
#: garment's up takes the front as its image's up instead: the up seen along itself has no
#: direction.
CUT_VIEW_PARALLEL = 1e-9

# --- extend (ptailor.edits.extend) ---
#: Without ``clearance``, new rows keep this many of the opening's mean edge lengths from
#: the body.
EXTEND_CLEARANCE_EDGES = 0.5
#: Smoothing passes of the row directions tried before giving up on crossing rows (a count).
EXTEND_MAX_SMOOTHING = 200
#: ``measure: pattern``: a seam reaching the opening is continued straight when its
#: continuation is within this many degrees of the end edge's outward normal ...
EXTEND_SEAM_MAX_DEG = 75.0
#: ... a column's offset is searched out to 2^this ``by`` along its direction (a count of
#: doublings) ...
EXTEND_REACH_DOUBLINGS = 8
#: ... and placed by this many bisection steps (a count: 2^-60 of the reach, rounding).
EXTEND_BISECTION_STEPS = 60
#: Two unit normals (of the edges at an opening's vertex) whose sum is shorter than this
#: (unitless) point opposite ways: a cusp, where the vertex takes one edge's normal.
EXTEND_CUSP = 1e-6
#: A smoothed row direction (a weighted sum of unit vectors) shorter than this (unitless)
#: averages to nothing: the direction keeps its old value.
EXTEND_SMOOTH_ZERO = 1e-12
#: A new row's triangle must keep a signed area above this times the row height squared
#: (relative): a smaller one is folded or degenerate, and the row directions are smoothed
#: again.
EXTEND_ROW_AREA_MIN_REL = 1e-9
#: The extension is measured on the drape by a geodesic distance limited to this many times
#: ``by`` (unitless); a row pushed further out (by the body) is measured without a limit.
EXTEND_MEASURE_REACH_BY = 3.0
#: The surface's outward continuation at an opening is read from the cloth within this many
#: mean edge lengths (of the opening's triangles) behind it (unitless): one bent or flared row of a
#: simulated drape does not set the direction of the new rows alone ...
EXTEND_BAND_EDGES = 4.0
#: ... and a new row whose triangle's normal makes a cosine below this (unitless) with the
#: row before it (the opening's triangle for the first), or that grows against the
#: surface's continuation, is folded back: a warning naming the opening.
EXTEND_FOLD_COS = 0.0

# --- loosen, tighten (ptailor.edits.loosen) ---
#: The offset falls off to zero over a band this many times ``|by|`` wide (unitless; the
#: offset's slope stays below 0.75). Lengths of the garment only, never of its mesh: the
#: same garment at any resolution gets the same edit (a band of mean edge lengths made a 1x
#: tee's loosen 5.8 mm away from the same garment's at 4x).
LOOSEN_FALLOFF_BY = 2.0
#: The offset follows normals smoothed over this many times ``|by|`` (unitless) ...
LOOSEN_SMOOTH_BY = 1.0
#: ... by this many implicit diffusion steps at the first smoothing width (a count) ...
LOOSEN_SMOOTH_STEPS = 4
#: ... and this many smoothing widths, each twice the last, are tried before an offset is
#: refused (a count).
LOOSEN_SMOOTH_LEVELS = 3
#: The smoothed normals must keep this area-weighted mean cosine (unitless) to the raw ones
#: on every panel that moves (below it the smoothing is wider than the panel: a thin
#: sleeve's normals cancel out and leak in from the rest).
LOOSEN_NORMAL_AGREEMENT = 0.6
#: A refused offset probes these fractions of its ``by`` (unitless, largest first) and names
#: the first that passes: what the user can take instead.
LOOSEN_PROBE_FRACTIONS = (0.75, 0.5, 0.25, 0.1)
#: Lumped vertex mass floor of the smoothing, relative to the mean mass (vertices of
#: degenerate triangles only: their row keeps a positive diagonal).
LOOSEN_MASS_FLOOR_REL = 1e-9
#: ``girth:`` is measured at this many levels spanning the region along its axis (a count;
#: those whose section of the region is closed loops count, else all of them): their mean
#: stands for the mean over the region's height, falloff bands of ``2 by`` at its borders
#: included (12 levels sampled a 12 cm band's 1.2 cm falloff by one level each side) ...
LOOSEN_GIRTH_LEVELS = 24
#: ... the axis is the garment's up, or the region's tube axis where that lies more than
#: this many degrees from the up (a sleeve in a T-pose: its girths are across the arm).
LOOSEN_GIRTH_TUBE_DEG = 45.0

#: A silhouette's image rows are this many mean edge lengths high (unitless) ...
SILHOUETTE_ROW_EDGES = 1.5
#: ... an outline point matches when the sketch, in its row, is within this fraction of
#: the sketch's span (relative; and within its ring's half-width: a sketch never grabs the
#: far outline) ...
SILHOUETTE_MATCH_REL = 0.5
#: ... and a ring may be scaled down to this at the least (unitless; below it the outline
#: collapses).
SILHOUETTE_MIN_RING_SCALE = 0.05

# --- scale, scale_seam (ptailor.edits.scale, .scale_seam, .region) ---
#: ``axis: auto`` on a region that is no tube falls back to its longest extent; more than
#: this many degrees from the garment's up is a warning (ptailor.edits.scale).
AUTO_AXIS_UP_DEG = 30.0
#: ``scale`` with ``axis: auto`` scales each connected part of its region about its own
#: axis (both sleeves: each around its arm) when every part holds at least this fraction
#: of the region's triangles (relative); else the region as one.
REGION_PART_MIN = 0.1
#: A scale_seam ``fix`` that the part's scaling would move by more than this fraction of
#: the garment's size (relative) lies inside the scaled part: an error
#: (ptailor.edits.scale_seam).
FIX_INSIDE_REL = 0.005
#: A gather with no fixed end on its part (scale_seam ``around``) spreads its extra length
#: over a band along the seam this many times the seam line's mean distance from its centre
#: wide (unitless; ptailor.method.gather): a neckline's slashes reach about as far below it
#: as the neck is wide, an armhole's into the sleeve cap.
GATHER_BAND_REL = 1.0

#: With a ``--body``, a region's (or a seam line's) axis is the body's near it: the
#: direction of largest extent of this many nearest body vertices per garment point (a
#: count), the body part nearest to the points (along the arm for a sleeve).
BODY_AXIS_NEIGHBOURS = 16

# --- mirror, body (ptailor.edits.mirror, .body) ---
#: A ``{loop: k}`` opening's mirror is the loop whose centroid is nearest the mirrored
#: centroid, within this fraction of the loop's length (relative).
MIRROR_LOOP_DIST = 0.25
#: A body normal interpolated at a point (barycentric sum of unit vertex normals) shorter
#: than this (unitless) cancels out: the face's normal is taken instead.
BODY_NORMAL_ZERO = 1e-12
#: A body must enclose a volume: at least this fraction (unitless) of the volume of the sphere
#: of its surface area (the shared bodies 0.32, a cube 0.72, a sphere 1; a flat, doubled sheet 0).
BODY_MIN_ROUNDNESS = 0.02
#: Push-out rounds (a count): a point pushed out of one part of a body into another that
#: overlaps it (an arm into the torso) is pushed again, up to this many times in all.
BODY_PUSH_ROUNDS = 4
#: A body's separate pieces are told nested or crossing by this many of their vertices (a
#: count, seeded sample): all inside another piece, nested; some, crossing.
BODY_PIECE_SAMPLES = 64

# --- steps asked in points of measure (ptailor.edits.asks) ---
#: A step asked in a measure (``loosen girth:``, ``scale measure:``, ``shorten``/``extend``
#: ``to:``) is solved until its measure on the edited drape is within this of the asked
#: value (cm; a tape measure reads 1 mm, and the spec sheets' tolerances are 5 mm) ...
ASK_TOL_CM = 0.02
#: ... in at most this many applications of the step (a count: the first guess, then secant
#: steps; the offset, scale and cut are near linear in their parameter, so two do).
ASK_TRIES = 5
#: A step that ends further than this from its asked value (cm: a miss a spec sheet would
#: see) warns, naming both: the step moves the measure little (a hem cut for a sleeve's
#: length) or not in proportion.
ASK_WARN_CM = 0.1

# --- how much of a girth a region covers (ptailor.edits.coverage) ---
#: A girth edit (``loosen``, ``tighten``, ``scale direction: around``) whose region covers
#: less than this fraction (unitless) of the garment's closed sections at its levels warns:
#: the girth grows only there (a poncho's centre strips without its side panels: a third;
#: one of a tee's front and back: a half). 0.9 leaves room for a seam allowance's sliver of
#: another panel at a level and a waist seam that is not level.
GIRTH_COVERAGE_MIN = 0.9
#: ... measured at this many levels spanning the region along the girths' axis (a count:
#: a few, as a tape measure is laid at a few heights).
GIRTH_COVERAGE_LEVELS = 7

# --- a drape edited elsewhere (ptailor.edits.drape) ---
#: A panel of a drape edited in another tool keeps its outline shape (``boundary: auto``,
#: as under a recipe's uniform scale of whole panels) when the best similarity (rotation,
#: uniform scale, translation) of its triangles' corners leaves a root mean square residual
#: below this fraction (unitless) of the panel's radius. An OBJ written with nine significant
#: digits (ptailor's) and read back moves a 5 cm cuff 100 cm from the origin by up to 1e-7 of
#: its radius; a deformed panel (the as-rigid-as-possible follow-up of a step) moves by far
#: more than 1e-5.
EDITED_SIMILAR_REL = 1e-5
