"""Quality gates: limits a garment's report must keep, else the garment fails (no folder);
and the recipe's ``expect:`` (the gate ``expect``), judged on the report.

A gate reads the report strictly: a key it needs that is missing, renamed or not a number
is a broken gate (``"... missing from the report"``), never a silent pass.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Gates:
    """Quality gates: a garment whose report breaks one fails and gets no folder.

    Attributes
    ----------
    max_area_change : float, optional
        Fraction: a panel with ``|area_after / area_before - 1|`` above it fails.
    max_boundary_deviation : float, optional
        In the report's units: a panel whose ``boundary_deviation`` is above it fails.
    max_intrinsic_error : float, optional
        A panel whose ``intrinsic_scale_error.p95`` is above it fails (the 95th percentile
        over the panel's triangles, so a few triangles at a seam do not decide).
    max_seam_mismatch : float, optional
        In the report's units: a seam whose ``|mismatch|`` (its two sides' length difference
        at the target ratio) is above it fails.
    max_verify_stretch : float, optional
        A panel whose re-drape stretch p95 (``verify.ours.panels.NAME.stretch.p95``: the
        adjusted pattern sewn and settled by the cloth engine) is above it fails.
    max_verify_displacement : float, optional
        In the report's units: a panel whose re-drape displacement p95 (from the edited
        drape, ``verify.ours.panels.NAME.displacement.p95``) is above it fails.
    max_spec_fit : float, optional
        In the report's units: a specification panel (``--spec``) whose written curves lie
        farther than this from the adjusted mesh outline (``spec.panels[].fit``) fails.
    fail_on_flips : bool
        A panel with ``flipped_triangles > 0`` fails.
    expect : bool
        A garment whose result misses a measure its recipe's ``expect:`` asks for (the
        report's ``expect``, :mod:`ptailor.report.expect`) fails: on by default, a gate only
        where the recipe has ``expect:``.
    """

    max_area_change: float | None = None
    max_boundary_deviation: float | None = None
    max_intrinsic_error: float | None = None
    max_seam_mismatch: float | None = None
    max_verify_stretch: float | None = None
    max_verify_displacement: float | None = None
    max_spec_fit: float | None = None
    fail_on_flips: bool = False
    expect: bool = True

    @property
    def panel_gates(self) -> bool:
        """True when a gate reads the report's panels."""
        return (
            self.max_area_change is not None
            or self.max_boundary_deviation is not None
            or self.max_intrinsic_error is not None
            or self.fail_on_flips
        )

    @property
    def verify_gates(self) -> bool:
        """True when a gate reads the report's re-drape check (``verify``)."""
        return self.max_verify_stretch is not None or self.max_verify_displacement is not None


class GateFailedError(Exception):
    """A report broke a quality gate (raised inside :func:`ptailor.run.garment.staged_run`)."""

    def __init__(self, problems: list[str], report: dict) -> None:
        self.problems = problems
        self.report = report
        super().__init__("; ".join(problems))


class MissingFieldError(Exception):
    """A gate's field is not in the report (missing, renamed, or not a number)."""


# --------------------------------------------------------------------------- lenient reads


def number(x: Any) -> float | None:
    """``x`` as a float when it is a number (not a bool), else None."""
    return float(x) if isinstance(x, int | float) and not isinstance(x, bool) else None


def area_change(panel: dict) -> float | None:
    """``|area_after / area_before - 1|`` of a report panel, or None."""
    a0, a1 = number(panel.get("area_before")), number(panel.get("area_after"))
    if a0 is None or a1 is None or a0 <= 0:
        return None
    return abs(a1 / a0 - 1.0)


def p95(panel: dict) -> float | None:
    """A report panel's ``intrinsic_scale_error.p95``, or None."""
    err = panel.get("intrinsic_scale_error")
    return number(err.get("p95")) if isinstance(err, dict) else None


def seam_mismatch(seam: dict) -> float | None:
    """``|mismatch|`` of a report seam, or None when the report lacks it."""
    mis = number(seam.get("mismatch"))
    return None if mis is None else abs(mis)


