"""Options shared by several commands, defined once, and the one builder of a run's options.

:func:`run_options` declares every option of one garment's run (what
:class:`~ptailor.run.options.RunOptions` holds), for ``adjust`` and ``batch`` alike;
:func:`build_run_options` turns a command's run parameters into ``RunOptions`` (``adjust``,
``batch`` and ``verify``). A command names its own parameters and takes the run's as
``**run``: the builder refuses a name that is not a run option.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import click

from ptailor.cli.verify_options import parse_cm, verify_options

if TYPE_CHECKING:
    from ptailor.run.options import RunOptions

#: the axes --up and --front take (:data:`ptailor.run.options.AXES`)
AXES = ["x", "y", "z", "-x", "-y", "-z"]
#: ``--method`` and ``--intrinsic`` (:data:`ptailor.run.options.METHODS`, ``INTRINSICS``)
METHODS = ["scale-preserving", "uniform"]
INTRINSICS = ["polar", "paper"]

UNIT_HELP = "mm, cm, m, in, or a scaled unit such as 0.3333cm"

WELD_HELP = (
    "Weld coincident drape vertices on reading: auto (when the panels' drapes touch only "
    "through coincident vertices, as per-piece CAD exports do; within 0.1 % of the mean edge "
    "length), off, or a distance (0.1mm; a bare number is in the computation units)."
)


class Finite(click.FloatRange):
    """A float option that must be a finite number within its range: ``nan`` passes every
    range comparison (a gate of ``nan`` never fired) and ``inf`` overflows what takes it
    (``--timeout inf``), so both are exit 2 naming the option."""

    name = "finite number"

    def convert(self, value, param, ctx):
        import math

        rv = super().convert(value, param, ctx)
        if not math.isfinite(rv):
            self.fail(f"{value!r} is not a finite number.", param, ctx)
        return rv


class GarmentPath(click.Path):
    """A garment file argument: ``-`` is refused with a clear line (a garment is an OBJ or
    a DXF with its drape beside it, read by name; only a recipe, and ``batch``'s list of
    garment paths, come from stdin)."""

    def __init__(self) -> None:
        super().__init__(dir_okay=False)

    def convert(self, value, param, ctx):
        if value == "-":
            self.fail(
                "a garment cannot be read from stdin ('-'): give its file (an OBJ, or a DXF "
                "with its drape); only the recipe may be '-'",
                param,
                ctx,
            )
        return super().convert(value, param, ctx)


def weld_option(fn):
    """``--weld auto|off|DISTANCE``."""
    return click.option(
        "--weld", default="auto", show_default=True, metavar="auto|off|DISTANCE", help=WELD_HELP
    )(fn)


def baseline_option(fn):
    """``--no-baseline``."""
    return click.option(
        "--no-baseline", is_flag=True, help="Skip the uniform-flattening comparison."
    )(fn)


def units_options(fn):
    """``--pattern-units``, ``--drape-units``, ``--weld``: how a garment's files are read."""
    for opt in reversed(
        [
            click.option(
                "--pattern-units",
                default=None,
                help=f"Unit of the pattern coordinates: {UNIT_HELP}, or auto (a [0,1] atlas, "
                "scale estimated from the drape) [default: cm, if the garment is then of "
                "human size, else exit 2].",
            ),
            click.option(
                "--drape-units",
                default=None,
                help=f"Unit of the drape: {UNIT_HELP} [default: cm, if the garment is then of "
                "human size, else exit 2].",
            ),
            weld_option,
        ]
    ):
        fn = opt(fn)
    return fn


def drape_option(fn):
    """``--drape``: the drape of a pattern-only garment (one garment's: not ``batch``'s)."""
    return click.option(
        "--drape",
        type=click.Path(dir_okay=False),
        default=None,
        help="OBJ holding the drape (v) when GARMENT holds only the pattern.",
    )(fn)


def garment_options(fn):
    """``--drape``, ``--pattern-units``, ``--drape-units``, ``--weld``."""
    return drape_option(units_options(fn))


