"""Exceptions, by kind. The CLI maps them to exit statuses in one place (``ptailor.cli.main``):

- :class:`PtailorError` (:class:`RecipeError`, :class:`NumericError`, :class:`AbsentError`):
  the input, exit 2;
- ``MemoryError``: out of memory, exit 2 (neither the garment's fault nor a bug);
- :class:`Interrupted`: a signal, exit 128 + it;
- any other exception: an internal error, a bug in ptailor, exit 1 with
  :func:`internal_error`'s line (the traceback only with ``ptailor --debug``).

The kind comes from the exception's type, never from its message.
"""

from __future__ import annotations


class PtailorError(Exception):
    """Bad input: a file or recipe the tool cannot use.

    Parameters
    ----------
    message : str
        One line saying what is wrong.
    path : str, optional
        The file the problem is in; prefixed to the message.
    """

    def __init__(self, message: str, *, path: str | None = None) -> None:
        self.path = path
        self.message = message
        super().__init__(f"{path}: {message}" if path else message)


class RecipeError(PtailorError):
    """A recipe with one or more problems, all collected before any garment is read.

    Parameters
    ----------
    problems : list of str
        Each problem, already naming its step (``steps[2].factor: ...``).
    path : str, optional
        The recipe file.
    """

    def __init__(self, problems: list[str], *, path: str | None = None) -> None:
        self.problems = list(problems)
        n = len(self.problems)
        head = f"{n} problem{'s' if n != 1 else ''} in recipe"
        super().__init__(head + ": " + "; ".join(self.problems), path=path)


class AbsentError(PtailorError):
    """A recipe step names what this garment lacks: a panel, a part of the body, an
    opening, a seam, a point of measure (``no panel named sleeve``, ``no part sleeves``).

    Still the input's kind (exit 2), but a step with ``optional: true`` is skipped on such a
    garment instead (:func:`ptailor.pipeline.apply_steps`): one recipe serves a catalogue in
    which some garments have no sleeves.
    """


class LimitError(PtailorError):
    """An edit larger than the garment allows where it is asked: an offset that turns part
    of a region inside out. Still the input's kind (exit 2); the step that raised it may
    probe smaller values and name one that passes (:func:`ptailor.edits.loosen.offset_step`).
    """


class NumericError(PtailorError):
    """A numeric failure of a solve: a singular or indefinite factorisation, a non-finite
    value where the method needs a finite one (still the input's kind, exit 2: the garment or
    the edit leaves a degenerate problem).

    Raised where the solve is (the factor and solve wrappers of :mod:`ptailor.method`, the
    finiteness checks), naming what failed; the pipeline prefixes the step (:meth:`at`).
    """

    def at(self, where: str) -> NumericError:
        """The same failure, its message prefixed with ``where`` (a step of the pipeline)."""
        return NumericError(f"{where}: {self.message}", path=self.path)


def internal_error(exc: BaseException, more: str = "") -> str:
    """One line for an exception of no known kind: a bug in ptailor, to be reported.

    ``internal error: TYPE: message (a bug in ptailor VERSION: please report it)``, with
    ``more`` before the closing parenthesis.
    """
    from ptailor import __version__

    what = " ".join(str(exc).split())
    what = f"{type(exc).__name__}: {what}" if what else type(exc).__name__
    return f"internal error: {what} (a bug in ptailor {__version__}: please report it{more})"


#: The line for a ``MemoryError`` (exit 2; ``batch``: the garment's ``input`` failure).
OUT_OF_MEMORY = "out of memory: the garment or its edit needs more memory than there is"


class Interrupted(KeyboardInterrupt):
    """SIGINT or SIGTERM during a command (a ``KeyboardInterrupt``, so that every clean-up
    that handles Ctrl-C handles SIGTERM too).

    Parameters
    ----------
    signum : int
        The signal; the CLI exits with 128 + it.
    """

    def __init__(self, signum: int) -> None:
        self.signum = signum
        super().__init__(signum)