def verify_panels(report: dict, which: str = "ours") -> dict | None:
    """The re-drape check's panels for the adjusted pattern (``verify.ours.panels``; or
    ``which`` re-drape's: ``baseline``, ``original``), or None when the report has none."""
    sec = report.get("verify")
    ours = sec.get(which) if isinstance(sec, dict) else None
    panels = ours.get("panels") if isinstance(ours, dict) else None
    return panels if isinstance(panels, dict) else None


def verify_number(panel: Any, measure: str) -> float | None:
    """A re-drape panel's ``MEASURE.p95`` (``stretch`` or ``displacement``), or None."""
    rec = panel.get(measure) if isinstance(panel, dict) else None
    return number(rec.get("p95")) if isinstance(rec, dict) else None


# --------------------------------------------------------------------------- strict reads


def _items(report: dict, key: str) -> list[dict]:
    """The report's ``panels`` or ``seams``; a missing or malformed list breaks the gate."""
    items = report.get(key)
    if not isinstance(items, list) or not all(isinstance(x, dict) for x in items):
        raise MissingFieldError(key)
    return items


def _units(report: dict) -> str:
    rec = report.get("units")
    return rec.get("computation", "") if isinstance(rec, dict) else rec or ""


def _flips(panel: dict) -> float | None:
    return number(panel.get("flipped_triangles"))


def _boundary(panel: dict) -> float | None:
    return number(panel.get("boundary_deviation"))


def _area_message(value: float, lim: float, units: str) -> str:
    return f"area change {100 * value:.3g} % > {100 * lim:.3g} %"


def _boundary_message(value: float, lim: float, units: str) -> str:
    return f"boundary deviation {value:.4g} > {lim:.4g} {units}".rstrip()


def _p95_message(value: float, lim: float, units: str) -> str:
    return f"intrinsic-scale error p95 {value:.4g} > {lim:.4g}"


def _flips_message(value: float, lim: float, units: str) -> str:
    flips = int(value)
    return f"{flips} flipped triangle{'s' if flips != 1 else ''}"


#: panel gates: (Gates attribute, the report field, reader, message)
_PANEL_GATES = (
    ("max_area_change", "area_before/area_after", area_change, _area_message),
    ("max_boundary_deviation", "boundary_deviation", _boundary, _boundary_message),
    ("max_intrinsic_error", "intrinsic_scale_error.p95", p95, _p95_message),
    ("fail_on_flips", "flipped_triangles", _flips, _flips_message),
)


def _limit(gates: Gates, attr: str) -> float | None:
    lim = getattr(gates, attr)
    if isinstance(lim, bool):  # fail_on_flips: more than 0 flips
        return 0 if lim else None
    return lim


def _panel_failures(panels: list[dict], gates: Gates, units: str) -> list[str]:
    """The gates the report's panels break, one line per panel and gate, in panel order.

    A panel without a field is not judged by that field's gate; a field that no panel has
    (renamed, or never written) breaks the gate.
    """
    set_gates = [(g, _limit(gates, g[0])) for g in _PANEL_GATES]
    set_gates = [(g, lim) for g, lim in set_gates if lim is not None]
    probs = []
    for p in panels:  # a loop over panels
        for (_, _, read, message), lim in set_gates:
            value = read(p)
            if value is not None and value > lim:
                probs.append(f"{p.get('name', '?')}: {message(value, lim, units)}")
    for (_, field, read, _), _ in set_gates:
        if panels and all(read(p) is None for p in panels):
            probs.append(f"report: no panel has {field} (a gate cannot pass without it)")
    return probs


def _seam_failures(seams: list[dict], lim: float, units: str) -> list[str]:
    probs = []
    for s in seams:  # a loop over seams
        mis = seam_mismatch(s)
        if mis is None or mis > lim:
            shown = "missing" if mis is None else f"{mis:.4g} > {lim:.4g} {units}".rstrip()
            probs.append(f"seam {' / '.join(s.get('panels', ['?']))}: mismatch {shown}")
    return probs


#: re-drape gates: (Gates attribute, the panel's measure, what a failure says)
_VERIFY_GATES = (
    ("max_verify_stretch", "stretch", "re-drape stretch p95"),
    ("max_verify_displacement", "displacement", "re-drape displacement p95"),
)


