"""Pattern pieces: point location, carrying marks, outline offsets, piece matching."""

from __future__ import annotations

import numpy as np
import pytest

from ptailor.errors import PtailorError
from ptailor.method.transfer import carry_points, locate_points
from ptailor.model.frame import Frame
from ptailor.model.garment import panels
from ptailor.model.offset import offset_closed
from ptailor.model.pieces import Piece
from ptailor.model.polyline import corners, signed_area
from ptailor.pieces.carry import carry_piece
from ptailor.pieces.draw import mesh_pieces
from ptailor.pieces.match import PieceMatch, match_pieces
from ptailor.pieces.plan import piece_plan
from ptailor.samples import cone_skirt, lantern_sleeve


def _grid(nx: int = 6, ny: int = 4, seed: int = 0):
    rng = np.random.default_rng(seed)
    x, y = np.meshgrid(np.linspace(0, 10, nx), np.linspace(0, 6, ny))
    V = np.stack([x.ravel(), y.ravel()], 1)
    V[(V[:, 0] > 0) & (V[:, 0] < 10) & (V[:, 1] > 0) & (V[:, 1] < 6)] += rng.uniform(
        -0.3, 0.3, (((nx - 2) * (ny - 2)), 2)
    )
    i = np.arange(nx * ny).reshape(ny, nx)
    a, b, c, d = i[:-1, :-1].ravel(), i[:-1, 1:].ravel(), i[1:, 1:].ravel(), i[1:, :-1].ravel()
    F = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    return V, F


def test_points_inside_are_found_with_their_barycentric_coordinates():
    V, F = _grid()
    rng = np.random.default_rng(1)
    f = rng.integers(0, len(F), 50)
    w = rng.dirichlet([1, 1, 1], 50)
    P = np.einsum("ki,kij->kj", w, V[F[f]])
    loc = locate_points(V, F, P)
    assert np.all(loc.distance == 0)
    np.testing.assert_allclose(carry_points(V, F, loc), P, atol=1e-12)
    np.testing.assert_allclose(loc.bary.sum(1), 1.0)
    assert np.all(loc.bary >= -1e-9)


def test_carrying_follows_any_affine_map_also_just_outside_the_mesh():
    V, F = _grid()
    P = np.array([[2.0, 3.0], [5.0, -0.2], [10.3, 4.0], [0.0, 6.0]])  # two just outside
    A = np.array([[1.3, 0.4], [-0.2, 0.8]])
    t = np.array([5.0, -2.0])
    loc = locate_points(V, F, P)
    assert loc.distance[1] == pytest.approx(0.2) and loc.distance[2] == pytest.approx(0.3)
    np.testing.assert_allclose(carry_points(V @ A.T + t, F, loc), P @ A.T + t, atol=1e-12)


def test_location_is_restricted_to_the_given_faces():
    V, F = _grid()
    half = np.flatnonzero(V[F].mean(1)[:, 0] < 5)
    loc = locate_points(V, F, np.array([[8.0, 3.0]]), faces=half)
    assert loc.face[0] in set(half.tolist()) and loc.distance[0] > 1.5


def test_offset_of_a_rectangle_is_the_rectangle_grown_by_d_with_square_corners():
    R = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 5.0], [0.0, 5.0]])
    for P in (R, R[::-1]):
        grown = offset_closed(P, 1.5)
        assert len(grown) == 4
        np.testing.assert_allclose(np.sort(grown, axis=0)[[0, -1]], [[-1.5, -1.5], [11.5, 6.5]])
        assert np.sign(signed_area(grown)) == np.sign(signed_area(P))
        assert abs(signed_area(grown)) == pytest.approx(13 * 8)


def test_offset_of_a_circle_has_the_radius_plus_d_and_sharp_points_are_clipped():
    t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    C = 10 * np.stack([np.cos(t), np.sin(t)], 1)
    r = np.linalg.norm(offset_closed(C, 1.0), axis=1)
    assert r.min() > 10.99 and r.max() < 11.01
    spike = np.array([[0.0, 0.0], [20.0, 0.0], [0.0, 1.0]])  # a 2.9 degree point at (20, 0)
    tip = np.array([20.0, 0.0])
    u = tip / 20 + (tip - spike[2]) / np.linalg.norm(tip - spike[2])
    u /= np.linalg.norm(u)  # the point's bisector, outward
    for d in (1.0, np.array([1.0, 1.0 + 1e-9, 1.0])):  # GEOS's buffer; the per-edge union
        bev = offset_closed(spike, d)
        assert len(bev) == 4  # clipped: two points at the spike
        reach = (bev - tip) @ u
        assert reach.max() == pytest.approx(4.0, abs=1e-6)  # the mitre limit, 4 allowances


