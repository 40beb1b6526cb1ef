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
tool orientations, id, scene, task frames) as one record, so that these travel together
instead of as parallel lists that must be kept in step:
:class:`lfdkit.io.training.TrainingData` holds its demonstrations so,
:meth:`lfdkit.skill.Skill.fit` and :func:`lfdkit.io.save_demos` take them and
``load_demos(path, as_records=True)`` gives them. :func:`demo_fields` is the
one place records are split back into the lists the estimators below take.

Files
-----
Demonstration files (CSV, NPZ, JSON) are read and written by
:mod:`lfdkit.io` (:func:`lfdkit.io.load_demos`, :func:`lfdkit.io.save_demos`,
...), which describes the formats in :mod:`lfdkit.io.demos`.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, NamedTuple

if TYPE_CHECKING:  # annotations only: this module stays import-free (PathLike for io.atomic)
    import numpy as np

    from lfdkit.model.scene import Scene

__all__ = ["Demo", "DemoFields", "DemoId", "PathLike", "demo_fields"]

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
    frames : dict of str to ndarray, or None
        The poses of the task frames while it was recorded (the objects it
        acts on, its start), by name in the file's order: in 2-D ``[x, y,
        angle]`` (angle in rad, anticlockwise), in 3-D ``[x, y, z, qx, qy,
        qz, qw]`` (a unit quaternion); what :class:`lfdkit.imitate.TPGMM`
        learns in. None when not recorded.
    """

    points: np.ndarray
    times: np.ndarray | None = None
    orientations: np.ndarray | None = None
    id: DemoId | None = None
    scene: Scene | None = None
    frames: dict[str, np.ndarray] | None = None


class DemoFields(NamedTuple):
    """The fields of a list of :class:`Demo` records, one list per field, in order.

    What the estimators below the records take (:func:`demo_fields`);
    ``times``, ``orientations``, ``ids``, ``scenes`` and ``frames`` hold None
    where a record has none.
    """

    points: list[Any]
    times: list[Any]
    orientations: list[Any]
    ids: list[DemoId | None]
    scenes: list[Any]
    frames: list[Any]


def demo_fields(
    demos: Any, name: str = "demos", *, given: dict[str, Any] | None = None
) -> DemoFields | None:
    """Split :class:`Demo` records into parallel lists; None if ``demos`` holds none.

    Lets a function take either form: records, or the arrays (with their
    times, orientations and scenes as separate arguments).

    Parameters
    ----------
    demos : sequence of Demo, or anything else
        The demonstrations as a caller gave them.
    name : str
        The argument's name, for the error.
    given : dict, optional
        The separate arguments the records replace, by name (``{"times":
        times}``): with records, each must be None.

    Returns
    -------
    DemoFields or None
        None when ``demos`` is not a list or tuple of records (arrays, say).

    Raises
    ------
    TypeError
        If the sequence mixes records with other things.
    ValueError
        If records come with one of ``given`` too.
    """
    if not isinstance(demos, Sequence) or isinstance(demos, (str, bytes)):
        return None
    records = [isinstance(demo, Demo) for demo in demos]
    if not any(records):
        return None
    if not all(records):
        j = records.index(False)
        raise TypeError(
            f"{name}[{j}]: expected a Demo record like the others, got "
            f"{type(demos[j]).__name__}; give all records or all arrays"
        )
    for field, value in (given or {}).items():
        if value is not None:
            raise ValueError(
                f"{field}: the Demo records carry their own {field}; give {field}= "
                "only with demonstrations as arrays"
            )
    return DemoFields(
        [demo.points for demo in demos],
        [demo.times for demo in demos],
        [demo.orientations for demo in demos],
        [demo.id for demo in demos],
        [demo.scene for demo in demos],
        [demo.frames for demo in demos],
    )
