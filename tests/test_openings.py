"""Openings: boundary loops of the drape named from geometry."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ptailor.model.frame import Frame
from ptailor.model.openings import Opening, openings

SHARED = Path(__file__).parents[2] / "shared"


# ---------------------------------------------------------------- generated meshes


def tube(radii, heights, n=48):
    """An open surface of revolution around y: ring j has radius radii[j] at heights[j]."""
    radii = np.asarray(radii, dtype=float)
    heights = np.asarray(heights, dtype=float)
    t = 2 * np.pi * np.arange(n) / n
    V = np.concatenate(
        [
            np.c_[r * np.cos(t), np.full(n, h), r * np.sin(t)]
            for r, h in zip(radii, heights, strict=True)
        ]
    )
    j, i = np.meshgrid(np.arange(len(radii) - 1), np.arange(n), indexing="ij")
    j, i = j.ravel(), i.ravel()
    a, b = j * n + i, j * n + (i + 1) % n
    c, d = a + n, b + n
    F = np.concatenate([np.c_[a, c, b], np.c_[b, c, d]])
    return V, F


def holey_ellipsoid(axes, holes, nu=96, nv=64):
    """A lat-long ellipsoid with caps removed: holes = [(direction, angle_deg)].

    Directions are on the unit sphere before scaling by ``axes``; removed caps leave
    unreferenced vertices in V, as real exports do.
    """
    th = np.pi * np.arange(1, nv) / nv  # polar angle from +y, poles excluded
    ph = 2 * np.pi * np.arange(nu) / nu
    T, P = np.meshgrid(th, ph, indexing="ij")
    D = np.c_[(np.sin(T) * np.cos(P)).ravel(), np.cos(T).ravel(), (np.sin(T) * np.sin(P)).ravel()]
    D = np.vstack([D, [0, 1, 0], [0, -1, 0]])
    top, bot = len(D) - 2, len(D) - 1
    j, i = np.meshgrid(np.arange(nv - 2), np.arange(nu), indexing="ij")
    j, i = j.ravel(), i.ravel()
    a, b = j * nu + i, j * nu + (i + 1) % nu
    c, d = a + nu, b + nu
    last = (nv - 2) * nu
    k = np.arange(nu)
    F = np.concatenate(
        [
            np.c_[a, b, c],
            np.c_[b, d, c],
            np.c_[np.full(nu, top), (k + 1) % nu, k],
            np.c_[np.full(nu, bot), last + k, last + (k + 1) % nu],
        ]
    )
    cen = D[F].mean(axis=1)
    cen /= np.linalg.norm(cen, axis=1, keepdims=True)
    keep = np.ones(len(F), dtype=bool)
    for direction, angle in holes:
        u = np.asarray(direction, dtype=float)
        u /= np.linalg.norm(u)
        keep &= cen @ u < np.cos(np.radians(angle))
    return D * np.asarray(axes, dtype=float), F[keep]


def names(ops: list[Opening]) -> list[str]:
    return sorted(o.name for o in ops)


def by_name(ops: list[Opening]) -> dict[str, Opening]:
    return {o.name: o for o in ops}


def rotation(axis, angle):
    axis = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


# ---------------------------------------------------------------- frame


def test_body_frame_left_is_plus_x_for_y_up_z_front():
    R = Frame((0, 1, 0), (0, 0, 1)).matrix()
    np.testing.assert_allclose(R, np.eye(3), atol=1e-15)
    R = Frame((0, 0, 2), (0, -1, 0.3)).matrix()  # z up, -y front, front not orthogonal
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(R[1], [0, 0, 1])
    np.testing.assert_allclose(R[0], [1, 0, 0], atol=1e-12)


@pytest.mark.parametrize(
    ("up", "front"), [((0, 0, 0), (0, 0, 1)), ((0, 1, 0), (0, 2, 0)), ((np.nan, 1, 0), (0, 0, 1))]
)
def test_bad_frame_raises(up, front):
    V, F = tube([10, 10], [0, 20])
    with pytest.raises(ValueError):
        openings(V, F, frame=Frame(up, front))


# ---------------------------------------------------------------- generated garments


def test_cylinder_is_waist_and_hem():
    n, r = 48, 10.0
    V, F = tube([r, r, r, r], [0, 10, 20, 30], n=n)
    ops = openings(V, F, frame=Frame())
    assert names(ops) == ["hem", "waist"]
    o = by_name(ops)
    perimeter = n * 2 * r * np.sin(np.pi / n)
    assert o["hem"].length == pytest.approx(perimeter)
    assert o["waist"].length == pytest.approx(perimeter)
    np.testing.assert_allclose(o["hem"].centroid, [0, 0, 0], atol=1e-12)
    np.testing.assert_allclose(o["waist"].centroid, [0, 30, 0], atol=1e-12)
    np.testing.assert_array_equal(np.sort(o["hem"].loop), np.arange(n))
    assert o["hem"].loop.dtype.kind == "i"


def test_cone_skirt_and_no_faces():
    V, F = tube([40, 30, 20, 14], [0, 25, 50, 70])  # wide at the bottom
    o = by_name(openings(V, F, frame=Frame()))
    assert set(o) == {"hem", "waist"}
    assert o["hem"].centroid[1] == pytest.approx(0)
    assert o["waist"].centroid[1] == pytest.approx(70)
    assert o["hem"].length > o["waist"].length
    assert openings(V, np.zeros((0, 3), dtype=int), frame=Frame()) == []


def test_unreferenced_vertices_and_shifted_indices():
    V, F = tube([40, 30, 14], [0, 35, 70])
    junk = np.full((7, 3), 1e6)
    ops0 = openings(V, F, frame=Frame())
    ops1 = openings(np.vstack([junk, V]), F + 7, frame=Frame())
    assert [o.name for o in ops0] == [o.name for o in ops1]
    for a, b in zip(ops0, ops1, strict=True):
        np.testing.assert_array_equal(a.loop + 7, b.loop)
        np.testing.assert_allclose(a.centroid, b.centroid)


def test_other_frames_and_rotation():
    V, F = tube([40, 30, 14], [0, 35, 70])
    R = rotation([1, 2, 3], 0.7)
    up = R @ [0, 1, 0]
    o = by_name(openings(V @ R.T + [5, -3, 2], F, frame=Frame(up, R @ [0, 0, 1])))
    assert set(o) == {"hem", "waist"}
    assert (o["waist"].centroid - o["hem"].centroid) @ up == pytest.approx(70)
    # upside down: the names swap
    o2 = by_name(openings(V, F, frame=Frame(up=(0, -1, 0))))
    np.testing.assert_array_equal(o2["hem"].loop, o["waist"].loop)


def test_trousers():
    V, F = holey_ellipsoid(
        (20, 40, 12),
        [
            ((0, 1, 0), 35),
            ((np.sin(np.radians(25)), -np.cos(np.radians(25)), 0), 18),
            ((-np.sin(np.radians(25)), -np.cos(np.radians(25)), 0), 18),
        ],
    )
    o = by_name(openings(V, F, frame=Frame()))
    assert set(o) == {"waist", "leg_left", "leg_right"}
    assert o["leg_left"].centroid[0] > 5 > -5 > o["leg_right"].centroid[0]
    assert o["waist"].centroid[1] > 30
    # facing the other way (front = -z): the wearer's left is -x
    o = by_name(openings(V, F, frame=Frame(front=(0, 0, -1))))
    assert o["leg_left"].centroid[0] < 0 < o["leg_right"].centroid[0]


def _armholes(extra=()):
    c, s = np.cos(np.radians(35)), np.sin(np.radians(35))
    return [((0, 1, 0), 25), ((c, s, 0), 18), ((-c, s, 0), 18), *extra]


def test_sleeveless_top():
    V, F = holey_ellipsoid((20, 35, 12), _armholes([((0, -1, 0), 45)]))
    o = by_name(openings(V, F, frame=Frame()))
    assert set(o) == {"hem", "neckline", "armhole_left", "armhole_right"}
    assert o["armhole_left"].centroid[0] > 0 > o["armhole_right"].centroid[0]
    assert o["neckline"].centroid[1] > 30 > -20 > o["hem"].centroid[1]


def test_jumpsuit_and_unnamed_loop():
    t = np.radians(25)
    legs = [((np.sin(t), -np.cos(t), 0), 18), ((-np.sin(t), -np.cos(t), 0), 18)]
    V, F = holey_ellipsoid((20, 60, 12), _armholes(legs))
    o = by_name(openings(V, F, frame=Frame()))
    assert set(o) == {"neckline", "armhole_left", "armhole_right", "leg_left", "leg_right"}
    # a pocket-like hole at the front fits no rule
    V, F = holey_ellipsoid((20, 35, 12), _armholes([((0, -1, 0), 45), ((0, -0.3, 1), 8)]))
    ops = openings(V, F, frame=Frame())
    assert names(ops) == ["armhole_left", "armhole_right", "hem", "neckline", "opening_4"]
    assert ops[4].name == "opening_4" and ops[4].centroid[2] > 10


# ---------------------------------------------------------------- real garments


def read_obj(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Minimal OBJ reader: ``v`` positions and the ``v`` index of triangle ``f`` lines."""
    V, F = [], []
    with open(path) as fh:
        for line in fh:
            if line.startswith("v "):
                V.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                F.append([int(tok.split("/")[0]) - 1 for tok in line.split()[1:4]])
    return np.array(V), np.array(F, dtype=np.int64)


