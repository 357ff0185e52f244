"""Every numeric tolerance in one place (trimesh style)."""

#: Relative (to the panel's bounding-box diagonal) area below which a triangle is degenerate.
ZERO_AREA_REL = 1e-12
#: Local/global stitching stops when no panel's last step moved a vertex (rigid motion
#: removed) by more than this fraction of the panel's size ...
ARAP_STEP_TOL = 1e-7
#: ...or after this many iterations.
ARAP_MAX_ITER = 100
#: Default weights of the pinned-vertex and as-similar-as-possible terms (the paper's).
W_PIN = 1000.0
W_ASAP = 1000.0
#: With seam ease, panels whose drape no edge of changed length by more than this fraction
#: (untouched by the edits), and panels a step keeps, are stiffer in the stitching ...
KEPT_STRAIN = 1e-3
#: ... by this factor on their whole energy: the edited panels absorb the seams' cost.
KEPT_PANEL_WEIGHT = 1000.0
#: Seam constraints switch on at the first iteration where a seam edge misses its ratio by
#: more than this (relative).
SEAM_EXACT_REL = 1e-9
#: The seam constraints' curvature (the stitching's SQP step) leaves out the edges whose
#: weight is below this fraction of the largest (ptailor.method.ease.SeamEase.curvature)
SEAM_CURVATURE_MIN_REL = 0.05
#: A seam curve whose edge pairs' ratios all lie within this (relative) of its total's
#: ratio gets no total row (ptailor.method.ease.seam_ease): the pairs hold its total to
#: this fraction of its length (0.001 cm on a 1 m seam); a simulated pattern's float noise
#: is about 3e-6.
SEAM_TOTAL_UNIFORM_REL = 1e-5
#: A seam edge whose two sides miss their target ratio by more than this (relative) after
#: the solve is reported as a warning.
SEAM_WARN_REL = 1e-4
#: A seam side whose outline turning alternates vertex to vertex by more than this (radians)
#: after the stitching is reported as zigzagging (:func:`ptailor.method.ease.side_zigzag`).
#: An edit that stretches a jagged simulated outline evens it out, which alternates too (up
#: to 0.25 rad on the shared garments); the sawtooth of a stretched side at 16x reaches 1.9.
SEAM_ZIGZAG_RAD = 0.5
#: Seam sides get a bending stiffness ``mu = SEAM_BEND * size^3`` (``size`` the panel's
#: diagonal; ptailor.method.bend), which keeps a side the seam stretches from a sawtooth
#: on fine meshes and moves a smooth side by about 1e-5 of its panel's size. Vertices whose
#: target turning exceeds SEAM_BEND_CORNER_RAD are corners and get none.
SEAM_BEND = 1e-7
SEAM_BEND_CORNER_RAD = 0.35
#: Anderson acceleration history of the stitching iterations (0: plain local/global).
ANDERSON_HISTORY = 10
#: The stitching takes a Newton step when its largest residual fell by less than
#: NEWTON_CRAWL over the last NEWTON_WINDOW iterations (a slender panel's bending, where
#: local/global steps crawl); each solves its model by at most NEWTON_CG_MAX
#: preconditioned conjugate-gradient iterations, to NEWTON_CG_RTOL of the first residual.
NEWTON_WINDOW = 5
NEWTON_CRAWL = 0.5
NEWTON_CG_MAX = 40
NEWTON_CG_RTOL = 1e-3
#: A Newton step that does not lower the energy is halved up to this many times.
NEWTON_BACKTRACK = 3
#: Right-hand sides per back-substitution batch when the seam block of ``A^-1`` is formed
#: (SuperLU slows down twentyfold per column beyond about 32).
SEAM_BLOCK_CHUNK = 16
#: A 2D triangle whose signed area has the opposite sign of its panel's is flipped when
#: its magnitude exceeds this fraction of the panel's mean triangle area.
FLIP_REL = 1e-9
#: Boundary vertices where the outline turns by more than this are corners: the
#: as-similar-as-possible term (a tangent direction) does not apply there.
ASAP_CORNER_DEG = 30.0

