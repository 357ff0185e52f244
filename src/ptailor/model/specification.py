"""A parametric sewing pattern: panels of straight and curved edges, and stitches.

The data model of a GarmentCode or Garment-Pattern-Generator *specification*: each panel is
a closed loop of edges between its vertices (its own 2D frame), placed in 3D by a
translation and an XYZ Euler rotation; a stitch sews an edge of one panel to an edge of
another. Edge curves are evaluated by :mod:`ptailor.geometry.curves`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ptailor.geometry.curves import curve_points

__all__ = ["SpecEdge", "SpecPanel", "Specification", "Stitch"]


@dataclass(frozen=True)
class SpecEdge:
    """One panel edge.

    Attributes
    ----------
    endpoints : (int, int)
        Indices into the panel's vertices: start, end.
    kind : str
        ``straight``, ``quadratic``, ``cubic`` or ``circle``
        (:data:`ptailor.geometry.curves.CURVE_KINDS`).
    params : float array
        The curve's parameters (relative control points ``(1, 2)`` / ``(2, 2)``, or an
        arc's ``(radius, large_arc, right)`` in the specification's units).
    encoding : str
        How the file wrote the curvature: ``none``, ``list`` (Garment-Pattern-Generator's
        ``[x, y]``) or ``typed`` (GarmentCode's ``{"type", "params"}``).
    """

    endpoints: tuple[int, int]
    kind: str
    params: np.ndarray
    encoding: str = "none"


@dataclass(frozen=True)
class SpecPanel:
    """One panel.

    Attributes
    ----------
    name : str
    vertices : (k, 2) float array
        In the specification's units, the panel's own frame.
    edges : tuple of SpecEdge
        In loop order: each edge ends where the next one starts.
    translation : (3,) float array
    rotation : (3,) float array
        XYZ Euler angles, degrees.
    """

    name: str
    vertices: np.ndarray
    edges: tuple[SpecEdge, ...]
    translation: np.ndarray
    rotation: np.ndarray

    def edge_points(self, i: int, t: np.ndarray) -> np.ndarray:
        """Points ``(len(t), 2)`` of edge ``i`` at parameters ``t``."""
        e = self.edges[i]
        a, b = e.endpoints
        return curve_points(self.vertices[a], self.vertices[b], e.kind, e.params, t)

    def edge_lengths(self, samples: int = 512) -> np.ndarray:
        """Each edge curve's length ``(e,)``, as a polyline of ``samples`` segments."""
        t = np.linspace(0.0, 1.0, samples + 1)
        X = np.stack([self.edge_points(i, t) for i in range(len(self.edges))])
        return np.linalg.norm(np.diff(X, axis=1), axis=2).sum(axis=1)

    def outline(self, per_edge: int = 64) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The closed outline sampled ``per_edge`` times per edge (each edge's end left to
        the next edge).

        Returns
        -------
        P : (k, 2) float array
        edge : (k,) int array
            The edge each sample lies on.
        t : (k,) float array
            Its parameter on that edge.
        """
        t = np.linspace(0.0, 1.0, per_edge, endpoint=False)
        P = np.vstack([self.edge_points(i, t) for i in range(len(self.edges))])
        edge = np.repeat(np.arange(len(self.edges)), per_edge)
        return P, edge, np.tile(t, len(self.edges))

    def placement(self, X: np.ndarray) -> np.ndarray:
        """Panel points ``(k, 2)`` placed in 3D ``(k, 3)`` (specification units)."""
        from scipy.spatial.transform import Rotation

        R = Rotation.from_euler("xyz", self.rotation, degrees=True).as_matrix()
        X3 = np.column_stack([X, np.zeros(len(X))])
        return X3 @ R.T + self.translation


@dataclass(frozen=True)
class Stitch:
    """Two panel edges sewn together: ``((panel, edge), (panel, edge))``."""

    sides: tuple[tuple[str, int], tuple[str, int]]


@dataclass(frozen=True)
class Specification:
    """A parametric pattern as read from its file.

    Attributes
    ----------
    path : str
        The file it was read from (errors name it).
    flavour : str
        ``garmentcode`` (typed curvature) or ``gpg`` (Garment-Pattern-Generator).
    panels : tuple of SpecPanel
        In the file's order.
    stitches : tuple of Stitch
    units_in_meter : float
        Specification units per metre (``100``: centimetres).
    raw : dict
        The JSON as read; the writer keeps everything it does not change.
    units_source : str
        Where ``units_in_meter`` came from: ``file`` (``properties.units_in_meter``),
        ``option`` (``--spec-units``), ``absent`` (not given: 100 until the run infers it
        from the garment) or ``garment`` (so inferred).
    """

    path: str
    flavour: str
    panels: tuple[SpecPanel, ...]
    stitches: tuple[Stitch, ...]
    units_in_meter: float
    raw: dict = field(repr=False, compare=False, default_factory=dict)
    units_source: str = "file"

    @property
    def cm_per_unit(self) -> float:
        return 100.0 / self.units_in_meter

    def panel(self, name: str) -> SpecPanel:
        for p in self.panels:  # a loop over panels
            if p.name == name:
                return p
        raise KeyError(name)
