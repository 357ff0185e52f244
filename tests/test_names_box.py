"""Panel roles on a box mesh: the panels placed flat around the body and welded at the
seams by rows of triangles stretched across the gaps (GarmentCode's undraped meshes), whose
drape makes a bodice look like a strip (issue 42, item 9)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ptailor.geometry.labels import component_labels
from ptailor.model.garment import Garment
from ptailor.model.names import panel_layout
from ptailor.model.structure import structure
from ptailor.samples import flat_tee
from ptailor.samples.grid import split_pattern


def boxed_dress(*, gap: float = 25.0, waist: float = 30.0) -> Garment:
    """A two-tier dress as a box mesh: :func:`flat_tee` cut at the ``waist`` (a bodice over a
    skirt, the front bodice in halves at the centre front), its front layer moved ``gap``
    forward and its back ``gap`` back, the vertices of the seams between them left where
    they were (one row of stretched triangles along every front/back seam)."""
    g = flat_tee(sleeves="two", depth=1.0)
    lab = component_labels(g.F2, len(g.V2))
    c = g.V3[g.F3].mean(axis=1)
    body, front, low = np.abs(c[:, 0]) < 24.0, c[:, 2] > 0, c[:, 1] < waist
    n = int(lab.max()) + 1
    lab = np.where(body & low, np.where(front, n, n + 1), lab)
    lab = np.where(body & ~low & front & (c[:, 0] < 0), n + 2, lab)
    V2, F2, _ = split_pattern(g.V2, g.F2, lab)
    on_front = np.bincount(g.F3[front].ravel(), minlength=len(g.V3)) > 0
    on_back = np.bincount(g.F3[~front].ravel(), minlength=len(g.V3)) > 0
    V3 = g.V3.copy()
    V3[on_front & ~on_back, 2] += gap
    V3[on_back & ~on_front, 2] -= gap
    return replace(g, V3=V3, V2=V2, F2=F2)


def test_a_box_mesh_bodice_is_no_collar():
    g = boxed_dress()
    st = structure(g)
    names = st.layout.names
    assert sorted(names) == sorted(
        [
            "bodice_back",
            "bodice_front_left",
            "bodice_front_right",
            "skirt_back",
            "skirt_front",
            *(f"sleeve_{s}_{f}" for s in ("left", "right") for f in ("front", "back")),
        ]
    )
    assert all(r in ("body", "sleeve") for r in st.layout.role)
    back = names.index("bodice_back")
    assert "body (length/width 1.4, under 3.5 for a strip" in st.layout.why[back]
    # the drape's shape alone (no pattern given) takes the stretched back for a collar
    lab, n_p = st.panel_components
    by_drape = panel_layout(g.V3, g.F3, g.F2, lab, n_p, frame=g.frame)
    assert by_drape.role[back] == "collar"


def test_a_strip_is_one_in_its_pattern():
    """A waistband stays a waistband: the pattern's shape, not the drape's, decides."""
    from ptailor.samples import cone_skirt

    g = cone_skirt()
    c = g.V3[g.F3].mean(axis=1)
    top = float(g.V3[:, 1].max())
    lab = component_labels(g.F2, len(g.V2))
    band = c[:, 1] > top - 4.0
    lab = np.where(band, np.where(c[:, 2] > 0, lab.max() + 1, lab.max() + 2), lab)
    V2, F2, _ = split_pattern(g.V2, g.F2, lab)
    g = replace(g, V2=V2, F2=F2, face_group=np.full(g.n_faces, -1), group_names=())
    st = structure(g)
    assert sorted(st.layout.names) == [
        "skirt_back",
        "skirt_front",
        "waistband_back",
        "waistband_front",
    ]
