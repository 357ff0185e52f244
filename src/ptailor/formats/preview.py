"""What the pattern previews (``pattern.svg``, ``preview.png``) share: the colour scale
of the intrinsic-scale error and the checking of the inputs (:class:`Pattern`).

The sheet layout (where each panel, its name, the title, the scale bar and the legends go) is
:mod:`ptailor.formats.sheet`.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ptailor.errors import PtailorError

#: Colours of the outlines and text.
BEFORE = "#5c5c5c"  # the original outline, dashed
FRAME = "#8a8a8a"  # legend boxes
AFTER = "#1f4e79"  # the adjusted outline, solid
FILL = "#dce8f4"  # the adjusted panel when no error is shown
INK = "#222222"  # text, scale bar

#: Upper edges of the error bins (relative error, ``0.01`` = 1 %); the last bin is open.
ERROR_EDGES: tuple[float, ...] = (0.005, 0.01, 0.02, 0.05, 0.10)
#: One colour per bin, pale to dark: ColorBrewer YlOrRd, 6 classes (sequential, colour-blind
#: safe, print friendly).
ERROR_COLOURS: tuple[str, ...] = ("#ffffb2", "#fed976", "#feb24c", "#fd8d3c", "#f03b20", "#bd0026")
#: The bins' ranges as shown in the legend.
ERROR_LABELS: tuple[str, ...] = ("< 0.5 %", "0.5–1 %", "1–2 %", "2–5 %", "5–10 %", "≥ 10 %")
#: Triangles whose error is NaN (unknown).
NAN_BIN = len(ERROR_COLOURS)
NAN_COLOUR = "#a6a6a6"
NAN_LABEL = "unknown"
#: Title of the error legend.
ERROR_TITLE = "intrinsic-scale error:"


def error_bins(errors: np.ndarray) -> np.ndarray:
    """The bin of each error.

    Parameters
    ----------
    errors : (m,) float array
        Relative errors; the sign is ignored (``-0.03`` is a 3 % error).

    Returns
    -------
    (m,) int64 array
        ``k`` for ``ERROR_EDGES[k-1] <= |e| < ERROR_EDGES[k]`` (``0 .. len(ERROR_EDGES)``;
        an error on an edge goes to the upper bin: 2 % is in "2–5 %"), ``NAN_BIN`` for NaN.
        Infinite errors fall in the last bin.
    """
    e = np.abs(np.asarray(errors, dtype=np.float64))
    b = np.searchsorted(np.asarray(ERROR_EDGES), e, side="right").astype(np.int64)
    b[np.isnan(e)] = NAN_BIN
    return b


def bin_colour(b: int) -> str:
    """The colour of bin ``b`` (``NAN_BIN`` included)."""
    return NAN_COLOUR if b == NAN_BIN else ERROR_COLOURS[b]


def bin_label(b: int) -> str:
    """The legend text of bin ``b`` (``NAN_BIN`` included)."""
    return NAN_LABEL if b == NAN_BIN else ERROR_LABELS[b]


@dataclass(frozen=True)
class Pattern:
    """Checked inputs of a preview (float64 / int64 arrays; the caller's arrays untouched).

    Attributes
    ----------
    before, after : list (per panel) of list of (k, 2) float arrays
        The outlines in pattern coordinates.
    names : list of str
    triangles : list (per panel) of ((n, 2) float array, (m, 3) int array) or None
        The adjusted pattern's vertices and triangles, every triangle counter-clockwise
        (pattern coordinates, y up) so that a bin's triangles fill their union under the
        non-zero rule.
    bins : list (per panel) of (m,) int arrays or None
        Each triangle's error bin (see :func:`error_bins`).
    """

    before: list[list[np.ndarray]]
    after: list[list[np.ndarray]]
    names: list[str]
    triangles: list[tuple[np.ndarray, np.ndarray]] | None
    bins: list[np.ndarray] | None

    @cached_property
    def used_bins(self) -> list[int]:
        """The bins with at least one triangle, ascending (``NAN_BIN`` last)."""
        if self.bins is None or not self.bins:
            return []
        counts = np.bincount(np.concatenate(self.bins), minlength=NAN_BIN + 1)
        return np.flatnonzero(counts).tolist()


class NonFiniteOutputError(PtailorError, ValueError):
    """NaN or infinity in what a preview would draw: the run fails (exit 2), nothing is
    written (a ``ValueError`` too, as the other input errors of the previews)."""


def _loops(loops, what: str, p: int) -> list[np.ndarray]:
    out = []
    for j, L in enumerate(loops):
        A = np.asarray(L, dtype=np.float64)
        if A.ndim != 2 or A.shape[1] != 2 or len(A) < 2:
            raise ValueError(f"{what}[{p}][{j}]: expected a (k, 2) array with k >= 2")
        if not np.all(np.isfinite(A)):
            raise NonFiniteOutputError(
                f"pattern preview: non-finite coordinates in {what}[{p}][{j}] (nothing written)"
            )
        out.append(A)
    return out


def _mesh(tri, err, p: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    try:
        V, F = tri
    except (TypeError, ValueError):
        raise ValueError(f"triangles[{p}]: expected a (V, F) pair") from None
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F)
    if F.size == 0:
        F = np.zeros((0, 3), dtype=np.int64)
    if V.ndim != 2 or V.shape[1] != 2:
        raise ValueError(f"triangles[{p}]: V must be an (n, 2) array, got shape {V.shape}")
    if F.ndim != 2 or F.shape[1] != 3 or F.dtype.kind not in "iu":
        raise ValueError(f"triangles[{p}]: F must be an (m, 3) integer array")
    F = F.astype(np.int64)
    if len(F) and (F.min() < 0 or F.max() >= len(V)):
        raise ValueError(f"triangles[{p}]: F indexes outside V (n = {len(V)})")
    T = V[F]
    if len(F) and not np.isfinite(T).all():
        raise NonFiniteOutputError(
            f"pattern preview: non-finite vertices in triangles[{p}] (nothing written)"
        )
    E = np.asarray(err, dtype=np.float64)
    if E.shape != (len(F),):
        raise ValueError(f"errors[{p}]: expected shape ({len(F)},), got {E.shape}")
    # counter-clockwise, so that overlapping (flipped) triangles add up rather than cancel
    cross = (T[:, 1, 0] - T[:, 0, 0]) * (T[:, 2, 1] - T[:, 0, 1]) - (T[:, 1, 1] - T[:, 0, 1]) * (
        T[:, 2, 0] - T[:, 0, 0]
    )
    F = np.where((cross < 0)[:, None], F[:, [0, 2, 1]], F)
    return V, F, error_bins(E)


def check_inputs(
    outlines_before,
    outlines_after,
    names,
    triangles=None,
    errors=None,
    *,
    caller: str = "preview",
) -> Pattern:
    """Check and convert a preview's inputs.

    Parameters
    ----------
    outlines_before, outlines_after : list (per panel) of list of (k, 2) array-likes
    names : list of str
    triangles : list (per panel) of (V (n, 2), F (m, 3)) or None
    errors : list (per panel) of (m,) array-likes or None
        Given together with ``triangles`` or not at all.
    caller : str
        Prefix of the length-mismatch messages.

    Returns
    -------
    Pattern

    Raises
    ------
    ValueError
        When the lists differ in length, only one of ``triangles`` / ``errors`` is given, a
        loop is not a finite ``(k, 2)`` array, ``F`` is not an integer ``(m, 3)`` array
        indexing ``V``, or an error array is not ``(m,)``.
    """
    n = len(names)
    if len(outlines_before) != n or len(outlines_after) != n:
        raise ValueError(
            f"{caller}: {len(outlines_before)} 'before' panels, {len(outlines_after)} "
            f"'after' panels and {n} names"
        )
    if (triangles is None) != (errors is None):
        raise ValueError(f"{caller}: give both triangles and errors, or neither")
    if triangles is not None and (len(triangles) != n or len(errors) != n):
        raise ValueError(
            f"{caller}: {len(triangles)} triangle meshes, {len(errors)} error arrays and {n} names"
        )
    before = [_loops(ls, "outlines_before", p) for p, ls in enumerate(outlines_before)]
    after = [_loops(ls, "outlines_after", p) for p, ls in enumerate(outlines_after)]
    tris = bins = None
    if triangles is not None:
        meshes = [_mesh(t, e, p) for p, (t, e) in enumerate(zip(triangles, errors, strict=True))]
        tris = [(V, F) for V, F, _ in meshes]
        bins = [b for _, _, b in meshes]
    return Pattern(before, after, [_short(str(s)) for s in names], tris, bins)


def _short(name: str) -> str:
    """A panel name as drawn: at most ``PREVIEW_NAME_MAX`` characters (an ellipsis ends a
    shortened one), so that a long name cannot blow up the text layout."""
    from ptailor import tolerances as tol

    k = tol.PREVIEW_NAME_MAX
    return name if len(name) <= k else name[: k - 1] + "\u2026"
