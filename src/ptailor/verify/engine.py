"""The cloth engine: re-drape a garment from per-triangle rest shapes on NVIDIA Newton.

Newton (``newton``, Apache-2.0) and its kernel compiler ``warp-lang`` are an optional extra
(``pip install 'ptailor[sim]'``); they are imported only inside this module's functions, so
the rest of ptailor loads without them and :func:`engine_available` says whether they are here.

The solver is Newton's Style3D garment solver (projective dynamics, implicit, with cloth
self-collision and penalty contact against static collision meshes). Its rest shape is a 2D
panel triangle per face; ptailor gives every face its own panel triangle (three panel
vertices per face) built from the rest edge matrix, mirrored when it is clockwise (Style3D
silently drops clockwise panel triangles). The cloth's vertices are the drape's vertices,
so seams are the drape's welded edges. Newton is in SI units: positions are scaled by
``units_m`` on the way in and back on the way out.

The first run compiles warp's kernels (minutes of CPU; cached in warp's kernel cache,
``~/.cache/warp``, afterwards).
"""

from __future__ import annotations

import contextlib
import io
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ptailor.errors import PtailorError
from ptailor.verify import tolerances as verify_tol

#: what the missing-engine error says (the CLI prints it and exits 2)
INSTALL_HINT = "the cloth engine is not installed: pip install 'ptailor[sim]'"


class EngineMissingError(PtailorError):
    """Newton, warp or matplotlib (the picture) is not installed; the message says how to
    install them."""

    def __init__(self) -> None:
        super().__init__(INSTALL_HINT)


def _modules():
    """Import warp and newton quietly.

    Returns
    -------
    (module, module)
        ``warp`` and ``newton``.

    Raises
    ------
    EngineMissingError
        When either is not installed, or matplotlib (which draws ``verify.png``).
    """
    import importlib.util

    try:
        if importlib.util.find_spec("matplotlib") is None:  # the sim extra's picture
            raise ImportError("matplotlib")
        import warp as wp

        wp.config.log_level = max(wp.config.log_level, wp.LOG_WARNING)  # info goes to stdout
        import newton
        from newton.solvers import SolverStyle3D  # noqa: F401
    except ImportError as exc:
        raise EngineMissingError() from exc
    return wp, newton


def engine_available() -> bool:
    """Whether the cloth engine (newton and warp) can be imported.

    Returns
    -------
    bool
    """
    try:
        _modules()
    except EngineMissingError:
        return False
    return True


