"""Seam allowances by seam and opening: what each edge of a piece sews, and its allowance.

``--seam-allowance hem=3cm --seam-allowance 1cm`` names seams, seam lines and openings as
``ptailor inspect`` shows them. Each edge of a piece's outline is given the seam or opening
of the panel's boundary it lies on (the nearest boundary edge of its panel in the adjusted
pattern, through the piece's rigid map); its allowance is that name's value, a seam's line's
when the seam itself is not named, else the default.

Examples
--------
>>> from ptailor.samples import cone_skirt
>>> sorted(allowance_names(cone_skirt()).known())
['hem', 'skirt_side', 'skirt_side_left', 'skirt_side_right', 'waist']
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ptailor.errors import PtailorError
from ptailor.geometry.topology import edge_keys, half_edges
from ptailor.model.garment import Garment
from ptailor.model.seam_lines import seam_lines
from ptailor.model.structure import structure
from ptailor.pieces.carry import CarriedPiece
from ptailor.pieces.match import ClosedCurve
from ptailor.pieces.plan import PiecePlan
from ptailor.pipeline import Adjustment


@dataclass(frozen=True)
class AllowanceNames:
    """The names ``--seam-allowance`` takes on one garment.

    Attributes
    ----------
    seams : tuple of str
        Each seam's name (``structure(g).seam_names``).
    lines : dict of str to tuple of int
        Each seam line's name and its seams (indices into ``seams``), over every part.
    openings : tuple of str
        Each opening's name.
    """

    seams: tuple[str, ...]
    lines: dict[str, tuple[int, ...]]
    openings: tuple[str, ...]

    def known(self) -> list[str]:
        """Every name, seams first, then seam lines, then openings."""
        return [*self.seams, *(n for n in self.lines if n not in self.seams), *self.openings]

    def values(self, default: float, named: Mapping[str, float]) -> np.ndarray:
        """The allowance of each seam then each opening ``(s + o,)``: its own name's, its
        seam line's, else ``default``."""
        line_of: dict[int, float] = {}
        for name, seams in self.lines.items():  # a loop over seam lines
            if name in named:
                line_of.update(dict.fromkeys(seams, named[name]))
        seam = [named.get(n, line_of.get(k, default)) for k, n in enumerate(self.seams)]
        return np.array(seam + [named.get(n, default) for n in self.openings], dtype=np.float64)


def allowance_names(g: Garment) -> AllowanceNames:
    """The seams, seam lines and openings of ``g`` by name (as ``ptailor inspect`` shows)."""
    st = structure(g)
    names = list(st.seam_names)
    lines: dict[str, set[int]] = {}
    for ln in seam_lines(g.V3, st.seams, names):  # a loop over seam lines
        lines.setdefault(ln.name, set()).update(ln.seams)
    return AllowanceNames(
        seams=tuple(names),
        lines={n: tuple(sorted(s)) for n, s in lines.items()},
        openings=tuple(op.name for op in st.openings),
    )


def check_allowance_names(g: Garment, named: Mapping[str, float], *, path: str) -> None:
    """Refuse a ``--seam-allowance NAME=D`` whose name is no seam, seam line or opening of
    ``g`` (:class:`~ptailor.errors.PtailorError`, exit 2), listing the known names."""
    if not named:
        return
    known = allowance_names(g).known()
    unknown = [n for n in named if n not in known]
    if unknown:
        raise PtailorError(
            f"--seam-allowance: no seam or opening named {', '.join(unknown)} (known: "
            f"{', '.join(known)})",
            path=path,
        )


@dataclass(frozen=True)
class PieceAllowance:
    """One piece's allowances.

    Attributes
    ----------
    edges : (k,) float array
        The allowance of each outline edge (edge ``i``: ``outline[i] -> outline[i + 1]``).
    runs : list of dict
        The outline's runs of edges on one seam or opening, in outline order: ``name``
        (``""`` for an edge on neither), ``kind`` (``seam``, ``opening``, ``edge``),
        ``allowance`` and ``length`` (of the sew line), computation units.
    """

    edges: np.ndarray
    runs: list[dict]


