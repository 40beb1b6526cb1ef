"""The sweeping scene of thesis §6.4, described once: table, cube, brush, dustpan, cups, markers.

A UR5 with a brush sweeps a green cube over a table into a dustpan, past cups
and markers. Every number of that scene is written in this module, once: the
MuJoCo model (:mod:`.sim`), the figures (:mod:`.figures`), the scenario
generators below and the workflow of ``lfdkit demo`` (:mod:`.demo`) read them
from here.

Frames and units
----------------
Metres, kilograms, radians. The robot's base frame is the world frame; the
table top is the plane ``z = 0`` (the UR5 stands on the table, as in Fig 6.14).
Colours are RGBA, four numbers in [0, 1].

The objects
-----------
* :data:`TABLE` (:class:`Table`): the table top.
* :data:`CUBE` (:class:`Cube`): the green cube that is swept, a free body.
* :data:`BRUSH` (:class:`Brush`): the tool, a box head on a handle below the
  flange; its flange height while sweeping is the thesis's
  :data:`SWEEP_HEIGHT` (0.192 m), the default of :func:`sweeping_poses`
  (the brush's flange poses along a table path).
* :class:`Dustpan`: a floor flush with the table and three low walls, placed
  per scene.
* The obstacle classes (:data:`OBSTACLE_CLASSES`): a cup and a marker stand on
  the table as upright cylinders, free bodies, of a class's radius, height,
  mass and colour. The radii are those of the synthetic demonstrator
  (:data:`lfdkit.datasets.emulation.CUP_RADIUS`,
  :data:`~lfdkit.datasets.emulation.MARKER_RADIUS`: the data set, a lower
  layer, owns them and this table reads them). An obstacle's own ``radius``
  is its cylinder's; where it is 0 the class's radius is used. A class the
  table does not know (e.g. ``"bowl"``) stands as
  :data:`DEFAULT_OBSTACLE_CLASS`, a cup's cylinder (radius 3 cm where the
  obstacle gives none).

The dimensions of the brush, the cube and the dustpan are chosen for the
synthetic demonstrator of :func:`lfdkit.datasets.emulation.sweeping`, which
passes 6.3–7.1 cm from a cup's centre (3 cm radius): a brush 5 cm wide then
clears the cup by 0.8–1.6 cm. The thesis does not give them.

Scenarios
---------
:class:`SweepingTask` is one physical scene (cube, dustpan, obstacles).
:func:`random_scenarios` makes the unseen scenes of the experiment (a moved
dustpan, a cup and a marker near the straight sweep); :func:`unseen_scenes`
places the fixed designs of ``lfdkit demo`` (:data:`UNSEEN_DESIGNS`) along a
sweep. The demonstrator's own data set, with its held-out scenes, is
:func:`lfdkit.datasets.emulation.sweeping`, from the straight sweep
:data:`~lfdkit.datasets.emulation.SWEEP_START` →
:data:`~lfdkit.datasets.emulation.SWEEP_GOAL`; :data:`NOMINAL_DUSTPAN` is the
dustpan that sweep ends in.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np

from lfdkit.core.geometry import left_normals, path_length, resample_between
from lfdkit.core.validation import check_finite, check_path, check_positive, check_random_state
from lfdkit.datasets.emulation import CUP_RADIUS, MARKER_RADIUS, SWEEP_GOAL, SWEEP_START
from lfdkit.execute.poses import path_yaw
from lfdkit.model.scene import Obstacle, Scene

__all__ = [
    "BRUSH",
    "CUBE",
    "CUBE_SIZE",
    "DEFAULT_OBSTACLE_CLASS",
    "GOAL_APPROACH",
    "GOAL_DEPTH",
    "NEW_GOAL",
    "NOMINAL_DUSTPAN",
    "OBSTACLE_CLASSES",
    "SWEEP_HEIGHT",
    "TABLE",
    "TABLE_Z",
    "UNSEEN_DESIGNS",
    "Brush",
    "Cube",
    "Dustpan",
    "ObstacleClass",
    "SweepScenario",
    "SweepingTask",
    "Table",
    "obstacle",
    "obstacle_class",
    "random_scenarios",
    "sweeping_poses",
    "unseen_scenes",
]

SWEEP_HEIGHT = 0.192
"""Height of the brush's tool frame (the flange) above the base frame in the thesis (m, §6.4)."""