def _verify_failures(report: dict, gates: Gates, units: str) -> list[str]:
    """The re-drape gates the report breaks: a panel above a limit, or one without the
    number (strict: a report without the check breaks every re-drape gate)."""
    panels = verify_panels(report)
    set_gates = [g for g in _VERIFY_GATES if getattr(gates, g[0]) is not None]
    if panels is None or not panels:
        return [
            f"report: no verify.ours.panels (the re-drape check, --verify): "
            f"--{attr.replace('_', '-')} cannot pass without it"
            for attr, _, _ in set_gates
        ]
    probs = []
    for name, panel in panels.items():  # a loop over panels
        for attr, measure, what in set_gates:
            lim = getattr(gates, attr)
            value = verify_number(panel, measure)
            unit = f" {units}" if measure == "displacement" and units else ""
            if value is None:
                probs.append(f"{name}: {what} missing from the report")
            elif value > lim:
                probs.append(f"{name}: {what} {value:.4g} > {lim:.4g}{unit}")
    return probs


def gate_failures(report: dict, gates: Gates) -> list[str]:
    """Every gate the report breaks, one line per panel and gate.

    The report is read strictly: a seam without its ``mismatch``, a field that no panel has,
    or a missing ``panels`` / ``seams`` list breaks the gates that read it.
    """
    probs = []
    units = _units(report)
    try:
        if gates.panel_gates:
            probs += _panel_failures(_items(report, "panels"), gates, units)
        if gates.max_seam_mismatch is not None:
            probs += _seam_failures(_items(report, "seams"), gates.max_seam_mismatch, units)
    except MissingFieldError as exc:
        probs.append(f"report: no {exc} list (a gate cannot pass without it)")
    if gates.verify_gates:
        probs += _verify_failures(report, gates, units)
    if gates.max_spec_fit is not None:
        probs += _spec_failures(report, gates.max_spec_fit, units)
    if gates.expect:
        probs += _expect_failures(report)
    return probs


def _expect_failures(report: dict) -> list[str]:
    """The measures the result missed (``expect: hem: asked ...``), none where the report
    has no ``expect`` (its recipe asks for none); a malformed one breaks the gate."""
    from ptailor.report.expect import missed_lines

    recs = report.get("expect")
    if recs is None:
        return []
    if not isinstance(recs, list) or not all(isinstance(r, dict) and "ok" in r for r in recs):
        return ["report: expect is not a list of judged measures (the gate cannot pass)"]
    return [f"expect: {line}" for line in missed_lines(report)]


#: each gate's option, by its :class:`Gates` attribute
GATE_OPTIONS = {
    "max_area_change": "--max-area-change",
    "max_boundary_deviation": "--max-boundary-deviation",
    "max_intrinsic_error": "--max-intrinsic-error",
    "max_seam_mismatch": "--max-seam-mismatch",
    "max_verify_stretch": "--max-verify-stretch",
    "max_verify_displacement": "--max-verify-displacement",
    "max_spec_fit": "--max-spec-fit",
    "fail_on_flips": "--fail-on-flips",
    "expect": "expect",
}


def broken_gates(report: dict, gates: Gates) -> list[str]:
    """The options of the gates the report breaks (``["--max-area-change"]``; the
    recipe's ``expect:`` is ``expect``), in :data:`GATE_OPTIONS` order: each set gate
    judged alone by :func:`gate_failures`.

    For a record's ``failed_gates``, which a catalogue filters on.
    """
    out = []
    for attr, option in GATE_OPTIONS.items():
        value = getattr(gates, attr)
        if value is None or value is False:
            continue
        if gate_failures(report, Gates(**{"expect": False, attr: value})):
            out.append(option)
    return out


def _spec_failures(report: dict, lim: float, units: str) -> list[str]:
    """The specification panels whose written curves lie farther than ``lim`` from the
    adjusted mesh outline (strict: a report without ``spec`` breaks the gate)."""
    spec = report.get("spec")
    if not isinstance(spec, dict) or not isinstance(spec.get("panels"), list):
        return ["report: no spec section (--spec): --max-spec-fit cannot pass without it"]
    probs = []
    for p in spec["panels"]:  # a loop over specification panels
        fit = number(p.get("fit"))
        if fit is None or fit > lim:
            shown = "missing" if fit is None else f"{fit:.4g} > {lim:.4g} {units}".rstrip()
            probs.append(f"spec panel {p.get('name', '?')}: fit {shown}")
    return probs
