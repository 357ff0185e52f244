"""What ``ptailor inspect`` shows: panels, seams, openings and units of a garment (and, with
``--spec``, how its specification's panels and stitches match them), or the pieces, sizes
and units of a DXF pattern."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ptailor import tolerances as tol
from ptailor.formats.garment import LoadedGarment
from ptailor.geometry.triangles import signed_areas_2d, triangle_areas
from ptailor.model.names import seam_names
from ptailor.model.pieces import PatternFile
from ptailor.model.seam_lines import seam_lines
from ptailor.model.structure import structure
from ptailor.model.units import CM_PER
from ptailor.report.metrics import panel_sizes

if TYPE_CHECKING:
    from ptailor.spec.match import SpecMatching


def _why(name: str, layout, i: int) -> str:
    """Why panel ``i`` is called ``name``: the layout's rules, or the file's group name."""
    why = layout.why[i] if i < len(layout.why) else ""
    if name != layout.names[i]:
        return f"the file's group name (its geometry reads {layout.names[i]}: {why})"
    return why


def garment_summary(loaded: LoadedGarment) -> dict:
    """A JSON-ready description of a garment, named under its frame.

    Parameters
    ----------
    loaded : LoadedGarment

    Returns
    -------
    dict
        ``frame`` (what the positions are measured in), ``panels`` (with ``position``, a
        phrase, ``centroid``, the area-weighted drape centroid in the drape's frame like the
        openings', and ``wearer``, the same point as ``(left, up, front)`` from the centre
        line and the lowest point), ``seams`` (with a
        ``name`` from where they run), ``seam_lines`` (name, the part seen from, the panels
        across, its seams: :func:`ptailor.model.seam_lines.seam_lines`), ``openings``,
        ``units``, ``triangles``.
    """
    g = loaded.garment
    st = structure(g)
    names = [p.name for p in st.panels]
    snames = seam_names(g.V3, st.seams, st.layout, names)
    out_s = [
        {
            "name": sname,
            "panels": [names[s.panels[0]], names[s.panels[1]]],
            "edges": len(s.edges3),
            "lengths": [round(la, 3), round(lb, 3)],
        }
        for s, sname in zip(st.seams, snames, strict=True)
        for la, lb in [s.lengths(g.V2)]
    ]
    out_l = [
        {
            "name": ln.name,
            "part": names[ln.part],
            "panels": [names[i] for i in ln.panels],
            "seams": [snames[i] for i in ln.seams],
        }
        for ln in seam_lines(g.V3, st.seams, snames)
    ]
    out_o = [
        {
            "name": o.name,
            "vertices": len(o.loop),
            "length": round(float(o.length), 3),
            "centroid": [round(float(x), 3) for x in o.centroid],
        }
        for o in st.openings
    ]
    read = loaded.intake.get("units", {})
    units = {"computation": g.units}
    units.update(
        {k: read[k] for k in ("pattern", "pattern_source", "drape", "drape_source") if k in read}
    )
    if loaded.pattern_units_estimated:
        units["pattern_scale_estimate"] = round(loaded.pattern_scale, 6)
    return {
        "inputs": loaded.inputs,
        "frame": (
            f"centroids (panels, openings) in the drape's coordinates, in {g.units}; a panel's"
            " wearer is (left, up, front) from the centre line and the lowest point"
        ),
        "triangles": g.n_faces,
        "panels": _panel_summaries(g, st),
        "seams": out_s,
        "seam_lines": out_l,
        "openings": out_o,
        "units": units,
        "intake": loaded.intake,
    }


def _panel_summaries(g, st) -> list[dict]:
    """:func:`garment_summary`'s ``panels``: size, area, orientation, where each sits."""
    plist, flab, vlab, layout = st.panels, st.face_panel, st.vertex_panel, st.layout
    n = len(plist)
    sizes = panel_sizes(g.V2, vlab, n)
    area = np.bincount(flab, np.abs(signed_areas_2d(g.V2, g.F2)), minlength=n)
    a3 = triangle_areas(g.V3, g.F3)
    tc = g.V3[g.F3].mean(axis=1) * a3[:, None]  # area-weighted triangle centroids
    c3 = np.stack([np.bincount(flab, tc[:, j], minlength=n) for j in range(3)], axis=1)
    c3 /= np.maximum(np.bincount(flab, a3, minlength=n), tol.TINY)[:, None]
    return [
        {
            "name": p.name,
            "triangles": int(p.faces.size),
            "size": [round(float(sizes[p.index, 0]), 3), round(float(sizes[p.index, 1]), 3)],
            "area": round(float(area[p.index]), 3),
            "orientation": "mirrored (clockwise)" if p.mirrored else "counter-clockwise",
            "position": layout.position(p.index),
            "centroid": [round(float(x), 3) for x in c3[p.index]],
            "wearer": [round(float(x), 3) for x in layout.centroid[p.index]],
            "why": _why(p.name, layout, p.index),
        }
        for p in plist
    ]


