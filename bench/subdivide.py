"""Subdivide a garment OBJ: every triangle split into four at its edge midpoints, drape and
pattern alike, groups kept.

    python bench/subdivide.py IN.obj OUT.obj [--levels 2]

One level turns each triangle ``(a, b, c)`` into ``(a, ab, ca)``, ``(ab, b, bc)``,
``(ca, bc, c)`` and ``(ab, bc, ca)``, in ``v`` and in ``vt`` with the same corners, so the
drape and the pattern stay one mesh seen twice: the same garment at four times the
triangles. A midpoint is one new vertex per distinct edge of ``F3`` (welded seams stay
welded) and, separately, per distinct edge of ``F2`` (each side of a seam gets its own
pattern midpoint). Positions are linear interpolations, so the subdivided garment is the
same surface: an edit of it must give the same pattern as the edit of the original at the
original vertices. ``v`` records that no face uses are kept (their indices do not move).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np


def midpoint_subdivision(V: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One level of midpoint subdivision of one mesh.

    Parameters
    ----------
    V : (n, d) float array
    F : (m, 3) int array

    Returns
    -------
    W : (n + e, d) float array
        ``V`` followed by one midpoint per distinct edge.
    G : (4m, 3) int array
        Triangle ``4i + k`` is the ``k``-th child of triangle ``i`` (corner children 0-2,
        the middle one 3), with ``F``'s orientation.
    E : (e, 2) int array
        The two old vertices of each new one (``W[n + j] = (V[E[j, 0]] + V[E[j, 1]]) / 2``).
    """
    F = np.asarray(F, dtype=np.int64)
    n, m = len(V), len(F)
    a, b, c = F.T
    half = np.stack([np.stack([a, b], 1), np.stack([b, c], 1), np.stack([c, a], 1)], 1)
    key = np.sort(half.reshape(-1, 2), axis=1)  # (3m, 2): edges ab, bc, ca of each triangle
    E, inv = np.unique(key, axis=0, return_inverse=True)
    mid = n + inv.reshape(m, 3)  # midpoint of ab, bc, ca
    ab, bc, ca = mid.T
    G = np.stack(
        [np.stack([a, ab, ca], 1), np.stack([ab, b, bc], 1),
         np.stack([ca, bc, c], 1), np.stack([ab, bc, ca], 1)],
        axis=1,
    ).reshape(-1, 3)  # fmt: skip
    W = np.concatenate([V, 0.5 * (V[E[:, 0]] + V[E[:, 1]])])
    return W, G, E


def subdivide_garment(
    V3: np.ndarray, F3: np.ndarray, V2: np.ndarray, F2: np.ndarray, *, levels: int = 1
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``levels`` midpoint subdivisions of drape and pattern together.

    Returns
    -------
    V3, F3, V2, F2 : the subdivided garment (the first ``len(V3)`` / ``len(V2)`` vertices
        are the original ones, unmoved)
    parent : (m * 4**levels,) int array
        The original triangle of each new one.
    """
    parent = np.arange(len(F3))
    for _ in range(levels):
        V3, F3, _ = midpoint_subdivision(V3, F3)
        V2, F2, _ = midpoint_subdivision(V2, F2)
        parent = np.repeat(parent, 4)
    return V3, F3, V2, F2, parent


def subdivide_obj(src: str | Path, dst: str | Path, *, levels: int = 1) -> int:
    """Read ``src``, subdivide it ``levels`` times, write ``dst`` (the file's groups kept when
    they are contiguous); return the number of triangles written."""
    from ptailor.formats.obj import read_obj
    from unweld import write_derived

    m = read_obj(src)
    if m.fvt is None:
        raise SystemExit(f"{src}: no vt indices in the faces (no pattern to subdivide)")
    V3, F3, V2, F2, parent = subdivide_garment(m.v, m.fv, m.vt, m.fvt, levels=levels)
    write_derived(
        dst, m, V3=V3, F3=F3, V2=V2, F2=F2, parent=parent,
        header=[*m.header, f"subdivided {levels}x (1 -> {4**levels}) from {Path(src).name} "
                "by bench/subdivide.py"],
    )  # fmt: skip
    return len(F3)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("src")
    ap.add_argument("dst")
    ap.add_argument("--levels", type=int, default=1, help="1: 4x the triangles, 2: 16x")
    a = ap.parse_args()
    n = subdivide_obj(a.src, a.dst, levels=a.levels)
    print(f"{a.dst}: {n} triangles")


if __name__ == "__main__":
    main()
