"""Every numeric tolerance and limit, named in one of five modules: this one and one per
package that has many of its own (the naming rules keep theirs for now).

- ``ptailor.tolerances`` (this module): the shared guards, geometry, pattern pieces, what
  ptailor reads (input bounds), numeric safety, recipes, outputs and batch,
  specifications, the report.
- :mod:`ptailor.model.tolerances`: intake, the frame, polylines, openings, the sagittal
  plane, seam lines.
- :mod:`ptailor.method.tolerances`: the stitching, the 3D deformation, rotations, geodesic
  distance, transfer.
- :mod:`ptailor.edits.tolerances`: how the drape deforms and splits in each edit.
- :mod:`ptailor.verify.tolerances`: the re-drape check.
- ``ptailor.model.names``: the naming rules keep theirs while that package is rewritten.

Every constant has a ``#:`` comment: what it bounds, its unit (cm, bytes, seconds, degrees,
radians; *relative*: a fraction of a size the comment names; *unitless*: a cosine, a
ratio, a barycentric coordinate; *a count*) and why that value. Code reads a constant as
an attribute (``tol.ROUNDING_REL``, ``method_tol.ARAP_STEP_TOL``), so a test may patch it.
No other module defines a module-level numeric constant (``tests/test_tolerances.py``,
which lists the few that are not tolerances), and geometry never reads a naming rule's
threshold: an edit's constants are its own, so a new naming rule cannot move a drape.

A literal that decides something (``x < 1e-9``, ``d > 0.05 * size``) is named here. These
may stay inline, as they decide nothing a tolerance would:

- arithmetic: ``0.5 *``, ``2.0 *``, ``/ 3.0`` (a centroid), ``/ 12.0`` (a segment's second
  moment), ``% 360.0``, unit factors (``2.54``), percentiles that define a statistic
  (``np.percentile(x, 95)``: the report's p95), a perpendicular picked away from an axis
  (``abs(n[0]) < 0.9``), an ``np.arange`` end nudged past its last step (``+ 1e-9``), the
  ``n ** 3 < 2^63`` bound of an int64 key;
- guards: a divisor's floor ``max(d, TINY)`` where ``d`` is zero only when the numerator
  is too (:data:`TINY` wherever it repeats; a guard used once with another floor,
  ``max(size, 1e-9)``, stays), a floor that keeps a tolerance positive at zero size
  (``+ 1e-12``), a clip that keeps a value off a singular end (``1.0 - 1e-12``), candidates
  rounded before they are compared (``np.round(cand, 9)``);
- drawing: fonts, gaps, strokes, dashes, figure and colour-bar placement of the previews
  and pictures (``ptailor.formats.sheet``, ``.footer``, ``.svg``, ``.png``,
  ``.dxf.writer``'s text, ``ptailor.verify.picture``): a picture's layout, not a result;
- the sizes of the generated sample garments (``ptailor.samples``) and the demo's;
- how much of a list a message quotes (the first 3 or 5 names, 200 characters);
- work splitting that changes the time, never a result: chunk sizes, a sort or a select by
  size, size groups of an exact search (``ptailor.method.transfer``);
- a keyword default that sets a resolution, documented in its signature (samples per
  specification edge, ``outline(per_edge=64)``; a picture's camera angles);
- the fields of a settings dataclass (:class:`ptailor.verify.engine.Settings`), each
  documented with its unit there: its fields are the one place their defaults are given,
  like a recipe step's.
"""