# 3D surface deformation (ptailor.method.deform)
#: A triangle whose doubled area is at most this times its longest squared edge is
#: degenerate: its cotangents are taken as zero.
DEFORM_DEGENERATE_REL = 1e-12
#: Uniform weight added to every triangle edge in ARAP surface deformation, relative to the
#: mean absolute cotangent weight. It keeps a vertex whose triangles are all degenerate
#: attached to its neighbours (instead of an empty row making the system singular); on a
#: sound mesh its effect is of this relative order. Rigid motions stay exact.
DEFORM_UNIFORM_REG = 1e-8
#: A follow-up deformation in which strips sewn to an edited region grow by similarities
#: (``edits/follow.py``) iterates up to this many times (the energy's own stop ends it
#: sooner): the default 5 leave a 40 cm cuff 1.6 cm from a similarity of its pattern, 20 to
#: convergence 0.16 cm.
FOLLOW_SIMILAR_ITER = 40
#: Singular-value ratio below which a component's handles count as collinear (or a single
#: point): the rigid pre-alignment then only translates that component.
DEFORM_COLLINEAR_REL = 1e-10

# Surgery (shorten, cut)
#: Field values within this many mean edge lengths of zero snap to zero before splitting,
#: so a cut passing next to a vertex goes through it instead of making a sliver.
SPLIT_SNAP_REL = 1e-3

# Geodesic distance (ptailor.method.geodesic)
#: A distance that decreases by less than this fraction of (itself plus the mean edge
#: length) is still lowered, but does not make its triangles active again; the iteration
#: stops when no change is larger, so the result is a fixed point to about this order.
GEODESIC_REL_TOL = 1e-12
#: A triangle corner whose ``|a|^2 |b|^2 - (a.b)^2`` (squared doubled area) is at most this
#: times ``|a|^2 |b|^2`` (an angle below about 1e-7 rad) is degenerate: only the one-point
#: (edge) updates apply there.
GEODESIC_DEGENERATE_REL = 1e-14
#: With a finite ``limit``, vertices below ``limit`` plus this many longest edge lengths
#: keep propagating. A value may depend on a neighbour's slightly larger value (through an
#: obtuse triangle), so the band reaches a little beyond ``limit``.
GEODESIC_BAND_MARGIN_EDGES = 2.0
#: Vertices propagate in order of distance, this many mean edge lengths at a time.
GEODESIC_STEP_EDGES = 2.0

# Pattern pieces (ptailor.pieces, ptailor.model.polyline)
#: An outline point where the outline turns by more than this is a turn point (corner).
CORNER_DEG = 30.0
#: A seam-allowance corner is mitred unless the mitre would reach further than this many
#: allowances from the corner; then it is bevelled.
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
#: Past twice this many iterations, the stitching stops when the largest residual of the
#: last this many iterations is not below (1 - ARAP_STALL_GAIN) of the best before them
#: (a large ``max_iter`` on a problem that no longer converges; the default cap is 100).
ARAP_STALL_ITER = 200
ARAP_STALL_GAIN = 0.01
#: Largest extent of a garment's drape or pattern in its computation unit (any unit): a
#: garment checked by ``check_garment`` has squared lengths and areas far from overflow.
GARMENT_SIZE_MAX = 1e12

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
#: ``axis: auto`` on a region that is no tube falls back to its longest extent; more than
#: this many degrees from the garment's up is a warning (ptailor.edits.scale).
AUTO_AXIS_UP_DEG = 30.0
#: A batch worker checks this often (seconds) that its batch is alive, and ends if not.
WORKER_PARENT_POLL_S = 0.5
#: A scale_seam ``fix`` that the part's scaling would move by more than this fraction of
#: the garment's size lies inside the scaled part: an error (ptailor.edits.scale_seam).
FIX_INSIDE_REL = 0.005
#: ``scale`` with ``axis: auto`` scales each connected part of its region about its own
#: axis (both sleeves: each around its arm) when every part holds at least this fraction
#: of the region's triangles; else the region as one.
REGION_PART_MIN = 0.1
#: A cut or shorten that removes more than this fraction of a panel's pattern area says so.
SURGERY_REMOVED_WARN = 0.5
#: A seam of the scaled part continues a scale_seam's seam line where it leaves their
#: shared end vertex within this many degrees of straight on (ptailor.edits.scale_seam).
SEAM_LINE_TURN_DEG = 60.0

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
#: A frame's front whose part perpendicular to up is shorter than this fraction of its
#: length (unitless) is parallel to up (ptailor.model.frame.Frame): no side can be told.
FRAME_PARALLEL = 1e-9
