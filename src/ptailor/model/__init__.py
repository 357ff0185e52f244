"""The garment: one triangle mesh seen twice (drape ``V3, F3`` and pattern ``V2, F2``)."""

from ptailor.model.garment import Garment, Panel
from ptailor.model.seams import Seam

# classes only: the functions stay in their modules (``ptailor.model.seams.seams``), so that
# ``ptailor.model.seams`` is the module, not a function hiding it
__all__ = ["Garment", "Panel", "Seam"]
