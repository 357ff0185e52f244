"""Every tolerance and limit of the re-drape check (:mod:`ptailor.verify`): the mean body's
fit, the simulation mesh, the simulation's setup.

Constants only, each with what it bounds, its unit and why that value (the rules and the
literals that may stay inline: :mod:`ptailor.tolerances`). The simulation's physical
settings (stiffness, density, contact, time step) are the fields of
:class:`ptailor.verify.engine.Settings`, each documented there with its unit: a settings
dataclass's fields are the one place their defaults are given.
"""

# --- the mean body fitted into a garment (ptailor.verify.fit) ---
#: A top whose cuffs lie more than this from straight down (degrees, averaged over the
#: cuffs) is in a T-pose: the T-pose body is taken, else the A-pose one.
FIT_T_POSE_DEG = 70.0
#: The mean body's neck base and waist, as fractions of its height (unitless: the mean
#: body's own landmarks) ...
FIT_NECK_HEIGHT = 0.835
FIT_WAIST_HEIGHT = 0.61
#: ... the rows of the body within this fraction of its height (unitless) of the anchor's
#: height give the torso's mid-depth there.
FIT_ANCHOR_BAND = 0.02
#: Body scales tried (unitless, about the anchor): half to one and a half times the mean
#: body ...
FIT_SCALE_RANGE = (0.5, 1.5)
#: ... the largest one at which at most this fraction (unitless) of the torso's garment
#: vertices lies inside the body (a fitted body leaves at most 0.5 % inside) ...
FIT_INSIDE_MAX = 0.005
#: ... found by this many bisection steps on the scale (a count: 1/1000 of the range).
FIT_SCALE_STEPS = 10
#: The body's offsets from the anchor tried, up/down and front/back: up to this (cm), in
#: steps of FIT_OFFSET_STEP_CM (cm): where a garment hangs is not a landmark it hits exactly.
FIT_OFFSET_CM = 6.0
FIT_OFFSET_STEP_CM = 2.0
#: Garment vertices the fit looks at, at most (a count, evenly subsampled: the inside test
#: costs per point) ...
FIT_POINTS = 6000
#: ... of the torso (those no farther out than the hem reaches) when it has at least this
#: many (a count), else of the whole garment.
FIT_TORSO_MIN_POINTS = 100
#: The drape's vertices the posed body's inside fraction is measured on, at most (a count,
#: evenly subsampled: trimesh's ray test costs per point, 7 s for 6,900 at tee6 16x; the
#: fraction's standard error at 5 % is 0.5 % with 2,000).
FIT_INSIDE_POINTS = 2000
#: The whole drape's inside fraction asks the ray test only of the points inside by the
#: nearest body vertex's normal or within this many median body edges of the body (unitless:
#: farther out, that normal's side is the body's side: exact on the shared garments, and the
#: test 2-4x faster there).
FIT_NEAR_EDGES = 2.0

# --- the simulation mesh (ptailor.verify.proxy) ---
#: The simulation pattern's area may differ from the garment's by this fraction (relative)
#: ...
PROXY_AREA_TOL = 0.01
#: ... and this fraction of its triangles may be folded in the pattern (relative; the
#: collapse sees the drape, not the pattern: dress_initial at 8,000 triangles folds 2; tee6
#: at 64x folds 12 of 9,248, whose re-drapes blew up (stretch p95 4-8), and passes at
#: 16,000).
PROXY_FOLD_TOL = 1e-3
#: Targets tried, times ``max_faces`` (unitless), until a decimation passes the checks.
PROXY_TARGETS = (1.0, 2.0)
#: A decimation that keeps more than this fraction of the triangles (relative) is not used.
PROXY_MIN_GAIN = 0.8
#: Candidate simulation triangles tried per point when locating it (a count).
PROXY_CANDIDATES = 12
#: A point whose smallest barycentric coordinate in its simulation triangle is below minus
#: this (unitless) lies outside it: it is located again among more candidates (a point on
#: an edge computes to about -1e-16).
PROXY_OUTSIDE_BARY = 1e-9

