"""The re-drape check in a few terminal lines (``adjust --verify``, ``ptailor verify``)."""

from __future__ import annotations

__all__ = ["summary_lines"]


def _state(r: dict, units: str) -> str:
    """Settled or not, and why (where it still moved when it stopped at the cap)."""
    state = "settled" if r.get("settled") else "step cap"
    settle = r.get("settle") or {}
    if settle.get("move_p95") is not None:
        state += (
            f"; moved p95 {settle['move_p95']:.3g} {units} in its last {settle['window_steps']}"
        )
        state += " steps"
    if not r.get("settled") and r.get("moving"):
        m = r["moving"][0]
        state += f"; still moving {r['speed_p95']:.3g} {units}/s, most {m['panel']}"
        state += f" {m['speed_p95']:.3g} {units}/s"
    return state


def _null_lines(sec: dict, units: str) -> list[str]:
    """The null test's and the verdict's lines (none for a report written before them)."""
    null, ver = sec.get("null"), sec.get("verdict")
    if not isinstance(null, dict) or not isinstance(ver, dict):
        return []
    lim = null.get("limits", {})
    lines = [
        f"  null test: the original pattern from the original drape lands mean "
        f"{null['mean']:.3g} {units}, p95 {null['p95']:.3g} {units}, max {null['max']:.3g} "
        f"{units} from it (limits {lim.get('mean', float('nan')):.3g}, "
        f"{lim.get('p95', float('nan')):.3g} {units}): "
        + ("holds" if null.get("holds") else "does NOT hold")
    ]
    lines.append(f"  verdict: {ver.get('result', '?')}: {ver.get('reason', '')}")
    return lines


def summary_lines(doc: dict) -> list[str]:
    """The check in a few lines: per re-drape, its worst panel's stretch and displacement,
    settled or not and why; the null test and the verdict.

    Parameters
    ----------
    doc : dict
        ``report.json`` (``adjust --verify``) or ``verify.json`` (``ptailor verify``): its
        ``verify`` section and ``units``.

    Returns
    -------
    list of str
    """
    sec = doc["verify"]
    units = doc.get("units", "")
    if isinstance(units, dict):  # (adjust's report)
        units = units.get("computation", "")
    cpu = sec.get("cpu_seconds")
    lines = [
        f"re-drape: {sec.get('engine', '?')} on {sec.get('device', '?')}, rest "
        f"{sec.get('rest', '?')}, {sec.get('steps', 0)} steps in {sec.get('seconds', 0):.1f} s"
        + (f" ({cpu:.1f} s CPU)" if cpu is not None else "")
    ]
    for kind in ("ours", "baseline", "original"):
        r = sec.get(kind)
        if not isinstance(r, dict):
            continue
        panels = r.get("panels", {})
        s95 = max((p["stretch"]["p95"] for p in panels.values()), default=float("nan"))
        d95 = max((p["displacement"]["p95"] for p in panels.values()), default=float("nan"))
        lines.append(
            f"  {kind:<9} stretch p95 {s95:.3f}  displacement p95 {d95:.3g} {units}  "
            f"({_state(r, units)})"
        )
    return lines + _null_lines(sec, units)