TABLE_Z = 0.0
"""Height of the table plane in the robot base frame (m): the UR5 stands on the table."""

Colour = tuple[float, float, float, float]


# ------------------------------------------------------------------ the objects
@dataclass(frozen=True)
class Table:
    """The table top: the plane ``z = 0``, a square of side ``2 * half_size`` (m)."""

    half_size: float = 1.2
    rgba: Colour = (0.85, 0.78, 0.65, 1.0)


#: The table of the experiment.
TABLE = Table()


@dataclass(frozen=True)
class Cube:
    """The cube that is swept into the dustpan.

    Attributes
    ----------
    size : float
        Side, m.
    mass : float
        kg.
    friction : (float, float, float)
        MuJoCo's sliding, torsional and rolling friction.
    rgba : Colour
    """

    size: float = 0.025
    mass: float = 0.03
    friction: tuple[float, float, float] = (0.5, 0.01, 0.001)
    rgba: Colour = (0.1, 0.8, 0.1, 1.0)


#: The green cube of the experiment.
CUBE = Cube()
#: Side of the green cube (m), :attr:`CUBE.size <Cube.size>`.
CUBE_SIZE = CUBE.size


@dataclass(frozen=True)
class Brush:
    """A box brush head on a handle below the flange.

    The tool frame is the flange: sweeping poses
    (:func:`sweeping_poses`) put it at ``sweep_height`` with
    its ``z`` axis down, its ``x`` axis along the path and the brush's long
    edge along its ``y`` axis; the handle runs down the tool ``z`` axis to the
    head, whose bottom is ``clearance`` above the table.

    Attributes
    ----------
    width : float
        Length of the brush edge, across the path (tool ``y``), m.
    thickness : float
        Along the path (tool ``x``), m.
    height : float
        Height of the head, m.
    clearance : float
        Gap between the head and the table at the sweeping height, m.
    sweep_height : float
        Height of the flange while sweeping, m (thesis 0.192).
    mass : float
        Mass of the head, kg.
    friction : (float, float, float)
        MuJoCo's friction of the head.
    rgba : Colour
        Colour of the head.
    handle_radius, handle_mass : float
        m and kg.
    handle_rgba : Colour
    """

    width: float = 0.05
    thickness: float = 0.02
    height: float = 0.025
    clearance: float = 0.002
    sweep_height: float = SWEEP_HEIGHT
    mass: float = 0.1
    friction: tuple[float, float, float] = (0.8, 0.01, 0.001)
    rgba: Colour = (0.9, 0.75, 0.2, 1.0)
    handle_radius: float = 0.008
    handle_mass: float = 0.1
    handle_rgba: Colour = (0.45, 0.3, 0.2, 1.0)

    @property
    def head_centre(self) -> float:
        """Distance of the head's centre below the flange, along tool ``z`` (m)."""
        return self.sweep_height - self.clearance - 0.5 * self.height


#: The brush used in the experiment.
BRUSH = Brush()

#: How far into the dustpan, on its centre line, the brush stops (m).
GOAL_DEPTH = 0.02
#: Stretch before the dustpan over which plans return to the nominal (m): the dustpan's depth.
#: Here, not in ``execution``, so that planning alone (``batch evaluate --check plan``)
#: does not import the execution pipeline and SciPy.
GOAL_APPROACH = 0.1


