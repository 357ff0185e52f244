"""Mesh intake: weld coincident drape vertices, drop duplicate and zero-area faces, and check
that drape and pattern are in the same units.

CAD systems export garments per piece: each panel's drape vertices apart, the seams only
coincident positions. ptailor's model needs one drape vertex per seam point (seams are the 3D
edges whose two faces use different 2D edges), so such a drape is welded on reading. Every
function here is pure and returns index maps (gpytoolbox / libigl style): ``I`` (new to old)
and ``J`` (old to new) for vertices, ``keep`` (new to old) for faces.

The weld is done here with a k-d tree rather than with pymeshlab's
``meshing_merge_close_vertices``: measured on the shared garments, pymeshlab's merge is exact
in positions and keeps the surviving vertices in order (a vertex attribute carries the
index map), but it merges greedily (points 0.6 and 1.2 tolerances apart along a line leave
two vertices: the result depends on the vertex order in the file), deletes the faces the
merge makes degenerate without saying which, and cannot tell a 3D-duplicate face from two
panels' faces that only share drape vertices (it sees no ``vt``). pymeshlab is used for what
it is best at: the topological measures that ``inspect`` shows (:func:`topology`). The units
check is :mod:`ptailor.model.unit_ratio`'s.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from ptailor import tolerances as tol
from ptailor.errors import PtailorError
from ptailor.geometry.labels import component_labels, used_indices
from ptailor.geometry.topology import edge_groups, edge_keys, half_edges
from ptailor.geometry.triangles import edge_lengths, triangle_areas
from ptailor.model import tolerances as model_tol
from ptailor.model.unit_ratio import UNIT_RATIO_RANGE, UnitMismatchError, check_units, unit_ratios

# the units check moved to ptailor.model.unit_ratio; its names are still importable from here
__all__ = [
    "UNIT_RATIO_RANGE",
    "WELD_REL",
    "IntakeResult",
    "UnitMismatchError",
    "check_units",
    "duplicate_faces",
    "intake",
    "non_manifold_edges",
    "topology",
    "unit_ratios",
    "weld_joins_panels",
    "weld_vertices",
    "zero_area_faces",
]

#: see :data:`ptailor.model.tolerances.WELD_REL`
WELD_REL = model_tol.WELD_REL


def weld_vertices(
    V: np.ndarray, F: np.ndarray, *, distance: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Merge the referenced vertices closer than ``distance`` (transitively).

    Clusters are the connected components of the "closer than ``distance``" graph, so they
    do not depend on the vertex order. Each cluster keeps the lexicographically smallest
    position of its vertices (no averaging: coincident seams stay exactly where the file put
    them, and the result does not depend on the vertex order); new vertices keep the order
    of the old ones. Unreferenced vertices are kept, never merged.

    Parameters
    ----------
    V : (n, 3) float array
        Finite positions.
    F : (m, 3) int array
    distance : float
        >= 0; 0 merges exactly coincident vertices only.

    Returns
    -------
    W : (k, 3) float array
        ``V[I]``.
    G : (m, 3) int array
        ``J[F]``; triangles may become degenerate (repeated corners).
    I : (k,) int array
        Old index of each new vertex.
    J : (n,) int array
        New index of each old vertex.
    """
    n = len(V)
    used = used_indices(F, n)
    if _clearly_apart(V[used], distance):  # a welded garment: every vertex its own cluster
        I = np.arange(n)
        return V[I], I[F], I, I.copy()
    from scipy.spatial import cKDTree  # (0.1-0.2 s to import: only when needed)

    pairs = cKDTree(V[used]).query_pairs(distance, output_type="ndarray")
    pairs = used[pairs] if len(pairs) else np.zeros((0, 2), dtype=np.int64)
    A = sp.coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, lab = connected_components(A, directed=False)
    # representative: the lexicographically smallest position in each cluster (then the
    # lowest index), so that the kept positions do not depend on the vertex order either
    order = np.lexsort((np.arange(n), V[:, 2], V[:, 1], V[:, 0]))
    rank = np.empty(n, dtype=np.int64)
    rank[order] = np.arange(n)
    best = np.full(lab.max() + 1 if n else 0, n, dtype=np.int64)
    np.minimum.at(best, lab, rank)
    rep = order[best]
    I = used_indices(rep, n)
    new_of_rep = np.empty(n, dtype=np.int64)
    new_of_rep[I] = np.arange(len(I))
    J = new_of_rep[rep[lab]]
    return V[I], J[F], I, J


#: a generic unit direction (no garment's axis): projections on it are seldom close
_DIRECTION = np.array([0.5377, 0.8314, 0.1402]) / np.linalg.norm([0.5377, 0.8314, 0.1402])