# --- shared guards: the same value for the same reason, wherever it repeats ---
#: Division guard (in the divisor's unit): ``x / max(d, TINY)`` where ``d`` is zero only
#: when ``x`` is too (a zero-length edge, an empty panel). Far below any length, area or
#: weight ptailor computes, yet a normal double (the smallest is 2.2e-308), so the quotient
#: is zero, not NaN, for a zero numerator.
TINY = 1e-300
#: A penalty or cost larger than any real one (unitless), still finite so that sums and
#: comparisons stay ordinary numbers (an arc fit's wrong-side candidate).
HUGE = 1e300
#: Cost of an infeasible pair in an assignment (unitless): far above the real costs
#: (relative distances and areas, well below 1; a pair past its threshold is infeasible),
#: so a pair at this cost is never chosen over a feasible one, and ``cost < COST_NONE``
#: tells them apart (the sagittal plane's panel pairs, pieces to panels, specification
#: panels to panels).
COST_NONE = 1e6
#: Two values computed along different float paths from the same data are equal when they
#: differ by at most this fraction of the size they are measured against (relative): sums
#: over a garment's up to millions of terms round to about 1e-16 times their count, while
#: a real difference on a garment (a micrometre on a metre) is 1e-6. Ties, "unchanged",
#: zero-length and flat tests, and slack on a box or a search radius use it.
ROUNDING_REL = 1e-9

# --- geometry (ptailor.geometry) ---
#: A Bezier foot's Newton step falls back to Gauss-Newton where the full Newton curvature is
#: at most this fraction of the Gauss-Newton one (relative): not a descent there.
CURVE_NEWTON_CURVATURE_REL = 1e-12
#: Newton (or Gauss-Newton) steps per foot of a point on a Bezier edge (a count), from the
#: nearer of the previous foot and the nearest of 257 samples: quadratic convergence from
#: there reaches rounding in a few.
CURVE_FOOT_STEPS = 6
#: ``scipy.optimize.least_squares``'s ``xtol``, ``ftol`` and ``gtol`` when an arc's centre
#: is fitted (relative): near the double's resolution (2.2e-16), so the fit stops when it
#: stalls, not at scipy's default 1e-8.
CURVE_ARC_FIT_TOL = 1e-15
#: An arc's radius is grown by this fraction (relative) before its flags are tried: a
#: semicircle's radius, rounded below half the chord, would be grown to it, where the two
#: candidate centres coincide and the flags tell nothing.
CURVE_ARC_RADIUS_GROW_REL = 1e-12

# Pattern pieces (ptailor.pieces, ptailor.model.polyline)
#: An outline point where the outline turns by more than this is a turn point (corner).
CORNER_DEG = 30.0
#: A seam-allowance corner is mitred unless the mitre would reach further than this many
#: allowances from the corner; then it is clipped there (GEOS's mitre limit, the same ratio).
MITER_LIMIT = 4.0
#: A DXF piece matches a panel where it lies when the mean distance between their outlines
#: is below this fraction of the piece's bounding-box diagonal ...
PIECE_MATCH_REL = 0.01
#: ... and, when moved, after the best rigid fit (rotation, reflection, translation) when
#: its area is within this fraction of the panel's.
PIECE_AREA_REL = 0.1
#: Match costs (relative to the piece's diagonal) closer than this are a tie, and a tie goes
#: to the panel with the piece's name (a pattern whose panels overlap, like tee6's four
#: sleeves at one spot, or identical sleeve pieces matched by shape).
PIECE_TIE_REL = 1e-6
#: A DXF piece's cut line may lie this far (cm, on average) outside the drape's mesh of the
#: sew line: a seam allowance (both thresholds above widen by it).
PIECE_ALLOWANCE_CM = 2.5
#: A construction mark further than this fraction of the piece diagonal (beyond the
#: outline's own distance from the mesh) from every remaining triangle was cut away.
MARK_KEEP_REL = 0.002
#: A surface is tube-like (:func:`ptailor.geometry.tube_axis.tube_axis`: a panel's grain
#: follows its own axis, not the body's up; ``axis: auto`` of an edit region takes that
#: axis) when the middle eigenvalue of its normalised normal tensor exceeds this ...
GRAIN_TUBE_MIN = 0.1
#: ... and this many times the smallest.
GRAIN_TUBE_RATIO = 4.0
#: Seams of at least this many edges get a balance notch at their middle (pieces drawn
#: from a mesh).
BALANCE_MIN_EDGES = 4
#: Nearest points on a closed outline start from samples, this many along its length (a
#: count): the segments of the 8 nearest samples are then searched exactly ...
PIECE_CURVE_SAMPLES = 4096
#: ... each outline resampled to this many points (a count) when outlines are compared.
PIECE_SAMPLES = 256
#: Rigid-fit (ICP) residuals, relative to the piece's diagonal, closer than this are a tie
#: (a symmetric outline fits several ways): the first such fit is kept.
PIECE_FIT_TIE_REL = 1e-6
#: ICP stops when a step moves the fit by less than this (unitless: rotation entries, and
#: translation over the outline's size) ...
PIECE_ICP_STILL = 1e-10
#: ... or after this many iterations (a count) when a moved piece is matched by shape.
PIECE_ICP_ITER = 30
#: A piece is compared with a panel as they lie only when their bounding boxes come within
#: this fraction of the piece's diagonal (relative) plus the seam allowance.
PIECE_MATCH_REACH_REL = 0.1
#: A piece read from a file whose outline lies further from the drape's mesh (mean
#: distance) than this many ``--seam-allowance`` (unitless) already has one (a cut line):
#: a warning says the option added another.
PIECE_OUTSIDE_ALLOWANCE_WARN = 0.25