@dataclass(frozen=True)
class Dustpan:
    """A dustpan on the table: a floor flush with the table and three low walls.

    The frame's origin is the middle of the opening; its ``x`` axis points into
    the dustpan (the direction the cube arrives from), at ``yaw`` from the
    world ``x`` axis. A cube is *in* the dustpan when its centre lies over
    the floor, ``0 <= x <= depth`` and ``|y| <= width / 2``.

    Attributes
    ----------
    position : ndarray, shape (2,)
        Middle of the opening, m.
    yaw : float
        rad.
    depth, width : float
        Inner size of the floor, m.
    wall_height, wall_thickness : float
        m.
    floor_thickness : float
        m; the floor's top is this far above the table.
    floor_rgba, wall_rgba : Colour
    """

    position: np.ndarray
    yaw: float
    depth: float = 0.12
    width: float = 0.16
    wall_height: float = 0.03
    wall_thickness: float = 0.006
    floor_thickness: float = 0.001
    floor_rgba: Colour = (0.2, 0.2, 0.2, 1.0)
    wall_rgba: Colour = (0.3, 0.3, 0.3, 1.0)

    def __post_init__(self) -> None:
        position = np.asarray(self.position, dtype=np.float64)
        if position.shape != (2,) or not np.all(np.isfinite(position)):
            raise ValueError(f"dustpan position: expected 2 finite numbers, got {self.position!r}")
        for name in ("depth", "width", "wall_height", "wall_thickness", "floor_thickness"):
            check_positive(getattr(self, name), f"dustpan {name}")
        object.__setattr__(self, "position", position)
        object.__setattr__(self, "yaw", check_finite(self.yaw, "dustpan yaw"))

    @classmethod
    def for_sweep(cls, start: Any, goal: Any) -> Dustpan:
        """The dustpan a straight sweep from ``start`` to ``goal`` ends in.

        It faces ``start``; its opening lies :data:`GOAL_DEPTH` before ``goal`` on
        the line, so that its :meth:`goal` is ``goal``.
        """
        start = np.asarray(start, dtype=np.float64)
        goal = np.asarray(goal, dtype=np.float64)
        direction = (goal - start) / np.linalg.norm(goal - start)
        return cls(goal - GOAL_DEPTH * direction, float(np.arctan2(direction[1], direction[0])))

    @property
    def axes(self) -> np.ndarray:
        """Rows: the dustpan's ``x`` (inwards) and ``y`` axes in the world, (2, 2)."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        return np.array([[c, s], [-s, c]])

    def local(self, points: Any) -> np.ndarray:
        """World points (…, 2) in the dustpan frame."""
        return (np.asarray(points, dtype=np.float64) - self.position) @ self.axes.T

    def contains(self, point: Any) -> bool:
        """Whether a point (2,) lies over the floor."""
        x, y = self.local(point)
        return bool(0.0 <= x <= self.depth and abs(y) <= 0.5 * self.width)

    def goal(self, depth: float = GOAL_DEPTH) -> np.ndarray:
        """Where the brush should stop: ``depth`` into the dustpan on its centre line (2,)."""
        return self.position + depth * self.axes[0]


@dataclass(frozen=True)
class ObstacleClass:
    """How the obstacles of one class stand on the table: upright cylinders, free bodies.

    Attributes
    ----------
    radius : float
        The cylinder's radius where an obstacle gives none (radius 0), m.
    height : float
        m.
    mass : float
        kg.
    rgba : Colour
    """

    radius: float
    height: float
    mass: float
    rgba: Colour

    def cylinder_radius(self, obstacle: Obstacle) -> float:
        """The radius of ``obstacle``'s cylinder: its own, or the class's where it is 0."""
        return float(obstacle.radius) or self.radius


#: The obstacle classes of the sweeping task, by label (read-only).
OBSTACLE_CLASSES: Mapping[str, ObstacleClass] = MappingProxyType(
    {
        "cup": ObstacleClass(CUP_RADIUS, height=0.10, mass=0.25, rgba=(0.85, 0.85, 0.9, 1.0)),
        "marker": ObstacleClass(MARKER_RADIUS, height=0.14, mass=0.02, rgba=(0.1, 0.1, 0.8, 1.0)),
    }
)
#: How an obstacle of a class not in :data:`OBSTACLE_CLASSES` stands: as a cup.
DEFAULT_OBSTACLE_CLASS = OBSTACLE_CLASSES["cup"]


def obstacle_class(label: str) -> ObstacleClass:
    """The class description of ``label``; :data:`DEFAULT_OBSTACLE_CLASS` for an unknown one."""
    return OBSTACLE_CLASSES.get(label, DEFAULT_OBSTACLE_CLASS)


def obstacle(label: str, position: Any) -> Obstacle:
    """An obstacle of class ``label`` at ``position`` (2,), with the class's radius."""
    return Obstacle(label, position, obstacle_class(label).radius)


