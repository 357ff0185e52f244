"""Limits an edit checks at apply time: amounts too small to matter, sizes too large."""

from __future__ import annotations

from ptailor import tolerances as tol
from ptailor.errors import PtailorError


def check_by(by: float, mean_edge: float, *, what: str) -> None:
    """Refuse a ``by`` too small to change anything (below ``tol.EDIT_MIN_BY_REL`` edges)."""
    if not by >= tol.EDIT_MIN_BY_REL * mean_edge:
        raise PtailorError(
            f"{what} by {by:g}: too small, below {tol.EDIT_MIN_BY_REL:g} of the opening's mean "
            f"edge length ({mean_edge:.4g}); nothing would change"
        )


def check_new_triangles(new: float, m: int, *, what: str) -> None:
    """Refuse an edit creating more triangles than the limits, before allocating them."""
    cap = min(
        max(tol.EDIT_NEW_TRIANGLES_FACTOR * m, tol.EDIT_NEW_TRIANGLES_FLOOR),
        tol.EDIT_MAX_TRIANGLES,
    )
    if not new <= cap:
        raise PtailorError(
            f"{what}: would create {new:.3g} triangles, more than the limit of {cap:.0f} "
            f"(the larger of {tol.EDIT_NEW_TRIANGLES_FACTOR:g} times the garment's {m} and "
            f"{tol.EDIT_NEW_TRIANGLES_FLOOR}, at most {tol.EDIT_MAX_TRIANGLES}); do less"
        )
