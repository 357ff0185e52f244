"""Load a garment from an OBJ (v = drape, vt = pattern), or a pattern file plus a drape file."""

from __future__ import annotations

import re
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ptailor import tolerances as tol
from ptailor.errors import PtailorError
from ptailor.formats import is_pattern_file, pattern_reader_for, reader_for
from ptailor.model.frame import DEFAULT_FRAME, Frame, frame_from_header
from ptailor.model.garment import Garment
from ptailor.model.pieces import PatternFile
from ptailor.model.repair import check_units, intake, unit_ratios
from ptailor.model.size import check_size, garment_size, size_warning
from ptailor.model.unit_ratio import pattern_scale_estimate
from ptailor.model.units import CM_PER, factor
from ptailor.model.validate import check_garment

_UNIT_RE = re.compile(r"^\s*([0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)?\s*(mm|cm|m|in)\s*$")


def parse_units(text: str, *, what: str) -> float:
    """Centimetres per file unit from ``cm``, ``in``, ... or a scaled unit like ``0.3333cm``.

    Raises
    ------
    PtailorError
        For anything else (``auto`` is handled by the caller).
    """
    m = _UNIT_RE.match(text)
    if not m:
        known = ", ".join(CM_PER)
        raise PtailorError(f"{what}: unknown unit {text!r} (use {known}, auto, or e.g. 0.5cm)")
    cm = float(m.group(1) or 1.0) * CM_PER[m.group(2)]
    lo, hi = tol.UNIT_CM_RANGE
    if not (np.isfinite(cm) and lo <= cm <= hi):
        raise PtailorError(
            f"{what}: {text!r} is {cm:g} cm per unit, outside the sane range "
            f"[{lo:g}, {hi:g}] cm (1 micrometre to 1 kilometre)"
        )
    return cm


def parse_length(text: str, *, to: str, what: str) -> float:
    """A length such as ``1.5``, ``1cm`` or ``0.375in`` in unit ``to`` (a bare number is in ``to``).

    Raises
    ------
    PtailorError
        Anything else, or a negative or non-finite length.
    """
    try:
        value = float(text)
    except ValueError:
        m = _UNIT_RE.match(text)
        if not m or m.group(1) is None:
            msg = f"{what}: not a length: {text!r} (e.g. 1, 1cm, 10mm, 0.375in)"
            raise PtailorError(msg) from None
        value = float(m.group(1)) * CM_PER[m.group(2)] / CM_PER[to]
    if not np.isfinite(value) or value < 0:
        raise PtailorError(f"{what}: must be a length >= 0, not {text!r}")
    limit = tol.LENGTH_MAX_CM / CM_PER[to] if to in CM_PER else None
    if limit is not None and value > limit:
        raise PtailorError(
            f"{what}: {text!r} is longer than {tol.LENGTH_MAX_CM:g} cm, the longest length "
            "ptailor takes"
        )
    return value


@dataclass(frozen=True)
class LoadedGarment:
    """A garment in computation units, and how to write it back in file units.

    Attributes
    ----------
    garment : Garment
        Drape and pattern in ``garment.units``.
    drape_scale, pattern_scale : float
        File units times this gives computation units.
    pattern_units_estimated : bool
        True when ``pattern_units='auto'`` estimated ``pattern_scale`` from the drape.
    inputs : dict
        Role (``garment``, ``drape``) to path.
    header : tuple of str
        The pattern file's leading comments.
    pattern : PatternFile or None
        The CAD pattern (DXF pieces, in its own units) when the pattern came from one.
    intake : dict
        What the intake repaired (:func:`load_garment`).
    vertex_map : (n3,) int array or None
        The drape file's vertex of each drape vertex (the weld's,
        :attr:`ptailor.model.repair.IntakeResult.vertex_map`): a drape edited elsewhere in
        the file's numbering is welded as the garment was.
    """

    garment: Garment
    drape_scale: float
    pattern_scale: float
    pattern_units_estimated: bool
    inputs: dict[str, str]
    header: tuple[str, ...]
    pattern: PatternFile | None = None
    intake: dict = field(default_factory=dict)
    vertex_map: np.ndarray | None = None


def parse_weld(text: str | float, *, units: str) -> str | float:
    """``--weld``: ``auto``, ``off``, or a distance (a length such as ``0.1mm``; a bare
    number is in ``units``) returned in ``units``.

    Raises
    ------
    PtailorError
        Anything else (exit 2).
    """
    if not isinstance(text, str):
        return float(text)
    t = text.strip().lower()
    if t in ("auto", "off"):
        return t
    try:
        return parse_length(t, to=units, what="--weld")
    except PtailorError:
        raise PtailorError(
            f"--weld: expected auto, off or a distance such as 0.1mm, not {text!r}"
        ) from None


