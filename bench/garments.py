"""The garment a benchmark runs on, given on the command line (shared by the benchmarks).

``--garment PATH`` with ``ptailor adjust``'s own options for it (``--pattern-units``,
``--drape-units``, ``--up``, ``--front``: the same names, values and defaults): the file
goes as it is to every ``ptailor`` subprocess, with those options; in this process it is
read in cm and turned y up, z front (a turn changes no timing), so that recipes placed in
its coordinates need no axes. What the edits act on is found by ``ptailor inspect --json``
(the names ptailor gives, whatever they are: no panel, seam or opening name is assumed),
and the boxes and planes from the drape's extent along up (:func:`placed_edits`).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import subprocess
from pathlib import Path

import numpy as np

from timing import one_blas_thread_env, ptailor_command

AXES = ("x", "y", "z", "-x", "-y", "-z")

#: ``../shared`` beside the project (``PTAILOR_SHARED`` moves it)
SHARED = Path(os.environ.get("PTAILOR_SHARED", Path(__file__).resolve().parents[2] / "shared"))
#: the shared garments the benchmarks run on: key -> (path under ``SHARED/garments``,
#: pattern units)
REAL = {
    "tee6": ("gpg_tee6/tee6_sim.obj", "cm"),
    "tshirt": ("diffavatar/tshirt.obj", "auto"),
    "longsleeve": ("diffavatar/longsleeve_initial.obj", "auto"),
    "dress": ("diffavatar/dress_initial.obj", "auto"),
}


def add_garment_options(ap: argparse.ArgumentParser, *, many: bool = False) -> None:
    """``--garment PATH`` (repeatable with ``many``) and ``ptailor adjust``'s unit and axis
    options for it."""
    ap.add_argument(
        "--garment",
        type=Path,
        action="append" if many else "store",
        metavar="PATH",
        help="an OBJ (v = drape, vt = pattern) to run on instead of the default garments"
        + (" (repeatable)" if many else ""),
    )
    ap.add_argument("--pattern-units", help="as ptailor adjust's (mm, cm, 0.3333cm, auto, ...)")
    ap.add_argument("--drape-units", help="as ptailor adjust's")
    ap.add_argument("--up", choices=AXES, help="as ptailor adjust's [default: y]")
    ap.add_argument("--front", choices=AXES, help="as ptailor adjust's [default: z]")


@dataclasses.dataclass(frozen=True)
class GarmentOptions:
    """A garment file's unit and axis options, as ``ptailor adjust`` takes them (None: the
    command's default)."""

    pattern_units: str | None = None
    drape_units: str | None = None
    up: str | None = None
    front: str | None = None

    @classmethod
    def from_args(cls, args: argparse.Namespace) -> GarmentOptions:
        return cls(args.pattern_units, args.drape_units, args.up, args.front)

    def cli(self) -> list[str]:
        """The options for a ``ptailor adjust``, ``batch`` or ``inspect`` of the file."""
        out = []
        for flag, value in (
            ("--pattern-units", self.pattern_units),
            ("--drape-units", self.drape_units),
            ("--up", self.up),
            ("--front", self.front),
        ):
            if value is not None:
                out += [flag, value]
        return out

    def frame(self) -> np.ndarray:
        """Rows: the garment's left, up and front (``x``, ``y``, ``z`` once turned)."""
        up, front = axis(self.up or "y"), axis(self.front or "z")
        if abs(float(up @ front)) > 0.5:
            raise SystemExit(f"--up {self.up} and --front {self.front} are parallel")
        return np.stack([np.cross(up, front), up, front])


def axis(name: str) -> np.ndarray:
    """``"-z"`` -> ``(0, 0, -1)``."""
    v = np.zeros(3)
    v["xyz".index(name[-1])] = -1.0 if name.startswith("-") else 1.0
    return v


def load_turned(path: Path, opts: GarmentOptions):
    """The garment of ``path`` in cm, turned y up and z front (a ``Garment``)."""
    from ptailor.formats.garment import load_garment

    g = load_garment(path, pattern_units=opts.pattern_units, drape_units=opts.drape_units)
    g = g.garment
    return dataclasses.replace(g, V3=np.asarray(g.V3, dtype=float) @ opts.frame().T)


def subdivided(g, levels: int):
    """``g`` with each triangle split in four ``levels`` times (``bench/subdivide.py``)."""
    from subdivide import subdivide_garment

    if levels == 0:
        return g
    V3, F3, V2, F2, parent = subdivide_garment(g.V3, g.F3, g.V2, g.F2, levels=levels)
    group = g.face_group[parent] if len(g.face_group) else g.face_group
    return dataclasses.replace(g, V3=V3, F3=F3, V2=V2, F2=F2, face_group=group)


def inspect(path: Path, opts: GarmentOptions) -> dict:
    """``ptailor inspect PATH --json`` with the garment's options."""
    cmd = [*ptailor_command(), "inspect", str(path), "--json", *opts.cli()]
    r = subprocess.run(cmd, capture_output=True, text=True, env=one_blas_thread_env())
    if r.returncode != 0:
        raise SystemExit(f"ptailor inspect {path}: {r.stderr.strip()}")
    return json.loads(r.stdout)


