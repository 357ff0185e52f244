"""The naming rules: a panel's side, role (strip, limb, body), tier and face, and the names
that follow (the module docstring of :mod:`ptailor.model.names` states the rules)."""

from __future__ import annotations

import numpy as np

from ptailor.model import tolerances as model_tol
from ptailor.model.names.measures import OpeningTouch, PanelMeasures

_CENTRED_OPENINGS = ("neckline", "hem", "waist", "armhole_left", "armhole_right")


def strip_shape(perim: np.ndarray, At: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Long side ``L`` of the rectangle with each panel's area and perimeter, and whether
    the panel is a strip (``L / width >= model_tol.NAMES_STRIP_ASPECT``)."""
    half = perim / 2.0
    disc = np.sqrt(np.maximum(half**2 - 4.0 * At, 0.0))
    L = (half + disc) / 2.0
    w = np.maximum((half - disc) / 2.0, 1e-300)
    return L, L / w >= model_tol.NAMES_STRIP_ASPECT


def sides(pm: PanelMeasures) -> tuple[list[str], np.ndarray, np.ndarray]:
    """Each panel's side (``left``/``right``/``centre``), its centroid's left offset from
    the centre line, and whether it straddles the centre line."""
    n_p = len(pm.At)
    side = ["centre"] * n_p
    s_rel = pm.cen_abs[:, 0] - pm.s0
    reach_l = pm.hi_abs[:, 0] - pm.s0
    reach_r = pm.s0 - pm.lo_abs[:, 0]
    centred = (np.minimum(reach_l, reach_r) > 0) & (
        np.minimum(reach_l, reach_r) >= model_tol.NAMES_CENTRED * np.maximum(reach_l, reach_r)
    )
    # a panel in the centre plane (a fin standing out from the centre front) is its own
    # mirror image: centred, not on the side its last bits fall on
    width = float(pm.hi_abs[:, 0].max() - pm.lo_abs[:, 0].min()) if n_p else 0.0
    centred |= np.maximum(np.abs(reach_l), np.abs(reach_r)) <= model_tol.NAMES_ON_LINE * width
    for p in range(n_p):
        if not centred[p]:
            side[p] = "left" if s_rel[p] > 0 else "right"
    return side, s_rel, centred


def strip_roles(
    strip: np.ndarray, L: np.ndarray, centred: np.ndarray, touches: OpeningTouch
) -> list[str]:
    """``strap``, ``collar`` or ``waistband`` for strips along openings, else ``body``."""
    role = ["body"] * len(strip)
    t_neck, t_waist = touches("neckline"), touches("waist")
    t_arm = touches("armhole_left") + touches("armhole_right")
    t_other = touches("hem") + touches("cuff_left") + touches("cuff_right")
    for p in range(len(strip)):
        if not strip[p] or t_other[p] > 0:
            continue
        if t_arm[p] > 0 and not centred[p]:
            role[p] = "strap"
        elif t_neck[p] >= model_tol.NAMES_STRIP_TOUCH * L[p] and t_arm[p] == 0:
            role[p] = "collar"
        elif t_waist[p] >= model_tol.NAMES_STRIP_TOUCH * L[p]:
            role[p] = "waistband"
    return role


def _limb_group(
    sname: str,
    tc: np.ndarray,
    free: np.ndarray,
    W: np.ndarray,
    centred: np.ndarray,
    s_rel: np.ndarray,
    limb_side: list[str],
) -> list[int]:
    """The panels of one side's limb: seam-connected free panels from those at the cuff."""
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
    return sorted(grp)


def limbs(
    role: list[str],
    side: list[str],
    W: np.ndarray,
    centred: np.ndarray,
    s_rel: np.ndarray,
    touches: OpeningTouch,
) -> tuple[list[str], list[str], list[str]]:
    """Sleeves and cuffs: seam-connected groups of body panels touching no centred opening
    that reach a cuff; on a lone limb (openings ``top`` and ``cuff``) every panel, those at
    the cuff not reaching the top being cuffs.

    Returns
    -------
    role, side, limb_side : lists of str
        Updated copies; ``limb_side`` is ``left``/``right`` for limb panels, else ``""``.
    """
    role, side = list(role), list(side)
    n_p = len(role)
    t_centred = sum(touches(n) for n in _CENTRED_OPENINGS)
    free = np.array([role[p] == "body" and t_centred[p] == 0 for p in range(n_p)], dtype=bool)
    limb_side = [""] * n_p
    if "cuff" in touches.index and "top" in touches.index:  # a lone limb (a sleeve sample)
        t_top = touches("top")
        limb = np.flatnonzero(free).tolist()
        for p in limb:
            limb_side[p] = "centre"
            cuffish = touches("cuff")[p] > 0 and t_top[p] == 0 and len(limb) > 1
            role[p] = "cuff" if cuffish else "sleeve"
        return role, side, limb_side
    for sname in ("left", "right"):
        tc = touches(f"cuff_{sname}")
        members = _limb_group(sname, tc, free, W, centred, s_rel, limb_side)
        if not members:
            continue
        body_adj = {p: bool((W[p] * ~free).sum() > 0) for p in members}
        any_body = any(body_adj.values())
        for p in members:
            limb_side[p] = sname
            side[p] = sname
            cuffish = tc[p] > 0 and not body_adj[p] and any_body and len(members) > 1
            role[p] = "cuff" if cuffish else "sleeve"
    return role, side, limb_side


def tiers(body: np.ndarray, touches: OpeningTouch, ops: list, pm: PanelMeasures) -> list[str]:
    """``bodice``/``skirt`` for the body panels of a two-tier top or a skirt, ``leg`` for
    those that reach a leg opening (trousers, a jumpsuit's lower part: its others ``bodice``),
    else ``""``."""
    oname = touches.index
    tops = [oname[n] for n in ("neckline", "armhole_left", "armhole_right") if n in oname]
    tier = [""] * len(body)
    if "leg_left" in oname and "leg_right" in oname:
        legs = body & ((touches("leg_left") > 0) | (touches("leg_right") > 0))
        for p in np.flatnonzero(body).tolist():
            tier[p] = "leg" if legs[p] else "bodice" if tops else ""
        return tier
    hem_p = body & (touches("hem") > 0)
    if tops and hem_p.any():
        top_low = min(float(pm.X[ops[k].loop, 1].min()) for k in tops)
        waist_h = float(pm.hi_abs[hem_p, 1].max())
        if waist_h < top_low:
            for p in np.flatnonzero(body).tolist():
                tier[p] = "bodice" if pm.cen_abs[p, 1] > waist_h else "skirt"
    elif not tops and "waist" in oname:
        for p in np.flatnonzero(body).tolist():
            tier[p] = "skirt"
    return tier


def faces(body: np.ndarray, tier: list[str], centred: np.ndarray, pm: PanelMeasures) -> list[str]:
    """``front``/``back`` against the area-weighted mean of the panel's tier (body panels;
    ``""`` for a tube around the body: a panel straddling the tier's mean front coordinate
    like the centre line, holding at least ``NAMES_WRAP_SHARE`` of the tier's area), else of the
    garment."""
    n_p = len(body)
    cen_abs, At = pm.cen_abs, pm.At
    face = ["front"] * n_p
    for t in sorted(set(tier)):
        members = np.array([body[p] and tier[p] == t for p in range(n_p)])
        if not members.any():
            continue
        ft = float((cen_abs[members, 2] * At[members]).sum() / max(At[members].sum(), 1e-300))
        fwd, bwd = pm.hi_abs[:, 2] - ft, ft - pm.lo_abs[:, 2]
        wraps = centred & (np.minimum(fwd, bwd) > 0)
        wraps &= np.minimum(fwd, bwd) >= model_tol.NAMES_CENTRED * np.maximum(fwd, bwd)
        wraps &= At >= model_tol.NAMES_WRAP_SHARE * float(At[members].sum())
        for p in np.flatnonzero(members).tolist():
            # a panel around the body (a tube) is neither front nor back
            face[p] = "" if wraps[p] else "front" if cen_abs[p, 2] >= ft else "back"
    for p in np.flatnonzero(~body).tolist():
        face[p] = "front" if cen_abs[p, 2] >= pm.f0 else "back"
    return face


def _base_name(role: str, side: str, face: str, tier: str) -> str:
    """One panel's name from its role, side, face and tier."""
    sd = "" if side == "centre" else f"_{side}"
    if role == "body" and not face:
        return tier or "body"
    if role == "body":
        pre = f"{tier}_" if tier else ""
        return f"{pre}{face}{sd}"
    if role in ("sleeve", "cuff", "strap"):
        return f"{role}{sd}"
    return role


def _faced_strips(base: list[str], role: list[str], face: list[str]) -> list[str]:
    """Strips and cuffs sharing a name but not a face: both get ``_front`` / ``_back``."""
    n_p = len(base)
    faced = list(base)
    for p in range(n_p):
        if role[p] in ("collar", "waistband", "strap", "cuff"):
            same = [q for q in range(n_p) if base[q] == base[p]]
            if len({face[q] for q in same}) > 1:
                faced[p] = f"{base[p]}_{face[p]}"
    return faced


def _two_piece_limbs(
    base: list[str], role: list[str], limb_side: list[str], cen_abs: np.ndarray
) -> list[str]:
    """A two-piece limb: front/back or upper/lower by the larger offset between its halves."""
    base = list(base)
    n_p = len(base)
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
    return base


def base_names(
    role: list[str],
    side: list[str],
    face: list[str],
    tier: list[str],
    limb_side: list[str],
    cen_abs: np.ndarray,
) -> list[str]:
    """Each panel's name before equal names are told apart."""
    base = [_base_name(*a) for a in zip(role, side, face, tier, strict=True)]
    base = _faced_strips(base, role, face)
    return _two_piece_limbs(base, role, limb_side, cen_abs)


def unique_names(
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
        Panels that got the same qualifier (two both above the largest) are told apart
        again the same way along the other axis (``front_right_upper``,
        ``front_right_upper_side``); names still equal get ``_2``, ``_3``, ...
    """
    out = list(base)
    for name in sorted(set(base)):
        idx = [p for p, b in enumerate(base) if b == name]
        if len(idx) > 1:
            _qualify_panels(out, idx, area, cen, ext, reach, frozenset())
    return suffix_duplicates(out)


def _qualify_panels(
    out: list[str],
    idx: list[int],
    area: np.ndarray,
    cen: np.ndarray,
    ext: np.ndarray,
    reach: np.ndarray,
    used: frozenset,
) -> None:
    """Qualify the panels ``idx`` of one name in ``out`` against the largest of them, along
    up (``_upper``/``_lower``) or across (``_side``/``_centre``), whichever offset dominates
    and is not in ``used``; recurse into panels that got the same qualifier."""
    idx = sorted(idx, key=lambda p: (-area[p], p))
    ref, name = idx[0], out[idx[0]]
    got: dict[tuple[str, str], list[int]] = {}
    for p in idx[1:]:
        dh = (cen[p, 1] - cen[ref, 1]) / max(ext[ref, 1], 1e-12)
        ds = (reach[p] - reach[ref]) / max(ext[ref, 0], 1e-12)
        if "across" in used or ("up" not in used and abs(dh) >= abs(ds)):
            word, axis = ("upper" if dh > 0 else "lower"), "up"
        elif ds > 0:
            word, axis = "side", "across"
        elif len(idx) == 2:  # the inner of two side by side keeps the name
            out[ref] = f"{name}_side"
            continue
        else:
            word, axis = "centre", "across"
        out[p] = f"{name}_{word}"
        got.setdefault((out[p], axis), []).append(p)
    for (_, axis), same in got.items():
        if len(same) > 1 and not used:  # one more axis, then _2, _3
            _qualify_panels(out, same, area, cen, ext, reach, used | {axis})


def mirror_name(name: str) -> str:
    """``name`` with ``left`` and ``right`` swapped (``bodice_front_left`` ->
    ``bodice_front_right``; ``armhole_left_upper`` -> ``armhole_right_upper``)."""
    swap = {"left": "right", "right": "left"}
    return "_".join(swap.get(w, w) for w in name.split("_"))


def mirror_pairs(cen: np.ndarray, area: np.ndarray, ext: np.ndarray, side: list[str]) -> list:
    """Left/right panels that are each other's mirror image across the centre line.

    Parameters
    ----------
    cen : (n_p, 3) float array
        Centroids ``(left, up, front)`` relative to the centre line.
    area : (n_p,) float array
    ext : (n_p, 3) float array
        Extents per panel.
    side : list of str
        ``left``/``right``/``centre`` per panel.

    Returns
    -------
    list of (int, int)
        ``(left panel, right panel)``, nearest pairs first: the mirrored centroids within a
        tenth of the panel's extent and the areas within 15 %.
    """
    left = [p for p, sd in enumerate(side) if sd == "left"]
    right = [q for q, sd in enumerate(side) if sd == "right"]
    if not left or not right:
        return []
    L, R = np.array(left), np.array(right)
    M = cen[L] * np.array([-1.0, 1.0, 1.0])
    d = np.linalg.norm(M[:, None, :] - cen[R][None, :, :], axis=2)
    scale = np.maximum(np.max(ext[L], axis=1), 1e-12)[:, None]
    ratio = area[L][:, None] / np.maximum(area[R][None, :], 1e-300)
    ok = (d <= 0.1 * scale) & (np.abs(ratio - 1.0) <= 0.15)
    pairs, used_l, used_r = [], set(), set()
    for i, j in zip(*np.unravel_index(np.argsort(d, axis=None), d.shape), strict=True):
        if ok[i, j] and i not in used_l and j not in used_r:
            pairs.append((int(L[i]), int(R[j])))
            used_l.add(i)
            used_r.add(j)
    return pairs


def mirrored_names(names: list[str], pairs: list) -> list[str]:
    """Mirror panels named alike: the right one of each pair takes the left one's name with
    ``left`` and ``right`` swapped, unless another panel has that name."""
    out = list(names)
    for p, q in pairs:
        want = mirror_name(out[p])
        if out[q] != want and want not in out:
            out[q] = want
    return out


def suffix_duplicates(names: list[str]) -> list[str]:
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


def reasons(
    pm: PanelMeasures,
    aspect: np.ndarray,
    strip: np.ndarray,
    role: list[str],
    side: list[str],
    face: list[str],
    tier: list[str],
    s_rel: np.ndarray,
    touches: OpeningTouch,
) -> list[str]:
    """Why each panel has its name: the rules that fired and the measures they used.

    Parameters
    ----------
    aspect : (n_p,) float array
        Length over width of the rectangle with each panel's area and outline length (of
        its pattern, as the strip test read it).
    strip : (n_p,) bool array
        Whether the strip test found each panel a strip.

    Returns
    -------
    list of str
        One line per panel, for example ``"body (length/width 1.4, under 3.5 for a
        strip); bodice (centroid 32.1 above the hem panels' top 30.5); front (centroid 9.1
        ahead of its tier's mean); centre (reaches 20.3 left and 21.0 right of the centre
        line)"``.
    """
    n_p = len(role)
    names = list(touches.index)
    on = [
        [n for n in names if touches(n)[p] > 0] for p in range(n_p)
    ]  # the openings each panel touches
    ft: dict[str, float] = {}
    for t in sorted(set(tier)):
        m = np.array([role[p] == "body" and tier[p] == t for p in range(n_p)])
        if m.any():
            ft[t] = float((pm.cen_abs[m, 2] * pm.At[m]).sum() / max(pm.At[m].sum(), 1e-300))
    out = []
    for p in range(n_p):  # a loop over panels
        touching = f", touches {', '.join(on[p])}" if on[p] else ", touches no opening"
        if role[p] == "body":
            short = "" if strip[p] else f", under {model_tol.NAMES_STRIP_ASPECT:g} for a strip"
            why = [f"body (length/width {_r(aspect[p]):.2g}{short}{touching})"]
        elif role[p] in ("sleeve", "cuff"):
            why = [
                f"{role[p]} (in the limb that reaches cuff_{side[p]}, no centred opening{touching})"
            ]
        else:
            why = [
                f"{role[p]} (a strip: length/width {_r(aspect[p]):.2g}"
                f" >= {model_tol.NAMES_STRIP_ASPECT:g}"
                f"{touching})"
            ]
        if tier[p]:
            why.append(f"{tier[p]} (its tier: centroid height {_r(pm.cen_abs[p, 1] - pm.h0):.3g})")
        if role[p] == "body" and tier[p] in ft:
            d = float(pm.cen_abs[p, 2] - ft[tier[p]])
            if not face[p]:
                why.append("around the body (it straddles its tier's mean front coordinate)")
            else:
                where = "ahead of" if d >= 0 else "behind"
                why.append(f"{face[p]} (centroid {_r(abs(d)):.3g} {where} its tier's mean)")
        reach_l = float(pm.hi_abs[p, 0] - pm.s0)
        reach_r = float(pm.s0 - pm.lo_abs[p, 0])
        if side[p] == "centre":
            why.append(
                f"centre (reaches {_r(reach_l):.3g} left and {_r(reach_r):.3g} right of the"
                " centre line)"
            )
        else:
            why.append(
                f"{side[p]} (centroid {_r(abs(float(s_rel[p]))):.3g} {side[p]} of the centre line)"
            )
        out.append("; ".join(why))
    return out


def _r(x: float) -> float:
    """A measure as shown: rounded to 1e-6 (sums in another order give the same words)."""
    return round(float(x), 6) + 0.0
