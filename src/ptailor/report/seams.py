"""The report's ``seams``: each seam's sides before and after, measured against the input.

A step that cuts or grows a seam (``shorten``, ``extend``, ``cut``) changes the garment's
triangles; the seam's ratio asked is still the one it has in the input (times a gather a
step set), never the ratio the cut left: a seam a step could not true shows as a mismatch,
in the record, in the batch's ``max_seam_mismatch`` and as a warning.
"""

from __future__ import annotations

import numpy as np

from ptailor import tolerances as tol
from ptailor.method import tolerances as method_tol
from ptailor.model.names import seam_names
from ptailor.model.structure import structure
from ptailor.model.units import CM_PER
from ptailor.pipeline import Adjustment, seam_factors
from ptailor.report.records import SeamRecord


def _r(x: float, nd: int = 6) -> float:
    return round(float(x), nd)


def input_seams(adj: Adjustment, seam_list: list) -> list[int]:
    """The input seam each seam of the adjusted garment lies on (index into
    ``structure(adj.original).seams``; -1 for none): the one most of its drape vertices
    lie on; after no surgery (the same triangles), the seam itself."""
    g0, g = adj.original, adj.state.base
    if g0 is None or g0 is g or (g0.F3.shape == g.F3.shape and np.array_equal(g0.F3, g.F3)):
        return list(range(len(seam_list)))
    from scipy.spatial import cKDTree  # (0.1 s: only after surgery)

    s0 = structure(g0)
    owner = np.full(len(g0.V3), -1, dtype=np.int64)  # an input vertex's seam (one of them)
    for k, sm in enumerate(s0.seams):  # a loop over seams
        owner[np.asarray(sm.edges3).ravel()] = k
    size = float(np.linalg.norm(np.ptp(g0.V3, axis=0))) or 1.0
    tree = cKDTree(g0.V3)
    out = []
    for sm in seam_list:  # a loop over seams
        v = np.unique(np.asarray(sm.edges3).ravel())
        d, j = tree.query(g.V3[v])
        hit = owner[j[d <= tol.ROUNDING_REL * size]]
        hit = hit[hit >= 0]
        out.append(int(np.bincount(hit).argmax()) if len(hit) else -1)
    return out


def input_seam_edges(adj: Adjustment, seam_list: list) -> list[int]:
    """The input seam whose edges each seam of the adjusted garment continues (index into
    ``structure(adj.original).seams``; -1 for none): the one most of its drape edges that
    are input edges belong to. A seam a step made (new rows of ``extend`` sewn where three
    panels met) touches input seams only at a vertex and has none: its own ratio is its
    target."""
    g0, g = adj.original, adj.state.base
    if g0 is None or g0 is g or (g0.F3.shape == g.F3.shape and np.array_equal(g0.F3, g.F3)):
        return list(range(len(seam_list)))
    from scipy.spatial import cKDTree

    from ptailor.geometry.topology import edge_keys

    s0 = structure(g0)
    n0 = len(g0.V3)
    E0 = np.concatenate([sm.edges3 for sm in s0.seams]) if s0.seams else np.zeros((0, 2), int)
    own0 = np.repeat(np.arange(len(s0.seams)), [len(sm.edges3) for sm in s0.seams])
    k0 = edge_keys(E0, n=n0)
    order = np.argsort(k0)
    size = float(np.linalg.norm(np.ptp(g0.V3, axis=0))) or 1.0
    tree = cKDTree(g0.V3)
    out = []
    for sm in seam_list:  # a loop over seams
        d, j = tree.query(g.V3[np.asarray(sm.edges3)])
        on = (d <= tol.ROUNDING_REL * size).all(axis=1) & (j[:, 0] != j[:, 1])
        q = edge_keys(j[on], n=n0)
        pos = np.minimum(np.searchsorted(k0[order], q), max(len(k0) - 1, 0))
        hit = own0[order[pos]][k0[order[pos]] == q] if len(k0) else np.zeros(0, int)
        out.append(int(np.bincount(hit).argmax()) if len(hit) else -1)
    return out


def stable_seam_names(adj: Adjustment, seam_list: list, now: list[str], match: list[int]):
    """Seam names kept across surgery: a seam of the edited garment that lies on a seam of
    the input (``match``: :func:`input_seams`) takes that seam's name (the second piece of
    one seam ``NAME_2``, ...), so a cut does not rename the seams it did not create (a
    V-neck once turned ``shoulder_right`` into ``shoulder_right_right``). Seams with no such
    seam keep ``now``."""
    g0, g = adj.original, adj.state.base
    if g0 is None or g0 is g or (g0.F3.shape == g.F3.shape and np.array_equal(g0.F3, g.F3)):
        return now
    s0 = structure(g0)
    names0 = seam_names(g0.V3, s0.seams, s0.layout, [p.name for p in s0.panels])
    out = list(now)
    taken: dict[int, int] = {}
    for i, k in enumerate(match):  # a loop over seams
        if k < 0:
            continue
        taken[k] = taken.get(k, 0) + 1
        out[i] = names0[k] if taken[k] == 1 else f"{names0[k]}_{taken[k]}"
    if len(set(out)) < len(out):  # a clash with a new seam's name: the names as computed
        return now
    return out


