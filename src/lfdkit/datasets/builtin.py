"""Every built-in data set in one list, and any of them written as files ``lfdkit learn`` reads.

:func:`catalog` lists the data sets one :class:`DatasetInfo` each, without
generating them: the synthetic mimicking sets (:data:`MIMIC_DATASETS`, known
ground-truth path), the closed handwriting shapes (:data:`CLOSED_DATASETS`),
the emulation sets (:data:`EMULATION_DATASETS`, demonstrations around
obstacles by a demonstrator whose reward is known) and, when the optional
package is installed (:func:`lasa_available`), the 30 LASA handwriting shapes
as ``lasa:NAME``; then the timed 3-D reach for running a skill on a robot
(``reach``, :func:`lfdkit.datasets.robots.reach_demos`). Dimensions, counts and
units are those of the generators' defaults (a test generates each and
compares). The example arms' URDFs (``urdf:panda``, ``urdf:ur5``,
``urdf:ur5e``, :data:`lfdkit.datasets.robots.EXAMPLE_URDFS`) are not data sets
of demonstrations, so not in the catalogue, but :func:`export_dataset` writes
them too.

:func:`export_dataset` writes one as a demonstrations file (CSV, NPZ or JSON,
:func:`lfdkit.io.save_demos`) and, for an emulation set, a scene file
(:func:`lfdkit.io.save_scenes`), atomically and never over an existing file
unless ``overwrite``; :func:`dataset_demos` gives the arrays it writes. The
command ``lfdkit datasets`` is these two functions.

What an export holds
--------------------
* A mimicking or closed set: its demonstrations, ids ``0, 1, ...``.
* An emulation set: its clean demonstrations (``free-1``, ``free-2``, ...;
  :attr:`EmulationSet.free_demos`) and, when a scene file is asked for, every
  demonstration around obstacles after them (``cup-1``, ``marker-1``, ... by
  the class of its obstacle, in the set's order, training and test alike),
  with their obstacles in the scene file. Without a scene file only the clean
  ones are written: a demonstration around an obstacle that no scene file
  lists would be learned from as a clean one.
* A LASA shape: its 7 demonstrations with their times (a ``t`` column).
* ``reach``: its 6 demonstrations with their times (a ``t`` column).
* ``wipe``: one recording of 4.3 cycles with its times and the tool's
  orientation (``t`` and ``qx,qy,qz,qw`` columns), for ``lfdkit learn --periodic``.
* ``dustpan``: 8 timed sweeps into a dustpan moved and turned, with the
  brush's start pose and the pan's (``frame_start_*`` and ``frame_pan_*``
  columns), for ``lfdkit learn --task-frames``.
* ``urdf:NAME``: the arm's URDF, as shipped.

Generated sets depend on ``seed`` (0 by default, so an export is
reproducible); LASA shapes are recorded data and take none.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Literal

import numpy as np

from lfdkit.datasets.emulation import EMULATION_DATASETS, load_emulation_dataset
from lfdkit.datasets.lasa import LASA_SHAPES, lasa_available, load_lasa
from lfdkit.datasets.robots import (
    URDF_PREFIX,
    dustpan_demos,
    export_urdf,
    reach_demos,
    wipe_demo,
)
from lfdkit.datasets.synthetic import CLOSED_DATASETS, MIMIC_DATASETS, load_dataset
from lfdkit.io import check_output_path, save_demos, save_scenes
from lfdkit.model.demos import DemoId
from lfdkit.model.scene import Scene

__all__ = [
    "LASA_PREFIX",
    "DatasetDemos",
    "DatasetInfo",
    "catalog",
    "dataset_demos",
    "dataset_info",
    "export_dataset",
]

#: Names of the LASA shapes in the catalogue: ``lasa:Angle``, ``lasa:BendedLine``, ...
LASA_PREFIX = "lasa:"

DatasetKind = Literal["mimic", "closed", "emulation", "lasa", "robot"]


@dataclass(frozen=True)
class DatasetInfo:
    """One line of the catalogue: what a built-in data set is.

    Attributes
    ----------
    name : str
        What :func:`export_dataset` and ``lfdkit datasets export`` take
        (``"walking"``, ``"sweeping"``, ``"lasa:Angle"``).
    kind : {"mimic", "closed", "emulation", "lasa", "robot"}
        A mimicking set with a known ground-truth path, a closed handwriting
        shape, an emulation set (demonstrations around obstacles, known true
        reward), a LASA shape (recorded by a person) or a timed 3-D motion
        for running a skill on a robot (``reach``).
    n_dims : int
        Dimension of the points, 2 or 3.
    n_demos : int
        Demonstrations without obstacles (all of them, but for an emulation set).
    n_obstacle_demos : int
        Demonstrations recorded around obstacles (emulation sets; 0 otherwise).
    units : str
        Unit of the coordinates (:data:`lfdkit.core.units.UNITS`).
    summary : str
        What it is, in one line.
    """

    name: str
    kind: DatasetKind
    n_dims: int
    n_demos: int
    n_obstacle_demos: int
    units: str
    summary: str


# name: (n_dims, clean demonstrations, demonstrations around obstacles, units, summary)
_BUILT_IN: dict[str, tuple[int, int, int, str, str]] = {
    "quasi_circular": (2, 2, 0, "m", "two bands either side of a quasi-circle (thesis Fig 4.5)"),
    "noisy_band": (2, 10, 0, "m", "smooth offsets and noise about an S-shaped path"),
    "deburring_linear": (2, 10, 0, "mm", "deburring a straight edge, burr residuals (§6.2)"),
    "deburring_circular": (2, 10, 0, "mm", "deburring a half-circle edge, burr residuals (§6.2)"),
    "walking": (2, 30, 0, "m", "walking along a corridor and through a door (thesis Fig 4.7)"),
    "da_vinci": (3, 4, 0, "m", "pick and place between two walls, 3-D (thesis Fig 4.10)"),
    "different_extents": (2, 10, 0, "m", "S-shaped band, each starting and stopping elsewhere"),
    "local_detours": (2, 10, 0, "m", "S-shaped band, two demonstrations swerve once"),
    "uneven_sampling": (2, 10, 0, "m", "S-shaped band, 60-160 points at uneven speeds"),
    "loops": (2, 10, 0, "m", "S-shaped band, two demonstrations loop once"),
    "closed_circle": (2, 7, 0, "mm", "a circle drawn once, ending where it starts"),
    "nearly_closed_o": (2, 7, 0, "mm", "a handwritten 'o' stopping short of its start"),
    "figure_eight": (2, 7, 0, "mm", "a figure-eight drawn once, crossing itself"),
    "letter_a": (2, 7, 0, "mm", "a handwritten 'a': a bowl, a turn and a down-stroke"),
    "artificial": (2, 5, 8, "m", "an S path around one obstacle a scene (thesis §5.5)"),
    "da_vinci_marker": (3, 5, 12, "m", "pick and place around a marker, 3-D (thesis §6.3)"),
    "sweeping": (2, 5, 12, "m", "sweeps around a cup or a marker (thesis §6.4)"),
    "reach": (3, 6, 0, "m", "a timed 3-D reach over a box (6 s), for lfdkit execute"),
    "wipe": (3, 1, 0, "m", "4.3 cycles of a wipe with a rocking tool, for --periodic"),
    "dustpan": (2, 8, 0, "m", "sweeps into a dustpan moved and turned, for --task-frames"),
}
#: The timed motions for a robot (kind ``robot``), listed after the LASA shapes.
_ROBOT_SETS = ("reach", "wipe", "dustpan")


def _kind(name: str) -> DatasetKind:
    if name in _ROBOT_SETS:
        return "robot"
    if name in EMULATION_DATASETS:
        return "emulation"
    return "closed" if name in CLOSED_DATASETS else "mimic"


def catalog(*, lasa: bool | None = None) -> list[DatasetInfo]:
    """The built-in data sets, one :class:`DatasetInfo` each, in a stable order.

    Parameters
    ----------
    lasa : bool, optional
        Whether to list the 30 LASA shapes (``lasa:NAME``); by default when
        their package is installed (:func:`lasa_available`).

    Returns
    -------
    list of DatasetInfo
        The mimicking sets, the closed shapes, the emulation sets, the LASA
        shapes, then the robot motions. Nothing is generated or read.
    """
    names = [*MIMIC_DATASETS, *CLOSED_DATASETS, *EMULATION_DATASETS]
    entries = [DatasetInfo(name, _kind(name), *_BUILT_IN[name]) for name in names]
    if lasa_available() if lasa is None else lasa:
        entries += [
            DatasetInfo(
                f"{LASA_PREFIX}{shape}",
                "lasa",
                2,
                7,
                0,
                "mm",
                "LASA handwriting shape, drawn by a person (with times)",
            )
            for shape in LASA_SHAPES
        ]
    return entries + [DatasetInfo(name, "robot", *_BUILT_IN[name]) for name in _ROBOT_SETS]


def dataset_info(name: str) -> DatasetInfo:
    """The catalogue entry of ``name`` (a LASA shape's whether or not its package is installed).

    ``lasa:NAME`` is matched case-insensitively, like :func:`load_lasa`.

    Raises
    ------
    ValueError
        If there is no data set ``name``; the message starts with ``name:``
        and lists the names.
    """
    if not isinstance(name, str):
        raise ValueError(f"name: expected a data set name, got {type(name).__name__}")
    if name.casefold().startswith(LASA_PREFIX):
        shape = name[len(LASA_PREFIX) :].casefold()
        for entry in catalog(lasa=True):
            if entry.kind == "lasa" and entry.name[len(LASA_PREFIX) :].casefold() == shape:
                return entry
        raise ValueError(
            f"name: unknown LASA shape {name!r}; choose from "
            + ", ".join(f"{LASA_PREFIX}{s}" for s in LASA_SHAPES)
        )
    if name in _BUILT_IN:
        return next(entry for entry in catalog(lasa=False) if entry.name == name)
    raise ValueError(
        f"name: unknown data set {name!r}; choose from {', '.join(_BUILT_IN)} "
        f"or {LASA_PREFIX}SHAPE (a LASA shape)"
        + (f"; {name} is an example arm: export it to a file" if _is_urdf(name) else "")
    )


@dataclass(frozen=True, eq=False)
class DatasetDemos:
    """What :func:`export_dataset` writes: demonstrations, ids, times and scenes.

    Attributes
    ----------
    info : DatasetInfo
        The data set's catalogue entry.
    demos : list of ndarray, each (n_j, q)
        The demonstrations, float64, in ``info.units``.
    ids : list of int or str
        Their ids, unique.
    times : list of ndarray, each (n_j,), or None
        Sample times in seconds (LASA shapes), else None.
    scenes : dict of id to Scene
        The obstacles of the demonstrations recorded around them, by id
        (empty when there are none or they were not asked for).
    orientations : list of ndarray, each (n_j, 4), or None
        The tool's orientation (``wipe``), else None.
    frames : list of dict, or None
        Each demonstration's task frames' poses by name (``dustpan``:
        :attr:`lfdkit.model.demos.Demo.frames`), else None.
    """

    info: DatasetInfo
    demos: list[np.ndarray]
    ids: list[DemoId]
    times: list[np.ndarray] | None
    scenes: dict[DemoId, Scene]
    orientations: list[np.ndarray] | None = None
    frames: list[dict[str, np.ndarray]] | None = None


def dataset_demos(name: str, *, seed: int = 0, obstacles: bool = True) -> DatasetDemos:
    """The demonstrations (and scenes) of a built-in data set, as :func:`export_dataset` writes.

    Parameters
    ----------
    name : str
        A catalogue name (:func:`catalog`).
    seed : int
        Seed of a generated set (ignored for LASA shapes, which are recorded).
    obstacles : bool
        Emulation sets: also the demonstrations around obstacles and their
        scenes (after the clean ones); otherwise the clean ones only.

    Returns
    -------
    DatasetDemos

    Raises
    ------
    ValueError
        If ``name`` is unknown (the message lists the names).
    ModuleNotFoundError
        For a LASA shape when its package is not installed.
    """
    info = dataset_info(name)
    if info.kind == "lasa":
        shape = load_lasa(info.name[len(LASA_PREFIX) :])
        demos = [np.array(d) for d in shape.demos]
        return DatasetDemos(info, demos, list(range(len(demos))), list(shape.times), {})
    if info.name == "wipe":
        positions, t, orientations = wipe_demo(seed=seed)
        return DatasetDemos(info, [positions], [0], [t], {}, [orientations])
    if info.name == "dustpan":
        demos, times, frames = dustpan_demos(seed=seed)
        return DatasetDemos(info, demos, list(range(len(demos))), times, {}, frames=frames)
    if info.kind == "robot":
        demos, times = reach_demos(seed=seed)
        return DatasetDemos(info, demos, list(range(len(demos))), times, {})
    if info.kind != "emulation":
        data = load_dataset(info.name, seed=seed)
        return DatasetDemos(info, list(data.demos), list(range(data.n_demos)), None, {})
    data = load_emulation_dataset(info.name, seed=seed)
    demos = list(data.free_demos)
    ids: list[DemoId] = [f"free-{j + 1}" for j in range(len(demos))]
    scenes: dict[DemoId, Scene] = {}
    if obstacles:
        counts: dict[str, int] = {}
        for demo, scene in zip(data.demos, data.scenes, strict=True):
            label = scene.labels[0] if len(scene) else "obstacle"
            counts[label] = counts.get(label, 0) + 1
            key = f"{label}-{counts[label]}"
            demos.append(demo)
            ids.append(key)
            scenes[key] = scene
    return DatasetDemos(info, demos, ids, None, scenes)


def export_dataset(
    name: str,
    demos_path: str | os.PathLike[str],
    *,
    scenes_path: str | os.PathLike[str] | None = None,
    seed: int = 0,
    overwrite: bool = False,
) -> DatasetDemos | None:
    """Write a built-in data set as a demonstrations file (and a scene file).

    Parameters
    ----------
    name : str
        A catalogue name (:func:`catalog`).
    demos_path : path
        The demonstrations file, ``.csv``, ``.npz`` or ``.json``
        (:func:`lfdkit.io.save_demos`); for an example arm (``urdf:NAME``)
        its URDF file.
    scenes_path : path, optional
        Emulation sets only: the scene file (``.csv`` or ``.json``) of the
        demonstrations around obstacles, which are then written too.
    seed : int
        Seed of a generated set (ignored for LASA shapes).
    overwrite : bool
        Replace existing files; otherwise an existing file is left as it is
        and nothing is written.

    Returns
    -------
    DatasetDemos or None
        What was written (:func:`dataset_demos`); None for an example arm.

    Raises
    ------
    ValueError
        If ``name`` is unknown, or ``scenes_path`` is given for a data set
        without obstacles.
    FileExistsError
        If a file exists and ``overwrite`` is false (checked before writing).
    """
    if _is_urdf(name):
        if scenes_path is not None:
            raise ValueError(f"scenes_path: {name} is an example arm's URDF; it has no scenes")
        export_urdf(name, demos_path, overwrite=overwrite)
        return None
    info = dataset_info(name)
    if scenes_path is not None and info.kind != "emulation":
        raise ValueError(
            f"scenes_path: {info.name} has no obstacles; only emulation sets "
            f"({', '.join(EMULATION_DATASETS)}) have scenes"
        )
    # Both outputs checked before either is written.
    for path in (demos_path, scenes_path):
        if path is not None:
            check_output_path(os.fspath(path), overwrite=overwrite)
    data = dataset_demos(info.name, seed=seed, obstacles=scenes_path is not None)
    save_demos(
        demos_path,
        data.demos,
        times=data.times,
        ids=data.ids,
        orientations=data.orientations,
        frames=data.frames,
        overwrite=overwrite,
    )
    if scenes_path is not None:
        save_scenes(scenes_path, data.scenes, overwrite=overwrite)
    return data


def _is_urdf(name: object) -> bool:
    return isinstance(name, str) and name.casefold().startswith(URDF_PREFIX)
