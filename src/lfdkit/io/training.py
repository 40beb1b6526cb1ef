"""Training files: a demonstrations file and its scene file, split for learning.

:func:`read_training_data` reads the demonstrations (:func:`lfdkit.io.load_demos`)
and, optionally, the scenes they were recorded in (:func:`lfdkit.io.load_scenes`),
and splits them as :meth:`lfdkit.skill.Skill.fit` takes them: the clean
demonstrations (no scene, or an empty one), from which the path, the timing and
the orientation are learned, and the demonstrations around obstacles with their
scenes, from which the reward is learned. It checks what ties the two files
together (every scene names a demonstration of the file, obstacles of the
demonstration's dimension) and what learning needs (at least 2 clean
demonstrations of at least 3 points; orientations for all of them or none),
each refusal one line naming the file and the demonstration.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from lfdkit.io.demos import load_demo_files
from lfdkit.io.scenes import load_scenes
from lfdkit.model.demos import Demo, DemoId
from lfdkit.model.scene import Scene

__all__ = ["TrainingData", "read_training_data"]


class TrainingData(NamedTuple):
    """Demonstrations from files, split by whether they were recorded around obstacles.

    Each demonstration is one :class:`~lfdkit.model.demos.Demo` record (points,
    times, orientations, id, scene); the ``free_*``, ``obstacle_*`` and
    ``scenes`` properties list one field of them, in the file's order, as
    :meth:`lfdkit.skill.Skill.fit` takes them.

    Attributes
    ----------
    clean : list of Demo
        Demonstrations without a scene, or with an empty one: the clean
        demonstrations the generalized path, the timing (from their times)
        and the orientation (from their orientations) are learned from.
    around_obstacles : list of Demo
        Demonstrations whose scene has obstacles: the reward is learned from them.
    """

    clean: list[Demo]
    around_obstacles: list[Demo]

    @property
    def free_demos(self) -> list[np.ndarray]:
        """The clean demonstrations' points, each (n_j, q)."""
        return [demo.points for demo in self.clean]

    @property
    def free_ids(self) -> list[DemoId]:
        """The clean demonstrations' ids."""
        return [demo.id for demo in self.clean]

    @property
    def free_times(self) -> list[np.ndarray | None]:
        """The clean demonstrations' times in seconds, each (n_j,), None where the file has none."""
        return [demo.times for demo in self.clean]

    @property
    def free_orientations(self) -> list[np.ndarray | None]:
        """The clean demonstrations' unit quaternions, each (n_j, 4), None where none given."""
        return [demo.orientations for demo in self.clean]

    @property
    def obstacle_demos(self) -> list[np.ndarray]:
        """The points of the demonstrations around obstacles, each (n_j, q)."""
        return [demo.points for demo in self.around_obstacles]

    @property
    def obstacle_ids(self) -> list[DemoId]:
        """The ids of the demonstrations around obstacles."""
        return [demo.id for demo in self.around_obstacles]

    @property
    def scenes(self) -> list[Scene]:
        """One scene per demonstration around obstacles."""
        return [demo.scene for demo in self.around_obstacles]


def read_training_data(
    demos_path: str | os.PathLike[str] | Sequence[str | os.PathLike[str]],
    scenes_path: str | os.PathLike[str] | None = None,
) -> TrainingData:
    """Read a demonstrations file and, optionally, the scene file of the obstacle demonstrations.

    Parameters
    ----------
    demos_path : path or sequence of paths
        Demonstrations, ``.csv``, ``.npz`` or ``.json`` (:func:`lfdkit.io.load_demos`);
        several files are one set (:func:`lfdkit.io.demos.load_demo_files`: a CSV
        without a ``demo`` column is one demonstration named by its file's stem).
    scenes_path : path, optional
        Scenes by demonstration id, ``.csv`` or ``.json``
        (:func:`lfdkit.io.load_scenes`). A demonstration it does not
        list, or lists with no obstacle, is a clean demonstration.

    Raises
    ------
    ValueError
        If a file is malformed (the message names the file, line and field),
        demonstrations mix dimensions, or the scene file names a
        demonstration id that the demonstrations file does not have.
    """
    records = load_demo_files(
        [demos_path] if isinstance(demos_path, (str, os.PathLike)) else demos_path
    )
    demos, ids = [demo.points for demo in records], [demo.id for demo in records]
    if not isinstance(demos_path, (str, os.PathLike)):  # named in errors: the first file
        demos_path = demos_path[0] if len(demos_path) == 1 else ", ".join(map(str, demos_path))
    dims = {demo.shape[1] for demo in demos}
    if len(dims) > 1:
        first = demos[0].shape[1]
        j = next(j for j, demo in enumerate(demos) if demo.shape[1] != first)
        raise ValueError(
            f"{os.fspath(demos_path)}: demonstration {ids[j]!r} is {demos[j].shape[1]}-D, "
            f"but {ids[0]!r} is {first}-D; all demonstrations must share their dimension"
        )
    scenes = {} if scenes_path is None else load_scenes(scenes_path)
    known = set(ids)
    stray = [key for key in scenes if key not in known]
    if stray:
        raise ValueError(
            f"{os.fspath(scenes_path)}: demo {stray[0]!r} is not in {os.fspath(demos_path)} "
            f"(its ids: {', '.join(map(str, ids[:5]))}{', ...' if len(ids) > 5 else ''})"
        )
    short = [(key, len(demo)) for demo, key in zip(demos, ids, strict=True) if len(demo) < 3]
    if short:
        raise ValueError(
            f"{os.fspath(demos_path)}: demonstration {short[0][0]!r} has {short[0][1]} "
            "points; a path needs at least 3"
        )
    data = TrainingData([], [])
    for read in records:
        demo, key = read.points, read.id
        scene = scenes.get(key)
        record = dataclasses.replace(read, scene=scene)
        if scene is None or not len(scene):
            data.clean.append(record)
        else:
            if scene.positions.shape[1] != demo.shape[1]:
                raise ValueError(
                    f"{os.fspath(scenes_path)}: demo {key!r}: {scene.positions.shape[1]}-D "
                    f"obstacles for a {demo.shape[1]}-D demonstration"
                )
            if scene.moving:  # named by its file and demo (Skill.fit_reward says why)
                i = next(i for i, o in enumerate(scene) if o.moving)
                raise ValueError(
                    f"{os.fspath(scenes_path)}: demo {key!r}: obstacle {i} "
                    f"({scene.labels[i]!r}) moves; the reward is learned from standing "
                    "obstacles only: give where it stood during the demonstration"
                )
            data.around_obstacles.append(record)
    if len(data.clean) < 2:
        raise ValueError(
            f"{os.fspath(demos_path)}: needs at least 2 demonstrations without obstacles to "
            f"learn the path from, found {len(data.clean)}"
        )
    given = [demo.orientations is not None for demo in data.clean]
    if any(given) and not all(given):
        missing = data.clean[given.index(False)].id
        raise ValueError(
            f"{os.fspath(demos_path)}: demonstration {missing!r} has no orientation (qx, qy, "
            "qz, qw) but others have; give them for all clean demonstrations or none"
        )
    return data