# ------------------------------------------------------------------ one scene
@dataclass(frozen=True)
class SweepingTask:
    """The physical scene of one sweep: the cube, the dustpan and the obstacles.

    Attributes
    ----------
    cube : ndarray, shape (2,)
        Start of the cube's centre on the table, m.
    dustpan : Dustpan
    scene : Scene
        Obstacles, 2-D positions on the table, standing as their class
        (:func:`obstacle_class`) describes; each obstacle's ``radius`` is its
        cylinder's (the class's radius where it is 0).
    cube_yaw : float
        Initial heading of the cube (rad), e.g. the path's first direction.
    """

    cube: np.ndarray
    dustpan: Dustpan
    scene: Scene = field(default_factory=Scene)
    cube_yaw: float = 0.0

    def __post_init__(self) -> None:
        cube = np.asarray(self.cube, dtype=np.float64)
        if cube.shape != (2,) or not np.all(np.isfinite(cube)):
            raise ValueError(f"cube: expected 2 finite numbers, got {self.cube!r}")
        if not isinstance(self.dustpan, Dustpan):
            raise TypeError(f"dustpan: expected a Dustpan, got {type(self.dustpan).__name__}")
        if not isinstance(self.scene, Scene):
            raise TypeError(f"scene: expected a Scene, got {type(self.scene).__name__}")
        if len(self.scene) and self.scene.positions.shape[1] != 2:
            raise ValueError("scene: obstacles must be 2-D positions on the table")
        object.__setattr__(self, "cube", cube)
        object.__setattr__(self, "cube_yaw", float(self.cube_yaw))

    @classmethod
    def for_path(
        cls, path: Any, dustpan: Dustpan, scene: Scene | None = None, *, brush: Brush = BRUSH
    ) -> SweepingTask:
        """The cube placed just in front of the brush at the start of ``path`` (n, 2).

        The direction is that of the path's first 2 cm (a DMP rollout creeps
        off its start, so the first segment alone can point anywhere).
        """
        path = check_path(path, "path", n_dims=2, min_points=2)
        length = path_length(path)
        if not length > 0:
            raise ValueError("path: has zero length (all points coincide)")
        lead = resample_between(path, 0.0, min(0.02, length), 2)
        tangent = (lead[1] - lead[0]) / np.linalg.norm(lead[1] - lead[0])
        ahead = 0.5 * brush.thickness + 0.5 * CUBE.size + 0.004
        yaw = math.atan2(tangent[1], tangent[0])
        return cls(path[0] + ahead * tangent, dustpan, Scene() if scene is None else scene, yaw)


# ------------------------------------------------------------------ scenarios
#: Where the thesis's dustpan stands (middle of its opening), m: the demonstrator's
#: straight sweep ends :data:`GOAL_DEPTH` inside it, at ``SWEEP_GOAL``.
NOMINAL_DUSTPAN = np.array([SWEEP_GOAL[0] - GOAL_DEPTH, SWEEP_GOAL[1]])