def spec_option(*, writes: bool = True):
    """``--spec`` and ``--spec-units``: the garment's pattern specification (GarmentCode,
    Garment-Pattern-Generator) and its unit; ``writes``: the command writes it back adjusted."""
    what = (
        "matched to the garment's panels and seams, and written back adjusted as "
        "OUT/specification.json"
        if writes
        else "each of its panels shown with the garment's panel it is, each stitch with its seam"
    )
    spec = click.option(
        "--spec",
        type=click.Path(dir_okay=False),
        default=None,
        help=f"The pattern's specification JSON (GarmentCode or Garment-Pattern-Generator): "
        f"{what} (with --pattern-units auto its panel sizes fix the pattern's scale); auto: "
        "the one beside the garment (STEM_specification.json, for tee6_sim.obj "
        "tee6_specification.json), none if there is none.",
    )
    units = click.option(
        "--spec-units",
        default=None,
        help=f"Unit of the specification's numbers: {UNIT_HELP}; replaces its "
        "properties.units_in_meter [default: that; without it (older Garment-Pattern-"
        "Generator files) the usual unit (cm, 1/3 cm, mm, m, ...) at which its panels have "
        "the garment's area].",
    )
    return lambda fn: spec(units(fn))


def axes_options(fn):
    """``--up`` and ``--front``: the garment's axes, for naming openings."""
    for opt in reversed(
        [
            click.option(
                "--up",
                default=None,
                type=click.Choice(AXES),
                help="Up axis [default: the recipe's, else y].",
            ),
            click.option(
                "--front",
                default=None,
                type=click.Choice(AXES),
                help="Front axis [default: the recipe's, else z].",
            ),
        ]
    ):
        fn = opt(fn)
    return fn


def method_options(fn):
    """``--method`` and ``--intrinsic``: the recipe's flatten settings overridden."""
    for opt in reversed(
        [
            click.option(
                "--method",
                type=click.Choice(METHODS),
                default=None,
                help="Override the recipe's flatten method (uniform: the paper's baseline).",
            ),
            click.option(
                "--intrinsic",
                type=click.Choice(INTRINSICS),
                default=None,
                help="Override how intrinsic scale targets are formed (paper: the paper's "
                "designated-edge formula).",
            ),
        ]
    ):
        fn = opt(fn)
    return fn


def output_options(fn):
    """``--formats``, ``--paper``, ``--seam-allowance`` and ``--show-measures``: what is
    written, on which paper the cutting sheet, how the DXF is cut, what the previews show."""
    for opt in reversed(
        [
            click.option(
                "--formats",
                default="obj,dxf,svg,png",
                show_default=True,
                help="Outputs besides report.json: obj (garment.obj), dxf (pattern.dxf), svg "
                "(pattern.svg), png (preview.png), pdf (pattern.pdf: the cutting sheet, "
                "1:1 on tiled pages), cut (pattern_cut.svg: the cutting sheet on one "
                "sheet, in mm).",
            ),
            click.option(
                "--paper",
                default="A4",
                show_default=True,
                metavar="PAPER",
                help="pattern.pdf's paper: A4, Letter or A3 (tiled pages with registration "
                "marks), A0 (a plotter sheet) or roll:WIDTH (one plotter sheet as long as "
                "the pattern: roll:914mm, roll:36in).",
            ),
            click.option(
                "--seam-allowance",
                multiple=True,
                metavar="[NAME=]LENGTH",
                help="Write pattern.dxf with a seam allowance: the cut line is the adjusted "
                "outline offset outward (GEOS's mitre buffer: never crosses itself), the "
                "outline becomes the sew line (layer 14). A bare LENGTH is every edge's; "
                "NAME=LENGTH (repeatable) a seam's, seam line's or opening's as `ptailor "
                "inspect` names them (hem=3cm). A number in the recipe's units, or with a "
                "unit: 1cm, 10mm, 0.375in.",
            ),
            click.option(
                "--show-measures",
                is_flag=True,
                help="Draw the adjusted garment's points of measure (chest, hem, sleeve length, "
                "...) on pattern.svg's and preview.png's pieces, named (docs/measures.md).",
            ),
        ]
    ):
        fn = opt(fn)
    return fn


