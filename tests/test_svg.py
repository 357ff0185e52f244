"""SVG of a pattern before and after adjustment."""

from __future__ import annotations

import itertools
import re
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from ptailor.formats.preview import NAN_COLOUR, bin_colour, error_bins
from ptailor.formats.svg import pattern_svg

NS = {"s": "http://www.w3.org/2000/svg"}


def circle(c, r, k=40):
    t = 2 * np.pi * np.arange(k) / k
    return np.c_[c[0] + r * np.cos(t), c[1] + r * np.sin(t)]


def rect(x0, y0, w, h):
    return np.array([[x0, y0], [x0 + w, y0], [x0 + w, y0 + h], [x0, y0 + h]], dtype=float)


@pytest.fixture
def pattern():
    """Three panels, one with a hole, in overlapping pattern coordinates (as packed atlases)."""
    rng = np.random.default_rng(0)
    before = [
        [rect(0, 0, 40, 60), circle((20, 40), 5)],  # a panel with a hole
        [rect(-10, 5, 30, 20)],
        [circle((5, 5), 12) + rng.normal(0, 0.2, (40, 2))],
    ]
    after = [
        [rect(-1, 0, 42, 57), circle((20, 38), 5.5)],
        [rect(-10, 5, 33, 20)],
        [circle((5, 5), 13)],
    ]
    names = ["front", "sleeve & cuff <L>", "collar"]
    return before, after, names


def points(d: str) -> np.ndarray:
    return np.array(re.findall(r"(-?\d+\.\d+),(-?\d+\.\d+)", d), dtype=float)


def parse(svg: str):
    root = ET.fromstring(svg)
    assert root.tag == "{http://www.w3.org/2000/svg}svg"
    return root


def test_structure(pattern):
    before, after, names = pattern
    root = parse(pattern_svg(before, after, names, title="Tee & co"))
    groups = root.findall("s:g[@class='panel']", NS)
    assert len(groups) == 3
    for g, b, a, name in zip(groups, before, after, names, strict=True):
        paths = g.findall("s:path", NS)
        dashed = [p for p in paths if p.get("stroke-dasharray")]
        solid = [p for p in paths if not p.get("stroke-dasharray") and p.get("stroke") != "none"]
        assert len(dashed) == len(b) and len(solid) == len(a)
        assert all(p.get("class") == "before" for p in dashed)
        assert all(p.get("class") == "after" for p in solid)
        # the original is drawn first, beneath the adjusted outline
        assert paths.index(dashed[-1]) < paths.index(solid[0])
        assert [t.text for t in g.findall("s:text", NS)] == [name]
        for path, loop in zip(dashed + solid, b + a, strict=True):
            assert len(points(path.get("d"))) == len(loop)
            assert path.get("d").endswith("Z")
    texts = [t.text for t in root.iter("{http://www.w3.org/2000/svg}text")]
    assert "10 cm" in texts and "Tee & co" in texts
    assert root.find("s:title", NS).text == "Tee & co"


def test_coordinates_translated_and_flipped(pattern):
    before, after, names = pattern
    root = parse(pattern_svg(before, after, names))
    for g, b, a in zip(root.findall("s:g[@class='panel']", NS), before, after, strict=True):
        paths = [p for p in g.findall("s:path", NS) if p.get("class") in ("before", "after")]
        loops = b + a
        Q = np.concatenate([points(p.get("d")) for p in paths])
        P = np.concatenate(loops)
        # svg = (x, -y) + one shift per panel, to 3 decimals
        shift = Q - P * [1, -1]
        np.testing.assert_allclose(shift, shift[0] + np.zeros_like(shift), atol=2e-3)