def load_garment(
    path: str | Path,
    *,
    drape: str | Path | None = None,
    units: str = "cm",
    pattern_units: str | None = "cm",
    drape_units: str | None = "cm",
    size: str | None = None,
    dxf_units: str | None = None,
    weld: str | float = "auto",
    frame: Frame | None = None,
) -> LoadedGarment:
    """Read, repair and check a garment.

    Parameters
    ----------
    path : str or Path
        OBJ with ``v`` = drape and ``vt`` = pattern; or, with ``drape``, a pattern-only OBJ
        (pattern in ``vt``, or in a planar ``v`` when it has no ``vt``).
    drape : str or Path, optional
        OBJ whose ``v`` is the drape, with the same faces as ``path``.
    units : str
        Computation (and report) unit.
    pattern_units, drape_units : str or None
        File units: ``mm``, ``cm``, ``m``, ``in``, a scaled unit such as ``0.3333cm``, or
        for the pattern ``auto`` (normalised atlas: scale estimated from the drape's area).
        None: not given, read as ``cm`` but only if the garment then has a human size
        (:func:`ptailor.model.size.size_problem`: the drape when ``drape_units`` is None,
        the pieces when ``pattern_units`` is None, or ``auto`` with the drape's unit not
        given); else :class:`UnitMismatchError` naming the options and the units under which
        it would be of that size.
    weld : str or float
        ``auto``, ``off`` or a distance in ``units`` (:func:`parse_weld`,
        :func:`ptailor.model.repair.intake`).
    frame : Frame, optional
        The wearer's axes in the drape's coordinates (the command line's ``--up`` and
        ``--front``, else the recipe's): the garment carries it. None: the frame the
        file's comment lines state (``# ptailor frame: up z, front -y``, as ptailor writes
        a garment in any frame but the default), else
        :data:`~ptailor.model.frame.DEFAULT_FRAME`.

    Returns
    -------
    LoadedGarment
        ``intake`` records the repairs (weld, duplicate and zero-area faces, non-manifold
        edges), the pattern/drape length ratios and where each unit came from.

    Raises
    ------
    PtailorError
        Naming the file and the problem; a pattern/drape length ratio outside [0.5, 2]
        (a unit mistake) names the unit options and the ratio, as does a garment of no human
        size read in units not given.
    """
    # numeric warnings of the repairs and checks are not printed: every value they concern
    # is checked (check_garment), and a failure is one line naming the file
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore", RuntimeWarning)
        loaded = _load_garment(
            path,
            drape=drape,
            units=units,
            pattern_units=pattern_units,
            drape_units=drape_units,
            size=size,
            dxf_units=dxf_units,
            weld=weld,
        )
    if frame is None:
        try:
            frame = frame_from_header(loaded.header) or DEFAULT_FRAME
        except ValueError as exc:
            raise PtailorError(f"its frame comment: {exc}", path=path) from None
    return replace(loaded, garment=loaded.garment.with_frame(frame))


def _load_garment(
    path: str | Path,
    *,
    drape: str | Path | None,
    units: str,
    pattern_units: str,
    drape_units: str,
    size: str | None,
    dxf_units: str | None,
    weld: str | float,
) -> LoadedGarment:
    weld = parse_weld(weld, units=units)
    if is_pattern_file(path):
        return _load_pattern_pair(
            str(path), drape, units=units, drape_units=drape_units, size=size, dxf_units=dxf_units
        )
    mesh, (V3, F3, V2, F2), inputs, err_path = _read_meshes(path, drape)
    spath = str(path)
    drape_given, pattern_given = drape_units is not None, pattern_units is not None
    drape_units, pattern_units = drape_units or "cm", pattern_units or "cm"
    d_cm = parse_units(drape_units, what="--drape-units")
    to_units = 1.0 / CM_PER[units] if units in CM_PER else factor("cm", units)
    drape_scale = d_cm * to_units
    V3 = V3 * drape_scale
    fixed = intake(V3, F3, V2, F2, weld=weld, path=err_path)
    V3, F3, V2, F2 = fixed.V3, fixed.F3, fixed.V2, fixed.F2
    estimated = pattern_units == "auto"
    if estimated:
        pattern_scale = _estimated_pattern_scale(V3, F3, V2, F2, path=spath)
    else:
        pattern_scale = parse_units(pattern_units, what="--pattern-units") * to_units
    ratio, per_panel = unit_ratios(V3, F3, V2 * pattern_scale, F2, lengths3=fixed.lengths3)
    if not estimated:
        check_units(ratio, path=err_path, pattern_units=pattern_units, drape_units=drape_units)
    record = {
        **fixed.record,
        "faces_read": len(mesh.fv),
        "warnings": list(fixed.warnings),
        "units": _units_record(
            units,
            pattern=pattern_units if pattern_given else None,
            drape=drape_units if drape_given else None,
            ratio=ratio,
            per_panel=per_panel,
        ),
    }
    g = Garment(
        V3=np.ascontiguousarray(V3, dtype=np.float64),
        F3=np.ascontiguousarray(F3, dtype=np.int64),
        V2=np.ascontiguousarray(V2 * pattern_scale, dtype=np.float64),
        F2=np.ascontiguousarray(F2, dtype=np.int64),
        face_group=mesh.face_group[fixed.faces],
        group_names=mesh.group_names,
        units=units,
    )
    check_garment(g, path=err_path)
    record["warnings"] += _given_units_warning(
        g,
        cm_per_unit=1.0 / to_units,
        drape=drape_units if drape_given else None,
        pattern=pattern_units if pattern_given else None,
    )
    _check_default_units(
        g,
        cm_per_unit=1.0 / to_units,
        drape_given=drape_given,
        pattern_given=pattern_given,
        estimated=estimated,
        path=err_path,
    )
    return LoadedGarment(
        garment=g,
        drape_scale=drape_scale,
        pattern_scale=pattern_scale,
        pattern_units_estimated=estimated,
        inputs=inputs,
        header=mesh.header,
        intake=record,
        vertex_map=fixed.vertex_map,
    )


