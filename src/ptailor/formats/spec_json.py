"""Pattern specifications (GarmentCode, Garment-Pattern-Generator JSON): reader and writer.

Both projects write ``{"pattern": {"panels": {NAME: panel}, "stitches": [...]},
"properties": {"units_in_meter": ...}, ...}``; a panel holds ``vertices`` (its own 2D
frame), ``edges`` (``{"endpoints": [i, j], "curvature": ...}`` in loop order),
``translation`` and ``rotation`` (XYZ Euler, degrees). They differ in the curvature:

- Garment-Pattern-Generator: ``"curvature": [u, v]``, one quadratic Bezier control point,
  relative to the edge (``properties.curvature_coords: relative``) or absolute;
- GarmentCode: ``"curvature": {"type": "quadratic" | "cubic" | "circle", "params": ...}``.

Stitches are ``[{"panel", "edge"}, {"panel", "edge"}]`` (older files:
``{"from": {...}, "to": {...}}``). The JSON is read as it is: no re-rooting of edge loops,
no flipping, no renumbering; the writer gives back the same structure with the new
geometry and keeps every key it does not change.
"""

from __future__ import annotations

import copy
import json
from pathlib import Path
from typing import Any

import numpy as np

from ptailor import tolerances as tol
from ptailor.errors import PtailorError
from ptailor.formats.json_input import read_json
from ptailor.geometry.curves import to_absolute, to_relative
from ptailor.model.specification import SpecEdge, Specification, SpecPanel, Stitch

__all__ = [
    "read_specification",
    "specification_beside",
    "specification_json",
    "write_specification",
]


def _finite(x: Any, n: int | None, *, what: str, path: str) -> np.ndarray:
    """``x`` as a float array of ``n`` numbers (any length when None), each finite and
    within ``tol.SPEC_MAX_COORD`` of zero."""
    ok = isinstance(x, list) and all(
        isinstance(v, (int, float)) and not isinstance(v, bool) for v in x
    )
    if ok and (n is None or len(x) == n):
        a = np.asarray(x, dtype=float)
        if not np.all(np.isfinite(a)):
            raise PtailorError(f"{what}: not a finite number in {x!r}", path=path)
        if np.any(np.abs(a) > tol.SPEC_MAX_COORD):
            raise PtailorError(
                f"{what}: a number beyond +-{tol.SPEC_MAX_COORD:g} in {json.dumps(x)[:80]}",
                path=path,
            )
        return a
    size = f"{n} numbers" if n is not None else "a list of numbers"
    raise PtailorError(f"{what}: expected {size}, got {json.dumps(x)[:80]}", path=path)


def _relative(P0, P1, pts: np.ndarray, *, what: str, path: str) -> np.ndarray:
    """Absolute control points ``(k, 2)`` relative to the edge ``P0 -> P1``, bounded."""
    if float(np.linalg.norm(P1 - P0)) <= tol.SPEC_MAX_COORD * np.finfo(float).eps:
        raise PtailorError(
            f"{what}: a curved edge whose two ends coincide (its absolute control points "
            "have no frame)",
            path=path,
        )
    rel = to_relative(P0, P1, pts)
    return _finite(rel.ravel().tolist(), None, what=f"{what} (relative)", path=path).reshape(-1, 2)