def dxf_options(fn):
    """``--size`` and ``--dxf-units``: how a DXF pattern is read."""
    for opt in reversed(
        [
            click.option(
                "--size",
                default=None,
                help="DXF pattern: the size to read [default: the file's sample size, else "
                "its first].",
            ),
            click.option(
                "--dxf-units",
                type=click.Choice(["mm", "cm", "in"]),
                default=None,
                help="DXF pattern: its unit [default: from the file's 'Units:' text; METRIC "
                "is mm or cm, judged from the drape, or from the piece sizes without one].",
            ),
        ]
    ):
        fn = opt(fn)
    return fn


def sizes_option(fn):
    """``--sizes all|S,M,L``: every chosen size of a graded DXF nest, adjusted."""
    return click.option(
        "--sizes",
        default=None,
        metavar="all|S,M,...",
        help="Graded DXF pattern (a nest of sizes): write every chosen size, each adjusted as "
        "the drape's size (--size, default the sample size) was, its grade kept: pattern.dxf "
        "holds them all as a graded nest, pattern_SIZE.dxf each one (docs/dxf.md).",
    )(fn)


def report_units_option(help_text: str = "Unit to report lengths in."):
    """``--units mm|cm|m|in``: the unit ``inspect`` and ``measure`` report lengths in."""
    return click.option(
        "--units",
        "units",
        default="cm",
        show_default=True,
        type=click.Choice(["mm", "cm", "m", "in"]),
        help=help_text,
    )


def body_options(fn):
    """``--body`` (a file or ``auto``), ``--body-units`` and ``--write-body``: the body a
    garment is worn on."""
    fn = click.option(
        "--write-body",
        is_flag=True,
        help="Write the body used (the file's or --body auto's fit) to OUT/body.obj, in the "
        "garment's frame and its drape file's units, to look at.",
    )(fn)
    fn = click.option(
        "--body-units", default="cm", show_default=True, help="Unit of the body mesh."
    )(fn)
    return click.option(
        "--body",
        type=click.Path(dir_okay=False),
        default=None,
        help="Watertight body mesh in the garment's frame (rows that extend adds are pushed "
        "out of it; the re-drapes collide with it), or auto: GarmentCode's mean body fitted "
        "to the drape (pose, scale and place; the fit goes into the report and verify.json).",
    )(fn)


def run_options(fn):
    """Every option of one garment's run, in ``--help`` order: ``--pattern-units``,
    ``--drape-units``, ``--weld``, ``--spec``, ``--spec-units``, ``--up``, ``--front``,
    ``--method``,
    ``--intrinsic``, ``--body``, ``--body-units``, ``--write-body``, ``--verify``,
    ``--verify-rest``, ``--verify-max-steps``, ``--no-baseline``, ``--formats``,
    ``--seam-allowance``, ``--show-measures``, ``--size``, ``--dxf-units``, ``--sizes``.

    ``adjust`` and ``batch`` both take exactly these (each has options of its own besides);
    the command gets them as keyword arguments, for :func:`build_run_options`.
    """
    for opt in reversed(
        [
            units_options,
            spec_option(),
            axes_options,
            method_options,
            body_options,
            verify_options,
            baseline_option,
            output_options,
            dxf_options,
            sizes_option,
        ]
    ):
        fn = opt(fn)
    return fn


#: run parameters whose :class:`~ptailor.run.options.RunOptions` field has another name
#: (``ptailor verify``'s ``--rest``, ``--max-steps``, ``--null-mean`` and ``--null-p95``)
RENAMED = {
    "rest": "verify_rest",
    "max_steps": "verify_max_steps",
    "null_mean": "verify_null_mean",
    "null_p95": "verify_null_p95",
}


