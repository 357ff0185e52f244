"""The names table: every panel's, seam's and opening's name, pinned per garment.

``tests/names/KEY.json`` holds, for one garment (each generated sample of
:mod:`ptailor.samples` in the variants its options name, and each shared garment in
../shared/garments), the names ``ptailor inspect --json`` gives it: its panels (and where the
file names them, ``geometry``: what the naming rules read from the drape), its seams with the
two panels each joins, its openings. The garments, their options, units and axes are in
``tests/names/cases.py``; this test names each again and compares.

A change to the naming rules (``src/ptailor/model/names``, ``model/openings``) that moves a
row must change the table in the same commit. Rewrite it with

    python tests/names/regenerate.py            # every case (shared ones when ../shared exists)
    python tests/names/regenerate.py dress      # the cases whose key contains a word

and read ``git diff tests/names``: each changed line is a renamed panel, seam or opening. A
new sample, a new option value or a new shared garment needs its case in ``cases.py`` (a test
here fails without one). The shared garments' cases skip when ../shared is absent.

Two more checks over every case: the table keeps one scheme (each word once, one side at
most, no ``_2``, every left name beside its right one: :mod:`ptailor.model.names`), and the
garment reflected across its centre plane gets the mirror names. The whole file runs in
about 5 s.
"""

from __future__ import annotations

import inspect
import json

import pytest

from tests.names.cases import CASES, HERE, dumps, names_of, shared_file

#: every case is quick (0.05-0.3 s; the shared garments' files are read in bulk): all run in
#: the quick loop


@pytest.mark.parametrize("case", CASES, ids=[c.key for c in CASES])
def test_names_are_the_tables(case):
    if case.shared and not shared_file(case).is_file():
        pytest.skip(f"{shared_file(case)} not available (../shared is absent)")
    assert case.path.is_file(), f"no table for {case.key}: python tests/names/regenerate.py"
    want = json.loads(case.path.read_text())
    got = names_of(case)
    if got != want:  # the rows that moved, then the whole comparison
        moved = [
            f"{k}: {w!r} -> {g!r}"
            for k in ("panels", "geometry", "seams", "openings")
            for w, g in zip(want.get(k, []), got.get(k, []), strict=False)
            if w != g
        ]
        print("\n".join(moved))
    assert got == want, "the names moved: python tests/names/regenerate.py (see the docstring)"


def test_the_table_files_are_written_by_the_regenerator():
    """Every table file has its case and reads as the regenerator writes it."""
    known = {c.path.name: c for c in CASES}
    for p in sorted(HERE.glob("*.json")):
        assert p.name in known, f"{p.name}: no case in tests/names/cases.py"
        assert dumps(json.loads(p.read_text())) == p.read_text(), p.name
    assert len(known) == len(CASES), "two cases share a key"


def test_every_sample_and_its_options_have_a_case():
    """Each function of ptailor.samples is in the table, and each value of a sample's
    string or boolean option (the lantern's axis, the cylinder's mirror, the tee's sleeves)."""
    from ptailor import samples

    named = {c.garment.partition(":")[2] for c in CASES if not c.shared}
    makers = {n for n in samples.__all__ if inspect.isfunction(getattr(samples, n))}
    assert makers <= named, f"samples without a case: {sorted(makers - named)}"
    assert set(samples.SAMPLES.values()) <= {getattr(samples, n) for n in named}
    choices = {
        ("lantern_sleeve", "axis"): {"x", "y", "z"},
        ("cylinder", "mirrored"): {True, False},
        ("flat_tee", "sleeves"): {"one", "two", "none"},
        ("gored_skirt", "gores"): {2, 4, 6},
    }
    for (name, option), values in choices.items():
        default = inspect.signature(getattr(samples, name)).parameters[option].default
        have = {c.options.get(option, default) for c in CASES if c.garment == f"sample:{name}"}
        assert have == values, (name, option, have)


def test_every_shared_garment_has_a_case():
    from tests.conftest import GARMENTS

    if not GARMENTS.is_dir():
        pytest.skip(f"{GARMENTS} not available (../shared is absent)")
    cased = {shared_file(c) for c in CASES if c.shared}
    found = {p for p in GARMENTS.rglob("*.obj")}
    assert found <= cased, f"shared garments without a case: {sorted(found - cased)}"


def _swap(name: str) -> str:
    return "_".join({"left": "right", "right": "left"}.get(w, w) for w in name.split("_"))


@pytest.mark.parametrize("case", CASES, ids=[c.key for c in CASES])
def test_the_table_keeps_one_scheme(case):
    """Every name of the table says each word once (no ``bodice_front_right_bodice_front_
    upper``, no ``side_right_left``), at most one side, no ``_2`` (a place word tells equal
    names apart), and a name with a side has its mirror name beside it."""
    if not case.path.is_file():
        pytest.skip(f"no table for {case.key}")
    t = json.loads(case.path.read_text())
    names = [*t["panels"], *t.get("geometry", []), *(s[0] for s in t["seams"])]
    for n in names:
        w = n.split("_")
        assert len(w) == len(set(w)) and not {"left", "right"} <= set(w), n
        assert not w[-1].isdigit() or n.startswith(("panel_", "opening_")), n
    own = [*t.get("geometry", t["panels"]), *(s[0] for s in t["seams"])]
    lonely = [n for n in own if _swap(n) not in own]
    assert not lonely, f"names without their mirror name: {lonely}"


@pytest.mark.parametrize(
    "case",
    # a shared garment, mirrored and named again: 0.1-0.4 s each (the quick loop's rule:
    # real-garment tests of 0.3 s or more are slow)
    [pytest.param(c, marks=pytest.mark.slow) if c.shared else c for c in CASES],
    ids=[c.key for c in CASES],
)
def test_a_mirrored_garment_gets_the_mirror_names(case):
    """The garment reflected across its centre plane: the same rows with left and right
    swapped (a panel or seam and its mirror image are named from their shared place)."""
    from dataclasses import replace

    import numpy as np

    from tests.names.cases import garment_of, names_of

    if case.shared and not shared_file(case).is_file():
        pytest.skip(f"{shared_file(case)} not available (../shared is absent)")
    g = garment_of(case)
    left = np.asarray(g.frame.side)
    flip = np.eye(3) - 2.0 * np.outer(left, left)
    m = replace(
        g,
        V3=g.V3 @ flip.T,
        F3=np.ascontiguousarray(g.F3[:, ::-1]),
        V2=g.V2 * np.array([-1.0, 1.0]),
        F2=np.ascontiguousarray(g.F2[:, ::-1]),
    )
    want, got = names_of(case), names_of(case, garment=m)
    assert got["panels"] == [_swap(n) for n in want["panels"]]
    assert got.get("geometry") == (
        [_swap(n) for n in want["geometry"]] if "geometry" in want else None
    )
    rows = sorted([_swap(n), *sorted(map(_swap, ab))] for n, *ab in want["seams"])
    assert sorted([n, *sorted(ab)] for n, *ab in got["seams"]) == rows
    assert sorted(got["openings"]) == sorted(map(_swap, want["openings"]))
