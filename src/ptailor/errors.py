"""Exceptions. The CLI maps :class:`PtailorError` to exit status 2, once."""

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
