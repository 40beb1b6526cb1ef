"""Values kept by a digest of the arrays they were made from, the least recently used out first.

Why (issue 34): a skill's model choice plans each training scene a dozen
times over, and parts of each plan depend on fewer inputs than the plan (the
corridor on the nominal alone, the grid's obstacle terms on the reward and
the levels): made once, they are the same numbers at a fraction of the cost.
:func:`array_digest` names the inputs by their bytes (blake2b, 20 bytes), so a
value is reused only for inputs equal to the bit; :class:`DigestMemo` keeps
values up to a count or a byte size, safe across threads (the IOC plans on
threads).
"""

from __future__ import annotations

import hashlib
import threading
from collections.abc import Callable
from typing import Any, Generic, TypeVar

import numpy as np

__all__ = ["DigestMemo", "array_digest"]

Value = TypeVar("Value")


def array_digest(*arrays: np.ndarray, label: str = "") -> bytes:
    """A 20-byte digest of ``label`` and each array's shape and bytes (C order, float64 as given).

    Parameters
    ----------
    *arrays : ndarray
        Read in C order (a Fortran-ordered or strided array gives the digest
        of its C-ordered copy).
    label : str
        Whatever else tells values apart (e.g. a point count, a kernel's form).

    Returns
    -------
    bytes
    """
    digest = hashlib.blake2b(digest_size=20)
    digest.update(label.encode())
    for array in arrays:
        digest.update(repr(array.shape).encode())
        digest.update(np.ascontiguousarray(array).data)
    return digest.digest()


class DigestMemo(Generic[Value]):
    """Values by key, the least recently used out first past ``max_items`` or ``max_bytes``.

    Parameters
    ----------
    max_items : int, optional
        The most values kept (default: no bound on the count).
    max_bytes : int, optional
        The most bytes kept, each value's from ``size`` (default: no bound);
        a value larger on its own is not kept.
    size : callable, optional
        A value's bytes (default: ``value.nbytes``), with ``max_bytes``.
    """

    def __init__(
        self,
        max_items: int | None = None,
        max_bytes: int | None = None,
        size: Callable[[Any], int] | None = None,
    ) -> None:
        self.max_items = max_items
        self.max_bytes = max_bytes
        self._size = size or (lambda value: int(value.nbytes))
        self._items: dict[bytes, Value] = {}
        self._bytes = 0
        self._lock = threading.Lock()

    def __len__(self) -> int:
        return len(self._items)

    @property
    def nbytes(self) -> int:
        """Bytes kept (0 without ``max_bytes``)."""
        return self._bytes

    def get(self, key: bytes) -> Value | None:
        """The value kept under ``key`` (now the most recently used), or None."""
        with self._lock:
            found = self._items.pop(key, None)
            if found is not None:
                self._items[key] = found  # the most recently used last
            return found

    def put(self, key: bytes, value: Value) -> Value:
        """Keep ``value`` under ``key``; the value kept (one already there stays), or ``value``."""
        size = self._size(value) if self.max_bytes is not None else 0
        with self._lock:
            kept = self._items.get(key)
            if kept is not None:
                return kept
            if self.max_bytes is not None and size > self.max_bytes:
                return value
            self._items[key] = value
            self._bytes += size
            while (self.max_items is not None and len(self._items) > self.max_items) or (
                self.max_bytes is not None and self._bytes > self.max_bytes
            ):
                oldest = self._items.pop(next(iter(self._items)))
                if self.max_bytes is not None:
                    self._bytes -= self._size(oldest)
            return value