@dataclass(frozen=True)
class SweepScenario:
    """An unseen scene: the dustpan and the obstacles (the cube starts at ``start``).

    Attributes
    ----------
    start : ndarray, shape (2,)
        Start of the sweep (the brush behind the cube), m.
    dustpan : Dustpan
    scene : Scene
    """

    start: np.ndarray
    dustpan: Dustpan
    scene: Scene

    @property
    def goal(self) -> np.ndarray:
        """Where the brush stops: just inside the dustpan, on its centre line (2,)."""
        return self.dustpan.goal()


def random_scenarios(
    n: int,
    seed: Any = None,
    *,
    start: Any = SWEEP_START,
    dustpan_shift: tuple[float, float] = (0.12, 0.08),
    lateral: float = 0.03,
) -> list[SweepScenario]:
    """Random unseen sweeping scenes.

    The dustpan's opening moves from :data:`NOMINAL_DUSTPAN` by up to
    ``dustpan_shift[0]`` towards the cube and ``±dustpan_shift[1]``
    sideways (uniform), facing the cube. A cup and a marker stand near the
    straight line from the start to the dustpan: one at a fraction
    ``U[0.3, 0.45]`` of the way, the other (random order) at ``U[0.55, 0.7]``,
    each ``U[−lateral, lateral]`` off the line. With the 5 cm brush every
    obstacle within 5.5 cm (cup) or 3.5 cm (marker) of the line is hit by a
    straight sweep.

    Parameters
    ----------
    n : int
        Number of scenarios.
    seed : None, int or numpy.random.Generator
    start : array_like, shape (2,)
        Start of the sweep, m (default the demonstrator's, (−0.4, 0.45)).
    dustpan_shift : (float, float)
        Largest move of the dustpan along and across the sweep, m.
    lateral : float
        Largest offset of an obstacle from the line, m.

    Returns
    -------
    list of SweepScenario
    """
    n = check_positive(n, "n", integer=True)
    rng = check_random_state(seed)
    start = np.asarray(start, dtype=np.float64)
    scenarios = []
    for _ in range(n):
        shift = np.array(
            [-rng.uniform(0.0, dustpan_shift[0]), rng.uniform(-dustpan_shift[1], dustpan_shift[1])]
        )
        opening = NOMINAL_DUSTPAN + shift
        direction = opening - start
        yaw = math.atan2(direction[1], direction[0])
        dustpan = Dustpan(opening, yaw)
        line = dustpan.goal() - start
        normal = np.array([-line[1], line[0]]) / np.linalg.norm(line)
        fractions = [rng.uniform(0.3, 0.45), rng.uniform(0.55, 0.7)]
        labels = ["cup", "marker"] if rng.random() < 0.5 else ["marker", "cup"]
        obstacles = tuple(
            obstacle(label, start + u * line + rng.uniform(-lateral, lateral) * normal)
            for label, u in zip(labels, fractions, strict=True)
        )
        scenarios.append(SweepScenario(start.copy(), dustpan, Scene(obstacles)))
    return scenarios


#: The moved dustpan of ``lfdkit demo``: the goal of its unseen scenes (m).
NEW_GOAL = np.array([0.36, 0.50])
#: Obstacles of the unseen scenes of ``lfdkit demo``: (class, fraction along the
#: straight sweep, offset across it in metres, left positive).
UNSEEN_DESIGNS = (
    (("cup", 0.40, 0.02), ("marker", 0.62, -0.015)),
    (("marker", 0.38, -0.01), ("cup", 0.60, 0.025)),
    (("cup", 0.42, -0.03), ("marker", 0.55, 0.02), ("cup", 0.72, 0.05)),
)


