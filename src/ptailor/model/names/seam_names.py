"""Seams named from the panels they join and where they run."""

from __future__ import annotations

import numpy as np

from ptailor.model.names.layout import PanelLayout
from ptailor.model.names.roles import _suffix_duplicates, mirror_name

#: A seam is vertical when the up component of its principal direction is at least this
#: (37 degrees from up), level when at most ``_LEVEL`` (53 degrees); in between (a diagonal
#: seam, where a mirror pair could fall on both sides of one threshold) it is neither.
_VERTICAL = 0.8
_LEVEL = 0.6
#: A front/back seam in this top fraction of its tier, not vertical, is a shoulder seam.
_SHOULDER = 0.75
#: A seam between two fronts (backs) is a centre seam when its midpoint is this close to the
#: centre line (fraction of the tier's half-width).
_CENTRE_SEAM = 0.15


def seam_names(
    V3: np.ndarray, seam_list: list, layout: PanelLayout, panel_names: list[str] | None = None
) -> list[str]:
    """Name seams by the panels they join and where they run.

    Parameters
    ----------
    V3 : (n3, 3) float array
        Drape positions.
    seam_list : list of Seam
        :func:`ptailor.model.seams.seams` (``panels`` index the layout's panels).
    layout : PanelLayout
    panel_names : list of str, optional
        The panels' names (from the file or the layout, default the layout's), used for
        seams no rule names.

    Returns
    -------
    list of str
        Unique names, one per seam:

        - sleeve and body: ``armhole_<side>``; cuff and sleeve: ``cuff_<side>``; within one
          limb (a sleeve's own seam): ``sleeve_<side>``, the cuff's own
          ``cuff_<side>_end``; strap and body: ``strap_<side>``; collar and body:
          ``neckline``; within the collar: ``collar``; waistband and body: ``waist``, within
          it ``waistband``;
        - two body panels of different tiers: ``waist_<bodice panel's name without
          bodice_>``;
        - two body panels of one tier (prefixed ``bodice_``/``skirt_`` on a two-tier
          garment), front and back: ``shoulder_<side>`` when the seam is not vertical and in
          the top quarter of the tier, else ``side_<side>``; both front (back):
          ``yoke_front`` (``yoke_back``) when the seam is level, ``<panel a>_<panel b>``
          when it is diagonal, else ``center_front`` (``center_back``) when its midpoint is
          near the centre line, else ``princess_front_<side>`` (``princess_back_<side>``);
          (vertical: the up component of the seam's principal direction >= 0.8; level:
          <= 0.6);
        - a body panel around the body (a tube) and another: a vertical seam is
          ``side_<side>`` or ``center_front``/``center_back`` by where its midpoint sits,
          any other ``<panel a>_<panel b>``;
        - anything else: ``<panel a>_<panel b>``.

        Equal names get ``_front``/``_back``, ``_upper``/``_lower`` or ``_left``/``_right``
        along the axis that separates their midpoints most, then ``_2``, ``_3``, ...
    """
    X = np.asarray(V3, dtype=np.float64) @ layout.frame.T
    origin = np.array([layout.s0, layout.h0, layout.f0])
    pn = list(layout.names if panel_names is None else panel_names)
    base, mids = [], []
    for s in seam_list:  # a loop over seams
        e = np.asarray(s.edges3)
        P, Q = X[e[:, 0]] - origin, X[e[:, 1]] - origin
        seg = np.linalg.norm(Q - P, axis=1)
        tot = float(seg.sum())
        mid = ((P + Q) * 0.5 * seg[:, None]).sum(0) / tot if tot > 0 else P.mean(0)
        pts = np.concatenate([P, Q])
        if len(pts) > 1:
            _, _, vt = np.linalg.svd(pts - pts.mean(0), full_matrices=False)
            upc = abs(float(vt[0, 1]))
        else:
            upc = 0.5
        mids.append(mid)
        base.append(_seam_base(s.panels, mid, upc, layout, pn))
    M = np.array(mids).reshape(-1, 3)
    return _mirrored(_qualify(base, M), seam_list, M, layout.mirror)


def _mirrored(names: list[str], seam_list: list, mids: np.ndarray, mirror: np.ndarray) -> list[str]:
    """Mirror seams named alike: a seam on the wearer's right whose panels are the mirror
    images of a left seam's (a centred panel its own) takes the left one's name with
    ``left`` and ``right`` swapped, unless another seam has that name."""
    if len(mirror) == 0 or not len(names):
        return names
    out = list(names)
    pairs = [tuple(sorted(int(mirror[p]) for p in s.panels)) for s in seam_list]
    own = [tuple(sorted(int(p) for p in s.panels)) for s in seam_list]
    flip = mids * np.array([-1.0, 1.0, 1.0])
    for i in np.argsort(-mids[:, 0], kind="stable").tolist():  # left seams first
        if mids[i, 0] <= 0 or -1 in pairs[i]:
            continue
        cand = [j for j in range(len(out)) if own[j] == pairs[i] and j != i and mids[j, 0] < 0]
        if not cand:
            continue
        j = min(cand, key=lambda k: float(np.linalg.norm(mids[k] - flip[i])))
        want = mirror_name(out[i])
        if out[j] != want and want not in out:
            out[j] = want
    return out


