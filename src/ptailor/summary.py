"""What ``ptailor inspect`` shows: panels, seams, openings and units of a garment."""

from __future__ import annotations

import numpy as np

from ptailor.formats.garment import LoadedGarment
from ptailor.method.flatten import panel_labels, vertex_labels
from ptailor.model.garment import panels, signed_areas_2d
from ptailor.model.openings import openings
from ptailor.model.seams import seams
from ptailor.report.metrics import panel_sizes


def garment_summary(loaded: LoadedGarment, *, up=(0.0, 1.0, 0.0), front=(0.0, 0.0, 1.0)) -> dict:
    """A JSON-ready description of a garment.

    Parameters
    ----------
    loaded : LoadedGarment
    up, front : (3,) sequence of float
        Axes for naming openings.

    Returns
    -------
    dict
        ``panels``, ``seams``, ``openings``, ``units``, ``triangles``.
    """
    g = loaded.garment
    plist = panels(g)
    flab = panel_labels(plist, g.n_faces)
    vlab = vertex_labels(plist, len(g.V2))
    n = len(plist)
    sizes = panel_sizes(g.V2, vlab, n)
    area = np.bincount(flab, np.abs(signed_areas_2d(g.V2, g.F2)), minlength=n)
    names = [p.name for p in plist]
    out_p = [
        {
            "name": p.name,
            "triangles": int(p.faces.size),
            "size": [round(float(sizes[p.index, 0]), 3), round(float(sizes[p.index, 1]), 3)],
            "area": round(float(area[p.index]), 3),
            "orientation": "mirrored (clockwise)" if p.mirrored else "counter-clockwise",
        }
        for p in plist
    ]
    out_s = []
    for s in seams(g.F3, g.F2, flab):
        la, lb = s.lengths(g.V2)
        out_s.append(
            {
                "panels": [names[s.panels[0]], names[s.panels[1]]],
                "edges": len(s.edges3),
                "lengths": [round(la, 3), round(lb, 3)],
            }
        )
    out_o = [
        {
            "name": o.name,
            "vertices": len(o.loop),
            "length": round(float(o.length), 3),
            "centroid": [round(float(x), 3) for x in o.centroid],
        }
        for o in openings(g.V3, g.F3, up=up, front=front)
    ]
    units = {"computation": g.units}
    if loaded.pattern_units_estimated:
        units["pattern_scale_estimate"] = round(loaded.pattern_scale, 6)
    return {
        "inputs": loaded.inputs,
        "triangles": g.n_faces,
        "panels": out_p,
        "seams": out_s,
        "openings": out_o,
        "units": units,
    }


def summary_text(info: dict) -> str:
    """Plain-text rendering of :func:`garment_summary`."""
    u = info["units"]["computation"]
    lines = [f"{info['triangles']} triangles, {len(info['panels'])} panels, lengths in {u}"]
    if "pattern_scale_estimate" in info["units"]:
        lines.append(
            f"pattern scale estimated: {info['units']['pattern_scale_estimate']} {u} per unit"
        )
    lines.append("panels:")
    for p in info["panels"]:
        lines.append(
            f"  {p['name']:<16} {p['triangles']:>7} tris  {p['size'][0]:8.2f} x {p['size'][1]:8.2f}"
            f"  {p['orientation']}"
        )
    lines.append("seams:")
    for s in info["seams"]:
        a, b = s["panels"]
        lines.append(
            f"  {a} / {b}: {s['lengths'][0]:.2f} / {s['lengths'][1]:.2f} ({s['edges']} edges)"
        )
    lines.append("openings:")
    for o in info["openings"]:
        c = ", ".join(f"{x:.1f}" for x in o["centroid"])
        lines.append(f"  {o['name']:<16} length {o['length']:8.2f}  at ({c})")
    return "\n".join(lines)