def _curvature(
    c: Any, P0: np.ndarray, P1: np.ndarray, *, absolute: bool, what: str, path: str
) -> tuple[str, np.ndarray, str]:
    """An edge's ``(kind, params, encoding)`` from its ``curvature`` value."""
    if c is None:
        return "straight", np.zeros(0), "none"
    if isinstance(c, list):  # Garment-Pattern-Generator: one control point
        p = _finite(c, 2, what=f"{what} curvature", path=path)
        rel = _relative(P0, P1, p[None], what=what, path=path)[0] if absolute else p
        return "quadratic", rel[None, :], "list"
    if not isinstance(c, dict) or "type" not in c:
        raise PtailorError(
            f"{what}: curvature must be [u, v] or {{type, params}}, got {json.dumps(c)[:80]}",
            path=path,
        )
    kind, params = c.get("type"), c.get("params")
    if kind in ("quadratic", "cubic"):
        k = 1 if kind == "quadratic" else 2
        if not isinstance(params, list) or len(params) != k:
            raise PtailorError(
                f"{what}: a {kind} curvature takes {k} control point(s) [u, v]", path=path
            )
        pts = np.array([_finite(q, 2, what=f"{what} {kind} control point", path=path)
                        for q in params])  # fmt: skip
        if absolute:
            pts = _relative(P0, P1, pts, what=what, path=path)
        return kind, pts, "typed"
    if kind == "circle":
        p = _finite(params, 3, what=f"{what} circle curvature [radius, large_arc, right]",
                    path=path)  # fmt: skip
        if p[0] <= 0 or p[1] not in (0, 1) or p[2] not in (0, 1):
            raise PtailorError(
                f"{what}: circle curvature needs a radius > 0 and flags 0 or 1, got {params}",
                path=path,
            )
        return kind, p, "typed"
    raise PtailorError(
        f"{what}: unknown curvature type {kind!r} (known: quadratic, cubic, circle)", path=path
    )


def _panel(name: str, p: Any, *, absolute: bool, path: str) -> SpecPanel:
    what = f"panel {name!r}"
    if not isinstance(p, dict):
        raise PtailorError(f"{what}: not an object", path=path)
    verts = p.get("vertices")
    if not isinstance(verts, list) or len(verts) < 2:
        raise PtailorError(f"{what}: needs a list of at least 2 vertices [x, y]", path=path)
    V = np.array([_finite(v, 2, what=f"{what} vertex {i}", path=path)
                  for i, v in enumerate(verts)])  # fmt: skip
    raw_edges = p.get("edges")
    if not isinstance(raw_edges, list) or len(raw_edges) < 2:
        raise PtailorError(f"{what}: needs a list of at least 2 edges", path=path)
    edges = []
    for i, e in enumerate(raw_edges):  # a loop over a panel's edges
        ew = f"{what} edge {i}"
        ends = e.get("endpoints") if isinstance(e, dict) else None
        if not (
            isinstance(ends, list)
            and len(ends) == 2
            and all(isinstance(k, int) and not isinstance(k, bool) for k in ends)
            and all(0 <= k < len(V) for k in ends)
        ):
            raise PtailorError(
                f"{ew}: endpoints must be two vertex indices in 0..{len(V) - 1}, got "
                f"{json.dumps(ends)}",
                path=path,
            )
        kind, params, enc = _curvature(
            e.get("curvature"), V[ends[0]], V[ends[1]], absolute=absolute, what=ew, path=path
        )
        edges.append(SpecEdge((ends[0], ends[1]), kind, params, enc))
    for i, e in enumerate(edges):  # the loop closes: each edge ends where the next starts
        nxt = edges[(i + 1) % len(edges)]
        if e.endpoints[1] != nxt.endpoints[0]:
            raise PtailorError(
                f"{what}: edges {i} and {(i + 1) % len(edges)} do not join (edge {i} ends at "
                f"vertex {e.endpoints[1]}, the next starts at {nxt.endpoints[0]}): the edges "
                "must form one closed loop in order",
                path=path,
            )
    T = _finite(p.get("translation", [0, 0, 0]), 3, what=f"{what} translation", path=path)
    R = _finite(p.get("rotation", [0, 0, 0]), 3, what=f"{what} rotation", path=path)
    return SpecPanel(name=name, vertices=V, edges=tuple(edges), translation=T, rotation=R)


def _stitch_side(s: Any, panels: dict[str, SpecPanel], *, what: str, path: str) -> tuple:
    if not isinstance(s, dict) or "panel" not in s or "edge" not in s:
        raise PtailorError(f"{what}: each side must be {{panel, edge}}", path=path)
    name, edge = s["panel"], s["edge"]
    if not isinstance(name, str):
        raise PtailorError(
            f"{what}: a side's panel must be a panel name, got {json.dumps(name)[:80]}",
            path=path,
        )
    if name not in panels:
        raise PtailorError(f"{what}: no panel {name!r} in the specification", path=path)
    n = len(panels[name].edges)
    if not isinstance(edge, int) or isinstance(edge, bool) or not 0 <= edge < n:
        raise PtailorError(
            f"{what}: panel {name!r} has no edge {edge!r} (it has edges 0..{n - 1})", path=path
        )
    return (name, edge)


