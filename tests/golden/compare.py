"""Golden expectations: how an output folder is stored and compared.

A text output (OBJ, SVG, DXF, JSON, YAML, the ``.ptailor`` stamp) is split into its
*skeleton* (the text with every number replaced by ``#``) and its *numbers*. The skeleton
must be identical: the same lines, names, topology, keys, entity kinds. The numbers must
agree within the stated tolerances:

- ``ABS`` = 1e-6 and ``REL`` = 1e-6: ``|a - b| <= ABS + REL * |b|`` (the unit of the
  file: cm, except where a file says otherwise), and
- a printed number may also differ by one unit in its last printed digit (a value on a
  rounding boundary: ``12.345`` vs ``12.346`` in an SVG printed to 0.01 mm).

``report.json``'s ``timing_s`` and each ``path`` differ between runs and are left out (so
is the hash of an input an earlier run of the case wrote: :data:`VOLATILE_INPUTS`);
the run's temporary folder, the repository and ../shared/garments are written ``<RUN>``,
``<ROOT>`` and ``<SHARED>`` in every file. A PNG is compared by its
pixels: at most ``PNG_PIXELS`` of them may differ by more than ``PNG_LEVEL`` (antialiased
edges move with the last bit of a coordinate).

Integers (face indices, counts, DXF group codes) must be equal: the last-digit allowance is
for numbers with a decimal point or exponent, and of the two files' precisions the finer.
"""

from __future__ import annotations

import io
import json
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

ABS = 1e-6
REL = 1e-6
PNG_PIXELS = 0.002
PNG_LEVEL = 48

#: a number not inside a word (``tee6`` stays text); hashes (``c298f5...``) are masked first
_NUMBER = re.compile(rb"(?<![A-Za-z0-9_.])[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")
_HASH = re.compile(rb"(?<![0-9A-Za-z])(?=[0-9]*[a-fA-F])[0-9a-fA-F]{32,}(?![0-9A-Za-z])")
#: report.json keys whose values change from run to run
VOLATILE_KEYS = frozenset({"timing_s", "path", "seconds"})
#: inputs that an earlier ptailor run of the case wrote (the ``dxf-of`` cases' DXF): their
#: ``sha256`` is left out, as their bytes carry that run's last bits (1e-10 of a mm in a
#: coordinate), which numpy and BLAS versions move; the outputs made from them are compared
VOLATILE_INPUTS = ("<RUN>/identity/",)


@dataclass(frozen=True)
class Stored:
    """One output file as stored: skeleton bytes, numbers, and each number's last digit."""

    skeleton: bytes
    numbers: np.ndarray  # (n,) float
    ulps: np.ndarray  # (n,) float: one unit in the last printed digit


def _clean_json(obj):
    if isinstance(obj, dict):
        written = str(obj.get("path", "")).startswith(VOLATILE_INPUTS)
        return {
            k: _clean_json(v)
            for k, v in obj.items()
            if k not in VOLATILE_KEYS and not (written and k == "sha256")
        }
    if isinstance(obj, list):
        return [_clean_json(v) for v in obj]
    return obj


def _ulp(token: bytes) -> float:
    if b"." not in token and b"e" not in token.lower():
        return 0.0  # an integer: exact
    mant, _, exp = token.lower().partition(b"e")
    digits = mant.split(b".")[1] if b"." in mant else b""
    return 10.0 ** min(300, -len(digits) + (int(exp) if exp else 0))


def text_parts(data: bytes) -> Stored:
    """Split a text file into skeleton and numbers."""
    pieces = _HASH.split(data)
    hashes = _HASH.findall(data)
    tokens = [t for piece in pieces for t in _NUMBER.findall(piece)]
    masked = [_NUMBER.sub(b"#", piece) for piece in pieces]
    skeleton = b"".join(m + h for m, h in zip(masked, [*hashes, b""], strict=True))
    numbers = np.array([float(t) for t in tokens], dtype=float)
    ulps = np.array([_ulp(t) for t in tokens], dtype=float)
    return Stored(skeleton, numbers, ulps)