def boundary_labels(g: Garment, loop: np.ndarray) -> np.ndarray:
    """The seam or opening of each edge of a panel's boundary loop.

    Parameters
    ----------
    g : Garment
    loop : (b,) int array
        Pattern vertices (into ``V2``) of a closed boundary loop of one panel.

    Returns
    -------
    (b,) int array
        Per edge ``loop[i] -> loop[i + 1]``: a seam's index, ``len(seams)`` plus an
        opening's index, or -1 (neither).
    """
    st = structure(g)
    n3 = len(g.V3)
    keys, labels = [], []
    for k, sm in enumerate(st.seams):  # a loop over seams
        keys.append(edge_keys(np.asarray(sm.edges3).reshape(-1, 2), n=n3))
        labels.append(np.full(len(keys[-1]), k))
    for j, op in enumerate(st.openings):  # a loop over openings
        L = np.asarray(op.loop, dtype=np.int64)
        E = np.stack([L, np.roll(L, -1)], axis=1)[: len(L) if op.closed else len(L) - 1]
        keys.append(edge_keys(E, n=n3))
        labels.append(np.full(len(E), len(st.seams) + j))
    if not keys:
        return np.full(len(loop), -1, dtype=np.int64)
    key, lab = np.concatenate(keys), np.concatenate(labels)
    order = np.argsort(key, kind="stable")
    key, lab = key[order], lab[order]
    # the loop's pattern edges -> their half-edges -> the drape edges they are
    h2, h3 = half_edges(g.F2), half_edges(g.F3)
    n2 = len(g.V2)
    directed = h2[:, 0].astype(np.int64) * n2 + h2[:, 1]
    o2 = np.argsort(directed)
    a, b = loop, np.roll(loop, -1)
    he = np.full(len(loop), -1, dtype=np.int64)
    for p, q in ((a, b), (b, a)):  # the loop in either direction
        want = p.astype(np.int64) * n2 + q
        pos = np.minimum(np.searchsorted(directed[o2], want), len(o2) - 1)
        he = np.where((he < 0) & (directed[o2[pos]] == want), o2[pos], he)
    k3 = edge_keys(h3[np.maximum(he, 0)], n=n3)
    pos = np.minimum(np.searchsorted(key, k3), len(key) - 1)
    return np.where((he >= 0) & (key[pos] == k3), lab[pos], -1)


def piece_allowances(
    adj: Adjustment,
    plan: PiecePlan,
    carried: list[CarriedPiece | None],
    *,
    default: float,
    named: Mapping[str, float],
) -> list[PieceAllowance | None]:
    """Each carried piece's allowance per outline edge, and its runs for the report.

    Parameters
    ----------
    adj : Adjustment
    plan : PiecePlan
        The carried plan (:func:`~ptailor.pieces.plan.carry_plan`'s, ``panel_names`` set).
    carried : list of CarriedPiece or None
        One per piece of ``plan``.
    default : float
        The allowance of an edge no name sets (0: none), computation units.
    named : mapping of str to float
        Allowances by seam, seam line or opening name.

    Returns
    -------
    list of PieceAllowance or None
        ``None`` where ``carried`` has none.
    """
    g = adj.state.base  # the adjusted garment's triangles and names; its pattern is adj's
    st = structure(g)
    names = allowance_names(g)
    value = names.values(default, named)
    label_name = [*names.seams, *names.openings]
    kind = ["seam"] * len(names.seams) + ["opening"] * len(names.openings)
    index = {p.name: i for i, p in enumerate(st.panels)}
    out: list[PieceAllowance | None] = []
    for cp, m, pn in zip(carried, plan.matches, plan.panel_names, strict=True):  # pieces
        if cp is None or pn not in index or not st.panel_loops(index[pn]):
            out.append(None if cp is None else _uniform(cp, default))
            continue
        loop = st.panel_loops(index[pn])[0]
        lab = boundary_labels(g, loop)
        P = np.asarray(cp.piece.outline, dtype=np.float64)
        mid = m.to_panel(0.5 * (P + np.roll(P, -1, axis=0)))
        edge_lab = lab[ClosedCurve(adj.result.V2[loop]).nearest_segment(mid)]
        d = np.where(edge_lab >= 0, value[np.maximum(edge_lab, 0)], default)
        out.append(PieceAllowance(edges=d, runs=_runs(P, edge_lab, d, label_name, kind)))
    return out


def _uniform(cp: CarriedPiece, default: float) -> PieceAllowance:
    P = np.asarray(cp.piece.outline, dtype=np.float64)
    lab = np.full(len(P), -1)
    d = np.full(len(P), default)
    return PieceAllowance(d, _runs(P, lab, d, [], []))


def _runs(P: np.ndarray, lab: np.ndarray, d: np.ndarray, names: list, kinds: list) -> list:
    """The runs of consecutive outline edges with one label (cyclic), in outline order."""
    k = len(lab)
    length = np.linalg.norm(np.roll(P, -1, axis=0) - P, axis=1)
    change = np.flatnonzero(lab != np.roll(lab, 1))
    if len(change) == 0:
        change = np.array([0])
    ends = np.r_[change[1:], change[0] + k]
    runs = []
    for s, e in zip(change, ends, strict=True):  # a loop over runs (seams and openings)
        idx = np.arange(s, e) % k
        j = int(lab[s])
        runs.append(
            {
                "name": names[j] if j >= 0 else "",
                "kind": kinds[j] if j >= 0 else "edge",
                "allowance": round(float(d[s]), 6),
                "length": round(float(length[idx].sum()), 6),
            }
        )
    return runs
