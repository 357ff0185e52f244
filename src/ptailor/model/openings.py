"""Openings: the boundary loops of the drape, named from geometry.

One recipe should be able to say ``hem`` for a T-shirt, a dress and a skirt, so the names come
from where a loop sits on the garment, not from the file. See :func:`openings` for the rules.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ptailor.geometry.labels import component_labels, used_indices
from ptailor.geometry.topology import loop_halfedges
from ptailor.geometry.triangles import triangle_areas
from ptailor.model import tolerances as model_tol
from ptailor.model.boundary import boundary_curves
from ptailor.model.frame import Frame


@dataclass(frozen=True)
class Opening:
    """One opening of a garment: a boundary loop of the drape.

    Attributes
    ----------
    name : str
        ``hem``, ``neckline``, ``waist``, ``cuff_left``, ``cuff_right``, ``leg_left``,
        ``leg_right``, ``armhole_left``, ``armhole_right``, else ``opening_<k>``.
    loop : (k,) int array
        Ordered drape vertex indices (into ``V3``) of the loop, in boundary half-edge order.
    length : float
        3D perimeter of the closed loop.
    centroid : (3,) float array
        Length-weighted centroid of the loop (its edges' midpoints weighted by their length).
    closed : bool
        False for an open chain: the free edge of a piece sewn onto the middle of another
        (a T-seam: placket, pocket, strip), whose ends lie inside the cloth; its ``length``
        and ``centroid`` are those of the chain itself, without the chord between its ends.
    """

    name: str
    loop: np.ndarray
    length: float
    centroid: np.ndarray
    closed: bool = True


def _loop_geometry(P: np.ndarray, closed: bool = True) -> tuple[float, np.ndarray, np.ndarray]:
    """Length, length-weighted centroid and best-fit plane normal of a polyline.

    Parameters
    ----------
    P : (k, 3) float array
        The polyline's points.
    closed : bool
        Whether the last point joins the first.
    """
    Q = np.roll(P, -1, axis=0)
    seg = np.linalg.norm(Q - P, axis=1)
    if not closed:
        seg[-1] = 0.0  # no chord between the ends
    length = float(seg.sum())
    if length > 0.0:
        centroid = ((P + Q) * 0.5 * seg[:, None]).sum(axis=0) / length
        w = 0.5 * (seg + np.roll(seg, 1))  # each vertex carries half its two edges
    else:
        centroid = P.mean(axis=0)
        w = np.ones(len(P))
    X = (P - centroid) * np.sqrt(w)[:, None]
    _, _, vt = np.linalg.svd(X, full_matrices=False)
    normal = vt[-1] if vt.shape[0] == 3 else np.zeros(3)
    return length, centroid, normal


def moved_openings(source: list[Opening], V3: np.ndarray) -> list[Opening]:
    """The openings ``source`` of a garment, on the same cloth draped as ``V3``.

    An edit that moves the drape but keeps its triangles keeps its openings: the same loops
    under the same names (the naming rules read the garment it came from, not how far the
    edit moved it), with their lengths and centroids measured on ``V3``.

    Parameters
    ----------
    source : list of Opening
        :func:`openings` of the garment before the move.
    V3 : (n, 3) float array
        The moved drape (the same vertices).

    Returns
    -------
    list of Opening
        One per source opening, in its order.
    """
    out = []
    for o in source:  # a loop over the openings (a handful)
        length, centroid, _ = _loop_geometry(np.asarray(V3, dtype=np.float64)[o.loop], o.closed)
        out.append(Opening(o.name, o.loop, length, centroid, o.closed))
    return out


def descended_openings(
    source: list[Opening], found: list[Opening], vertex_source: np.ndarray
) -> list[Opening]:
    """The openings ``found`` on a garment cut from another, named as the source's were.

    A cut that removes triangles (a V neckline, a shortened hem) reshapes an opening but
    leaves it the same opening: each source opening names the found loop that keeps the
    most of its vertices (a loop keeps a name only once); a loop that keeps none of a named
    opening's vertices (a new hole) keeps the name the rules gave it unless a carried name
    took it, then ``opening_<k>``.

    Parameters
    ----------
    source : list of Opening
        The source garment's openings.
    found : list of Opening
        :func:`openings` of the cut garment.
    vertex_source : (n,) int array
        Each drape vertex of the cut garment's source vertex, -1 for a vertex the cut made.

    Returns
    -------
    list of Opening
        ``found``, renamed, in its order.
    """
    vs = np.asarray(vertex_source, dtype=np.int64)
    n_src = int(max((int(o.loop.max()) for o in source if len(o.loop)), default=-1)) + 1
    owner = np.full(max(n_src, 1), -1, dtype=np.int64)
    for k, o in enumerate(source):  # a loop over the openings (a handful)
        owner[o.loop] = k
    # shared[i, k]: how many of found loop i's vertices were source opening k's
    shared = np.zeros((len(found), len(source)), dtype=np.int64)
    for i, o in enumerate(found):  # a loop over the openings
        src = vs[o.loop]
        src = src[(src >= 0) & (src < len(owner))]
        k = owner[src]
        shared[i] = np.bincount(k[k >= 0], minlength=len(source))[: len(source)]
    names: list[str | None] = [None] * len(found)
    for k in np.argsort(-shared.max(axis=0, initial=0), kind="stable"):  # best kept first
        free = [i for i in range(len(found)) if names[i] is None and shared[i, k] > 0]
        if free:
            names[max(free, key=lambda i: shared[i, k])] = source[k].name
    taken = {n for n in names if n is not None}
    out = []
    for i, o in enumerate(found):  # a loop over the openings
        name = names[i] or (o.name if o.name not in taken else f"opening_{i}")
        out.append(Opening(name, o.loop, o.length, o.centroid, o.closed))
    return out


def openings(V3, F3, *, frame: Frame, F2=None, curves=None) -> list[Opening]:
    """The openings (boundary loops of the drape) with names from geometry.

    Parameters
    ----------
    V3 : (n, 3) float array
        Drape positions; vertices no triangle uses are ignored.
    F3 : (m, 3) int array
        Drape triangles.
    frame : Frame
        The wearer's axes (``Garment.frame``; ``front`` is orthogonalised against ``up``).
    F2 : (m, 3) int array, optional
        Pattern triangles. At a drape edge of three or more faces (a T-seam) they tell the
        panel (two faces on one pattern edge) from the piece sewn onto it; without them the
        flattest pair of faces is taken for the panel
        (:func:`ptailor.model.boundary.boundary_curves`).
    curves : (list of (k,) int arrays, (c,) bool array), optional
        ``boundary_curves(F3, V=V3, F2=F2)``, when the caller already has it.

    Returns
    -------
    list of Opening
        In :func:`ptailor.model.boundary.boundary_curves` order (longest loop first, ties by
        first vertex); names are unique. Loops are traced deterministically on non-manifold
        drapes: edges of three or more faces are sewn (never boundary), each sector of a
        non-manifold vertex is traced on its own, loops are simple, and no loop has zero
        length. The free edge of a strip sewn onto a panel's middle is an open chain
        (``closed`` False).

    Notes
    -----
    Everything is measured in the wearer's frame: ``left = up x front`` is the wearer's left
    (y up, z front: the wearer's left is +x, so ``cuff_left`` has the larger x). ``height``
    is the coordinate along ``up``; ``H`` the garment's height (referenced vertices).

    1. Loops shorter than 5 % of the longest loop are ignored (``opening_<k>``). Each other
       loop gets its perimeter, centroid and best-fit plane normal; it is *horizontal* when
       that normal is within 60 degrees of ``up``.
    2. The centre line is the garment's area-weighted mean left coordinate. A loop that
       straddles it is *centred*; a loop entirely on the wearer's left (right) of it is a
       *left* (*right*) *side loop*.
    3. Legs: if both sides have side loops, the lowest side loop of each side is horizontal,
       both lie in the lower half of the garment, below every centred loop, and there is at
       most one centred loop, they are ``leg_left`` and ``leg_right`` (trousers, shorts,
       jumpsuits).
    4. Sleeves: if (after the legs) both sides still have side loops, the longest one on each
       side is a sleeve opening and the garment is a *top*. They are ``cuff_left`` and
       ``cuff_right`` when they lie outside the torso: the torso's half-width is the largest
       distance from the centre line of the garment's vertices in a band just below the two
       loops (as tall as the taller loop, at least 5 % of ``H``), and the loops are cuffs when
       the sum of their two inner edges' distances from the centre line exceeds the sum of the
       two half-widths (an empty band counts as zero width), or (with ``F2``) when both lie
       on pattern panels that hold no centred loop: pieces sewn onto the body (a short
       sleeve hanging within the torso's width). Otherwise they are ``armhole_left`` and
       ``armhole_right`` (sleeveless tops and dresses).
    5. Centred loops, sorted by centroid height:
       - top with legs (jumpsuit): the highest is ``neckline``;
       - top: with two or more, the highest is ``neckline`` and the lowest horizontal other
         one ``hem``; with one, it is ``hem`` when horizontal and below both sleeve loops'
         centroids, else ``neckline``;
       - legs without a top (trousers): the highest horizontal one is ``waist``;
       - a lone tube whose two horizontal loops are as far apart as the longer one is long
         (a sleeve: the lantern sample's are 48 apart and 28 around) is a limb: ``top`` and
         ``cuff``;
       - neither (skirt, tube): among the horizontal ones the lowest is ``hem`` and, when
         there are two or more, the highest is ``waist``. A short wide tube (a cylinder
         20 tall and 30 around) therefore gets ``waist`` on top and ``hem`` at the bottom.
    6. Every other loop is ``opening_<k>``, ``k`` its index in the returned list.
    """
    V3 = np.asarray(V3, dtype=np.float64)
    F3 = np.asarray(F3, dtype=np.int64).reshape(-1, 3)
    loops, closed = _loops(V3, F3, F2, curves)
    if not loops:
        return []
    m = _loop_measures(V3, F3, loops, closed, frame.matrix())
    if F2 is not None:
        m = replace(m, panels=_loop_panels(F3, np.asarray(F2, dtype=np.int64), loops))
    return _named_openings(m, _opening_names(m))


@dataclass(frozen=True)
class _LoopMeasures:
    """The garment and its loops measured in the wearer's frame (rules 1 and 2).

    Attributes
    ----------
    loops : list of (k,) int arrays
    closed : (c,) bool array
    S, Hc : (n,) float arrays
        Left coordinate and height of every vertex.
    used : (u,) int array
        The vertices a triangle uses.
    h_min, H : float
        The garment's lowest height and its height.
    s0 : float
        The centre line's left coordinate.
    length : (c,) float array
    centroid : (c, 3) float array
    ch : (c,) float array
        Centroid heights.
    smin, smax : (c,) float arrays
        Each loop's extent along left.
    big : (c,) bool array
        Loops long enough to be named.
    horizontal : (c,) bool array
    panels : list of frozenset of int
        The pattern panels (components of ``F2``) each loop's edges lie on; empty without
        ``F2``.
    """

    loops: list
    closed: np.ndarray
    S: np.ndarray
    Hc: np.ndarray
    used: np.ndarray
    h_min: float
    H: float
    s0: float
    length: np.ndarray
    centroid: np.ndarray
    ch: np.ndarray
    smin: np.ndarray
    smax: np.ndarray
    big: np.ndarray
    horizontal: np.ndarray
    panels: list = field(default_factory=list)


def _loop_panels(F3: np.ndarray, F2: np.ndarray, loops: list) -> list[frozenset]:
    """The pattern panels (components of ``F2``) each loop's edges lie on."""
    lab = component_labels(F2, int(F2.max()) + 1 if F2.size else 0)
    return [  # a loop over the loops (a handful)
        frozenset(lab[loop_halfedges(F3, L) // 3].tolist()) for L in loops
    ]


def _loops(V3: np.ndarray, F3: np.ndarray, F2, curves) -> tuple[list, np.ndarray]:
    """The boundary loops and whether each is closed (none without triangles)."""
    if not len(F3):
        return [], np.zeros(0, dtype=bool)
    return boundary_curves(F3, V=V3, F2=F2) if curves is None else curves


def _loop_measures(
    V3: np.ndarray, F3: np.ndarray, loops: list, closed, frame: np.ndarray
) -> _LoopMeasures:
    """Every loop's length, centroid and plane, and the garment's extent and centre line."""
    used = used_indices(F3, len(V3))
    S = V3 @ frame[0]  # left coordinate per vertex
    Hc = V3 @ frame[1]  # height per vertex
    h_min, h_max = float(Hc[used].min()), float(Hc[used].max())
    n = len(loops)
    geo = [_loop_geometry(V3[L], bool(c)) for L, c in zip(loops, closed, strict=True)]
    length = np.array([g[0] for g in geo])
    cen = np.array([g[1] for g in geo]).reshape(n, 3)
    nrm = np.array([g[2] for g in geo]).reshape(n, 3)
    return _LoopMeasures(
        loops=loops,
        closed=closed,
        S=S,
        Hc=Hc,
        used=used,
        h_min=h_min,
        H=h_max - h_min,
        s0=_centre_line(V3, F3, S, used),
        length=length,
        centroid=cen,
        ch=cen @ frame[1],
        smin=np.array([S[L].min() for L in loops]),
        smax=np.array([S[L].max() for L in loops]),
        big=length >= model_tol.OPENING_MIN_REL_LENGTH * length.max(),
        horizontal=np.abs(nrm @ frame[1]) >= model_tol.OPENING_HORIZONTAL_COS,
    )


def _opening_names(m: _LoopMeasures) -> dict[int, str]:
    """The names of the loops by rules 2 to 5 (a loop left out is ``opening_<k>``)."""
    n, s0, ch = len(m.loops), m.s0, m.ch
    # a loop touching the centre line is on the side it reaches into: its end on the line is
    # there up to rounding (which grows with the distance from the origin), not exactly
    eps = model_tol.OPENING_ON_LINE * float(np.ptp(m.S[m.used])) if len(m.used) else 0.0
    lo, hi = m.smin >= s0 - eps, m.smax <= s0 + eps
    centred = [i for i in range(n) if m.big[i] and lo[i] == hi[i]]  # across it, or on it
    left = [i for i in range(n) if m.big[i] and lo[i] and not hi[i]]
    right = [i for i in range(n) if m.big[i] and hi[i] and not lo[i]]
    centred.sort(key=lambda i: (ch[i], i))
    names: dict[int, str] = {}

    # 3. legs
    legs = _legs(left, right, centred, ch, m.horizontal, m.h_min + 0.5 * m.H)
    if legs is not None:
        ll, lr = legs
        names[ll], names[lr] = "leg_left", "leg_right"
        left.remove(ll)
        right.remove(lr)

    # 4. sleeves or armholes
    sleeve_h = None
    if left and right:
        sl = max(left, key=lambda i: (m.length[i], -i))
        sr = max(right, key=lambda i: (m.length[i], -i))
        band = (m.Hc[m.loops[sl]], m.Hc[m.loops[sr]])
        inner = (m.smin[sl] - s0) + (s0 - m.smax[sr])
        kind = _sleeve_kind(band, inner, m.Hc, m.S, m.used, s0, m.H)
        if kind == "armhole" and _sewn_on(m.panels, (sl, sr), centred):
            kind = "cuff"  # a short sleeve hanging within the torso's width
        names[sl], names[sr] = f"{kind}_left", f"{kind}_right"
        sleeve_h = min(ch[sl], ch[sr])

    # 5. centred loops
    names.update(
        _centred_names(
            centred, m.horizontal, ch, sleeve_h, has_legs=legs is not None, lengths=m.length
        )
    )
    return names


def _named_openings(m: _LoopMeasures, names: dict[int, str]) -> list[Opening]:
    """The openings of the loops, a loop without a name ``opening_<k>`` (rule 6)."""
    return [
        Opening(
            name=names.get(i, f"opening_{i}"),
            loop=m.loops[i],
            length=float(m.length[i]),
            centroid=m.centroid[i],
            closed=bool(m.closed[i]),
        )
        for i in range(len(m.loops))
    ]


def _centre_line(V3: np.ndarray, F3: np.ndarray, S: np.ndarray, used: np.ndarray) -> float:
    """The garment's area-weighted mean left coordinate ``S`` (the centre line)."""
    # sums in an order that depends on the cloth, not on the face order or corner rotation
    Fs = np.sort(F3, axis=1)
    area = triangle_areas(V3, Fs)
    face_s = np.sort(S[Fs], axis=1).sum(axis=1) / 3.0
    tot = np.sort(area).sum()
    return float(np.sort(area * face_s).sum() / tot) if tot > 0 else float(S[used].mean())


def _legs(
    left: list[int],
    right: list[int],
    centred: list[int],
    ch: np.ndarray,
    horizontal: np.ndarray,
    mid: float,
) -> tuple[int, int] | None:
    """The two leg openings (rule 3), or None; ``mid`` the garment's mid height."""
    if not (left and right and len(centred) <= 1):
        return None
    ll = min(left, key=lambda i: (ch[i], i))
    lr = min(right, key=lambda i: (ch[i], i))
    lowest_centred = ch[centred[0]] if centred else np.inf
    if horizontal[ll] and horizontal[lr] and max(ch[ll], ch[lr]) < min(mid, lowest_centred):
        return ll, lr
    return None


def _sewn_on(panels: list, sides: tuple[int, int], centred: list[int]) -> bool:
    """Whether both side loops lie on pattern panels that hold no centred loop (neckline,
    hem): pieces sewn onto the body, sleeves, whose openings are cuffs wherever they hang.
    False without the panels (no ``F2``) or without a centred loop."""
    if not panels or not centred:
        return False
    body = frozenset().union(*(panels[i] for i in centred))
    return all(panels[i] and not panels[i] & body for i in sides)


def _sleeve_kind(
    band: tuple[np.ndarray, np.ndarray],
    inner: float,
    Hc: np.ndarray,
    S: np.ndarray,
    used: np.ndarray,
    s0: float,
    H: float,
) -> str:
    """``cuff`` or ``armhole`` for the two sleeve loops (rule 4).

    ``band``: the heights of the two loops' vertices; ``inner``: the sum of their inner
    edges' distances from the centre line ``s0``.
    """
    hl, hr = band
    lo = min(hl.min(), hr.min())
    band_h = max(np.ptp(hl), np.ptp(hr), model_tol.OPENING_BAND_REL * H)
    sel = used[(Hc[used] < lo) & (Hc[used] >= lo - band_h)]
    d = S[sel] - s0
    half_l = max(float(d.max()), 0.0) if d.size else 0.0
    half_r = max(float(-d.min()), 0.0) if d.size else 0.0
    return "cuff" if inner > half_l + half_r else "armhole"


def _centred_names(
    centred: list[int],
    horizontal: np.ndarray,
    ch: np.ndarray,
    sleeve_h: float | None,
    *,
    has_legs: bool,
    lengths: np.ndarray,
) -> dict[int, str]:
    """Names of the centred loops (rule 5); ``sleeve_h`` None when the garment is no top."""
    names: dict[int, str] = {}
    flat = [i for i in centred if horizontal[i]]
    if sleeve_h is not None and has_legs:
        if centred:
            names[centred[-1]] = "neckline"
    elif sleeve_h is not None:
        if len(centred) >= 2:
            names[centred[-1]] = "neckline"
            if flat and flat[0] != centred[-1]:
                names[flat[0]] = "hem"
        elif centred:
            i = centred[0]
            names[i] = "hem" if horizontal[i] and ch[i] < sleeve_h else "neckline"
    elif has_legs:
        if flat:
            names[flat[-1]] = "waist"
    elif _lone_limb(centred, flat, ch, lengths):
        names[flat[-1]], names[flat[0]] = "top", "cuff"
    elif flat:
        names[flat[0]] = "hem"
        if len(flat) >= 2:
            names[flat[-1]] = "waist"
    return names


def _lone_limb(centred: list[int], flat: list[int], ch: np.ndarray, lengths: np.ndarray) -> bool:
    """A lone tube that is a sleeve (or a trouser leg), not a skirt: two horizontal loops
    only, as far apart as the longer one is long at least (the lantern: 48 apart, 28 around;
    a skirt's hem is longer than the skirt: the cone skirt 57 and 188)."""
    if len(centred) != 2 or len(flat) != 2:
        return False
    lo, hi = flat
    return float(ch[hi] - ch[lo]) >= model_tol.OPENING_LIMB_LENGTH * float(
        max(lengths[lo], lengths[hi])
    )
