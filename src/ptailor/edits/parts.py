"""Regions by part of the body: ``region: {part: torso}``, from the garment's structure.

A part is every panel that goes around that part of the body, read off the panel layout
(:attr:`ptailor.model.structure.GarmentStructure.layout`: each panel's role, side and tier)
and the openings, never off the panels' names: a poncho's centre strips and side panels, a
princess-seamed bodice's six pieces and a tee's front and back are each one ``torso``.

========================  ==================================================================
part                      the panels
========================  ==================================================================
``torso``                 every body panel (role ``body``: a top's front and back, a
                          dress's bodice and skirt, a skirt's gores; not its sleeves, cuffs,
                          collar, waistband or straps)
``bodice``                the body panels above the waist: a two-tier garment's ``bodice``
                          tier, or every body panel of a one-tier top (one with a neckline
                          or armholes); none of them reaching a leg opening (a jumpsuit's)
``skirt``                 the body panels below the waist: a two-tier garment's ``skirt``
                          tier, or a skirt's (a garment with a waist and no neckline); none
                          of them reaching a leg opening
``sleeves``               the sleeve and cuff panels, both sides
``sleeve_left``,          those of one side (the wearer's)
``sleeve_right``
``legs``                  the body panels that reach a leg opening (``leg_left``,
                          ``leg_right``)
``leg_left``,             those that reach that side's leg opening
``leg_right``
``collar``, ``waistband``  the panels of that role
========================  ==================================================================

A garment without the part (a tank top's ``sleeves``) raises
:class:`~ptailor.errors.AbsentError`: a step with ``optional: true`` is then skipped.
"""

from __future__ import annotations

import numpy as np

from ptailor.errors import AbsentError
from ptailor.model.garment import Garment
from ptailor.model.structure import structure

#: The parts a region may name, and what each takes (the recipe schema's enum).
PARTS = {
    "torso": "every body panel (bodice and skirt; not sleeves, cuffs, collar, waistband, straps)",
    "bodice": "the body panels above the waist (a one-tier top's whole body), none reaching a leg",
    "skirt": "the body panels below the waist (a skirt's whole body), none reaching a leg",
    "sleeves": "the sleeve and cuff panels",
    "sleeve_left": "the sleeve and cuff panels on the wearer's left",
    "sleeve_right": "the sleeve and cuff panels on the wearer's right",
    "legs": "the body panels that reach a leg opening",
    "leg_left": "the body panels that reach the left leg opening",
    "leg_right": "the body panels that reach the right leg opening",
    "collar": "the collar's panels",
    "waistband": "the waistband's panels",
}

#: The roles of a limb's panels (the rest go around the trunk).
LIMB_ROLES = ("sleeve", "cuff")


def touching(garment: Garment, names: tuple[str, ...]) -> np.ndarray:
    """Panels (layout indices) with a drape vertex on one of the openings ``names``.

    Returns
    -------
    (n_p,) bool array
    """
    st = structure(garment)
    lab, n_p = st.panel_components
    on = np.zeros(len(garment.V3), dtype=bool)
    for o in st.layout.openings:  # a loop over a garment's few openings
        if o.name in names:
            on[o.loop] = True
    out = np.zeros(n_p, dtype=bool)
    out[lab[on[garment.F3].any(axis=1)]] = True
    return out


def part_panels(part: str, garment: Garment) -> np.ndarray:
    """The panels (layout indices, as ``structure(garment).panel_components``'s labels) of
    a part of the body (:data:`PARTS`).

    Parameters
    ----------
    part : str
        A key of :data:`PARTS`.
    garment : Garment

    Returns
    -------
    (k,) int array
        Ascending, non-empty.

    Raises
    ------
    AbsentError
        The garment has no panel of that part (or no naming rule recognised it), naming
        the parts it has.
    """
    ops = structure(garment).layout.openings
    if all(o.name.startswith("opening_") for o in ops):  # the naming rules' "recognised"
        raise AbsentError(
            f"no part {part}: no rule recognised this garment's openings (no neckline, hem,"
            " waist, cuff or leg); name its panels, region: {panels: [...]}"
        )
    sel = part_masks(garment)
    mask = sel.get(part)
    if mask is None or not mask.any():
        have = ", ".join(k for k, m in sel.items() if m.any()) or "none"
        raise AbsentError(f"no part {part} on this garment (it has: {have})")
    return np.flatnonzero(mask)


def part_masks(garment: Garment) -> dict[str, np.ndarray]:
    """Every part of :data:`PARTS` as a ``(n_p,)`` bool mask over the garment's panels."""
    lay = structure(garment).layout
    role, side, tier = (np.asarray(x, dtype=object) for x in (lay.role, lay.side, lay.tier))
    body = role == "body"
    limb = np.isin(role, LIMB_ROLES)
    names = {o.name for o in lay.openings}
    top = bool(names & {"neckline", "armhole_left", "armhole_right"})
    one_tier = not np.any(body & (tier != ""))
    legs = {s: touching(garment, (f"leg_{s}",)) & body for s in ("left", "right")}
    any_leg = legs["left"] | legs["right"]
    skirt = body & (tier == "skirt") | (body & one_tier & ("waist" in names) & (not top))
    return {
        "torso": body,
        "bodice": body & ((tier == "bodice") | (one_tier & top)) & ~any_leg,
        "skirt": skirt & ~any_leg,
        "sleeves": limb,
        "sleeve_left": limb & (side == "left"),
        "sleeve_right": limb & (side == "right"),
        "legs": any_leg,
        "leg_left": legs["left"],
        "leg_right": legs["right"],
        "collar": role == "collar",
        "waistband": role == "waistband",
    }


def part_faces(part: str, garment: Garment) -> np.ndarray:
    """The triangles of a part of the body (:func:`part_panels`), ascending ``(k,)``."""
    lab, _ = structure(garment).panel_components
    return np.flatnonzero(np.isin(lab, part_panels(part, garment)))


def mirror_part(part: str) -> str:
    """A part's mirror image across the body's centre (``sleeve_left`` and
    ``sleeve_right``; ``torso`` its own)."""
    for a, b in (("_left", "_right"), ("_right", "_left")):
        if part.endswith(a):
            return part[: -len(a)] + b
    return part
