"""Make the bodies ptailor ships (``src/ptailor/verify/bodies``) from GarmentCode's mean body.

    python bench/make_bodies.py [--shared ../shared] [--faces 14000]

Reads ``bodies/mean_all.obj`` (A-pose) and ``bodies/mean_all_tpose.obj`` (T-pose) of the
shared data (MIT, GarmentCode; metres, y up, z front, feet at 0, 23,752 vertices), decimates
each with pymeshlab's quadric edge collapse to ``--faces`` triangles keeping the topology
(closed, one piece: 7,002 vertices at 14,000), and writes ``body_apose.npz`` and
``body_tpose.npz`` (float32 vertices ``V``, int32 faces ``F``) beside the licence.
"""

from __future__ import annotations

import argparse
import shutil
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
OUT = HERE.parent / "src" / "ptailor" / "verify" / "bodies"


def main() -> None:
    import pymeshlab

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--shared", type=Path, default=HERE.parent.parent / "shared")
    ap.add_argument("--faces", type=int, default=14000)
    args = ap.parse_args()
    OUT.mkdir(parents=True, exist_ok=True)
    for src, pose in (("mean_all.obj", "a"), ("mean_all_tpose.obj", "t")):
        ms = pymeshlab.MeshSet()
        ms.load_new_mesh(str(args.shared / "bodies" / src))
        ms.meshing_decimation_quadric_edge_collapse(
            targetfacenum=args.faces, preservetopology=True, preservenormal=True, qualitythr=0.5
        )
        m = ms.current_mesh()
        V, F = m.vertex_matrix().astype(np.float32), m.face_matrix().astype(np.int32)
        np.savez_compressed(OUT / f"body_{pose}pose.npz", V=V, F=F)
        print(f"{pose}-pose: {len(V)} vertices, {len(F)} triangles")
    shutil.copy(args.shared / "bodies" / "LICENSE.MIT.txt", OUT / "LICENSE.MIT.txt")


if __name__ == "__main__":
    main()
