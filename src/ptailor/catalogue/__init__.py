"""A catalogue a person looks at: one static HTML page per batch (``OUT/index.html``), a
row per garment with its status, reason, thumbnail and numbers, sortable and filterable,
and a page per garment (``OUT/NAME/index.html``) with its pattern, tables, steps and
warnings (``ptailor batch --html``, ``ptailor report OUT``).

- :mod:`~ptailor.catalogue.rows`: the rows, from a run's records and the folders under OUT;
- :mod:`~ptailor.catalogue.thumbnails`: a garment's preview made small (Pillow), once;
- :mod:`~ptailor.catalogue.pages`: what each page shows, rendered with jinja2 (autoescaped);
- :mod:`~ptailor.catalogue.write`: the files, written where ptailor may write them.
"""

from __future__ import annotations

from ptailor.catalogue.rows import (
    CATALOGUE_DIR,
    INDEX,
    RESERVED_NAMES,
    Row,
    Summary,
    catalogue_rows,
    read_log,
    saved_records,
)
from ptailor.catalogue.write import check_catalogue_target, write_catalogue

__all__ = [
    "CATALOGUE_DIR",
    "INDEX",
    "RESERVED_NAMES",
    "Row",
    "Summary",
    "catalogue_rows",
    "check_catalogue_target",
    "read_log",
    "saved_records",
    "write_catalogue",
]
