"""A garment's points of measure, named from its structure.

Which measures a garment has follows from its openings and panel roles
(:func:`ptailor.model.structure.structure`): a neckline and two sleeve openings make a top, legs
make trousers, a waist and a hem a skirt, a bodice and skirt tier a dress. A measure whose
landmark the garment lacks is absent, never guessed. Definitions: :mod:`ptailor.measures.table`.
"""

from __future__ import annotations

from ptailor.measures import landmarks as lm
from ptailor.measures.lines import MaterialLine, line_length
from ptailor.measures.measure import Measure
from ptailor.measures.table import (
    BICEP_BELOW_UNDERARM_CM,
    CHEST_BELOW_ARMHOLE_CM,
    HIP_BELOW_WAIST_CM,
    MEASURES,
    THIGH_BELOW_CROTCH_CM,
)
from ptailor.model.garment import Garment
from ptailor.model.units import factor


def _line_measure(g: Garment, name: str, line: MaterialLine | None, **where) -> list[Measure]:
    if line is None or len(line) == 0:
        return []
    return [
        Measure(
            name,
            MEASURES[name].kind,
            line_length(line, g.V3, g.F3),
            line_length(line, g.V2, g.F2),
            line,
            **where,
        )
    ]


def _girth_at(g: Garment, ctx: lm.Context, name: str, h: float, faces) -> list[Measure]:
    line = lm.horizontal_girth(g, ctx, h, faces)
    return _line_measure(g, name, line, height=float(h))


def _top(g: Garment, ctx: lm.Context, cm: float) -> list[Measure]:
    out: list[Measure] = []
    out += _line_measure(g, "neck", ctx.opening_line("neckline"))
    under = lm.underarm_height(g, ctx)
    if under is not None:
        out += _girth_at(g, ctx, "chest", under - CHEST_BELOW_ARMHOLE_CM * cm, ctx.torso)
    if "hem" in ctx.openings:
        out += _line_measure(g, "hem", ctx.opening_line("hem"))
    hps = lm.high_point_shoulder(g, ctx)
    if hps is not None and "hem" in ctx.openings:
        out += lm.body_length(g, ctx, hps)
        out += lm.neck_drop(g, ctx, hps)
    return out


def _sleeves(g: Garment, ctx: lm.Context, cm: float) -> list[Measure]:
    out: list[Measure] = []
    for side in ("left", "right"):
        limb = lm.sleeve(g, ctx, side)
        if limb is None:
            if f"armhole_{side}" in ctx.openings:
                out += _line_measure(g, f"armhole_{side}", ctx.opening_line(f"armhole_{side}"))
            continue
        out += _limb(g, limb, f"_{side}", cm)
    return out


def _limb(g: Garment, limb: lm.Limb, suffix: str, cm: float) -> list[Measure]:
    out = _line_measure(g, "sleeve_length" + suffix, lm.overarm(g, limb))
    at = limb.under + BICEP_BELOW_UNDERARM_CM * cm
    if at < limb.reach:
        point = limb.origin + at * limb.axis
        out += _line_measure(
            g, "bicep" + suffix, lm.limb_girth(g, limb, point), point=point, axis=limb.axis
        )
    out += _line_measure(g, "cuff" + suffix, limb.cuff)
    return out


def _lower(g: Garment, ctx: lm.Context, cm: float, legs: bool) -> list[Measure]:
    """Waist, hip, hem and length of a skirt, trousers or a dress's skirt."""
    out: list[Measure] = []
    waist = lm.waist(g, ctx)
    if waist is not None:
        line, h_waist = waist
        seamed = ctx.tiered or ctx.waist_seamed
        out += _line_measure(g, "waist", line, height=h_waist if seamed else None)
        floor = lm.crotch_height(g, ctx) if legs else lm.hem_top(g, ctx)
        h_hip = h_waist - HIP_BELOW_WAIST_CM * cm
        if floor is not None and h_hip > floor:
            out += _girth_at(g, ctx, "hip", h_hip, ctx.lower)
    if legs:
        return out + _legs(g, ctx, cm)
    if not ctx.tiered and "hem" in ctx.openings:
        out += _line_measure(g, "hem", ctx.opening_line("hem"))
    if waist is not None:
        out += _line_measure(g, "skirt_length", lm.centre_front_length(g, ctx, waist[1]))
    return out


def _legs(g: Garment, ctx: lm.Context, cm: float) -> list[Measure]:
    out: list[Measure] = []
    crotch = lm.crotch_height(g, ctx)
    for side in ("left", "right"):
        faces = ctx.lower & (ctx.face_side == side)
        if crotch is not None:
            out += _girth_at(g, ctx, f"thigh_{side}", crotch - THIGH_BELOW_CROTCH_CM * cm, faces)
        out += lm.inseam(g, ctx, side, f"inseam_{side}")
        out += _line_measure(g, f"leg_opening_{side}", ctx.opening_line(f"leg_{side}"))
    return out


def garment_measures(g: Garment) -> list[Measure]:
    """The garment's points of measure, in its units.

    Parameters
    ----------
    g : Garment

    Returns
    -------
    list of Measure
        In :data:`~ptailor.measures.table.MEASURES` order; a measure the garment lacks is
        absent.
    """
    cm = factor("cm", g.units)
    ctx = lm.context(g)
    out: list[Measure] = []
    if ctx.lone_limb is not None:
        out += _limb(g, ctx.lone_limb, "", cm)
    else:
        if ctx.is_top:
            out += _top(g, ctx, cm)
            out += _sleeves(g, ctx, cm)
        if ctx.has_legs or ctx.tiered or not ctx.is_top:
            out += _lower(g, ctx, cm, ctx.has_legs)
    order = {n: i for i, n in enumerate(MEASURES)}
    seen: set[str] = set()
    uniq = [m for m in out if not (m.name in seen or seen.add(m.name))]
    return sorted(uniq, key=lambda m: order[m.name])
