"""MuJoCo simulation of the sweeping experiment (thesis §6.4, Fig 6.14–6.15).

A UR5 with a brush sweeps a green cube over a table into a dustpan, past cups
and markers. The robot is an :class:`lfdkit.robot.arm.Arm` (``arm=``, default
the thesis's UR5; the sweep needs a UR-type arm for its inverse kinematics),
built by :mod:`lfdkit.robot.mujoco` from the description's DH table, masses,
link radii, joint limits and servo gains, so MuJoCo's flange pose equals
:func:`lfdkit.robot.ur5.forward` to round-off
(:func:`lfdkit.robot.mujoco.flange_poses`). This module adds the scene: the
brush is a box on a handle fixed to the flange; cube, cups and markers are
free bodies, so physics decides where the cube goes and whether an obstacle
is hit.

Frames and units
----------------
Metres, seconds, radians. The robot's base frame is the world frame; the table
top is the plane ``z = 0`` (the UR5 stands on the table, as in Fig 6.14). The
tool frame is the flange: sweeping poses (:func:`lfdkit.robot.poses.sweeping_poses`)
put it at ``z = 0.192`` with its ``z`` axis down, its ``x`` axis along the
path and the brush's long edge along its ``y`` axis. The brush head's bottom
is :attr:`Brush.clearance` above the table.

Dimensions (:data:`BRUSH`, :data:`CUBE_SIZE`, :class:`Dustpan`) are chosen for
the synthetic demonstrator of :func:`lfdkit.datasets.emulation.sweeping`,
which passes 6.3–7.1 cm from a cup's centre (3 cm radius): a brush 5 cm wide
then clears the cup by 0.8–1.6 cm. The thesis does not give them.

Control
-------
Position actuators (PD, the arm's ``kp``/``kv`` per joint) follow the time-parameterised
joint trajectory, commanded at every 2 ms physics step with a velocity
feed-forward (``q_ref + kv/kp · q̇_ref``) that cancels the damping's lag;
the links are gravity-compensated. The robot starts at the trajectory's first
configuration (lowering the brush onto the table is not simulated), waits
:data:`SETTLE_TIME`, sweeps, and waits again for the cube to come to rest.

Outcome
-------
:func:`simulate_sweep` never raises for what happens in the scene: a cube that
misses the dustpan, a touched obstacle, tracking beyond the tolerance, an
unstable simulation or (in :func:`execute_sweep`) a path the robot cannot
follow are reported in :class:`SweepResult` (``success``, ``failures``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from html import escape
from typing import Any

import numpy as np

from lfdkit._validation import check_finite, check_path, check_positive
from lfdkit.geometry import (
    path_length,
    project_onto_polyline,
    resample,
    resample_between,
    smooth_path,
)
from lfdkit.robot import ur5
from lfdkit.robot.arm import UR5, Arm, check_arm
from lfdkit.robot.mujoco import (
    ROBOT_CONTACT,
    actuators_xml,
    load_mujoco,
    mjcf_numbers,
    robot_xml,
)
from lfdkit.robot.poses import SWEEP_HEIGHT, sweeping_poses
from lfdkit.robot.timing import Timing, time_parameterize
from lfdkit.scene import Scene

__all__ = [
    "BRUSH",
    "CUBE_SIZE",
    "HOME",
    "TRACKING_TOLERANCE",
    "Brush",
    "Dustpan",
    "SweepResult",
    "SweepingTask",
    "build_model",
    "execute_sweep",
    "simulate_sweep",
    "sweep_motion",
    "sweeping_mjcf",
]

#: Physics step (s).
TIMESTEP = 0.002
#: Rest before and after the sweep (s).
SETTLE_TIME = 0.3
#: Largest accepted distance of the simulated tool from the planned tool path (m).
TRACKING_TOLERANCE = 0.005
#: Side of the green cube (m).
CUBE_SIZE = 0.025
#: A configuration of a UR-type arm with the brush down in front of it (rad); picks the
#: IK branch.
HOME = np.array([0.0, -1.2, 1.6, -1.97, -1.5708, 0.0])

# Collision groups: the robot and brush (ROBOT_CONTACT) hit objects, not the table or
# themselves.
_OBJECT = 'contype="1" conaffinity="3"'
_FIXED = 'contype="1" conaffinity="1"'


@dataclass(frozen=True)
class Brush:
    """A box brush head on a handle below the flange.

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
    """

    width: float = 0.05
    thickness: float = 0.02
    height: float = 0.025
    clearance: float = 0.002
    sweep_height: float = SWEEP_HEIGHT

    @property
    def head_centre(self) -> float:
        """Distance of the head's centre below the flange, along tool ``z`` (m)."""
        return self.sweep_height - self.clearance - 0.5 * self.height


