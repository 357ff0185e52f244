"""Wavefront OBJ with ``v`` = drape and ``vt`` = pattern (faces ``f v/vt[/vn]``).

The layout CLO 3D, Marvelous Designer and the public garment datasets use. Parsing is
vectorised: each record kind is joined and converted by numpy in one call.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ptailor.errors import PtailorError


@dataclass(frozen=True)
class ObjMesh:
    """The raw content of an OBJ file.

    Attributes
    ----------
    v : (nv, 3) float array
        Vertex positions (a 2D ``v`` gets z = 0).
    vt : (nt, 2) float array
        Texture coordinates (empty when absent).
    fv : (m, 3) int array
        Triangles as 0-based ``v`` indices (polygons fan-triangulated).
    fvt : (m, 3) int array or None
        The same triangles as ``vt`` indices, or None when the faces carry none.
    face_group : (m,) int array
        Index into ``group_names`` of the ``g``/``o`` group each triangle follows (-1: none).
    group_names : tuple of str
    header : tuple of str
        Leading comment lines (without ``#``), for unit hints.
    """

    v: np.ndarray
    vt: np.ndarray
    fv: np.ndarray
    fvt: np.ndarray | None
    face_group: np.ndarray
    group_names: tuple[str, ...]
    header: tuple[str, ...]


def _floats(lines: list[str], path: str, what: str, width: int) -> np.ndarray:
    """Parse records such as ``v x y z`` into an ``(k, width)`` array (extra columns dropped)."""
    if not lines:
        return np.zeros((0, width))
    counts = np.fromiter((ln.count(" ") for ln in lines), dtype=np.int64, count=len(lines))
    body = " ".join(ln.split(None, 1)[1] if " " in ln else "" for ln in lines)
    try:
        vals = np.array(body.split(), dtype=np.float64)
    except ValueError as exc:
        raise PtailorError(f"unreadable '{what}' record ({exc})", path=path) from None
    ncol = len(vals) // len(lines) if len(vals) % len(lines) == 0 else -1
    if ncol >= 2 and np.all(counts == counts[0]):
        arr = vals.reshape(len(lines), ncol)
    else:
        # ragged records (tabs, double spaces, optional w): the slow, exact path
        rows = [ln.split()[1:] for ln in lines]
        ncol = min(len(r) for r in rows)
        arr = np.array([r[:ncol] for r in rows], dtype=np.float64)
    if arr.shape[1] < 2:
        raise PtailorError(f"'{what}' records need at least 2 coordinates", path=path)
    if arr.shape[1] < width:
        arr = np.hstack([arr, np.zeros((len(arr), width - arr.shape[1]))])
    return arr[:, :width]


def _faces(
    lines: list[str], nv: int, nt: int, path: str
) -> tuple[np.ndarray, np.ndarray | None, np.ndarray]:
    """Parse ``f`` records; return (fv, fvt or None, polygon index of each triangle)."""
    corners_per = np.array([len(ln.split()) - 1 for ln in lines], dtype=np.int64)
    if np.any(corners_per < 3):
        bad = int(np.flatnonzero(corners_per < 3)[0])
        raise PtailorError(f"face {bad + 1} has fewer than 3 corners", path=path)
    corners = " ".join(ln.split(None, 1)[1] for ln in lines).split()
    slashes = {c.count("/") for c in corners[:: max(1, len(corners) // 1000)]}
    k = corners[0].count("/")
    joined = " ".join(corners)
    if len(slashes) != 1 or joined.count("/") != k * len(corners) or k > 2:
        raise PtailorError("faces mix corner formats (v, v/vt, v/vt/vn, v//vn)", path=path)
    try:
        nums = np.array(
            joined.replace("//", "/0/").replace("/", " ").split(), dtype=np.int64
        ).reshape(len(corners), k + 1)
    except ValueError:
        raise PtailorError("unreadable 'f' record", path=path) from None
    has_vt = k >= 1 and not np.all(nums[:, 1] == 0) if k else False

    def resolve(idx: np.ndarray, count: int, what: str) -> np.ndarray:
        out = np.where(idx < 0, idx + count, idx - 1)
        if np.any((out < 0) | (out >= count)) or np.any(idx == 0):
            raise PtailorError(f"face refers to a missing '{what}' (index out of range)", path=path)
        return out

    cv = resolve(nums[:, 0], nv, "v")
    cvt = resolve(nums[:, 1], nt, "vt") if has_vt else None
    # fan triangulation, vectorised over polygons
    start = np.concatenate([[0], np.cumsum(corners_per)[:-1]])
    ntri = corners_per - 2
    poly = np.repeat(np.arange(len(lines)), ntri)
    local = np.arange(ntri.sum()) - np.repeat(np.cumsum(ntri) - ntri, ntri)
    base = start[poly]
    tri = np.stack([base, base + local + 1, base + local + 2], axis=1)
    return cv[tri], (cvt[tri] if cvt is not None else None), poly


def read_obj(path: str | Path) -> ObjMesh:
    """Read an OBJ file.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    ObjMesh

    Raises
    ------
    PtailorError
        Missing or unreadable file, no vertices or faces, indices out of range.
    """
    spath = str(path)
    try:
        raw = Path(path).read_bytes()
    except FileNotFoundError:
        raise PtailorError("no such file", path=spath) from None
    except OSError as exc:
        raise PtailorError(f"cannot read file ({exc.strerror})", path=spath) from None
    if b"\0" in raw[:4096]:
        raise PtailorError("not an OBJ file (binary content)", path=spath)
    text = raw.decode("utf-8", errors="replace")
    lines = [ln.strip() for ln in text.splitlines()]
    header: list[str] = []
    for ln in lines:
        if ln and not ln.startswith("#"):
            break
        if ln:
            header.append(ln.lstrip("#").strip())
    v_l = [ln for ln in lines if ln.startswith("v ") or ln.startswith("v\t")]
    vt_l = [ln for ln in lines if ln.startswith("vt ") or ln.startswith("vt\t")]
    kinds = np.array([ln[:2] for ln in lines], dtype="<U2")
    is_f = (kinds == "f ") | (kinds == "f\t")
    is_g = np.isin(kinds, ["g ", "o ", "g\t", "o\t", "g", "o"])
    f_l = [lines[i] for i in np.flatnonzero(is_f)]
    if not v_l or not f_l:
        raise PtailorError("not an OBJ file (no 'v' or no 'f' records)", path=spath)
    v = _floats(v_l, spath, "v", 3)
    vt = _floats(vt_l, spath, "vt", 2)
    fv, fvt, poly = _faces(f_l, len(v), len(vt), spath)
    # group of each face: the last g/o line before it
    g_pos = np.flatnonzero(is_g)
    g_names_all = [lines[i].split(None, 1)[1].strip() if " " in lines[i] else "" for i in g_pos]
    names = tuple(dict.fromkeys(n for n in g_names_all if n))
    name_idx = {n: i for i, n in enumerate(names)}
    g_idx = np.array([name_idx.get(n, -1) for n in g_names_all] or [-1], dtype=np.int64)
    f_pos = np.flatnonzero(is_f)[poly]
    which = np.searchsorted(g_pos, f_pos) - 1
    face_group = (
        np.where(which >= 0, g_idx[np.maximum(which, 0)], -1)
        if len(g_pos)
        else (np.full(len(fv), -1, dtype=np.int64))
    )
    return ObjMesh(
        v=v,
        vt=vt,
        fv=fv,
        fvt=fvt,
        face_group=face_group,
        group_names=names,
        header=tuple(header),
    )


def _block(prefix: str, X: np.ndarray) -> str:
    if len(X) == 0:
        return ""
    # one formatting call over the whole array (no Python loop over vertices)
    fmt = prefix + " " + " ".join(["%.9g"] * X.shape[1]) + "\n"
    return (fmt * len(X)) % tuple(X.ravel().tolist())


def write_obj(
    path: str | Path,
    *,
    V3: np.ndarray,
    F3: np.ndarray,
    V2: np.ndarray,
    F2: np.ndarray,
    face_panel: np.ndarray,
    panel_names: list[str],
    header: list[str] = (),  # type: ignore[assignment]
) -> None:
    """Write a garment OBJ: ``v`` = drape, ``vt`` = pattern, one ``g`` group per panel.

    Parameters
    ----------
    path : str or Path
    V3 : (n3, 3) float array
    F3 : (m, 3) int array
    V2 : (n2, 2) float array
    F2 : (m, 3) int array
    face_panel : (m,) int array
        Panel index per triangle; triangles are written grouped by panel, in order.
    panel_names : list of str
    header : list of str
        Comment lines written first.
    """
    order = np.argsort(face_panel, kind="stable")
    parts = ["".join(f"# {h}\n" for h in header), _block("v", V3), _block("vt", V2)]
    fp = face_panel[order]
    cuts = np.flatnonzero(np.diff(fp)) + 1
    for grp in np.split(order, cuts) if len(order) else []:
        a, b = F3[grp] + 1, F2[grp] + 1
        rows = np.stack([a[:, 0], b[:, 0], a[:, 1], b[:, 1], a[:, 2], b[:, 2]], 1)
        parts.append(f"g {panel_names[int(face_panel[grp[0]])]}\n")
        parts.append(("f %d/%d %d/%d %d/%d\n" * len(rows)) % tuple(rows.ravel().tolist()))
    Path(path).write_text("".join(parts))
