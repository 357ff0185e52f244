"""The garments of the names table and the names each one gets.

A case is a generated sample with some of its options (:mod:`ptailor.samples`, built in
memory, in cm) or a shared garment (read from ../shared/garments as ``ptailor inspect`` reads
it, with its known units), and the wearer's axes it is named in. :func:`names_of` answers what
``ptailor inspect --json`` names: every panel (and, where the file names its panels, the name
the rules read from the drape), every seam with the two panels it joins, every opening.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

HERE = Path(__file__).resolve().parent


@dataclass(frozen=True)
class Case:
    """One garment of the table.

    key : the table file's stem (``tests/names/KEY.json``).
    garment : ``sample:FUNCTION`` (a function of :mod:`ptailor.samples`) or ``shared:PATH``
        (relative to ../shared/garments).
    options : the sample's keyword options.
    units : the shared garment's ``(pattern units, drape units)``.
    up, front : the wearer's axes (``--up``, ``--front``).
    """

    key: str
    garment: str
    options: dict = field(default_factory=dict)
    units: tuple[str, str] = ("cm", "cm")
    up: str = "y"
    front: str = "z"

    @property
    def shared(self) -> bool:
        return self.garment.startswith("shared:")

    @property
    def path(self) -> Path:
        """The table file."""
        return HERE / f"{self.key}.json"


def _sample(name: str, key: str | None = None, up="y", front="z", **options) -> Case:
    return Case(key or name, f"sample:{name}", options, up=up, front=front)


def _shared(key: str, path: str, pattern: str, drape: str = "cm") -> Case:
    return Case(f"shared-{key}", f"shared:{path}", units=(pattern, drape))


#: every function of :mod:`ptailor.samples` in the variants its options name (a sample's
#: discrete options: the lantern's axis, the cylinder's mirrored pattern, the gores, the
#: tee's sleeves), and every shared garment
CASES: tuple[Case, ...] = (
    _sample("lantern_sleeve"),
    _sample("lantern_sleeve", "lantern_sleeve-axis-x", up="x", front="y", axis="x"),
    _sample("lantern_sleeve", "lantern_sleeve-axis-z", up="z", front="x", axis="z"),
    _sample("sample_for_triangles", n_triangles=2000),
    _sample("cylinder"),
    _sample("cylinder", "cylinder-mirrored", mirrored=True),
    _sample("tseam_tube"),
    _sample("cone_skirt"),
    _sample("unnamed_skirt"),
    _sample("gored_skirt", "gored_skirt-gores-2", gores=2),
    _sample("gored_skirt", "gored_skirt-gores-4", gores=4),
    _sample("gored_skirt", "gored_skirt-gores-6", gores=6),
    _sample("bodice"),
    _sample("halved_bodice"),
    _sample("flat_tee", "flat_tee-sleeves-two", sleeves="two"),
    _sample("flat_tee", "flat_tee-sleeves-one", sleeves="one"),
    _sample("flat_tee", "flat_tee-sleeves-none", sleeves="none"),
    _shared("tee6", "gpg_tee6/tee6_sim.obj", "0.3333cm", "0.3333cm"),
    _shared("tshirt", "diffavatar/tshirt.obj", "auto"),
    _shared("longsleeve", "diffavatar/longsleeve_initial.obj", "auto"),
    _shared("dress", "diffavatar/dress_initial.obj", "auto"),
    _shared("shirt_mean", "garmentcode/shirt_mean_boxmesh.obj", "auto"),
    _shared("shorts", "garmentcode_more/shorts_boxmesh.obj", "126.7879cm"),
    _shared("skirt_flared", "garmentcode_more/skirt_flared_boxmesh.obj", "224.96cm"),
    _shared("shirt_longsleeve", "garmentcode_more/shirt_longsleeve_boxmesh.obj", "230.88cm"),
    _shared("jumpsuit", "garmentcode_more/jumpsuit_boxmesh.obj", "203.50cm"),
)


def shared_file(case: Case) -> Path:
    """The shared garment's file (it may be absent: a fresh clone has no ../shared)."""
    from tests.conftest import GARMENTS

    return GARMENTS / case.garment.partition(":")[2]


def garment_of(case: Case):
    """The case's garment, as ``ptailor inspect`` reads it (a sample as generated), worn in
    the case's axes."""
    from ptailor.model.frame import Frame

    frame = Frame.from_names(case.up, case.front)
    kind, _, what = case.garment.partition(":")
    if kind == "sample":
        from ptailor import samples

        make: Callable = getattr(samples, what)
        return make(**case.options).with_frame(frame)
    from ptailor.formats.garment import load_garment

    pattern, drape = case.units
    path = shared_file(case)
    return load_garment(path, pattern_units=pattern, drape_units=drape, frame=frame).garment


def names_of(case: Case, garment=None) -> dict:
    """What the table holds for ``case``: the garment's names, as ``ptailor inspect --json``
    has them (:func:`ptailor.report.inspection.garment_summary`); of ``garment`` instead
    of the case's own when given (the same garment moved), named under its frame."""
    from ptailor.model.names import seam_names
    from ptailor.model.structure import structure

    g = garment_of(case) if garment is None else garment
    st = structure(g)
    panels = [p.name for p in st.panels]
    seams = seam_names(g.V3, st.seams, st.layout, panels)
    out: dict = {"garment": case.garment}
    if case.options:
        out["options"] = dict(case.options)
    if case.shared:
        out["units"] = {"pattern": case.units[0], "drape": case.units[1]}
    out["axes"] = {"up": case.up, "front": case.front}
    out["panels"] = panels
    if list(st.layout.names) != panels:  # the file names its panels: what the rules read
        out["geometry"] = list(st.layout.names)
    out["seams"] = [
        [name, panels[s.panels[0]], panels[s.panels[1]]]
        for s, name in zip(st.seams, seams, strict=True)
    ]
    out["openings"] = [o.name for o in st.openings]
    return out


def dumps(table: dict) -> str:
    """The table file's text: JSON, one panel, seam or opening to a line (a renamed one is
    one line of the diff)."""
    lines = ["{"]
    items = list(table.items())
    for i, (k, v) in enumerate(items):
        comma = "," if i < len(items) - 1 else ""
        if isinstance(v, list) and v:
            rows = [json.dumps(x) for x in v]
            body = ",\n".join(f"    {r}" for r in rows)
            lines.append(f"  {json.dumps(k)}: [\n{body}\n  ]{comma}")
        else:
            lines.append(f"  {json.dumps(k)}: {json.dumps(v)}{comma}")
    lines.append("}")
    return "\n".join(lines) + "\n"
