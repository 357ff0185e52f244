"""The unit of a DXF pattern (header, ``Units:`` text, piece sizes) and its
reconciliation with a drape's ``vt`` unit.
"""

from __future__ import annotations

import re
from dataclasses import replace
from typing import Any

import numpy as np

from ptailor import tolerances as tol
from ptailor.formats.dxf.astm import CM_PER_UNIT, INSUNITS
from ptailor.model.pieces import PatternFile, Piece


def file_units(
    override: str | None,
    text: str,
    insunits: Any,
    pieces: tuple[Piece, ...],
    measurement: Any = None,
) -> tuple[str, str]:
    """The coordinates' unit and where it came from.

    In order: the caller's override; ``Units: ENGLISH`` (inches); ``$INSUNITS`` in the
    header (mm, cm or in; an inch code under ``Units: METRIC`` is ignored); then, for
    ``METRIC``, ``$MEASUREMENT = 1`` or nothing said, millimetres, as AAMA/ASTM exports
    write metric patterns, unless the pieces are of a garment's size only in centimetres
    (:func:`ptailor.model.size.size_problem`: a METRIC file in cm whose largest piece
    reads 7.3 cm in mm is in cm). A file that says nothing is in mm when its largest piece
    exceeds ``DXF_MM_ABOVE`` units, else cm. A drape, when there is one, has the last word
    (:func:`ptailor.formats.garment._load_dxf_pair`).
    """
    if override is not None:
        return override, f"{override} given by the caller"
    word = text.strip().upper()
    quoted = f"'Units: {text.strip()}' in the file"
    ok = (
        isinstance(insunits, int | float)
        and np.isfinite(insunits)
        and abs(insunits) < tol.DXF_HEADER_CODE_MAX
    )
    code = INSUNITS.get(int(insunits)) if ok else None
    if word == "ENGLISH":
        return "in", quoted
    if code is not None and (word != "METRIC" or code != "in"):
        src = f"{quoted}, " if word else ""
        return code, f"{src}$INSUNITS = {int(insunits)} ({code}) in the header"
    largest = max((float(p.extent.max()) for p in pieces), default=0.0)
    if word == "METRIC":
        src = quoted
    elif word:
        src = f"unknown {quoted}"
    elif isinstance(measurement, int | float) and measurement == 1:
        src = "$MEASUREMENT = 1 (metric) in the header"
    else:  # nothing said: pieces are 5-200 cm, 50-2000 mm
        unit = "mm" if largest > tol.DXF_MM_ABOVE else "cm"
        return (
            unit,
            f"no units in the file; {unit} judged from the piece sizes (largest {largest:.4g})",
        )
    if pieces and size_in(pieces, "cm") is None and size_in(pieces, "mm") is not None:
        return "cm", (
            f"{src}; cm, as the pieces are of garment size only in cm (largest piece "
            f"{largest:.4g} units)"
        )
    return "mm", f"{src}; mm, as AAMA/ASTM metric files are written (largest piece {largest:.4g})"


def size_in(pieces: tuple[Piece, ...], unit: str) -> str | None:
    """What is not of a garment's size about the pieces read in ``unit``, or None
    (:func:`ptailor.model.size.size_problem`; each piece measured along its principal
    axes)."""
    from ptailor.model.size import GarmentSize, principal_extents, size_problem

    ext = np.array(
        [principal_extents(p.outline) for p in pieces if len(p.outline) >= 3], dtype=np.float64
    ).reshape(-1, 2)
    return size_problem(GarmentSize(extent=float("nan"), pieces=ext * CM_PER_UNIT[unit]))


#: see :data:`ptailor.tolerances.DXF_VT_UNIT_SLACK`
VT_UNIT_SLACK = tol.DXF_VT_UNIT_SLACK
_VT_HEADER = re.compile(r"\bvt:\s*([0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*(mm|cm|m|in)\s+per unit")


