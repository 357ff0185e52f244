"""The options of one run: a frozen, typed record built once (by the CLI) and passed down.

Its constructor is where the options are checked, once, for every command and for a
manifest row's overrides (``dataclasses.replace`` runs it again): a bad value raises
:class:`~ptailor.errors.PtailorError` (exit 2) naming the option, before any file is read.
Batch stamps a garment's output folder with :meth:`RunOptions.stamped`, so that every option
that changes the outputs decides whether a folder is up to date.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from ptailor.errors import PtailorError
from ptailor.run.outputs import DEFAULT_FORMATS, FORMATS
from ptailor.verify.rest import REST_MODES

#: the flatten overrides (``--method``, ``--intrinsic``)
METHODS = ("scale-preserving", "uniform")
INTRINSICS = ("polar", "paper")
AXES = ("x", "y", "z", "-x", "-y", "-z")
DXF_UNITS = ("mm", "cm", "in")


def _one_of(value, known: tuple[str, ...], option: str) -> None:
    if value is not None and value not in known:
        raise PtailorError(f"{option} must be one of {', '.join(known)}, not {value!r}")


@dataclass(frozen=True)
class RunOptions:
    """How one garment is read, adjusted and written (everything but the files themselves).

    Attributes
    ----------
    pattern_units, drape_units : str or None
        File units (``mm``, ``cm``, ``m``, ``in``, a scaled unit such as ``0.3333cm``; the
        pattern also ``auto``), see :func:`ptailor.formats.garment.load_garment`; None: not
        given (``cm``, if the garment is then of human size).
    weld : str or float
        ``auto``, ``off`` or a distance (``0.1mm``; a bare number in the recipe's units).
    method, intrinsic : str, optional
        Override the recipe's flatten settings.
    baseline : bool
        Compute uniform flattening for comparison.
    formats : tuple of str
        Outputs to write besides ``report.json`` (:data:`ptailor.run.outputs.FORMATS`;
        default :data:`~ptailor.run.outputs.DEFAULT_FORMATS`, all but the cutting sheet).
    up, front : str, optional
        The garment's axes (``y``, ``-z``, ...); default the recipe's, else y up, z front.
    body : str, optional
        A watertight body mesh (any format trimesh reads) in ``body_units``: extended rows
        are pushed out of it.
    body_units : str
    write_body : bool
        Write the body the run used (a file or ``--body auto``'s fit) as ``body.obj`` beside
        the outputs, in the garment's frame and its drape file's units, to look at.
    size, dxf_units : str, optional
        For a CAD pattern: the size to read, and its unit (default: from the file).
    sizes : str, optional
        For a graded CAD pattern (a nest of sizes): ``all`` or a comma-separated list of
        sizes, each written adjusted as ``size`` (the drape's size) was, its grade kept
        (:mod:`ptailor.pieces.grade`).
    seam_allowance : float, optional
        In the recipe's units: the DXF's cut line is the adjusted outline offset by this
        (GEOS's mitre buffer), and the outline itself becomes the sew line (layer 14).
    seam_allowances : tuple of (str, float)
        Allowances by seam, seam line or opening name (``hem=3cm``), in the recipe's
        units, over ``seam_allowance`` (which is then the other edges'; none: 0).
    verify : bool
        Re-drape the adjusted pattern, the uniform baseline and the original pattern with
        the cloth engine (:mod:`ptailor.verify`): the report gets ``verify`` and the output
        folder ``verify_ours.obj``, ``verify_baseline.obj`` and ``verify.png``.
    verify_rest : str
        ``intrinsic`` (each triangle rests as its pattern triangle through the original
        garment's intrinsic scale) or ``pattern`` (plain cloth cut from the pattern).
    verify_max_steps : int, optional
        The re-drapes' step cap (default: the engine's).
    verify_null_mean, verify_null_p95 : float, optional
        The null test's limits, cm: the original pattern re-draped from the original drape
        must land at most this far from it, mean and 95th percentile (default 1.0 and 2.5
        cm, :mod:`ptailor.verify.verdict`), else the verdict is inconclusive.
    spec : str, optional
        A GarmentCode or Garment-Pattern-Generator specification JSON of the garment's
        pattern: matched to its panels and written back adjusted (``specification.json``).
    spec_units : str, optional
        The specification's unit (``cm``, ``0.3333cm``): replaces its
        ``properties.units_in_meter`` (default: that, or inferred from the garment).
    show_measures : bool
        ``pattern.svg`` and ``preview.png`` draw the adjusted garment's points of measure
        (:mod:`ptailor.measures`) on its pieces, named.
    paper : str
        The cutting sheet's (``pattern.pdf``) paper: ``A4``, ``Letter``, ``A3`` (tiled
        pages), ``A0`` (a plotter sheet, tiled when outgrown) or ``roll:WIDTH``
        (:func:`ptailor.formats.cutting.parse_paper`).
    edited_drape : str, optional
        An OBJ of the garment's drape edited elsewhere (same vertices and faces): the edit,
        in place of the recipe's steps (:mod:`ptailor.run.edited`).
    """

    pattern_units: str | None = None
    drape_units: str | None = None
    weld: str | float = "auto"
    method: str | None = None
    intrinsic: str | None = None
    baseline: bool = True
    formats: tuple[str, ...] = DEFAULT_FORMATS
    up: str | None = None
    front: str | None = None
    body: str | None = None
    body_units: str = "cm"
    write_body: bool = False
    size: str | None = None
    dxf_units: str | None = None
    sizes: str | None = None
    seam_allowance: float | None = None
    seam_allowances: tuple[tuple[str, float], ...] = ()
    verify: bool = False
    verify_rest: str = "intrinsic"
    verify_max_steps: int | None = None
    verify_null_mean: float | None = None
    verify_null_p95: float | None = None
    spec: str | None = None
    spec_units: str | None = None
    show_measures: bool = False
    paper: str = "A4"
    edited_drape: str | None = None

    def __post_init__(self) -> None:
        from ptailor.formats.garment import parse_units, parse_weld

        if self.pattern_units is not None and self.pattern_units != "auto":
            parse_units(self.pattern_units, what="--pattern-units")
        if self.drape_units is not None:
            parse_units(self.drape_units, what="--drape-units")
        if self.spec_units is not None:
            parse_units(self.spec_units, what="--spec-units")
        parse_units(self.body_units, what="--body-units")
        parse_weld(self.weld, units="cm")  # (the syntax; a bare number is the recipe's units)
        _one_of(self.method, METHODS, "--method")
        _one_of(self.intrinsic, INTRINSICS, "--intrinsic")
        _one_of(self.up, AXES, "--up")
        _one_of(self.front, AXES, "--front")
        _one_of(self.dxf_units, DXF_UNITS, "--dxf-units")
        _one_of(self.verify_rest, REST_MODES, "--rest")
        unknown = [f for f in self.formats if f not in FORMATS]
        if isinstance(self.formats, str) or unknown:
            raise PtailorError(
                f"--formats: unknown output format(s) {', '.join(unknown or [self.formats])} "
                f"(known: {', '.join(FORMATS)})"
            )
        from ptailor.formats.cutting import parse_paper

        parse_paper(self.paper)
        a = self.seam_allowance
        if a is not None and not (isinstance(a, (int, float)) and math.isfinite(a) and a >= 0):
            raise PtailorError(f"--seam-allowance must be a length >= 0, not {a}")
        for name, a in self.seam_allowances:  # the named allowances
            if not (isinstance(a, (int, float)) and math.isfinite(a) and a >= 0):
                raise PtailorError(f"--seam-allowance {name} must be a length >= 0, not {a}")
        if self.sizes is not None and not all(sizes_list(self.sizes)):
            raise PtailorError(
                f"--sizes must be all or a comma-separated list of sizes, not {self.sizes!r}"
            )
        for opt, v in (
            ("--null-mean", self.verify_null_mean),
            ("--null-p95", self.verify_null_p95),
        ):
            if v is not None and not (
                isinstance(v, (int, float))
                and not isinstance(v, bool)
                and math.isfinite(v)
                and v > 0
            ):
                raise PtailorError(f"{opt} must be a length > 0, not {v}")
        n = self.verify_max_steps
        if n is not None and (isinstance(n, bool) or not isinstance(n, int) or n < 1):
            raise PtailorError(f"--max-steps must be at least 1, not {n}")

    def stamped(self) -> dict:
        """The options as a JSON-ready dict with sorted keys (``formats`` sorted): what
        a batch stamp hashes."""
        data = asdict(self)
        data["formats"] = sorted(data["formats"])
        for key in ("spec_units", "sizes", "edited_drape", "seam_allowances",
                    "verify_null_mean", "verify_null_p95"):  # (older stamps)  # fmt: skip
            if data[key] in (None, ()):
                del data[key]
        if data["paper"] == "A4":  # (the default: stamps written before the option stay valid)
            del data["paper"]
        return dict(sorted(data.items()))


def sizes_list(sizes: str) -> list[str]:
    """``--sizes S,M,L`` as its names (``["S", "M", "L"]``; ``all`` as ``["all"]``); an
    empty name (``S,,M``) stays, as ``""``, for the check to refuse."""
    return [s.strip() for s in str(sizes).split(",")]