def normalised(path: Path, places: dict[str, Path]) -> bytes:
    """The file's bytes, each folder of ``places`` written ``<KEY>``, JSON's volatile keys out."""
    data = path.read_bytes()
    for key, folder in places.items():
        for d in sorted({str(folder), str(folder.resolve())}, key=len, reverse=True):
            data = data.replace(d.encode(), f"<{key}>".encode())
    if path.suffix == ".json":
        obj = _clean_json(json.loads(data))
        data = json.dumps(obj, indent=1, sort_keys=False).encode()
    return data


def store(out: Path, places: dict[str, Path]) -> dict[str, np.ndarray]:
    """Arrays for ``np.savez_compressed``: every file of the output folder ``out``."""
    arrays: dict[str, np.ndarray] = {}
    names = sorted(p.name for p in out.iterdir() if p.is_file())
    arrays["files"] = np.array(names)
    for name in names:
        p = out / name
        if p.suffix == ".png":
            arrays[f"{name}:png"] = np.frombuffer(p.read_bytes(), dtype=np.uint8)
            continue
        parts = text_parts(normalised(p, places))
        arrays[f"{name}:skeleton"] = np.frombuffer(parts.skeleton, dtype=np.uint8)
        arrays[f"{name}:numbers"] = parts.numbers
        with np.errstate(divide="ignore"):  # an integer's 0 is stored as -32768: 10**-32768 = 0
            log = np.where(parts.ulps > 0, np.round(np.log10(parts.ulps)), -32768)
        arrays[f"{name}:ulps"] = log.astype(np.int16)
    return arrays


def _pixels(data: bytes) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(data)).convert("RGB"), dtype=np.int16)


def _first_difference(a: bytes, b: bytes) -> str:
    al, bl = a.splitlines(), b.splitlines()
    for i, (x, y) in enumerate(zip(al, bl, strict=False)):
        if x != y:
            return f"line {i + 1}: expected {y[:120]!r}, got {x[:120]!r}"
    return f"{len(bl)} lines expected, {len(al)} written"


def differences(out: Path, places: dict[str, Path], expected: dict[str, np.ndarray]) -> list[str]:
    """Every way the output folder ``out`` departs from ``expected`` (empty: it holds)."""
    problems: list[str] = []
    names = sorted(p.name for p in out.iterdir() if p.is_file())
    want = [str(n) for n in expected["files"]]
    if names != want:
        problems.append(f"files: expected {want}, written {names}")
    for name in sorted(set(names) & set(want)):
        p = out / name
        if p.suffix == ".png":
            a, b = _pixels(p.read_bytes()), _pixels(expected[f"{name}:png"].tobytes())
            if a.shape != b.shape:
                problems.append(f"{name}: image {a.shape} expected {b.shape}")
                continue
            off = float((np.abs(a - b).max(axis=2) > PNG_LEVEL).mean())
            if off > PNG_PIXELS:
                problems.append(
                    f"{name}: {off:.2%} of the pixels differ (at most {PNG_PIXELS:.2%})"
                )
            continue
        got = text_parts(normalised(p, places))
        skel = expected[f"{name}:skeleton"].tobytes()
        if got.skeleton != skel:
            problems.append(f"{name}: text differs, {_first_difference(got.skeleton, skel)}")
            continue
        want_n = expected[f"{name}:numbers"]
        ulps = 10.0 ** expected[f"{name}:ulps"].astype(float)
        gap = np.abs(got.numbers - want_n)
        allowed = np.maximum(ABS + REL * np.abs(want_n), np.minimum(ulps, got.ulps) * 1.000001)
        bad = np.flatnonzero(gap > allowed)
        if bad.size:
            i = bad[np.argmax(gap[bad] / allowed[bad])]
            problems.append(
                f"{name}: {bad.size} of {gap.size} numbers out of tolerance, worst number {i}: "
                f"expected {want_n[i]!r}, got {got.numbers[i]!r}"
            )
    return problems
