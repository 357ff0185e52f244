"""Results of pure functions of a garment's arrays, kept by the arrays' content.

A garment's topology is traced by several consumers that each hold only arrays: the
flatten and its baseline (each panel's boundary loops), the pieces and the outputs (the
same loops again), the seam ease and the pieces (the seam half-edges). The garments they
hold are different objects (a copy with new positions, the adjusted garment), so the
per-garment cache (:mod:`ptailor.model.structure`) cannot share the work; the arrays'
content can. :func:`keep` and :func:`recall` hold the last :data:`SIZE` results by a
digest of their array arguments (SHA-256, which CPUs hash in hardware: about 1.3 ms for a
100k-triangle index array, 5x less than BLAKE2b, against tens of milliseconds for the
tracing it saves).

Results are returned as stored: a memoized function hands callers copies of its arrays
when they may write to them.
"""

from __future__ import annotations

import hashlib
import threading
from collections import OrderedDict
from typing import Any

import numpy as np

#: results kept (least recently used dropped first)
SIZE = 32

_store: OrderedDict[tuple, Any] = OrderedDict()
_lock = threading.Lock()


def array_key(*arrays: np.ndarray | None) -> tuple:
    """A key for the content of ``arrays``: dtype, shape and the SHA-256 digest of each.

    Examples
    --------
    >>> a = np.arange(6).reshape(2, 3)
    >>> array_key(a) == array_key(a.copy()), array_key(a) == array_key(a.T)
    (True, False)
    >>> array_key(None)
    (None,)
    """
    out: list = []
    for a in arrays:
        if a is None:
            out.append(None)
            continue
        a = np.ascontiguousarray(a)
        digest = hashlib.sha256(memoryview(a.reshape(-1)).cast("B")).digest()
        out.append((a.dtype.str, a.shape, digest))
    return tuple(out)


def recall(name: str, key: tuple) -> Any | None:
    """The result kept for ``(name, key)``, or None.

    Parameters
    ----------
    name : str
        The function (keys of different functions never meet).
    key : tuple
        :func:`array_key` of its arrays and its other arguments.

    Examples
    --------
    >>> keep("doc", ("k",), 1)
    1
    >>> recall("doc", ("k",)), recall("doc", ("other",))
    (1, None)
    """
    k = (name, key)
    with _lock:
        if k in _store:
            _store.move_to_end(k)
            return _store[k]
    return None


def keep(name: str, key: tuple, value: Any) -> Any:
    """Keep ``value`` for ``(name, key)`` (:func:`recall`) and return it."""
    with _lock:
        _store[(name, key)] = value
        while len(_store) > SIZE:
            _store.popitem(last=False)
    return value


def clear() -> None:
    """Forget every kept result."""
    with _lock:
        _store.clear()
