"""Checks that a garment is usable, each failing with one clear line."""

from __future__ import annotations

import numpy as np

from ptailor import tolerances as tol
from ptailor.errors import PtailorError
from ptailor.geometry.triangles import signed_areas_2d, triangle_areas
from ptailor.model import tolerances as model_tol
from ptailor.model.garment import Garment


def check_garment(g: Garment, *, path: str | None = None) -> None:
    """Raise :class:`PtailorError` if the garment cannot be adjusted.

    Checks finite coordinates, matching triangle counts, a consistent pattern-to-drape
    vertex map (one 2D vertex is one 3D vertex) and no zero-area triangles in 2D or 3D.

    Parameters
    ----------
    g : Garment
    path : str, optional
        Named in the error message.
    """
    if len(g.F2) != len(g.F3):
        raise PtailorError(
            f"pattern and drape have different faces ({len(g.F2)} vs {len(g.F3)} triangles)",
            path=path,
        )
    if len(g.F3) == 0:
        raise PtailorError("no triangles", path=path)
    used3, used2 = _used_rows(g.V3, g.F3), _used_rows(g.V2, g.F2)
    if not np.all(np.isfinite(used3)):
        raise PtailorError("NaN or infinite drape coordinates (v)", path=path)
    if not np.all(np.isfinite(used2)):
        raise PtailorError("NaN or infinite pattern coordinates (vt)", path=path)
    # one pattern vertex must sit on one drape vertex
    to3 = np.full(len(g.V2), -1, dtype=np.int64)
    to3[g.F2.ravel()] = g.F3.ravel()
    if np.any(to3[g.F2.ravel()] != g.F3.ravel()):
        raise PtailorError(
            "pattern and drape have different faces (a pattern vertex maps to two drape vertices)",
            path=path,
        )
    with np.errstate(all="ignore"):
        diag3 = float(np.ptp(used3, axis=0).max())
        diag2 = float(np.ptp(used2, axis=0).max())
    for name, d in (("drape coordinates (v)", diag3), ("pattern coordinates (vt)", diag2)):
        # squared sizes and areas must stay finite (an overflow here is no garment)
        if not (np.isfinite(d) and d <= tol.GARMENT_SIZE_MAX):
            raise PtailorError(
                f"{name} span {d:g} {g.units}: beyond {tol.GARMENT_SIZE_MAX:g}, no garment",
                path=path,
            )
    with np.errstate(all="ignore"):
        a3 = triangle_areas(g.V3, g.F3)
        a2 = np.abs(signed_areas_2d(g.V2, g.F2))
    for name, a, d in (("3D (drape)", a3, diag3), ("2D (pattern)", a2, diag2)):
        bad = np.flatnonzero(a <= model_tol.ZERO_AREA_REL * max(d, tol.TINY) ** 2)
        if bad.size:
            raise PtailorError(
                f"{bad.size} zero-area triangle(s) in {name}, first is face {int(bad[0]) + 1}",
                path=path,
            )


def _used_rows(V: np.ndarray, F: np.ndarray) -> np.ndarray:
    """The rows of ``V`` the triangles ``F`` use, in order (``V[np.unique(F)]``): ``V``
    itself when they use every row (no copy), else a copy through a mask (linear time)."""
    used = np.zeros(len(V), dtype=bool)
    used[F.ravel()] = True
    return V if used.all() else V[used]