def _clearly_apart(P: np.ndarray, distance: float, *, rounds: int = 32) -> bool:
    """True when no two points of ``P`` ((k, 3) floats) lie within ``distance`` by a margin
    far above rounding, False when unsure: points that close project on a unit direction
    that close, so each is compared with its next neighbours in projection order."""
    if len(P) < 2 or P.shape[1] != 3:
        return len(P) < 2
    reach = (
        distance * (1 + model_tol.REPAIR_APART_MARGIN_REL)
        + float(np.abs(P).max()) * model_tol.REPAIR_APART_ROUNDING_REL
    )
    order = np.argsort(p := P @ _DIRECTION)
    p = p[order]
    for k in range(1, rounds + 1):
        close = np.flatnonzero(p[k:] - p[:-k] <= reach)
        if not close.size:
            return True
        a, b = order[close], order[close + k]
        if np.any(np.sqrt(((P[a] - P[b]) ** 2).sum(axis=1)) <= reach):
            return False
    return False


def weld_joins_panels(F3: np.ndarray, face_panel: np.ndarray, J: np.ndarray) -> int:
    """How many drape vertices a weld ``J`` merges with a vertex of another panel.

    Parameters
    ----------
    F3 : (m, 3) int array
        The drape triangles before the weld.
    face_panel : (m,) int array
        Panel of each triangle (the connected components of ``F2``).
    J : (n,) int array
        New index of each old vertex (:func:`weld_vertices`).

    Returns
    -------
    int
        The old vertices in merged groups (two or more old vertices) whose triangles lie on
        two or more panels (0: the weld joins no two panels, as in a welded garment, where
        seam vertices are already one vertex each).
    """
    n = len(J)
    big = np.iinfo(np.int64).max
    corner_panel = np.repeat(face_panel, 3)
    pmin = np.full(n, big, dtype=np.int64)
    pmax = np.full(n, -1, dtype=np.int64)
    np.minimum.at(pmin, F3.ravel(), corner_panel)
    np.maximum.at(pmax, F3.ravel(), corner_panel)
    used = np.flatnonzero(pmax >= 0)
    k = int(J.max()) + 1 if n else 0
    low = np.full(k, big, dtype=np.int64)
    high = np.full(k, -1, dtype=np.int64)
    np.minimum.at(low, J[used], pmin[used])
    np.maximum.at(high, J[used], pmax[used])
    size = np.bincount(J[used], minlength=k)
    mixed = (low != high) & (size > 1)
    return int(mixed[J[used]].sum())


def duplicate_faces(F3: np.ndarray, F2: np.ndarray) -> np.ndarray:
    """Faces that repeat an earlier face, in 3D and in 2D (any corner order).

    Parameters
    ----------
    F3, F2 : (m, 3) int arrays

    Returns
    -------
    (m,) bool array
        True for every copy after the first.
    """
    k3, k2 = _face_key(F3), _face_key(F2)
    if k3 is None or k2 is None:  # too many vertices for one integer per face
        key = np.concatenate([np.sort(F3, axis=1), np.sort(F2, axis=1)], axis=1)
        return ~np.isin(np.arange(len(F3)), np.unique(key, axis=0, return_index=True)[1])
    dup = np.zeros(len(F3), dtype=bool)
    s3 = np.sort(k3)
    if not np.any(s3[1:] == s3[:-1]):  # every drape face differs: no copies (the usual case)
        return dup
    order = np.lexsort((k2, k3))  # stable: each run of equal faces starts with the first
    same = (k3[order[1:]] == k3[order[:-1]]) & (k2[order[1:]] == k2[order[:-1]])
    dup[order[1:][same]] = True
    return dup


def _face_key(F: np.ndarray) -> np.ndarray | None:
    """One int64 per row of ``F`` ((m, 3) ints in ``0 .. n - 1``), equal for rows with the
    same corners in any order; None when ``n ** 3`` does not fit."""
    n = int(F.max()) + 1 if F.size else 1
    if n >= 2_000_000:
        return None
    a, b, c = (F[:, k].astype(np.int64) for k in range(3))
    lo = np.minimum(np.minimum(a, b), c)
    hi = np.maximum(np.maximum(a, b), c)
    return (lo * n + (a + b + c - lo - hi)) * n + hi


def zero_area_faces(V: np.ndarray, F: np.ndarray) -> np.ndarray:
    """Degenerate triangles: repeated corners, or area at most ``ZERO_AREA_REL`` times the
    squared bounding-box size of the referenced vertices (:func:`check_garment`'s test).

    Parameters
    ----------
    V : (n, 2) or (n, 3) float array
    F : (m, 3) int array

    Returns
    -------
    (m,) bool array
    """
    used = np.zeros(len(V), dtype=bool)
    used[F.ravel()] = True
    d = float(np.ptp(V if used.all() else V[used], axis=0).max()) if used.any() else 0.0
    area = triangle_areas(V, F)
    repeated = (F[:, 0] == F[:, 1]) | (F[:, 1] == F[:, 2]) | (F[:, 2] == F[:, 0])
    return repeated | (area <= model_tol.ZERO_AREA_REL * max(d, tol.TINY) ** 2)