def build_run_options(params: Mapping[str, Any], *, units: str = "cm", **fixed: Any) -> RunOptions:
    """The run's options from a command's run parameters: the one place a command's
    options become a :class:`~ptailor.run.options.RunOptions` (which checks them).

    Parameters
    ----------
    params : mapping
        The run parameters by their click name, as the command got them (its ``**run``):
        a ``RunOptions`` field by its own name, or ``no_baseline`` (``baseline`` negated),
        ``formats`` (``obj,svg``: split), ``seam_allowance`` (``1cm``: parsed), ``rest`` and
        ``max_steps`` (``verify_rest`` and ``verify_max_steps``, :data:`RENAMED`),
        ``null_mean`` / ``verify_null_mean`` and the p95's (a length: in cm). A field not
        given keeps its default.
    units : str
        The recipe's unit (default cm): a seam allowance is converted to it (a bare number
        is in it).
    **fixed
        Fields the command sets itself (``ptailor verify``: ``verify=True``).

    Returns
    -------
    RunOptions

    Raises
    ------
    PtailorError
        A bad value, naming its option (exit 2).
    TypeError
        A parameter that is not a run option (a command's own parameter passed on).
    """
    from ptailor.run.options import RunOptions

    values = {RENAMED.get(name, name): value for name, value in params.items()}
    if "no_baseline" in values:
        values["baseline"] = not values.pop("no_baseline")
    if "formats" in values:
        values["formats"] = parse_formats(values["formats"])
    if "seam_allowance" in values:
        default, named = parse_seam_allowance(values["seam_allowance"], units=units)
        values["seam_allowance"], values["seam_allowances"] = default, named
    for key in ("verify_null_mean", "verify_null_p95"):
        if isinstance(values.get(key), str):
            values[key] = parse_cm(values[key], units=units, what=f"--{key[7:].replace('_', '-')}")
    return RunOptions(**values, **fixed)


def check_engine_first(verify: bool) -> None:
    """With ``--verify``: refuse a missing cloth engine before any file is read (exit 2)."""
    if verify:
        from ptailor.run.checks import check_engine

        check_engine()


def parse_formats(formats: str) -> tuple[str, ...]:
    """``--formats obj,svg`` as a tuple (checked by :class:`~ptailor.run.options.RunOptions`)."""
    return tuple(f for f in formats.split(",") if f)


def parse_seam_allowance(
    seam_allowance: str | Sequence[str] | None, *, units: str
) -> tuple[float | None, tuple[tuple[str, float], ...]]:
    """``--seam-allowance`` (repeatable: a bare ``1cm``, ``10mm``, a number in ``units``;
    ``NAME=LENGTH`` for a seam, seam line or opening) in ``units``.

    Returns
    -------
    default : float or None
        The bare value (None when none is given).
    named : tuple of (str, float)
        ``NAME=LENGTH`` values, in the order given.

    Raises
    ------
    PtailorError
        A bad length, two bare values or one name twice (exit 2).
    """
    from ptailor.errors import PtailorError
    from ptailor.formats.garment import parse_length

    if seam_allowance is None:
        return None, ()
    given = [seam_allowance] if isinstance(seam_allowance, str) else list(seam_allowance)
    default: float | None = None
    named: dict[str, float] = {}
    for text in given:  # a loop over the option's values
        name, eq, length = text.rpartition("=")
        name = name.strip()
        what = f"--seam-allowance {name}" if eq else "--seam-allowance"
        value = parse_length(length, to=units, what=what)
        if eq and not name:
            raise PtailorError(f"--seam-allowance {text!r}: NAME=LENGTH needs a name")
        if (name in named) if eq else (default is not None):
            raise PtailorError(f"--seam-allowance: {name or 'a bare length'} given twice")
        if eq:
            named[name] = value
        else:
            default = value
    return default, tuple(named.items())