@pytest.fixture(scope="module")
def garment():
    cache: dict[str, tuple[np.ndarray, np.ndarray]] = {}

    def load(rel: str):
        path = SHARED / "garments" / rel
        if not path.exists():
            pytest.skip(f"{path} not available")
        if rel not in cache:
            cache[rel] = read_obj(path)
        return cache[rel]

    return load


# name -> (loop size, length, centroid), checked by hand against the loops of each file
REAL = {
    "gpg_tee6/tee6_sim.obj": {
        "hem": (52, 310.9, (-0.2, -72.0, 3.6)),
        "neckline": (29, 158.9, (0.0, 77.6, -0.5)),
        "cuff_left": (20, 100.3, (87.9, 58.9, -7.3)),
        "cuff_right": (20, 100.2, (-87.7, 58.0, -8.7)),
    },
    "diffavatar/tshirt.obj": {
        "hem": (53, 101.5, (0.0, 103.5, -4.4)),
        "neckline": (26, 48.9, (-0.4, 163.7, -6.0)),
        "cuff_left": (20, 34.9, (33.5, 137.0, -6.0)),
        "cuff_right": (20, 35.0, (-33.2, 136.2, -5.5)),
    },
    "diffavatar/longsleeve_initial.obj": {
        "hem": (60, 116.9, (-0.2, 76.0, -3.8)),
        "neckline": (24, 40.4, (0.0, 135.6, 0.4)),
        "cuff_left": (16, 31.5, (38.2, 106.5, -1.0)),
        "cuff_right": (16, 31.6, (-37.4, 107.0, -1.5)),
    },
    "diffavatar/dress_initial.obj": {
        "hem": (189, 341.2, (-1.9, 13.8, -7.7)),
        "neckline": (62, 115.2, (-1.7, 124.7, -7.2)),
        "armhole_left": (36, 64.2, (10.7, 122.8, -6.7)),
        "armhole_right": (36, 66.5, (-14.6, 122.6, -8.5)),
    },
}


