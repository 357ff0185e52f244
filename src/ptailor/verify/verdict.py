"""The null test and the verdict of a re-drape check, from its report section alone.

The **null test**: the original pattern, re-draped on the same body from the original
drape, must land where it started (:func:`null_test`): mean and 95th-percentile vertex
displacement at most ``NULL_MEAN_CM`` and ``NULL_P95_CM`` by default. When it does not,
the body (or the garment's hang under this simulator) does not fit this garment, every
re-drape moves for that reason too, and the check cannot rank two patterns.

The **verdict** (:func:`verdict`) ranks ours against the uniform baseline only when the
null test holds and its re-drape settled: on stretch (the worst panel's stretch p95 above
the null re-drape's own, panel by panel: a pattern too tight) and on displacement (the 95th
percentile of the vertices' distance from the edited drape: a pattern that does not rest
like the edit). Else it is ``inconclusive``, with the reason.

Only dicts and numbers: no engine (a report's ``verify`` section can be judged again).
"""

from __future__ import annotations

import math

from ptailor.verify import tolerances as verify_tol

__all__ = ["null_test", "verdict"]


def _num(x) -> float:
    """A report number as a float (nan for None)."""
    return float("nan") if x is None else float(x)


def null_test(
    R: dict,
    *,
    cm_per_unit: float,
    mean_cm: float | None = None,
    p95_cm: float | None = None,
) -> dict:
    """Whether the original pattern's re-drape from the original drape reproduced it.

    Parameters
    ----------
    R : dict
        The null re-drape's report (``verify.original``): ``displacement`` ``{mean, p95,
        max}`` over the drape's vertices (from the original drape, report units),
        ``panels`` (each with its ``displacement``), ``settled``.
    cm_per_unit : float
        Centimetres per report unit.
    mean_cm, p95_cm : float, optional
        The limits, cm (default ``NULL_MEAN_CM``, ``NULL_P95_CM``).

    Returns
    -------
    dict
        ``{"mean", "p95", "max"}`` (report units), ``"limits": {"mean", "p95"}`` (report
        units), ``"panels": {NAME: {"mean", "p95", "max"}}``, ``"settled"``, ``"holds"``
        (both within the limits; nan fails) and ``"why"`` (a sentence, in cm).
    """
    mean_cm = verify_tol.NULL_MEAN_CM if mean_cm is None else float(mean_cm)
    p95_cm = verify_tol.NULL_P95_CM if p95_cm is None else float(p95_cm)
    d = R.get("displacement") or {}
    mean, p95, mx = _num(d.get("mean")), _num(d.get("p95")), _num(d.get("max"))
    holds = bool(mean * cm_per_unit <= mean_cm and p95 * cm_per_unit <= p95_cm)
    panels = {n: dict(p["displacement"]) for n, p in R.get("panels", {}).items()}
    worst = max(panels, key=lambda n: _num(panels[n].get("p95")), default=None)
    why = (
        f"the original pattern re-draped from the original drape lands mean "
        f"{mean * cm_per_unit:.2f} cm, p95 {p95 * cm_per_unit:.2f} cm from it "
        f"({'within' if holds else 'beyond'} {mean_cm:g} and {p95_cm:g} cm)"
    )
    if not holds and worst is not None:
        why += f"; most in {worst} (p95 {_num(panels[worst].get('p95')) * cm_per_unit:.2f} cm)"
    return {
        "mean": mean,
        "p95": p95,
        "max": mx,
        "limits": {"mean": mean_cm / cm_per_unit, "p95": p95_cm / cm_per_unit},
        "panels": panels,
        "settled": bool(R.get("settled", False)),
        "holds": holds,
        "why": why,
    }


def _stretch_excess(R: dict, null: dict) -> float:
    """The largest panel stretch p95 above the null re-drape's same panel (its own, where
    the null has none)."""
    out = []
    for name, p in R.get("panels", {}).items():
        ref = _num(null.get("panels", {}).get(name, {}).get("stretch", {}).get("p95"))
        s = _num(p["stretch"]["p95"])
        out.append(s - (ref if math.isfinite(ref) else 1.0))
    finite = [x for x in out if math.isfinite(x)]
    return max(finite) if finite else float("nan")