def non_manifold_edges(F: np.ndarray) -> np.ndarray:
    """Edges used by more than two triangles (T-seams, a piece sewn onto another's middle).

    Parameters
    ----------
    F : (m, 3) int array

    Returns
    -------
    (k, 2) int array
        Each such edge once, its vertices ascending, rows sorted.
    """
    E = half_edges(F)
    E = E[E[:, 0] != E[:, 1]]
    if not len(E):
        return np.zeros((0, 2), dtype=np.int64)
    n = int(E.max()) + 1
    key = edge_keys(E, n=n)
    _, inv, cnt = edge_groups(key)
    many = np.unique(key[cnt[inv] > 2])
    return np.stack([many // n, many % n], axis=1)


def topology(V: np.ndarray, F: np.ndarray) -> dict:
    """pymeshlab's topological measures of a triangle mesh (for ``inspect``).

    Parameters
    ----------
    V : (n, 3) float array
    F : (m, 3) int array

    Returns
    -------
    dict
        ``non_manifold_edges`` (counted here, :func:`non_manifold_edges`: pymeshlab's
        ``non_two_manifold_edges`` depends on what the process measured before, measured
        with pymeshlab 2025.7: one T-seam edge counts 1 in a fresh process and 3 after a
        manifold mesh was measured), ``non_manifold_vertices``,
        ``faces_on_non_manifold_edges`` (pymeshlab's
        ``compute_selection_by_non_manifold_edges_per_face``), ``boundary_edges``,
        ``holes``, ``components``, ``genus`` (``None`` where pymeshlab leaves it undefined:
        a non-manifold mesh), ``unreferenced_vertices``.
    """
    import pymeshlab

    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=V, face_matrix=F.astype(np.int32)))
    t = ms.get_topological_measures()
    ms.compute_selection_by_non_manifold_edges_per_face()
    sel = int(ms.current_mesh().selected_face_number())
    manifold = bool(t["is_mesh_two_manifold"])
    return {
        "non_manifold_edges": len(non_manifold_edges(F)),
        "non_manifold_vertices": int(t["non_two_manifold_vertices"]),
        "faces_on_non_manifold_edges": sel,
        "boundary_edges": int(t["boundary_edges"]),
        "holes": int(t["number_holes"]) if manifold else None,
        "components": int(t["connected_components_number"]),
        "genus": int(t["genus"]) if manifold else None,
        "unreferenced_vertices": int(t["unreferenced_vertices"]),
    }


@dataclass(frozen=True)
class IntakeResult:
    """A repaired garment's arrays, its index maps and what was done.

    Attributes
    ----------
    V3 : (k, 3) float array
        Welded drape (``V3_in[vertex_map]``).
    F3 : (m', 3) int array
    V2 : (n2, 2) float array
        The pattern, untouched.
    F2 : (m', 3) int array
    faces : (m',) int array
        Input face of each kept face (ascending).
    vertex_map : (k,) int array
        Input drape vertex of each new one.
    record : dict
        JSON-ready counts (:func:`intake`).
    warnings : list of str
    lengths3 : (m', 3) float array or None
        ``edge_lengths(V3, F3)`` for :func:`unit_ratios` when nothing was welded or dropped.
    """

    V3: np.ndarray
    F3: np.ndarray
    V2: np.ndarray
    F2: np.ndarray
    faces: np.ndarray
    vertex_map: np.ndarray
    record: dict
    warnings: list[str] = field(default_factory=list)
    lengths3: np.ndarray | None = None