def spec_summary(matching: SpecMatching, info: dict) -> dict:
    """The ``spec`` section of :func:`garment_summary`: each specification panel with the
    mesh panel it is matched to, each stitch with its seam and the two edges' lengths.

    Parameters
    ----------
    matching : SpecMatching
        The specification matched to the garment
        (:func:`ptailor.run.spec.matched_specification`, in the summary's axes).
    info : dict
        :func:`garment_summary` of the same garment: its panels and seams are in the
        structure's order, which the matching's indices refer to.

    Returns
    -------
    dict
        ``input``, ``format``, ``units_in_meter``, ``panels`` (``name``, ``panel``,
        ``mirrored``, ``fit``: the largest distance of the specification outline from the
        mesh panel's, ``residual``: the fit's mean distance over the outline's size) and
        ``stitches`` (``stitch``, ``sides``, ``seam``, ``spec_lengths``, ``mesh_lengths``);
        lengths in the summary's computation units.
    """
    spec = matching.spec
    panels = [
        {
            "name": spec.panels[m.spec].name,
            "panel": info["panels"][m.panel]["name"],
            "mirrored": bool(np.linalg.det(m.R) < 0),
            "fit": round(float(m.distance), 3),
            "residual": round(float(m.residual), 6),
        }
        for m in matching.panels
    ]
    stitches = []
    for sm in matching.stitches:  # a loop over stitches
        (pa, ea), (pb, eb) = spec.stitches[sm.stitch].sides
        stitches.append(
            {
                "stitch": int(sm.stitch),
                "sides": [f"{pa}.{ea}", f"{pb}.{eb}"],
                "seam": info["seams"][sm.seam]["name"],
                "spec_lengths": [round(float(x), 3) for x in sm.spec_lengths],
                "mesh_lengths": [round(float(x), 3) for x in sm.mesh_lengths],
            }
        )
    return {
        "input": spec.path,
        "format": spec.flavour,
        "units_in_meter": spec.units_in_meter,
        "panels": panels,
        "stitches": stitches,
    }


def spec_text(sec: dict, units: str) -> list[str]:
    """Lines of :func:`spec_summary` (lengths in ``units``)."""
    lines = [f"specification ({sec['format']}, {sec['input']}):"]
    for p in sec["panels"]:
        mirrored = "  mirrored" if p["mirrored"] else ""
        lines.append(f"  {p['name']} -> {p['panel']}  fit {p['fit']:.3f} {units}{mirrored}")
    for s in sec["stitches"]:
        (sa, sb), (ma, mb) = s["spec_lengths"], s["mesh_lengths"]
        lines.append(
            f"  stitch {s['stitch']}  {s['sides'][0]} / {s['sides'][1]}  -> {s['seam']}"
            f"  spec {sa:.2f} / {sb:.2f}, mesh {ma:.2f} / {mb:.2f}"
        )
    return lines


