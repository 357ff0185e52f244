"""SHA-256 digests of files and texts (hex strings), the one place that hashes inputs.

Files are read in 1 MiB blocks, so a large garment is never held in memory to be hashed.

Examples
--------
>>> text_sha256("")
'e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855'
"""

from __future__ import annotations

import hashlib
from pathlib import Path

#: bytes read at a time when hashing a file
_BLOCK = 1 << 20


def file_sha256(path: str | Path) -> str:
    """Hex SHA-256 of a file's bytes, read in blocks.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    str
        64 hex digits.

    Raises
    ------
    OSError
        The file cannot be read.
    """
    h = hashlib.sha256()
    with Path(path).open("rb") as fh:
        for block in iter(lambda: fh.read(_BLOCK), b""):
            h.update(block)
    return h.hexdigest()


def text_sha256(text: str) -> str:
    """Hex SHA-256 of a text's UTF-8 bytes.

    Parameters
    ----------
    text : str

    Returns
    -------
    str
        64 hex digits.
    """
    return hashlib.sha256(text.encode()).hexdigest()
