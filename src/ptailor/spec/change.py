"""What the adjustment did to one specification panel."""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["PanelChange"]


@dataclass(frozen=True)
class PanelChange:
    """What the adjustment did to one specification panel.

    Attributes
    ----------
    name : str
    source : str
        The input panel it came from.
    how : str
        ``carried`` (same triangles: every point carried) or ``outline`` (its triangles
        changed: edges read off the adjusted mesh outline).
    edge_sources : tuple of int
        Per edge, the input edge it came from (``-1``: a new edge).
    bent : tuple of (int, float)
        Straight edges that got a curve, with their points' largest distance from the chord
        (specification units).
    refit : tuple of float
        Per edge, the largest distance of its carried points from the refitted curve
        (specification units).
    removed : tuple of int
        Input edges that left the outline.
    to_pattern : (A (2, 2), b (2,))
        Affine map from the new panel's frame to the adjusted pattern (computation units):
        ``Y = X @ A.T + b``.
    """

    name: str
    source: str
    how: str
    edge_sources: tuple[int, ...]
    bent: tuple[tuple[int, float], ...]
    refit: tuple[float, ...]
    removed: tuple[int, ...] = ()
    to_pattern: tuple = field(default=(), repr=False)
    panel: int = -1  # index into the adjusted garment's panels
