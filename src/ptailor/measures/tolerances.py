"""Every tolerance of the points of measure (:mod:`ptailor.measures`).

Constants only, each with what it bounds, its unit and why that value.
"""

#: A drape vertex closer to a section's plane than this fraction of the garment's size
#: (relative to its bounding-box diagonal) lies on the plane: a plane through a column of
#: vertices (a centre-front seam) cuts along it, never into slivers by rounding noise.
PLANE_SNAP = 1e-9
#: A limb whose axis is within this of the up axis (the sine of the angle, unitless) has no
#: "over" direction from up: its overarm is taken on the wearer's front.
VERTICAL_LIMB = 1e-6
