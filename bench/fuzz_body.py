"""Fuzzing campaign for ``--body`` meshes (issue 43): N seeded mutants, outside pytest.

Each case takes a closed, outward sphere (an icosphere of 320 triangles, radius 20 cm) and
applies one to three mutations: geometric ones (faces reversed, all or a few; the mesh
flattened along an axis; vertices collapsed to one point; faces dropped or duplicated; the
mesh scaled to 1e-9 or 1e6; two spheres overlapping; a single triangle; coincident corners)
and the OBJ reader's text mutations (``bench/fuzz_obj.py``'s :func:`mutate`), then reads it
with :func:`ptailor.edits.body.read_body` and pushes a few points out of it, in a forked
child with a time limit.

The contract: a :class:`~ptailor.errors.PtailorError` of one line naming the file, or a body:
finite vertices, every edge walked once each way (consistently oriented and closed), a
positive volume (outward faces) of at least ``BODY_MIN_ROUNDNESS`` of a sphere of its
area, and push-out that leaves every point outside or on it. Counted: tracebacks (by
signature), hangs, bad messages, wrong (an accepted mesh that is no body).

    python bench/fuzz_body.py --cases 1000 --seed 1 [--timeout 20] [--json out.json]

The mutator (:func:`mutate_body`) is shared with ``tests/test_fuzz_body.py``.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import random
import sys
import tempfile
import time
from collections import Counter
from functools import partial
from pathlib import Path

import numpy as np

_spec = importlib.util.spec_from_file_location(
    "fuzz_obj", Path(__file__).resolve().parent / "fuzz_obj.py"
)
fuzz_obj = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(fuzz_obj)


def base_body() -> tuple[np.ndarray, np.ndarray]:
    """The unmutated body: an icosphere of radius 20 (cm), 320 outward triangles."""
    import trimesh

    s = trimesh.creation.icosphere(subdivisions=2, radius=20.0)
    return np.asarray(s.vertices, dtype=float), np.asarray(s.faces, dtype=np.int64)


def obj_bytes(V: np.ndarray, F: np.ndarray) -> bytes:
    """``V``, ``F`` as OBJ text (``%.9g`` coordinates)."""
    lines = [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in V]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in F]
    return ("\n".join(lines) + "\n").encode()


def _geometric(V: np.ndarray, F: np.ndarray, rng: random.Random) -> tuple[np.ndarray, np.ndarray]:
    kind = rng.randrange(10)
    V, F = V.copy(), F.copy()
    if kind == 0:
        F = F[:, ::-1]
    elif kind == 1:
        k = rng.randrange(1, 8) if len(F) > 8 else len(F)
        idx = rng.sample(range(len(F)), k)
        F[idx] = F[idx][:, ::-1]
    elif kind == 2:
        V[:, rng.randrange(3)] *= rng.choice([0.0, 1e-12, 1e-3])
    elif kind == 3:
        V[:] = V[rng.randrange(len(V))]
    elif kind == 4:
        keep = [i for i in range(len(F)) if rng.random() > 0.02]
        F = F[keep]
    elif kind == 5:
        F = np.r_[F, F[: rng.randrange(1, 20)]]
    elif kind == 6:
        V = V * rng.choice([1e-9, 1e6, -1.0])
    elif kind == 7:
        F = np.r_[F, F + len(V)]
        V = np.r_[V, V + rng.uniform(0, 30)]
    elif kind == 8:
        F = F[:1]
    else:
        i = rng.randrange(len(F))
        F[i, 1] = F[i, 0]
    return V, F


def mutate_body(rng: random.Random) -> bytes:
    """One mutant body file (OBJ bytes): geometric mutations, then maybe text ones."""
    V, F = base_body()
    for _ in range(rng.randrange(1, 3)):
        V, F = _geometric(V, F, rng)
    data = obj_bytes(V, F)
    if rng.random() < 0.3:
        data = fuzz_obj.mutate(data, rng)
    return data


def body_problem(m) -> str:
    """Why an accepted ``trimesh.Trimesh`` is not a body, or ``""``."""
    from ptailor.edits import tolerances as edit_tol

    V, F = np.asarray(m.vertices), np.asarray(m.faces)
    if not np.isfinite(V).all():
        return "nonfinite vertices"
    D = np.stack([F, np.roll(F, -1, axis=1)], axis=2).reshape(-1, 2)
    fwd = sorted(map(tuple, D.tolist()))
    back = sorted(map(tuple, D[:, ::-1].tolist()))
    if fwd != back:
        return "not closed and consistently oriented"
    T = V[F]
    vol = float(np.einsum("ij,ij->i", T[:, 0], np.cross(T[:, 1], T[:, 2])).sum()) / 6.0
    area = float(np.linalg.norm(np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0]), axis=1).sum()) / 2
    if vol < edit_tol.BODY_MIN_ROUNDNESS * area**1.5 / (6.0 * np.sqrt(np.pi)):
        return "no volume or inside out"
    return ""


def check_case(data: bytes, work: Path) -> list[tuple[str, str]]:
    """Read one mutant and push points out of it; the contract's breaches (kind, detail)."""
    from ptailor.edits.body import push_out, read_body, winding_numbers
    from ptailor.errors import PtailorError

    path = work / "body.obj"
    path.write_bytes(data)
    try:
        m = read_body(str(path), units="cm", to="cm")
    except PtailorError as exc:
        msg = str(exc)
        if str(path) not in msg or "\n" in msg:
            return [("message", msg[:120])]
        return [("exit", "refused")]
    except Exception as exc:
        return [("traceback", fuzz_obj.signature(exc))]
    why = body_problem(m)
    if why:
        return [("wrong", why)]
    P = np.asarray(m.vertices).mean(axis=0) + np.zeros((4, 3))
    Q = push_out(P, m, clearance=0.5)
    if np.any(winding_numbers(Q, np.asarray(m.vertices), np.asarray(m.faces)) > 0.5):
        return [("wrong", "a pushed-out point is still inside")]
    return [("exit", "accepted")]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=20.0, help="per case, seconds")
    ap.add_argument("--json", type=Path, default=None, help="write the counts here")
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as td:  # every lazy import once, before the forks
        check_case(obj_bytes(*base_body()), Path(td))
    outcomes: Counter = Counter()
    breaches: Counter = Counter()
    t_start = time.perf_counter()
    for case in range(args.cases):
        data = mutate_body(random.Random(args.seed * 1_000_003 + case))
        res, _ = fuzz_obj.run_forked(partial(check_case, data), args.timeout)
        for kind, detail in res:
            if kind == "exit":
                outcomes[detail] += 1
            else:
                breaches[f"{kind}: {detail}"] += 1
    kinds = Counter(k.split(":")[0] for k in breaches.elements())
    summary = {
        "cases": args.cases,
        "seed": args.seed,
        "seconds": round(time.perf_counter() - t_start, 1),
        "outcomes": dict(sorted(outcomes.items())),
        "tracebacks": kinds.get("traceback", 0),
        "hangs": kinds.get("hang", 0),
        "bad_messages": kinds.get("message", 0),
        "wrong": kinds.get("wrong", 0),
        "breaches": dict(breaches.most_common()),
    }
    print(json.dumps(summary, indent=2))
    if args.json:
        args.json.write_text(json.dumps(summary, indent=2))
    return 1 if breaches else 0


if __name__ == "__main__":
    sys.exit(main())