@dataclass(frozen=True)
class Settings:
    """Simulation settings, SI units.

    Parameters
    ----------
    dt : float
        Time step, s.
    max_steps : int
        Step cap; the re-drape stops here when it has not settled.
    check_every : int
        Steps between settle checks.
    settle_speed : float
        Settled when the 95th percentile of the free vertices' speeds is below this, m/s ...
    settle_checks : int
        ... on this many checks in a row ...
    settle_window : int
        ... and the 95th percentile of the free vertices' displacement over the last this
        many steps (rounded up to whole checks) ...
    settle_move : float
        ... is below this, m (:mod:`ptailor.verify.settle`; a window or move of 0 turns the
        displacement test off).
    density : float
        Cloth mass per rest area, kg/m^2 (cotton shirting 0.1-0.2).
    stretch : tuple of float
        Style3D in-plane stiffness (weft, warp, shear), N/m: the panel's x and y and shear.
    bend : tuple of float
        Style3D bending stiffness (weft, warp, bias).
    drag : float
        Velocity damping, 1/s: velocities are scaled by ``exp(-drag * dt)`` each step (air and
        internal friction; lets a drape come to rest within the step cap).
    friction : float
        Coulomb friction between cloth and body.
    friction_slip : float
        Body friction's smoothing, m of slip per step: below it friction grows linearly with
        the slip (Newton's IPC-style regularisation), so cloth creeping slower than this per
        step is held only that fraction of ``friction``. Newton's Style3D default is 1 cm
        (1 m/s at 1/100 s): cloth slides down a slope at any creep.
    contact_ke : float
        Body contact penalty stiffness (Newton's ``soft_contact_ke``).
    contact_kd : float
        Body contact damping (``soft_contact_kd``).
    radius : float
        Cloth particle radius, m: the cloth rests this far outside the body.
    contact_gap : float
        Extra body-contact detection distance, m: a contact found this far ahead holds the
        cloth as a plane until the next search.
    collide_every : int
        Steps between body contact searches. Tight cloth snaps onto the body at metres per
        second: searching every 10 steps (Newton's example) with a 5 mm gap lets a 0.7x rest
        tube started 15 % wide pass through its cylinder; every step with a 1 cm gap holds it,
        for about the same time per step on a simple body.
    self_collision : bool or None
        Cloth-cloth contact (Newton's vertex-face, edge-edge and untangling terms). It is most
        of the time per step (5k triangles: 36 ms with, 15 ms without). None (the default):
        on for a garment hanging free, off on a body, which keeps a garment's front and back
        apart (tee6 on its fitted body: the same speeds at every settle check with and
        without, in half the time).
    self_radius : float
        Cloth-cloth contact radius, m (the cloth is twice this thick to itself), at most;
        capped at 0.4 x the median rest edge, so a surface's own next-but-one neighbours are
        not contacts (Newton's 3 mm pushes a fine mesh apart in its own plane).
    iterations : int
        Style3D nonlinear iterations per step.
    linear_iterations : int
        PCG iterations per nonlinear iteration.
    sim_faces : int
        A garment with more triangles is simulated on a decimated copy of about this many
        (:func:`ptailor.verify.proxy.simulation_mesh`, every pattern boundary kept) and the
        result carried back: the check's time does not grow with the export's resolution.
    """

    dt: float = 1.0 / 100.0
    # 20 s simulated: loosened (2 cm) re-drapes settle late (tee6's at 1,100-1,120 steps,
    # the long-sleeve's ours at 1,660; bench/README.md, "2026-12-06, later")
    max_steps: int = 2000
    check_every: int = 20
    settle_speed: float = 2e-3
    settle_checks: int = 3
    settle_window: int = 100
    settle_move: float = 1e-3
    density: float = 0.15
    # in-plane stiffness: at (100, 100, 10) N/m the shared garments sagged 2 cm under their
    # own weight and failed the null test (tee6 mean 2.02 cm); at 1000 each they settle and
    # three of four hold it, tee6 at 1.03 cm (docs/verify.md, "What makes it hold")
    stretch: tuple[float, float, float] = (1000.0, 1000.0, 1000.0)
    bend: tuple[float, float, float] = (2e-5, 1e-5, 5e-6)
    drag: float = 5.0
    friction: float = 0.2
    friction_slip: float = 1e-2
    contact_ke: float = 1000.0  # 100 let the ten times stiffer cloth press into the body
    contact_kd: float = 1e-5
    radius: float = 1e-3
    contact_gap: float = 1e-2
    collide_every: int = 1
    self_collision: bool | None = None
    self_radius: float = 3e-3
    iterations: int = 4
    linear_iterations: int = 10
    sim_faces: int = 8000


@dataclass(frozen=True)
class Drape:
    """A settled (or capped) re-drape.

    Parameters
    ----------
    V : (n, 3) float array
        Final vertex positions, in the input's units.
    steps : int
        Steps taken.
    seconds : float
        Wall time of the simulation (model build and stepping), s.
    settled : bool
        Whether it came to rest before ``max_steps``.
    device : str
        Warp device it ran on (``"cpu"``, ``"cuda:0"``).
    engine : str
        Engine name and version.
    speed : (n,) float array or None
        Each vertex's speed when it stopped (the last settle check), input units per second
        (0 for pinned and unused vertices).
    settle : dict or None
        Why it settled or not (:meth:`ptailor.verify.settle.Settle.record`, input units).
    cpu_seconds : float or None
        CPU time of the simulation (this process, every thread), s.
    """

    V: np.ndarray
    steps: int
    seconds: float
    settled: bool
    device: str
    engine: str
    speed: np.ndarray | None = None
    settle: dict | None = None
    cpu_seconds: float | None = None


def panel_triangles(rest: np.ndarray) -> np.ndarray:
    """One counter-clockwise panel triangle per face from rest edge matrices.

    Parameters
    ----------
    rest : (m, 2, 2) float array
        Columns: rest edges ``p1 - p0`` and ``p2 - p0``.

    Returns
    -------
    (m, 3, 2) float array
        Corners ``0, e1, e2``, with x negated where ``det(rest) < 0`` (a mirror changes
        no length or angle, so the cloth's rest metric is the same).
    """
    rest = np.asarray(rest, dtype=float)
    P = np.zeros((len(rest), 3, 2))
    P[:, 1] = rest[:, :, 0]
    P[:, 2] = rest[:, :, 1]
    P[np.linalg.det(rest) < 0, :, 0] *= -1.0
    return P


def _check_inputs(V: np.ndarray, F: np.ndarray, rest: np.ndarray, units_m: float, pinned) -> None:
    """Raise ValueError naming the first argument of the wrong shape or value."""
    if V.ndim != 2 or V.shape[1] != 3 or not np.isfinite(V).all():
        raise ValueError(f"V3 must be a finite (n, 3) array, got shape {V.shape}")
    if len(F) and (F.min() < 0 or F.max() >= len(V)):
        raise ValueError("F3 indexes vertices outside V3")
    if rest.shape != (len(F), 2, 2) or not np.isfinite(rest).all():
        raise ValueError(f"rest must be a finite ({len(F)}, 2, 2) array, got shape {rest.shape}")
    if not (units_m > 0 and np.isfinite(units_m)):
        raise ValueError(f"units_m must be positive, got {units_m}")
    if len(pinned) and (pinned.min() < 0 or pinned.max() >= len(V)):
        raise ValueError("pinned indexes vertices outside V3")


