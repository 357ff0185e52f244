"""The re-drape check's options (``--verify`` and its settings for ``adjust`` and
``batch``; ``--rest``, ``--max-steps``, ``--null-mean``, ``--null-p95`` for ``verify``)."""

from __future__ import annotations

import click


def rest_option(name: str = "--rest"):
    """``--rest intrinsic|pattern``: how the re-drapes' triangles rest."""
    return click.option(
        name,
        type=click.Choice(["intrinsic", "pattern"]),
        default="intrinsic",
        show_default=True,
        help="Re-drape rest shapes: intrinsic (each pattern triangle through the original "
        "garment's intrinsic scale: the original pattern rests as the original drape) or "
        "pattern (plain cloth cut from the pattern).",
    )


def max_steps_option(name: str = "--max-steps"):
    """``--max-steps N``: the re-drapes' step cap."""
    return click.option(
        name,
        type=click.IntRange(min=1),
        default=None,
        metavar="N",
        help="Re-drape: stop each simulation after N steps when it has not settled "
        "[default: the engine's, 2000 = 20 s].",
    )


def null_options(prefix: str = ""):
    """``--null-mean`` and ``--null-p95`` (``--verify-null-...`` for ``adjust`` and
    ``batch``): the null test's limits."""
    what = {
        "mean": ("1cm", "mean"),
        "p95": ("2.5cm", "95th-percentile"),
    }

    def deco(fn):
        for key in ("p95", "mean"):
            default, word = what[key]
            fn = click.option(
                f"--{prefix}null-{key}",
                f"null_{key}" if not prefix else f"verify_null_{key}",
                default=None,
                metavar="LENGTH",
                help=f"Null test: the original pattern re-draped from the original drape must "
                f"land at most this far from it ({word} over its vertices; 1cm, 10mm, a bare "
                f"number in the computation units) or the verdict is inconclusive "
                f"[default: {default}].",
            )(fn)
        return fn

    return deco


def verify_options(fn):
    """``--verify``, ``--verify-rest``, ``--verify-max-steps``, ``--verify-null-mean``,
    ``--verify-null-p95``: the re-drape check."""
    for opt in reversed(
        [
            click.option(
                "--verify",
                is_flag=True,
                help="Re-drape check: sew the adjusted pattern and the uniform baseline on "
                "the edited drape, the original pattern on the original drape (the null "
                "test), with the cloth engine (pip install 'ptailor[sim]'); the report gets "
                "verify (with the null test and the verdict), the folder verify_ours.obj, "
                "verify_baseline.obj and verify.png.",
            ),
            rest_option("--verify-rest"),
            max_steps_option("--verify-max-steps"),
            null_options("verify-"),
        ]
    ):
        fn = opt(fn)
    return fn


def parse_cm(text: str, *, units: str, what: str) -> float:
    """A length option (``1cm``, ``10mm``, a bare number in ``units``) in cm."""
    from ptailor.formats.garment import parse_length
    from ptailor.model.units import CM_PER

    return parse_length(text, to=units, what=what) * CM_PER[units]