def _stitches(pattern: dict, panels: dict[str, SpecPanel], *, path: str) -> list[Stitch]:
    """The stitches, each a pair of distinct panel edges, none repeated (either way round)."""
    raw = pattern.get("stitches")
    if raw is None:
        raw = []
    if not isinstance(raw, list):
        raise PtailorError(
            f"pattern.stitches must be a list of stitches, got {json.dumps(raw)[:80]}", path=path
        )
    stitches: list[Stitch] = []
    seen: dict[frozenset, int] = {}
    for i, s in enumerate(raw):  # a loop over stitches
        what = f"stitch {i}"
        if isinstance(s, dict) and "from" in s and "to" in s:
            s = [s["from"], s["to"]]
        if not isinstance(s, list) or len(s) != 2:
            raise PtailorError(f"{what}: must be a pair of {{panel, edge}}", path=path)
        sides = tuple(_stitch_side(x, panels, what=what, path=path) for x in s)
        label = " to ".join(f"{n}.{e}" for n, e in sides)
        if sides[0] == sides[1]:
            raise PtailorError(f"{what} ({label}): sews an edge to itself", path=path)
        key = frozenset(sides)
        if key in seen:
            raise PtailorError(
                f"{what} ({label}) repeats stitch {seen[key]}: each pair of edges is stitched once",
                path=path,
            )
        seen[key] = i
        stitches.append(Stitch(sides))  # type: ignore[arg-type]
    return stitches


def _parameters(raw: dict, panels: dict[str, SpecPanel], *, path: str) -> None:
    """Garment-Pattern-Generator's design parameters, where ptailor rewrites them: each
    ``influence`` a list of objects whose ``panel`` is a panel name and whose
    ``edge_list`` is a list."""
    params = raw.get("parameters")
    if params is None:
        return
    if not isinstance(params, dict):
        raise PtailorError("parameters must be an object of design parameters", path=path)
    for name, par in params.items():  # a loop over design parameters
        influence = par.get("influence") if isinstance(par, dict) else None
        if influence is None:
            continue
        what = f"design parameter {name!r}"
        if not isinstance(influence, list):
            raise PtailorError(f"{what}: influence must be a list", path=path)
        for k, inf in enumerate(influence):  # the panels it moves
            panel = inf.get("panel") if isinstance(inf, dict) else None
            if not isinstance(panel, str):
                raise PtailorError(
                    f"{what}: influence {k} must be {{panel: NAME, edge_list: [...]}}, got "
                    f"{json.dumps(inf)[:80]}",
                    path=path,
                )
            if "edge_list" in inf and not isinstance(inf["edge_list"], list):
                raise PtailorError(f"{what}: influence {k}: edge_list must be a list", path=path)


def _properties(raw: dict, *, path: str) -> tuple[float | None, bool]:
    """``(units_in_meter or None when absent, absolute)`` from ``properties``."""
    props = raw.get("properties", {})
    if not isinstance(props, dict):
        raise PtailorError("properties must be an object", path=path)
    um = props.get("units_in_meter")
    lo, hi = tol.SPEC_UNITS_IN_METER
    if um is not None and (
        isinstance(um, bool) or not isinstance(um, (int, float)) or not lo <= um <= hi
    ):
        raise PtailorError(
            f"properties.units_in_meter must be a number in [{lo:g}, {hi:g}], got "
            f"{json.dumps(um)[:40]}",
            path=path,
        )
    coords = props.get("curvature_coords", "relative")
    if coords not in ("relative", "absolute"):
        raise PtailorError(
            f"properties.curvature_coords must be relative or absolute, got "
            f"{json.dumps(coords)[:40]}",
            path=path,
        )
    return (None if um is None else float(um)), coords == "absolute"