@pytest.mark.parametrize("rel", sorted(REAL))
def test_real_garments(garment, rel):
    V, F = garment(rel)
    ops = openings(V, F, frame=Frame())
    got = by_name(ops)
    assert set(got) == set(REAL[rel])
    for name, (k, length, centroid) in REAL[rel].items():
        o = got[name]
        assert len(o.loop) == k
        assert o.length == pytest.approx(length, abs=0.06)
        np.testing.assert_allclose(o.centroid, centroid, atol=0.06)
        assert np.isin(o.loop, F).all()


def test_tee6_mirrored_and_rotated(garment):
    V, F = garment("gpg_tee6/tee6_sim.obj")
    o = by_name(openings(V, F, frame=Frame()))
    # mirrored left-right (faces flipped to keep the orientation): the cuffs swap
    m = by_name(openings(V * [-1, 1, 1], F[:, ::-1], frame=Frame()))
    assert set(m) == set(o)
    np.testing.assert_array_equal(np.sort(m["cuff_left"].loop), np.sort(o["cuff_right"].loop))
    # the same garment stored z up and facing -y
    R = rotation([1, 0, 0], np.pi / 2)  # y -> z, z -> -y
    r = by_name(openings(V @ R.T, F, frame=Frame((0, 0, 1), (0, -1, 0))))
    for name in o:
        np.testing.assert_array_equal(r[name].loop, o[name].loop)
        np.testing.assert_allclose(r[name].centroid, R @ o[name].centroid, atol=1e-9)


# ---------------------------------------------------------------- non-manifold drapes