#: The brush used in the experiment.
BRUSH = Brush()


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
    """

    position: np.ndarray
    yaw: float
    depth: float = 0.12
    width: float = 0.16
    wall_height: float = 0.03
    wall_thickness: float = 0.006

    def __post_init__(self) -> None:
        position = np.asarray(self.position, dtype=np.float64)
        if position.shape != (2,) or not np.all(np.isfinite(position)):
            raise ValueError(f"dustpan position: expected 2 finite numbers, got {self.position!r}")
        for name in ("depth", "width", "wall_height", "wall_thickness"):
            check_positive(getattr(self, name), f"dustpan {name}")
        object.__setattr__(self, "position", position)
        object.__setattr__(self, "yaw", check_finite(self.yaw, "dustpan yaw"))

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

    def goal(self, depth: float = 0.02) -> np.ndarray:
        """Where the brush should stop: ``depth`` into the dustpan on its centre line (2,)."""
        return self.position + depth * self.axes[0]


@dataclass(frozen=True)
class SweepingTask:
    """The physical scene of one sweep: the cube, the dustpan and the obstacles.

    Attributes
    ----------
    cube : ndarray, shape (2,)
        Start of the cube's centre on the table, m.
    dustpan : Dustpan
    scene : Scene
        Obstacles, 2-D positions on the table. Class ``"marker"`` is a thin
        tall cylinder, every other class a cup; each obstacle's ``radius`` is
        the cylinder's (a class default where it is 0).
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
        ahead = 0.5 * brush.thickness + 0.5 * CUBE_SIZE + 0.004
        yaw = math.atan2(tangent[1], tangent[0])
        return cls(path[0] + ahead * tangent, dustpan, Scene() if scene is None else scene, yaw)


@dataclass
class SweepResult:
    """What happened in one simulated sweep.

    Attributes
    ----------
    success : bool
        Cube in the dustpan, no obstacle touched, tracking within tolerance,
        simulation stable.
    cube_in_dustpan : bool
    touched : list of int
        Indices (in the task's scene) of obstacles anything touched.
    tracking_error : float
        Largest distance of the simulated flange from the planned flange
        position at the same time, m (nan if not simulated).
    path_error : float
        Largest distance of the simulated flange from the planned tool path
        (a polyline), m.
    failures : list of str
        One line per failure; empty on success.
    cube_final : ndarray, shape (2,)
        Where the cube came to rest (nan if not simulated).
    duration : float
        Length of the sweep, s.
    times : ndarray, shape (m,)
        Sample times of the traces, s.
    tool_trace : ndarray, shape (m, 3)
        Simulated flange positions, m.
    cube_trace : ndarray, shape (m, 2)
        Simulated cube centre, m.
    obstacle_shift : ndarray, shape (L,)
        How far each obstacle moved, m.
    joint_path : ndarray, shape (n, n_joints) or None
        The commanded joint waypoints, rad.
    timing : Timing or None
    image : ndarray, shape (720, 960, 3) or None
        The rendered final scene (with the planned path in red and the cube's
        trace in green), when asked for and OpenGL is available.
    """

    success: bool
    cube_in_dustpan: bool
    touched: list[int]
    tracking_error: float
    path_error: float
    failures: list[str]
    cube_final: np.ndarray
    duration: float
    times: np.ndarray
    tool_trace: np.ndarray
    cube_trace: np.ndarray
    obstacle_shift: np.ndarray
    joint_path: np.ndarray | None = None
    timing: Timing | None = field(default=None, repr=False)
    image: np.ndarray | None = field(default=None, repr=False)

    def summary(self) -> str:
        """One line: success or the failures."""
        if self.success:
            return (
                f"success: cube in the dustpan, no obstacle touched, "
                f"tracking {self.tracking_error * 1e3:.2f} mm"
            )
        return "; ".join(self.failures)