def intake(
    V3: np.ndarray,
    F3: np.ndarray,
    V2: np.ndarray,
    F2: np.ndarray,
    *,
    weld: str | float = "auto",
    path: str | None = None,
) -> IntakeResult:
    """Weld the drape, then drop duplicate and zero-area faces.

    Parameters
    ----------
    V3 : (n3, 3) float array
    F3 : (m, 3) int array
    V2 : (n2, 2) float array
    F2 : (m, 3) int array
    weld : ``"auto"``, ``"off"`` or float
        ``auto``: weld at ``WELD_REL`` times the mean drape edge length when that merges
        vertices of different panels (panels that touch only through coincident vertices,
        as per-piece CAD exports come); then every coincident group is welded; a
        number: weld at that distance (drape units) in any case; ``off``: never (a warning
        says when ``auto`` would have welded).
    path : str, optional
        Named in errors.

    Returns
    -------
    IntakeResult
        ``record`` holds ``weld`` (the mode), ``weld_distance``, ``welded_vertices``
        (vertices removed by the weld), ``pieces_before`` / ``pieces_after`` (connected
        drape pieces), ``duplicate_faces``, ``zero_area_faces_3d``, ``zero_area_faces_2d``
        and ``non_manifold_edges`` (after the repairs).

    Raises
    ------
    PtailorError
        Every face is degenerate.
    """
    m = len(F3)
    rec: dict = {"weld": weld if isinstance(weld, str) else "distance"}
    warnings: list[str] = []
    I = np.arange(len(V3))
    finite = m and (np.isfinite(V3).all() or np.isfinite(V3[used_indices(F3, len(V3))]).all())
    if not finite or len(F2) != m:
        # check_garment names the problem (NaNs, mismatched faces)
        rec.update(welded_vertices=0, duplicate_faces=0, zero_area_faces_3d=0)
        rec.update(zero_area_faces_2d=0, non_manifold_edges=0)
        return IntakeResult(V3, F3, V2, F2, np.arange(m), I, rec, warnings)
    lengths3 = edge_lengths(V3, F3)
    n_pieces = int(component_labels(F3, len(V3)).max()) + 1
    rec["pieces_before"] = n_pieces
    V3, F3, I, welded, warnings = _welded(V3, F3, V2, F2, weld=weld, mean_edge=lengths3.mean())
    rec.update(welded)
    z3, z2, dup = _bad_faces(V3, F3, V2, F2)
    drop = z3 | z2 | dup
    rec["duplicate_faces"] = int(dup.sum())
    rec["zero_area_faces_3d"] = int(z3.sum())
    rec["zero_area_faces_2d"] = int((z2 & ~z3).sum())
    if drop.all():
        what = "3D (drape)" if z3.any() else "2D (pattern)"
        raise PtailorError(f"every triangle is zero-area in {what}: nothing to adjust", path=path)
    keep = np.flatnonzero(~drop)
    F3, F2 = F3[keep], F2[keep]
    same = not rec["welded_vertices"] and not drop.any()  # V3 and F3 as measured before
    rec["pieces_after"] = n_pieces if same else int(component_labels(F3, len(V3)).max()) + 1
    lengths3 = lengths3 if same else None
    rec["non_manifold_edges"] = len(non_manifold_edges(F3))
    if drop.any():
        warnings.append(
            f"dropped {int(drop.sum())} triangle(s) on reading: {rec['duplicate_faces']} "
            f"duplicate, {rec['zero_area_faces_3d']} zero-area in 3D, "
            f"{rec['zero_area_faces_2d']} zero-area in 2D"
        )
    return IntakeResult(V3, F3, V2, F2, keep, I, rec, warnings, lengths3)


def _welded(
    V3: np.ndarray,
    F3: np.ndarray,
    V2: np.ndarray,
    F2: np.ndarray,
    *,
    weld: str | float,
    mean_edge: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict, list[str]]:
    """The drape welded as ``weld`` says (:func:`intake`).

    Returns
    -------
    V3 : (k, 3) float array
    F3 : (m, 3) int array
    I : (k,) int array
        Input vertex of each new one.
    record : dict
        ``weld_distance`` (None when nothing was welded) and ``welded_vertices``.
    warnings : list of str
        Why ``--weld off`` left coincident vertices of different panels apart.
    """
    dist = WELD_REL * float(mean_edge) if isinstance(weld, str) else float(weld)
    W, G, I2, J = weld_vertices(V3, F3, distance=dist)
    joins = 0
    if len(I2) < len(V3):
        joins = weld_joins_panels(F3, component_labels(F2, len(V2)), J)
    do_weld = weld != "off" and (weld != "auto" or joins > 0)
    if do_weld and len(I2) < len(V3):
        return W, G, I2, {"weld_distance": dist, "welded_vertices": len(J) - len(I2)}, []
    warnings = []
    if weld == "off" and joins:
        warnings.append(
            f"{joins} drape vertices of different panels coincide (an unwelded export?): "
            "--weld off keeps them apart, so the seams there are not seen"
        )
    record = {"weld_distance": None, "welded_vertices": 0}
    return V3, F3, np.arange(len(V3)), record, warnings


def _bad_faces(
    V3: np.ndarray, F3: np.ndarray, V2: np.ndarray, F2: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Faces to drop: zero-area in 3D, zero-area in 2D (when the pattern is finite), and
    duplicates of a face kept (:func:`duplicate_faces`, the zero-area ones left out); each
    ``(m,)`` bool."""
    z3 = zero_area_faces(V3, F3)
    finite2 = np.isfinite(V2).all() or np.isfinite(V2[used_indices(F2, len(V2))]).all()
    z2 = zero_area_faces(V2, F2) if finite2 else np.zeros(len(F2), bool)
    dup = duplicate_faces(F3, F2) & ~(z3 | z2)
    return z3, z2, dup
