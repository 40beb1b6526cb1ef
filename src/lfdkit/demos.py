"""Demonstrations: the data model.

A *demonstration set* is a plain ``list`` of float64 arrays, one per
demonstration, each of shape ``(n_points_j, n_dims)``. Lengths may differ
between demonstrations; ``n_dims`` is shared (2 or 3 normally, any ``>= 2``
accepted). Coordinates are in whatever unit the user works in (metres for
robot data); lfdkit never rescales them.

Optionally each demonstration carries its sample times, a float64 array of
shape ``(n_points_j,)`` in seconds, strictly increasing, and an id
(:data:`DemoId`) that matches it with its scene.

Files
-----
Demonstration files (CSV, NPZ, JSON) are read and written by
:mod:`lfdkit.io` (:func:`lfdkit.io.load_demos`, :func:`lfdkit.io.save_demos`,
...), which describes the formats in :mod:`lfdkit.io.demos`. The file
functions and constants that used to live in this module (``load_demos``,
``save_demos``, ``save_path``, ``path_csv``, ``atomic_write``,
``check_output_path``, ``OutputExistsError``, ``NotRegularFileError``,
``load_json``, ``json_float_array``, ``SUPPORTED_SUFFIXES``,
``JSON_FORMAT``, ``MAX_FILE_BYTES``, ...) are still reachable as
``lfdkit.demos.<name>``: the first access imports :mod:`lfdkit.io` and
forwards to it. New code imports them from :mod:`lfdkit.io`.
"""

from __future__ import annotations

import importlib
import os
from typing import Any

__all__ = ["DemoId", "PathLike"]

PathLike = str | os.PathLike[str]
"""A file-system path: ``str`` or any ``os.PathLike``."""

DemoId = int | str
"""Identifier of one demonstration in a file: an ``int`` or a non-empty ``str``."""

# The public names that lived here before the file I/O moved to lfdkit.io.
_MOVED_TO_IO = frozenset(
    """JSON_FORMAT JSON_VERSION MAX_FILE_BYTES MAX_JSON_DEPTH MAX_NPZ_ARRAY_BYTES
    MAX_NPZ_MEMBERS STALE_TEMP_SECONDS SUPPORTED_SUFFIXES NotRegularFileError
    OutputExistsError atomic_write check_output_path json_float_array load_demos
    load_json path_csv save_demos save_path""".split()
)


def __getattr__(name: str) -> Any:
    """Forward the names that moved to :mod:`lfdkit.io` (imported on first access)."""
    if name not in _MOVED_TO_IO:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module("lfdkit.io"), name)


def __dir__() -> list[str]:
    return sorted({*globals(), *_MOVED_TO_IO})