def _source(name: str, old: set[str]) -> str:
    """The input panel a panel came from (a panel cut in two gets a ``_k`` suffix)."""
    return name if name in old else name.rsplit("_", 1)[0]


def _input_lengths(adj: Adjustment, seam_list: list, match: list[int]) -> list:
    """Each seam's two side lengths in the input pattern, its sides in the order of the
    seam's (``None`` for a seam on no input seam): by the panels' names, else (a seam
    sewn to its own panel) the order nearer the ratio the steps left before the solve."""
    g0, g = adj.original, adj.state.base
    if g0 is None:
        g0 = g
    s0 = structure(g0)
    names0 = [p.name for p in s0.panels]
    names = [p.name for p in adj.state.panels]
    old = set(names0)
    out: list = []
    for sm, k in zip(seam_list, match, strict=True):  # a loop over seams
        if k < 0:
            out.append(None)
            continue
        la0, lb0 = s0.seams[k].lengths(g0.V2)
        now = tuple(_source(names[p], old) for p in sm.panels)
        was = tuple(names0[p] for p in s0.seams[k].panels)
        if was[0] == was[1] or set(now) != set(was):
            la, lb = sm.lengths(g.V2)
            r = la / max(lb, tol.TINY)
            swap = abs(r - lb0 / max(la0, tol.TINY)) < abs(r - la0 / max(lb0, tol.TINY))
        else:
            swap = now != was
        out.append((lb0, la0) if swap else (la0, lb0))
    return out


def seam_records(adj: Adjustment, gs) -> list[SeamRecord]:
    """The report's ``seams``: per seam its sides' lengths in the input and after, the
    ratio of the two and its target: the input's ratio times the gathers the recipe set
    (never the ratio a cut left). A seam a step cut or grew also gives ``length_cut``: its
    sides as the step left them, before the flattening."""
    st = adj.state
    g = st.base
    V2a = adj.result.V2
    names = [p.name for p in st.panels]
    gathers = seam_factors(st)
    seam_list = gs.seams
    now = seam_names(g.V3, seam_list, gs.layout, names)
    seam_name = stable_seam_names(adj, seam_list, now, input_seams(adj, seam_list))
    before = _input_lengths(adj, seam_list, input_seam_edges(adj, seam_list))
    out: list[SeamRecord] = []
    for si, s in enumerate(seam_list):  # one record per seam
        lac, lbc = s.lengths(g.V2)
        la0, lb0 = before[si] if before[si] is not None else (lac, lbc)
        la1, lb1 = s.lengths(V2a)
        pa, pb = s.panels
        f = gathers.get((pa, pb), 1.0) / gathers.get((pb, pa), 1.0) if pa != pb else 1.0
        r0 = la0 / max(lb0, tol.TINY)
        target = r0 * f
        rec: SeamRecord = {
            "name": seam_name[si],
            "panels": [names[pa], names[pb]],
            "edges": len(s.edges3),
            "length_before": [_r(la0), _r(lb0)],
            "length_after": [_r(la1), _r(lb1)],
            "ratio_before": _r(r0, 6),
            "ratio_after": _r(la1 / max(lb1, tol.TINY), 6),
            "ratio_target": _r(target, 6),
            "mismatch": _r(la1 - target * lb1, 6),
        }
        if max(abs(lac - la0), abs(lbc - lb0)) > tol.ROUNDING_REL * max(la0, lb0, tol.TINY):
            rec["length_cut"] = [_r(lac), _r(lbc)]
        out.append(rec)
    return out


def seam_warnings(adj: Adjustment, seams: list[SeamRecord]) -> list[str]:
    """One line per seam whose sides miss their target ratio by more than
    ``method_tol.SEAM_MISMATCH_WARN_CM`` (none with ``flatten.seams: free``, which keeps no
    ratio)."""
    if adj.settings.get("seams") == "free":
        return []
    u = adj.state.base.units
    limit = method_tol.SEAM_MISMATCH_WARN_CM / CM_PER[u]
    out = []
    for s in seams:  # a loop over seams
        if abs(s["mismatch"]) > limit:
            out.append(
                f"seam {s['name']} ({' / '.join(s['panels'])}) misses its sides' ratio by"
                f" {abs(s['mismatch']):.3g} {u} (ratio {s['ratio_after']:.4f}, target"
                f" {s['ratio_target']:.4f}): its sides no longer sew together"
            )
    return out
