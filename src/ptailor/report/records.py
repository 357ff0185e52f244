"""The shape of ``report.json``: typed records for its sections (docs/report.md says what
each field means).

The report stays a JSON-ready dict (it is written, hashed into batch records, printed with
``--json``); these ``TypedDict`` shapes say which keys each part has, so a reader
(``summary_lines``, batch records, the tests) and a type checker see the same fields the
builder (:func:`ptailor.report.build.build_report`) writes.
"""

from __future__ import annotations

from typing import Any, TypedDict


class ErrorStats(TypedDict):
    """Intrinsic-scale error of a panel's triangles (relative)."""

    mean: float
    p95: float
    max: float


class _PanelRequired(TypedDict):
    name: str
    triangles: int
    mirrored: bool
    outline_kept: bool
    area_before: float
    area_after: float
    size_before: list[float]
    size_after: list[float]
    boundary_deviation: float
    intrinsic_scale_error: ErrorStats
    flipped_triangles: int


class PanelRecord(_PanelRequired, total=False):
    """One panel: before/after area and size, outline deviation, error, flips; with the
    uniform baseline (``--no-baseline`` leaves it out) the baseline's numbers."""

    baseline_area_after: float
    baseline_size_after: list[float]
    baseline_intrinsic_scale_error: ErrorStats


class _SeamRequired(TypedDict):
    name: str
    panels: list[str]
    edges: int
    length_before: list[float]
    length_after: list[float]
    ratio_before: float
    ratio_after: float
    ratio_target: float
    mismatch: float


class SeamRecord(_SeamRequired, total=False):
    """One seam: its two sides' lengths in the input and after, their ratio and its target
    (the input's ratio, times a gather); a seam a step cut or grew also its sides as the
    step left them (``length_cut``)."""

    length_cut: list[float]


class ConvergedWhen(TypedDict):
    step: float
    seam_violation: float
    newton_step: float


class SolverRecord(TypedDict):
    """The stitching solver's run (:class:`ptailor.method.solver.StitchInfo`)."""

    iterations: int
    newton_steps: int
    converged: bool
    energy: float
    w_pin: float
    w_asap: float
    seams: str
    seam_violation: float
    residual: float
    factorizations: dict[str, int]
    converged_when: ConvergedWhen


class BaselineSolverRecord(TypedDict):
    """The uniform baseline's stitching run: the same solver, stopping rule and cap as ours."""

    iterations: int
    newton_steps: int
    converged: bool
    energy: float
    residual: float
    factorizations: int


class BaselineRecord(TypedDict):
    """The report's ``baseline`` (absent with ``--no-baseline``)."""

    solver: BaselineSolverRecord


class InputRecord(TypedDict):
    path: str
    sha256: str | None


class _ReportRequired(TypedDict):
    ptailor_version: str
    method: str
    intrinsic: str | None
    boundary: str
    units: dict[str, Any]
    inputs: dict[str, InputRecord]
    steps: list[dict[str, Any]]
    solver: SolverRecord
    panels: list[PanelRecord]
    seams: list[SeamRecord]
    timing_s: dict[str, float]
    warnings: list[str]
    outputs: list[str]


class Report(_ReportRequired, total=False):
    """``report.json``. The sections a run adds when it has them: ``baseline`` (the uniform
    baseline's solve, unless ``--no-baseline``), ``pattern`` (the pieces
    written), ``intake`` (what reading repaired), ``verify`` (``--verify``), ``body_fit``
    (``--body auto``), ``spec`` (``--spec``), ``measures`` (the points of measure before and
    after), ``expect`` (the recipe's ``expect:`` judged)."""

    baseline: BaselineRecord
    pattern: dict[str, Any]
    intake: dict[str, Any]
    verify: dict[str, Any]
    body_fit: dict[str, Any]
    spec: dict[str, Any]
    measures: dict[str, Any]
    expect: list[dict[str, Any]]