def test_viewbox_contains_everything_and_cells_do_not_overlap(pattern):
    before, after, names = pattern
    root = parse(pattern_svg(before, after, names))
    x0, y0, w, h = map(float, root.get("viewBox").split())
    assert (x0, y0) == (0, 0)
    boxes = []
    for g in root.findall("s:g[@class='panel']", NS):
        Q = np.concatenate([points(p.get("d")) for p in g.findall("s:path", NS)])
        t = g.find("s:text", NS)
        Q = np.vstack([Q, [[float(t.get("x")), float(t.get("y"))]]])
        assert (Q >= 0).all() and (Q[:, 0] <= w).all() and (Q[:, 1] <= h).all()
        boxes.append((Q.min(axis=0), Q.max(axis=0)))
    for i in range(len(boxes)):
        for j in range(i + 1, len(boxes)):
            (a0, a1), (b0, b1) = boxes[i], boxes[j]
            assert (a1 < b0).any() or (b1 < a0).any(), (i, j)
    bar = root.find("s:g[@id='scale-bar']", NS)
    for p in bar.findall("s:path", NS):
        Q = points(p.get("d"))
        assert (Q >= 0).all() and (Q[:, 0] <= w).all() and (Q[:, 1] <= h).all()


@pytest.mark.parametrize(
    ("units", "css", "label", "length"),
    [("cm", "cm", "10 cm", 10), ("mm", "mm", "100 mm", 100), ("m", "cm", "0.1 m", 10),
     ("in", "in", "4 in", 4)],
)  # fmt: skip
def test_real_size(pattern, units, css, label, length):
    before, after, names = pattern
    k = 0.01 if units == "m" else 1.0  # the same 1:1 print for a pattern in metres
    scaled = [[L * k for L in p] for p in before], [[L * k for L in p] for p in after]
    root = parse(pattern_svg(*scaled, names, units=units))
    _, _, w, h = map(float, root.get("viewBox").split())
    assert root.get("width") == f"{w:.3f}{css}"  # user units are the css unit
    assert root.get("height") == f"{h:.3f}{css}"
    bar = root.find("s:g[@id='scale-bar']", NS)
    assert bar.find("s:text", NS).text == label
    ends = points(bar.find("s:path", NS).get("d"))[:2]
    assert ends[1, 0] - ends[0, 0] == pytest.approx(length, abs=2e-3)
    if units == "m":
        # metres are drawn in cm: the same document as the pattern in cm, but the bar's label
        cm = pattern_svg(before, after, names, units="cm")
        assert cm.replace(">10 cm<", ">0.1 m<") == pattern_svg(*scaled, names, units="m")


def test_unknown_units_get_a_round_bar(pattern):
    before, after, names = pattern
    scaled = [[L / 100 for L in p] for p in before], [[L / 100 for L in p] for p in after]
    root = parse(pattern_svg(*scaled, names, units="uv"))
    assert re.fullmatch(r"\d+\.\d{3}", root.get("width"))
    label = root.find("s:g[@id='scale-bar']/s:text", NS).text
    assert label.endswith(" uv") and float(label.split()[0]) in (0.1, 0.2, 0.5)
    # drawn 1000 times larger (largest panel 0.6 uv -> 600 user units): readable font sizes
    assert 100 <= float(root.get("width")) <= 10000
    ends = points(root.find("s:g[@id='scale-bar']/s:path", NS).get("d"))[:2]
    assert ends[1, 0] - ends[0, 0] == pytest.approx(1000 * float(label.split()[0]))
    assert float(root.find("s:g[@class='panel']/s:text", NS).get("font-size")) >= 10


def test_deterministic_and_input_types(pattern):
    before, after, names = pattern
    s1 = pattern_svg(before, after, names)
    s2 = pattern_svg(before, after, names)
    s3 = pattern_svg(
        [[L.tolist() for L in p] for p in before], [[L.tolist() for L in p] for p in after], names
    )
    assert s1 == s2 == s3
    assert "-0.000" not in s1
    assert not re.search(r"\d[eE][-+]\d", s1)  # no exponent notation
    assert "sleeve &amp; cuff &lt;L&gt;" in s1


def test_empty_and_bad_input(pattern):
    parse(pattern_svg([], [], []))
    before, after, names = pattern
    with pytest.raises(ValueError, match="names"):
        pattern_svg(before, after, names[:2])
    bad = [[np.array([[0.0, 0.0], [np.nan, 1.0], [1.0, 1.0]])], *before[1:]]
    with pytest.raises(ValueError, match=r"outlines_before\[0\]\[0\]"):
        pattern_svg(bad, after, names)
    with pytest.raises(ValueError, match=r"outlines_after\[1\]\[0\]"):
        pattern_svg(before, [after[0], [np.zeros((5, 3))], after[2]], names)


