"""Rewrite the names table (tests/names/KEY.json) from what the naming rules answer now.

    python tests/names/regenerate.py            # every case (shared ones when ../shared exists)
    python tests/names/regenerate.py dress tee  # the cases whose key contains a word

Run it after a change to the naming rules (src/ptailor/model/names, model/openings) and commit
the table with the change: ``git diff tests/names`` lists every name the change moved.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:  # run as a script: the tests package from the repository
    sys.path.insert(0, str(ROOT))

from tests.names.cases import CASES, dumps, names_of, shared_file  # noqa: E402


def main(words: list[str]) -> int:
    """Write the table files of the cases matching ``words`` (all when empty)."""
    for case in CASES:
        if words and not any(w in case.key for w in words):
            continue
        if case.shared and not shared_file(case).is_file():
            print(f"{case.key}: skipped ({shared_file(case)} is absent)")
            continue
        text = dumps(names_of(case))
        old = case.path.read_text() if case.path.is_file() else None
        if old != text:
            case.path.write_text(text)
        print(f"{case.key}: {'unchanged' if old == text else 'written'}")
    known = {c.path.name for c in CASES}
    for p in sorted(case.path.parent.glob("*.json")):
        if p.name not in known:
            print(f"{p.name}: no case names it (remove it, or add its case to cases.py)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
