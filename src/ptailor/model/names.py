"""Panels and seams named from the drape's geometry.

A recipe written for a catalogue says ``sleeve_left`` or ``side_right``, not ``panel_3``. When
the file's groups do not name the panels, :func:`panel_layout` names them from where they sit
on the garment, in the wearer's frame the openings use (:func:`ptailor.model.openings.
body_frame`: y up and z front by default; ``left = up x front`` is the wearer's left, +x),
and :func:`seam_names` names every seam from the panels it joins and where it runs.

Panel rules (see :func:`panel_layout` for the details):

- *limbs*: panels that touch no centred opening (neckline, hem, waist, armholes), joined by
  seams into a group that touches ``cuff_left`` (``cuff_right``), form the left (right)
  sleeve (a panel joins only from that side of the centre line, not straddling it, its
  centroid at least half as far out as those of the panels at the cuff). A limb panel
  seamed to the body is a sleeve, one touching the cuff opening that is not seamed to the
  body (while the limb has a panel that is) is a cuff: ``sleeve_left``, ``cuff_left``. A
  two-piece sleeve is split front/back (``sleeve_left_front``, ``sleeve_left_back``) or,
  when its halves sit above each other rather than before and behind, upper/lower
  (``sleeve_left_upper``, ``sleeve_left_lower``).
- *strips*: narrow panels (length / width >= 3.5 for the rectangle with the panel's 3D area
  and perimeter) whose long side runs along an opening: along the neckline ``collar``, along
  a ``waist`` opening ``waistband``; a strip on one side touching an armhole is a ``strap``.
- *body*: everything else. When the garment is a top (it has a neckline or armholes) whose
  hem panels all end below the lowest point of the neckline and armholes, it has two tiers:
  panels whose centroid is above the hem panels' top are ``bodice_*``, the others
  ``skirt_*``; a garment with a waist opening and no neckline is a skirt (``skirt_*``).
  A body panel is ``front`` or ``back`` by its centroid's front coordinate against its tier's
  area-weighted mean, and ``_left``/``_right`` unless it straddles the centre line (the
  smaller of its two reaches across it is at least a third of the larger). A panel that
  straddles both the centre line and, the same way, the tier's mean front coordinate goes
  around the body (a tube): it is named by its tier alone (``skirt``), else ``body``.
- Strips or cuffs sharing a name but not a face are ``_front``/``_back`` (``collar_front``,
  ``collar_back``). Other panels sharing a name: the largest keeps it, the others get
  ``_upper``/``_lower`` (stacked) or ``_side``/``_centre`` (outward/inward of it), whichever
  offset dominates (measured against the largest's extent); of two side by side, the inner
  keeps the name and the outer is ``_side`` (``bodice_back_left``,
  ``bodice_back_left_side``); names still equal get ``_2``, ``_3``, ...

Everything is vectorised over triangles; loops run over panels, openings and seams only.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor.geometry.triangles import triangle_areas
from ptailor.model.openings import Opening, body_frame, openings
from ptailor.model.seams import edge_keys, half_edges

#: A strip is at least this long for its width (rectangle with the panel's area and perimeter).
_STRIP_ASPECT = 3.5
#: A strip's long side lies along an opening when this fraction of its length touches it.
_STRIP_TOUCH = 0.4
#: A panel straddles the centre line when its shorter reach across it is this fraction of
#: its longer one.
_CENTRED = 1.0 / 3.0
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

_CENTRED_OPENINGS = ("neckline", "hem", "waist", "armhole_left", "armhole_right")


@dataclass(frozen=True)
class PanelLayout:
    """Where each panel sits on the garment, and the name that follows.

    Attributes
    ----------
    names : list of str
        Geometric name per panel, unique.
    role : list of str
        ``body``, ``sleeve``, ``cuff``, ``collar``, ``waistband`` or ``strap``.
    side : list of str
        ``left``, ``right`` or ``centre``.
    face : list of str
        ``front`` or ``back``; ``""`` for a body panel around the body (a tube).
    tier : list of str
        ``""`` (one-tier garment, limbs and strips), ``bodice`` or ``skirt``.
    centroid : (n_p, 3) float array
        Area-weighted 3D centroid per panel in the wearer's frame ``(left, up, front)``,
        relative to the garment's centre (area-weighted mean left and front coordinates, the
        lowest point's height).
    lo, hi : (n_p, 3) float arrays
        Per-panel extents in the same coordinates.
    height : float
        The garment's height along up.
    s0, f0 : float
        The centre line's left and front coordinates (absolute, in the frame).
    h0 : float
        The garment's lowest height (absolute).
    frame : (3, 3) float array
        Rows ``(left, up, front)``.
    openings : list of Opening
    """

    names: list[str]
    role: list[str]
    side: list[str]
    face: list[str]
    tier: list[str]
    centroid: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    height: float
    s0: float
    f0: float
    h0: float
    frame: np.ndarray
    openings: list[Opening]

    def position(self, p: int) -> str:
        """A short phrase for panel ``p``'s place: side, front/back and height band.

        Returns
        -------
        str
            For example ``"left, back, upper"``: ``left``/``right``/``centre``; ``front`` or
            ``back``, left out when the centroid is within 10 % of the garment's depth of
            the centre; height bands of the garment's height: ``top`` >= 80 %, ``upper`` >=
            55 %, ``middle`` >= 30 %, ``lower`` >= 10 %, else ``bottom``.
        """
        c = self.centroid[p]
        t = c[1] / self.height if self.height > 0 else 0.5
        band = (
            "top"
            if t >= 0.8
            else "upper"
            if t >= 0.55
            else "middle"
            if t >= 0.3
            else "lower"
            if t >= 0.1
            else "bottom"
        )
        depth = float(self.hi[:, 2].max() - self.lo[:, 2].min()) if len(self.hi) else 0.0
        if abs(c[2]) < 0.1 * depth or not self.face[p]:
            return f"{self.side[p]}, {band}"
        return f"{self.side[p]}, {self.face[p]}, {band}"


def _per_panel_extent(X: np.ndarray, lab: np.ndarray, n_p: int) -> tuple[np.ndarray, np.ndarray]:
    """Per-panel min and max of face-corner coordinates.

    Parameters
    ----------
    X : (m, 3, 3) float array
        Corner coordinates per face.
    lab : (m,) int array
    n_p : int

    Returns
    -------
    lo, hi : (n_p, 3) float arrays
    """
    lo = np.full((n_p, 3), np.inf)
    hi = np.full((n_p, 3), -np.inf)
    if len(lab) == 0:
        return lo, hi
    order = np.argsort(lab, kind="stable")
    sl = lab[order]
    starts = np.flatnonzero(np.r_[True, sl[1:] != sl[:-1]])
    present = sl[starts]
    lo[present] = np.minimum.reduceat(X.min(axis=1)[order], starts, axis=0)
    hi[present] = np.maximum.reduceat(X.max(axis=1)[order], starts, axis=0)
    return lo, hi


def _unique_names(
    base: list[str], area: np.ndarray, cen: np.ndarray, ext: np.ndarray, reach: np.ndarray
) -> list[str]:
    """Disambiguate equal names: the largest keeps it, others get a place qualifier.

    Parameters
    ----------
    base : list of str
        Proposed name per panel.
    area : (n_p,) float array
    cen : (n_p, 3) float array
        Centroids ``(left, up, front)`` relative to the centre line.
    ext : (n_p, 3) float array
        Extents per panel.
    reach : (n_p,) float array
        Distance of each centroid from the centre line.

    Returns
    -------
    list of str
    """
    out = list(base)
    for name in sorted(set(base)):
        idx = [p for p, b in enumerate(base) if b == name]
        if len(idx) < 2:
            continue
        idx.sort(key=lambda p: (-area[p], p))
        ref = idx[0]
        for p in idx[1:]:
            dh = (cen[p, 1] - cen[ref, 1]) / max(ext[ref, 1], 1e-12)
            ds = (reach[p] - reach[ref]) / max(ext[ref, 0], 1e-12)
            if abs(dh) >= abs(ds):
                out[p] = f"{name}_{'upper' if dh > 0 else 'lower'}"
            elif ds > 0:
                out[p] = f"{name}_side"
            elif len(idx) == 2:  # the inner of two side by side keeps the name
                out[ref] = f"{name}_side"
            else:
                out[p] = f"{name}_centre"
    return _suffix_duplicates(out)


def _suffix_duplicates(names: list[str]) -> list[str]:
    """Names still equal get ``_2``, ``_3``, ... in list order (the first keeps its name)."""
    seen: dict[str, int] = {}
    taken = set(names)
    out = []
    for n in names:
        if n not in seen:
            seen[n] = 1
            out.append(n)
            continue
        k = seen[n] + 1
        while f"{n}_{k}" in taken:
            k += 1
        seen[n] = k
        taken.add(f"{n}_{k}")
        out.append(f"{n}_{k}")
    return out


def panel_layout(
    V3: np.ndarray,
    F3: np.ndarray,
    F2: np.ndarray,
    face_panel: np.ndarray,
    n_panels: int,
    *,
    up=(0.0, 1.0, 0.0),
    front=(0.0, 0.0, 1.0),
) -> PanelLayout:
    """Name every panel from where it sits on the drape.

    Parameters
    ----------
    V3 : (n3, 3) float array
        Drape positions.
    F3, F2 : (m, 3) int arrays
        Drape and pattern triangles.
    face_panel : (m,) int array
        Panel index per triangle, ``0 .. n_panels - 1``.
    n_panels : int
    up, front : 3-vectors
        The wearer's up and front directions.

    Returns
    -------
    PanelLayout
        See the module docstring for the rules.
    """
    n_p = int(n_panels)
    frame = body_frame(up, front)
    V3 = np.asarray(V3, dtype=np.float64)
    F3 = np.asarray(F3, dtype=np.int64).reshape(-1, 3)
    lab = np.asarray(face_panel, dtype=np.int64)
    X = V3 @ frame.T  # (n3, 3): left, up, front
    Xc = X[F3]  # (m, 3, 3)
    area = triangle_areas(V3, F3)
    At = np.bincount(lab, area, minlength=n_p)
    Atot = max(float(At.sum()), 1e-300)
    fc = Xc.mean(axis=1)
    cen_abs = np.stack([np.bincount(lab, area * fc[:, k], minlength=n_p) for k in range(3)], 1)
    cen_abs = cen_abs / np.maximum(At, 1e-300)[:, None]
    lo_abs, hi_abs = _per_panel_extent(Xc, lab, n_p)
    s0 = float((area * fc[:, 0]).sum() / Atot)
    f0 = float((area * fc[:, 2]).sum() / Atot)
    used = np.flatnonzero(np.bincount(F3.ravel(), minlength=len(V3)) > 0)
    h0 = float(X[used, 1].min()) if used.size else 0.0
    H = float(X[used, 1].max()) - h0 if used.size else 0.0

    # boundary and seam half-edges, their 3D lengths and panels
    h3 = half_edges(F3)
    hlen = np.linalg.norm(V3[h3[:, 1]] - V3[h3[:, 0]], axis=1)
    hpan = np.repeat(lab, 3)
    # one sort of the drape's edges: runs of one are boundary, runs of two interior edges
    # (a seam when the two pattern edges differ); T-seams (3+ faces) are sewn, never
    # boundary (as openings() has them), and give no adjacency (enough to name panels)
    h2 = half_edges(np.asarray(F2, dtype=np.int64).reshape(-1, 3))
    key = edge_keys(h3)
    order = np.argsort(key, kind="stable")
    ks = key[order]
    start = np.r_[True, ks[1:] != ks[:-1]] if len(ks) else np.zeros(0, dtype=bool)
    run_id = np.cumsum(start) - 1
    run_len = np.bincount(run_id)[run_id] if len(ks) else np.zeros(0, dtype=np.int64)
    bnd = np.sort(order[run_len == 1])
    two = np.flatnonzero(start & (run_len == 2))
    first, second = order[two], order[two + 1]
    same_dir = h3[first, 0] == h3[second, 0]
    e2 = np.where(same_dir[:, None], h2[second], h2[second][:, ::-1])
    is_seam = np.any(h2[first] != e2, axis=1)
    pairs = np.stack([first[is_seam], second[is_seam]], axis=1)
    sh = pairs.ravel()
    perim = np.bincount(hpan[bnd], hlen[bnd], minlength=n_p) + np.bincount(
        hpan[sh], hlen[sh], minlength=n_p
    )
    # seam adjacency (3D length between panels)
    W = np.zeros((n_p, n_p))
    if len(pairs):
        np.add.at(W, (hpan[pairs[:, 0]], hpan[pairs[:, 1]]), hlen[pairs[:, 0]])
    W = W + W.T

    # touch[k, p]: length of opening k's loop on panel p
    ops = openings(V3, F3, up=up, front=front, F2=F2)
    n_o = len(ops)
    vid = np.full(len(V3), -1, dtype=np.int64)
    for k, o in enumerate(ops):  # a loop over openings
        vid[o.loop] = k
    a, b = vid[h3[bnd, 0]], vid[h3[bnd, 1]]
    on = (a >= 0) & (a == b)
    touch = np.zeros((max(n_o, 1), n_p))
    np.add.at(touch, (a[on], hpan[bnd][on]), hlen[bnd][on])
    oname = {o.name: k for k, o in enumerate(ops)}

    def touches(name: str) -> np.ndarray:
        k = oname.get(name)
        return touch[k] if k is not None else np.zeros(n_p)

    # strip geometry: the rectangle with the panel's area and perimeter
    half = perim / 2.0
    disc = np.sqrt(np.maximum(half**2 - 4.0 * At, 0.0))
    L = (half + disc) / 2.0
    w = np.maximum((half - disc) / 2.0, 1e-300)
    strip = L / w >= _STRIP_ASPECT

    role = ["body"] * n_p
    side = ["centre"] * n_p
    s_rel = cen_abs[:, 0] - s0
    reach_l = hi_abs[:, 0] - s0
    reach_r = s0 - lo_abs[:, 0]
    centred = (np.minimum(reach_l, reach_r) > 0) & (
        np.minimum(reach_l, reach_r) >= _CENTRED * np.maximum(reach_l, reach_r)
    )
    for p in range(n_p):
        if not centred[p]:
            side[p] = "left" if s_rel[p] > 0 else "right"

    # strips along openings
    t_neck, t_waist = touches("neckline"), touches("waist")
    t_arm = touches("armhole_left") + touches("armhole_right")
    t_other = touches("hem") + touches("cuff_left") + touches("cuff_right")
    for p in range(n_p):
        if not strip[p] or t_other[p] > 0:
            continue
        if t_arm[p] > 0 and not centred[p]:
            role[p] = "strap"
        elif t_neck[p] >= _STRIP_TOUCH * L[p] and t_arm[p] == 0:
            role[p] = "collar"
        elif t_waist[p] >= _STRIP_TOUCH * L[p]:
            role[p] = "waistband"

    # limbs: seam-connected groups of panels touching no centred opening, reaching a cuff
    t_centred = sum(touches(n) for n in _CENTRED_OPENINGS)
    free = np.array([role[p] == "body" and t_centred[p] == 0 for p in range(n_p)], dtype=bool)
    limb_side = [""] * n_p
    for sname in ("left", "right"):
        tc = touches(f"cuff_{sname}")
        grp = set(np.flatnonzero(free & (tc > 0)).tolist())
        # a limb panel sits out on its side: at least half as far out as the cuff's panels
        far = 0.5 * float(np.mean(np.abs(s_rel[sorted(grp)]))) if grp else 0.0
        frontier = list(grp)
        while frontier:  # a walk over panels
            p = frontier.pop()
            for q in np.flatnonzero((W[p] > 0) & free).tolist():
                on_side = (
                    not centred[q] and (s_rel[q] > 0) == (sname == "left") and abs(s_rel[q]) >= far
                )
                if q not in grp and not limb_side[q] and on_side:
                    grp.add(q)
                    frontier.append(q)
        if not grp:
            continue
        members = sorted(grp)
        body_adj = {p: bool((W[p] * ~free).sum() > 0) for p in members}
        any_body = any(body_adj.values())
        for p in members:
            limb_side[p] = sname
            side[p] = sname
            cuffish = tc[p] > 0 and not body_adj[p] and any_body and len(members) > 1
            role[p] = "cuff" if cuffish else "sleeve"

    # tiers of the body panels
    body = np.array([r == "body" for r in role])
    tops = [oname[n] for n in ("neckline", "armhole_left", "armhole_right") if n in oname]
    tier = [""] * n_p
    hem_p = body & (touches("hem") > 0)
    if tops and hem_p.any():
        top_low = min(float(X[ops[k].loop, 1].min()) for k in tops)
        waist_h = float(hi_abs[hem_p, 1].max())
        if waist_h < top_low:
            for p in np.flatnonzero(body).tolist():
                tier[p] = "bodice" if cen_abs[p, 1] > waist_h else "skirt"
    elif not tops and "waist" in oname:
        for p in np.flatnonzero(body).tolist():
            tier[p] = "skirt"

    # front/back: against the area-weighted mean of the panel's tier (body), else the garment
    face = ["front"] * n_p
    for t in sorted(set(tier)):
        members = np.array([body[p] and tier[p] == t for p in range(n_p)])
        if not members.any():
            continue
        ft = float((cen_abs[members, 2] * At[members]).sum() / max(At[members].sum(), 1e-300))
        fwd, bwd = hi_abs[:, 2] - ft, ft - lo_abs[:, 2]
        wraps = centred & (np.minimum(fwd, bwd) > 0)
        wraps &= np.minimum(fwd, bwd) >= _CENTRED * np.maximum(fwd, bwd)
        for p in np.flatnonzero(members).tolist():
            # a panel around the body (a tube) is neither front nor back
            face[p] = "" if wraps[p] else "front" if cen_abs[p, 2] >= ft else "back"
    for p in np.flatnonzero(~body).tolist():
        face[p] = "front" if cen_abs[p, 2] >= f0 else "back"

    # base names
    base = []
    for p in range(n_p):
        r = role[p]
        sd = "" if side[p] == "centre" else f"_{side[p]}"
        if r == "body" and not face[p]:
            base.append(tier[p] or "body")
        elif r == "body":
            pre = f"{tier[p]}_" if tier[p] else ""
            base.append(f"{pre}{face[p]}{sd}")
        elif r in ("sleeve", "cuff", "strap"):
            base.append(f"{r}{sd}")
        else:
            base.append(r)
    # strips and cuffs sharing a name but not a face: both get _front / _back
    faced = list(base)
    for p in range(n_p):
        if role[p] in ("collar", "waistband", "strap", "cuff"):
            same = [q for q in range(n_p) if base[q] == base[p]]
            if len({face[q] for q in same}) > 1:
                faced[p] = f"{base[p]}_{face[p]}"
    base = faced
    # a two-piece limb: front/back or upper/lower by the larger offset between its halves
    for sname in ("left", "right"):
        sl = [p for p in range(n_p) if limb_side[p] == sname and role[p] == "sleeve"]
        if len(sl) == 2:
            p, q = sl
            d = cen_abs[p] - cen_abs[q]
            if abs(d[2]) >= abs(d[1]):
                hi_p = d[2] > 0
                base[p] += "_front" if hi_p else "_back"
                base[q] += "_back" if hi_p else "_front"
            else:
                hi_p = d[1] > 0
                base[p] += "_upper" if hi_p else "_lower"
                base[q] += "_lower" if hi_p else "_upper"
    rel = cen_abs - np.array([s0, h0, f0])
    names = _unique_names(base, At, rel, hi_abs - lo_abs, np.abs(s_rel))
    return PanelLayout(
        names=names,
        role=role,
        side=side,
        face=face,
        tier=tier,
        centroid=rel,
        lo=lo_abs - np.array([s0, h0, f0]),
        hi=hi_abs - np.array([s0, h0, f0]),
        height=H,
        s0=s0,
        f0=f0,
        h0=h0,
        frame=frame,
        openings=ops,
    )


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
    return _qualify(base, np.array(mids).reshape(-1, 3))


def _side_of(x: float) -> str:
    return "left" if x > 0 else "right"


def _seam_base(
    pp: tuple[int, int], mid: np.ndarray, upc: float, lay: PanelLayout, pn: list[str]
) -> str:
    """The name of one seam before equal names are told apart (``upc``: the up component of
    its principal direction)."""
    vertical, level = upc >= _VERTICAL, upc <= _LEVEL
    a, b = int(pp[0]), int(pp[1])
    ra, rb = lay.role[a], lay.role[b]
    roles = {ra, rb}
    sd = _side_of(float(mid[0]))
    if roles == {"sleeve", "body"}:
        return f"armhole_{lay.side[a] if ra == 'sleeve' else lay.side[b]}"
    if roles == {"cuff", "sleeve"}:
        return f"cuff_{lay.side[a]}"
    if roles <= {"sleeve", "cuff"} and lay.side[a] == lay.side[b]:
        return f"cuff_{lay.side[a]}_end" if roles == {"cuff"} else f"sleeve_{lay.side[a]}"
    if "strap" in roles and roles <= {"strap", "body", "collar"}:
        return f"strap_{lay.side[a] if ra == 'strap' else lay.side[b]}"
    if roles == {"collar", "body"}:
        return "neckline"
    if roles == {"collar"}:
        return "collar"
    if roles == {"waistband", "body"}:
        return "waist"
    if roles == {"waistband"}:
        return "waistband"
    if roles == {"body"}:
        ta, tb = lay.tier[a], lay.tier[b]
        if ta != tb:
            upper = a if ta == "bodice" else b
            if lay.tier[upper] != "bodice":
                return "waist"
            return f"waist_{lay.names[upper].removeprefix('bodice_')}"
        pre = f"{ta}_" if ta else ""
        fa, fb = lay.face[a], lay.face[b]
        members = [p for p in range(len(lay.tier)) if lay.role[p] == "body" and lay.tier[p] == ta]
        t_lo = float(lay.lo[members, 1].min())
        t_hi = float(lay.hi[members, 1].max())
        half_w = max(float(np.abs(np.r_[lay.lo[members, 0], lay.hi[members, 0]]).max()), 1e-12)
        if not fa or not fb:  # a panel around the body
            if not vertical:
                return f"{pn[a]}_{pn[b]}" if a != b else pn[a]
            if abs(mid[0]) >= abs(mid[2]):
                return f"{pre}side_{sd}"
            return f"{pre}center_{'front' if mid[2] > 0 else 'back'}"
        if fa != fb:
            top = (mid[1] - t_lo) >= _SHOULDER * max(t_hi - t_lo, 1e-12)
            return f"{pre}{'shoulder' if top and not vertical else 'side'}_{sd}"
        if level:
            return f"{pre}yoke_{fa}"
        if not vertical:  # diagonal: named by its panels
            return f"{pn[a]}_{pn[b]}"
        if abs(mid[0]) <= _CENTRE_SEAM * half_w:
            return f"{pre}center_{fa}"
        return f"{pre}princess_{fa}_{sd}"
    return f"{pn[a]}_{pn[b]}" if a != b else pn[a]


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