def test_many_panels_wrap_into_rows():
    before = [[rect(0, 0, 10 + k, 20)] for k in range(12)]
    root = parse(pattern_svg(before, before, [f"p{k}" for k in range(12)]))
    _, _, w, h = map(float, root.get("viewBox").split())
    assert 0.5 < w / h < 3.0  # wrapped, not one long row
    tops = {
        round(points(g.find("s:path[@class='after']", NS).get("d"))[:, 1].min(), 3)
        for g in root.findall("s:g[@class='panel']", NS)
    }
    assert 1 < len(tops) < 12


# --- triangles coloured by intrinsic-scale error ---------------------------------------------


def grid_mesh(x0, y0, w, h, nx, ny):
    """A rectangle split into ``2 * nx * ny`` triangles (counter-clockwise)."""
    xs, ys = np.meshgrid(np.linspace(x0, x0 + w, nx + 1), np.linspace(y0, y0 + h, ny + 1))
    V = np.c_[xs.ravel(), ys.ravel()]
    i = (np.arange(ny)[:, None] * (nx + 1) + np.arange(nx)[None, :]).ravel()
    F = np.r_[np.c_[i, i + 1, i + nx + 2], np.c_[i, i + nx + 2, i + nx + 1]]
    return V, F


@pytest.fixture
def meshed():
    """Two meshed rectangles; errors over every bin, NaN in panel 1."""
    V0, F0 = grid_mesh(0, 0, 40, 60, 4, 6)  # 48 triangles
    V1, F1 = grid_mesh(-10, 5, 30, 20, 3, 2)  # 12 triangles
    e0 = np.resize([0.0, 0.004, 0.007, 0.015, 0.03, -0.03, 0.07, 0.2], len(F0))
    e1 = np.full(len(F1), 0.001)
    e1[[2, 5]] = np.nan
    before = [[rect(0, 0, 38, 58)], [rect(-10, 5, 30, 20)]]
    after = [[rect(0, 0, 40, 60)], [rect(-10, 5, 30, 20)]]
    return before, after, ["front", "back"], [(V0, F0), (V1, F1)], [e0, e1]


def error_paths(g):
    return [p for p in g.findall("s:path", NS) if p.get("class") == "error"]


def legend(root) -> dict[str, str]:
    """Error legend: label -> swatch colour."""
    g = root.find("s:g[@id='error-legend']", NS)
    rects = g.findall("s:rect", NS)
    labels = [t.text for t in g.findall("s:text", NS)][1:]
    assert len(rects) == len(labels)
    return {t: r.get("fill") for t, r in zip(labels, rects, strict=True)}


def test_triangles_grouped_by_bin(meshed):
    before, after, names, tris, errs = meshed
    root = parse(pattern_svg(before, after, names, triangles=tris, errors=errs))
    for g, (V, F), e, b, a in zip(
        root.findall("s:g[@class='panel']", NS), tris, errs, before, after, strict=True
    ):
        bins = error_bins(e)
        paths = error_paths(g)
        used = sorted(set(bins.tolist()))
        assert [int(p.get("data-bin")) for p in paths] == used  # one path per used bin
        for p in paths:
            k = int(p.get("data-bin"))
            d = p.get("d")
            assert d.count("M") == d.count("Z") == np.sum(bins == k)
            assert d.count("L") == 2 * np.sum(bins == k)
            assert p.get("fill") == bin_colour(k)
        assert g.find("s:path[@class='fill']", NS) is None  # no light fill under triangles
        # the triangles are drawn first, then the original, then the adjusted outline
        classes = [p.get("class") for p in g.findall("s:path", NS)]
        assert classes == ["error"] * len(paths) + ["before"] * len(b) + ["after"] * len(a)
        # same translation and flip as the outlines: corners are vertices, to 2 decimals
        shift = points(g.find("s:path[@class='after']", NS).get("d"))[0] - a[0][0] * [1, -1]
        Q = np.concatenate([points(p.get("d")) for p in paths])
        assert len(Q) == 3 * len(F)
        dist = np.abs((Q - shift)[:, None, :] - V[None] * [1, -1]).max(axis=2).min(axis=1)
        assert dist.max() <= 0.006


