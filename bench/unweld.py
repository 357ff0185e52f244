"""Unweld a garment OBJ the way per-piece CAD exports come: each panel's drape vertices apart.

    python bench/unweld.py IN.obj OUT.obj [--every-vertex] [--shuffle SEED]

Every panel (a connected component of the pattern ``vt``) gets its own copy of each drape
vertex it uses, so panels share no ``v`` and seams are only coincident positions. The
pattern (``vt`` and the faces' ``vt`` indices) is written unchanged, so an unwelded garment
read with ``--weld auto`` must give the same seams, openings and adjusted pattern as the
original. ``--shuffle`` also permutes the new ``v`` records (a weld must not depend on the
order vertices come in).
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import numpy as np


def unweld(
    F3: np.ndarray,
    F2: np.ndarray,
    n2: int,
    *,
    every_vertex: bool = False,
    shuffle: int | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Split the drape so that no two panels share a drape vertex.

    Parameters
    ----------
    F3 : (m, 3) int array
        Drape triangles.
    F2 : (m, 3) int array
        Pattern triangles (panels are its connected components).
    n2 : int
        Number of pattern vertices.
    every_vertex : bool
        Split further: one drape vertex per pattern vertex (a panel's seam with itself, a
        dart, comes apart too).
    shuffle : int, optional
        Seed of a random permutation of the new drape vertices.

    Returns
    -------
    I : (k,) int array
        Old drape vertex of each new one (``V3_new = V3[I]``).
    G : (m, 3) int array
        The new drape triangles, indices into ``V3_new``.
    """
    from ptailor.geometry.labels import component_labels

    lab = F2.ravel() if every_vertex else np.repeat(component_labels(F2, n2), 3)
    # one new vertex per distinct (panel, old vertex) pair, in panel order
    keys = np.stack([lab, F3.ravel()], axis=1)
    uniq, inv = np.unique(keys, axis=0, return_inverse=True)
    I = uniq[:, 1]
    G = inv.reshape(-1, 3)
    if shuffle is not None:
        perm = np.random.default_rng(shuffle).permutation(len(I))  # new position of each
        J = np.empty_like(perm)
        J[perm] = np.arange(len(perm))
        I, G = I[J], perm[G]
    return I, G


def write_derived(
    dst: str | Path,
    m,
    *,
    V3: np.ndarray,
    F3: np.ndarray,
    V2: np.ndarray,
    F2: np.ndarray,
    parent: np.ndarray,
    header: list[str],
) -> None:
    """Write a garment made from the OBJ ``m`` (a :class:`ptailor.formats.obj.ObjMesh`):
    triangle ``i`` of ``F3``/``F2`` comes from ``m``'s face ``parent[i]`` and keeps its
    group when the file's groups are contiguous (``write_obj`` groups by panel); a file
    without groups is written without any."""
    from ptailor.formats.obj import write_obj

    grouped = bool(m.group_names) and bool(np.all(np.diff(m.face_group) >= 0))
    face_panel = np.maximum(m.face_group, 0)[parent] if grouped else np.zeros(len(F3), np.int64)
    write_obj(
        dst,
        V3=V3,
        F3=F3,
        V2=V2,
        F2=F2,
        face_panel=face_panel,
        panel_names=list(m.group_names) if grouped else ["-"],
        header=header,
    )
    if not grouped:  # the source names no groups: write none
        text = Path(dst).read_text()
        Path(dst).write_text(re.sub(r"(?m)^g -\n", "", text))


def unweld_obj(
    src: str | Path, dst: str | Path, *, every_vertex: bool = False, shuffle: int | None = None
) -> int:
    """Read ``src``, unweld its drape, write ``dst`` (one ``g`` group per panel kept as in the
    file when it has groups); return the number of drape vertices written."""
    from ptailor.formats.obj import read_obj

    m = read_obj(src)
    I, G = unweld(m.fv, m.fvt, len(m.vt), every_vertex=every_vertex, shuffle=shuffle)
    write_derived(
        dst, m, V3=m.v[I], F3=G, V2=m.vt, F2=m.fvt, parent=np.arange(len(G)),
        header=[f"unwelded from {Path(src).name} by bench/unweld.py"],
    )  # fmt: skip
    return len(I)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("src")
    ap.add_argument("dst")
    ap.add_argument("--shuffle", type=int, default=None, metavar="SEED")
    ap.add_argument("--every-vertex", action="store_true", help="one v per vt")
    a = ap.parse_args()
    n = unweld_obj(a.src, a.dst, every_vertex=a.every_vertex, shuffle=a.shuffle)
    print(f"{a.dst}: {n} drape vertices")


if __name__ == "__main__":
    main()