def _pick_device(wp, device: str | None) -> str:
    """``device`` when given, else warp's first GPU when there is one, else the CPU."""
    if device is not None:
        return device
    return "cuda:0" if wp.get_cuda_device_count() > 0 else "cpu"


def _model(wp, newton, V, F, P, body, s: Settings, device: str):
    """Build and finalize the Newton model (SI inputs)."""
    from newton.solvers import SolverStyle3D, style3d

    builder = newton.ModelBuilder(up_axis=newton.Axis.Y, gravity=(0.0, -9.81, 0.0))
    SolverStyle3D.register_custom_attributes(builder)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # degenerate rest triangles are dropped, not fatal
        style3d.add_cloth_mesh(
            builder,
            pos=wp.vec3(0.0, 0.0, 0.0),
            rot=wp.quat_identity(),
            vel=wp.vec3(0.0, 0.0, 0.0),
            vertices=V.tolist(),
            indices=F.reshape(-1).tolist(),
            density=s.density,
            panel_verts=P.reshape(-1, 2).tolist(),
            panel_indices=list(range(3 * len(F))),
            tri_aniso_ke=wp.vec3(*s.stretch),
            edge_aniso_ke=wp.vec3(*s.bend),
            particle_radius=s.radius,
        )
    if body is not None:
        Vb = np.asarray(body[0], dtype=np.float32)
        Fb = np.asarray(body[1], dtype=np.int32).reshape(-1)
        cfg = newton.ModelBuilder.ShapeConfig(mu=s.friction)
        builder.add_shape_mesh(
            body=-1,
            mesh=newton.Mesh(Vb, Fb),
            cfg=cfg,
        )
    model = builder.finalize(device=device)
    model.soft_contact_ke = s.contact_ke
    model.soft_contact_kd = s.contact_kd
    model.soft_contact_mu = s.friction
    return model


def _pin(wp, newton, model, pinned: np.ndarray) -> None:
    """Hold the ``pinned`` particles where they are (inactive: the solver leaves them)."""
    if len(pinned) == 0:
        return
    flags = model.particle_flags.numpy()
    flags[pinned] &= ~np.int32(int(newton.ParticleFlags.ACTIVE)).astype(flags.dtype)
    model.particle_flags = wp.array(flags, dtype=model.particle_flags.dtype, device=model.device)


def self_radius(P: np.ndarray, s: Settings) -> float:
    """The cloth-cloth contact radius for panel triangles ``P`` (m, 3, 2), m: see Settings."""
    if len(P) == 0:
        return s.self_radius
    edges = np.linalg.norm(P - np.roll(P, 1, axis=1), axis=2)
    return float(min(s.self_radius, verify_tol.ENGINE_SELF_RADIUS_EDGES * np.median(edges)))


def self_collision(s: Settings, has_body: bool) -> bool:
    """Whether cloth-cloth contact is on: the setting, or when it is None (auto) whether the
    garment hangs free (no body)."""
    return (not has_body) if s.self_collision is None else bool(s.self_collision)


def _solver(newton, model, s: Settings, radius: float, has_body: bool):
    """Newton's Style3D solver with the settings' iterations and cloth-cloth contact."""
    from newton.solvers import SolverStyle3D

    solver = SolverStyle3D(
        model,
        config=SolverStyle3D.Config(iterations=s.iterations, linear_iterations=s.linear_iterations),
    )
    if not self_collision(s, has_body):
        # body contacts stay: Collision evaluates them with the cloth-cloth terms off
        solver.collision.stiff_vf = solver.collision.stiff_ee = solver.collision.stiff_ef = 0.0
    solver.collision.radius = radius  # the BVHs are refit with it every step
    solver.collision.friction_epsilon = s.friction_slip
    return solver


