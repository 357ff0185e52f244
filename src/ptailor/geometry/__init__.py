"""Pure array geometry: triangles, 2x2 closed forms, rotations, segments, tube axes,
pattern-to-drape maps and labels.

Every function takes and returns plain numpy arrays (``V`` vertices, ``F`` triangles), in
the style of gpytoolbox and libigl; the only project import is :mod:`ptailor.tolerances`.
"""

from ptailor.geometry.closed_forms import det2, inv2, sqrt_spd2
from ptailor.geometry.labels import component_labels, scatter_labels, used_indices
from ptailor.geometry.pattern_maps import (
    least_squares_preimages,
    pattern_jacobians,
    pseudo_inverses,
)
from ptailor.geometry.rotations import (
    closest_rotations,
    det3,
    max_trace_rotations,
    rigid_fit,
    rigid_fit_groups,
    rigid_fits_3d,
)
from ptailor.geometry.segments import nearest_segment_distance, segment_feet
from ptailor.geometry.triangles import (
    edge_lengths,
    edge_matrices,
    signed_areas_2d,
    triangle_areas,
    triangle_normals,
)
from ptailor.geometry.tube_axis import extent_axis, normal_tensor, tube_axis

__all__ = [
    "closest_rotations",
    "component_labels",
    "det2",
    "det3",
    "edge_lengths",
    "edge_matrices",
    "extent_axis",
    "inv2",
    "least_squares_preimages",
    "max_trace_rotations",
    "nearest_segment_distance",
    "normal_tensor",
    "pattern_jacobians",
    "pseudo_inverses",
    "rigid_fit",
    "rigid_fit_groups",
    "rigid_fits_3d",
    "scatter_labels",
    "segment_feet",
    "signed_areas_2d",
    "sqrt_spd2",
    "triangle_areas",
    "triangle_normals",
    "tube_axis",
    "used_indices",
]
