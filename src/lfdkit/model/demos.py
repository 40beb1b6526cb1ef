"""Demonstrations: the data model.

A *demonstration set* is a plain ``list`` of float64 arrays, one per
demonstration, each of shape ``(n_points_j, n_dims)``. Lengths may differ
between demonstrations; ``n_dims`` is shared (2 or 3 normally, any ``>= 2``
accepted). Coordinates are in whatever unit the user works in (metres for
robot data); lfdkit never rescales them.

Optionally each demonstration carries its sample times, a float64 array of
shape ``(n_points_j,)`` in seconds, strictly increasing, and an id
(:data:`DemoId`) that matches it with its scene.

:class:`Demo` holds one demonstration with what was recorded with it (times,
tool orientations, id, scene) as one record, so that these travel together
instead of as parallel lists that must be kept in step
(:class:`lfdkit.io.training.TrainingData` holds its demonstrations so).

Files
-----
Demonstration files (CSV, NPZ, JSON) are read and written by
:mod:`lfdkit.io` (:func:`lfdkit.io.load_demos`, :func:`lfdkit.io.save_demos`,
...), which describes the formats in :mod:`lfdkit.io.demos`.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # annotations only: this module stays import-free (PathLike for io.atomic)
    import numpy as np

    from lfdkit.model.scene import Scene

__all__ = ["Demo", "DemoId", "PathLike"]

PathLike = str | os.PathLike[str]
"""A file-system path: ``str`` or any ``os.PathLike``."""

DemoId = int | str
"""Identifier of one demonstration in a file: an ``int`` or a non-empty ``str``."""


@dataclass(frozen=True, eq=False)
class Demo:
    """One demonstration and what was recorded with it.

    Attributes
    ----------
    points : ndarray, shape (n_points, q)
        The path, in the user's length unit.
    times : ndarray, shape (n_points,), or None
        Sample times in seconds, strictly increasing; None when not recorded.
    orientations : ndarray, shape (n_points, 4), or None
        The tool's orientation at each point, unit quaternions ``[x, y, z, w]``;
        None when not recorded.
    id : int or str, or None
        Its id in its file (:data:`DemoId`), which matches it with its scene.
    scene : Scene or None
        The obstacles it was recorded around; None (or an empty scene) for a
        clean demonstration.
    """

    points: np.ndarray
    times: np.ndarray | None = None
    orientations: np.ndarray | None = None
    id: DemoId | None = None
    scene: Scene | None = None
