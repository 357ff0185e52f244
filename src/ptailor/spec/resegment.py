"""Reading a changed panel's outline into segments (shorten, extend, cut).

A panel whose triangles changed is read off the adjusted mesh: each vertex of its outline is
labelled with the input edge it lies on (or as new), runs of one label become segments, and a
run of new outline is split at its corners; its pieces extend the edge they go on straight
from, or replace the input edges that left the outline (the hem a shorten moved keeps its id).
"""

from __future__ import annotations

import numpy as np

from ptailor import tolerances as tol
from ptailor.model.specification import SpecPanel

__all__ = ["cleaned_labels", "edge_labels", "outline_segments"]


def edge_labels(sp: SpecPanel, X: np.ndarray, reach: float) -> tuple[np.ndarray, np.ndarray]:
    """Per point ``X`` (panel frame) the edge it lies on within ``reach`` (-1: none) and
    its parameter there."""
    from scipy.spatial import cKDTree

    n = 512
    P, edge, t = sp.outline(n)
    d, idx = cKDTree(P).query(X)
    lab = np.where(d <= reach, edge[idx], -1)
    tt = t[idx]
    # the sample at t = 0 of the next edge is t = 1 of this one: nearest ends stay on
    return lab, tt


def _runs(lab: np.ndarray) -> list[tuple[int, np.ndarray]]:
    """Cyclic runs of equal labels ``(label, positions)``, starting at a label change."""
    n = len(lab)
    change = np.flatnonzero(lab != np.roll(lab, 1))
    if len(change) == 0:
        return [(int(lab[0]), np.arange(n))]
    start = change[0]
    order = (np.arange(n) + start) % n
    lab_r = lab[order]
    cuts = np.flatnonzero(np.diff(lab_r)) + 1
    return [(int(g[0]), order[s]) for g, s in
            zip(np.split(lab_r, cuts), np.split(np.arange(n), cuts), strict=True)]  # fmt: skip


def _corners(Z: np.ndarray, window: float) -> np.ndarray:
    """Interior positions of an open polyline ``Z`` that are corners: where the chords
    ``window`` long before and after a vertex turn by more than
    :data:`ptailor.tolerances.SPEC_CORNER_DEG`, the sharpest vertex of each such stretch (a
    cut line's zigzag through the triangles is no corner; pieces shorter than ``window`` are
    not split off)."""
    if len(Z) < 3:
        return np.zeros(0, dtype=np.int64)
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(Z, axis=0), axis=1))])
    inner = np.arange(1, len(Z) - 1)
    ok = (s[inner] >= window) & (s[inner] <= s[-1] - window)
    if not ok.any():
        return np.zeros(0, dtype=np.int64)
    inner = inner[ok]

    def at(x):
        return np.stack([np.interp(x, s, Z[:, 0]), np.interp(x, s, Z[:, 1])], axis=1)

    a = Z[inner] - at(s[inner] - window)
    b = at(s[inner] + window) - Z[inner]
    turn = np.degrees(np.abs(np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], (a * b).sum(1))))
    sharp = turn > tol.SPEC_CORNER_DEG
    out = []
    for grp in np.split(np.arange(len(inner)), np.flatnonzero(np.diff(sharp.astype(int))) + 1):
        if len(grp) and sharp[grp[0]]:  # one corner per stretch: its sharpest vertex
            out.append(int(inner[grp[np.argmax(turn[grp])]]))
    return np.array(out, dtype=np.int64)


def _turns(Zl: np.ndarray, a: np.ndarray, b: np.ndarray, window: float) -> bool:
    """Whether the outline turns a corner where run ``a`` (loop positions) meets the run
    ``b`` after it: a corner within half a window of the junction's ends."""
    P = np.vstack([Zl[a], Zl[b]])
    c = _corners(P, window)
    if not len(c):
        return False
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(P, axis=0), axis=1))])
    j = len(a)  # the junction: the outline's edge from a's last vertex to b's first
    near = np.minimum(np.abs(s[c] - s[j - 1]), np.abs(s[c] - s[j]))
    return bool(np.any(near <= 0.5 * window))