def summary_text(info: dict) -> str:
    """Plain-text rendering of :func:`garment_summary`."""
    u = info["units"]["computation"]
    lines = [f"{info['triangles']} triangles, {len(info['panels'])} panels, lengths in {u}"]
    if "pattern_scale_estimate" in info["units"]:
        lines.append(
            f"pattern scale estimated: {info['units']['pattern_scale_estimate']} {u} per unit"
        )
    lines.extend(intake_lines(info.get("intake") or {}))
    lines.append("panels:")
    for p in info["panels"]:
        lines.append(
            f"  {p['name']:<24} {p['triangles']:>7} tris  {p['size'][0]:8.2f} x {p['size'][1]:8.2f}"
            f"  {p['orientation']:<20}  {p['position']}"
        )
        if p.get("why"):
            lines.append(f"      why: {p['why']}")
    lines.append("seams:")
    for s in info["seams"]:
        a, b = s["panels"]
        lines.append(
            f"  {s['name']:<24} {a} / {b}: {s['lengths'][0]:.2f} / {s['lengths'][1]:.2f}"
            f" ({s['edges']} edges)"
        )
    if info.get("seam_lines"):
        lines.append("seam lines (a recipe's seam: NAME with part: PART scales the whole line):")
        for ln in info["seam_lines"]:
            lines.append(f"  {ln['name']:<24} {ln['part']}: {', '.join(ln['seams'])}")
    lines.append("openings:")
    for o in info["openings"]:
        c = ", ".join(f"{x:.1f}" for x in o["centroid"])
        lines.append(f"  {o['name']:<16} length {o['length']:8.2f}  at ({c})")
    if info.get("measures"):
        lines.append("points of measure (cm, drape / pattern; ptailor measure):")
        for m in info["measures"]:
            lines.append(
                f"  {m['name']:<20} {m['kind']:<7} {m['drape']:8.2f} / {m['pattern']:8.2f}"
            )
    if info.get("spec"):
        lines.extend(spec_text(info["spec"], u))
    return "\n".join(lines)


def pattern_summary(pattern: PatternFile) -> dict:
    """A JSON-ready description of a DXF pattern's pieces (no drape needed).

    Parameters
    ----------
    pattern : PatternFile

    Returns
    -------
    dict
        ``inputs``, ``style``, ``pieces`` (name, size in file units and in cm, quantity,
        notches, grain line and its angle), ``count``, ``sizes``, ``size``,
        ``sample_size``, ``units``.
    """
    to_cm = CM_PER[pattern.units]
    out_p = []
    for p in pattern.pieces:
        ext = p.extent
        grain = p.grain is not None
        angle = None
        if grain:
            d = np.asarray(p.grain[1], dtype=float) - np.asarray(p.grain[0], dtype=float)
            angle = round(float(np.degrees(np.arctan2(d[1], d[0])) % 180.0), 2)
        out_p.append(
            {
                "name": p.name,
                "size": [round(float(ext[0]), 3), round(float(ext[1]), 3)],
                "size_cm": [round(float(ext[0] * to_cm), 2), round(float(ext[1] * to_cm), 2)],
                "quantity": int(p.quantity),
                "points": len(p.outline),
                "notches": len(p.notches),
                "grain": grain,
                "grain_angle": angle,
                "internal_lines": len(p.internal),
                "drills": len(p.drills),
            }
        )
    return {
        "inputs": {"pattern": pattern.path},
        "style": pattern.style,
        "pieces": out_p,
        "count": len(out_p),
        "sizes": list(pattern.sizes),
        "size": pattern.size,
        "sample_size": pattern.sample_size,
        "units": {"file": pattern.units, "text": pattern.units_text, "note": pattern.units_note},
    }


def grade_summary(sizes: tuple[PatternFile, ...], sample: str) -> list[dict]:
    """Each size's grade from ``sample``: per size and piece, the width, height and area
    difference from the sample size's piece of the same name (file units), and the largest
    distance between a point and its sample-size point (``max_delta``; outlines
    corresponded point by point, else by length between turn points: ``correspondence``).

    Parameters
    ----------
    sizes : tuple of PatternFile
        Every size of one file (:func:`ptailor.formats.dxf.read_dxf_sizes`).
    sample : str

    Returns
    -------
    list of dict
    """
    from ptailor.model.correspond import at_places, corresponding

    base = next((pf for pf in sizes if pf.size == sample), sizes[0])
    ref = {p.name.casefold(): p for p in base.pieces}
    out = []
    for pf in sizes:  # a loop over sizes
        for p in pf.pieces:  # a loop over pieces
            p0 = ref.get(p.name.casefold())
            if p0 is None:
                continue
            where = corresponding(p0.outline, p0.turn, p.outline, p.turn)
            delta = np.linalg.norm(at_places(p.outline, where) - p0.outline, axis=1)
            dw, dh = (p.extent - p0.extent).tolist()
            out.append(
                {
                    "size": pf.size,
                    "piece": p.name,
                    "width": round(dw, 4),
                    "height": round(dh, 4),
                    "area": round(p.area - p0.area, 4),
                    "max_delta": round(float(delta.max(initial=0.0)), 4),
                    "correspondence": where.how,
                }
            )
    return out