# Input bounds: the OBJ reader, garment checks, options (ptailor.formats.obj, .garment)
#: Largest OBJ file read, bytes (a 5-million-triangle garment is about 300 MB).
OBJ_MAX_BYTES = 1 << 30
#: Longest OBJ line, bytes (a polygon of a few thousand corners fits).
OBJ_MAX_LINE = 1 << 16
#: Most triangles read from an OBJ (after fan triangulation of its polygons).
OBJ_MAX_TRIANGLES = 5_000_000
#: Longest ``g``/``o`` group name, characters: longer ones are refused (a name is a label,
#: not data; CAD tools cap names at about 255).
OBJ_MAX_NAME = 200
#: Largest |coordinate| in an OBJ (``v`` and ``vt``), in the file's units: 1e6 (10 km in
#: mm, 10,000 km in m) is beyond any garment, and keeps every squared length and area finite.
OBJ_COORD_MAX = 1e6
#: Centimetres per unit of a scaled unit (``--pattern-units 0.5cm``): from 1 micrometre
#: to 1 kilometre.
UNIT_CM_RANGE = (1e-4, 1e5)
#: A garment read in a unit nobody gave (``--drape-units``/``--pattern-units`` left at the
#: ``cm`` default, a DXF that says only ``METRIC``) must be of human size
#: (:mod:`ptailor.model.size`): its drape's largest extent, and its largest piece's length,
#: in this range (cm: a sock to a gown in T-pose) ...
GARMENT_EXTENT_CM = (15.0, 250.0)
#: ... the drape at most this thick in its thinnest principal direction (cm: a body is 20-45
#: cm deep and the shared garments 27-51 cm; a Garment-Pattern-Generator tee in 1/300 m
#: read as cm is 93; a hooped gown needs its units given) ...
GARMENT_THICKNESS_MAX_CM = 80.0
#: ... its largest piece at least this long (cm) ...
PIECE_LENGTH_MIN_CM = 10.0
#: ... and no piece wider (its smaller principal extent) than the widest cloth (cm).
PIECE_WIDTH_MAX_CM = 160.0
#: ... and beside a ``--body``, its drape's largest extent this many times the body's.
BODY_SIZE_RATIO = (0.1, 1.5)
#: A ``--body`` FILE is refused when more than this fraction of the drape's vertices lie
#: inside it (a body is worn inside its garment: a fitted one leaves at most 0.5 % inside) ...
BODY_INSIDE_MAX = 0.2
#: ... judged on at most this many drape vertices (evenly spaced in the file's order).
BODY_CHECK_POINTS = 2000
#: Largest length given as an option (``--seam-allowance``, ``--weld``), centimetres.
LENGTH_MAX_CM = 1e4
#: Longest panel name drawn in a preview (longer ones are shortened with an ellipsis).
PREVIEW_NAME_MAX = 60

