"""ptailor: scale-preserving 2D sewing-pattern adjustment driven by 3D garment edits.

The layout follows the architecture:

- :mod:`ptailor.model`   the garment (drape + pattern), panels, seams, openings, units
- :mod:`ptailor.method`  intrinsic scale targets and the ARAP/ASAP stitching solver
- :mod:`ptailor.edits`   recipe operations, one module each, registered by name
- :mod:`ptailor.formats` readers and writers in a dispatch table keyed by extension
- :mod:`ptailor.report`  distortion metrics and the report
- :mod:`ptailor.cli`     the thin click layer, one module per command
"""

__version__ = "0.1.0"