def _sfx(side: str) -> str:
    """``_left``/``_right``; nothing for a centred (lone) limb."""
    return f"_{side}" if side in ("left", "right") else ""


def _side_of(x: float) -> str:
    return "left" if x > 0 else "right"


def _seam_base(
    pp: tuple[int, int], mid: np.ndarray, upc: float, lay: PanelLayout, pn: list[str]
) -> str:
    """The name of one seam before equal names are told apart (``upc``: the up component of
    its principal direction)."""
    a, b = int(pp[0]), int(pp[1])
    roles = {lay.role[a], lay.role[b]}
    name = _role_seam(a, b, lay)
    if name is not None:
        return name
    if roles == {"body"}:
        return _body_seam(a, b, mid, upc, lay, pn)
    return f"{pn[a]}_{pn[b]}" if a != b else pn[a]


def _role_seam(a: int, b: int, lay: PanelLayout) -> str | None:
    """The name of a seam at a sleeve, cuff, strap, collar or waistband; None otherwise."""
    ra, rb = lay.role[a], lay.role[b]
    roles = {ra, rb}
    if roles == {"sleeve", "body"}:
        return f"armhole{_sfx(lay.side[a] if ra == 'sleeve' else lay.side[b])}"
    if roles == {"cuff", "sleeve"}:
        return f"cuff{_sfx(lay.side[a])}"
    if roles <= {"sleeve", "cuff"} and lay.side[a] == lay.side[b]:
        return f"cuff{_sfx(lay.side[a])}_end" if roles == {"cuff"} else f"sleeve{_sfx(lay.side[a])}"
    if "strap" in roles and roles <= {"strap", "body", "collar"}:
        return f"strap_{lay.side[a] if ra == 'strap' else lay.side[b]}"
    fixed = {
        frozenset({"collar", "body"}): "neckline",
        frozenset({"collar"}): "collar",
        frozenset({"waistband", "body"}): "waist",
        frozenset({"waistband"}): "waistband",
    }
    return fixed.get(frozenset(roles))


def _body_seam(a: int, b: int, mid: np.ndarray, upc: float, lay: PanelLayout, pn: list[str]) -> str:
    """The name of a seam between two body panels."""
    ta, tb = lay.tier[a], lay.tier[b]
    if ta != tb:
        upper = a if ta == "bodice" else b
        if lay.tier[upper] != "bodice":
            return "waist"
        return f"waist_{lay.names[upper].removeprefix('bodice_')}"
    pre = f"{ta}_" if ta else ""
    fa, fb = lay.face[a], lay.face[b]
    vertical = upc >= _VERTICAL
    sd = _side_of(float(mid[0]))
    if not fa or not fb:  # a panel around the body
        if not vertical:
            return f"{pn[a]}_{pn[b]}" if a != b else pn[a]
        if abs(mid[0]) >= abs(mid[2]):
            return f"{pre}side_{sd}"
        return f"{pre}center_{'front' if mid[2] > 0 else 'back'}"
    members = [p for p in range(len(lay.tier)) if lay.role[p] == "body" and lay.tier[p] == ta]
    if fa != fb:
        t_lo = float(lay.lo[members, 1].min())
        t_hi = float(lay.hi[members, 1].max())
        top = (mid[1] - t_lo) >= _SHOULDER * max(t_hi - t_lo, 1e-12)
        return f"{pre}{'shoulder' if top and not vertical else 'side'}_{sd}"
    if upc <= _LEVEL:
        return f"{pre}yoke_{fa}"
    if not vertical:  # diagonal: named by its panels
        return f"{pn[a]}_{pn[b]}"
    half_w = max(float(np.abs(np.r_[lay.lo[members, 0], lay.hi[members, 0]]).max()), 1e-12)
    if abs(mid[0]) <= _CENTRE_SEAM * half_w:
        return f"{pre}center_{fa}"
    return f"{pre}princess_{fa}_{sd}"


def _qualify(base: list[str], mids: np.ndarray) -> list[str]:
    """Tell equal seam names apart along the axis that separates their midpoints most."""
    out = list(base)
    words = (("right", "left"), ("lower", "upper"), ("back", "front"))
    for name in sorted(set(base)):
        idx = [i for i, b in enumerate(base) if b == name]
        if len(idx) < 2:
            continue
        M = mids[idx]
        ax = int(np.argmax(np.ptp(M, axis=0)))
        cut = float(np.median(M[:, ax]))
        for j, i in enumerate(idx):
            hi = M[j, ax] > (M[1 - j, ax] if len(idx) == 2 else cut)
            out[i] = f"{name}_{words[ax][int(hi)]}"
    return _suffix_duplicates(out)
