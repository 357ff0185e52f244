"""Matching a pattern specification to the garment mesh made from it.

Each specification panel is matched to one mesh panel by shape and by place: its outline
(every edge curve sampled) is fitted onto each mesh panel's outline by a rigid map
(reflections allowed: exporters mirror panels), and of the fits that match the shape, the
one that puts the panel where the specification places it in 3D wins (identical sleeve
halves, and the two sides of a symmetric front, differ only there). The specification's 3D
frame is GarmentCode's (y up, z front), turned onto the run's ``up`` and ``front``. Panels
and fits are paired by an assignment over the places. Then every stitch must land on a seam
of the mesh between the two matched panels.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor import tolerances as tol
from ptailor.errors import PtailorError
from ptailor.geometry.rotations import rigid_fit
from ptailor.method.transfer import locate_points
from ptailor.model.garment import Garment, Panel
from ptailor.model.polyline import resample_closed, signed_area
from ptailor.model.specification import Specification
from ptailor.model.units import CM_PER
from ptailor.pieces.draw import outer_loop
from ptailor.pieces.match import ClosedCurve, fit_residual, icp_fit, shape_fits

__all__ = ["PanelMatch", "SpecMatching", "StitchMatch", "match_specification", "spec_scale"]


@dataclass(frozen=True)
class PanelMatch:
    """A specification panel and the mesh panel it is.

    Attributes
    ----------
    spec : int
        Index into the specification's panels.
    panel : int
        Index into the garment's panels.
    R : (2, 2) float array
        Rotation or reflection; pattern point = ``R @ (k * spec point) + t`` with ``k`` the
        specification-to-computation unit scale.
    t : (2,) float array
    residual : float
        Mean outline distance over the outline's diagonal.
    distance : float
        Largest distance of the sampled specification outline from the mesh panel's
        outline, computation units.
    """

    spec: int
    panel: int
    R: np.ndarray
    t: np.ndarray
    residual: float
    distance: float

    def to_pattern(self, X: np.ndarray, k: float) -> np.ndarray:
        """Specification points ``(j, 2)`` to pattern points."""
        return (k * X) @ self.R.T + self.t

    def to_spec(self, Y: np.ndarray, k: float) -> np.ndarray:
        """Pattern points ``(j, 2)`` back to specification points."""
        return ((Y - self.t) @ self.R) / k


@dataclass(frozen=True)
class StitchMatch:
    """A stitch and the seam of the mesh it is.

    Attributes
    ----------
    stitch : int
        Index into the specification's stitches.
    seam : int
        Index into the garment's seams (``structure(g).seams``).
    spec_lengths : (float, float)
        The two edges' curve lengths, computation units.
    mesh_lengths : (float, float)
        The pattern lengths of the mesh's boundary along each edge, computation units.
    """

    stitch: int
    seam: int
    spec_lengths: tuple[float, float]
    mesh_lengths: tuple[float, float]


@dataclass(frozen=True)
class SpecMatching:
    """A specification matched to a garment.

    Attributes
    ----------
    spec : Specification
    scale : float
        Specification units times this gives the garment's computation units.
    panels : tuple of PanelMatch
        One per specification panel, in its order.
    stitches : tuple of StitchMatch
        One per stitch, in its order.
    """

    spec: Specification
    scale: float
    panels: tuple[PanelMatch, ...]
    stitches: tuple[StitchMatch, ...]


def spec_scale(spec: Specification, units: str) -> float:
    """Specification units to ``units``."""
    return spec.cm_per_unit / CM_PER[units]


def match_specification(
    garment: Garment,
    spec: Specification,
    panel_list: list[Panel],
    *,
    seams: list,
) -> SpecMatching:
    """Match a specification's panels to the garment's panels and its stitches to seams.

    Parameters
    ----------
    garment : Garment
        The garment the specification describes (pattern and drape in ``garment.units``;
        its frame places the specification's, y up and z front).
    spec : Specification
    panel_list : list of Panel
        The garment's panels.
    seams : list of Seam
        The garment's seams over ``panel_list`` (:attr:`GarmentStructure.seams`).

    Returns
    -------
    SpecMatching

    Raises
    ------
    PtailorError
        Naming the specification file and the panel or stitch that matches nothing.
    """
    k = spec_scale(spec, garment.units)
    V2, F2 = garment.V2, garment.F2
    if len(spec.panels) != len(panel_list):
        raise PtailorError(
            f"the specification has {len(spec.panels)} panels, the garment "
            f"{len(panel_list)}: they do not describe the same pattern",
            path=spec.path,
        )
    mesh = []
    for p in panel_list:  # a loop over panels
        B = V2[outer_loop(F2, p.faces, V2)]
        mesh.append((B, ClosedCurve(B), resample_closed(B, 256), abs(signed_area(B))))
    outlines = [sp.outline(tol.SPEC_PER_EDGE)[0] * k for sp in spec.panels]
    # the specification's 3D places of the same samples (its frame: y up, z front)
    placed = [sp.placement(X / k) * k for sp, X in zip(spec.panels, outlines, strict=True)]
    cands = _candidates(garment, panel_list, mesh, outlines)
    for i, sp in enumerate(spec.panels):  # a loop over spec panels
        if not any((i, j) in cands for j in range(len(panel_list))):
            raise PtailorError(
                f"panel {sp.name!r}: no panel of the garment has its shape and size "
                f"(outline fit within {tol.SPEC_MATCH_REL:g} of its size, area within "
                f"{tol.SPEC_AREA_REL:.0%})",
                path=spec.path,
            )
    first_error = None
    for rows, cols, fits, alts in _placements(
        cands, placed, garment, panel_list, garment.frame.matrix().T
    ):
        while True:  # this placement, then its panels' other fits where a stitch misses
            try:
                matches = _panel_matches(spec, panel_list, mesh, outlines, rows, cols, fits)
                stitches = _stitch_matches(garment, spec, matches, panel_list, seams, k)
            except _StitchMissError as exc:
                first_error = first_error or exc
                pair = next(((i, j) for (i, j) in alts if i in exc.spec_panels and alts[i, j]),
                            None)  # fmt: skip
                if pair is None:  # no other fit of its panels: the next placement
                    break
                fits[pair] = alts[pair].pop(0)
                continue
            except PtailorError as exc:  # this placement's panels do not all match
                first_error = first_error or exc
                break
            return SpecMatching(spec=spec, scale=k, panels=matches, stitches=stitches)
    assert first_error is not None  # there is always a first hypothesis
    raise first_error


class _StitchMissError(PtailorError):
    """A stitch that lands on no seam; ``spec_panels``: its two panels' indices."""

    def __init__(self, message: str, *, path: str, spec_panels: set[int]) -> None:
        super().__init__(message, path=path)
        self.spec_panels = spec_panels


def _panel_matches(spec, panel_list, mesh, outlines, rows, cols, fits) -> tuple[PanelMatch, ...]:
    """The assignment's matches, in the specification's panel order."""
    matches = []
    for i, j in zip(rows, cols, strict=True):  # a loop over spec panels
        if (i, j) not in fits:
            raise PtailorError(
                f"panel {spec.panels[i].name!r}: its shape matches only panels that other "
                f"specification panels match better (garment panel {panel_list[j].name!r} "
                "is left)",
                path=spec.path,
            )
        R, t, res, _ = fits[i, j]
        X = outlines[i] @ R.T + t
        dist = float(mesh[j][1].nearest(X)[0].max())
        matches.append(PanelMatch(int(i), int(j), R, t, float(res), dist))
    matches.sort(key=lambda m: m.spec)
    return tuple(matches)


def _candidates(
    garment: Garment, panel_list: list[Panel], mesh: list[tuple], outlines: list[np.ndarray]
) -> dict[tuple[int, int], list[tuple]]:
    """Per (specification panel, mesh panel) pair whose areas and shapes match, the rigid
    fits that match the shape (a symmetric outline fits more than one way):
    ``(R, t, residual, Y3)`` with ``Y3`` the drape points under the fitted outline."""
    V2, F2, V3, F3 = garment.V2, garment.F2, garment.V3, garment.F3
    out: dict[tuple[int, int], list[tuple]] = {}
    for i, X in enumerate(outlines):  # spec panels
        A = resample_closed(X, 256)
        area = abs(signed_area(X))
        diag = float(np.linalg.norm(np.ptp(A, axis=0)))
        for j, (_, cb, Bs, barea) in enumerate(mesh):  # mesh panels
            if abs(area - barea) > tol.SPEC_AREA_REL * max(area, barea):
                continue
            # coarse first (64 samples), then the fits worth it refined at full resolution
            step = tol.SPEC_COARSE_STRIDE
            coarse = shape_fits(
                A[::step], cb, Bs[::step], diag, iterations=tol.SPEC_COARSE_ICP_ITER
            )
            best = min(f[2] for f in coarse)
            if best > tol.SPEC_COARSE_FACTOR * tol.SPEC_MATCH_REL:
                continue
            fits = []
            for R, t, res in coarse:  # the starts that may fit the shape
                if res <= tol.SPEC_START_FACTOR * best + tol.SPEC_START_SLACK:
                    R, t = icp_fit(A, cb, R, t, diag)
                    fits.append((R, t, fit_residual(A, R, t, cb, Bs, diag)))
            fits.sort(key=lambda f: f[2])
            if fits[0][2] > tol.SPEC_MATCH_REL:
                continue
            keep = []
            for R, t, res in fits:  # the fits that match the shape
                if res <= tol.SPEC_KEEP_FACTOR * fits[0][2] + tol.SPEC_KEEP_SLACK:
                    loc = locate_points(V2, F2, X @ R.T + t, faces=panel_list[j].faces)
                    keep.append((R, t, res, np.einsum("ki,kij->kj", loc.bary, V3[F3[loc.face]])))
            out[i, j] = keep
    return out


def _cube_rotations() -> list[np.ndarray]:
    from itertools import permutations, product

    out = []
    for perm in permutations(range(3)):  # a loop over the 48 signed permutations
        for signs in product((1.0, -1.0), repeat=3):
            M = np.zeros((3, 3))
            M[np.arange(3), perm] = signs
            if np.linalg.det(M) > 0:
                out.append(M)
    return out


def _unit_cloud(C: np.ndarray) -> np.ndarray:
    """Points ``(n, 3)`` centred on their mean and scaled to unit RMS radius."""
    D = C - C.mean(axis=0)
    return D / max(float(np.sqrt((D * D).sum(1).mean())), tol.TINY)


def _assignment(cost: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    from scipy.optimize import linear_sum_assignment

    big = np.where(np.isfinite(cost), cost, tol.COST_NONE)
    rows, cols = linear_sum_assignment(big)
    return rows, cols, float(big[rows, cols].sum())


def _placements(cands, placed, garment: Garment, panel_list: list[Panel], Q0: np.ndarray):
    """Hypotheses of which mesh panel each specification panel is, and by which fit, most
    likely first: ``(rows, cols, fits, alts)`` (``alts``: per pair its other fits, next
    most likely first, for the caller to try where a stitch misses its seam).

    Panels are assigned by their places: the specification's panel centroids and the
    drape's, each cloud centred and scaled to unit size, the specification's turned by the
    run's axes ``Q0`` first, then by each of the 24 axis turns refined by a rigid fit of the
    assigned centroids (a drape turned any way from the specification's frame); each
    assignment once. Of a pair's fits, the one whose outline, centred, lies closest to the
    specification's placed outline, centred and turned, wins (it tells the two sides of a
    symmetric panel apart; a thin strip's flip, a few cm in 3D, is left to the stitches).
    The caller keeps the first hypothesis its stitches confirm.
    """
    from ptailor.geometry.triangles import triangle_areas

    V3, F3 = garment.V3, garment.F3
    a3 = triangle_areas(V3, F3) + tol.TINY
    c_mesh = np.array([np.average(V3[F3[p.faces]].mean(axis=1), axis=0, weights=a3[p.faces])
                       for p in panel_list])  # fmt: skip
    Cm = _unit_cloud(c_mesh)
    Cs = _unit_cloud(np.array([X.mean(axis=0) for X in placed]))
    n = len(placed)
    ok = np.zeros((n, n), dtype=bool)
    for i, j in cands:  # candidate pairs
        ok[i, j] = True

    def solve(Q):
        d = np.linalg.norm(Cm[None, :, :] - (Cs @ Q.T)[:, None, :], axis=2)
        return _assignment(np.where(ok, d, np.inf))

    def fitted(Q, rows, cols):
        fits, alts = {}, {}
        for i, j in zip(rows, cols, strict=True):  # the assigned pairs: which fit is in place
            if (i, j) not in cands:
                continue
            P = (placed[i] - placed[i].mean(axis=0)) @ Q.T
            ranked = sorted(
                cands[i, j],
                key=lambda f: (
                    float(np.linalg.norm(f[3] - f[3].mean(axis=0) - P, axis=1).mean()) + f[2]
                ),
            )
            fits[i, j], alts[i, j] = ranked[0], ranked[1:]
        return fits, alts

    seen = set()
    for G in [np.eye(3), *_cube_rotations()]:  # the run's axes, then the 24 turns
        Q = G @ Q0
        if seen:  # a turn: refined
            for _ in range(3):  # refine the turn: a rigid fit of the assigned centroids
                r, c, _ = solve(Q)
                keep = ok[r, c]
                if keep.sum() < 2:
                    break
                Q, _ = rigid_fit(Cs[r[keep]], Cm[c[keep]])
        rows, cols, _ = solve(Q)
        fits, alts = fitted(Q, rows, cols)
        key = tuple((i, j, *np.round(f[0], 6).ravel()) for (i, j), f in sorted(fits.items()))
        if key in seen:
            continue
        seen.add(key)
        yield rows, cols, fits, alts


def _boundary_near(
    garment: Garment, panel: Panel, Y: np.ndarray, reach: float
) -> tuple[np.ndarray, float]:
    """The panel's boundary edges (pattern vertex pairs) whose middles lie within ``reach``
    of the polyline ``Y``, and their total length."""
    from ptailor.geometry.segments import segment_feet
    from ptailor.model.boundary import boundary_loops

    E = []
    for lp in boundary_loops(garment.F2[panel.faces]):  # a panel's boundary loops
        E.append(np.column_stack([lp, np.roll(lp, -1)]))
    E = np.vstack(E)
    mid = garment.V2[E].mean(axis=1)
    d, _ = segment_feet(mid[:, None, :], Y[None, :-1], Y[None, 1:])
    near = d.min(axis=1) <= reach
    sel = E[near]
    length = float(np.linalg.norm(garment.V2[sel[:, 1]] - garment.V2[sel[:, 0]], axis=1).sum())
    return sel, length


def _stitch_matches(
    garment: Garment,
    spec: Specification,
    matches: tuple[PanelMatch, ...],
    panel_list: list[Panel],
    seams: list,
    k: float,
) -> tuple[StitchMatch, ...]:
    """Every stitch's seam: the seam between the two matched panels whose pattern edges lie
    along both stitched edges."""
    index = {p.name: i for i, p in enumerate(spec.panels)}
    lengths = [p.edge_lengths() * k for p in spec.panels]
    t = np.linspace(0.0, 1.0, tol.SPEC_PER_EDGE + 1)
    out = []
    for si, st in enumerate(spec.stitches):  # a loop over stitches
        sides = []
        for name, e in st.sides:  # the two sides
            m = matches[index[name]]
            sp = spec.panels[m.spec]
            Y = m.to_pattern(sp.edge_points(e, t), k)
            reach = max(3.0 * m.distance, tol.SPEC_FIT_WARN_CM / CM_PER[garment.units])
            E, length = _boundary_near(garment, panel_list[m.panel], Y, reach)
            sides.append((m.panel, E, length, float(lengths[m.spec][e])))
        (pa, Ea, la, sa), (pb, Eb, lb, sb) = sides
        best, best_n = -1, 0
        for s_i, s in enumerate(seams):  # a loop over seams
            if set(s.panels) != {pa, pb}:
                continue
            ea = s.edges_a if s.panels[0] == pa else s.edges_b
            eb = s.edges_b if s.panels[0] == pa else s.edges_a
            got = min(_shared_edges(ea, Ea), _shared_edges(eb, Eb))
            if pa == pb:  # a seam of a panel with itself (a dart, a one-piece sleeve): either way
                got = max(got, min(_shared_edges(eb, Ea), _shared_edges(ea, Eb)))
            if got > best_n:
                best, best_n = s_i, got
        a_name, b_name = (f"{n}.{e}" for n, e in st.sides)
        if best < 0 or best_n < 0.5 * min(len(Ea), len(Eb)):
            raise _StitchMissError(
                f"stitch {si} ({a_name} to {b_name}): no seam of the garment joins panels "
                f"{panel_list[pa].name!r} and {panel_list[pb].name!r} along these edges",
                path=spec.path,
                spec_panels={index[n] for n, _ in st.sides},
            )
        out.append(StitchMatch(si, best, (sa, sb), (la, lb)))
    return tuple(out)


def _shared_edges(A: np.ndarray, B: np.ndarray) -> int:
    """How many undirected edges ``A`` ``(p, 2)`` and ``B`` ``(q, 2)`` share."""
    if len(A) == 0 or len(B) == 0:
        return 0
    n = int(max(A.max(), B.max())) + 1
    ka = np.sort(A, axis=1) @ np.array([n, 1])
    kb = np.sort(B, axis=1) @ np.array([n, 1])
    return int(np.isin(kb, ka).sum())