@dataclasses.dataclass(frozen=True)
class Layout:
    """What the edits of a garment act on, from ``ptailor inspect`` and the turned drape.

    Attributes
    ----------
    bottom, top : str
        The lowest and highest openings along up.
    small, large : str
        The panels of the least and the largest area.
    seam : (str, str)
        The longest seam between two different panels, the larger panel first.
    lo, hi : (3,) float arrays
        The turned drape's extent (cm).
    """

    bottom: str
    top: str
    small: str
    large: str
    seam: tuple[str, str]
    lo: np.ndarray
    hi: np.ndarray

    @classmethod
    def of(cls, info: dict, g, opts: GarmentOptions) -> Layout:
        """From ``inspect``'s JSON of the file and the turned garment ``g``."""
        up = axis(opts.up or "y")
        ops = sorted(info["openings"], key=lambda o: float(np.dot(o["centroid"], up)))
        if not ops:
            raise SystemExit("the garment has no openings: no hem to shorten, none to fix")
        area = {p["name"]: float(p["area"]) for p in info["panels"]}
        between = [s for s in info["seams"] if len(set(s["panels"])) == 2]
        if between:
            s = max(between, key=lambda s: max(s["lengths"]))
            seam = tuple(sorted(s["panels"], key=lambda n: -area[n]))
        else:
            seam = (max(area, key=area.get),) * 2
        used = np.unique(g.F3)
        return cls(
            bottom=ops[0]["name"],
            top=ops[-1]["name"],
            small=min(area, key=area.get),
            large=max(area, key=area.get),
            seam=seam,
            lo=g.V3[used].min(axis=0),
            hi=g.V3[used].max(axis=0),
        )


def _box(lay: Layout, y0: float, y1: float, *, half: bool = False) -> str:
    """A box over the whole drape across, from ``y0`` to ``y1`` of its height (fractions);
    ``half``: the left half only (x from the centre)."""
    pad = 0.1 * (lay.hi - lay.lo) + 1.0
    lo, hi = lay.lo - pad, lay.hi + pad
    h = lay.hi[1] - lay.lo[1]
    lo[1], hi[1] = lay.lo[1] + y0 * h, lay.lo[1] + y1 * h
    if half:
        lo[0] = 0.5 * (lay.lo[0] + lay.hi[0])
    return f"{{box: {{min: {_xyz(lo)}, max: {_xyz(hi)}}}}}"


def _xyz(p) -> str:
    return "[" + ", ".join(f"{float(x):.3f}" for x in p) + "]"


#: the scale every benchmark's first run makes: the whole garment 1.2 around its axis
SCALE = "steps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.2}]\n"


def not_developable(lay: Layout) -> str:
    """The smallest panel 1.1 around (the rest follows; the stitching iterates)."""
    step = f"{{op: scale, region: {{panels: [{lay.small}]}}, direction: around, factor: 1.1}}"
    return f"steps: [{step}]\n"


def placed_edits(lay: Layout) -> dict[str, str | tuple[str, ...]]:
    """Each registered edit operation once, placed on the garment (recipe texts by a label;
    a tuple: alternatives, the first the garment takes is measured): on the lantern sleeve,
    the seam is sleeve/cuff (the sleeve gathered into the cuff, its top fixed), the bottom
    opening the cuff."""
    a, b = lay.seam
    mid = 0.5 * (lay.lo + lay.hi)
    cut = _xyz([mid[0], lay.lo[1] + 0.625 * (lay.hi[1] - lay.lo[1]), mid[2]])
    return {
        "scale around 1.2": SCALE,
        f"scale {lay.small} 1.1 (ARAP follow)": not_developable(lay),
        f"scale_seam {a}/{b} 1.3": (
            f"steps: [{{op: scale_seam, seam: [{a}, {b}], part: {a}, factor: 1.3, "
            f"fix: [{lay.top}]}}]",
            # (the top opening may lie inside the part, where it cannot stay put)
            f"steps: [{{op: scale_seam, seam: [{a}, {b}], part: {a}, factor: 1.3}}]",
        ),
        f"shorten {lay.bottom} 5": f"steps: [{{op: shorten, opening: {lay.bottom}, by: 5}}]",
        f"extend {lay.bottom} 5": f"steps: [{{op: extend, opening: {lay.bottom}, by: 5}}]",
        "cut plane at 5/8 of the height": (
            f"steps: [{{op: cut, plane: {{point: {cut}, normal: [0, 1, 0]}}}}]"
        ),
        "loosen box 2": f"steps: [{{op: loosen, region: {_box(lay, 0.375, 0.79)}, by: 2}}]",
        "tighten box 1": f"steps: [{{op: tighten, region: {_box(lay, 0.375, 0.79)}, by: 1}}]",
        "mirror (loosen half box 2)": (
            f"steps: [{{op: loosen, region: {_box(lay, 0.375, 0.79, half=True)}, by: 2,"
            " symmetric: true}]"
        ),
    }