def test_error_bins_and_colours(meshed):
    before, after, names, tris, _ = meshed
    cases = [(0.03, "2–5 %"), (-0.03, "2–5 %"), (0.02, "2–5 %"), (0.0499, "2–5 %"),
             (0.05, "5–10 %"), (0.0, "< 0.5 %"), (0.1, "≥ 10 %"), (np.inf, "≥ 10 %")]  # fmt: skip
    for e, label in cases:
        errs = [np.zeros(len(tris[0][1])), np.full(len(tris[1][1]), e)]
        root = parse(pattern_svg(before, after, names, triangles=tris, errors=errs))
        (p,) = error_paths(root.findall("s:g[@class='panel']", NS)[1])
        assert p.get("fill") == legend(root)[label], e
    # the 2-5 % colour is its own
    assert list(legend(root).values()).count(legend(root)["2–5 %"]) == 1


def test_legend_lists_the_bins(meshed):
    before, after, names, tris, errs = meshed
    root = parse(pattern_svg(before, after, names, triangles=tris, errors=errs))
    g = root.find("s:g[@id='error-legend']", NS)
    assert g.find("s:text", NS).text == "intrinsic-scale error:"
    lg = legend(root)
    assert list(lg) == ["< 0.5 %", "0.5–1 %", "1–2 %", "2–5 %", "5–10 %", "≥ 10 %", "unknown"]
    assert len(set(lg.values())) == 7
    # sequential: each bin darker than the one before
    lum = [sum(w * int(c[i : i + 2], 16) for w, i in zip((0.3, 0.59, 0.11), (1, 3, 5), strict=True))
           for c in list(lg.values())[:6]]  # fmt: skip
    assert all(a > b for a, b in itertools.pairwise(lum))
    # the outline legend stays
    texts = [t.text for t in root.find("s:g[@id='legend']", NS).findall("s:text", NS)]
    assert texts == ["original", "adjusted"]
    # everything inside the sheet
    _, _, w, h = map(float, root.get("viewBox").split())
    for r in g.findall("s:rect", NS):
        x, y = float(r.get("x")), float(r.get("y"))
        assert x >= 0 and x + float(r.get("width")) <= w and y + float(r.get("height")) <= h
    for t in root.iter("{http://www.w3.org/2000/svg}text"):
        assert 0 <= float(t.get("x")) <= w and 0 < float(t.get("y")) <= h


def test_nan_is_grey_and_only_then_in_the_legend(meshed):
    before, after, names, tris, errs = meshed
    root = parse(pattern_svg(before, after, names, triangles=tris, errors=errs))
    paths = error_paths(root.findall("s:g[@class='panel']", NS)[1])
    grey = [p for p in paths if p.get("fill") == legend(root)["unknown"]]
    assert len(grey) == 1 and grey[0].get("d").count("M") == 2
    assert grey[0].get("fill") == NAN_COLOUR
    r, g, b = (int(NAN_COLOUR[i : i + 2], 16) for i in (1, 3, 5))
    assert r == g == b  # neutral grey, unlike every bin
    clean = [errs[0], np.nan_to_num(errs[1])]
    assert "unknown" not in legend(
        parse(pattern_svg(before, after, names, triangles=tris, errors=clean))
    )


def test_without_triangles_old_style(pattern):
    before, after, names = pattern
    root = parse(pattern_svg(before, after, names))
    assert root.find("s:g[@id='error-legend']", NS) is None
    for g in root.findall("s:g[@class='panel']", NS):
        assert not error_paths(g)
        assert g.find("s:path[@class='fill']", NS).get("fill") == "#dce8f4"


def test_triangle_coordinates_short_and_oriented(meshed):
    before, after, names, tris, errs = meshed
    # one triangle given clockwise: written counter-clockwise like the others (on screen: y down)
    V, F = tris[0]
    F = F.copy()
    F[0] = F[0, [0, 2, 1]]
    svg = pattern_svg(before, after, names, triangles=[(V, F), tris[1]], errors=errs)
    root = parse(svg)
    for p in root.iter("{http://www.w3.org/2000/svg}path"):
        if p.get("class") == "error":
            d = p.get("d")
            assert re.fullmatch(
                r"(M\d+\.\d\d,\d+\.\d\dL\d+\.\d\d,\d+\.\d\dL\d+\.\d\d,\d+\.\d\dZ)+", d
            )
            T = points(d).reshape(-1, 3, 2)
            u, v = T[:, 1] - T[:, 0], T[:, 2] - T[:, 0]
            assert np.all(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0] < 0)  # one orientation