def unseen_scenes(start: Any, goal: Any = NEW_GOAL, designs: Any = UNSEEN_DESIGNS) -> list[Scene]:
    """One scene per design, placed along the straight sweep from ``start`` to ``goal`` (2,)."""
    start = np.asarray(start, dtype=np.float64)
    goal = np.asarray(goal, dtype=np.float64)
    normal = left_normals(np.vstack([start, goal]))[0]
    return [
        Scene(
            tuple(
                obstacle(label, start + u * (goal - start) + across * normal)
                for label, u, across in design
            )
        )
        for design in designs
    ]


def sweeping_poses(
    path: Any,
    *,
    height: float = SWEEP_HEIGHT,
    tool_down: bool = True,
    yaw_offset: float = 0.0,
    yaw: Any = None,
) -> np.ndarray:
    """Tool poses for sweeping along a planar path at a fixed height (thesis §6.4).

    The tool frame sits at ``(x, y, height)``; its x axis points along the path
    tangent, rotated by ``yaw_offset`` about the vertical, so the brush's long
    edge, along the tool y axis, is orthogonal to the path. With ``tool_down``
    the tool z axis points down (roll and pitch zero with the tool facing the
    table): ``R = Rz(ψ) Rx(π)``, columns ``x = (cos ψ, sin ψ, 0)``,
    ``y = (sin ψ, −cos ψ, 0)``, ``z = (0, 0, −1)``; otherwise ``R = Rz(ψ)``.

    Parameters
    ----------
    path : array_like, shape (n, 2)
        Points on the table in the robot base frame (metres).
    height : float
        z coordinate of the tool frame in the base frame (metres); 0.192 in the thesis.
    tool_down : bool
        Point the tool z axis along −z of the base (true) or +z (false).
    yaw_offset : float
        Extra rotation (rad) about the vertical, e.g. for a brush mounted at an
        angle on the flange.
    yaw : array_like, shape (n,), optional
        The tool's heading at each point (rad), e.g. the demonstrated one
        (:func:`lfdkit.execute.poses.yaw_from_quaternions`), instead of the path's tangent;
        ``yaw_offset`` is added to it.

    Returns
    -------
    ndarray, shape (n, 4, 4)
        Homogeneous transforms of the tool in the base frame. The yaw ψ comes
        from :func:`lfdkit.execute.poses.path_yaw` (or ``yaw``), so it is
        continuous along the path. Every tool-down pose is a rotation by π
        (about a horizontal axis), where rotation vectors flip sign: convert
        with :func:`lfdkit.execute.poses.pose_vector` and then
        :func:`lfdkit.execute.poses.unwrap_rotvecs` before sending them to the robot.

    Raises
    ------
    ValueError
        If the path is not ``(n, 2)``, has fewer than 2 points, contains
        NaN/inf or has zero length, or if ``height``/``yaw_offset`` is not finite.
    """
    psi = path_yaw(path, yaw_offset=yaw_offset)
    arr = np.asarray(path, dtype=np.float64)
    if yaw is not None:
        given = np.asarray(yaw, dtype=np.float64)
        if given.shape != (len(arr),):
            raise ValueError(
                f"yaw: expected shape ({len(arr)},), one per path point, got {given.shape}"
            )
        if not np.isfinite(given).all():
            raise ValueError("yaw: contains NaN or an infinite value")
        psi = given + check_finite(yaw_offset, "yaw_offset")
    z = check_finite(height, "height")
    c, s = np.cos(psi), np.sin(psi)
    T = np.zeros((len(psi), 4, 4))
    T[:, 0, 0], T[:, 1, 0] = c, s  # tool x: along the path
    if tool_down:
        T[:, 0, 1], T[:, 1, 1] = s, -c  # tool y = z × x, orthogonal to the path
        T[:, 2, 2] = -1.0
    else:
        T[:, 0, 1], T[:, 1, 1] = -s, c
        T[:, 2, 2] = 1.0
    T[:, :2, 3] = arr
    T[:, 2, 3] = z
    T[:, 3, 3] = 1.0
    return T