# Numeric safety of the method and the edits (issue 12)
#: A step may not leave any drape triangle with an area below this fraction of its area
#: before the step (a collapsing scale, a subnormal factor): the step is refused.
EDIT_COLLAPSE_REL = 1e-9
#: An edit may create at most this many times the garment's triangles (or the floor
#: below, for small garments) ...
EDIT_NEW_TRIANGLES_FACTOR = 4.0
EDIT_NEW_TRIANGLES_FLOOR = 100_000
#: ... and never more than this many (checked before anything is allocated).
EDIT_MAX_TRIANGLES = 2_000_000
#: A ``shorten`` / ``extend`` ``by`` below this fraction of the opening's mean edge length
#: changes nothing measurable: the step is refused as too small.
EDIT_MIN_BY_REL = 1e-3
#: Flatten weights (``w_pin``, ``w_asap``) outside this range make the stitching matrix
#: overflow or lose the panel's shape: refused when the run starts.
FLATTEN_WEIGHT_RANGE = (1e-6, 1e9)
#: A panel whose intrinsic-scale error p95 exceeds this (relative) gets a report warning.
INTRINSIC_ERROR_WARN = 0.5
#: ``--seam-allowance`` at most this many times the largest piece's bounding-box diagonal.
SEAM_ALLOWANCE_MAX_REL = 0.5
#: Largest extent of a garment's drape or pattern in its computation unit (any unit): a
#: garment checked by ``check_garment`` has squared lengths and areas far from overflow.
GARMENT_SIZE_MAX = 1e12

# JSON files ptailor reads (ptailor.formats.json_input): specifications, catalogues, reports
#: A JSON file larger than this many bytes is refused before it is parsed (GarmentCode's
#: largest specifications are some 100 kB; a catalogue of 10,000 garments a few MB).
JSON_MAX_BYTES = 64 << 20
#: Arrays and objects nested deeper than this (a count) are refused before parsing:
#: Python's parser recurses per level (a specification nests 7 deep, a report 6).
JSON_MAX_DEPTH = 64
#: An integer literal longer than this many characters is refused: far past any count or
#: coordinate (a float holds 17 digits), and ``float()`` of a 400-digit one overflows.
JSON_MAX_INT_CHARS = 40

# DXF pattern files (ptailor.formats.dxf): a reader that fails closed
#: A DXF larger than this many bytes is refused before it is parsed (a graded Gerber
#: export of a whole style is a few MB).
DXF_MAX_BYTES = 64 * 1024 * 1024
#: A DXF with more entities than this (modelspace and blocks, vertices included) is refused.
DXF_MAX_ENTITIES = 500_000
#: A polyline (or a flattened curve) with more vertices than this is refused.
DXF_MAX_VERTICES = 200_000
#: A piece whose cut line (layer 1), or sew line (layer 14), comes in more parts than this
#: is refused (each part is a Python object chained end to end: about 0.4 ms a part).
DXF_MAX_BOUNDARY_PARTS = 20_000
#: A text (piece name, annotation, style text) longer than this many characters is refused.
DXF_MAX_TEXT = 1_000
#: Every coordinate read (after the block's INSERT transform) lies within this many file
#: units of the origin (1e7 mm is 10 km): beyond it, or not finite, the file is refused.
DXF_MAX_COORD = 1e7
#: A piece's outline must span at least this many file units (its bounding box's larger
#: side) ...
DXF_MIN_EXTENT = 1e-3
#: ... and enclose at least this fraction of its bounding box's area: below, it is a line
#: or a point, not a piece.
DXF_MIN_AREA_REL = 1e-6
#: A ``Quantity:`` above this is refused (a piece is cut a few times per garment).
DXF_MAX_QUANTITY = 1_000
#: An MTEXT's raw text (formatting codes included) may hold this many times DXF_MAX_TEXT
#: characters (a count) before it is decoded: codes cost a few characters each.
DXF_MTEXT_RAW_FACTOR = 8
#: A header value (``$INSUNITS``, ``$MEASUREMENT``) beyond +-this (unitless) is no code:
#: it is ignored (the codes are below 30).
DXF_HEADER_CODE_MAX = 1e6
#: A ``Quantity:`` written as a decimal (``"2.0"``) is read when an integer in 0..this
#: (a count; far above DXF_MAX_QUANTITY, which then refuses it with its own message).
DXF_QUANTITY_READ_MAX = 1e9
#: At most this many warnings of ezdxf's recover mode are kept per file (a count): bounds
#: the memory of a file that logs one per entity.
DXF_RECOVER_MESSAGES_MAX = 1000
#: Outline segments chain into a closed loop when their ends lie within this fraction of
#: the piece's bounding-box diagonal (relative) ...
DXF_CHAIN_REL = 1e-3
#: ... and consecutive outline points closer than this fraction of it (relative) are one
#: point (rounding).
DXF_DUPLICATE_REL = 1e-9
#: The diagonal those fractions are taken of is at least this (file units): a piece of no
#: extent still gets a positive chaining tolerance (DXF_MIN_EXTENT refuses it later).
DXF_DIAGONAL_MIN = 1e-12
#: A curve (spline, ellipse, bulge) is flattened to within this fraction of its control
#: polygon's extent (relative: a 1 m curve to 1 mm).
DXF_FLATTEN_REL = 1e-3
#: A file that names no unit is in millimetres when its largest piece exceeds this (file
#: units: 300 cm or 300 in is longer than any piece, 300 mm is an ordinary one).
DXF_MM_ABOVE = 300.0
#: A graded outline corresponds to the sample's point by point when an affine fit between
#: them leaves an RMS residual below this fraction of the diagonal (relative).
DXF_GRADE_FIT_REL = 0.05
#: Two sizes' outlines (or a piece before and after an adjustment) that do not correspond
#: point by point are matched by length between turn points: a turn point of one meets the
#: other's nearest (laid over its bounding box) when they are each other's nearest and
#: within this fraction of the diagonal (relative): a grade moves a corner by a few cm.
GRADE_TURN_MATCH_REL = 0.1
#: A drape's ``vt`` is taken in a unit when its size, judged from the drape's area, is
#: within this factor of it (unitless).
DXF_VT_UNIT_SLACK = 1.5