def test_corners_of_a_rectangle_and_none_on_a_circle():
    R = np.array([[0.0, 0.0], [5.0, 0.0], [10.0, 0.0], [10.0, 5.0], [0.0, 5.0]])
    assert corners(R).tolist() == [True, False, True, True, True]
    t = np.linspace(0, 2 * np.pi, 100, endpoint=False)
    assert not corners(np.stack([np.cos(t), np.sin(t)], 1)).any()


def _pieces(g):
    plist = panels(g)
    return plist, mesh_pieces(g.V2, g.F2, plist)


def test_mesh_pieces_outline_the_panels_counter_clockwise_with_a_vertical_grain_line():
    g = lantern_sleeve()
    plist, pieces = _pieces(g)
    assert [pc.name for pc in pieces] == [p.name for p in plist]
    for pc in pieces:
        assert signed_area(pc.outline) > 0
        assert pc.turn.sum() == 4  # the sleeve's and the cuff's rectangles
        d = pc.grain[1] - pc.grain[0]
        assert d[0] == 0 and d[1] > 0


def test_pieces_match_their_panels_by_position():
    g = cone_skirt()
    plist, pieces = _pieces(g)
    m = match_pieces(pieces, g.V2, g.F2, plist)
    assert [x.panel for x in m] == [p.index for p in plist]
    assert all(x.how == "position" and x.residual < 1e-9 for x in m)


@pytest.mark.slow
def test_moved_and_flipped_pieces_match_by_shape_with_the_right_rigid_map():
    g = lantern_sleeve()
    plist, pieces = _pieces(g)
    c, s = np.cos(0.7), np.sin(0.7)
    moves = [
        (np.array([[c, -s], [s, c]]), np.array([300.0, -40.0])),
        (np.array([[-1.0, 0.0], [0.0, 1.0]]), np.array([-500.0, 10.0])),  # a reflection
    ]
    moved = []
    for pc, (R, t) in zip(pieces, moves, strict=True):
        moved.append(Piece(name=pc.name, outline=pc.outline @ R.T + t, grain=pc.grain @ R.T + t))
    m = match_pieces(moved, g.V2, g.F2, plist)
    for pc, mv, x in zip(pieces, moved, m, strict=True):
        assert x.how == "shape"
        np.testing.assert_allclose(x.to_panel(mv.grain), pc.grain, atol=1e-6)
    assert np.linalg.det(m[1].R) < 0


def _two_overlapping_squares():
    """Two identical square panels at one spot of the pattern, named "left" and "right"."""
    from ptailor.model.garment import Panel

    V, F = _grid(4, 4)
    V2 = np.concatenate([V, V])
    F2 = np.concatenate([F, F + len(V)])
    m = len(F)
    plist = [
        Panel(0, "left", np.arange(m), np.arange(len(V)), False),
        Panel(1, "right", np.arange(m, 2 * m), np.arange(len(V), 2 * len(V)), False),
    ]
    return V2, F2, plist


@pytest.mark.parametrize("shift", [0.0, 500.0])  # where they lie (position), moved (shape)
def test_tied_pieces_go_to_the_panels_with_their_names(shift):
    V2, F2, plist = _two_overlapping_squares()
    outline = mesh_pieces(V2, F2, plist)[0].outline + shift
    for names in (["right", "left"], ["left", "right"]):
        pieces = [Piece(name=n, outline=outline.copy()) for n in names]
        m = match_pieces(pieces, V2, F2, plist)
        assert [plist[x.panel].name for x in m] == names
        assert {x.how for x in m} == {"position" if shift == 0 else "shape"}


def test_a_piece_that_matches_no_panel_is_an_error_naming_it():
    g = lantern_sleeve()
    plist, _ = _pieces(g)
    stray = Piece(name="pocket", outline=np.array([[0.0, 0], [3, 0], [3, 2], [0, 2]]) + 900)
    with pytest.raises(PtailorError, match=r"'pocket'.*match no panel"):
        match_pieces([stray], g.V2, g.F2, plist, path="p.dxf")


