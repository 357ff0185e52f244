"""Panels and seams named from the drape's geometry.

A recipe written for a catalogue says ``sleeve_left`` or ``side_right``, not ``panel_3``. When
the file's groups do not name the panels, :func:`panel_layout` names them from where they sit
on the garment, in the wearer's frame the openings use (:class:`ptailor.model.frame.
Frame`: y up and z front by default; ``left = up x front`` is the wearer's left, +x),
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
- *strips*: narrow panels (length / width >= 3.5 for the rectangle with the area and outline
  length of the panel's pattern: a box mesh's stretched seam rows make a bodice look narrow in
  3D) whose long side runs along an opening: along the neckline ``collar``, along
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
  ``bodice_back_left_side``); panels that got the same qualifier are told apart again the
  same way along the other axis (``front_right_upper``, ``front_right_upper_side``); names
  still equal get ``_2``, ``_3``, ...
- A panel in the centre plane (reaching across it by float noise only) is centred.

Names, panels' and seams' alike, follow one scheme: ``[tier_]kind[_face][_side][_place]``
(``bodice_front_right``, ``sleeve_left_back``, ``bodice_yoke_front_left``,
``skirt_side_right_outer``): each word once, the side (``left``/``right``) the only word a
mirror swaps, place words last. A panel or seam and its mirror image are told apart from the
others by their shared place (the mean of the one's measures and the other's mirrored), and
get mirror names: naming the mirrored garment gives the mirror names. A seam between a panel
and one that continues it (above it, across the body) is a yoke seam, not the two panels'
names joined; ``tests/names/`` pins every name of the samples and shared garments.

Everything is vectorised over triangles; loops run over panels, openings and seams only.
"""

from ptailor.model.names.layout import PanelLayout, panel_layout
from ptailor.model.names.seam_names import seam_names

__all__ = ["PanelLayout", "panel_layout", "seam_names"]
