"""A garment's thumbnail: its ``preview.png`` made small with Pillow, written once."""

from __future__ import annotations

import io
from pathlib import Path

#: the thumbnail's file, in the garment's folder
THUMBNAIL = "thumbnail.png"
#: the preview it is made from
PREVIEW = "preview.png"
#: the largest thumbnail, pixels (width, height); the preview's aspect is kept
THUMBNAIL_SIZE = (360, 240)


def thumbnail_bytes(preview: str | Path, *, size: tuple[int, int] = THUMBNAIL_SIZE) -> bytes:
    """A PNG of ``preview`` fitted into ``size`` (Pillow's Lanczos reduction).

    Parameters
    ----------
    preview : str or Path
        A PNG (a garment's ``preview.png``).
    size : (2,) tuple of int
        The box the thumbnail fits in, pixels.

    Returns
    -------
    bytes
        The thumbnail, PNG.

    Raises
    ------
    OSError
        The preview cannot be read or is not an image Pillow knows.
    """
    from PIL import Image

    with Image.open(preview) as im:
        im = im.convert("RGB")
        im.thumbnail(size, Image.Resampling.LANCZOS)
        buf = io.BytesIO()
        im.save(buf, format="PNG", optimize=True)
    return buf.getvalue()


def thumbnail_current(folder: Path) -> bool:
    """Whether the folder's thumbnail exists and is not older than its preview."""
    thumb, preview = folder / THUMBNAIL, folder / PREVIEW
    try:
        return thumb.stat().st_mtime_ns >= preview.stat().st_mtime_ns
    except OSError:
        return False
