"""Assertions that an adjusted garment is valid, and garments built for them (shared by the
edit tests)."""

from __future__ import annotations

import dataclasses
import sys

import numpy as np

from ptailor.geometry.topology import edge_keys, half_edges
from ptailor.geometry.triangles import signed_areas_2d, triangle_areas
from ptailor.model.garment import Garment, panels
from ptailor.model.seams import seams


def assert_valid(g: Garment, *, V2: np.ndarray | None = None) -> None:
    """Manifold drape, no zero-area or flipped triangles, consistent pattern orientation."""
    V2 = g.V2 if V2 is None else V2
    _, cnt = np.unique(edge_keys(half_edges(g.F3)), return_counts=True)
    assert cnt.max() <= 2, "non-manifold drape edge"
    diag = np.ptp(g.V3[np.unique(g.F3)], axis=0).max()
    assert triangle_areas(g.V3, g.F3).min() > 1e-12 * diag**2, "zero-area drape triangle"
    for p in panels(g):
        sa = signed_areas_2d(V2, g.F2[p.faces])
        sign = -1 if p.mirrored else 1
        assert np.all(sa * sign > 1e-12 * diag**2), f"flipped or zero-area triangle in {p.name}"


def seam_sides(g: Garment, V2: np.ndarray) -> list[tuple[float, float]]:
    """Both sides' lengths of every seam."""
    flab = np.empty(g.n_faces, dtype=np.int64)
    for p in panels(g):
        flab[p.faces] = p.index
    return [s.lengths(V2) for s in seams(g.F3, g.F2, flab)]


def assert_seams_equal(g: Garment, V2: np.ndarray, *, rtol: float = 1e-6) -> None:
    """Every seam's two sides have the same length."""
    for la, lb in seam_sides(g, V2):
        assert abs(la - lb) <= rtol * max(la, lb), (la, lb)


def adjust_sample_cli(tmp_path, step: str, *, sample: str = "cone_skirt"):
    """Run ``ptailor adjust`` on a generated sample with a one-step recipe; return the result."""
    from click.testing import CliRunner

    from ptailor.cli.main import cli
    from ptailor.samples.obj_text import sample_obj_text

    src = tmp_path / f"{sample}.obj"
    src.write_text(sample_obj_text(sample))
    rec = tmp_path / "r.yaml"
    rec.write_text(f"steps: [{step}]\n")
    return CliRunner().invoke(cli, ["adjust", str(src), str(rec), "-o", str(tmp_path / "o")])


def regrouped(g, grp, names):
    """Garment ``g`` with its faces in groups ``grp`` (``(m,)`` int, 0 keeping ``g``'s
    pattern vertices) named ``names``: each other group gets pattern vertices of its own,
    moved apart (10 cm up per group), so the groups are panels sewn where they meet."""
    import dataclasses

    F2, V2, n = g.F2.copy(), [g.V2], len(g.V2)
    for k in range(1, int(grp.max()) + 1):
        fk = np.flatnonzero(grp == k)
        u, inv = np.unique(g.F2[fk], return_inverse=True)
        V2.append(g.V2[u] + np.array([0.0, 10.0 * k]))
        F2[fk] = (n + inv).reshape(-1, 3)
        n += len(u)
    return dataclasses.replace(
        g, V2=np.concatenate(V2), F2=F2, face_group=grp, group_names=tuple(names)
    )


def subdivided(g: Garment, levels: int = 1) -> Garment:
    """``g`` with every triangle split in four ``levels`` times (bench/subdivide.py), drape and
    pattern alike: the same garment at ``4 ** levels`` times the triangles."""
    from tests.conftest import ROOT

    if str(ROOT / "bench") not in sys.path:
        sys.path.insert(0, str(ROOT / "bench"))
    from subdivide import subdivide_garment

    V3, F3, V2, F2, parent = subdivide_garment(g.V3, g.F3, g.V2, g.F2, levels=levels)
    return dataclasses.replace(g, V3=V3, F3=F3, V2=V2, F2=F2, face_group=g.face_group[parent])