def read_specification(path: str | Path, *, units_in_meter: float | None = None) -> Specification:
    """Read a GarmentCode or Garment-Pattern-Generator specification JSON.

    Parameters
    ----------
    path : str or Path
    units_in_meter : float, optional
        The specification's unit (units per metre), given: it replaces the file's
        ``properties.units_in_meter`` (``--spec-units``).

    Returns
    -------
    Specification
        Its ``units_source`` says where the unit came from: ``file``, ``option``, or
        ``absent`` (then ``units_in_meter`` is 100, to be inferred from the garment:
        :func:`ptailor.run.spec.spec_unit`).

    Raises
    ------
    PtailorError
        The file is missing, not JSON (too large, too deep, a key repeated), or not a
        specification; naming the panel, edge, stitch or design parameter at fault.
    """
    path = str(path)
    raw = read_json(path, what="specification")
    pattern = raw.get("pattern") if isinstance(raw, dict) else None
    if not isinstance(pattern, dict) or not isinstance(pattern.get("panels"), dict):
        raise PtailorError("not a pattern specification: no pattern.panels object", path=path)
    if not pattern["panels"]:
        raise PtailorError("the specification has no panels", path=path)
    if len(pattern["panels"]) > tol.SPEC_MAX_PANELS:
        raise PtailorError(
            f"{len(pattern['panels'])} panels (at most {tol.SPEC_MAX_PANELS})", path=path
        )
    n_edges = sum(
        len(p["edges"]) if isinstance(p, dict) and isinstance(p.get("edges"), list) else 0
        for p in pattern["panels"].values()
    )
    if n_edges > tol.SPEC_MAX_EDGES:
        raise PtailorError(f"{n_edges} edges (at most {tol.SPEC_MAX_EDGES})", path=path)
    um, absolute = _properties(raw, path=path)
    panels = {n: _panel(n, p, absolute=absolute, path=path) for n, p in pattern["panels"].items()}
    stitches = _stitches(pattern, panels, path=path)
    _parameters(raw, panels, path=path)
    typed = any(e.encoding == "typed" for p in panels.values() for e in p.edges)
    flavour = "garmentcode" if typed or "panel_order" in pattern else "gpg"
    source = "option" if units_in_meter is not None else ("file" if um is not None else "absent")
    return Specification(
        path=path,
        flavour=flavour,
        panels=tuple(panels.values()),
        stitches=tuple(stitches),
        units_in_meter=float(units_in_meter or um or 100.0),
        raw=raw,
        units_source=source,
    )


def _edge_json(e: SpecEdge, V: np.ndarray, old: dict | None, *, flavour: str, absolute: bool):
    out = {k: v for k, v in (old or {}).items() if k not in ("endpoints", "curvature")}
    out = {"endpoints": [int(e.endpoints[0]), int(e.endpoints[1])], **out}
    if e.kind == "straight":
        return out
    P0, P1 = V[e.endpoints[0]], V[e.endpoints[1]]
    if e.kind == "circle":
        r, large, right = (float(x) for x in e.params)
        out["curvature"] = {"type": "circle", "params": [r, int(large), int(right)]}
        return out
    pts = to_absolute(P0, P1, e.params) if absolute else np.asarray(e.params).reshape(-1, 2)
    enc = e.encoding if e.encoding != "none" else ("list" if flavour == "gpg" else "typed")
    if enc == "list" and e.kind == "quadratic":
        out["curvature"] = [float(pts[0, 0]), float(pts[0, 1])]
    else:
        out["curvature"] = {"type": e.kind, "params": [[float(a), float(b)] for a, b in pts]}
    return out


