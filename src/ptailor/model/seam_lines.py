"""Seam lines: a panel's seams with other panels that continue each other.

The paper's seam line is "the line created by joining two or more pieces of fabric": the whole
armhole (a sleeve's seams with the front and with the back), the whole waist (a skirt panel's
seams with every bodice panel above it), not one seam curve between two panels. A line is seen
from one panel, its ``part``; its name is the stem its seams' names share (``armhole_left_front``
and ``armhole_left_back`` make ``armhole_left``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor import tolerances as tol
from ptailor.model import tolerances as model_tol
from ptailor.model.seams import Seam


@dataclass(frozen=True)
class SeamLine:
    """One named seam line.

    Attributes
    ----------
    name : str
        The stem its seams' names share.
    part : int
        The panel the line is seen from (on one side of every seam of the line).
    panels : tuple of int
        The panels across the line, in the order found.
    seams : tuple of int
        Its seams, indices into the seam list.
    """

    name: str
    part: int
    panels: tuple[int, ...]
    seams: tuple[int, ...]


def seam_line(
    V3: np.ndarray,
    seam_list: list[Seam],
    part: int,
    other: int,
    *,
    turn_deg: float = model_tol.SEAM_LINE_TURN_DEG,
) -> list[int]:
    """The panels ``part`` meets across the seam line through its seam with ``other``, in
    the order found (``other`` first).

    From the seam with ``other``, a seam of ``part`` with another panel joins the line where
    it continues it: it shares an end vertex with the line and leaves that vertex at more
    than ``turn_deg`` from the line's own way in (the back half of an armhole continues the
    front half at the underarm and the shoulder point; a two-piece sleeve's own seam,
    meeting the armhole square, does not). ``part``'s seams with itself (a tube's closing
    seam) never join.

    Parameters
    ----------
    V3 : (n, 3) float array
        The drape.
    seam_list : list of Seam
    part, other : int
        Panel indices; ``part`` and ``other`` share a seam.
    turn_deg : float, keyword-only

    Returns
    -------
    list of int
        Panel indices, ``other`` first.
    """
    curves: dict[int, list[np.ndarray]] = {}
    for sm in seam_list:  # a loop over seams (tens)
        if part in sm.panels and sm.panels[0] != sm.panels[1]:
            x = sm.panels[1] if sm.panels[0] == part else sm.panels[0]
            curves.setdefault(x, []).append(sm.edges3)
    edges = {x: np.concatenate(e) for x, e in curves.items()}
    line = [other]
    E = edges[other]
    cos_max = float(np.cos(np.radians(180.0 - turn_deg)))

    def ends(Ex: np.ndarray) -> dict[int, np.ndarray]:
        """End vertices of a chain of edges with the unit direction leaving each."""
        v, c = np.unique(Ex.ravel(), return_counts=True)
        out = {}
        for u in v[c == 1].tolist():  # a chain has two ends
            e = Ex[(Ex == u).any(axis=1)][0]
            w = e[1] if e[0] == u else e[0]
            d = V3[w] - V3[u]
            out[u] = d / max(float(np.linalg.norm(d)), tol.TINY)
        return out

    grown = True
    while grown:  # a loop over the line's panels (a few)
        grown = False
        mine = ends(E)
        for x, Ex in edges.items():
            if x in line:
                continue
            for u, d in ends(Ex).items():
                if u in mine and float(d @ mine[u]) < cos_max:  # leaves u the line's way on
                    line.append(x)
                    E = np.concatenate([E, Ex])
                    grown = True
                    break
    return line


def name_stem(names: list[str]) -> str:
    """The longest common prefix of ``names`` in whole ``_``-separated words ("" if none)."""
    words = [n.split("_") for n in names]
    stem: list[str] = []
    for group in zip(*words, strict=False):
        if len(set(group)) != 1:
            break
        stem.append(group[0])
    return "_".join(stem)


def seam_lines(V3: np.ndarray, seam_list: list[Seam], seam_name: list[str]) -> list[SeamLine]:
    """Every named seam line of a garment: for each panel, its seam lines of two or more
    seams whose names share a stem (the line's name).

    A line whose seams share no stem (a front's armhole half running on into its side seam)
    is not named: it is reached through any one of its seams' names.

    Parameters
    ----------
    V3 : (n, 3) float array
    seam_list : list of Seam
    seam_name : list of str
        Each seam's name (:func:`ptailor.model.names.seam_names`).

    Returns
    -------
    list of SeamLine
        By part, then by first seam; no two with one part and one name.
    """
    panels = sorted({p for s in seam_list for p in s.panels})
    out: list[SeamLine] = []
    for part in panels:  # a loop over panels
        done: set[frozenset] = set()
        others = [
            s.panels[1] if s.panels[0] == part else s.panels[0]
            for s in seam_list
            if part in s.panels and s.panels[0] != s.panels[1]
        ]
        for other in dict.fromkeys(others):
            line = seam_line(V3, seam_list, part, other)
            key = frozenset(line)
            if key in done:
                continue
            done.add(key)
            members = tuple(
                i
                for i, s in enumerate(seam_list)
                if part in s.panels
                and s.panels[0] != s.panels[1]
                and (set(s.panels) - {part}) <= key
            )
            if len(members) < 2:
                continue
            stem = name_stem([seam_name[i] for i in members])
            if stem and all(ln.name != stem or ln.part != part for ln in out):
                out.append(SeamLine(stem, part, tuple(line), members))
    return out
