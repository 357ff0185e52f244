"""Draw docs/measures.md's pictures: the points of measure of a tee, a skirt and a dress.

    python docs/measures/make.py          # rewrite docs/measures/*.svg
    python docs/measures/make.py --check  # exit 1 when a picture differs from what is drawn

The tee is ``ptailor.samples.flat_tee``, the skirt ``ptailor.samples.gored_skirt``, the dress
the shared DiffAvatar dress (``../shared/garments/diffavatar/dress_initial.obj``, read as
``ptailor inspect --pattern-units auto --drape-units cm`` reads it): without ../shared the
dress is left as it is. ``tests/test_pom_pictures.py`` checks that the committed pictures are
what this draws today.
"""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
DRESS = ROOT.parent / "shared" / "garments" / "diffavatar" / "dress_initial.obj"


def garments() -> dict:
    """``{name: (garment, title)}`` of the pictures that can be drawn here."""
    from ptailor.samples import flat_tee, gored_skirt

    out = {
        "tee": (flat_tee(), "tee: ptailor.samples.flat_tee()"),
        "skirt": (gored_skirt(), "skirt: ptailor.samples.gored_skirt()"),
    }
    if DRESS.is_file():
        from ptailor.formats.garment import load_garment

        g = load_garment(DRESS, pattern_units="auto", drape_units="cm").garment
        out["dress"] = (g, "dress: DiffAvatar dress_initial.obj")
    return out


def pictures() -> dict[str, str]:
    """``{name: SVG text}``: each garment's points of measure drawn."""
    from ptailor.formats.pom_svg import measures_svg
    from ptailor.measures import garment_measures

    return {
        name: measures_svg(g, garment_measures(g), title=title)
        for name, (g, title) in garments().items()
    }


def main(argv: list[str]) -> int:
    check = "--check" in argv
    stale = []
    for name, svg in pictures().items():
        path = HERE / f"{name}.svg"
        if check:
            if not path.is_file() or path.read_text() != svg:
                stale.append(path.name)
        else:
            path.write_text(svg)
            print(f"wrote {path.relative_to(ROOT)}")
    if stale:
        print(f"differs from what is drawn today: {', '.join(stale)}", file=sys.stderr)
    return 1 if stale else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