# Recipes (ptailor.recipe): read and validated whole, with bounded work, before any garment
#: A recipe file larger than this (bytes) is refused before it is parsed (real recipes are
#: a few hundred bytes; YAML parsing is linear, but 50 MB of comments is not a recipe).
RECIPE_MAX_BYTES = 1_000_000
#: Nesting deeper than this (mappings and lists) is refused before composing (a recipe is
#: at most about 6 deep: steps, a step, region, box, min, a point).
RECIPE_MAX_DEPTH = 32
#: At most this many YAML aliases (``*name``) per recipe: anchors let a recipe reuse a
#: region or a step, but a "billion laughs" document needs many.
RECIPE_MAX_ALIASES = 100
#: The document, with every alias expanded, may hold at most this many values (scalars,
#: lists and mappings); checked on the event stream, before anything is built.
RECIPE_MAX_NODES = 20_000
#: A number written with more characters than this is refused by the reader (an int of
#: 10^4000 digits, or sexagesimal ``1:2:3:...`` with a quadratic cost).
RECIPE_MAX_NUMBER_CHARS = 40
#: Every recipe number (lengths, coordinates, factors, weights) lies within +-this.
RECIPE_NUMBER_MAX = 1e6
#: A parameter that must be > 0 (a factor, a length, a weight) must be at least this.
RECIPE_POSITIVE_MIN = 1e-6
#: A direction (axis, plane normal, view) needs a component at least this large.
RECIPE_DIRECTION_MIN = 1e-6
#: Lengths an edit adds or removes (``by`` of extend, shorten, loosen, tighten; extend's
#: ``clearance``) are at most this many centimetres (converted to the recipe's units).
RECIPE_MAX_LENGTH_CM = 1000.0
#: A value quoted in a message is cut to this many characters.
RECIPE_SHOW_CHARS = 80
#: A recipe holds at most this many steps (each is checked, by the rules and the schema).
RECIPE_MAX_STEPS = 200
#: A recipe's ``expect:`` without ``tol`` allows this many centimetres between the
#: achieved measure and its target (a pattern maker's usual +-1/4 in on a girth).
EXPECT_TOL_CM = 0.5