def _run_of(runs, r, pos):
    """The loop positions of the run after the run ``(r, pos)``."""
    i = next(k for k, (rr, pp) in enumerate(runs) if rr == r and pp is pos)
    return runs[(i + 1) % len(runs)][1]


def cleaned_labels(lab: np.ndarray, Zl: np.ndarray, window: float) -> np.ndarray:
    """Labels with runs of an input edge shorter than ``window`` next to new outline made
    new (a corner of the new outline that touches an old edge is no part of that edge)."""
    lab = lab.copy()
    runs = _runs(lab)
    for i, (r, pos) in enumerate(runs):  # a loop over the outline's runs
        nb = (runs[i - 1][0], runs[(i + 1) % len(runs)][0])
        short = len(pos) <= 2 or np.linalg.norm(np.diff(Zl[pos], axis=0), axis=1).sum() < window
        if r >= 0 and short and -1 in nb and len(runs) > 2:
            lab[pos] = -1
    return lab


def outline_segments(lab: np.ndarray, Zl: np.ndarray, n_e: int, window: float) -> list[list]:
    """The outline's segments ``[source edge or -1, loop positions, how]`` in loop order,
    from the first run of the lowest surviving edge; ``how`` is ``kept`` (part of an input
    edge), ``extended`` (an input edge the new outline goes on from) or ``new``. A run of
    new outline is split at its corners; pieces that go on straight from the edge before
    or after extend it; the rest replace, in order, the input edges between its two
    neighbours that left the outline (the hem a shorten moved keeps its id), or are new."""
    runs = _runs(lab)
    present = {r for r, _ in runs if r >= 0}
    if present:
        i0 = next(i for i, (r, _) in enumerate(runs) if r == min(present))
        runs = runs[i0:] + runs[:i0]
    segs: list[list] = []
    for r, pos in runs:  # a loop over the outline's runs
        if r >= 0:
            segs.append([r, pos, "kept"])
            continue
        prev_r = segs[-1][0] if segs else runs[-1][0]
        after = _run_of(runs, r, pos) if len(runs) > 1 else None
        nxt = int(lab[after[0]]) if after is not None else -1
        gone = _between(prev_r, nxt, n_e, present)
        ext = np.concatenate([pos[:1] - 1, pos, pos[-1:] + 1]) % len(lab)
        cut = _corners(Zl[ext], window) - 1
        cut = cut[(cut > 0) & (cut < len(pos))]
        mids, tail = (np.split(pos, cut) if len(cut) else [pos]), None
        if prev_r >= 0 and segs and not _turns(Zl, segs[-1][1], mids[0], window):
            segs[-1][1] = np.concatenate([segs[-1][1], mids.pop(0)])  # it goes on: extended
            segs[-1][2] = "extended"
        if mids and nxt >= 0 and after is not None and not _turns(Zl, mids[-1], after, window):
            tail = mids.pop()
        for j, pc in enumerate(mids):  # the pieces of a new outline run
            segs.append([gone[j] if j < len(gone) else -1, pc, "new"])
        if tail is not None:
            segs.append([nxt, tail, "lead"])
    return _merged_leads(segs)


def _merged_leads(segs: list[list]) -> list[list]:
    """A piece leading straight into the run of its edge joins that run (``extended``)."""
    merged: list[list] = []
    for s in segs:  # a loop over segments
        if merged and s[2] != "new" and merged[-1][2] == "lead" and merged[-1][0] == s[0]:
            merged[-1] = [s[0], np.concatenate([merged[-1][1], s[1]]), "extended"]
        else:
            merged.append(s)
    if len(merged) > 1 and merged[-1][2] == "lead" and merged[0][0] == merged[-1][0]:
        last = merged.pop()  # the run it leads into is the first one
        merged[0] = [last[0], np.concatenate([last[1], merged[0][1]]), "extended"]
    return [[s[0], s[1], "extended" if s[2] == "lead" else s[2]] for s in merged]


def _between(a: int, b: int, n: int, present: set[int]) -> list[int]:
    """Input edges strictly between ``a`` and ``b`` in loop order that no run holds."""
    if a < 0 or b < 0:
        return []
    out, i = [], (a + 1) % n
    while i != b and len(out) < n:
        if i not in present:
            out.append(i)
        i = (i + 1) % n
    return out
