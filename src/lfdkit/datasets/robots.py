"""Examples for running a skill on a robot: a timed 3-D reach and three arms' URDFs.

The README's "Your robot" section runs a 3-D skill on arms described by URDF
files. A new user has neither, so lfdkit ships both, reachable by one command
(``lfdkit datasets export reach -o reach.csv``, ``lfdkit datasets export
urdf:panda -o panda.urdf``) and nothing is downloaded:

* :func:`reach_demos`: six timed demonstrations of a reach over a box, in
  metres, in front of a robot's base: x about 0.45 m, y from -0.3 to 0.3 m, up
  from 0.15 m to about 0.37 m and down again, each about 6 s (±5 %) with a
  minimum-jerk-like ``(1 - cos)/2`` progress, 1 cm of spread in height and
  depth. Every pose is within reach of the UR5 (0.85 m), the UR5e and the
  Panda, and 6 s keeps every arm within its joint limits at half speed.
* :data:`EXAMPLE_URDFS`: kinematic chains only (no meshes or inertias), written
  from the makers' published DH tables with their position and speed limits;
  the Panda's hand has two fingers, so its tip link must be named
  (``panda_hand_tcp``). :func:`example_urdf` gives a file's path,
  :func:`export_urdf` copies one (atomically, never over a file unless asked).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from lfdkit.core.rotations import exp, multiply
from lfdkit.core.validation import check_positive, check_random_state
from lfdkit.datasets._shared import check_count_at_least
from lfdkit.io import atomic_write, check_output_path

__all__ = [
    "DUSTPAN_DURATION",
    "EXAMPLE_URDFS",
    "URDF_PREFIX",
    "WIPE_PERIOD",
    "dustpan_demos",
    "dustpan_sweep",
    "example_urdf",
    "export_urdf",
    "reach_demos",
    "wipe_demo",
]

#: Names of the example arms in the catalogue: ``urdf:panda``, ``urdf:ur5``, ``urdf:ur5e``.
URDF_PREFIX = "urdf:"

#: The shipped URDFs: name -> (joints, tip link to name or None, what it is).
EXAMPLE_URDFS: dict[str, tuple[int, str | None, str]] = {
    "panda": (
        7,
        "panda_hand_tcp",
        "Franka Emika Panda, kinematic chain (--tip-link panda_hand_tcp)",
    ),
    "ur5": (6, None, "Universal Robots UR5 from its DH table, kinematic chain"),
    "ur5e": (6, None, "Universal Robots UR5e from its DH table, kinematic chain"),
}

_URDF_FOLDER = Path(__file__).parent / "urdf"


def example_urdf(name: str) -> Path:
    """The path of a shipped example URDF (``"panda"``, ``"ur5"``, ``"ur5e"``).

    ``name`` may carry the ``urdf:`` prefix and the ``.urdf`` suffix, in any case.

    Raises
    ------
    ValueError
        If there is no such example; the message starts with ``name:`` and lists them.
    """
    if not isinstance(name, str):
        raise ValueError(f"name: expected an example arm's name, got {type(name).__name__}")
    key = name.casefold().removeprefix(URDF_PREFIX).removesuffix(".urdf")
    if key not in EXAMPLE_URDFS:
        raise ValueError(
            f"name: no example URDF {name!r}; choose from "
            + ", ".join(URDF_PREFIX + known for known in EXAMPLE_URDFS)
        )
    return _URDF_FOLDER / f"{key}.urdf"


def export_urdf(name: str, path: str | os.PathLike[str], *, overwrite: bool = False) -> Path:
    """Copy a shipped example URDF to ``path``, atomically, over a file only with ``overwrite``.

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    ValueError
        If ``name`` is not an example (:func:`example_urdf`).
    FileExistsError
        If ``path`` exists and ``overwrite`` is false.
    """
    text = example_urdf(name).read_text(encoding="utf-8")
    check_output_path(os.fspath(path), overwrite=overwrite)
    return atomic_write(path, lambda handle: handle.write(text), overwrite=overwrite)


def reach_demos(
    n_demos: int = 6, *, seed: object = 0, n_points: int = 120
) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Timed demonstrations of a 3-D reach over a box, in metres and seconds.

    Parameters
    ----------
    n_demos : int
        Number of demonstrations (at least 1).
    seed : None, int or numpy.random.Generator
        Their random durations, heights and depths.
    n_points : int
        Samples per demonstration (at least 10), evenly spaced in time.

    Returns
    -------
    demos : list of ndarray, each (n_points, 3)
        Positions ``x, y, z`` (m) in the robot's base frame.
    times : list of ndarray, each (n_points,)
        Sample times from 0 (s), each demonstration lasting about 6 s.
    """
    n_demos = check_count_at_least(n_demos, "n_demos")
    n_points = check_count_at_least(n_points, "n_points", 10)
    rng = check_random_state(seed)
    demos, times = [], []
    for _ in range(n_demos):
        duration = 6.0 * (1.0 + 0.05 * rng.standard_normal())
        t = np.linspace(0.0, duration, n_points)
        progress = 0.5 - 0.5 * np.cos(np.pi * t / duration)
        height = 0.22 + 0.01 * rng.standard_normal()
        depth = 0.45 + 0.01 * rng.standard_normal()
        demos.append(
            np.column_stack(
                [
                    np.full_like(t, depth),
                    -0.3 + 0.6 * progress,
                    0.15 + height * np.sin(np.pi * progress),
                ]
            )
        )
        times.append(t)
    return demos, times


#: Seconds per cycle of the ``wipe`` recording.
WIPE_PERIOD = 1.6


