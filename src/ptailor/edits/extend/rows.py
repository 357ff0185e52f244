"""The rows ``extend`` adds: their plan (opening, pattern columns, grid), their triangles."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor import tolerances as tol
from ptailor.edits.opening import OpeningEdges
from ptailor.edits.pattern_distance import PatternDistance, edge_distance
from ptailor.edits.state import EditState
from ptailor.errors import PtailorError
from ptailor.geometry.triangles import triangle_normals
from ptailor.model.garment import panel_labels


@dataclass(frozen=True)
class RowPlan:
    """What both ways of growing rows beyond an opening share.

    Attributes
    ----------
    name : str
        The opening, for messages.
    by : float
        Length added.
    rows : int
        Rows of new triangles.
    oe : OpeningEdges
        The opening's ``k`` edges.
    cols : (c,) int array
        Pattern vertices on the opening (the columns), ascending.
    ca, cb : (k,) int arrays
        Column of the start and of the end of each opening edge.
    flab : (m,) int array
        Panel of every triangle.
    orient : (k,) float array
        ``-1`` where the edge's panel is mirrored, else ``+1``.
    n_src : (k, 3) float array
        Unit normals of the edges' triangles on the edited drape.
    field : PatternDistance
        Pattern distance from the opening's edges, each in its own panel.
    A3, B3 : (rows + 1, k) int arrays
        Drape vertices at the start and end of each edge, row by row (row 0: the opening).
    A2, B2 : (rows + 1, k) int arrays
        The same in the pattern.
    odd : (rows, k) bool array
        Checkerboard of the quads (diagonal on ties).
    src : (2 rows k,) int array
        Opening edge each new triangle grows from.
    """

    name: str
    by: float
    rows: int
    oe: OpeningEdges
    cols: np.ndarray
    ca: np.ndarray
    cb: np.ndarray
    flab: np.ndarray
    orient: np.ndarray
    n_src: np.ndarray
    field: PatternDistance
    A3: np.ndarray
    B3: np.ndarray
    A2: np.ndarray
    B2: np.ndarray
    odd: np.ndarray
    src: np.ndarray

    @property
    def nc(self) -> int:
        """Number of columns."""
        return len(self.cols)

    @property
    def col_panel(self) -> np.ndarray:
        """Panel of each column, ``(c,)``."""
        out = np.empty(len(self.cols), dtype=np.int64)
        out[self.ca], out[self.cb] = self.flab[self.oe.face], self.flab[self.oe.face]
        return out

    @property
    def inv(self) -> np.ndarray:
        """Column of the start (first ``k``) and end (last ``k``) of each edge, ``(2k,)``."""
        return np.concatenate([self.ca, self.cb])


def row_plan(state: EditState, oe: OpeningEdges, *, name: str, by: float, rows: int) -> RowPlan:
    """The :class:`RowPlan` of ``rows`` rows beyond an opening of ``state``."""
    g = state.base
    k = len(oe.a3)
    flab = panel_labels(state.panels, g.n_faces)
    cols, inv = np.unique(np.concatenate([oe.a2, oe.b2]), return_inverse=True)
    nc = len(cols)
    ca, cb = inv[:k], inv[k:]
    grid3 = np.vstack([oe.a3[None], len(g.V3) + np.arange(rows * k).reshape(rows, k)])
    grid2 = np.vstack([cols[None], len(g.V2) + np.arange(rows * nc).reshape(rows, nc)])
    return RowPlan(
        name=name,
        by=by,
        rows=rows,
        oe=oe,
        cols=cols,
        ca=ca,
        cb=cb,
        flab=flab,
        orient=np.where([p.mirrored for p in state.panels], -1.0, 1.0)[flab[oe.face]],
        n_src=triangle_normals(state.V3, g.F3[oe.face]),
        field=edge_distance(g.V2, oe.a2, oe.b2, flab[oe.face]),
        A3=grid3,
        B3=grid3[:, np.roll(np.arange(k), -1)],
        A2=grid2[:, ca],
        B2=grid2[:, cb],
        odd=(np.arange(rows)[:, None] + np.arange(k)[None, :]) % 2 == 1,
        src=np.broadcast_to(np.arange(k)[None, :, None], (rows, k, 2)).reshape(-1),
    )


@dataclass(frozen=True)
class Rows:
    """New rows beyond an opening, in the drape (edited and original) and the pattern.

    Attributes
    ----------
    new_e, new_b : (rows k, 3) float arrays
        Edited and original drape positions, row by row (``k`` per row, opening order).
    new_2 : (rows c, 2) float array
        Pattern positions, ``c`` columns per row.
    use_b : (rows, k) bool array
        Quad diagonals (:func:`quad_rows`).
    smoothing : int
        Smoothing passes of the drape rows.
    pattern_smoothing : int
        Smoothing passes of the pattern directions (``measure: pattern``).
    """

    new_e: np.ndarray
    new_b: np.ndarray
    new_2: np.ndarray
    use_b: np.ndarray
    smoothing: int
    pattern_smoothing: int = 0


def quad_rows(A: np.ndarray, B: np.ndarray, use_b: np.ndarray) -> np.ndarray:
    """Triangulate the quads between consecutive rows of vertex indices.

    Parameters
    ----------
    A, B : (r + 1, k) int arrays
        Row ``j`` holds the vertex at the start and at the end of each opening edge; row 0
        is the opening, whose half-edge ``A[0] -> B[0]`` has its triangle on the left.
    use_b : (r, k) bool array
        Split each quad along ``A[j] - B[j + 1]`` (else ``B[j] - A[j + 1]``).

    Returns
    -------
    (2 r k, 3) int array
        Two triangles per quad, row by row; oriented like the triangles at the opening
        (each row's edge ``B[j] -> A[j]`` is the twin of the row below).
    """
    a0, a1, b0, b1 = A[:-1], A[1:], B[:-1], B[1:]
    u = use_b[..., None]
    t0 = np.where(u, np.stack([b0, a0, b1], -1), np.stack([b0, a0, a1], -1))
    t1 = np.where(u, np.stack([a0, a1, b1], -1), np.stack([b0, a1, b1], -1))
    return np.stack([t0, t1], axis=2).reshape(-1, 3)


def shorter_diagonals(V: np.ndarray, A: np.ndarray, B: np.ndarray, odd: np.ndarray) -> np.ndarray:
    """Which diagonal splits each quad between rows: the shorter one, ties in a checkerboard.

    Parameters
    ----------
    V : (n, d) float array
        Positions of the grid's vertices.
    A, B : (r + 1, k) int arrays
        The rows' vertices (as :func:`quad_rows` takes them).
    odd : (r, k) bool array
        The checkerboard used on ties.

    Returns
    -------
    (r, k) bool array
        ``use_b`` of :func:`quad_rows`: split along ``A[j] - B[j + 1]``.
    """
    dA = np.linalg.norm(V[A[1:]] - V[B[:-1]], axis=2)
    dB = np.linalg.norm(V[A[:-1]] - V[B[1:]], axis=2)
    tie = np.abs(dA - dB) <= tol.ROUNDING_REL * (dA + dB)
    return np.where(tie, odd, dB < dA)


def crossing_error(name: str, by: float, where: str) -> PtailorError:
    """The error for rows that would cross ``where`` (``"in the drape"``, a panel's pattern)."""
    return PtailorError(
        f"extend {name} by {by:g}: the new rows would cross {where} (the opening turns too "
        "sharply for that length); extend by less"
    )
