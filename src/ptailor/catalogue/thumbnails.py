"""A garment's thumbnail: its ``preview.png`` made small with Pillow, written once."""

from __future__ import annotations

import io
from pathlib import Path

from ptailor import tolerances as tol

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
        The preview cannot be read, is not an image Pillow knows, or has more than
        :data:`~ptailor.tolerances.THUMBNAIL_PREVIEW_MAX_PIXELS` pixels (Pillow's
        decompression-bomb refusal, and any other of its decoding errors, too).
    """
    from PIL import Image

    try:
        return _thumbnail(preview, size)
    except (ValueError, SyntaxError, EOFError, Image.DecompressionBombError) as exc:
        raise OSError(f"not a preview Pillow can read ({exc})") from None


def _thumbnail(preview: str | Path, size: tuple[int, int]) -> bytes:
    from PIL import Image

    with Image.open(preview) as im:
        w, h = im.size
        if w * h > tol.THUMBNAIL_PREVIEW_MAX_PIXELS:
            raise OSError(
                f"the preview is {w} x {h} pixels, more than "
                f"{tol.THUMBNAIL_PREVIEW_MAX_PIXELS} (not one ptailor wrote)"
            )
        im = im.convert("RGB")
        # reducing_gap: a box reduction first, then Lanczos (Pillow's fast path, same look);
        # no optimize pass (it cost a third of the time for 2 % of the size)
        im.thumbnail(size, Image.Resampling.LANCZOS, reducing_gap=3.0)
        buf = io.BytesIO()
        im.save(buf, format="PNG")
    return buf.getvalue()


def thumbnails(folders: list[Path], *, workers: int | None = None) -> dict[Path, bytes | OSError]:
    """The thumbnails the folders need (a preview and no current thumbnail), made on
    ``workers`` threads (Pillow decodes and resizes without the GIL; default: the cores).

    Returns
    -------
    dict
        Folder -> the thumbnail's PNG, or the ``OSError`` its preview raised.
    """
    import os
    from concurrent.futures import ThreadPoolExecutor

    todo = [f for f in folders if (f / PREVIEW).is_file() and not thumbnail_current(f)]

    def one(folder: Path) -> bytes | OSError:
        try:
            return thumbnail_bytes(folder / PREVIEW)
        except OSError as exc:
            return exc

    if not todo:
        return {}
    with ThreadPoolExecutor(max_workers=workers or os.cpu_count() or 1) as pool:
        return dict(zip(todo, pool.map(one, todo), strict=True))


def thumbnail_current(folder: Path) -> bool:
    """Whether the folder's thumbnail exists and is not older than its preview."""
    thumb, preview = folder / THUMBNAIL, folder / PREVIEW
    try:
        return thumb.stat().st_mtime_ns >= preview.stat().st_mtime_ns
    except OSError:
        return False
