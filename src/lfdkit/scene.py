"""Scenes: obstacles with a class label and a position (2-D or 3-D).

The data model of an environment, shared by emulation, the robot
simulation, the metrics and the plots. A :class:`Scene` holds the obstacles
of one environment; each :class:`Obstacle` has a class label, a centre of
shape ``(q,)`` with ``q`` 2 or 3, and a radius, both in the units of the
paths (metres for robot data). Both are immutable and validate on
construction: a non-empty label, a finite 2-D or 3-D centre, a finite
radius ``>= 0``, and one dimension for all the obstacles of a scene.

Scene files (the scenes of several demonstrations keyed by demonstration
id) are read and written by :mod:`lfdkit.io.scenes`.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["Obstacle", "Scene"]


@dataclass(frozen=True, eq=False)
class Obstacle:
    """One obstacle: a class label (e.g. ``"cup"``) and a position.

    Attributes
    ----------
    label : str
        Obstacle class; the reward has one Gaussian term per class.
    position : ndarray, shape (q,)
        Centre, in the units of the paths.
    radius : float
        Physical radius (units of the paths) for collision and clearance checks;
        the reward does not use it (the learned precision sets the response).
    """

    label: str
    position: np.ndarray
    radius: float = 0.0

    def __post_init__(self) -> None:
        if not isinstance(self.label, str) or not self.label:
            raise ValueError(f"label: expected a non-empty string, got {self.label!r}")
        position = np.asarray(self.position, dtype=np.float64)
        if position.ndim != 1 or position.size not in (2, 3):
            raise ValueError(
                f"position: expected a 2-D or 3-D point, got shape {np.shape(self.position)}"
            )
        if not np.all(np.isfinite(position)):
            raise ValueError(f"position: contains NaN or infinite values ({self.label!r})")
        position.setflags(write=False)
        object.__setattr__(self, "position", position)
        radius = float(self.radius)
        if not np.isfinite(radius) or radius < 0:
            raise ValueError(f"radius: must be finite and >= 0, got {self.radius!r}")
        object.__setattr__(self, "radius", radius)


@dataclass(frozen=True, eq=False)
class Scene:
    """The obstacles of one environment.

    Attributes
    ----------
    obstacles : tuple of Obstacle
        May be empty (a free scene).
    """

    obstacles: tuple[Obstacle, ...] = ()

    def __post_init__(self) -> None:
        obstacles = tuple(self.obstacles)
        for i, obstacle in enumerate(obstacles):
            if not isinstance(obstacle, Obstacle):
                raise TypeError(f"obstacles[{i}]: expected an Obstacle, got {type(obstacle)}")
        dims = {o.position.size for o in obstacles}
        if len(dims) > 1:
            raise ValueError("obstacles: mixed 2-D and 3-D positions in one scene")
        object.__setattr__(self, "obstacles", obstacles)

    @classmethod
    def from_arrays(
        cls, labels: Sequence[str], positions: Any, radii: Sequence[float] | None = None
    ) -> Scene:
        """Build a scene from parallel lists of labels, positions ``(n, q)`` and radii."""
        positions = np.asarray(positions, dtype=np.float64)
        if positions.ndim != 2 or positions.shape[0] != len(labels):
            raise ValueError(
                f"positions: expected shape ({len(labels)}, q) to match labels, "
                f"got {positions.shape}"
            )
        radii = [0.0] * len(labels) if radii is None else list(radii)
        if len(radii) != len(labels):
            raise ValueError(f"radii: expected {len(labels)} values, got {len(radii)}")
        return cls(
            tuple(
                Obstacle(lab, pos, rad)
                for lab, pos, rad in zip(labels, positions, radii, strict=True)
            )
        )

    @property
    def positions(self) -> np.ndarray:
        """Obstacle centres, shape (n_obstacles, q); (0, 0) for an empty scene."""
        if not self.obstacles:
            return np.zeros((0, 0))
        return np.array([o.position for o in self.obstacles])

    @property
    def radii(self) -> np.ndarray:
        """Physical radius of each obstacle, shape (n_obstacles,)."""
        return np.array([o.radius for o in self.obstacles], dtype=np.float64)

    @property
    def labels(self) -> tuple[str, ...]:
        """Class label of each obstacle."""
        return tuple(o.label for o in self.obstacles)

    @property
    def classes(self) -> tuple[str, ...]:
        """Distinct class labels, in order of first appearance."""
        return tuple(dict.fromkeys(self.labels))

    def __len__(self) -> int:
        return len(self.obstacles)

    def __iter__(self):
        return iter(self.obstacles)

    def mirrored(self, axis: int = 1) -> Scene:
        """The scene reflected in coordinate ``axis`` (for symmetry checks)."""
        flip = np.ones(self.positions.shape[1] if self.obstacles else 1)
        flip[axis] = -1.0
        return Scene(tuple(Obstacle(o.label, o.position * flip, o.radius) for o in self.obstacles))

    def with_obstacles(self, obstacles: Iterable[Obstacle]) -> Scene:
        """A new scene with more obstacles."""
        return Scene((*self.obstacles, *obstacles))