# Output folders and batch (ptailor.run.folder, ptailor.batch)
#: Staging folders (``.NAME.XXXXXXXX.tmp``, ``.NAME.old-.NAME.XXXXXXXX.tmp``) carry at most
#: this many bytes of the output folder's name; a longer name is cut and an 8-digit hash of
#: it added, so that both fit the 255 bytes of a file name.
STAGING_NAME_BYTES = 96
#: At most this many distinct library warnings (numpy, ezdxf) are kept for one run's report.
LIBRARY_WARNINGS_MAX = 20
#: ``batch --timeout``: a garment past its timeout that does not stop (stuck in native code)
#: has its worker killed max(this, a quarter of the timeout) seconds later.
TIMEOUT_GRACE_S = 5.0
#: The longest ``batch --timeout`` (seconds: 30 days); beyond it a timer overflows.
BATCH_TIMEOUT_MAX_S = 2_592_000.0
#: A batch worker checks this often (seconds) that its batch is alive, and ends if not.
WORKER_PARENT_POLL_S = 0.5
#: A folder's ``.ptailor`` marker larger than this (bytes) is no marker of ptailor's ...
OUTPUT_MARKER_MAX_BYTES = 1 << 20
#: ... and a legacy folder's ``report.json`` larger than this (bytes) is no report of its.
LEGACY_REPORT_MAX_BYTES = 64 << 20
#: A garment still unfinished after this many broken process pools runs in a worker of its
#: own (a count), so that a garment that kills its worker fails by itself and the others
#: finish.
BATCH_POOL_STRIKES = 2
#: A manifest (``batch --manifest``) larger than this (bytes) is refused.
MANIFEST_MAX_BYTES = 64 << 20
#: A manifest's message lists at most this many problems (a count; then how many more).
MANIFEST_PROBLEMS_SHOWN = 10
#: What ptailor reads back (``report.json``, ``batch.json``, ``catalogue.json``): a file
#: larger than this (bytes) is not one ptailor wrote ...
READBACK_MAX_BYTES = 64 << 20
#: ... nor one nested deeper than this (arrays and objects; ptailor's own nest 6 deep) ...
READBACK_MAX_DEPTH = 32
#: ... nor a file name in it longer than this (bytes: what a file system takes) ...
READBACK_NAME_MAX_BYTES = 255
#: ... and a batch log (``--log``, JSON lines) larger than this (bytes) is refused.
READBACK_LOG_MAX_BYTES = 1 << 30
#: A number read back is at most this large in magnitude (a larger one, or an integer of
#: more digits than a float holds, was not written by ptailor).
READBACK_NUMBER_MAX = 1e300
#: A garment's ``preview.png`` larger than this (pixels) gets no thumbnail: ptailor's own
#: previews have about 1.5 M; Pillow's decompression-bomb guard starts at 89 M.
THUMBNAIL_PREVIEW_MAX_PIXELS = 64_000_000
#: A step field longer than this (characters) is cut on a catalogue page.
CATALOGUE_SHOWN_MAX = 240
#: A preview PNG's ``size`` is at least this many pixels (a smaller one is refused).
PREVIEW_MIN_PIXELS = 16
#: Sheet layout: shelf widths and sheet sizes within this (in the pattern's unit) are equal:
#: sums of piece widths round to far less, a visible difference is far more.
SHEET_LAYOUT_TIE = 1e-9