# ------------------------------------------------------------------ model
def _brush_xml(brush: Brush) -> list[str]:
    """The brush's geoms in the flange body: a handle down the tool ``z`` axis and the head."""
    return [
        f'<geom name="handle" type="cylinder" fromto="0 0 0 0 0 {brush.head_centre!r}" '
        f'size="0.008" mass="0.1" rgba="0.45 0.3 0.2 1" {ROBOT_CONTACT}/>',
        f'<geom name="brush" type="box" pos="0 0 {brush.head_centre!r}" '
        f'size="{0.5 * brush.thickness!r} {0.5 * brush.width!r} {0.5 * brush.height!r}" '
        f'mass="0.1" friction="0.8 0.01 0.001" rgba="0.9 0.75 0.2 1" {ROBOT_CONTACT}/>',
    ]


def _obstacle_xml(scene: Scene) -> str:
    lines = []
    for index, obstacle in enumerate(scene):
        marker = obstacle.label == "marker"
        radius = float(obstacle.radius) or (0.01 if marker else 0.03)
        height, mass = (0.14, 0.02) if marker else (0.10, 0.25)
        colour = "0.1 0.1 0.8 1" if marker else "0.85 0.85 0.9 1"
        x, y = (float(v) for v in obstacle.position)
        lines.append(
            f'    <body name="obstacle{index}" pos="{x!r} {y!r} {0.5 * height + 1e-4}">\n'
            f'      <freejoint name="obstacle{index}"/>\n'
            f'      <geom name="obstacle{index}" type="cylinder" size="{radius!r} {0.5 * height}" '
            f'mass="{mass}" rgba="{colour}" {_OBJECT}/>\n'
            f"    </body>"
        )
    return "\n".join(lines)


def _dustpan_xml(pan: Dustpan) -> str:
    t, h = pan.wall_thickness, pan.wall_height
    x, y = (float(v) for v in pan.position)
    half_w = 0.5 * pan.width
    quat = mjcf_numbers([math.cos(0.5 * pan.yaw), 0.0, 0.0, math.sin(0.5 * pan.yaw)])
    return (
        f'    <body name="dustpan" pos="{x!r} {y!r} 0" quat="{quat}">\n'
        f'      <geom name="dustpan_floor" type="box" pos="{0.5 * pan.depth} 0 0.0005" '
        f'size="{0.5 * pan.depth} {half_w} 0.0005" rgba="0.2 0.2 0.2 1" '
        f'contype="0" conaffinity="0"/>\n'
        f'      <geom name="dustpan_back" type="box" pos="{pan.depth + 0.5 * t} 0 {0.5 * h}" '
        f'size="{0.5 * t} {half_w + t} {0.5 * h}" rgba="0.3 0.3 0.3 1" {_OBJECT}/>\n'
        f'      <geom name="dustpan_left" type="box" pos="{0.5 * pan.depth} {half_w + 0.5 * t} '
        f'{0.5 * h}" size="{0.5 * pan.depth} {0.5 * t} {0.5 * h}" rgba="0.3 0.3 0.3 1" '
        f"{_OBJECT}/>\n"
        f'      <geom name="dustpan_right" type="box" pos="{0.5 * pan.depth} '
        f'{-(half_w + 0.5 * t)} {0.5 * h}" size="{0.5 * pan.depth} {0.5 * t} {0.5 * h}" '
        f'rgba="0.3 0.3 0.3 1" {_OBJECT}/>\n'
        f"    </body>"
    )


def sweeping_mjcf(task: SweepingTask | None = None, *, brush: Brush = BRUSH, arm: Arm = UR5) -> str:
    """The MJCF (MuJoCo XML) of the arm with a brush, table and the task's objects.

    With ``task`` None: the robot and the table only (for kinematic checks).
    """
    arm = check_arm(arm)
    quarter = CUBE_SIZE / 2
    objects = ""
    if task is not None:
        cx, cy = (float(v) for v in task.cube)
        cube_quat = mjcf_numbers(
            [math.cos(0.5 * task.cube_yaw), 0.0, 0.0, math.sin(0.5 * task.cube_yaw)]
        )
        objects = "\n".join(
            [
                f'    <body name="cube" pos="{cx!r} {cy!r} {quarter + 1e-4}" quat="{cube_quat}">',
                '      <freejoint name="cube"/>',
                f'      <geom name="cube" type="box" size="{quarter} {quarter} {quarter}" '
                f'mass="0.03" friction="0.5 0.01 0.001" rgba="0.1 0.8 0.1 1" {_OBJECT}/>',
                "    </body>",
                _dustpan_xml(task.dustpan),
                _obstacle_xml(task.scene),
            ]
        )
    return f"""<mujoco model="lfdkit {escape(arm.name)} sweeping">
  <compiler angle="radian" autolimits="true"/>
  <option timestep="{TIMESTEP}" integrator="implicitfast" cone="elliptic"/>
  <visual>
    <global offwidth="960" offheight="720"/>
    <quality shadowsize="2048"/>
  </visual>
  <default>
    <geom friction="0.5 0.01 0.001" solref="0.004 1"/>
  </default>
  <worldbody>
    <light pos="0.3 0.2 2.0" dir="0 0 -1" diffuse="0.8 0.8 0.8"/>
    <camera name="overview" pos="0.0 1.0 1.2" xyaxes="-1 0 0 0 -0.893 0.45" fovy="45"/>
    <camera name="top" pos="0.0 0.45 1.6" xyaxes="1 0 0 0 1 0"/>
    <geom name="table" type="plane" size="1.2 1.2 0.01" rgba="0.85 0.78 0.65 1" {_FIXED}/>
    <geom name="base" type="cylinder" size="0.075 0.045" pos="0 0 0.045"
          rgba="0.3 0.3 0.35 1" contype="0" conaffinity="0"/>
{robot_xml(arm, _brush_xml(brush))}
{objects}
  </worldbody>
  <actuator>
{actuators_xml(arm)}
  </actuator>
</mujoco>
"""