def sew_strip(V, F, line, width, *, flat, n_w=2):
    """Sew a strip onto the drape along ``line`` (a path of mesh edges): a T-seam.

    The strip's long edge is ``line`` itself (its drape edges are then used by three faces);
    it stands out along the surface normal (a fin) or, ``flat``, lies on the surface
    towards +x (a placket), 0.3 above it.
    """
    P = V[line]
    nrm = P / np.linalg.norm(P, axis=1, keepdims=True)
    w = width * np.arange(1, n_w + 1) / n_w
    if flat:
        new = P[:, None, :] + w[None, :, None] * np.array([1.0, 0, 0]) + 0.3 * nrm[:, None, :]
    else:
        new = P[:, None, :] + w[None, :, None] * nrm[:, None, :]
    k = len(line)
    idx = np.c_[line, len(V) + np.arange(k * n_w).reshape(k, n_w)]
    a, b, c, d = idx[:-1, :-1], idx[:-1, 1:], idx[1:, 1:], idx[1:, :-1]
    S = np.concatenate(
        [np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)]
    )
    return np.vstack([V, new.reshape(-1, 3)]), np.vstack([F, S])


@pytest.mark.parametrize("flat", [False, True])
@pytest.mark.parametrize("from_neck", [True, False])
def test_placket_keeps_the_neckline(flat, from_neck):
    """A strip sewn down the front (edges of three faces) adds one open opening only."""
    V, F = holey_ellipsoid((20, 35, 12), _armholes([((0, -1, 0), 45)]))
    base = openings(V, F, frame=Frame())
    nu = 96
    col = np.arange(63) * nu + nu // 4  # the front meridian (+z)
    col = col[np.isin(col, F)]
    line = col[:12] if from_neck else col[4:14]
    V2, F2 = sew_strip(V, F, line, 3.0, flat=flat)
    ref = None
    for seed in range(4):
        p = np.random.default_rng(seed).permutation(len(F2))
        ops = openings(V2, F2[p], frame=Frame())
        got = [(o.name, o.loop.tolist(), o.closed) for o in ops]
        ref = got if ref is None else ref
        assert got == ref
    o = by_name(ops)
    for b in base:  # the garment's own openings are unchanged
        assert o[b.name].loop.tolist() == b.loop.tolist()
        assert o[b.name].length == pytest.approx(b.length)
    extra = [x for x in ops if x.name not in by_name(base)]
    assert len(extra) == 1 and not extra[0].closed and extra[0].name.startswith("opening_")
    # its length is the strip's free edge: both ends and the far long edge
    k = len(line)
    new = V2[len(V) :].reshape(k, 2, 3)
    chain = np.vstack([V[line[0]], new[0], new[1:-1, 1], new[-1, ::-1], V[line[-1]]])
    free = np.linalg.norm(np.diff(chain, axis=0), axis=1).sum()
    assert extra[0].length == pytest.approx(free, rel=1e-12)
    assert {int(extra[0].loop[0]), int(extra[0].loop[-1])} == {int(line[0]), int(line[-1])}
    assert all(x.length > 0 for x in ops)


def test_bow_tie_openings_are_simple_and_nonzero():
    """Two tubes touching at one rim vertex: a non-manifold boundary vertex."""
    V1, F1 = tube([10, 10], [0, 20], n=16)
    V2, F2 = tube([10, 10], [20, 40], n=16)
    V2 = V2 + (V1[16 + 8] - V2[0])  # tube 2's bottom vertex 0 on tube 1's top vertex 24
    remap = np.r_[16 + 8, len(V1) + np.arange(len(V2) - 1)]
    V = np.vstack([V1, V2[1:]])
    F = np.vstack([F1, remap[F2]])
    ref = None
    for seed in range(4):
        p = np.random.default_rng(seed).permutation(len(F))
        ops = openings(V, F[p], frame=Frame())
        got = [(o.name, o.loop.tolist()) for o in ops]
        ref = got if ref is None else ref
        assert got == ref
        assert len(ops) == 4
        for o in ops:
            assert o.closed and o.length > 0 and len(np.unique(o.loop)) == len(o.loop) == 16


@pytest.mark.parametrize("shift", [(100.0, 0.0, 3.0), (-250.0, 17.0, 0.5), (1e4, 0.0, 0.0)])
def test_a_loop_touching_the_centre_line_keeps_its_side_wherever_the_garment_is(shift):
    """The T-seam tube's strip ends on the centre line: which side its loop lies on once
    followed the rounding of the garment's position (moved by (100, 0, 3): 'neckline' and
    'armhole_right' in place of 'waist' and 'opening_2')."""
    from ptailor.samples import tseam_tube

    g = tseam_tube()
    want = [o.name for o in openings(g.V3, g.F3, F2=g.F2, frame=Frame())]
    got = [o.name for o in openings(g.V3 + np.array(shift), g.F3, F2=g.F2, frame=Frame())]
    assert got == want
