"""Seams named from the panels they join and where they run."""

from __future__ import annotations

import numpy as np

from ptailor.model import tolerances as model_tol
from ptailor.model.names.layout import PanelLayout
from ptailor.model.names.roles import mirror_name, suffix_duplicates

#: the words a mirror swaps; place words along each axis (across: of a sided name)
_SIDES = frozenset({"left", "right"})
_WORDS = (("inner", "outer"), ("lower", "upper"), ("back", "front"))
_ACROSS = (("right", -1), ("", 0), ("left", 1))
_FLIP = np.array([-1.0, 1.0, 1.0])


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
          the top quarter of the tier, else ``side_<side>``; both front (back): when the
          seam is not vertical (it runs across, level or slanting: a panel and the one above
          it) ``yoke_front`` (``yoke_back``), else ``center_front`` (``center_back``), each
          with ``_<side>`` when it is off the centre line (a vertical one then
          ``princess_front_<side>``): a seam between a left and a right panel is on it, one
          between two panels of one side off it, any other by its midpoint; a panel's seam
          with itself is a dart, ``dart_<face>[_<side>]``; vertical: the up component of
          the seam's principal direction >= 0.8;
        - two leg panels (tier ``leg``: trousers, a jumpsuit's lower part), vertical:
          ``inseam_<side>`` / ``outseam_<side>`` between a leg's front and back (nearer /
          farther from the centre line than the leg's middle), ``crotch_front`` /
          ``crotch_back`` between the two legs, ``dart_<face>_<side>`` within one;
        - a body panel around the body (a tube) and another: a vertical seam is
          ``side_<side>`` or ``center_front``/``center_back`` by where its midpoint sits,
          any other is named by its panels (below);
        - anything else by its panels: the first one's name, then the words of the second's
          it lacks (each word once: ``cuff_left`` and ``front`` give ``cuff_left_front``).

        One scheme for every name: ``[tier_]kind[_face][_side][_place]``, where ``_side``
        (``left``/``right``) is the only word a mirror swaps. A seam and its mirror image
        (the seam across the centre line between the mirror images of its panels) are named
        from their shared place, the mean of the one's midpoint and the other's mirrored,
        so they get mirror names. Equal names are told apart by place words
        (:func:`_place_words`): ``_upper``/``_lower``, ``_front``/``_back``, across the
        body ``_left``/``_right`` (for a name without a side) or ``_inner``/``_outer`` (for
        one with it), along the axis that separates their midpoints most, then along
        another; ``_2``, ``_3``, ... only where no axis does.
    """
    X = np.asarray(V3, dtype=np.float64) @ layout.frame.T
    origin = np.array([layout.s0, layout.h0, layout.f0])
    pn = list(layout.names if panel_names is None else panel_names)
    geo = [_seam_geometry(X[np.asarray(s.edges3)] - origin) for s in seam_list]
    M = np.array([m for m, _ in geo]).reshape(-1, 3)
    U = np.array([u for _, u in geo])
    partner = _partners(seam_list, M, layout.mirror)
    # a seam and its mirror image are named from their shared place: the mean of the one's
    # midpoint and the other's mirrored (so the two get mirror names, whichever side the
    # last bits of an asymmetric mesh fall on)
    S = (M + M[partner] * _FLIP) / 2.0
    S[partner == np.arange(len(M))] = M[partner == np.arange(len(M))]
    Us = (U + U[partner]) / 2.0
    base = [_seam_base(s.panels, S[i], Us[i], layout, pn) for i, s in enumerate(seam_list)]
    return _mirrored(_qualify(base, S), partner, S)


def _seam_geometry(E: np.ndarray) -> tuple[np.ndarray, float]:
    """A seam's length-weighted midpoint and the up component of its principal direction,
    from its edges ``E`` (``(k, 2, 3)``, in the wearer's frame)."""
    P, Q = E[:, 0], E[:, 1]
    seg = np.linalg.norm(Q - P, axis=1)
    tot = float(seg.sum())
    mid = ((P + Q) * 0.5 * seg[:, None]).sum(0) / tot if tot > 0 else P.mean(0)
    pts = np.concatenate([P, Q])
    if len(pts) < 2:
        return mid, 0.5
    _, _, vt = np.linalg.svd(pts - pts.mean(0), full_matrices=False)
    return mid, abs(float(vt[0, 1]))


def _partners(seam_list: list, mids: np.ndarray, mirror: np.ndarray) -> np.ndarray:
    """Each seam's mirror image: a seam on the other side of the centre line whose panels
    are the mirror images of its own (a centred panel its own) and whose midpoint lies
    nearer the mirrored one than ``NAMES_MIRROR_NEAR`` of the two midpoints' distance, nearest
    first; a seam without one is its own (the front and back seams of two halves, each
    across the centre line, are not each other's).

    Returns
    -------
    (n_s,) int array
    """
    n = len(seam_list)
    partner = np.arange(n)
    if len(mirror) == 0 or n == 0:
        return partner
    own = [tuple(sorted(int(p) for p in s.panels)) for s in seam_list]
    image = [tuple(sorted(int(mirror[p]) for p in s.panels)) for s in seam_list]
    flip = mids * _FLIP
    cand = [
        (float(np.linalg.norm(mids[j] - flip[i])), i, j)
        for i in range(n)
        if mids[i, 0] > 0 and -1 not in image[i]
        for j in range(n)
        if j != i and own[j] == image[i] and mids[j, 0] < 0
    ]
    apart = [float(np.linalg.norm(mids[i] - mids[j])) for _, i, j in cand]
    cand = [c for c, a in zip(cand, apart, strict=True) if c[0] <= model_tol.NAMES_MIRROR_NEAR * a]
    for _, i, j in sorted(cand):  # a loop over candidate pairs, nearest first
        if partner[i] == i and partner[j] == j:
            partner[i], partner[j] = j, i
    return partner


def _mirrored(names: list[str], partner: np.ndarray, mids: np.ndarray) -> list[str]:
    """Mirror seams named alike: the right seam of each pair takes the left one's name with
    ``left`` and ``right`` swapped, unless another seam has that name."""
    out = list(names)
    for i in np.flatnonzero((partner != np.arange(len(partner))) & (mids[:, 0] > 0)).tolist():
        want, j = mirror_name(out[i]), int(partner[i])
        if out[j] != want and want not in out:
            out[j] = want
    return out


def _joined(a: str, b: str) -> str:
    """A seam named by its panels: ``a``'s words, then those of ``b`` that ``a`` lacks, so
    that each word (the tier, the face, the side a mirror swaps) is said once
    (``cuff_left`` and ``front``: ``cuff_left_front``; ``skirt`` and ``skirt_front``:
    ``skirt_front``; a panel's seam with itself: its name)."""
    words = a.split("_")
    return "_".join(words + [w for w in b.split("_") if w not in words])


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
    return _joined(pn[a], pn[b])


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
    vertical = upc >= model_tol.NAMES_VERTICAL
    sd = _side_of(float(mid[0]))
    if not fa or not fb:  # a panel around the body
        if not vertical:
            return _joined(pn[a], pn[b])
        if abs(mid[0]) >= abs(mid[2]):
            return f"{pre}side_{sd}"
        return f"{pre}center_{'front' if mid[2] > 0 else 'back'}"
    members = [p for p in range(len(lay.tier)) if lay.role[p] == "body" and lay.tier[p] == ta]
    if ta == "leg" and vertical:
        return _leg_seam(a, b, mid, lay, members)
    if fa != fb:
        t_lo = float(lay.lo[members, 1].min())
        t_hi = float(lay.hi[members, 1].max())
        top = (mid[1] - t_lo) >= model_tol.NAMES_SHOULDER * max(t_hi - t_lo, 1e-12)
        return f"{pre}{'shoulder' if top and not vertical else 'side'}_{sd}"
    half_w = max(float(np.abs(np.r_[lay.lo[members, 0], lay.hi[members, 0]]).max()), 1e-12)
    centred = abs(mid[0]) <= model_tol.NAMES_CENTRE_SEAM * half_w
    if a == b:  # a panel sewn to itself
        return f"{pre}dart_{fa}" + ("" if centred else f"_{sd}")
    sides = {lay.side[a], lay.side[b]}
    if sides <= {"left", "right"}:  # the two halves' seam; two panels of one side's
        centred = len(sides) == 2
    if not vertical:  # across the body (level or slanting): a panel and the one above it
        return f"{pre}yoke_{fa}" + ("" if centred else f"_{sd}")
    return f"{pre}center_{fa}" if centred else f"{pre}princess_{fa}_{sd}"


def _leg_seam(a: int, b: int, mid: np.ndarray, lay: PanelLayout, members: list[int]) -> str:
    """A vertical seam between two trouser-leg panels: ``inseam_<side>`` / ``outseam_<side>``
    (front to back, nearer / farther from the centre line than the leg's middle), else
    ``crotch_front`` / ``crotch_back`` (the left leg to the right one), else a seam within one
    side and face (``dart_<face>_<side>``)."""
    sd = _side_of(float(mid[0]))
    if lay.side[a] != lay.side[b]:
        return f"crotch_{'front' if mid[2] > 0 else 'back'}"
    if lay.face[a] == lay.face[b]:
        return f"dart_{lay.face[a]}_{sd}"
    mine = [p for p in members if lay.side[p] == lay.side[a]]
    middle = float(np.mean(0.5 * (lay.lo[mine, 0] + lay.hi[mine, 0])))
    return f"{'inseam' if abs(mid[0]) < abs(middle) else 'outseam'}_{sd}"


def _qualify(base: list[str], mids: np.ndarray) -> list[str]:
    """Tell equal seam names apart by where their midpoints sit (:func:`_place_words`)."""
    out = list(base)
    for name in sorted(set(base)):
        idx = [i for i, b in enumerate(base) if b == name]
        if len(idx) < 2:
            continue
        words = _place_words(mids[idx], sided=bool(_SIDES & set(name.split("_"))))
        for i, w in zip(idx, words, strict=True):
            out[i] = "_".join([name, *w])
    return suffix_duplicates(out)


def _place_words(M: np.ndarray, *, sided: bool) -> list[list[str]]:
    """Place words that tell apart seams of one name, mirror images alike.

    The seams are split along the axis that separates their midpoints most, at the widest
    gap between them (where the gaps are even, at the median: an odd count's middle seam is
    ``middle``), and each part again, along another axis, while its seams still share the
    words: ``lower``/``upper``, ``back``/``front``, and across the body
    ``right``/``left`` by the side of the centre line a midpoint lies on (a seam on the
    centre line gets no side word), or, for a name that already has its side (and for the
    seams of one side), ``inner``/``outer`` by the distance from the centre line. A side
    word goes first (``waist_right_back``, as ``armhole_right_back``).

    Parameters
    ----------
    M : (k, 3) float array
        Midpoints ``(left, up, front)`` from the centre line.
    sided : bool
        The name has its side word.

    Returns
    -------
    list of list of str
        The words per seam (seams no axis separates keep equal words: ``_2``, ``_3`` follow).
    """
    words: list[list[str]] = [[] for _ in range(len(M))]
    _split(M, list(range(len(M))), sided, words, frozenset())
    return [sorted(w, key=lambda x: x not in _SIDES) for w in words]


def _split(
    M: np.ndarray, members: list[int], sided: bool, words: list[list[str]], used: frozenset
) -> None:
    """Split ``members`` along the axis not in ``used`` that separates them most (axis
    ``-1``: the side of the centre line); recurse into the parts."""
    best = None
    for ax in (0, 1, 2):
        key = -1 if ax == 0 and not sided else ax
        parts = None if key in used else _parts(M[members], key)
        if parts is not None and (best is None or parts[0] > best[0]):
            best = (*parts, key)
    if best is None:
        return
    _, groups, key = best
    for word, sub in groups:
        chosen = [members[k] for k in sub]
        for m in chosen:
            if word:
                words[m].append(word)
        if len(chosen) > 1:
            _split(M, chosen, sided or key == -1, words, used | {key})


def _parts(M: np.ndarray, key: int) -> tuple[float, list] | None:
    """How axis ``key`` splits the midpoints ``M`` (0: by the distance from the centre
    line; -1: by its side): its spread and ``(word, indices)`` per part, or None when it
    separates nothing (by side: when all lie on the centre line)."""
    if key == -1:
        x = M[:, 0]
        tol = model_tol.NAMES_CENTRE_SEAM * max(float(np.abs(x).max()), 1e-12)
        side = np.where(x > tol, 1, np.where(x < -tol, -1, 0))
        groups = [(w, np.flatnonzero(side == v).tolist()) for w, v in _ACROSS]
        groups = [g for g in groups if g[1]]
        if len(groups) < 2 and groups[0][0] == "":
            return None
        return float(np.ptp(x)), groups
    v = np.abs(M[:, 0]) if key == 0 else M[:, key]
    order = np.argsort(v, kind="stable")
    gaps = np.diff(v[order])
    if not len(gaps) or gaps.max() <= 0.0:
        return None
    lo_w, hi_w = _WORDS[key]
    n, widest = len(v), np.sort(gaps)[::-1]
    if (
        len(gaps) > 1 and widest[0] < model_tol.NAMES_EVEN_GAPS * widest[1]
    ):  # evenly spread: at the median
        lo, mid = order[: n // 2], order[n // 2 : (n + 1) // 2]
        parts = [(lo_w, lo), ("middle", mid), (hi_w, order[(n + 1) // 2 :])]
    else:  # at the widest gap
        cut = int(np.argmax(gaps)) + 1
        parts = [(lo_w, order[:cut]), (hi_w, order[cut:])]
    return float(np.ptp(v)), [(w, sorted(p.tolist())) for w, p in parts if len(p)]