def reconcile_units(
    pattern: PatternFile,
    *,
    v: np.ndarray,
    fv: np.ndarray,
    vt: np.ndarray,
    fvt: np.ndarray,
    header: tuple[str, ...] = (),
    drape_cm: float = 1.0,
    fixed: bool = False,
) -> tuple[PatternFile, str, str]:
    """The units of a DXF and of its drape's ``vt``, each decided on its own.

    A DXF and the ``vt`` that triangulates its pieces need not share a unit (ptailor writes
    the DXF in mm and the ``vt`` in the garment's unit, CLO 3D both in mm). A ``METRIC`` DXF
    (unless ``fixed``: the caller gave its unit, or ``$INSUNITS`` did) is in mm or cm,
    one that names no unit in mm, cm or in, whichever makes its pieces (times their
    quantity, twice for a fold piece) the drape's area. The ``vt`` unit comes
    from a ptailor header (``vt: 1 cm per unit``), else from the drape's area: the DXF's
    unit when the ``vt`` is within ``VT_UNIT_SLACK`` of that size, else the nearest of mm,
    cm, m and in, else the DXF's.

    Parameters
    ----------
    pattern : PatternFile
    v : (n, 3) float array
        The drape, in its file unit.
    fv : (m, 3) int array
    vt : (k, 2) float array
    fvt : (m, 3) int array
    header : tuple of str
        The drape OBJ's leading comments.
    drape_cm : float
        Centimetres per drape unit.
    fixed : bool
        The DXF's unit was given: keep it.

    Returns
    -------
    pattern : PatternFile
        With ``units`` and ``units_note`` decided.
    vt_unit : str
        For :func:`ptailor.formats.garment.load_garment`'s ``pattern_units`` (``cm``,
        ``0.1cm``, ...).
    note : str
        Where the ``vt`` unit came from.
    """
    from ptailor.geometry.triangles import triangle_areas

    a3 = float(triangle_areas(np.asarray(v, dtype=float) * drape_cm, fv).sum())  # cm^2
    if not fixed:
        pattern = _dxf_unit_from_drape(pattern, drape_area=a3)
    vt_unit, note = _vt_unit(pattern, vt=vt, fvt=fvt, header=header, drape_area=a3)
    return pattern, vt_unit, note


def _dxf_unit_from_drape(pattern: PatternFile, *, drape_area: float) -> PatternFile:
    """The DXF's unit judged from the drape's area, when the file leaves it open.

    Only a ``METRIC`` file (mm or cm) or one naming no unit (mm, cm or in) whose header did
    not give ``$INSUNITS``: the unit that makes its pieces (times their quantity, twice for a
    fold piece) ``drape_area`` square centimetres. Any other file comes back as it is.
    """
    word = pattern.units_text.strip().upper()
    said = "$INSUNITS" in pattern.units_note  # the header named the unit
    choices = ("mm", "cm") if word == "METRIC" else ("mm", "cm", "in") if not word else ()
    if said or not choices:
        return pattern
    a3 = drape_area
    ap = sum(
        p.area * max(int(p.quantity), 1) * (2.0 if p.mirror is not None else 1.0)
        for p in pattern.pieces
    )
    ratio = float(np.sqrt(ap / a3)) if ap > 0 and a3 > 0 else 10.0  # file units per cm
    unit = min(choices, key=lambda u: abs(np.log(ratio * CM_PER_UNIT[u])))
    src = "'Units: METRIC' in the file" if word else "no units in the file"
    note = (
        f"{src}; {unit} judged from the drape (the pieces are {ratio:.3g} file units "
        "per cm of drape)"
    )
    kept = tuple(w for w in pattern.warnings if not w.startswith("the largest piece is"))
    return replace(pattern, units=unit, units_note=note, warnings=kept)


def _vt_unit(
    pattern: PatternFile,
    *,
    vt: np.ndarray,
    fvt: np.ndarray,
    header: tuple[str, ...],
    drape_area: float,
) -> tuple[str, str]:
    """The unit of the drape's ``vt`` and where it came from.

    A ptailor header (``vt: 1 cm per unit``) says it; else the ``vt``'s area against
    ``drape_area`` (cm^2) picks the DXF's unit when within ``VT_UNIT_SLACK``, else the
    nearest of mm, cm, m and in, else the DXF's unit all the same.
    """
    from ptailor.geometry.triangles import signed_areas_2d

    for line in header:  # ptailor's own garment.obj says its vt unit
        m = _VT_HEADER.search(line)
        if m:
            return (
                f"{m.group(1)}{m.group(2)}",
                f"vt: {m.group(1)} {m.group(2)} per unit (the drape's header)",
            )
    a3 = drape_area
    a2 = float(np.abs(signed_areas_2d(np.asarray(vt, dtype=float), fvt)).sum())
    if not (a2 > 0 and a3 > 0 and np.isfinite(a2) and np.isfinite(a3)):
        return pattern.units, f"vt in the DXF's unit ({pattern.units})"
    cm_per_vt = float(np.sqrt(a3 / a2))
    off = {u: abs(np.log(cm_per_vt / CM_PER_UNIT_ALL[u])) for u in CM_PER_UNIT_ALL}
    slack = np.log(VT_UNIT_SLACK)
    why = f"judged from the drape: {cm_per_vt:.4g} cm of drape per vt unit"
    if off.get(pattern.units, np.inf) <= slack:
        return pattern.units, f"vt in {pattern.units}, the DXF's unit ({why})"
    best = min(off, key=lambda u: off[u])
    if off[best] <= slack:
        return best, f"vt in {best}, unlike the DXF ({pattern.units}) ({why})"
    return pattern.units, f"vt taken in the DXF's unit ({pattern.units}); {why}"


#: centimetres per unit, for the ``vt`` of a drape (metres too)
CM_PER_UNIT_ALL: dict[str, float] = {"mm": 0.1, "cm": 1.0, "in": 2.54, "m": 100.0}
