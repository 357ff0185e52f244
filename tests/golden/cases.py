"""The golden runs: (garment, recipe, options) whose every output is stored in tests/golden/.

Each case is one ``ptailor adjust`` run. Its outputs are compared file by file with the stored
expectation by :mod:`golden.compare`; ``python -m pytest tests/test_golden.py --refresh-golden``
rewrites the expectations on purpose (see tests/golden/README.md).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
RECIPES = ROOT / "recipes"


@dataclass(frozen=True)
class Case:
    """One golden run.

    garment : ``sample:NAME`` (a generated sample of :data:`ptailor.samples.SAMPLES`),
        ``shared:PATH`` (relative to ../shared/garments; skipped when absent) or
        ``dxf-of:NAME`` (the sample's pattern written as DXF by an identity run, with the
        sample's OBJ as ``--drape``).
    recipe : a file name in recipes/.
    args : further ``ptailor adjust`` options (``{SHARED}``: ../shared/garments).
    """

    name: str
    garment: str
    recipe: str
    args: tuple[str, ...] = field(default=())


TEE6 = ("--pattern-units", "0.3333cm", "--drape-units", "0.3333cm")

CASES: tuple[Case, ...] = (
    # generated, analytic: the demo (elastic cuff), a cut, a loosen, a seam-line scale, an extend
    Case("lantern-wider", "sample:lantern_sleeve", "wider-around.yaml"),
    Case("cone-vneck", "sample:cone_skirt", "v-neck-front.yaml"),
    Case("bodice-loosen", "sample:bodice", "loosen-waist.yaml"),
    Case("skirt-fuller", "sample:skirt", "fuller-skirt.yaml"),
    Case("bodice-lengthen", "sample:bodice", "lengthen-bodice.yaml"),
    Case("cylinder-identity", "sample:cylinder", "identity.yaml"),
    # DXF in (the lantern sleeve's pattern as an AAMA file, its drape beside)
    Case("lantern-dxf-wider", "dxf-of:lantern_sleeve", "wider-around.yaml"),
    # the real garments: a scale with the specification written back, shortens
    Case(
        "tee6-wider-sleeves",
        "shared:gpg_tee6/tee6_sim.obj",
        "wider-sleeves.yaml",
        (*TEE6, "--spec", "auto"),
    ),
    Case("tee6-shorter-hem", "shared:gpg_tee6/tee6_sim.obj", "shorter-hem.yaml", TEE6),
    Case(
        "shirt-shorter-hem-pattern",
        "shared:garmentcode/shirt_mean_boxmesh.obj",
        "shorter-hem-pattern.yaml",
        ("--pattern-units", "auto", "--spec", "{SHARED}/garmentcode/shirt_mean_specification.json"),
    ),
    Case(
        "dress-shorter-hem",
        "shared:diffavatar/dress_initial.obj",
        "shorter-hem.yaml",
        ("--pattern-units", "auto"),
    ),
)