def test_unused_vertices_do_not_move_anything(meshed):
    before, after, names, tris, errs = meshed
    # the whole pattern's V for every panel (as a garment's V2), far-away junk included
    Vall = np.vstack([tris[0][0], tris[1][0], [[1000.0, -500.0]]])
    shared = [(Vall, tris[0][1]), (Vall, tris[1][1] + len(tris[0][0]))]
    s1 = pattern_svg(before, after, names, triangles=tris, errors=errs)
    s2 = pattern_svg(before, after, names, triangles=shared, errors=errs)
    assert s1 == s2


@pytest.mark.parametrize(("units", "css"), [("cm", "cm"), ("mm", "mm"), ("in", "in"), ("m", "cm")])
def test_real_size_with_triangles(meshed, units, css):
    before, after, names, tris, errs = meshed
    k = 0.01 if units == "m" else 1.0  # a pattern in metres
    before, after = ([[L * k for L in p] for p in ls] for ls in (before, after))
    tris = [(V * k, F) for V, F in tris]
    root = parse(pattern_svg(before, after, names, units=units, triangles=tris, errors=errs))
    _, _, w, h = map(float, root.get("viewBox").split())
    assert root.get("width") == f"{w:.3f}{css}"
    assert root.get("height") == f"{h:.3f}{css}"
    # the triangles are drawn in user units too
    factor = 100 if units == "m" else 1  # m: drawn in cm
    g = root.find("s:g[@class='panel']", NS)
    Q = np.concatenate([points(p.get("d")) for p in error_paths(g)])
    assert np.ptp(Q, axis=0) == pytest.approx(factor * np.ptp(tris[0][0], axis=0), abs=0.01)


def test_deterministic_and_inputs_untouched(meshed):
    before, after, names, tris, errs = meshed
    copies = [(V.copy(), F.copy()) for V, F in tris], [e.copy() for e in errs]
    s1 = pattern_svg(before, after, names, triangles=tris, errors=errs)
    s2 = pattern_svg(
        before, after, names,
        triangles=[(V.tolist(), F.tolist()) for V, F in tris], errors=[e.tolist() for e in errs],
    )  # fmt: skip
    assert s1 == s2
    for (V, F), (V0, F0) in zip(tris, copies[0], strict=True):
        np.testing.assert_array_equal(V, V0)
        np.testing.assert_array_equal(F, F0)
    for e, e0 in zip(errs, copies[1], strict=True):
        np.testing.assert_array_equal(e, e0)


def test_bad_triangles(meshed):
    before, after, names, tris, errs = meshed
    with pytest.raises(ValueError, match="triangle meshes"):
        pattern_svg(before, after, names, triangles=tris[:1], errors=errs)
    with pytest.raises(ValueError, match="error arrays"):
        pattern_svg(before, after, names, triangles=tris, errors=[*errs, errs[0]])
    with pytest.raises(ValueError, match="both"):
        pattern_svg(before, after, names, errors=errs)
    with pytest.raises(ValueError, match="both"):
        pattern_svg(before, after, names, triangles=tris)
    with pytest.raises(ValueError, match=r"errors\[1\]"):
        pattern_svg(before, after, names, triangles=tris, errors=[errs[0], errs[1][:-1]])
    V, F = tris[1]
    with pytest.raises(ValueError, match=r"triangles\[1\].*outside"):
        pattern_svg(before, after, names, triangles=[tris[0], (V, F + 100)], errors=errs)
    with pytest.raises(ValueError, match=r"triangles\[1\].*integer"):
        pattern_svg(before, after, names, triangles=[tris[0], (V, F * 1.0)], errors=errs)
    with pytest.raises(ValueError, match=r"triangles\[0\].*\(n, 2\)"):
        pattern_svg(before, after, names, triangles=[(np.zeros((5, 3)), F), tris[1]], errors=errs)
