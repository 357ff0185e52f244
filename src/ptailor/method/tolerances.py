"""Every tolerance and limit of the method (:mod:`ptailor.method`): the stitching, the 3D
deformation, the geodesic distance, the rotations and the small solves.

Constants only, each with what it bounds, its unit and why that value (the rules and the
literals that may stay inline: :mod:`ptailor.tolerances`). Code reads them as attributes
(``method_tol.ARAP_STEP_TOL``), so a test may patch one.
"""

# --- the stitching (ptailor.method.flatten, ptailor.method.solver) ---
#: Local/global stitching stops when no panel's last step moved a vertex (rigid motion
#: removed) by more than this fraction of the panel's size (relative) ...
ARAP_STEP_TOL = 1e-7
#: ... or after this many iterations (a count).
ARAP_MAX_ITER = 100
#: Default weights of the pinned-vertex and as-similar-as-possible terms (unitless, the
#: paper's).
W_PIN = 1000.0
W_ASAP = 1000.0
#: With seam ease, panels whose drape no edge of changed length by more than this fraction
#: (relative; untouched by the edits), and panels a step keeps, are stiffer in the
#: stitching ...
KEPT_STRAIN = 1e-3
#: ... by this factor on their whole energy (unitless): the edited panels absorb the seams'
#: cost. At 1000 a kept slender panel (the shared long-sleeve's collars) bent by 1e-5 of its
#: size, which local/global closes at 1.5 % a step: two Newton steps; at 10000 the bend is
#: ten times smaller and below the step tolerance (docs/method.md, "What crawls").
KEPT_PANEL_WEIGHT = 10000.0
#: Seam constraints switch on at the first iteration where a seam edge misses its ratio by
#: more than this (relative).
SEAM_EXACT_REL = 1e-9
#: The seam constraints' curvature (the stitching's SQP step) leaves out the edges whose
#: weight is below this fraction of the largest (relative;
#: ptailor.method.ease.SeamEase.curvature)
SEAM_CURVATURE_MIN_REL = 0.05
#: A seam curve whose edge pairs' ratios all lie within this (relative) of its total's
#: ratio gets no total row (ptailor.method.ease.seam_ease): the pairs hold its total to
#: this fraction of its length (0.001 cm on a 1 m seam); a simulated pattern's float noise
#: is about 3e-6.
SEAM_TOTAL_UNIFORM_REL = 1e-5
#: Seam edge pairs with a side shorter than this fraction of the mean seam edge (relative)
#: get no seam row (ptailor.method.ease.seam_ease): a side of (nearly) zero length has no
#: ratio to keep.
SEAM_MIN_LENGTH_REL = 1e-6
#: A seam edge whose two sides miss their target ratio by more than this (relative) after
#: the solve is reported as a warning.
SEAM_WARN_REL = 1e-4
#: A seam whose two sides, after the adjustment, miss the length ratio they have in the
#: input (times a step's gather) by more than this (cm: 0.1 mm, a pattern maker's truing)
#: is reported as a warning: a cut or grown seam the step could not true, a seam the
#: stitching did not meet.
SEAM_MISMATCH_WARN_CM = 0.01
#: A seam side whose outline turning alternates vertex to vertex by more than this (radians)
#: after the stitching is reported as zigzagging (:func:`ptailor.method.ease.side_zigzag`).
#: An edit that stretches a jagged simulated outline evens it out, which alternates too (up
#: to 0.25 rad on the shared garments); the sawtooth of a stretched side at 16x reaches 1.9.
SEAM_ZIGZAG_RAD = 0.5
#: Seam sides get a bending stiffness ``mu = SEAM_BEND * size^3`` (unitless factor; ``size``
#: the panel's diagonal; ptailor.method.bend), which keeps a side the seam stretches from a
#: sawtooth on fine meshes and moves a smooth side by about 1e-5 of its panel's size.
#: Vertices whose target turning exceeds SEAM_BEND_CORNER_RAD (radians, 20 degrees) are
#: corners and get none.
SEAM_BEND = 1e-7
SEAM_BEND_CORNER_RAD = 0.35
#: Anderson acceleration history of the stitching iterations (a count; 0: plain
#: local/global).
ANDERSON_HISTORY = 10
#: Anderson's least squares (columns scaled to a unit diagonal) get this ridge on the
#: diagonal (unitless), for stability: nearly parallel differences of a converging run
#: leave the scaled Gram matrix singular to rounding.
ANDERSON_RIDGE = 1e-10
#: The stitching takes a Newton step when its largest residual fell by less than
#: NEWTON_CRAWL (relative) over the last NEWTON_WINDOW iterations (a slender panel's
#: bending, where local/global steps crawl); each solves its model by at most NEWTON_CG_MAX
#: preconditioned conjugate-gradient iterations, to NEWTON_CG_RTOL (relative) of the first
#: residual.
NEWTON_WINDOW = 5
NEWTON_CRAWL = 0.5
NEWTON_CG_MAX = 40
NEWTON_CG_RTOL = 1e-3
#: A Newton step that only confirms convergence (every panel's local/global step already
#: below ARAP_STEP_TOL after an earlier Newton step) stops after at most this many
#: conjugate-gradient iterations (a count): the crawl it looks for is the slowest mode, the
#: one the first iterations resolve (the shared long-sleeve's sleeve 1.1: its move
#: 9.27e-9 with 8 against 9.23e-9 with 40, at 1x; 1.13e-8 against 1.04e-8 at 4x).
NEWTON_CONFIRM_CG = 8
#: A Newton step that does not lower the energy is halved up to this many times (a count).
NEWTON_BACKTRACK = 3
#: Past twice this many iterations, the stitching stops when the largest residual of the
#: last this many iterations is not below (1 - ARAP_STALL_GAIN, relative) of the best before
#: them (a large ``max_iter`` on a problem that no longer converges; the default cap is 100).
ARAP_STALL_ITER = 200
ARAP_STALL_GAIN = 0.01
#: Right-hand sides per back-substitution batch when the seam block of ``A^-1`` is formed
#: (a count: SuperLU slows down twentyfold per column beyond about 32).
SEAM_BLOCK_CHUNK = 16
#: Diagonal shifts, relative to the largest diagonal entry, tried in turn when a small
#: dense SPD system (the seam block) is factored (ptailor.method.solver.small_systems): the
#: matrix as it is, then shifts near rounding that let a semidefinite one factor (least
#: squares only where none does).
SPD_SHIFTS = (0.0, 1e-12, 1e-9)
#: A 2D triangle whose signed area has the opposite sign of its panel's is flipped when
#: its magnitude exceeds this fraction of the panel's mean triangle area (relative).
FLIP_REL = 1e-9
#: Boundary vertices where the outline turns by more than this (degrees) are corners: the
#: as-similar-as-possible term (a tangent direction) does not apply there.
ASAP_CORNER_DEG = 30.0