# --- the simulation's setup (ptailor.verify.engine, ptailor.run.verify) ---
#: The cloth-cloth contact radius is capped at this many median rest edges (unitless), so
#: a surface's own next-but-one neighbours are not contacts (Newton's 3 mm pushes a fine
#: mesh apart in its own plane).
ENGINE_SELF_RADIUS_EDGES = 0.4
#: A frame whose up's cosine to +y is below -1 plus this (unitless) is upside down: it is
#: turned by half a turn about x (the rotation formula divides by 1 + cos, which is zero
#: there).
UPSIDE_DOWN = 1e-12

# --- the arms posed to the sleeves (ptailor.verify.pose) ---
#: The body's rows, for finding its arms, are this fraction of its height apart (unitless:
#: 1.7 cm on the mean body, about its vertex spacing) ...
FIT_ARM_ROW = 0.01
#: ... and a row whose vertices leave a gap wider than this many median edge lengths
#: (unitless) between the torso and what lies beyond holds the arm beyond the gap (the
#: mean body's armpit opens 2.8 cm at its top row, its edges are 1.5 cm).
FIT_ARM_GAP_EDGES = 1.5
#: The upper arm, whose principal axis is the bone: the arm from the armpit down this
#: fraction of the height (unitless: 19 cm, the humerus without the elbow).
FIT_UPPER_ARM = 0.11
#: The arm moves rigidly beyond this fraction of the height from the shoulder joint along
#: the bone (unitless: 8.6 cm); nearer, the weights blend to the torso's.
FIT_ARM_BAND = 0.05
#: An arm's abduction is kept within these (degrees from straight down): below, the arm
#: enters the torso; above, the shoulder folds.
FIT_ARM_ABDUCTION = (20.0, 100.0)
#: ... and its forward swing within this (degrees either way).
FIT_ARM_FORWARD = 30.0
#: A shoulder moves at most this far (cm, the fitted body's) onto its sleeve's axis (at 6 the
#: draped tops reached it, tee6's sleeves hung off the arms and its null test failed, mean
#: 1.03 cm; at 10: 0.43 cm, and tshirt 0.41, long-sleeve 0.96 hold it too).
FIT_SHOULDER_SHIFT_CM = 10.0

# --- the legs posed to the trouser legs (ptailor.verify.legs) ---
#: The thigh, whose axis is the leg's bone: the leg from the crotch down this fraction of the
#: height (unitless: 26 cm on the mean body, above the knee; its axis leans 2.4 degrees out and
#: 7.4 back, within 1.5 degrees of that from 17 to 34 cm).
FIT_THIGH = 0.15
#: The hip joint lies this fraction of the height above the crotch on the bone (unitless:
#: 8.6 cm, the femur's head about the height of the greater trochanter).
FIT_HIP_ABOVE_CROTCH = 0.05
#: The leg moves rigidly beyond this fraction of the height from the hip joint along the
#: bone (unitless: 8.6 cm, the crotch's height); the torso above the joint by as much does not
#: move; the weights blend in between.
FIT_LEG_BAND = 0.05
#: A leg's abduction is kept within these (degrees from straight down, out from the body):
#: below, the thighs enter each other; above, the groin folds.
FIT_LEG_ABDUCTION = (0.0, 45.0)
#: ... and its forward swing within this (degrees either way).
FIT_LEG_FORWARD = 30.0
#: A hip moves at most this far (cm, the fitted body's) onto its trouser leg's axis.
FIT_HIP_SHIFT_CM = 6.0

# --- the null test and the verdict (ptailor.verify.verdict) ---
#: The null test (the original pattern re-draped from the original drape) holds when its
#: vertices land on average at most this far from the original drape (cm) ...
NULL_MEAN_CM = 1.0
#: ... and their 95th percentile at most this far (cm): a re-drape that does not reproduce
#: the garment it started from (a body that does not fit it) cannot rank two patterns.
NULL_P95_CM = 2.5
#: Two re-drapes whose worst-panel stretch p95 above the null's differ by at most this
#: (unitless) tie on stretch ...
VERDICT_STRETCH_TIE = 0.005
#: ... and whose displacement p95 from their start differ by at most this (cm) tie on
#: displacement (a few mm: the settle test's own resolution).
VERDICT_DISPLACEMENT_TIE_CM = 0.2