def specification_json(spec: Specification, *, edge_sources: dict | None = None) -> dict:
    """The JSON of ``spec``: its ``raw`` with panels and stitches replaced.

    Parameters
    ----------
    spec : Specification
    edge_sources : dict, optional
        Panel name to, per edge, the index of the input edge it came from (``-1``: new);
        its other keys (labels) are kept. Default: edge ``i`` came from edge ``i``.
    """
    raw = copy.deepcopy(spec.raw)
    pattern = raw.setdefault("pattern", {})
    old_panels = pattern.get("panels", {})
    props = raw.get("properties") if isinstance(raw.get("properties"), dict) else {}
    absolute = props.get("curvature_coords", "relative") == "absolute"
    panels = {}
    for p in spec.panels:  # a loop over panels
        old = old_panels.get(p.name, {})
        old_edges = old.get("edges", []) if isinstance(old, dict) else []
        src = (edge_sources or {}).get(p.name, list(range(len(p.edges))))
        edges = [
            _edge_json(e, p.vertices, old_edges[s] if 0 <= s < len(old_edges) else None,
                       flavour=spec.flavour, absolute=absolute)
            for e, s in zip(p.edges, src, strict=True)
        ]  # fmt: skip
        new = dict(old) if isinstance(old, dict) else {}
        new["vertices"] = [[float(x), float(y)] for x, y in p.vertices]
        new["edges"] = edges
        new["translation"] = [float(x) for x in p.translation]
        new["rotation"] = [float(x) for x in p.rotation]
        panels[p.name] = {k: new[k] for k in (*old.keys(), *new.keys()) if k in new}
    pattern["panels"] = panels
    if "panel_order" in pattern:
        pattern["panel_order"] = [n for n in pattern["panel_order"] if n in panels]
    old_st = pattern.get("stitches", [])
    stitches = []
    for i, s in enumerate(spec.stitches):  # a loop over stitches
        sides = [{"panel": n, "edge": int(e)} for n, e in s.sides]
        if i < len(old_st) and isinstance(old_st[i], dict) and "from" in old_st[i]:
            stitches.append({**old_st[i], "from": sides[0], "to": sides[1]})
        else:
            stitches.append(sides)
    pattern["stitches"] = stitches
    if edge_sources and isinstance(raw.get("parameters"), dict):
        _renumber_parameters(raw["parameters"], edge_sources)
    return raw


def _renumber_parameters(params: dict, edge_sources: dict) -> None:
    """Garment-Pattern-Generator's design parameters name edges by id
    (``influence[].edge_list[]``: an id, or ``{"id": id or [ids], ...}``): the ids follow
    their edges to where the writer put them; an id whose edge left the pattern is dropped
    (an entry left without ids is dropped too)."""
    for par in params.values():  # a loop over design parameters
        influence = par.get("influence") if isinstance(par, dict) else None
        for inf in influence if isinstance(influence, list) else []:  # the panels it moves
            src = edge_sources.get(inf.get("panel")) if isinstance(inf, dict) else None
            if src is None or not isinstance(inf.get("edge_list"), list):
                continue
            new_id = {int(s): i for i, s in enumerate(src) if s >= 0}

            def moved(x, new_id=new_id):
                if isinstance(x, int) and not isinstance(x, bool):
                    return new_id.get(x)
                if isinstance(x, list):
                    got = [new_id[v] for v in x if isinstance(v, int) and v in new_id]
                    return got or None
                return x

            items = []
            for item in inf["edge_list"]:  # the edges it moves
                if isinstance(item, dict) and "id" in item:
                    got = moved(item["id"])
                    if got is not None:
                        items.append({**item, "id": got})
                elif (got := moved(item)) is not None:
                    items.append(got)
            inf["edge_list"] = items


def write_specification(path: str | Path, spec: Specification, **options: Any) -> None:
    """Write ``spec`` as JSON (:func:`specification_json`'s options), two-space indented."""
    text = json.dumps(specification_json(spec, **options), indent=2)
    Path(path).write_text(text + "\n", encoding="utf-8")


def specification_beside(garment: str | Path) -> str | None:
    """The specification that comes beside a garment mesh (``--spec auto``), or None.

    GarmentCode and Garment-Pattern-Generator name it after the garment and drop the
    mesh's own suffix: ``tee6_sim.obj`` has ``tee6_specification.json``,
    ``shirt_mean_boxmesh.obj`` ``shirt_mean_specification.json``. Looked for, in order:
    ``STEM_specification.json`` for the stem and each shorter prefix of it at an
    underscore (``shirt_mean_boxmesh``, ``shirt_mean``, ``shirt``), then
    ``specification.json`` in the same folder.
    """
    p = Path(garment)
    parts = p.stem.split("_")
    names = [f"{'_'.join(parts[:n])}_specification.json" for n in range(len(parts), 0, -1)]
    for name in [*names, "specification.json"]:  # nearest name first
        q = p.with_name(name)
        if q.is_file():
            return str(q)
    return None