# --- 3D surface deformation (ptailor.method.deform, .arap, .cotangent) ---
#: A triangle whose doubled area is at most this times its longest squared edge (relative)
#: is degenerate: its cotangents are taken as zero.
DEFORM_DEGENERATE_REL = 1e-12
#: Uniform weight added to every triangle edge in ARAP surface deformation, relative to the
#: mean absolute cotangent weight. It keeps a vertex whose triangles are all degenerate
#: attached to its neighbours (instead of an empty row making the system singular); on a
#: sound mesh its effect is of this relative order. Rigid motions stay exact.
DEFORM_UNIFORM_REG = 1e-8
#: Singular-value ratio (unitless) below which a component's handles count as collinear (or
#: a single point): the rigid pre-alignment then only translates that component.
DEFORM_COLLINEAR_REL = 1e-10
#: The largest uniform scale (unitless; and its inverse the smallest) a ``similar`` cell may
#: take: a strip that follows an edit by similarities grows or shrinks at most twofold.
ARAP_SIMILAR_MAX = 2.0
#: Local/global iterations of arap_deform (a count), Anderson-accelerated with a history of
#: ARAP_ANDERSON: 5 end at least as close to the converged deformation as 10 plain ones did
#: (largest distance from it over the largest displacement, 100k-triangle sleeve: cuff
#: scaled by 1.3 13.2 % vs 15.1 %, scale_seam 1.3 13.0 % vs 15.4 %; at 20k 4.4 % vs 4.8 %
#: and 3.1 % vs 5.2 %).
ARAP_ITERATIONS = 5
ARAP_ANDERSON = 5
#: arap_deform stops early when its energy falls by less than this fraction of its previous
#: value (relative) ...
ARAP_ENERGY_TOL = 1e-6
#: ... and at once when the energy is at most this fraction of its scale (relative): the
#: energy's sum cancels to about 1e-16 of the scale, so below a hundred times that it is
#: zero (the rest pose).
ARAP_ZERO_ENERGY_REL = 1e-14

