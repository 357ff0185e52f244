"""The wearer's frame of a garment: which way is up and which way the wearer faces.

A garment carries its frame (:attr:`ptailor.model.garment.Garment.frame`): it is resolved
once, where the garment is read (the command line's ``--up``/``--front``, else the recipe's,
else :data:`DEFAULT_FRAME`), and every name from geometry (panels, openings, sides), every
measure and every view reads it from there. Nothing below the command line and the readers
takes the axes as loose arguments.

Examples
--------
>>> Frame.from_names("z", "-y")
Frame(up=(0.0, 0.0, 1.0), front=(0.0, -1.0, 0.0))
>>> Frame().side
(1.0, 0.0, 0.0)
>>> Frame((0, 0, 2), (0, -1, 0.3)).matrix().round(3).tolist()
[[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]]
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from ptailor.model import tolerances as model_tol

__all__ = ["AXIS_NAMES", "DEFAULT_FRAME", "Axis", "Frame", "axis_vector", "frame_from_header"]

Axis = tuple[float, float, float]
#: the names ``--up``, ``--front`` and a recipe's ``up:``, ``front:`` take
AXIS_NAMES = ("x", "y", "z", "-x", "-y", "-z")


def axis_vector(name: str) -> Axis:
    """The unit vector of an axis name: ``"-y"`` -> ``(0, -1, 0)``.

    Examples
    --------
    >>> axis_vector("-y")
    (0.0, -1.0, 0.0)
    """
    if name not in AXIS_NAMES:
        raise ValueError(f"not an axis name: {name!r} (one of {', '.join(AXIS_NAMES)})")
    sign = -1.0 if name.startswith("-") else 1.0
    v = [0.0, 0.0, 0.0]
    v["xyz".index(name[-1])] = sign
    return (v[0], v[1], v[2])


def _vector(v, what: str) -> Axis:
    a = np.asarray(v, dtype=np.float64).reshape(-1)
    if a.shape != (3,) or not np.all(np.isfinite(a)) or not np.any(a):
        raise ValueError(f"{what} axis must be a finite non-zero vector, got {tuple(a)}")
    x, y, z = (float(c) for c in a)
    return (x, y, z)


@dataclass(frozen=True)
class Frame:
    """The wearer's axes in the drape's coordinates.

    Attributes
    ----------
    up : (3,) tuple of float
        From the feet to the head (any length; :meth:`matrix` normalises).
    front : (3,) tuple of float
        The direction the wearer faces; not parallel to ``up`` (only its part
        perpendicular to ``up`` counts).

    Raises
    ------
    ValueError
        When ``up`` or ``front`` is zero or not finite, or they are parallel.
    """

    up: Axis = (0.0, 1.0, 0.0)
    front: Axis = (0.0, 0.0, 1.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "up", _vector(self.up, "up"))
        object.__setattr__(self, "front", _vector(self.front, "front"))
        self.matrix()  # raises when they are parallel

    @classmethod
    def from_names(cls, up: str, front: str) -> Frame:
        """The frame of two axis names (``"z"``, ``"-y"``)."""
        return cls(axis_vector(up), axis_vector(front))

    def names(self) -> tuple[str, str] | None:
        """``(up, front)`` as axis names when both lie along an axis (``("z", "-y")``),
        else None.

        Examples
        --------
        >>> Frame((0, 0, 2), (0, -1, 0)).names(), Frame((0, 1, 0), (1, 0, 1)).names()
        (('z', '-y'), None)
        """
        out = []
        for v in (self.up, self.front):
            k = [i for i, c in enumerate(v) if c != 0.0]
            if len(k) != 1:
                return None
            out.append(("-" if v[k[0]] < 0 else "") + "xyz"[k[0]])
        return out[0], out[1]

    def header(self) -> str | None:
        """The comment line a garment file carries its frame in (:func:`frame_from_header`
        reads it back), or None for the default frame or one off the axes."""
        names = self.names()
        if names is None or self == DEFAULT_FRAME:
            return None
        return f"{_HEADER} up {names[0]}, front {names[1]}"

    @property
    def side(self) -> Axis:
        """The wearer's left, ``up x front`` made unit (+x with y up and z front: the
        wearer faces +z)."""
        x, y, z = (float(c) for c in self.matrix()[0])
        return (x, y, z)

    def matrix(self) -> np.ndarray:
        """Orthonormal rows ``(left, up, front)``: ``front`` made orthogonal to ``up``,
        ``left = up x front``; ``V @ frame.matrix().T`` is ``V`` in a y-up, z-front frame.

        Returns
        -------
        (3, 3) float array
        """
        u = np.asarray(self.up)
        f = np.asarray(self.front)
        u = u / np.linalg.norm(u)
        f = f - (f @ u) * u
        nf = np.linalg.norm(f)
        if nf < model_tol.FRAME_PARALLEL * max(1.0, float(np.linalg.norm(self.front))):
            raise ValueError("front axis must be non-zero and not parallel to the up axis")
        f = f / nf
        return np.stack([np.cross(u, f), u, f])


#: the frame of garments that say none: y up, z front (the OBJ datasets' and every
#: generated sample's convention)
DEFAULT_FRAME = Frame()
#: how a garment file's comment line starts that says its frame (:meth:`Frame.header`)
_HEADER = "ptailor frame:"
_HEADER_RE = re.compile(r"^ptailor frame: up (-?[xyz]), front (-?[xyz])$")


def frame_from_header(header) -> Frame | None:
    """The frame a garment file's comment lines state (:meth:`Frame.header`), or None.

    Parameters
    ----------
    header : sequence of str
        The file's leading comment lines, without ``#``.

    Examples
    --------
    >>> frame_from_header(["made by hand", "ptailor frame: up z, front -y"])
    Frame(up=(0.0, 0.0, 1.0), front=(0.0, -1.0, 0.0))
    """
    for line in header:
        m = _HEADER_RE.match(line.strip())
        if m:
            return Frame.from_names(m.group(1), m.group(2))
    return None
