"""A progress line on stderr for commands that take a while: stage, iteration, residual.

Shown only on a terminal, only once the run has taken ``delay`` seconds (a quick run shows
nothing), rewritten in place at most ``1 / interval`` times a second, and erased when the
run ends: stdout and a redirected stderr never see it.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import TextIO

__all__ = ["ProgressLine", "progress_line"]


class ProgressLine:
    """``progress(stage, iteration, residual)`` drawn as one line on ``stream``.

    Parameters
    ----------
    stream : text stream
        Where the line goes (a terminal).
    delay : float
        Seconds after the start before the line first shows.
    interval : float
        Seconds between redraws within one stage.
    clock : callable
        Seconds now (``time.monotonic``; a test passes its own).
    """

    def __init__(
        self, stream: TextIO, *, delay: float = 1.0, interval: float = 0.1, clock=time.monotonic
    ) -> None:
        self.stream, self.delay, self.interval, self.clock = stream, delay, interval, clock
        self.start = clock()
        self.last = -float("inf")
        self.stage: str | None = None
        self.shown = False

    def __call__(self, stage: str, iteration: int = 0, residual: float | None = None) -> None:
        now = self.clock()
        if now - self.start < self.delay:
            self.stage = stage
            return
        if stage == self.stage and now - self.last < self.interval:
            return
        self.stage, self.last = stage, now
        text = f"ptailor: {stage}"
        if iteration:
            text += f", iteration {iteration}"
        if residual is not None:
            text += f", residual {residual:.1e}"
        text += f" ({now - self.start:.0f} s)"
        self.stream.write("\r\x1b[K" + text)
        self.stream.flush()
        self.shown = True

    def close(self) -> None:
        """Erase the line, if it was drawn."""
        if self.shown:
            self.stream.write("\r\x1b[K")
            self.stream.flush()
            self.shown = False


@contextmanager
def progress_line(*, quiet: bool = False, stream: TextIO | None = None) -> Iterator:
    """A :class:`ProgressLine` on stderr when it is a terminal (and not ``quiet``), else
    None; erased when the block ends, however it ends."""
    stream = sys.stderr if stream is None else stream
    isatty = getattr(stream, "isatty", None)
    if quiet or isatty is None or not isatty():
        yield None
        return
    line = ProgressLine(stream)
    try:
        yield line
    finally:
        line.close()