# --- the rotations of ARAP cells (ptailor.method.cell_rotations) ---
#: warm_rotations accepts a rotation once its Newton step is at most this (radians): the
#: error after it is of order the step cubed, below rounding (steps of 1.3e-5 and 3.9e-6
#: were followed by 8e-16 and 2e-16 on the sleeve's cells) ...
ROTATION_DONE = 1e-5
#: ... and its Hessian's determinant is above this times trace(M)^3 (relative: positive
#: definite, so the maximum is unique).
ROTATION_PD_REL = 1e-9
#: Newton steps at most (a count: two or three reach rounding from the previous iteration's
#: rotations) ...
ROTATION_STEPS = 6
#: ... stopping once at most one cell in this many is left (a count: all but 1 % accepted);
#: those left are computed by SVD.
ROTATION_SVD_SHARE = 100
#: While more than one cell in this many (a count) is still moving, a step is taken on all
#: cells (cheaper than gathering the few that are done); else only on those left.
ROTATION_GATHER_SHARE = 4

# --- geodesic distance (ptailor.method.geodesic) ---
#: A distance that decreases by less than this fraction of (itself plus the mean edge
#: length; relative) is still lowered, but does not make its triangles active again; the
#: iteration stops when no change is larger, so the result is a fixed point to about this
#: order.
GEODESIC_REL_TOL = 1e-12
#: A triangle corner whose ``|a|^2 |b|^2 - (a.b)^2`` (squared doubled area) is at most this
#: times ``|a|^2 |b|^2`` (relative: an angle below about 1e-7 rad) is degenerate: only the
#: one-point (edge) updates apply there.
GEODESIC_DEGENERATE_REL = 1e-14
#: With a finite ``limit``, vertices below ``limit`` plus this many longest edge lengths
#: keep propagating. A value may depend on a neighbour's slightly larger value (through an
#: obtuse triangle), so the band reaches a little beyond ``limit``.
GEODESIC_BAND_MARGIN_EDGES = 2.0
#: Vertices propagate in order of distance, this many mean edge lengths at a time.
GEODESIC_STEP_EDGES = 2.0

# --- barycentric transfer (ptailor.method.transfer) ---
#: Triangles (nearest by centroid) examined per point for a first guess (a count; the exact
#: search that follows makes the result independent of it, only the time depends on it).
TRANSFER_CANDIDATES = 8
#: A point whose barycentric coordinates are all at least minus this (unitless) lies inside
#: its triangle: a point on an edge computes to minus a few roundings (about -1e-16).
TRANSFER_INSIDE_BARY = 1e-12

#: A gather's map (ptailor.method.gather): its seam edges' rows weigh this many times a
#: triangle's (area over the seam edges' mean squared length, unitless), so the seam side
#: grows by the factor edge by edge (the shared tshirt's armhole: 1.199 of 1.2 at worst).
GATHER_SEAM_WEIGHT = 1e4
#: How many factors of the last matrices an edit factored are kept for reuse (a count):
#: a step that factors a matrix it factored before (the same drape, triangles and handles:
#: a scale's follow-up with the same handles, each factor a ``measure`` search tries) takes
#: the kept factor. Two cover a step and its follow-up; more would hold memory for nothing.
REUSE_FACTORS = 2
