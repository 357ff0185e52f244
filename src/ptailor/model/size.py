"""Is a garment of human size? The check that keeps a unit nobody gave from being wrong.

A file read in a unit nobody stated (``--drape-units`` and ``--pattern-units`` left at
their ``cm`` default, a DXF that says only ``METRIC``) can be three or ten times too large
or too small while its pattern and drape still agree with each other, so the
pattern/drape edge-ratio check (:func:`ptailor.model.repair.check_units`) passes. Absolute
size catches it: a garment's drape spans ``tol.GARMENT_EXTENT_CM`` (a sock to a gown in
T-pose) and is at most ``tol.GARMENT_THICKNESS_MAX_CM`` thick in its thinnest direction,
its largest piece is at least ``tol.PIECE_LENGTH_MIN_CM`` long, and no piece is
wider (its smaller principal extent) than ``tol.PIECE_WIDTH_MAX_CM``, the widest cloth a
piece is cut from.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ptailor import tolerances as tol
from ptailor.geometry.labels import component_labels
from ptailor.model import tolerances as model_tol

__all__ = [
    "GarmentSize",
    "check_size",
    "describe",
    "garment_size",
    "piece_extents",
    "plausible_units",
    "principal_extents",
    "size_problem",
]

#: units a message suggests when the default one gives no human size: name, cm per unit
CANDIDATE_UNITS = (
    ("mm", 0.1),
    ("cm", 1.0),
    ("in", 2.54),
    ("m", 100.0),
    ("0.3333cm", 1.0 / 3.0),  # 1/300 m: Garment-Pattern-Generator's simulated drapes
)


@dataclass(frozen=True)
class GarmentSize:
    """A garment's size in file units.

    Attributes
    ----------
    extent : float
        The drape's largest bounding-box extent (NaN without a drape).
    thickness : float
        The drape's smallest principal extent (along the eigenvector of its vertices'
        covariance with the least variance: a top's depth front to back), NaN without.
    pieces : (k, 2) float array
        Each pattern piece's length and width: its extents along its principal axes,
        the larger first (a connected component of the pattern's triangles).
    """

    extent: float
    pieces: np.ndarray
    thickness: float = float("nan")

    def scaled(self, s: float) -> GarmentSize:
        """The same garment measured in a unit ``s`` times as long."""
        return GarmentSize(
            extent=self.extent * s, pieces=self.pieces * s, thickness=self.thickness * s
        )


def principal_extents(P: np.ndarray) -> np.ndarray:
    """A point set's extents along its principal axes (the eigenvectors of its covariance),
    largest first.

    Parameters
    ----------
    P : (n, d) float array

    Returns
    -------
    (d,) float array
    """
    Q = np.asarray(P, dtype=np.float64)
    Q = Q - Q.mean(axis=0)
    _, axes = np.linalg.eigh(Q.T @ Q)
    return np.sort(np.ptp(Q @ axes, axis=0))[::-1]


def piece_extents(V2: np.ndarray, F2: np.ndarray) -> np.ndarray:
    """Length and width of each connected piece of a pattern.

    Parameters
    ----------
    V2 : (n, 2) float array
    F2 : (m, 3) int array

    Returns
    -------
    (k, 2) float array
        Per component of ``F2`` (in order of first appearance): its extents along its
        principal axes (the eigenvectors of its vertices' covariance), larger first; a
        piece lying rotated in the layout measures as laid straight.
    """
    V2 = np.asarray(V2, dtype=np.float64)
    F2 = np.asarray(F2)
    if len(F2) == 0:
        return np.zeros((0, 2))
    flab = component_labels(F2, len(V2))
    k = int(flab.max()) + 1
    vlab = np.full(len(V2), -1, dtype=np.int64)
    vlab[F2.ravel()] = np.repeat(flab, 3)
    used = np.flatnonzero(vlab >= 0)
    lab, P = vlab[used], V2[used]
    count = np.bincount(lab, minlength=k).astype(float)
    mean = np.stack([np.bincount(lab, P[:, j], minlength=k) for j in range(2)], 1)
    mean /= count[:, None]
    Q = P - mean[lab]
    cov = np.zeros((k, 2, 2))
    for i in range(2):
        for j in range(2):
            cov[:, i, j] = np.bincount(lab, Q[:, i] * Q[:, j], minlength=k)
    _, axes = np.linalg.eigh(cov)  # (k, 2, 2): columns are the principal axes
    proj = np.einsum("vi,vij->vj", Q, axes[lab])  # each vertex along its piece's axes
    hi = np.full((k, 2), -np.inf)
    lo = np.full((k, 2), np.inf)
    np.maximum.at(hi, lab, proj)
    np.minimum.at(lo, lab, proj)
    ext = hi - lo
    return -np.sort(-ext, axis=1)


def garment_size(
    V3: np.ndarray | None, F3: np.ndarray | None, V2: np.ndarray, F2: np.ndarray
) -> GarmentSize:
    """A garment's drape extent and piece sizes, in its file units.

    Parameters
    ----------
    V3 : (n3, 3) float array or None
        The drape (None: a pattern alone).
    F3 : (m, 3) int array or None
    V2 : (n2, 2) float array
    F2 : (m, 3) int array

    Returns
    -------
    GarmentSize
    """
    extent = thickness = float("nan")
    if V3 is not None and F3 is not None and len(F3):
        P = np.asarray(V3, dtype=np.float64)[np.unique(np.asarray(F3))]
        extent = float(np.ptp(P, axis=0).max())
        thickness = float(principal_extents(P)[-1])
    return GarmentSize(extent=extent, pieces=piece_extents(V2, F2), thickness=thickness)


def size_problem(size: GarmentSize) -> str | None:
    """What is not of human size about a garment measured in cm, or None.

    Parameters
    ----------
    size : GarmentSize
        In centimetres.

    Returns
    -------
    str or None
        ``"the drape is 660 cm across"``, ``"its largest piece is 220 x 205 cm"``, ...
    """
    lo, hi = tol.GARMENT_EXTENT_CM
    if np.isfinite(size.extent) and not lo <= size.extent <= hi:
        return f"the drape is {size.extent:.4g} cm across (a garment spans {lo:g}-{hi:g} cm)"
    if np.isfinite(size.thickness) and size.thickness > tol.GARMENT_THICKNESS_MAX_CM:
        return (
            f"the drape is {size.thickness:.4g} cm thick in its thinnest direction (a worn"
            f" garment, on a body 20-45 cm deep, is at most {tol.GARMENT_THICKNESS_MAX_CM:g})"
        )
    if len(size.pieces) == 0:
        return None
    big = size.pieces[int(np.argmax(size.pieces[:, 0]))]
    if big[0] > hi:
        return f"its largest piece is {big[0]:.4g} x {big[1]:.4g} cm (longer than {hi:g} cm)"
    if big[0] < tol.PIECE_LENGTH_MIN_CM:
        return (
            f"its largest piece is {big[0]:.3g} x {big[1]:.3g} cm (a garment's largest piece is"
            f" at least {tol.PIECE_LENGTH_MIN_CM:g} cm long)"
        )
    wide = size.pieces[int(np.argmax(size.pieces[:, 1]))]
    if wide[1] > tol.PIECE_WIDTH_MAX_CM:
        return (
            f"a piece is {wide[0]:.4g} x {wide[1]:.4g} cm (no piece is wider than the widest"
            f" cloth, {tol.PIECE_WIDTH_MAX_CM:g} cm)"
        )
    return None


def plausible_units(size: GarmentSize) -> list[tuple[str, GarmentSize]]:
    """The :data:`CANDIDATE_UNITS` under which a garment measured in file units is of
    human size, with its size in cm under each, the most typical (nearest a 70 cm
    garment) first."""
    out = []
    for name, cm in CANDIDATE_UNITS:
        s = size.scaled(cm)
        if size_problem(s) is None:
            out.append((name, s))

    def typical(item: tuple[str, GarmentSize]) -> float:  # nearest a 70 cm garment first
        cm = model_tol.UNIT_GUESS_TYPICAL_CM
        s = item[1]
        x = s.extent if np.isfinite(s.extent) else s.pieces[:, 0].max(initial=cm)
        return abs(float(np.log(max(x, 1e-9) / cm)))

    return sorted(out, key=typical)


def describe(size: GarmentSize) -> str:
    """``"60 cm across, largest piece 73 x 68 cm"`` (a size in cm)."""
    parts = []
    if np.isfinite(size.extent):
        parts.append(f"{size.extent:.3g} cm across, {size.thickness:.3g} cm thick")
    if len(size.pieces):
        big = size.pieces[int(np.argmax(size.pieces[:, 0]))]
        parts.append(f"largest piece {big[0]:.3g} x {big[1]:.3g} cm")
    return ", ".join(parts)


def check_size(size: GarmentSize, *, path: str | None, options: str) -> None:
    """Raise :class:`ptailor.model.repair.UnitMismatchError` when a garment read in ``cm``
    because no unit was given is not of human size.

    Parameters
    ----------
    size : GarmentSize
        In centimetres (its drape extent NaN, or its pieces empty, for what was given).
    path : str or None
        The file named in the message.
    options : str
        The unit options not given (``"--drape-units and --pattern-units"``).
    """
    from ptailor.model.repair import UnitMismatchError

    problem = size_problem(size)
    if problem is None:
        return
    fits = plausible_units(size)
    hint = (
        "; it is of a garment's size read in "
        + "; in ".join(f"{name} ({describe(s)})" for name, s in fits)
        if fits
        else ""
    )
    raise UnitMismatchError(
        f"read in cm, the unit taken when {options} {'is' if ' and ' not in options else 'are'}"
        f" not given, {problem}: not a garment's size. Give the file's units with {options}"
        f"{hint}",
        path=path,
    )


def size_warning(size: GarmentSize, *, options: str) -> str | None:
    """A warning when a garment read in the units it was given is not of human size: the
    user's word stands (no refusal), but never silently. None when it is.

    Parameters
    ----------
    size : GarmentSize
        In centimetres.
    options : str
        The unit options given (``"--drape-units mm"``).

    Returns
    -------
    str or None
    """
    problem = size_problem(size)
    if problem is None:
        return None
    return f"read with {options}, {problem}: not a garment's size; check the units"
