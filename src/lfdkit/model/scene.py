"""Scenes: obstacles with a class label and a position (2-D or 3-D).

The data model of an environment, shared by emulation, the robot
simulation, the metrics and the plots. A :class:`Scene` holds the obstacles
of one environment; each :class:`Obstacle` has a class label, a centre of
shape ``(q,)`` with ``q`` 2 or 3, and a radius, both in the units of the
paths (metres for robot data). Both are immutable and validate on
construction: a non-empty label, a finite 2-D or 3-D centre, a finite
radius ``>= 0``, and one dimension for all the obstacles of a scene.

Obstacle shapes
---------------
:class:`Obstacle` is the round obstacle (a disc, a ball, a standing
cylinder seen from above) and the contract every shape implements;
:class:`Capsule` (a rod) is a second shape, :class:`lfdkit.model.box.Box` (an
oriented box, in :mod:`lfdkit.model.box`) a third and
:class:`lfdkit.model.half_space.HalfSpace` (a table top, a floor, a wall) a
fourth. Every layer uses an obstacle only through the contract, so a new
shape is one subclass plus :func:`register_shape`:

========================  ====================================================
method                    used by
========================  ====================================================
``anchors()``             the reward (its class's Gaussian at each anchor), the
                          planner and the IOC
``balls()``               the planner's hard clearance (their union contains
                          the obstacle)
``has_extent``            whether it is a hard barrier at clearance 0 (volume)
``distance(path)``        clearance and collision metrics, the planner's
                          final check and its refusal of a start inside
``surface_gap(other)``    the gap between two obstacles (the safety floor's
                          open gaps, :mod:`lfdkit.emulate.gaps`); by default
                          through ``balls()``, ``extreme_point`` for a half-space
``outline()``, ``bounds()``  the plots
``fields()``/``from_fields``  scene files (:mod:`lfdkit.io.scenes`)
``solid(height)``         the MuJoCo simulation (a geom standing on the table)
``scaled``/``mirrored``   the IOC's normalisation, symmetry checks
========================  ====================================================

Moving obstacles
----------------
An obstacle may carry a :class:`lfdkit.model.motion.Motion` (``motion=``, keyword
only): a known velocity, a trajectory, or noisy observations with a tracker.
Its ``position`` is then where it is at ``t = 0`` (the plan's start),
:meth:`Obstacle.predict` gives where it will be (mean and covariance) and
:meth:`Obstacle.at` the static obstacle at a time; :attr:`Scene.moving` says
whether anything moves. A static obstacle (``motion=None``, the default) is
exactly as before: same geometry, repr and files.

Scene files (the scenes of several demonstrations keyed by demonstration
id) are read and written by :mod:`lfdkit.io.scenes`.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any, ClassVar

import numpy as np

from lfdkit.core.geometry import polyline_distances, segment_polyline_distance
from lfdkit.model.motion import Motion

__all__ = ["OBSTACLE_SHAPES", "Capsule", "Obstacle", "Scene", "register_shape"]


@dataclass(frozen=True, eq=False)
class Obstacle:
    """A round obstacle: a class label (e.g. ``"cup"``), a centre and a radius.

    A disc in 2-D (a vertical cylinder seen from above), a ball in 3-D. It is
    also the *obstacle contract*: every shape is a subclass that overrides
    the geometry methods below, and the reward, the planner, the IOC, the
    metrics, the plots, the scene files and the simulation use only them:

    * :meth:`anchors` — where the class's Gaussian reward term sits (the
      reward of an obstacle is the sum of the term at its anchors);
    * :meth:`balls` — balls whose union contains the obstacle: the planner's
      hard clearance keeps out of each of them;
    * :meth:`distance` — exact distance from a path to the surface;
    * :meth:`surface_gap` — the gap to another obstacle (by default through
      both ball covers; :meth:`extreme_point` for the gap to a half-space);
    * :meth:`outline` — the top view, for plots; :meth:`fields` and
      :meth:`from_fields` — the shape's extra file fields;
    * :meth:`scaled` and :meth:`mirrored` — the same shape transformed.

    A new shape registers its class with :func:`register_shape` under its
    :attr:`shape` name, which scene files give in their ``shape`` field.

    Attributes
    ----------
    label : str
        Obstacle class; the reward has one Gaussian term per class.
    position : ndarray, shape (q,)
        Centre, in the units of the paths (the reference point of any shape).
    radius : float
        Physical radius (units of the paths) for collision and clearance checks;
        the reward does not use it (the learned precision sets the response).
    motion : lfdkit.model.motion.Motion or None
        How the obstacle moves (keyword only): ``position`` is then where it is
        at ``t = 0`` (the plan's start) and :meth:`predict` where it will be;
        None (the default) for a static obstacle.
    """

    label: str
    position: np.ndarray
    radius: float = 0.0
    motion: Motion | None = field(default=None, kw_only=True, repr=False)

    #: Name of the shape in scene files.
    shape: ClassVar[str] = "round"
    #: Extra fields of the shape in scene files: name → "point" or "number".
    field_kinds: ClassVar[Mapping[str, str]] = {}

    def __post_init__(self) -> None:
        if not isinstance(self.label, str) or not self.label:
            raise ValueError(f"label: expected a non-empty string, got {self.label!r}")
        object.__setattr__(self, "position", _point(self.position, "position", self.label))
        radius = float(self.radius)
        if not np.isfinite(radius) or radius < 0:
            raise ValueError(f"radius: must be finite and >= 0, got {self.radius!r}")
        object.__setattr__(self, "radius", radius)
        if self.motion is not None and not isinstance(self.motion, Motion):
            raise TypeError(
                f"motion: expected an lfdkit.model.motion.Motion, got {type(self.motion).__name__}"
            )
        if self.motion is not None:
            self.predict([0.0])  # a motion of another dimension is refused here

    @property
    def n_dims(self) -> int:
        """Dimension ``q`` of the obstacle's coordinates."""
        return int(self.position.size)

    # ------------------------------------------------------------ motion
    @property
    def moving(self) -> bool:
        """Whether the obstacle has a motion."""
        return self.motion is not None

    def predict(self, times: Any) -> tuple[np.ndarray, np.ndarray]:
        """Where the reference point will be: means (n, q) and covariances (n, q, q).

        A static obstacle stays at its position with zero covariance.
        """
        t = np.asarray(times, dtype=np.float64).reshape(-1)
        if self.motion is None:
            q = self.n_dims
            return np.repeat(self.position[None], t.size, axis=0), np.zeros((t.size, q, q))
        try:
            means, covs = self.motion.predict(self.position, t)
        except ValueError as exc:  # a broadcast of mismatched dimensions
            raise ValueError(f"motion: {exc} ({self.label!r})") from None
        if means.shape[1] != self.n_dims:
            raise ValueError(
                f"motion: predicts {means.shape[1]}-D positions for a {self.n_dims}-D "
                f"obstacle ({self.label!r})"
            )
        return means, covs

    def at(self, t: float) -> Obstacle:
        """The static obstacle where its motion's mean puts it at time ``t`` (s)."""
        if self.motion is None:
            return self
        return self.translated(self.predict([t])[0][0] - self.position)

    def translated(self, shift: Any) -> Obstacle:
        """The static obstacle moved by ``shift`` (q,) (its motion dropped)."""
        return replace(self, position=self.position + np.asarray(shift, float), motion=None)

    # ------------------------------------------------------------ the contract
    @property
    def has_extent(self) -> bool:
        """Whether the obstacle has volume: a hard barrier for the planner even at clearance 0.

        A round obstacle (or a rod) of radius 0 is a point (a segment): it is
        a hard barrier only with a clearance, and otherwise only its reward
        response keeps a plan away. A shape with volume at radius 0 (a box)
        overrides this to answer True.
        """
        return self.radius > 0.0

    def anchors(self) -> np.ndarray:
        """Centres of the class's Gaussian reward term, shape (a, q): the centre."""
        return self.position[None]

    def balls(self) -> tuple[np.ndarray, np.ndarray]:
        """Balls containing the obstacle: centres (k, q) and radii (k,) — itself."""
        return self.position[None], np.array([self.radius])

    def clipped(self, lower: np.ndarray, upper: np.ndarray) -> Obstacle:
        """An obstacle that holds every part of this one lying in the box ``[lower, upper]``.

        The planner covers only this part with :meth:`balls` (points outside
        the box cannot be reached), so a long shape's balls stay small; a
        shape that is small anyway returns itself (the default).
        """
        return self

    def distance(self, path: np.ndarray) -> float:
        """Smallest distance from a polyline ``(n, q)`` to the surface; negative inside."""
        return float(polyline_distances(self.position[None], path)[0]) - self.radius

    def extreme_point(self, direction: np.ndarray) -> np.ndarray:
        """The obstacle's point farthest along ``direction`` (q,), shape (q,).

        Exact for a round obstacle; a shape that does not say answers with
        the farthest point of its ball cover (:meth:`balls`), a little
        beyond itself. Used for the gap to a half-space.
        """
        unit = np.asarray(direction, dtype=np.float64)
        unit = unit / np.linalg.norm(unit)
        centres, radii = self.balls()
        k = int(np.argmax(centres @ unit + radii))
        return centres[k] + radii[k] * unit

    def surface_gap(self, other: Obstacle) -> tuple[float, np.ndarray, np.ndarray]:
        """Surface-to-surface gap to ``other``, and the surface point of each nearest the other.

        Exact for two round obstacles. A shape with an exact answer (a
        half-space) overrides this and answers for every other shape itself
        (with :meth:`cover_gap` where it has none, never ``super()``); the
        default asks such a shape first, as Python's reflected operators do,
        and otherwise measures through both ball covers (:meth:`cover_gap`).

        Returns
        -------
        gap : float
            Units; negative where the two overlap (``-inf``: they intersect
            without bound, two half-spaces that are not parallel).
        mine, theirs : ndarray, shape (q,)
            The point of this obstacle's surface and of ``other``'s nearest each other.
        """
        if type(other).surface_gap is not Obstacle.surface_gap:
            gap, theirs, mine = other.surface_gap(self)
            return gap, mine, theirs
        return self.cover_gap(other)

    def cover_gap(self, other: Obstacle) -> tuple[float, np.ndarray, np.ndarray]:
        """:meth:`surface_gap` through both ball covers (:meth:`balls`): the closest two balls.

        Exact for round obstacles; for others at most the covers' overshoot too small.
        """
        (ci, ri), (cj, rj) = self.balls(), other.balls()
        centre = np.linalg.norm(ci[:, None, :] - cj[None, :, :], axis=-1)
        gaps = centre - ri[:, None] - rj[None, :]
        k, m = np.unravel_index(np.argmin(gaps), gaps.shape)
        unit = (cj[m] - ci[k]) / centre[k, m] if centre[k, m] > 0.0 else np.zeros_like(ci[k])
        return float(gaps[k, m]), ci[k] + ri[k] * unit, cj[m] - rj[m] * unit

    def outline(self, n_points: int = 64) -> np.ndarray:
        """The top view (first two coordinates) as a closed polygon, shape (n_points, 2)."""
        return self.position[:2] + self.radius * _unit_circle(
            np.linspace(0.0, 2.0 * np.pi, n_points)
        )

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Lowest and highest coordinates of the obstacle, each shape (q,)."""
        centres, radii = self.balls()
        return (centres - radii[:, None]).min(axis=0), (centres + radii[:, None]).max(axis=0)

    def fields(self) -> dict[str, Any]:
        """The shape's extra fields for scene files (none for a round obstacle)."""
        return {}

    def solid(self, height: float) -> tuple[np.ndarray, dict[str, str]]:
        """The obstacle standing on the plane ``z = 0``, for a physics simulation.

        Parameters
        ----------
        height : float
            How tall the obstacle stands (units of the paths), where its shape
            does not say (a round obstacle's cylinder).

        Returns
        -------
        centre : ndarray, shape (3,)
            Where the solid's centre is (its body's origin), above the plane.
        geom : dict of str to str
            MuJoCo geom attributes (``type``, ``size``, ``fromto``...) in a
            frame at ``centre``; the simulation adds names, mass and colour.
            A round obstacle is a vertical cylinder of its radius.
        """
        half = 0.5 * float(height)
        centre = np.array([*self.position[:2], half])
        return centre, {"type": "cylinder", "size": f"{self.radius!r} {half!r}"}

    def scaled(self, factor: float) -> Obstacle:
        """The obstacle with every length multiplied by ``factor`` (> 0)."""
        return self.transformed(factor, np.ones(self.n_dims))

    def mirrored(self, axis: int = 1) -> Obstacle:
        """The obstacle reflected in coordinate ``axis``."""
        flip = np.ones(self.n_dims)
        flip[axis] = -1.0
        return self.transformed(1.0, flip)

    def transformed(self, factor: float, flip: np.ndarray) -> Obstacle:
        """Every point ``p`` mapped to ``factor · flip · p`` (``flip`` of ±1 per axis)."""
        return type(self)(
            self.label,
            factor * flip * self.position,
            factor * self.radius,
            motion=None if self.motion is None else self.motion.transformed(factor, flip),
        )

    @classmethod
    def from_fields(
        cls, label: str, position: Any, radius: float, fields: Mapping[str, Any]
    ) -> Obstacle:
        """The obstacle from its file fields (``fields`` holds the shape's extra ones)."""
        return cls(label, position, radius)


@dataclass(frozen=True, eq=False)
class Capsule(Obstacle):
    """A rod: every point within ``radius`` of the segment ``position``–``end``.

    A marker or a bottle lying on the table, a cable, a wall edge. Its reward
    is the class's Gaussian term at points along the axis, at most
    ``max(radius, length / 16)`` apart (both ends included), so the response
    runs along the whole rod (and is higher than a round obstacle's where the
    terms overlap); the planner keeps out of balls centred on the axis whose
    union contains the rod.

    Attributes
    ----------
    end : ndarray, shape (q,)
        The other end of the axis (units of the paths).
    """

    end: np.ndarray = field(default_factory=lambda: np.zeros(0))

    shape: ClassVar[str] = "capsule"
    field_kinds: ClassVar[Mapping[str, str]] = {"end": "point"}

    def __post_init__(self) -> None:
        super().__post_init__()
        end = _point(self.end, "end", self.label)
        if end.size != self.position.size:
            raise ValueError(
                f"end: a {end.size}-D point for a {self.position.size}-D position ({self.label!r})"
            )
        object.__setattr__(self, "end", end)

    @property
    def length(self) -> float:
        """Length of the axis (units)."""
        return float(np.linalg.norm(self.end - self.position))

    def _axis_points(self, largest_gap: float) -> np.ndarray:
        """Points from ``position`` to ``end``, evenly spaced at most ``largest_gap`` apart."""
        count = 1 + max(1, int(np.ceil(self.length / largest_gap))) if largest_gap > 0 else 2
        return self.position + np.linspace(0.0, 1.0, count)[:, None] * (self.end - self.position)

    def anchors(self) -> np.ndarray:
        return self._axis_points(max(self.radius, self.length / 16.0))

    def balls(self) -> tuple[np.ndarray, np.ndarray]:
        # Balls of radius √(r² + (g/2)²) at gap g cover the rod between their
        # centres: g = r/2 keeps them within 3 % of the rod (at most 257 balls).
        centres = self._axis_points(max(0.5 * self.radius, self.length / 256.0))
        gap = float(np.linalg.norm(centres[1] - centres[0]))
        return centres, np.full(centres.shape[0], float(np.hypot(self.radius, 0.5 * gap)))

    def clipped(self, lower: np.ndarray, upper: np.ndarray) -> Capsule:
        # The axis clipped to the box grown by the radius (Liang–Barsky): every
        # point of the rod inside the box lies within the radius of that part.
        lower, upper = (
            np.asarray(lower, float) - self.radius,
            np.asarray(upper, float) + self.radius,
        )
        axis = self.end - self.position
        enter, leave = 0.0, 1.0
        with np.errstate(divide="ignore", invalid="ignore"):
            to_lower, to_upper = (lower - self.position) / axis, (upper - self.position) / axis
        for k in range(axis.size):
            if axis[k] == 0.0:
                if not lower[k] <= self.position[k] <= upper[k]:
                    enter, leave = 1.0, 0.0  # parallel to the box and outside it
                continue
            near, far = sorted((float(to_lower[k]), float(to_upper[k])))
            enter, leave = max(enter, near), min(leave, far)
        if enter > leave:  # nothing in the box: keep one end, as a ball (still part of the rod)
            enter = leave = 0.0
        if enter <= 0.0 and leave >= 1.0:
            return self
        return replace(
            self, position=self.position + enter * axis, end=self.position + leave * axis
        )

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        ends = np.stack([self.position, self.end])
        return ends.min(axis=0) - self.radius, ends.max(axis=0) + self.radius

    def distance(self, path: np.ndarray) -> float:
        return segment_polyline_distance(self.position, self.end, path) - self.radius

    def extreme_point(self, direction: np.ndarray) -> np.ndarray:
        """Exact: the end of the axis farthest along ``direction``, moved out by ``radius``.

        A capsule is the segment's points swept by a ball, and a linear function
        is largest over a segment at an end (at ``position`` where both are equal).
        """
        unit = np.asarray(direction, dtype=np.float64)
        unit = unit / np.linalg.norm(unit)
        tip = self.end if float(self.end @ unit) > float(self.position @ unit) else self.position
        return tip + self.radius * unit

    def outline(self, n_points: int = 64) -> np.ndarray:
        axis = self.end[:2] - self.position[:2]
        heading = float(np.arctan2(axis[1], axis[0])) if np.any(axis) else 0.0
        half = max(n_points // 2, 2)
        # Half a circle around each end, joined by the straight sides.
        around_start = heading + np.linspace(0.5 * np.pi, 1.5 * np.pi, half)
        around_end = heading + np.linspace(-0.5 * np.pi, 0.5 * np.pi, half)
        ring = np.vstack(
            [
                self.position[:2] + self.radius * _unit_circle(around_start),
                self.end[:2] + self.radius * _unit_circle(around_end),
            ]
        )
        return np.vstack([ring, ring[:1]])

    def fields(self) -> dict[str, Any]:
        return {"end": self.end}

    def solid(self, height: float) -> tuple[np.ndarray, dict[str, str]]:
        """A rod lying on the plane (``height`` is not used: it is as tall as it is wide)."""
        middle = 0.5 * (self.position[:2] + self.end[:2])
        hx, hy = (float(v) for v in 0.5 * (self.end[:2] - self.position[:2]))
        ends = f"{-hx!r} {-hy!r} 0.0 {hx!r} {hy!r} 0.0"
        return np.array([*middle, self.radius]), {
            "type": "capsule",
            "size": repr(float(self.radius)),
            "fromto": ends,
        }

    def transformed(self, factor: float, flip: np.ndarray) -> Capsule:
        return Capsule(
            self.label,
            factor * flip * self.position,
            factor * self.radius,
            factor * flip * self.end,
            motion=None if self.motion is None else self.motion.transformed(factor, flip),
        )

    def translated(self, shift: Any) -> Capsule:
        shift = np.asarray(shift, float)
        return replace(self, position=self.position + shift, end=self.end + shift, motion=None)

    @classmethod
    def from_fields(
        cls, label: str, position: Any, radius: float, fields: Mapping[str, Any]
    ) -> Capsule:
        if "end" not in fields:
            raise ValueError(f"end: a capsule needs the other end of its axis ({label!r})")
        return cls(label, position, radius, fields["end"])


#: Obstacle classes by their :attr:`Obstacle.shape` name (scene files name them).
OBSTACLE_SHAPES: dict[str, type[Obstacle]] = {}


#: Names a shape's fields cannot take: the columns and keys every scene file
#: already uses (CSV and JSON), so that a field can never be read as one of them.
RESERVED_FIELD_NAMES = frozenset(
    {"demo", "class", "x", "y", "z", "radius", "shape", "position", "vx", "vy", "vz"}
    | {"velocity", "trajectory", "observations", "format", "version", "scenes", "obstacles"}
)
_FIELD_KINDS = ("point", "number")
_BUILT_IN_SHAPES = ("round", "capsule", "box", "half_space")


def _field_columns(name: str, kind: str) -> list[str]:
    """A field's CSV columns, 2-D and 3-D: ``end`` (point) → end_x, end_y, end_z."""
    return [f"{name}_{c}" for c in "xyz"] if kind == "point" else [name]


def register_shape(shape: type[Obstacle]) -> type[Obstacle]:
    """Make an obstacle class known to the scene files under its ``shape`` name.

    The name and the field names are checked so that every scene file
    round-trips: the name is a lowercase identifier, not a built-in shape's
    (``round``, ``capsule``) unless it is that class; each field is a
    lowercase identifier of kind ``"point"`` or ``"number"`` whose name and
    CSV columns (``NAME_x, NAME_y, NAME_z`` for a point) collide neither
    with :data:`RESERVED_FIELD_NAMES` nor with each other, nor with another
    registered shape's columns of another meaning. Registering the same name
    again replaces the shape (a class redefined in a notebook).

    Raises
    ------
    TypeError
        If ``shape`` is not a subclass of :class:`Obstacle`.
    ValueError
        For a bad or protected name, or colliding fields (the message names them).
    """
    if not (isinstance(shape, type) and issubclass(shape, Obstacle)):
        raise TypeError(f"shape: expected a subclass of Obstacle, got {shape!r}")
    name = shape.shape
    if not isinstance(name, str) or not re.fullmatch(r"[a-z][a-z0-9_]*", name):
        raise ValueError(
            f"shape: {shape.__name__}.shape must be a lowercase identifier, got {name!r}"
        )
    if name in _BUILT_IN_SHAPES and name in OBSTACLE_SHAPES and OBSTACLE_SHAPES[name] is not shape:
        raise ValueError(
            f"shape: {name!r} is a built-in shape; give {shape.__name__} another shape name"
        )
    kinds = dict(shape.field_kinds)
    columns: dict[str, str] = {}  # column -> field
    for field_name, kind in kinds.items():
        where = f"shape: {shape.__name__}.field_kinds[{field_name!r}]"
        if not isinstance(field_name, str) or not re.fullmatch(r"[a-z][a-z0-9_]*", field_name):
            raise ValueError(f"{where}: a field name must be a lowercase identifier")
        if kind not in _FIELD_KINDS:
            raise ValueError(f"{where}: kind must be 'point' or 'number', got {kind!r}")
        for column in {field_name, *_field_columns(field_name, kind)}:
            if column in RESERVED_FIELD_NAMES:
                raise ValueError(
                    f"{where}: {column!r} is a column every scene file uses (reserved: "
                    f"{', '.join(sorted(RESERVED_FIELD_NAMES))}); rename the field"
                )
            if column in columns and columns[column] != field_name:
                raise ValueError(
                    f"{where}: its column {column!r} is also field {columns[column]!r}'s; "
                    "rename one of them"
                )
            columns[column] = field_name
    for other in OBSTACLE_SHAPES.values():
        if other.shape == name:
            continue
        for other_name, other_kind in other.field_kinds.items():
            for column in {other_name, *_field_columns(other_name, other_kind)}:
                mine = columns.get(column)
                if mine is not None and (mine, kinds[mine]) != (other_name, other_kind):
                    raise ValueError(
                        f"shape: {shape.__name__}.field_kinds[{mine!r}]: its column {column!r} "
                        f"is the {other.shape} shape's field {other_name!r} ({other_kind}); "
                        "rename the field"
                    )
    OBSTACLE_SHAPES[name] = shape
    return shape


register_shape(Obstacle)
register_shape(Capsule)


def _unit_circle(angle: np.ndarray) -> np.ndarray:
    return np.column_stack([np.cos(angle), np.sin(angle)])


def _point(value: Any, name: str, label: str) -> np.ndarray:
    point = np.asarray(value, dtype=np.float64)
    if point.ndim != 1 or point.size not in (2, 3):
        raise ValueError(f"{name}: expected a 2-D or 3-D point, got shape {np.shape(value)}")
    if not np.all(np.isfinite(point)):
        raise ValueError(f"{name}: contains NaN or infinite values ({label!r})")
    point.setflags(write=False)
    return point


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
    def has_extent(self) -> np.ndarray:
        """Whether each obstacle has volume (:attr:`Obstacle.has_extent`), shape (n_obstacles,).

        The planner's hard barriers: ``scene.has_extent | (clearance > 0)``.
        """
        return np.array([o.has_extent for o in self.obstacles], dtype=bool)

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

    def anchors(self) -> tuple[np.ndarray, np.ndarray]:
        """Every obstacle's reward anchors: points (A, q) and their obstacle's index (A,)."""
        if not self.obstacles:
            return np.zeros((0, 0)), np.zeros(0, dtype=np.intp)
        parts = [o.anchors() for o in self.obstacles]
        owner = np.repeat(np.arange(len(parts)), [p.shape[0] for p in parts])
        return np.concatenate(parts), owner

    def balls(
        self, within: tuple[np.ndarray, np.ndarray] | None = None
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Every obstacle's covering balls: centres (K, q), radii (K,), obstacle index (K,).

        ``within``, a box ``(lower, upper)`` of shape (q,) each: cover only
        each static obstacle's part in that box (:meth:`Obstacle.clipped`), for
        a planner whose paths cannot leave it; a moving obstacle is covered whole.
        """
        if not self.obstacles:
            return np.zeros((0, 0)), np.zeros(0), np.zeros(0, dtype=np.intp)
        parts = [
            (o if within is None or o.moving else o.clipped(*within)).balls()
            for o in self.obstacles
        ]
        owner = np.repeat(np.arange(len(parts)), [c.shape[0] for c, _ in parts])
        return (
            np.concatenate([c for c, _ in parts]),
            np.concatenate([r for _, r in parts]),
            owner,
        )

    def distances(self, path: np.ndarray) -> np.ndarray:
        """Distance from a polyline ``(n, q)`` to each obstacle's surface, shape (n_obstacles,)."""
        return np.array([o.distance(path) for o in self.obstacles], dtype=np.float64)

    def scaled(self, factor: float) -> Scene:
        """The scene with every length multiplied by ``factor``."""
        return Scene(tuple(o.scaled(factor) for o in self.obstacles))

    def mirrored(self, axis: int = 1) -> Scene:
        """The scene reflected in coordinate ``axis`` (for symmetry checks)."""
        return Scene(tuple(o.mirrored(axis) for o in self.obstacles))

    @property
    def moving(self) -> bool:
        """Whether any obstacle moves (has a :attr:`Obstacle.motion`)."""
        return any(o.motion is not None for o in self.obstacles)

    def at(self, t: float) -> Scene:
        """The static scene at time ``t`` (s): every moving obstacle at its predicted mean."""
        if not self.moving:
            return self
        return Scene(tuple(o.at(t) for o in self.obstacles))

    def with_obstacles(self, obstacles: Iterable[Obstacle]) -> Scene:
        """A new scene with more obstacles."""
        return Scene((*self.obstacles, *obstacles))


# The built-in box and half-space live in their own modules (one shape, one file); importing it
# here registers it wherever scenes are used. It imports this module's names,
# all defined by now.
import lfdkit.model.box  # noqa: E402
import lfdkit.model.half_space  # noqa: E402, F401