def build_model(task: SweepingTask | None = None, *, brush: Brush = BRUSH, arm: Arm = UR5) -> Any:
    """The compiled ``mujoco.MjModel`` of :func:`sweeping_mjcf`."""
    return load_mujoco().MjModel.from_xml_string(sweeping_mjcf(task, brush=brush, arm=arm))


# ------------------------------------------------------------------ running
def _render_camera(
    mujoco: Any, model: Any, data: Any, camera: str, traces: list[tuple[np.ndarray, tuple]]
) -> np.ndarray | None:
    """An RGB image (h, w, 3) with traces drawn as dots; None without an OpenGL context."""
    try:
        with mujoco.Renderer(model, 720, 960) as renderer:
            renderer.update_scene(data, camera=camera)
            scene = renderer.scene
            for points, rgba in traces:
                for point in points[:: max(1, len(points) // 150)]:
                    if scene.ngeom >= scene.maxgeom:
                        break
                    mujoco.mjv_initGeom(
                        scene.geoms[scene.ngeom],
                        mujoco.mjtGeom.mjGEOM_SPHERE,
                        np.array([0.004, 0.0, 0.0]),
                        np.asarray(point, dtype=np.float64),
                        np.eye(3).ravel(),
                        np.asarray(rgba, dtype=np.float32),
                    )
                    scene.ngeom += 1
            return renderer.render().copy()
    except Exception:  # no EGL/OSMesa/GLFW: rendering is optional
        return None


def simulate_sweep(
    timing: Timing,
    task: SweepingTask,
    *,
    brush: Brush = BRUSH,
    tolerance: float = TRACKING_TOLERANCE,
    render: bool = False,
    camera: str = "overview",
    sample_rate: float = 50.0,
    arm: Arm = UR5,
) -> SweepResult:
    """Run a joint trajectory in the sweeping scene and report what happened.

    Parameters
    ----------
    timing : Timing
        The joint trajectory (:func:`lfdkit.robot.timing.time_parameterize`).
    task : SweepingTask
    brush : Brush
    tolerance : float
        Largest accepted tracking error, m.
    render : bool
        Also render the final scene (``SweepResult.image``; None without OpenGL).
    camera : {"overview", "top"}
    sample_rate : float
        Rate of the recorded traces, Hz.
    arm : Arm
        The arm that runs ``timing`` (as many joints).

    Returns
    -------
    SweepResult
        With ``image`` (ndarray (720, 960, 3) or None) added when ``render``.
    """
    mujoco = load_mujoco()
    arm = check_arm(arm)
    if not isinstance(timing, Timing):
        raise TypeError(f"timing: expected a Timing, got {type(timing).__name__}")
    n_joints = arm.n_joints
    if timing.n_joints != n_joints:
        raise ValueError(
            f"timing: expected {n_joints} joints for the {arm.name}, got {timing.n_joints}"
        )
    tolerance = check_positive(tolerance, "tolerance")
    model = build_model(task, brush=brush, arm=arm)
    data = mujoco.MjData(model)
    flange = model.site("flange").id
    cube = model.body("cube").id
    n_obstacles = len(task.scene)
    obstacle_geoms = {model.geom(f"obstacle{i}").id: i for i in range(n_obstacles)}
    obstacle_bodies = [model.body(f"obstacle{i}").id for i in range(n_obstacles)]
    table = model.geom("table").id

    q0 = timing.sample(0.0)[0]
    data.qpos[:n_joints] = q0
    data.ctrl[:] = q0
    mujoco.mj_forward(model, data)
    obstacle_start = np.array([data.xpos[b, :2] for b in obstacle_bodies]).reshape(-1, 2)
    kv_over_kp = arm.kv / arm.kp
    duration = timing.duration
    total = duration + 2 * SETTLE_TIME
    n_steps = math.ceil(total / TIMESTEP)
    every = max(1, round(1.0 / (sample_rate * TIMESTEP)))
    step_times = np.arange(1, n_steps + 1) * TIMESTEP
    q_ref, qd_ref, _ = timing.sample(step_times - SETTLE_TIME)
    planned = ur5.forward(q_ref, arm=arm)[:, :3, 3]

    obstacle_of = np.full(model.ngeom, -1)  # obstacle index of each geom, -1 for others
    for geom, index in obstacle_geoms.items():
        obstacle_of[geom] = index
    touched: set[int] = set()
    tool_all = np.full((n_steps, 3), np.nan)
    cube_all = np.full((n_steps, 2), np.nan)
    unstable = ""
    for k in range(n_steps):
        data.ctrl[:] = q_ref[k] + kv_over_kp * qd_ref[k]
        mujoco.mj_step(model, data)
        if not np.all(np.isfinite(data.qpos)):
            unstable = f"simulation became unstable at t = {data.time:.3f} s"
            break
        tool_all[k] = data.site_xpos[flange]
        cube_all[k] = data.xpos[cube, :2]
        if data.ncon:
            pairs = data.contact.geom[: data.ncon]
            hit = obstacle_of[pairs]
            # an obstacle resting on the table is not touched; anything else is
            for side in (0, 1):
                mask = (hit[:, side] >= 0) & (pairs[:, 1 - side] != table)
                touched.update(int(i) for i in hit[mask, side])

    n_done = k + 1 if not unstable else k
    recorded = np.arange(0, n_done, every)
    if n_done and recorded[-1] != n_done - 1:
        recorded = np.append(recorded, n_done - 1)
    times = step_times[recorded]
    tool_trace, cube_trace = tool_all[recorded], cube_all[recorded]
    worst = float(np.linalg.norm(tool_all[:n_done] - planned[:n_done], axis=1).max())
    cube_final = cube_trace[-1] if len(cube_trace) else np.full(2, np.nan)
    shift = np.linalg.norm(data.xpos[obstacle_bodies, :2] - obstacle_start, axis=1)
    sweeping = (times >= SETTLE_TIME) & (times <= SETTLE_TIME + duration)
    path_error = (
        float(project_onto_polyline(tool_trace[sweeping], planned)[2].max())
        if sweeping.any() and not unstable
        else float("nan")
    )
    in_pan = bool(not unstable and task.dustpan.contains(cube_final))
    failures = []
    if unstable:
        failures.append(unstable)
        worst = float("nan")
    if not in_pan and not unstable:
        x, y = task.dustpan.local(cube_final)
        failures.append(
            f"cube missed the dustpan: rests at ({x:+.3f}, {y:+.3f}) m in the dustpan's frame"
        )
    for i in sorted(touched):
        obstacle = task.scene.obstacles[i]
        failures.append(f"touched obstacle {i} ({obstacle.label}), moved {shift[i] * 1e3:.1f} mm")
    if not unstable and worst > tolerance:
        failures.append(f"tracking error {worst * 1e3:.3g} mm exceeds {tolerance * 1e3:.3g} mm")
    result = SweepResult(
        success=not failures,
        cube_in_dustpan=in_pan,
        touched=sorted(touched),
        tracking_error=worst,
        path_error=path_error,
        failures=failures,
        cube_final=cube_final,
        duration=duration,
        times=times,
        tool_trace=tool_trace,
        cube_trace=cube_trace,
        obstacle_shift=shift,
        joint_path=timing.waypoints,
        timing=timing,
    )
    if render:
        ground = np.column_stack([planned[:, :2], np.full(len(planned), 0.003)])
        cube_path = np.column_stack([cube_trace, np.full(len(cube_trace), 0.003)])
        traces = [(ground, (0.9, 0.1, 0.1, 1.0)), (cube_path, (0.1, 0.7, 0.1, 1.0))]
        result.image = _render_camera(mujoco, model, data, camera, traces)
    return result


def _failed(message: str, task: SweepingTask) -> SweepResult:
    """A result for a sweep that could not be run."""
    return SweepResult(
        success=False,
        cube_in_dustpan=False,
        touched=[],
        tracking_error=float("nan"),
        path_error=float("nan"),
        failures=[message],
        cube_final=np.full(2, np.nan),
        duration=float("nan"),
        times=np.zeros(0),
        tool_trace=np.zeros((0, 3)),
        cube_trace=np.zeros((0, 2)),
        obstacle_shift=np.zeros(len(task.scene)),
    )


def sweep_motion(
    path: Any,
    *,
    brush: Brush = BRUSH,
    smoothing: float = 0.01,
    q_home: Any = HOME,
    arm: Arm = UR5,
) -> tuple[np.ndarray, np.ndarray]:
    """Tool poses and the continuous joint path that sweep along a table path.

    Parameters
    ----------
    path : array_like, shape (n, 2)
        The brush's path on the table, m.
    brush : Brush
        Gives the sweeping height.
    smoothing : float
        Width (m) of the corner rounding (:func:`lfdkit.geometry.smooth_path`);
        0 leaves the path as it is.
    q_home : array_like, shape (6,)
        Configuration that picks the IK branch.
    arm : Arm
        A UR-type arm (:attr:`lfdkit.robot.arm.Arm.ur_type`).

    Returns
    -------
    poses : ndarray, shape (m, 4, 4)
        Flange poses, one every 2 mm of path (so that a sharp but real turn of
        the brush stays below the IK's branch-flip threshold between poses).
    joints : ndarray, shape (m, 6)
        Joint angles, rad, on one continuous IK branch.

    Raises
    ------
    lfdkit.robot.ur5.KinematicsError
        Unreachable poses, joint limits or a singularity, naming the pose.
    """
    path = check_path(path, "path", n_dims=2, min_points=2)
    n_poses = max(len(path), math.ceil(path_length(path) / 0.002) + 1)
    if smoothing:
        path = smooth_path(path, check_positive(smoothing, "smoothing"), n_poses)
    else:
        path = resample(path, n_poses)
    frames = sweeping_poses(path, height=brush.sweep_height)
    q_start = ur5.nearest_solution(frames[0], q_home, arm=arm)
    return frames, ur5.inverse_path(frames, q_start, arm=arm)


def execute_sweep(
    path: Any,
    task: SweepingTask,
    *,
    brush: Brush = BRUSH,
    smoothing: float = 0.01,
    speed_fraction: float = 0.2,
    q_home: Any = HOME,
    tolerance: float = TRACKING_TOLERANCE,
    render: bool = False,
    camera: str = "overview",
    arm: Arm = UR5,
) -> SweepResult:
    """Sweep along a planned table path in MuJoCo: poses, IK, timing, simulation.

    Parameters
    ----------
    path : array_like, shape (n, 2)
        The planned path of the brush on the table (e.g. :meth:`lfdkit.skill.Skill.plan`), m.
    task : SweepingTask
    brush : Brush
    smoothing : float
        Width (m) of the corner rounding (:func:`lfdkit.geometry.smooth_path`)
        applied before the poses are made: a plan's corners would otherwise
        turn the brush abruptly. 0 leaves the path as it is.
    speed_fraction : float
        Fraction of the arm's joint speed limits (thesis: playback at 0.2).
    q_home : array_like, shape (6,)
        Configuration that picks the IK branch.
    tolerance : float
        Largest accepted tracking error, m.
    render : bool
        Render the final scene (``SweepResult.image``).
    camera : {"overview", "top"}
    arm : Arm
        A UR-type arm (:attr:`lfdkit.robot.arm.Arm.ur_type`); its limits time the motion.

    Returns
    -------
    SweepResult
        A path the robot cannot follow (unreachable, joint limits, a
        singularity) is reported as a failure, not raised.
    """
    try:
        _, joints = sweep_motion(path, brush=brush, smoothing=smoothing, q_home=q_home, arm=arm)
    except ur5.KinematicsError as exc:
        return _failed(f"the robot cannot follow the path: {exc}", task)
    timing = time_parameterize(joints, arm=arm, speed_fraction=speed_fraction)
    return simulate_sweep(
        timing, task, brush=brush, tolerance=tolerance, render=render, camera=camera, arm=arm
    )
