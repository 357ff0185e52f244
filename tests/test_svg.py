"""SVG of a pattern before and after adjustment."""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET

import numpy as np
import pytest

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
    ("units", "css", "factor", "label"),
    [("cm", "cm", 1, "10 cm"), ("mm", "mm", 1, "100 mm"), ("m", "cm", 100, "0.1 m"),
     ("in", "in", 1, "4 in")],
)  # fmt: skip
def test_real_size(pattern, units, css, factor, label):
    before, after, names = pattern
    root = parse(pattern_svg(before, after, names, units=units))
    _, _, w, h = map(float, root.get("viewBox").split())
    assert root.get("width") == f"{w * factor:.3f}{css}"
    assert root.get("height") == f"{h * factor:.3f}{css}"
    bar = root.find("s:g[@id='scale-bar']", NS)
    assert bar.find("s:text", NS).text == label
    ends = points(bar.find("s:path", NS).get("d"))[:2]
    assert ends[1, 0] - ends[0, 0] == pytest.approx(float(label.split()[0]), abs=2e-3)


def test_unknown_units_get_a_round_bar(pattern):
    before, after, names = pattern
    scaled = [[L / 100 for L in p] for p in before], [[L / 100 for L in p] for p in after]
    root = parse(pattern_svg(*scaled, names, units="uv"))
    assert re.fullmatch(r"\d+\.\d{3}", root.get("width"))
    label = root.find("s:g[@id='scale-bar']/s:text", NS).text
    assert label.endswith(" uv") and float(label.split()[0]) in (0.1, 0.2, 0.5)


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
