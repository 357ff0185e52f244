"""Wavefront OBJ with ``v`` = drape and ``vt`` = pattern (faces ``f v/vt[/vn]``).

The layout CLO 3D, Marvelous Designer and the public garment datasets use. Parsing is
vectorised: a well-formed file is scanned in bulk (:mod:`ptailor.formats.obj_scan`, the
same arrays), anything unusual is parsed record kind by record kind here, each record kind
joined and converted by numpy in one call, every problem named with the file.
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ptailor import tolerances as tol
from ptailor.errors import PtailorError
from ptailor.formats.obj_scan import Scan, scan

if TYPE_CHECKING:
    from ptailor.model.garment import Garment


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


_GROUP = re.compile(rb"^[go](?:[ \t]+([^\r\n]*?))?[ \t]*\r?$", re.M)


def _records(raw: bytes, tag: bytes) -> list[bytes]:
    """Bodies of the records ``tag ...`` (text after the tag), in file order."""
    # a bare tag (a line "v" alone) is a record too, of no values: skipping it would shift
    # every later index by one
    return re.findall(rb"^" + tag + rb"(?:[ \t]+([^\r\n]*)|[ \t]*(?=\r?$))", raw, re.M)


_HUGE_INDEX = "face refers to a missing vertex (index out of range: beyond any file's size)"


class _IndexOverflowError(Exception):
    """A face index too large for a 64-bit integer."""


def _numbers(bodies: list[bytes], dtype: type) -> np.ndarray | None:
    """Parse equal-length records in one call; None when they are ragged."""
    ncol = len(bodies[0].split())
    joined = b" ".join(bodies)
    try:
        vals = np.array(joined.split(), dtype=dtype)
    except ValueError:
        return None
    except OverflowError:  # an integer beyond int64: an index no file can hold
        raise _IndexOverflowError from None
    if ncol == 0 or vals.size != ncol * len(bodies):
        return None
    return vals.reshape(len(bodies), ncol)


def _floats(bodies: list[bytes], path: str, what: str, width: int) -> np.ndarray:
    """Parse records such as ``v x y z`` into an ``(k, width)`` array (extra columns dropped)."""
    if not bodies:
        return np.zeros((0, width))
    arr = _numbers(bodies, np.float64)
    if arr is None:
        # ragged records (an optional w, colours on some lines): the slow, exact path
        rows = [b.split() for b in bodies]
        counts = np.array([len(r) for r in rows])
        _check_count(counts, bodies, path, what, width)
        try:
            arr = np.array([r[:width] for r in rows], dtype=np.float64)
        except ValueError as exc:
            raise PtailorError(f"unreadable '{what}' record ({exc})", path=path) from None
    return _coords(arr, path, what, width)


def _check_count(counts: np.ndarray, bodies: list[bytes] | None, path: str, what: str,
                 width: int) -> None:  # fmt: skip
    """Every ``what`` record has at least ``width`` values (``v x y z``, ``vt u v``): a
    short one is an error naming it, not a reason to cut every record to its length (one
    ``v`` without z once flattened the whole drape)."""
    short = np.flatnonzero(counts < width)
    if not len(short):
        return
    i = int(short[0])
    body = b"" if bodies is None else bodies[i].strip()
    text = f": '{body.decode('utf-8', 'replace')[:60]}'" if body else ""
    raise PtailorError(
        f"'{what}' record {i + 1} has {int(counts[i])} value(s), needs {width}{text}"
        f" ({len(short)} such record(s))",
        path=path,
    )


def _coords(arr: np.ndarray, path: str, what: str, width: int) -> np.ndarray:
    """``(k, c)`` record numbers (``c >= width``) as ``(k, width)`` coordinates (cut),
    each checked finite and within ``OBJ_COORD_MAX``."""
    _check_count(np.full(len(arr), arr.shape[1]), None, path, what, width)
    arr = arr[:, :width]
    with np.errstate(invalid="ignore"):
        bad = ~(np.abs(arr) <= tol.OBJ_COORD_MAX)  # NaN compares False: caught too
    if bad.any():
        row, col = (int(i[0]) for i in np.nonzero(bad))
        x = float(arr[row, col])
        what_x = "NaN or infinite" if not np.isfinite(x) else f"beyond {tol.OBJ_COORD_MAX:g}"
        raise PtailorError(
            f"'{what}' record {row + 1}: coordinate {x:g} is {what_x} "
            f"(coordinates must be finite, |x| <= {tol.OBJ_COORD_MAX:g} file units)",
            path=path,
        )
    return arr


def _faces(
    bodies: list[bytes], nv: int, nt: int, path: str
) -> tuple[np.ndarray, np.ndarray | None, np.ndarray]:
    """Parse ``f`` records; return (fv, fvt or None, polygon index of each triangle)."""
    k = bodies[0].split()[0].count(b"/") if bodies[0].split() else 0
    if k > 2:
        raise PtailorError("unreadable 'f' record (more than two '/' in a corner)", path=path)
    flat = [b.replace(b"//", b"/0/").replace(b"/", b" ") for b in bodies]
    try:
        nums = _numbers(flat, np.int64)
    except _IndexOverflowError:
        raise PtailorError(_HUGE_INDEX, path=path) from None
    if nums is not None and nums.shape[1] % (k + 1) == 0:
        corners_per = np.full(len(bodies), nums.shape[1] // (k + 1), dtype=np.int64)
        nums = nums.reshape(-1, k + 1)
    else:
        corners_per = np.array([len(b.split()) for b in bodies], dtype=np.int64)
        try:
            nums = _numbers([b" ".join(flat)], np.int64)
        except _IndexOverflowError:
            raise PtailorError(_HUGE_INDEX, path=path) from None
        if nums is None or nums.size != corners_per.sum() * (k + 1):
            raise PtailorError("faces mix corner formats (v, v/vt, v/vt/vn, v//vn)", path=path)
        nums = nums.reshape(-1, k + 1)
    return _fan(nums, corners_per, k, nv, nt, path)


def _fan(
    nums: np.ndarray, corners_per: np.ndarray, k: int, nv: int, nt: int, path: str
) -> tuple[np.ndarray, np.ndarray | None, np.ndarray]:
    """Corner fields ``nums`` ((c, k + 1) ints, file order) of polygons of ``corners_per``
    corners as fan triangles: ``(fv, fvt or None, polygon index of each triangle)``."""
    if np.any(corners_per < 3):
        bad = int(np.flatnonzero(corners_per < 3)[0])
        raise PtailorError(f"face {bad + 1} has fewer than 3 corners", path=path)
    n_tri = int((corners_per - 2).sum())
    if n_tri > tol.OBJ_MAX_TRIANGLES:
        raise PtailorError(
            f"{n_tri} triangles: more than the {tol.OBJ_MAX_TRIANGLES} ptailor reads", path=path
        )
    has_vt = k >= 1 and not np.all(nums[:, 1] == 0)

    def resolve(idx: np.ndarray, count: int, what: str) -> np.ndarray:
        out = np.where(idx < 0, idx + count, idx - 1)
        bad = (out < 0) | (out >= count) | (idx == 0)
        if np.any(bad):
            first = int(idx[np.flatnonzero(bad)[0]])
            raise PtailorError(
                f"face refers to a missing '{what}' (index {first} out of range: the file has "
                f"{count} '{what}' records, indices 1..{count} or -{count}..-1)",
                path=path,
            )
        return out

    cv = resolve(nums[:, 0], nv, "v")
    cvt = resolve(nums[:, 1], nt, "vt") if has_vt else None
    # fan triangulation, vectorised over polygons
    start = np.concatenate([[0], np.cumsum(corners_per)[:-1]])
    ntri = corners_per - 2
    poly = np.repeat(np.arange(len(corners_per)), ntri)
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
        size = Path(path).stat().st_size
        if size > tol.OBJ_MAX_BYTES:
            raise PtailorError(
                f"file of {size} bytes: larger than the {tol.OBJ_MAX_BYTES} bytes ptailor reads",
                path=spath,
            )
        raw = Path(path).read_bytes()
    except FileNotFoundError:
        raise PtailorError("no such file", path=spath) from None
    except IsADirectoryError:
        raise PtailorError("is a folder, not an OBJ file", path=spath) from None
    except OSError as exc:
        raise PtailorError(f"cannot read file ({exc.strerror})", path=spath) from None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # no library warning is printed before the error line
        with np.errstate(all="ignore"):
            return _parse(raw, spath)


def _check_text(raw: bytes, spath: str) -> tuple[bytes, np.ndarray]:
    """The file's bytes without a UTF-8 BOM, with \\n line ends, and the positions of its
    \\n; line lengths checked."""
    if raw.startswith(b"\xef\xbb\xbf"):
        raw = raw[3:]
    if b"\0" in raw:
        raise PtailorError("not an OBJ file (binary content)", path=spath)
    if b"\n" not in raw and b"\r" in raw:  # classic Mac line ends
        raw = raw.replace(b"\r", b"\n")
    ends = np.flatnonzero(np.frombuffer(raw, dtype=np.uint8) == 10)
    bounds = np.concatenate([[-1], ends, [len(raw)]])
    lengths = np.diff(bounds) - 1
    if lengths.size and int(lengths.max()) > tol.OBJ_MAX_LINE:
        line = int(np.argmax(lengths))
        raise PtailorError(
            f"line {line + 1} is {int(lengths[line])} bytes long: longer than the "
            f"{tol.OBJ_MAX_LINE} bytes an OBJ line may have",
            path=spath,
        )
    return raw, ends


def _header(raw: bytes) -> tuple[str, ...]:
    """The leading comment lines (without ``#``), for unit hints."""
    header: list[str] = []
    for ln in raw[:4096].decode("utf-8", errors="replace").splitlines():
        ln = ln.strip()
        if ln and not ln.startswith("#"):
            break
        if ln:
            header.append(ln.lstrip("#").strip())
    return tuple(header)


def _parse(raw: bytes, spath: str) -> ObjMesh:
    raw, ends = _check_text(raw, spath)
    fast = scan(raw, ends)  # a well-formed file in bulk, else None
    if fast is not None:
        return _from_scan(fast, spath, _header(raw))
    return _parse_records(raw, spath, _header(raw))


def _from_scan(fast: Scan, spath: str, header: tuple[str, ...]) -> ObjMesh:
    """The mesh of a bulk scan, checked as :func:`_parse_records` checks it, in its order."""
    v = _coords(fast.v, spath, "v", 3)
    vt = _coords(fast.vt, spath, "vt", 2) if fast.vt is not None else np.zeros((0, 2))
    fv, fvt, poly = _fan(fast.nums, fast.corners_per, fast.slashes, len(v), len(vt), spath)
    return _mesh(v, vt, fv, fvt, poly, fast.group_lines, fast.face_line_group + 1, header, spath)


def _parse_records(raw: bytes, spath: str, header: tuple[str, ...]) -> ObjMesh:
    """The record-by-record parser: any file, each problem named."""
    # split at g/o records: chunk i follows group name i (chunk 0 has no group)
    parts = _GROUP.split(raw)
    chunks, gnames = (
        parts[0::2],
        [(n or b"").decode("utf-8", errors="replace").strip() for n in parts[1::2]],
    )
    f_chunks = [_records(c, b"f") for c in chunks]
    f_b = [b for fc in f_chunks for b in fc]
    v_b = _records(raw, b"v")
    if not v_b or not f_b:
        raise PtailorError("not an OBJ file (no 'v' or no 'f' records)", path=spath)
    v = _floats(v_b, spath, "v", 3)
    vt = _floats(_records(raw, b"vt"), spath, "vt", 2)
    fv, fvt, poly = _faces(f_b, len(v), len(vt), spath)
    per_chunk = np.array([len(fc) for fc in f_chunks], dtype=np.int64)
    face_chunk = np.repeat(np.arange(len(f_chunks)), per_chunk)
    return _mesh(v, vt, fv, fvt, poly, gnames, face_chunk, header, spath)


def _mesh(
    v: np.ndarray,
    vt: np.ndarray,
    fv: np.ndarray,
    fvt: np.ndarray | None,
    poly: np.ndarray,
    gnames: list[str],
    face_chunk: np.ndarray,
    header: tuple[str, ...],
    spath: str,
) -> ObjMesh:
    """The mesh, its group names checked; ``face_chunk``: per ``f`` record, 0 before any
    ``g``/``o`` record, else 1 + the index in ``gnames`` of the last one before it."""
    long_names = [n for n in gnames if len(n) > tol.OBJ_MAX_NAME]
    if long_names:
        raise PtailorError(
            f"a group name ('g'/'o' record) is {len(long_names[0])} characters long: longer "
            f"than the {tol.OBJ_MAX_NAME} ptailor reads ({long_names[0][:24]!r}...)",
            path=spath,
        )
    names = tuple(dict.fromkeys(n for n in gnames if n))
    name_idx = {n: i for i, n in enumerate(names)}
    chunk_group = np.array([-1] + [name_idx.get(n, -1) for n in gnames], dtype=np.int64)
    face_group = chunk_group[face_chunk][poly]
    return ObjMesh(
        v=v, vt=vt, fv=fv, fvt=fvt, face_group=face_group, group_names=names, header=header
    )


def _block(prefix: str, X: np.ndarray, path: str | Path = "") -> str:
    if len(X) == 0:
        return ""
    if not np.all(np.isfinite(X)):
        # never write NaN or infinity: fail the run (exit 2) rather than corrupt the file
        n = int((~np.isfinite(X)).any(axis=1).sum())
        raise PtailorError(
            f"refusing to write {n} non-finite '{prefix}' coordinate row(s)",
            path=Path(path).name or None,
        )
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
    header: Sequence[str] = (),
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
    parts = ["".join(f"# {h}\n" for h in header), _block("v", V3, path), _block("vt", V2, path)]
    fp = face_panel[order]
    cuts = np.flatnonzero(np.diff(fp)) + 1
    for grp in np.split(order, cuts) if len(order) else []:
        a, b = F3[grp] + 1, F2[grp] + 1
        rows = np.stack([a[:, 0], b[:, 0], a[:, 1], b[:, 1], a[:, 2], b[:, 2]], 1)
        parts.append(f"g {panel_names[int(face_panel[grp[0]])]}\n")
        parts.append(("f %d/%d %d/%d %d/%d\n" * len(rows)) % tuple(rows.ravel().tolist()))
    Path(path).write_text("".join(parts))


def write_garment(path: str | Path, garment: Garment, *, header: Sequence[str] = ()) -> None:
    """Write a :class:`~ptailor.model.Garment` as OBJ, one ``g`` group per panel.

    Parameters
    ----------
    path : str or Path
    garment : Garment
    header : list of str
        Comment lines written first.
    """
    from ptailor.model.structure import structure

    # the panels as the garment's groups name them (what a sample or a written garment has);
    # unnamed panels get names from the drape under the garment's own frame
    st = structure(garment)
    plist = st.panels
    write_obj(
        path,
        V3=garment.V3,
        F3=garment.F3,
        V2=garment.V2,
        F2=garment.F2,
        face_panel=st.face_panel,
        panel_names=[p.name for p in plist],
        header=[*header, *filter(None, [garment.frame.header()])],
    )