def _units_record(
    units: str,
    *,
    pattern: str | None,
    drape: str | None,
    ratio: float,
    per_panel: np.ndarray,
) -> dict:
    """The intake's ``units``: the computation unit, the pattern's and the drape's file
    units (None: not given, read as ``cm``) with where each came from, and the pattern/drape
    length ratios (``per_panel`` (k,) float array; NaN written as None)."""
    if pattern == "auto":
        pattern_source = "estimate"
    elif pattern is not None:
        pattern_source = "command line"
    else:
        pattern_source = "default, size checked"
    return {
        "computation": units,
        "pattern": pattern or "cm",
        "pattern_source": pattern_source,
        "drape": drape or "cm",
        "drape_source": "command line" if drape is not None else "default, size checked",
        "pattern_drape_ratio": round(ratio, 6) if np.isfinite(ratio) else None,
        "pattern_drape_ratio_per_panel": [
            round(float(x), 6) if np.isfinite(x) else None for x in per_panel
        ],
    }


def _check_default_units(
    g: Garment,
    *,
    cm_per_unit: float,
    drape_given: bool,
    pattern_given: bool,
    estimated: bool,
    path: str,
) -> None:
    """A garment read in units not given must be of a human size: the drape when its unit
    was not given, the pieces when theirs was not (or ``auto`` stood on a drape unit not
    given). ``cm_per_unit``: centimetres per unit of ``g``.

    Raises
    ------
    UnitMismatchError
        From :func:`ptailor.model.size.check_size`, naming the options not given.
    """
    check_pieces = not pattern_given or (estimated and not drape_given)
    if drape_given and not check_pieces:
        return
    measured = garment_size(
        None if drape_given else g.V3,
        g.F3,
        g.V2 if check_pieces else g.V2[:0],
        g.F2 if check_pieces else g.F2[:0],
    )
    check_size(
        measured.scaled(cm_per_unit),
        path=path,
        options=_not_given(drape_given, pattern_given),
    )


def _given_units_warning(
    g: Garment, *, cm_per_unit: float, drape: str | None, pattern: str | None
) -> list[str]:
    """:func:`ptailor.model.size.size_warning` on what was read in units the user gave (the
    drape with ``--drape-units``, the pieces with ``--pattern-units`` other than ``auto``):
    a cm drape read as mm, a 1/300 m file read as cm. A list of at most one warning."""
    pieces = pattern is not None and pattern != "auto"
    if drape is None and not pieces:
        return []
    measured = garment_size(
        g.V3 if drape is not None else None,
        g.F3,
        g.V2 if pieces else g.V2[:0],
        g.F2 if pieces else g.F2[:0],
    )
    given = " and ".join(
        f"{name} {value}"
        for name, value in (
            ("--drape-units", drape),
            ("--pattern-units", pattern if pieces else None),
        )
        if value is not None
    )
    found = size_warning(measured.scaled(cm_per_unit), options=given)
    return [] if found is None else [found]