# --- pattern specifications (GarmentCode / Garment-Pattern-Generator, ptailor.spec) ---
#: A specification panel matches a mesh panel whose outline area is within this fraction ...
SPEC_AREA_REL = 0.05
#: ... and onto whose outline its own fits with a mean distance below this fraction of its
#: size (tee6 and GarmentCode's shirt: 0.0004 and 0.00003; the next-best panel 0.02).
SPEC_MATCH_REL = 0.005
#: ``spec.fit``: an adjusted specification's edge curves farther than this from the adjusted
#: mesh outline are a warning (1 mm).
SPEC_FIT_WARN_CM = 0.1
#: A straight edge whose adjusted points leave its chord by more than this gets a curve.
SPEC_BEND_CM = 0.05
#: A specification outline is sampled this many times per edge (a count) when it is
#: matched ...
SPEC_PER_EDGE = 64
#: ... and this many when its curves are compared with a mesh outline (a count) ...
SPEC_FIT_SAMPLES = 128
#: ... and each edge carries this many samples to refit its curve (a count) ...
SPEC_REFIT_SAMPLES = 32
#: ... in this many rounds of geometric refitting of a Bezier edge (a count;
#: :func:`ptailor.geometry.curves.fit_curve`).
SPEC_REPARAMETRIZE = 8
#: Rounds of the robust similarity fit of a panel's frame (a count: iteratively reweighted
#: least squares).
SPEC_IRLS_ROUNDS = 12
#: A new outline run turns by more than this (degrees) at a corner: it is split there.
SPEC_CORNER_DEG = 35.0
#: A specification panel's best coarse fit must be within this many times SPEC_MATCH_REL
#: (unitless) for the panel to be tried at full resolution ...
SPEC_COARSE_FACTOR = 4.0
#: The coarse fits take every this-th sample (a count: 64 of 256) ...
SPEC_COARSE_STRIDE = 4
#: ... and this many ICP iterations (a count) ...
SPEC_COARSE_ICP_ITER = 12
#: ... and the starts refined are those within this many times the best coarse residual
#: (unitless) plus SPEC_START_SLACK (relative to the panel's size) ...
SPEC_START_FACTOR = 3.0
SPEC_START_SLACK = 1e-3
#: ... and the fits kept are those within this many times the best (unitless) plus
#: SPEC_KEEP_SLACK (relative): a symmetric panel fits two ways about as well, and both are
#: kept for its place in 3D to choose. The slack is the asymmetry a meshed symmetric panel
#: shows (a generated bodice's front: its two fits 5e-6 and 9e-5, which one is the better
#: depending on where the edge loop starts; 1e-6 kept only one, and a re-rooted loop was
#: refused); real fits are 3e-5 to 4e-4, the next-best other panel 0.02.
SPEC_KEEP_FACTOR = 2.0
SPEC_KEEP_SLACK = 1e-3
#: An adjusted outline's points are labelled with the specification edge within this many
#: times the input's own fit distance (unitless) of them, or SPEC_REACH_MIN_CM (cm) ...
SPEC_REACH_FITS = 3.0
SPEC_REACH_MIN_CM = 0.05
#: ... and an input corner is still in the panel when it lies within this many times the
#: fit distance (unitless) plus SPEC_CORNER_KEEP_REL of the outline's extent (relative).
SPEC_CORNER_KEEP_FITS = 3.0
SPEC_CORNER_KEEP_REL = 1e-6

#: Every number of a specification (vertex, control point, arc radius, translation,
#: rotation) lies within this many of its units of zero (1e7: 100 km in cm): beyond it the
#: file is refused where it is read (squared lengths stay finite; 1e300 overflowed).
SPEC_MAX_COORD = 1e7
#: ``properties.units_in_meter`` lies in this range (1e-3: a unit of 1 km; 1e6: of 1 um).
SPEC_UNITS_IN_METER = (1e-3, 1e6)
#: A specification with more panels than this, or more edges in all, is refused (counts:
#: GarmentCode's jumpsuit has 14 panels and some 120 edges).
SPEC_MAX_PANELS = 1_000
SPEC_MAX_EDGES = 20_000
#: A specification without ``units_in_meter``: its unit is the one of these (units per
#: metre) that makes its panel areas the garment's within SPEC_AREA_REL (Garment-Pattern-
#: Generator's older files: 100 cm or 300 (1/3 cm)) ...
SPEC_UNIT_GUESSES = (100.0, 300.0, 1000.0, 1.0, 10.0, 39.37007874015748)

# --- the report (ptailor.report) ---
#: A seam's target ratio differs from its ratio before when by more than this fraction of
#: it (relative): the summary counts it as gathered.
SUMMARY_RATIO_CHANGED_REL = 1e-6
#: The summary says every seam is at its target ("mismatch below 0.001") when the worst
#: mismatch is below this (in the garment's unit): what rounds to 0.000 at three decimals.
SUMMARY_MISMATCH_ZERO = 5e-4
