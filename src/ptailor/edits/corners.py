"""A cut's corners made vertices: a sketched polyline embedded in the mesh.

A cut splits triangles on the straight crossings of its edges, so a corner of the cutting
line that falls inside a triangle (the tip of a V) is lost: the new edge runs straight
across that triangle, short of the tip (a V asked 10 cm deep was 8.8 cm on a 4 cm mesh).
:func:`embed_polyline` first makes each such corner a vertex: the triangle that holds it in
the view's projection is split in three at it (or, where it lies on an edge, the edge's
triangles in two), in the original drape, the edited drape and the pattern with the same
barycentric coordinates, so the cut then passes exactly through it in the drape and in the
pattern. Next to a corner sharper than the triangles are small, an edge can cross both of
its arms with both ends on the kept side (the split keeps such an edge whole, and the cloth
inside the corner with it: the tip was then a vertex inside the kept cloth); such edges are
split at their crossings until the polyline crosses every edge at most once.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from ptailor import tolerances as tol
from ptailor.edits import tolerances as edit_tol
from ptailor.edits.state import EditState
from ptailor.geometry.topology import edge_keys
from ptailor.model.garment import Garment, panel_labels
from ptailor.model.structure import structure

#: ``project(X) -> P``: drape points ``(n, 3)`` to image points ``(n, 2)``.
Projection = Callable[[np.ndarray], np.ndarray]
#: ``field(X) -> phi``: the cut's field at drape points ``(n, 3)``, ``(n,)``: removed where
#: negative.
Field = Callable[[np.ndarray], np.ndarray]


@dataclass
class _Mesh:
    """The arrays an insertion grows: drapes (original, edited), pattern, triangles and the
    input triangle each triangle comes from."""

    V3b: np.ndarray
    V3e: np.ndarray
    V2: np.ndarray
    F3: np.ndarray
    F2: np.ndarray
    parent: np.ndarray


def mean_edge(V: np.ndarray, F: np.ndarray) -> float:
    """Mean edge length of a mesh (the scale the split's snap is relative to)."""
    E = V[F[:, [1, 2, 0]]] - V[F]
    return float(np.linalg.norm(E, axis=2).mean())


def embed_polyline(
    state: EditState,
    project: Projection,
    Q: np.ndarray,
    *,
    field: Field,
) -> tuple[EditState, int]:
    """Make a polyline's corners, and its crossings with edges it crosses more than once,
    vertices of the garment where the cut passes through them.

    Every triangle that holds an inner point of ``Q`` (a corner: the ends are extended
    straight) in the projection of the edited drape, where the cut passes through that
    point (``field`` within the snap of 0 at its drape position), gets a vertex there: a
    point within ``edit_tol.CUT_CORNER_SNAP_REL`` mean edge lengths of a vertex already has
    one; within that of an edge, the edge is split (each of its triangles in two: one new
    drape vertex, one new pattern vertex per side of a seam); else the triangle is split in
    three. Then an edge the polyline crosses where the split cannot see it (twice, next to a
    corner sharper than the triangles are small, or once with no change of sign between its
    ends, one of them on the polyline) is split at its crossings until none is. Positions
    follow by the same barycentric coordinates in the original drape, the edited drape and
    the pattern.

    Parameters
    ----------
    state : EditState
    project : callable
        ``(n, 3) -> (n, 2)``: the view's image of drape points.
    Q : (k, 2) float array
        The polyline in the image, ``k >= 2``.
    field : callable, keyword-only
        ``(n, 3) -> (n,)``: the cut's field (:data:`Field`).

    Returns
    -------
    state : EditState
        The same garment with the points inserted (panels, names and outline flags kept;
        the new triangles follow the input's).
    inserted : int
        Drape vertices inserted.
    """
    g = state.base
    mesh = _Mesh(g.V3, state.V3, g.V2, g.F3, g.F2, np.arange(len(g.F3)))
    h = mean_edge(state.V3, g.F3)
    r = edit_tol.CUT_CORNER_SNAP_REL * h

    def on_level(X: np.ndarray) -> np.ndarray:
        return np.abs(field(X)) <= r

    Q = np.asarray(Q, float).reshape(-1, 2)
    for q in Q[1:-1]:  # a loop over a sketch's few corners
        for _ in range(len(_candidates(mesh, project, q, on_level, r)[0])):
            faces, L, near_edge = _candidates(mesh, project, q, on_level, r)
            if len(faces) == 0:
                break
            if near_edge[0] >= 0:
                f, c = int(faces[0]), int(near_edge[0])
                a, b = mesh.F3[f, (c + 1) % 3], mesh.F3[f, (c + 2) % 3]
                Pa, Pb = project(mesh.V3e[[a, b]])
                ab = Pb - Pa
                t = float(np.clip((q - Pa) @ ab / max(float(ab @ ab), tol.TINY), 0.0, 1.0))
                _split_edge(mesh, int(a), int(b), t)
            else:
                _split_face(mesh, int(faces[0]), L[0])
    # each split leaves one crossing fewer on the edge, and the edges it makes from a point
    # on the polyline cross it at most once more: a bounded number of splits
    snap = edit_tol.SPLIT_SNAP_REL * h
    excess = _hidden_crossings(mesh, project, Q, field, r, snap)
    for _ in range(4 * len(excess[0]) + len(Q)):  # a loop over the few edges crossed twice
        edges, t = _hidden_crossings(mesh, project, Q, field, r, snap)
        if len(edges) == 0:
            break
        _split_edge(mesh, int(edges[0, 0]), int(edges[0, 1]), float(t[0]))
    inserted = len(mesh.V3b) - len(g.V3)
    if inserted == 0:
        return state, 0
    return _rebuilt(state, mesh), inserted


def _hidden_crossings(
    mesh: _Mesh, project: Projection, Q: np.ndarray, field: Field, r: float, snap: float
) -> tuple[np.ndarray, np.ndarray]:
    """Drape edges a polyline (its ends extended) crosses in the image, where the cut
    passes, where the split would not see it: twice or more, or once with no change of sign
    of the (snapped) field between their ends; each edge ``(a, b)`` and its first
    crossing's parameter from ``a``.

    Returns
    -------
    edges : (e, 2) int array
    t : (e,) float array
    """
    F = mesh.F3
    E = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    _, first = np.unique(edge_keys(E, n=len(mesh.V3e)), return_index=True)
    E = np.sort(E[first], axis=1)
    P = project(mesh.V3e)
    Pa, d = P[E[:, 0]], P[E[:, 1]] - P[E[:, 0]]
    A, w = Q[:-1], Q[1:] - Q[:-1]

    def cross(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        return x[..., 0] * y[..., 1] - x[..., 1] * y[..., 0]

    den = cross(d[:, None], w[None])  # (e, k - 1)
    ok = np.abs(den) > tol.TINY
    den = np.where(ok, den, 1.0)
    ap = A[None] - Pa[:, None]
    t = cross(ap, w[None]) / den
    s = cross(ap, d[:, None]) / den
    lo = np.where(np.arange(len(A)) == 0, -np.inf, 0.0)
    hi = np.where(np.arange(len(A)) == len(A) - 1, np.inf, 1.0)
    length = np.linalg.norm(d, axis=1)[:, None]
    hit = ok & (t * length > r) & ((1.0 - t) * length > r) & (s >= lo) & (s <= hi)
    # distinct crossings: a corner's two segments meet an edge at one point
    t = np.where(hit, t, np.inf)
    t.sort(axis=1)
    gap = np.diff(np.where(np.isfinite(t), t, 2.0), axis=1, prepend=-1.0)
    count = (np.isfinite(t) & (gap * length > r)).sum(axis=1)
    phi = field(mesh.V3e)
    s_ = np.where(np.abs(phi) <= snap, 0.0, phi)[E]
    hidden = np.flatnonzero((count >= 2) | ((count == 1) & (s_[:, 0] * s_[:, 1] >= 0)))
    if len(hidden) == 0:
        return np.zeros((0, 2), int), np.zeros(0)
    e, t0 = E[hidden], t[hidden, 0]
    X = (1.0 - t0[:, None]) * mesh.V3e[e[:, 0]] + t0[:, None] * mesh.V3e[e[:, 1]]
    keep = np.abs(field(X)) <= r
    return e[keep], t0[keep]


def _candidates(
    mesh: _Mesh, project: Projection, q: np.ndarray, on_level: Field, r: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Triangles that hold ``q`` (within ``r``) with no corner within ``r`` of it, where
    the cut passes through its drape position.

    Returns
    -------
    faces : (c,) int array
    L : (c, 3) float array
        ``q``'s barycentric coordinates in each.
    near_edge : (c,) int array
        The corner opposite the edge ``q`` lies on (within ``r``), -1 for none.
    """
    F = mesh.F3
    P = project(mesh.V3e)
    A, B, C = P[F[:, 0]], P[F[:, 1]], P[F[:, 2]]
    u, w, d = B - A, C - A, q[None] - A
    den = u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0]
    ok = np.abs(den) > tol.TINY
    den = np.where(ok, den, 1.0)
    lb = (d[:, 0] * w[:, 1] - d[:, 1] * w[:, 0]) / den
    lc = (u[:, 0] * d[:, 1] - u[:, 1] * d[:, 0]) / den
    L = np.stack([1.0 - lb - lc, lb, lc], 1)
    # distance of q to each edge's line: barycentric times the height over that edge
    opp = np.stack([C - B, A - C, B - A], 1)
    height = np.abs(den)[:, None] / np.maximum(np.linalg.norm(opp, axis=2), tol.TINY)
    dist = L * height
    inside = ok & np.all(dist >= -r, axis=1)
    near_corner = (np.linalg.norm(P[F] - q[None, None], axis=2) <= r).any(axis=1)
    cand = np.flatnonzero(inside & ~near_corner)
    if len(cand) == 0:
        return cand, np.zeros((0, 3)), np.zeros(0, int)
    Lc = np.clip(L[cand], 0.0, None)
    Lc /= Lc.sum(axis=1, keepdims=True)
    X = np.einsum("ij,ijk->ik", Lc, mesh.V3e[F[cand]])
    keep = np.asarray(on_level(X), bool)
    cand, Lc, dc = cand[keep], Lc[keep], dist[cand[keep]]
    near_edge = np.where((dc <= r).any(axis=1), np.argmin(dc, axis=1), -1)
    return cand, Lc, near_edge


def _split_face(mesh: _Mesh, f: int, L: np.ndarray) -> None:
    """Split triangle ``f`` in three at barycentric coordinates ``L`` ``(3,)``."""
    a3, a2 = mesh.F3[f], mesh.F2[f]
    x3, x2 = len(mesh.V3b), len(mesh.V2)
    mesh.V3b = np.concatenate([mesh.V3b, [L @ mesh.V3b[a3]]])
    mesh.V3e = np.concatenate([mesh.V3e, [L @ mesh.V3e[a3]]])
    mesh.V2 = np.concatenate([mesh.V2, [L @ mesh.V2[a2]]])
    rot = np.array([[0, 1], [1, 2], [2, 0]])  # each edge of f with the new vertex
    T3 = np.concatenate([a3[rot], np.full((3, 1), x3)], 1)
    T2 = np.concatenate([a2[rot], np.full((3, 1), x2)], 1)
    _replace_faces(mesh, np.array([f]), T3, T2, np.full(3, f))


def _split_edge(mesh: _Mesh, a: int, b: int, t: float) -> None:
    """Split the drape edge ``(a, b)`` at ``t`` (from ``a``), and every triangle on it in
    two."""
    F3 = mesh.F3
    # the triangles on the edge, each rotated so that the edge is its first two corners
    has = np.isin(F3, [a, b])
    rows = np.flatnonzero(has.sum(axis=1) == 2)
    k = np.argmin(has[rows], axis=1) + 1  # the corner after the two edge corners
    cyc = (k[:, None] + np.arange(3)[None]) % 3
    R3 = np.take_along_axis(F3[rows], cyc, axis=1)
    R2 = np.take_along_axis(mesh.F2[rows], cyc, axis=1)
    tl = np.where(R3[:, 0] == a, t, 1.0 - t)  # from each row's first corner
    x3 = len(mesh.V3b)
    point = np.array([[1.0 - t], [t]])
    mesh.V3b = np.concatenate([mesh.V3b, [(point * mesh.V3b[[a, b]]).sum(0)]])
    mesh.V3e = np.concatenate([mesh.V3e, [(point * mesh.V3e[[a, b]]).sum(0)]])
    # one new pattern vertex per pattern edge (two where the edge is a seam)
    key2 = np.sort(R2[:, :2], axis=1)
    _, first, inv = np.unique(key2, axis=0, return_index=True, return_inverse=True)
    inv = inv.ravel()
    P2 = (1.0 - tl[first, None]) * mesh.V2[R2[first, 0]] + tl[first, None] * mesh.V2[R2[first, 1]]
    x2 = len(mesh.V2) + inv
    mesh.V2 = np.concatenate([mesh.V2, P2])
    T3 = np.concatenate(
        [np.stack([R3[:, 0], np.full(len(rows), x3), R3[:, 2]], 1),
         np.stack([np.full(len(rows), x3), R3[:, 1], R3[:, 2]], 1)]
    )  # fmt: skip
    T2 = np.concatenate(
        [np.stack([R2[:, 0], x2, R2[:, 2]], 1), np.stack([x2, R2[:, 1], R2[:, 2]], 1)]
    )
    _replace_faces(mesh, rows, T3, T2, np.concatenate([rows, rows]))


def _replace_faces(
    mesh: _Mesh, rows: np.ndarray, T3: np.ndarray, T2: np.ndarray, parent_rows: np.ndarray
) -> None:
    """Replace triangles ``rows`` by ``T3``/``T2`` (each from ``parent_rows``), in place:
    the new triangles take the old ones' place in the order."""
    keep = np.ones(len(mesh.F3), bool)
    keep[rows] = False
    pos = np.concatenate([np.flatnonzero(keep), parent_rows]).astype(float)
    pos[keep.sum() :] += 0.5  # right after the triangle they come from
    order = np.argsort(pos, kind="stable")
    mesh.F3 = np.concatenate([mesh.F3[keep], T3])[order]
    mesh.F2 = np.concatenate([mesh.F2[keep], T2])[order]
    mesh.parent = np.concatenate([mesh.parent[keep], mesh.parent[parent_rows]])[order]


def _rebuilt(state: EditState, mesh: _Mesh) -> EditState:
    """The state on the grown mesh: the panels keep their names and flags, the new pattern
    vertices are interior or on edges whose ends keep their outline flags."""
    g = state.base
    plist = state.panels
    flab = panel_labels(plist, len(g.F3))
    base = Garment(
        V3=mesh.V3b,
        F3=mesh.F3,
        V2=mesh.V2,
        F2=mesh.F2,
        face_group=flab[mesh.parent],
        group_names=tuple(p.name for p in plist),
        units=g.units,
        frame=g.frame,
    )
    new_panels = structure(base).panels
    even = {p.name: bool(state.even[p.index]) for p in plist}
    free = None
    if state.outline_free is not None:
        free = np.zeros(len(mesh.V2), bool)
        free[: len(g.V2)] = state.outline_free
    return replace(
        state,
        base=base,
        V3=mesh.V3e,
        panels=new_panels,
        even=np.array([even.get(q.name, False) for q in new_panels]),
        outline_free=free,
    )