def _read_meshes(path: str | Path, drape: str | Path | None):
    """Read the garment OBJ (and its drape OBJ): ``(mesh, (V3, F3, V2, F2), inputs,
    err_path)``, in file units; ``err_path`` is the file a bad drape is blamed on."""
    spath = str(path)
    mesh = reader_for(path)(path)
    if drape is None:
        if mesh.fvt is None or len(mesh.vt) == 0:
            raise PtailorError(
                "faces carry no texture coordinates (vt): no pattern to adjust "
                "(give the drape with --drape if this file holds only the pattern)",
                path=spath,
            )
        return mesh, (mesh.v, mesh.fv, mesh.vt, mesh.fvt), {"garment": spath}, spath
    dpath = str(drape)
    dmesh = reader_for(drape)(drape)
    if mesh.fvt is not None and len(mesh.vt):
        V2, F2 = mesh.vt, mesh.fvt
    else:
        z = mesh.v[:, 2]
        if np.ptp(z) > tol.ROUNDING_REL * max(float(np.ptp(mesh.v[:, :2])), tol.TINY):
            raise PtailorError("no 2D pattern: no vt and the v are not planar", path=spath)
        V2, F2 = mesh.v[:, :2], mesh.fv
    if len(dmesh.fv) != len(F2):
        raise PtailorError(
            f"pattern and drape have different faces ({len(F2)} vs {len(dmesh.fv)} triangles"
            f" in {spath})",
            path=dpath,
        )
    return mesh, (dmesh.v, dmesh.fv, V2, F2), {"garment": spath, "drape": dpath}, dpath


def _not_given(drape_given: bool, pattern_given: bool) -> str:
    """The unit options a size check stands in for, in words."""
    names = [n for n, given in (("--drape-units", drape_given), ("--pattern-units", pattern_given))
             if not given]  # fmt: skip
    return " and ".join(names) or "--drape-units"


def _estimated_pattern_scale(V3, F3, V2, F2, *, path: str) -> float:
    """``--pattern-units auto``: :func:`ptailor.model.unit_ratio.pattern_scale_estimate`."""
    if not (np.all(np.isfinite(V2)) and np.all(np.isfinite(V3))):
        return 1.0  # check_garment reports the NaNs
    scale = pattern_scale_estimate(V3, F3, V2, F2)
    if not scale > 0:
        raise PtailorError("pattern has zero area", path=path)
    return scale


def _load_pattern_pair(
    path: str,
    drape: str | Path | None,
    *,
    units: str,
    drape_units: str | None,
    size: str | None,
    dxf_units: str | None,
) -> LoadedGarment:
    """A CAD pattern's pieces plus the drape OBJ whose ``vt`` triangulates them."""
    from ptailor.formats.dxf import reconcile_units
    from ptailor.model.repair import UnitMismatchError

    if drape is None:
        raise PtailorError(
            "a DXF pattern needs its drape: --drape DRAPE.obj (v = drape, vt = the "
            "triangulated pattern in the DXF's layout and units)",
            path=path,
        )
    pattern = pattern_reader_for(path)(path, size=size, units=dxf_units)
    dpath = str(drape)
    dmesh = reader_for(drape)(drape)
    if dmesh.fvt is None or len(dmesh.vt) == 0:
        raise PtailorError(
            "the drape has no texture coordinates (vt): nothing ties it to the DXF's pieces",
            path=dpath,
        )
    # the DXF's unit and the vt's, each on its own (ptailor writes mm and cm)
    pattern, vt_unit, vt_note = reconcile_units(
        pattern,
        v=dmesh.v,
        fv=dmesh.fv,
        vt=dmesh.vt,
        fvt=dmesh.fvt,
        header=tuple(getattr(dmesh, "header", ()) or ()),
        drape_cm=parse_units(drape_units or "cm", what="--drape-units"),
        fixed=dxf_units is not None,
    )
    pattern = replace(pattern, units_note=f"{pattern.units_note}; {vt_note}")
    try:
        loaded = load_garment(drape, units=units, pattern_units=vt_unit, drape_units=drape_units)
    except UnitMismatchError as exc:
        msg = exc.message.replace("check --pattern-units", "check --dxf-units")
        raise UnitMismatchError(msg, path=exc.path) from None
    loaded = replace(loaded, inputs={"pattern": path, "drape": dpath}, pattern=pattern)
    return _with_unit_sources(loaded, dxf_units=dxf_units)


def _with_unit_sources(loaded: LoadedGarment, *, dxf_units: str | None) -> LoadedGarment:
    """The intake's ``units`` of a CAD pattern: where the pattern's unit and the drape's
    ``vt`` unit each came from (given, the file, or judged)."""
    pf = loaded.pattern
    dxf_note, _, vt_note = (pf.units_note if pf is not None else "").partition("; vt")
    source = "command line" if dxf_units is not None else "file"
    if dxf_units is None and "judged" in dxf_note:
        source = "estimate"
    units_rec = dict(loaded.intake.get("units", {}))
    units_rec["vt"] = units_rec.pop("pattern", None)
    units_rec["vt_source"] = "estimate" if "judged" in vt_note else "file"
    units_rec.update(pattern_source=source, pattern_note=dxf_note)
    if pf is not None:
        units_rec["pattern"] = pf.units
    return replace(loaded, intake={**loaded.intake, "units": units_rec})
