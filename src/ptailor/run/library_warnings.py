"""Library noise: the warnings and log records numpy, ezdxf, ... emit while ptailor runs,
captured as one-line texts (for a report's ``warnings``) instead of printed."""

from __future__ import annotations

import contextlib
import logging
import warnings
from contextlib import contextmanager

from ptailor import tolerances
from ptailor.run.staging import hide_staging

LIBRARY_WARNINGS_MAX = tolerances.LIBRARY_WARNINGS_MAX
#: warnings meant for developers, not for the report (dropped)
_DEVELOPER_WARNINGS = (
    DeprecationWarning,
    PendingDeprecationWarning,
    FutureWarning,
    ImportWarning,
    ResourceWarning,
)


class _Collect(logging.Handler):
    def __init__(self, sink: list[str]) -> None:
        super().__init__(logging.WARNING)
        self.sink = sink

    def emit(self, record: logging.LogRecord) -> None:
        with contextlib.suppress(Exception):
            _add(self.sink, f"{record.name}: {record.getMessage()}")


def _add(sink: list[str], text: str) -> None:
    line = "library warning: " + hide_staging(" ".join(str(text).split()))[:300]
    if line not in sink and len(sink) < LIBRARY_WARNINGS_MAX:
        sink.append(line)


@contextmanager
def capture_library_warnings():
    """Capture Python warnings (numpy ``RuntimeWarning``...) and logging records of
    WARNING and above (ezdxf...) instead of printing them; yields the list of one-line
    texts, which grows while the block runs (a run puts it into its report's ``warnings``:
    :func:`ptailor.run.garment.staged_run`)."""
    sink: list[str] = []
    root = logging.getLogger()
    handler = _Collect(sink)
    saved = root.handlers[:]
    root.handlers = [handler]
    try:
        with warnings.catch_warnings():  # (restores showwarning and the filters)

            def show(message, category, *args, **kwargs) -> None:
                if not issubclass(category, _DEVELOPER_WARNINGS):
                    _add(sink, f"{category.__name__}: {message}")

            warnings.showwarning = show
            yield sink
    finally:
        root.handlers = saved
