"""The recipe format's vocabulary: its keys, flatten settings, axes and the
:class:`Recipe` a valid document becomes.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from ptailor import tolerances as tol
from ptailor.edits.checks import (
    choice,
    number,
)
from ptailor.edits.registry import COMMON_FIELDS, Step
from ptailor.errors import PtailorError
from ptailor.method import tolerances as method_tol
from ptailor.model.frame import AXIS_NAMES, DEFAULT_FRAME, Frame
from ptailor.recipe.expect import Expectation

FLATTEN_PARAMS = {
    "method": (choice("scale-preserving", "uniform"), "scale-preserving"),
    "intrinsic": (choice("polar", "paper"), "polar"),
    "boundary": (choice("auto", "similar", "free"), "auto"),
    "seams": (choice("ease", "free", "keep"), "ease"),
    # outside tol.FLATTEN_WEIGHT_RANGE the stitching matrix overflows or loses the shape
    "w_pin": (
        number(ge=tol.FLATTEN_WEIGHT_RANGE[0], le=tol.FLATTEN_WEIGHT_RANGE[1]),
        method_tol.W_PIN,
    ),
    "w_asap": (
        number(ge=tol.FLATTEN_WEIGHT_RANGE[0], le=tol.FLATTEN_WEIGHT_RANGE[1]),
        method_tol.W_ASAP,
    ),
    "max_iter": (number(ge=1, le=10000, integer=True), method_tol.ARAP_MAX_ITER),
}
TOP_KEYS = ("format", "units", "up", "front", "symmetric", "steps", "flatten", "expect")
#: A step key every operation accepts (see :mod:`ptailor.edits.mirror`): the fields every
#: :class:`ptailor.edits.Step` has.
STEP_KEYS = COMMON_FIELDS
#: Step parameters that are lengths an edit adds or removes, or a measure's asked length
#: (bounded by :data:`ptailor.tolerances.RECIPE_MAX_LENGTH_CM`).
LENGTH_PARAMS = {
    "extend": ("by", "clearance", "to"),
    "shorten": ("by", "to"),
    "loosen": ("by", "girth"),
    "tighten": ("by", "girth"),
    "scale": ("to", "by"),
}
#: Step parameters that are directions when given as ``[x, y, z]``: (op, path in the step).
DIRECTION_PARAMS = {
    "cut": (("plane", "normal"), ("view",)),
    "loosen": (("view",),),
    "tighten": (("view",),),
}
DEFAULT_UP, DEFAULT_FRONT = "y", "z"


def axes_problem(
    up: Any, front: Any, *, up_name: str = "up", front_name: str = "front"
) -> str | None:
    """Why ``up`` and ``front`` (axis names, or None for the default) cannot be a frame.

    The one rule of recipes (``up:``, ``front:``) and of the command line (``--up``,
    ``--front``): both must be axis names, and not parallel (``y`` and ``-y`` are).
    ``None`` stands for the default (y up, z front).
    """
    u = DEFAULT_UP if up is None else up
    f = DEFAULT_FRONT if front is None else front
    if u not in AXIS_NAMES or f not in AXIS_NAMES:
        return None  # reported by the choice check
    if u[-1] == f[-1]:
        uu = f"{up_name} {u}" + (" (the default)" if up is None else "")
        ff = f"{front_name} {f}" + (" (the default)" if front is None else "")
        return f"{ff} is parallel to {uu}: up and front must be different axes"
    return None


def resolve_frame(
    up: str | None,
    front: str | None,
    recipe: Recipe | None = None,
    *,
    default: Frame | None = DEFAULT_FRAME,
) -> Frame | None:
    """The garment's frame from axis names: the command line's, else the recipe's, else
    ``default``.

    Parameters
    ----------
    up, front : str or None
        ``--up``, ``--front`` (``"z"``, ``"-y"``, ...); None where not given.
    recipe : Recipe, optional
        Its ``up:``/``front:`` where the command line gives none.
    default : Frame or None
        When neither gives an axis: :data:`~ptailor.model.frame.DEFAULT_FRAME` (y up, z
        front), or None to leave it to the garment file (``load_garment(frame=None)``
        reads the frame a ptailor-written file states, else the default).

    Returns
    -------
    Frame or None

    Raises
    ------
    PtailorError
        When they are parallel (the same rule as a recipe's ``up``/``front``).
    """
    u = up or (recipe.up if recipe else None)
    f = front or (recipe.front if recipe else None)
    if u is None and f is None:
        return default
    bad = axes_problem(
        u,
        f,
        up_name="--up" if up else "up",
        front_name="--front" if front else "front",
    )
    if bad:
        raise PtailorError(bad)
    return Frame.from_names(u or DEFAULT_UP, f or DEFAULT_FRONT)


@dataclass(frozen=True)
class Recipe:
    """A validated recipe with every default filled in.

    Attributes
    ----------
    units : str
    steps : tuple of Step
        One typed step per recipe step (:class:`ptailor.edits.Step`: ``ScaleStep``,
        ``ShortenStep``, ...), every parameter filled in, ``symmetric`` resolved (the
        step's own, else the recipe's).
    flatten : dict
        ``method``, ``intrinsic``, ``boundary``, ``w_pin``, ``w_asap``, ``max_iter``.
    source : str
        Where it came from (a path, ``<stdin>`` or ``<string>``).
    up, front : str or None
        The garment's axes (``y``, ``-z``, ...) when the recipe sets them.
    symmetric : bool
        The recipe-level default of every step's ``symmetric`` (each step in ``steps``
        carries its own, resolved value).
    expect : tuple of Expectation
        The measures the result must reach (``expect:``; :mod:`ptailor.recipe.expect`),
        judged on the adjusted garment.
    """

    units: str = "cm"
    steps: tuple[Step, ...] = ()
    flatten: dict = field(default_factory=lambda: {k: d for k, (_, d) in FLATTEN_PARAMS.items()})
    source: str = "<string>"
    up: str | None = None
    front: str | None = None
    symmetric: bool = False
    expect: tuple[Expectation, ...] = ()

    def __post_init__(self) -> None:
        # the flatten settings' checks (the same the rules run on a recipe file), so that a
        # Recipe built in Python cannot carry a weight that overflows the stitching matrix
        problems = [
            msg
            for key, (check, _) in FLATTEN_PARAMS.items()
            if key in self.flatten
            for msg in check(self.flatten[key], f"flatten.{key}")
        ]
        if problems:
            raise PtailorError("; ".join(problems), path=self.source)
        object.__setattr__(self, "steps", tuple(self.steps))
        object.__setattr__(self, "expect", tuple(self.expect))

    def to_dict(self) -> dict[str, Any]:
        """The recipe as validated, every default filled in, without its source: the
        mapping the catalogue writes as YAML and a batch's stamp hashes.

        Returns
        -------
        dict
            ``units``, ``steps`` (each :meth:`ptailor.edits.Step.to_dict`), ``flatten``,
            ``up``, ``front``, ``symmetric``; ``expect`` (each measure's
            :meth:`~ptailor.recipe.expect.Expectation.to_dict`) when the recipe has it.
        """
        out = {
            "units": self.units,
            "steps": [s.to_dict() for s in self.steps],
            "flatten": dict(self.flatten),
            "up": self.up,
            "front": self.front,
            "symmetric": self.symmetric,
        }
        if self.expect:  # (absent otherwise: the stamps of recipes without it stay)
            out["expect"] = {e.name: e.to_dict() for e in self.expect}
        return out