def _order(a: float, b: float, tie: float) -> int:
    """-1 when ``a`` is lower (better) by more than ``tie``, 1 when ``b`` is, 0 a tie (or
    a nan)."""
    if not (math.isfinite(a) and math.isfinite(b)) or abs(a - b) <= tie:
        return 0
    return -1 if a < b else 1


def verdict(section: dict, null: dict, *, cm_per_unit: float) -> dict:
    """Ours against the baseline, when the null test allows it.

    Parameters
    ----------
    section : dict
        The check's section with ``ours``, ``baseline`` and ``original`` (the null
        re-drape): each with ``panels`` and ``displacement`` ``{mean, p95, max}`` (report
        units) and ``settled``.
    null : dict
        :func:`null_test`'s.
    cm_per_unit : float
        Centimetres per report unit.

    Returns
    -------
    dict
        ``holds`` (the null test held and its re-drape settled), ``result`` (``ours``,
        ``baseline``, ``tie``, ``mixed`` or ``inconclusive``), ``reason`` (a sentence);
        when it holds also ``ranking`` (best first), ``measures`` (per pattern:
        ``stretch_excess``, the worst panel's stretch p95 above the null's, and
        ``displacement_p95``, report units) and ``unsettled`` (the re-drapes that hit the
        step cap: their numbers are where they stopped).
    """
    if not null["holds"] or not null["settled"]:
        why = null["why"] if not null["holds"] else "the null re-drape did not settle"
        return {
            "holds": False,
            "result": "inconclusive",
            "reason": f"the body does not fit this garment (or it does not hang on it as "
            f"it was simulated): {why}; ours and the baseline are not ranked",
        }
    ref = section["original"]
    m = {
        k: {
            "stretch_excess": _stretch_excess(section[k], ref),
            "displacement_p95": _num(section[k]["displacement"]["p95"]),
        }
        for k in ("ours", "baseline")
    }
    by_s = _order(m["ours"]["stretch_excess"], m["baseline"]["stretch_excess"],
                  verify_tol.VERDICT_STRETCH_TIE)  # fmt: skip
    tie_d = verify_tol.VERDICT_DISPLACEMENT_TIE_CM / cm_per_unit
    by_d = _order(m["ours"]["displacement_p95"], m["baseline"]["displacement_p95"], tie_d)
    result = _result(by_s, by_d)
    unsettled = [k for k in ("ours", "baseline", "original") if not section[k]["settled"]]
    return {
        "holds": True,
        "result": result,
        "ranking": ["baseline", "ours"] if (by_s or by_d) > 0 else ["ours", "baseline"],
        "measures": m,
        "unsettled": unsettled,
        "reason": _reason(result, m, cm_per_unit, unsettled),
    }


def _result(by_s: int, by_d: int) -> str:
    """``ours`` / ``baseline`` when one is better on one measure and not worse on the other,
    ``tie`` when neither, ``mixed`` when each is better on one (ranked by stretch)."""
    if by_s == by_d == 0:
        return "tie"
    if by_s * by_d < 0:
        return "mixed"
    return "ours" if by_s + by_d < 0 else "baseline"


def _reason(result: str, m: dict, cm_per_unit: float, unsettled: list[str]) -> str:
    """The verdict in a sentence (displacements in cm)."""
    o, b = m["ours"], m["baseline"]
    nums = (
        f"stretch p95 above the null's {o['stretch_excess']:+.3f} (ours) vs "
        f"{b['stretch_excess']:+.3f} (baseline), displacement p95 "
        f"{o['displacement_p95'] * cm_per_unit:.2f} vs {b['displacement_p95'] * cm_per_unit:.2f} cm"
    )
    head = {
        "ours": "ours rests closer to the edit than the baseline",
        "baseline": "the baseline rests closer to the edit than ours",
        "tie": "ours and the baseline rest alike",
        "mixed": "ours and the baseline each win on one measure (ranked by stretch)",
    }[result]
    tail = f"; not settled: {', '.join(unsettled)}" if unsettled else ""
    return f"{head}: {nums}{tail}"
