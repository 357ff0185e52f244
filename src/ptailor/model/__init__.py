"""The garment: one triangle mesh seen twice (drape ``V3, F3`` and pattern ``V2, F2``)."""

from ptailor.model.garment import Garment, Panel, panels
from ptailor.model.seams import Seam, seams

__all__ = ["Garment", "Panel", "Seam", "panels", "seams"]