def wipe_demo(
    *, seed: object = 0, cycles: float = 4.3, n_points: int = 480
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One recording of a periodic wipe on a table, with the tool's orientation (issue 33).

    A 4 × 12 cm figure-eight at 0.45 m in front of the base, 0.1 m above it,
    :data:`WIPE_PERIOD` s a cycle, the tool pointing down (180° about x) and
    rocking ±9.2° about x and ±5.7° about y; 1 mm and 5 mrad of noise. The
    UR5 follows it (``tests/execute/test_rhythmic_wipe.py``).

    Parameters
    ----------
    seed : None, int or numpy.random.Generator
        The noise.
    cycles : float
        Cycles recorded (> 0; at least 1.5 to learn from).
    n_points : int
        Samples, evenly spaced in time (at least 10).

    Returns
    -------
    positions : ndarray, shape (n_points, 3)
        ``x, y, z`` (m) in the robot's base frame.
    times : ndarray, shape (n_points,)
        Seconds from 0.
    orientations : ndarray, shape (n_points, 4)
        Unit quaternions ``[x, y, z, w]``.
    """
    cycles = check_positive(cycles, "cycles")
    n_points = check_count_at_least(n_points, "n_points", 10)
    rng = check_random_state(seed)
    t = np.linspace(0.0, cycles * WIPE_PERIOD, n_points)
    u = 2.0 * np.pi * t / WIPE_PERIOD
    positions = np.c_[0.45 + 0.02 * np.sin(2 * u), 0.06 * np.sin(u), np.full_like(u, 0.1)]
    rock = np.outer(0.08 * np.sin(u), [1.0, 0.0, 0.0]) + np.outer(
        0.05 * np.sin(2 * u + 0.3), [0.0, 1.0, 0.0]
    )
    down = np.array([1.0, 0.0, 0.0, 0.0])
    orientations = multiply(exp(rock), down)
    positions = positions + rng.normal(0.0, 1e-3, positions.shape)
    orientations = multiply(orientations, exp(rng.normal(0.0, 2.5e-3, (n_points, 3))))
    return positions, t, orientations


#: Seconds of each sweep of the ``dustpan`` set.
DUSTPAN_DURATION = 1.5


def dustpan_sweep(start: np.ndarray, pan: np.ndarray, n_points: int = 100) -> np.ndarray:
    """The noise-free sweep from a brush's start pose into a dustpan's, shape (n_points, 2), m.

    The known answer of the ``dustpan`` set: leaving the start along its
    axis (0.4 m with a 8 cm bow) blended, by a smoothstep of the phase, into
    arriving along the pan's axis (from 0.4 m behind it with a 5 cm bow),
    each shape fixed in its own frame. Poses ``[x, y, angle]`` (m, rad).
    """
    t = np.linspace(0.0, 1.0, n_points)
    leave = np.c_[0.4 * t, 0.08 * np.sin(np.pi * t)]
    arrive = np.c_[-0.4 * (1.0 - t), 0.05 * np.sin(np.pi * (1.0 - t))]

    def world(pose: np.ndarray, local: np.ndarray) -> np.ndarray:
        c, s = np.cos(pose[2]), np.sin(pose[2])
        return local @ np.array([[c, s], [-s, c]]) + pose[:2]

    blend = (t * t * (3.0 - 2.0 * t))[:, None]
    return (1.0 - blend) * world(start, leave) + blend * world(pan, arrive)


def dustpan_demos(
    *, seed: object = 0, n_demos: int = 8, n_points: int = 100
) -> tuple[list[np.ndarray], list[np.ndarray], list[dict[str, np.ndarray]]]:
    """Sweeps into a dustpan moved and turned, with both task frames' poses (issue 33).

    A table task in front of an arm (within a UR5's reach): the brush starts
    near (0.2, -0.25) m turned up to ±0.3 rad, the dustpan stands about
    0.43 m ahead turned up to ±1 rad and moved up to ±8 cm; each sweep is :func:`dustpan_sweep` with
    a smooth 3 mm wiggle and 0.5 mm of noise, :data:`DUSTPAN_DURATION` s long.
    What ``lfdkit learn --task-frames`` learns from (``frame_start_*`` and
    ``frame_pan_*`` columns).

    Returns
    -------
    demos : list of ndarray, each (n_points, 2)
        Positions, m.
    times : list of ndarray, each (n_points,)
        Seconds from 0.
    frames : list of dict
        Each sweep's ``{"start": [x, y, angle], "pan": [x, y, angle]}`` (m, rad).
    """
    n_demos = check_count_at_least(n_demos, "n_demos", 1)
    n_points = check_count_at_least(n_points, "n_points", 10)
    rng = check_random_state(seed)
    t = np.linspace(0.0, 1.0, n_points)
    demos, times, frames = [], [], []
    for _ in range(n_demos):
        start = np.r_[np.array([0.2, -0.25]) + rng.uniform(-0.05, 0.05, 2), rng.uniform(-0.3, 0.3)]
        ahead = start[:2] + np.array([0.4, 0.15]) + rng.uniform(-0.08, 0.08, 2)
        pan = np.r_[ahead, rng.uniform(-1.0, 1.0)]
        wiggle = sum(
            0.003
            * rng.normal(size=2)
            * np.sin((k + 1) * np.pi * t + rng.uniform(0.0, 6.0))[:, None]
            for k in range(3)
        )
        demos.append(
            dustpan_sweep(start, pan, n_points) + wiggle + rng.normal(0, 5e-4, (n_points, 2))
        )
        times.append(DUSTPAN_DURATION * t)
        frames.append({"start": start, "pan": pan})
    return demos, times, frames
