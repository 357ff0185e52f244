"""The points of measure: names, kinds and definitions (ASTM D5585 / ISO 8559-1 style).

Every measure is a material line on the garment (:mod:`ptailor.measures.lines`); its ``drape``
value is the line's length in the drape, its ``pattern`` value the same line's length summed
over the pattern pieces it crosses. The definitions below are what ``docs/measures.md`` draws.
"""

from __future__ import annotations

from dataclasses import dataclass

#: how far below the armhole's lowest point the chest is taken (cm; ASTM D5585: 1 in)
CHEST_BELOW_ARMHOLE_CM = 2.5
#: how far below the underarm, along the sleeve, the bicep is taken (cm)
BICEP_BELOW_UNDERARM_CM = 2.5
#: how far below the waist the hip is taken (cm; ASTM D5585: 7 in)
HIP_BELOW_WAIST_CM = 18.0
#: how far below the crotch the thigh is taken (cm; ASTM D5585: 1 in)
THIGH_BELOW_CROTCH_CM = 2.5


@dataclass(frozen=True)
class MeasureDefinition:
    """One point of measure.

    Attributes
    ----------
    name : str
        The name a recipe uses (``chest``, ``sleeve_length_left``, ...).
    kind : str
        ``girth`` (around the body or a limb), ``length`` (down or along it) or ``depth``.
    garments : str
        Which garments have it, in words.
    definition : str
        Where the line runs.
    """

    name: str
    kind: str
    garments: str
    definition: str


_SIDED = ("left", "right")
#: the sided measures a lone sleeve has, unsuffixed
_LONE_LIMB = ("sleeve_length", "bicep", "cuff")

_TABLE: tuple[tuple[str, str, str, str, bool], ...] = (
    # name, kind, garments, definition, sided
    ("neck", "girth", "tops", "the neckline opening's length", False),
    (
        "chest",
        "girth",
        "tops",
        f"the torso panels' horizontal section {CHEST_BELOW_ARMHOLE_CM:g} cm below the armhole's "
        "lowest point (the lower of the two sides; where sleeves are sewn, the lowest point of "
        "the sleeve seam)",
        False,
    ),
    (
        "waist",
        "girth",
        "skirts, trousers, dresses",
        "the waist opening's length; on a dress, the horizontal section of the torso panels at "
        "the mean height of the seam between bodice and skirt",
        False,
    ),
    (
        "hip",
        "girth",
        "skirts, trousers, dresses",
        f"the horizontal section {HIP_BELOW_WAIST_CM:g} cm below the waist (absent where the "
        "hem or the crotch is higher)",
        False,
    ),
    ("hem", "girth", "tops, skirts, dresses", "the hem opening's length (the sweep)", False),
    (
        "body_length",
        "length",
        "tops, dresses",
        "from the high point shoulder straight down the front to the hem: the front panels' "
        "section by the plane through that point across the body (normal: the wearer's "
        "left), with the straight gap from the point to where that section enters the front "
        "(a neckline curving out past it); absent unless it reaches the hem. The high point "
        "shoulder is the highest point of the torso's neck edge on the wearer's left where "
        "front and back meet (the shoulder seam); the neck edge is the neckline on the torso "
        "panels, or the seam with a collar; on a strap dress, the bodice's top at the strap",
        False,
    ),
    (
        "neck_drop",
        "depth",
        "tops, dresses",
        "how far the neck edge's lowest point on the front lies below the high point shoulder, "
        "along the up axis (in the pattern: along the front panel's grain, the up axis carried "
        "into the pattern)",
        False,
    ),
    (
        "skirt_length",
        "length",
        "skirts, dresses",
        "from the waist down the centre front to the hem: the front half of the section by the "
        "plane through the centre line (normal: the wearer's left)",
        False,
    ),
    (
        "sleeve_length",
        "length",
        "tops with sleeves",
        "from the sleeve seam at the shoulder to the cuff along the top of the sleeve: the upper "
        "half of the sleeve's section by the plane through its axis (armhole seam centre to cuff "
        "centre) and the up axis",
        True,
    ),
    (
        "bicep",
        "girth",
        "tops with sleeves",
        f"the sleeve's section perpendicular to its axis, {BICEP_BELOW_UNDERARM_CM:g} cm along "
        "the axis past the underarm",
        True,
    ),
    ("cuff", "girth", "tops with sleeves", "the sleeve opening's length", True),
    ("armhole", "girth", "sleeveless tops and dresses", "the armhole opening's length", True),
    (
        "thigh",
        "girth",
        "trousers",
        f"the leg's horizontal section {THIGH_BELOW_CROTCH_CM:g} cm below the crotch (the lowest "
        "point where the left and right panels meet)",
        True,
    ),
    (
        "inseam",
        "length",
        "trousers",
        "the seam inside the leg, from the crotch to the leg opening (its drape length; in the "
        "pattern, the mean of its two sides)",
        True,
    ),
    ("leg_opening", "girth", "trousers", "the leg opening's length", True),
)


def _definitions() -> dict[str, MeasureDefinition]:
    out: dict[str, MeasureDefinition] = {}
    for name, kind, garments, text, sided in _TABLE:
        for suffix in _SIDED if sided else ("",):
            full = f"{name}_{suffix}" if suffix else name
            out[full] = MeasureDefinition(full, kind, garments, text)
        if name in _LONE_LIMB:  # a lone sleeve (no sides) has the unsuffixed one
            out[name] = MeasureDefinition(name, kind, "a lone sleeve", text)
    return out


#: every measure name a garment can have, with its definition
MEASURES: dict[str, MeasureDefinition] = _definitions()
#: the kinds of measure
KINDS = ("girth", "length", "depth")
