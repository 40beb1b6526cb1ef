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
...), which describes the formats in :mod:`lfdkit.io.demos`.
"""

from __future__ import annotations

import os

__all__ = ["DemoId", "PathLike"]

PathLike = str | os.PathLike[str]
"""A file-system path: ``str`` or any ``os.PathLike``."""

DemoId = int | str
"""Identifier of one demonstration in a file: an ``int`` or a non-empty ``str``."""
