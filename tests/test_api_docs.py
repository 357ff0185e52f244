"""docs/api.md's examples, run as doctests (the page is the API's tutorial: it must run)."""

from __future__ import annotations

import doctest
from pathlib import Path

import pytest

API_MD = Path(__file__).resolve().parents[1] / "docs" / "api.md"


@pytest.mark.slow
def test_api_md_examples_run():
    result = doctest.testfile(
        str(API_MD),
        module_relative=False,
        optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE,
        raise_on_error=False,
        verbose=False,
    )
    assert result.attempted >= 20  # (the page's examples were found)
    assert result.failed == 0
