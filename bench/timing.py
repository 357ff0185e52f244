"""Shared by the benchmark scripts (run as ``python bench/NAME.py``: this folder is on the path).

Timing helpers, the machine description written into each results file, the ``ptailor``
command as a subprocess, and libigl's ARAP parametrisation (the speed reference of issues
1 and 15).
"""

from __future__ import annotations

import contextlib
import os
import platform
import shutil
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
LIBIGL_ITERATIONS = 30


def median(xs: list[float]) -> float:
    return float(statistics.median(xs))


def median_time(fn: Callable[[], object], repeat: int) -> float:
    """Median wall time of ``repeat`` calls of ``fn``, in seconds."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


# ---------------------------------------------------------------------------------------
# the command line as a subprocess
# ---------------------------------------------------------------------------------------


def ptailor_command() -> list[str]:
    """The installed ``ptailor`` script next to this interpreter, else ``python -m ptailor``."""
    exe = Path(sys.executable).parent / "ptailor"
    if exe.exists():
        return [str(exe)]
    found = shutil.which("ptailor")
    return [found] if found else [sys.executable, "-m", "ptailor"]


def run_cli(args: list[str]) -> float:
    """Wall seconds of ``ptailor ARGS`` (stdout discarded; raises on a non-zero exit)."""
    t0 = time.perf_counter()
    subprocess.run(ptailor_command() + args, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - t0


def run_measured(cmd: list[str], **kwargs) -> tuple[float, float, float]:
    """Run ``cmd``; ``(wall s, CPU s, peak RSS MB)`` of that child alone (``os.wait4``).

    Raises
    ------
    subprocess.CalledProcessError
        The command exited non-zero.
    """
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, **kwargs)
    _, status, ru = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise subprocess.CalledProcessError(proc.returncode, cmd)
    return wall, ru.ru_utime + ru.ru_stime, ru.ru_maxrss / 1024.0


def one_blas_thread_env() -> dict:
    """This environment with one BLAS thread unless the user set one (as ptailor does)."""
    env = dict(os.environ)
    for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        env.setdefault(var, "1")
    return env


#: compiled bytecode for the benchmarks' subprocesses (``PYTHONPYCACHEPREFIX``)
PYCACHE = HERE / "results" / "pycache"


def cached_bytecode_env(env: dict | None = None) -> dict:
    """``env`` (default: this one) with bytecode written to and read from :data:`PYCACHE`.

    An installed package has its ``.pyc`` files; a checkout run with
    ``PYTHONDONTWRITEBYTECODE=1`` compiles every module of ``src/`` again in each process
    (about 0.5 s of ptailor's imports). Run one warm-up command first.
    """
    env = dict(os.environ if env is None else env)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    env["PYTHONPYCACHEPREFIX"] = str(PYCACHE)
    return env


# ---------------------------------------------------------------------------------------
# where a result was measured
# ---------------------------------------------------------------------------------------


def dist_version(name: str) -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version(name)
    except PackageNotFoundError:
        return "not installed"


def machine() -> dict:
    """CPU, cores, load, library versions and the git commit, for a results file."""
    import ptailor

    cpu = platform.processor() or platform.machine()
    with contextlib.suppress(OSError):
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    commit = "unknown"
    with contextlib.suppress(OSError, subprocess.CalledProcessError):
        commit = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"],
            cwd=HERE,
            check=True,
            capture_output=True,
            text=True,
        ).stdout.strip()
    load = None
    with contextlib.suppress(OSError):
        load = [round(x, 2) for x in os.getloadavg()]
    return {
        "cpu": cpu,
        "cores": os.cpu_count(),
        "load_average": load,
        "platform": platform.platform(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": dist_version("scipy"),
        "libigl": dist_version("libigl"),
        "ptailor": ptailor.__version__,
        "git_commit": commit,
    }


# ---------------------------------------------------------------------------------------
# libigl's ARAP parametrisation
# ---------------------------------------------------------------------------------------


def libigl_arap(
    V3: np.ndarray, F3: np.ndarray, V2: np.ndarray, F2: np.ndarray, pins: np.ndarray, repeat: int
) -> dict:
    """libigl's ARAP parametrisation (dim 2, ``max_iter`` 30) of a drape, timed.

    libigl needs one mesh, so the drape is re-indexed like the pattern: ``V = V3[to3]`` with
    ``to3[F2] = F3``, ``F = F2``, initial guess ``V2``.

    Parameters
    ----------
    V3 : (n3, 3) float array
        The drape to flatten.
    F3, F2 : (m, 3) int arrays
        Drape and pattern triangles, corner to corner.
    V2 : (n2, 2) float array
        The initial guess (the original pattern).
    pins : (k,) int array
        Pattern vertices held at ``V2`` (one per panel: libigl's Cholesky fails on a free one).
    repeat : int

    Returns
    -------
    dict
        ``median_s`` (precomputation + 30 solves), ``precomputation_median_s``,
        ``solve_30_median_s``, ``min_s``, ``cpu_median_s`` (CPU time of every thread),
        ``pins``, ``version``, ``energy`` and ``U``, the last solution ((n2, 2) array); or
        ``{"error": ...}``.
    """
    try:
        import igl
    except ImportError as exc:
        return {"error": f"libigl not importable: {exc}"}
    to3 = np.full(len(V2), -1, dtype=np.int64)
    to3[F2.ravel()] = F3.ravel()
    if np.any(to3 < 0):
        return {"error": "pattern has vertices no triangle uses; libigl needs every vertex"}
    V = np.ascontiguousarray(V3[to3])
    F = np.ascontiguousarray(F2, dtype=np.int64)
    b = np.ascontiguousarray(pins, dtype=np.int32)
    bc = np.ascontiguousarray(V2[b])
    pre, sol, cpu = [], [], []
    U = data = None
    for _ in range(repeat):
        data = igl.ARAPData()
        data.max_iter = LIBIGL_ITERATIONS
        c0 = time.process_time()
        t0 = time.perf_counter()
        try:
            igl.arap_precomputation(V, F, 2, b, data)
        except RuntimeError as exc:
            return {"error": f"arap_precomputation: {exc}"}
        t1 = time.perf_counter()
        U = igl.arap_solve(bc, data, np.ascontiguousarray(V2))
        t2 = time.perf_counter()
        cpu.append(time.process_time() - c0)
        pre.append(t1 - t0)
        sol.append(t2 - t1)
    tot = [p + s for p, s in zip(pre, sol, strict=True)]
    return {
        "version": getattr(igl, "__version__", dist_version("libigl")),
        "pins": len(b),
        "energy": str(data.energy),
        "precomputation_median_s": median(pre),
        "solve_30_median_s": median(sol),
        "median_s": median(tot),
        "min_s": min(tot),
        "cpu_median_s": median(cpu),
        "U": U,
    }