def pattern_summary_text(info: dict) -> str:
    """Plain-text rendering of :func:`pattern_summary`."""
    u = info["units"]["file"]
    n = info["count"]
    style = f" (style {info['style']})" if info["style"] else ""
    lines = [f"pattern: {info['inputs']['pattern']}{style}"]
    if info["sizes"]:
        sample = f", sample size {info['sample_size']}" if info["sample_size"] else ""
        lines.append(f"sizes: {' '.join(info['sizes'])} (showing {info['size']}{sample})")
    else:
        lines.append("sizes: none named in the file")
    lines.append(f"units: {u} ({info['units']['note']})")
    in_cm = u == "cm"  # one size column when the file is in cm
    cm_head = "" if in_cm else f" {'size (cm)':>17}"
    lines.append(f"  {'piece':<20} {'size (' + u + ')':>19}{cm_head}  qty  notches  grain")
    for p in info["pieces"]:
        w, h = p["size"]
        wc, hc = p["size_cm"]
        grain = f"yes {p['grain_angle']:.1f} deg" if p["grain"] else "no"
        cm = "" if in_cm else f" {wc:7.1f} x {hc:7.1f}"
        lines.append(
            f"  {p['name']:<20} {w:8.2f} x {h:8.2f}{cm}"
            f"  {p['quantity']:>3}  {p['notches']:>7}  {grain}"
        )
    lines.append(f"{n} piece{'s' if n != 1 else ''}")
    if info.get("grades"):
        lines.append(f"grade from sample size {info['size']} ({u}; area in {u}2):")
        lines.append(
            f"  {'size':<8} {'piece':<20} {'width':>8} {'height':>8} {'area':>10} {'max delta':>9}"
        )
        for g in info["grades"]:
            by = "" if g["correspondence"] == "point by point" else f"  ({g['correspondence']})"
            lines.append(
                f"  {g['size']:<8} {g['piece']:<20} {g['width']:+8.2f} {g['height']:+8.2f}"
                f" {g['area']:+10.1f} {g['max_delta']:9.2f}{by}"
            )
    return "\n".join(lines)


def intake_lines(intake: dict) -> list[str]:
    """``inspect``'s lines on reading: units and where they came from, the pattern/drape
    length ratio, repairs (weld, dropped faces) and the drape's topology."""
    if not intake:
        return []
    lines = []
    un = intake.get("units") or {}
    if un:
        ratio = un.get("pattern_drape_ratio")
        lines.append(
            f"units: pattern {un.get('pattern')} ({un.get('pattern_source')}), drape "
            f"{un.get('drape')} ({un.get('drape_source')})"
            + (f"; pattern/drape edge length ratio {ratio:.3f}" if ratio is not None else "")
        )
    weld = intake.get("weld")
    welded = intake.get("welded_vertices", 0)
    dist = intake.get("weld_distance")
    if weld == "distance" and dist is not None:
        weld = f"{dist:.3g}"
    how = f"welded {welded} drape vertices (within {dist:.3g})" if welded else "no weld"
    pieces = ""
    if "pieces_before" in intake:
        pieces = f", drape pieces {intake['pieces_before']} -> {intake['pieces_after']}"
    lines.append(
        f"repairs: --weld {weld}: {how}{pieces}; dropped {intake.get('duplicate_faces', 0)} "
        f"duplicate, {intake.get('zero_area_faces_3d', 0)} zero-area 3D and "
        f"{intake.get('zero_area_faces_2d', 0)} zero-area 2D triangles; "
        f"{intake.get('non_manifold_edges', 0)} non-manifold edges"
    )
    topo = intake.get("topology")
    if topo:
        lines.append(
            "drape topology (pymeshlab): "
            + ", ".join(f"{k.replace('_', ' ')} {v}" for k, v in topo.items() if v is not None)
        )
    lines.extend(f"warning: {w}" for w in intake.get("warnings", []))
    return lines