def test_carrying_under_a_uniform_scale_scales_every_mark():
    g = lantern_sleeve()
    plist, pieces = _pieces(g)
    p = plist[0]
    pc = pieces[0]
    pc = Piece(
        name=pc.name,
        outline=pc.outline,
        turn=pc.turn,
        notches=pc.outline[[3, 10]],
        grain=pc.grain,
        internal=(pc.outline[[0, 5]] * 0.5 + pc.outline.mean(0) * 0.5,),
        drills=pc.outline.mean(0, keepdims=True),
    )
    k = 1.25
    ident = PieceMatch(0, p.index, "position", np.eye(2), np.zeros(2), 0.0)
    out = carry_piece(
        pc, ident, V2=g.V2, F2=g.F2, faces=p.faces, V2_new=g.V2 * k, unchanged=True
    ).piece
    for a, b in [
        (out.outline, pc.outline),
        (out.notches, pc.notches),
        (out.grain, pc.grain),
        (out.internal[0], pc.internal[0]),
        (out.drills, pc.drills),
    ]:
        np.testing.assert_allclose(a, b * k, atol=1e-9)


def test_the_plan_draws_pieces_from_the_mesh_without_a_pattern_file():
    g = cone_skirt()
    plan = piece_plan(g, panels(g))
    assert not any(plan.from_file) and len(plan.pieces) == len(panels(g))
    assert plan.units == g.units


def test_the_plan_takes_the_panels_of_the_garments_cached_structure_by_default():
    from ptailor.model.structure import structure

    g = cone_skirt()
    plan = piece_plan(g)
    assert plan.panels == tuple(structure(g).panels)
    given = piece_plan(g, panels(g))
    assert [pc.name for pc in plan.pieces] == [pc.name for pc in given.pieces]
    for a, b in zip(plan.pieces, given.pieces, strict=True):
        np.testing.assert_array_equal(a.outline, b.outline)


def test_grain_follows_the_body_up_axis_whatever_the_layout():
    from ptailor.pieces.draw import grain_directions

    g = cone_skirt()
    plist = panels(g)
    np.testing.assert_allclose(
        grain_directions(g.V2, g.F2, g.V3, g.F3, plist, frame=Frame()), [[0, 1], [0, 1]], atol=1e-6
    )
    a = np.radians(30.0)
    R = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    turned = grain_directions(g.V2 @ R.T, g.F2, g.V3, g.F3, plist, frame=Frame())
    np.testing.assert_allclose(turned, [R @ [0, 1], R @ [0, 1]], atol=1e-6)
    # a garment lying on its side (up = x) has its grain across the same pattern
    side = grain_directions(
        g.V2, g.F2, g.V3[:, [1, 0, 2]], g.F3, plist, frame=Frame(up=(1.0, 0.0, 0.0))
    )
    np.testing.assert_allclose(side, [[0, 1], [0, 1]], atol=1e-6)
    pieces = mesh_pieces(g.V2 @ R.T, g.F2, plist, grain=turned)
    d = np.diff(pieces[0].grain, axis=0)[0]
    np.testing.assert_allclose(d / np.linalg.norm(d), R @ [0, 1], atol=1e-9)


def test_a_sleeve_in_t_pose_keeps_its_grain_along_the_arm():
    from ptailor.pieces.draw import grain_directions

    g = lantern_sleeve()
    plist = panels(g)
    T = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # the arm along -x
    got = grain_directions(g.V2, g.F2, g.V3 @ T.T, g.F3, plist, frame=Frame())
    np.testing.assert_allclose(np.abs(got), [[0, 1], [0, 1]], atol=1e-6)


def test_balance_notches_of_both_sides_of_a_seam_meet_in_the_drape():
    """The sleeve is 28 wide, the elastic cuff 40: the seam's middle notch sits at 14 on one
    and at 20 on the other, the same point of the drape."""
    g = lantern_sleeve()
    plist = panels(g)
    pieces = {pc.name: pc for pc in mesh_pieces(g.V2, g.F2, plist, F3=g.F3, V3=g.V3)}
    sleeve, cuff = pieces["sleeve"], pieces["cuff"]
    s_low = sleeve.notches[np.argmin(sleeve.notches[:, 1])]
    c_top = cuff.notches[np.argmax(cuff.notches[:, 1])]
    x0 = sleeve.outline[:, 0].min()
    assert s_low[0] - x0 == pytest.approx(14.0) and c_top[0] == pytest.approx(20.0)

    def on_drape(q):
        loc = locate_points(g.V2, g.F2, q[None])
        return np.einsum("ki,kij->kj", loc.bary, g.V3[g.F3[loc.face]])[0]

    np.testing.assert_allclose(on_drape(s_low), on_drape(c_top), atol=1e-9)