def _simulate(
    wp, newton, model, s: Settings, free: np.ndarray, has_body: bool, radius: float, progress=None
):
    """Step until settled or ``max_steps``; returns (positions (n, 3), steps, settled, the
    :class:`ptailor.verify.settle.Settle` with the last check's speeds and why)."""
    from ptailor.verify.settle import Settle

    solver = _solver(newton, model, s, radius, has_body)
    a, b = model.state(), model.state()
    control = model.control()
    pipeline = newton.CollisionPipeline(model, soft_contact_gap=s.contact_gap) if has_body else None
    contacts = pipeline.contacts() if has_body else None
    if contacts is None:
        contacts = newton.CollisionPipeline(model).contacts()
    keep = float(np.exp(-s.drag * s.dt))
    settle = Settle(s, free)
    steps, settled = 0, False
    while steps < s.max_steps and not settled:
        if pipeline is not None and steps % s.collide_every == 0:
            pipeline.collide(a, contacts)
        a.clear_forces()
        solver.step(a, b, control, contacts, s.dt)
        a, b = b, a
        if keep < 1.0:
            a.particle_qd.assign(a.particle_qd.numpy() * keep)
        steps += 1
        if steps % s.check_every == 0:
            settled = settle.check(a.particle_q.numpy(), a.particle_qd.numpy())
            if progress is not None:
                progress(steps, settle.speed_p95)
    if steps % s.check_every:  # the speeds where it stopped
        settle.check(a.particle_q.numpy(), a.particle_qd.numpy())
    return a.particle_q.numpy().astype(float), steps, settled, settle


def _sew_and_settle(wp, newton, V, F, P, body, s: Settings, dev, pinned, progress):
    """Build the cloth model (SI units), pin ``pinned`` and step it until it settles;
    returns :func:`_simulate`'s (positions, steps, settled, settle)."""
    model = _model(wp, newton, V, F, P, body, s, dev)
    _pin(wp, newton, model, pinned)
    free = np.zeros(len(V), dtype=bool)
    free[np.unique(F)] = True
    free[pinned] = False
    radius = self_radius(P, s)
    return _simulate(wp, newton, model, s, free, body is not None, radius, progress)


def redrape(
    V3: np.ndarray,
    F3: np.ndarray,
    rest: np.ndarray,
    *,
    units_m: float,
    pinned: np.ndarray,
    body: tuple[np.ndarray, np.ndarray] | None = None,
    settings: Settings = Settings(),
    device: str | None = None,
    progress: Callable[[int, float], None] | None = None,
) -> Drape:
    """Sew and drape cloth of the given rest shapes, starting from ``V3``, until it settles.

    Parameters
    ----------
    V3 : (n, 3) float array
        Start positions (the edited drape), y up, in the garment's units.
    F3 : (m, 3) int array
        Faces.
    rest : (m, 2, 2) float array
        Each face's rest edge matrix (columns ``p1 - p0``, ``p2 - p0``), garment units; may be
        mirrored (``det < 0``).
    units_m : float
        Metres per garment unit (0.01 for cm).
    pinned : (k,) int array
        Vertices held in place.
    body : ((nb, 3) float array, (mb, 3) int array), optional
        A static collision mesh in the garment's frame and units.
    settings : Settings
    device : str, optional
        Warp device; default the first GPU when warp finds one, else ``"cpu"``.
    progress : callable, optional
        ``progress(steps, speed_p95)`` at every settle check (the free vertices' 95th
        percentile speed, m/s): a progress line's feed.

    Returns
    -------
    Drape
        ``V`` (n, 3) in the garment's units; the pinned vertices exactly where they were.

    Raises
    ------
    EngineMissingError
        When newton or warp is not installed.
    ValueError
        When an array has the wrong shape, a non-finite value, or an index out of range.
    """
    V3 = np.asarray(V3, dtype=float)
    F = np.asarray(F3, dtype=np.int64).reshape(-1, 3)
    rest = np.asarray(rest, dtype=float)
    pinned = np.unique(np.asarray(pinned, dtype=np.int64).reshape(-1))
    _check_inputs(V3, F, rest, units_m, pinned)
    wp, newton = _modules()
    t0, c0 = time.perf_counter(), time.process_time()
    with contextlib.redirect_stderr(io.StringIO()):
        wp.init()  # on a machine without a GPU driver warp says so on stderr, every time
    dev = _pick_device(wp, device)
    V = V3 * units_m
    P = panel_triangles(rest * units_m)
    if body is not None:
        body = (np.asarray(body[0], dtype=float) * units_m, np.asarray(body[1]))
    # newton times its precompute with a ScopedTimer that prints to stdout
    with wp.ScopedDevice(dev), contextlib.redirect_stdout(io.StringIO()):
        X, steps, settled, settle = _sew_and_settle(
            wp, newton, V, F, P, body, settings, dev, pinned, progress
        )
    X = X / units_m
    X[pinned] = V3[pinned]  # held exactly, not through float32
    return Drape(
        V=X,
        steps=steps,
        seconds=time.perf_counter() - t0,
        settled=settled,
        device=str(dev),
        engine=f"newton {newton.__version__} (SolverStyle3D)",
        speed=np.asarray(settle.speed, dtype=float) / units_m,
        settle=settle.record(settled=settled, steps=steps, units_m=units_m),
        cpu_seconds=time.process_time() - c0,
    )
