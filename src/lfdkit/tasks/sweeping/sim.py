"""MuJoCo simulation of the sweeping experiment (thesis §6.4, Fig 6.14–6.15).

The scene is the one :mod:`.scenarios` describes (table, cube, brush, dustpan,
cups and markers, every dimension, mass and colour read from there). The robot
is an :class:`lfdkit.execute.arm.Arm` (``arm=``, default the thesis's UR5),
built by :mod:`lfdkit.execute.mujoco` from the description's DH table, masses,
link radii, joint limits and servo gains, so MuJoCo's flange pose equals
:func:`lfdkit.execute.ur5.forward` to round-off; its joint count, its limits
(for the timing) and its kinematics all come from the description, so another
arm (:data:`lfdkit.execute.arm.UR10`) sweeps without a change here. The sweep's
inverse kinematics is the analytic one of UR-type arms
(:attr:`lfdkit.execute.arm.Arm.ur_type`); :data:`HOME` picks its branch.

The brush is a box on a handle fixed to the flange; cube, cups and markers are
free bodies, so physics decides where the cube goes and whether an obstacle is
hit. An obstacle stands as its shape's solid
(:meth:`lfdkit.model.scene.Obstacle.solid`): a round one as an upright cylinder of
the height its class describes
(:func:`lfdkit.tasks.sweeping.scenarios.obstacle_class`; a class the task does
not know stands as a cup), a rod (:class:`lfdkit.model.scene.Capsule`) lying on the
table; of the obstacle's own radius (the class's where it is 0).

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
from dataclasses import dataclass, field, replace
from html import escape
from typing import Any

import numpy as np

from lfdkit.core.geometry import (
    arc_length,
    path_length,
    project_onto_polyline,
    resample,
    smooth_path,
)
from lfdkit.core.progress import ProgressLike, Stage, as_progress
from lfdkit.core.validation import check_path, check_positive
from lfdkit.execute import ur5
from lfdkit.execute.arm import UR5, Arm, check_arm
from lfdkit.execute.kinematics import joint_path
from lfdkit.execute.mujoco import (
    FIXED_CONTACT,
    OBJECT_CONTACT,
    ROBOT_CONTACT,
    actuators_xml,
    load_mujoco,
    mjcf_numbers,
    render_camera,
    robot_xml,
)
from lfdkit.execute.timing import Timing, time_parameterize
from lfdkit.model.scene import Scene
from lfdkit.tasks.sweeping.scenarios import (
    BRUSH,
    CUBE,
    TABLE,
    Brush,
    Dustpan,
    SweepingTask,
    obstacle_class,
    sweeping_poses,
)

__all__ = [
    "HOME",
    "RENDER_TRACES",
    "SETTLE_TIME",
    "TIMESTEP",
    "TRACKING_TOLERANCE",
    "SweepResult",
    "build_model",
    "execute_sweep",
    "simulate_sweep",
    "simulate_timed_path",
    "sweep_motion",
    "sweeping_mjcf",
]

#: Physics step (s).
TIMESTEP = 0.002
#: Rest before and after the sweep (s).
SETTLE_TIME = 0.3
#: Largest accepted distance of the simulated tool from the planned tool path (m).
TRACKING_TOLERANCE = 0.005
#: A configuration of a UR-type arm with the brush down in front of it (rad); picks the
#: IK branch.
HOME = np.array([0.0, -1.2, 1.6, -1.97, -1.5708, 0.0])

#: Height and width of a rendered image (pixels).
_IMAGE = (720, 960)
#: The render's traces by name, with their colours: the top view's
#: (:func:`lfdkit.tasks.sweeping.figures.sweep_figure`: its first run's colour,
#: ``lfdkit.app.plot.PLAN_COLORS[0]``, and the cube's path), the key of the picture.
RENDER_TRACES = {
    "brush path (planned)": "#1f77b4",
    "cube's path": "#404040",
    "moving obstacle's track": "#c030c0",
}
#: Physics steps between two counts of the simulation's progress.
_STEPS_PER_COUNT = 100


@dataclass
class SweepResult:
    """What happened in one simulated sweep.

    The fields after ``failures`` default to a sweep that was not simulated
    (NaN and empty traces).

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
        The rendered final scene, framed on the arm, the objects and the traces
        (the planned path and the cube's trace in :data:`RENDER_TRACES`'
        colours), when asked for and OpenGL is available. The ``overview``
        camera looks from the arm's side, so the picture is the top view's way
        round (x to the right, the arm's base at the bottom), with the arm's
        links see-through (:data:`ARM_ALPHA`) so as not to hide the dustpan.
    """

    success: bool
    cube_in_dustpan: bool
    touched: list[int]
    tracking_error: float = float("nan")
    path_error: float = float("nan")
    failures: list[str] = field(default_factory=list)
    cube_final: np.ndarray = field(default_factory=lambda: np.full(2, np.nan))
    duration: float = float("nan")
    times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    tool_trace: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    cube_trace: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    obstacle_shift: np.ndarray = field(default_factory=lambda: np.zeros(0))
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
        f'size="{brush.handle_radius!r}" mass="{brush.handle_mass!r}" '
        f'rgba="{mjcf_numbers(brush.handle_rgba)}" {ROBOT_CONTACT}/>',
        f'<geom name="brush" type="box" pos="0 0 {brush.head_centre!r}" '
        f'size="{0.5 * brush.thickness!r} {0.5 * brush.width!r} {0.5 * brush.height!r}" '
        f'mass="{brush.mass!r}" friction="{mjcf_numbers(brush.friction)}" '
        f'rgba="{mjcf_numbers(brush.rgba)}" {ROBOT_CONTACT}/>',
    ]


def _cube_xml(task: SweepingTask) -> str:
    half = CUBE.size / 2
    x, y = (float(v) for v in task.cube)
    quat = mjcf_numbers([math.cos(0.5 * task.cube_yaw), 0.0, 0.0, math.sin(0.5 * task.cube_yaw)])
    return (
        f'    <body name="cube" pos="{x!r} {y!r} {half + 1e-4}" quat="{quat}">\n'
        '      <freejoint name="cube"/>\n'
        f'      <geom name="cube" type="box" size="{half} {half} {half}" '
        f'mass="{CUBE.mass!r}" friction="{mjcf_numbers(CUBE.friction)}" '
        f'rgba="{mjcf_numbers(CUBE.rgba)}" {OBJECT_CONTACT}/>\n'
        "    </body>"
    )


def _obstacle_xml(scene: Scene) -> str:
    lines = []
    for index, obstacle in enumerate(scene):
        kind = obstacle_class(obstacle.label)
        # The obstacle's own shape (the contract's solid), of the class's radius where it has none.
        solid = replace(obstacle, radius=kind.cylinder_radius(obstacle))
        centre, geom = solid.solid(kind.height)
        x, y, z = (float(v) for v in centre)
        attributes = " ".join(f'{key}="{value}"' for key, value in geom.items())
        # A moving obstacle is a mocap body, driven along its motion (it pushes, is not pushed).
        # A plane (a half-space) is static in MuJoCo: a body with no joint and no mass.
        static = geom.get("type") == "plane"
        body = (
            f'    <body name="obstacle{index}" pos="{x!r} {y!r} {z + 1e-4}" mocap="true">\n'
            if obstacle.moving
            else f'    <body name="obstacle{index}" pos="{x!r} {y!r} {z}">\n'
            if static
            else f'    <body name="obstacle{index}" pos="{x!r} {y!r} {z + 1e-4}">\n'
            f'      <freejoint name="obstacle{index}"/>\n'
        )
        mass = "" if static else f'mass="{kind.mass!r}" '
        lines.append(
            body + f'      <geom name="obstacle{index}" {attributes} '
            f'{mass}rgba="{mjcf_numbers(kind.rgba)}" {OBJECT_CONTACT}/>\n'
            f"    </body>"
        )
    return "\n".join(lines)


def _dustpan_xml(pan: Dustpan) -> str:
    t, h, f = pan.wall_thickness, pan.wall_height, 0.5 * pan.floor_thickness
    x, y = (float(v) for v in pan.position)
    half_w = 0.5 * pan.width
    quat = mjcf_numbers([math.cos(0.5 * pan.yaw), 0.0, 0.0, math.sin(0.5 * pan.yaw)])
    wall = f'rgba="{mjcf_numbers(pan.wall_rgba)}" {OBJECT_CONTACT}'
    return (
        f'    <body name="dustpan" pos="{x!r} {y!r} 0" quat="{quat}">\n'
        f'      <geom name="dustpan_floor" type="box" pos="{0.5 * pan.depth} 0 {f}" '
        f'size="{0.5 * pan.depth} {half_w} {f}" rgba="{mjcf_numbers(pan.floor_rgba)}" '
        f'contype="0" conaffinity="0"/>\n'
        f'      <geom name="dustpan_back" type="box" pos="{pan.depth + 0.5 * t} 0 {0.5 * h}" '
        f'size="{0.5 * t} {half_w + t} {0.5 * h}" {wall}/>\n'
        f'      <geom name="dustpan_left" type="box" pos="{0.5 * pan.depth} {half_w + 0.5 * t} '
        f'{0.5 * h}" size="{0.5 * pan.depth} {0.5 * t} {0.5 * h}" {wall}/>\n'
        f'      <geom name="dustpan_right" type="box" pos="{0.5 * pan.depth} '
        f'{-(half_w + 0.5 * t)} {0.5 * h}" size="{0.5 * pan.depth} {0.5 * t} {0.5 * h}" '
        f"{wall}/>\n"
        f"    </body>"
    )


def sweeping_mjcf(task: SweepingTask | None = None, *, brush: Brush = BRUSH, arm: Arm = UR5) -> str:
    """The MJCF (MuJoCo XML) of the arm with a brush, table and the task's objects.

    With ``task`` None: the robot and the table only (for kinematic checks).
    """
    arm = check_arm(arm)
    objects = ""
    if task is not None:
        objects = "\n".join(
            [_cube_xml(task), _dustpan_xml(task.dustpan), _obstacle_xml(task.scene)]
        )
    height, width = _IMAGE
    return f"""<mujoco model="lfdkit {escape(arm.name)} sweeping">
  <compiler angle="radian" autolimits="true"/>
  <option timestep="{TIMESTEP}" integrator="implicitfast" cone="elliptic"/>
  <visual>
    <global offwidth="{width}" offheight="{height}"/>
    <quality shadowsize="2048"/>
  </visual>
  <asset>
    <!-- A pale sky where the view reaches past the table's edge (black by default). -->
    <texture type="skybox" builtin="gradient" rgb1="0.95 0.95 0.95" rgb2="0.8 0.8 0.8"
             width="32" height="32"/>
  </asset>
  <default>
    <geom friction="0.5 0.01 0.001" solref="0.004 1"/>
  </default>
  <worldbody>
    <light pos="0.3 0.2 2.0" dir="0 0 -1" diffuse="0.8 0.8 0.8"/>
    <camera name="overview" pos="0.0 -0.45 1.4" xyaxes="1 0 0 0 0.940 0.342" fovy="45"/>
    <camera name="top" pos="0.0 0.45 1.6" xyaxes="1 0 0 0 1 0"/>
    <geom name="table" type="plane" size="{TABLE.half_size!r} {TABLE.half_size!r} 0.01"
          rgba="{mjcf_numbers(TABLE.rgba)}" {FIXED_CONTACT}/>
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
@dataclass
class _Physics:
    """What stepping the scene along a reference recorded.

    ``tool`` (n, 3) and ``cube`` (n, 2) hold the flange and the cube's centre
    after each of the ``n`` steps run (fewer than asked for when the
    simulation became unstable, ``unstable`` then says when); ``touched`` the
    obstacles anything but the table touched, ``shift`` how far each moved.
    """

    data: Any
    tool: np.ndarray
    cube: np.ndarray
    touched: set[int]
    shift: np.ndarray
    unstable: str


def _step(
    model: Any,
    n_obstacles: int,
    q0: np.ndarray,
    command: np.ndarray,
    stage: Stage,
    mocap: dict[int, np.ndarray] | None = None,
) -> _Physics:
    """Start the arm at ``q0`` and command one row of ``command`` per physics step.

    ``stage`` counts the steps, :data:`_STEPS_PER_COUNT` at a time. ``mocap``
    maps a moving obstacle's index to its (x, y) at every step (n_steps, 2).
    """
    mujoco = load_mujoco()
    data = mujoco.MjData(model)
    flange = model.site("flange").id
    cube = model.body("cube").id
    obstacle_bodies = [model.body(f"obstacle{i}").id for i in range(n_obstacles)]
    table = model.geom("table").id
    obstacle_of = np.full(model.ngeom, -1)  # obstacle index of each geom, -1 for others
    for index in range(n_obstacles):
        obstacle_of[model.geom(f"obstacle{index}").id] = index

    data.qpos[: len(q0)] = q0
    data.ctrl[:] = q0
    driven = [
        (int(model.body_mocapid[obstacle_bodies[i]]), track) for i, track in (mocap or {}).items()
    ]
    for slot, track in driven:
        data.mocap_pos[slot, :2] = track[0]
    mujoco.mj_forward(model, data)
    obstacle_start = np.array([data.xpos[b, :2] for b in obstacle_bodies]).reshape(-1, 2)
    n_steps = len(command)
    touched: set[int] = set()
    tool = np.full((n_steps, 3), np.nan)
    cube_xy = np.full((n_steps, 2), np.nan)
    unstable = ""
    for k in range(n_steps):
        data.ctrl[:] = command[k]
        for slot, track in driven:
            data.mocap_pos[slot, :2] = track[k]
        mujoco.mj_step(model, data)
        if (k + 1) % _STEPS_PER_COUNT == 0 or k + 1 == n_steps:
            stage.advance((k + 1) - stage.done)
        if not np.all(np.isfinite(data.qpos)):
            unstable = f"simulation became unstable at t = {data.time:.3f} s"
            break
        tool[k] = data.site_xpos[flange]
        cube_xy[k] = data.xpos[cube, :2]
        if data.ncon:
            pairs = data.contact.geom[: data.ncon]
            hit = obstacle_of[pairs]
            # an obstacle resting on the table is not touched; anything else is
            for side in (0, 1):
                mask = (hit[:, side] >= 0) & (pairs[:, 1 - side] != table)
                touched.update(int(i) for i in hit[mask, side])
    n_done = k + 1 if not unstable else k
    shift = np.linalg.norm(data.xpos[obstacle_bodies, :2] - obstacle_start, axis=1)
    return _Physics(data, tool[:n_done], cube_xy[:n_done], touched, shift, unstable)


def _traces(physics: _Physics, step_times: np.ndarray, every: int) -> dict[str, np.ndarray]:
    """The recorded traces, as :class:`SweepResult` fields: every ``every``-th step and the last."""
    n_done = len(physics.tool)
    recorded = np.arange(0, n_done, every)
    if n_done and recorded[-1] != n_done - 1:
        recorded = np.append(recorded, n_done - 1)
    cube_trace = physics.cube[recorded]
    return {
        "times": step_times[recorded],
        "tool_trace": physics.tool[recorded],
        "cube_trace": cube_trace,
        "cube_final": cube_trace[-1] if len(cube_trace) else np.full(2, np.nan),
        "obstacle_shift": physics.shift,
    }


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
    progress: ProgressLike = None,
) -> SweepResult:
    """Run a joint trajectory in the sweeping scene and report what happened.

    Parameters
    ----------
    timing : Timing
        The joint trajectory (:func:`lfdkit.execute.timing.time_parameterize`).
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
    progress : Progress, callable, bool or None
        Counts the physics steps and reports the rendering
        (:func:`lfdkit.core.progress.as_progress`); default silent.

    Returns
    -------
    SweepResult
        With ``image`` (ndarray (720, 960, 3) or None) added when ``render``.
    """
    arm = check_arm(arm)
    if not isinstance(timing, Timing):
        raise TypeError(f"timing: expected a Timing, got {type(timing).__name__}")
    if timing.n_joints != arm.n_joints:
        raise ValueError(
            f"timing: expected {arm.n_joints} joints for the {arm.name}, got {timing.n_joints}"
        )
    tolerance = check_positive(tolerance, "tolerance")
    duration = timing.duration
    n_steps = math.ceil((duration + 2 * SETTLE_TIME) / TIMESTEP)
    step_times = np.arange(1, n_steps + 1) * TIMESTEP
    reference = timing.sample(step_times - SETTLE_TIME)
    q_ref, qd_ref = reference.positions, reference.velocities
    result = _simulate(
        q_ref,
        qd_ref,
        timing.sample(0.0).positions[0],
        step_times,
        duration,
        task,
        brush,
        tolerance,
        render,
        camera,
        sample_rate,
        arm,
        progress,
    )
    result.joint_path, result.timing = timing.waypoints, timing
    return result


def _simulate(
    q_ref: np.ndarray,
    qd_ref: np.ndarray,
    q0: np.ndarray,
    step_times: np.ndarray,
    duration: float,
    task: SweepingTask,
    brush: Brush,
    tolerance: float,
    render: bool,
    camera: str,
    sample_rate: float,
    arm: Arm,
    progress: ProgressLike,
) -> SweepResult:
    """Follow the joint reference (one row per physics step) in the task's scene."""
    progress = as_progress(progress)
    with progress.stage(f"simulate: build the MuJoCo scene ({arm.name})"):
        model = build_model(task, brush=brush, arm=arm)
    n_steps = len(step_times)
    planned = ur5.forward(q_ref, arm=arm)[:, :3, 3]
    # Velocity feed-forward: the servo's damping then pulls towards the reference speed.
    command = q_ref + arm.kv / arm.kp * qd_ref
    # Moving obstacles follow their motion's mean, in the sweep's time (0 when it starts).
    mocap = {
        i: o.predict(step_times - SETTLE_TIME)[0][:, :2]
        for i, o in enumerate(task.scene.obstacles)
        if o.moving
    }
    label = f"simulate: {n_steps} physics steps ({n_steps * TIMESTEP:.1f} s of motion)"
    with progress.stage(label, total=n_steps) as stage:
        physics = _step(model, len(task.scene), q0, command, stage, mocap)
    traces = _traces(physics, step_times, max(1, round(1.0 / (sample_rate * TIMESTEP))))

    n_done, unstable = len(physics.tool), physics.unstable
    worst = float(np.linalg.norm(physics.tool - planned[:n_done], axis=1).max())
    times = traces["times"]
    sweeping = (times >= SETTLE_TIME) & (times <= SETTLE_TIME + duration)
    path_error = (
        float(project_onto_polyline(traces["tool_trace"][sweeping], planned)[2].max())
        if sweeping.any() and not unstable
        else float("nan")
    )
    cube_final = traces["cube_final"]
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
    shift = physics.shift
    for i in sorted(physics.touched):
        obstacle = task.scene.obstacles[i]
        failures.append(f"touched obstacle {i} ({obstacle.label}), moved {shift[i] * 1e3:.1f} mm")
    if not unstable and worst > tolerance:
        failures.append(f"tracking error {worst * 1e3:.3g} mm exceeds {tolerance * 1e3:.3g} mm")
    result = SweepResult(
        success=not failures,
        cube_in_dustpan=in_pan,
        touched=sorted(physics.touched),
        tracking_error=worst,
        path_error=path_error,
        failures=failures,
        duration=duration,
        **traces,
    )
    if render:
        ground = np.column_stack([planned[:, :2], np.full(len(planned), 0.003)])
        cube_path = np.column_stack([traces["cube_trace"], np.full(len(times), 0.003)])
        brush_rgba, cube_rgba, track_rgba = (_rgba(c) for c in RENDER_TRACES.values())
        trace_colours = [(ground, brush_rgba), (cube_path, cube_rgba)]
        for track in mocap.values():
            dots = np.column_stack([track[::25], np.full(len(track[::25]), 0.003)])
            trace_colours.append((dots, track_rgba))
        with progress.stage(f"simulate: render the {camera} camera"):
            _see_through_arm(model)
            result.image = render_camera(
                model, physics.data, camera, trace_colours, size=_IMAGE, frame=True
            )
    return result


#: Opacity of the arm's links in the render: the overview camera looks over the arm (as
#: the top view does, x to the right), and the arm reaching to the dustpan would hide it.
ARM_ALPHA = 0.2


def _see_through_arm(model: Any) -> None:
    """Make the arm's links (bodies ``link1``...) see-through in ``model``; the tool stays."""
    for g in range(model.ngeom):
        if model.body(int(model.geom_bodyid[g])).name.startswith("link"):
            model.geom_rgba[g, 3] = ARM_ALPHA


def _rgba(hex_colour: str) -> tuple[float, float, float, float]:
    """``#rrggbb`` as RGBA numbers in [0, 1] (opaque)."""
    return (*(int(hex_colour[i : i + 2], 16) / 255.0 for i in (1, 3, 5)), 1.0)


def sweep_motion(
    path: Any,
    *,
    brush: Brush = BRUSH,
    smoothing: float = 0.01,
    q_home: Any = HOME,
    arm: Arm = UR5,
    yaw: Any = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Tool poses and the continuous joint path that sweep along a table path.

    Parameters
    ----------
    path : array_like, shape (n, 2)
        The brush's path on the table, m.
    brush : Brush
        Gives the sweeping height.
    smoothing : float
        Width (m) of the corner rounding (:func:`lfdkit.core.geometry.smooth_path`);
        0 leaves the path as it is.
    q_home : array_like, shape (arm.n_joints,)
        Configuration that picks the IK branch (:data:`HOME` for a UR-type arm).
    arm : Arm
        A UR-type arm (:attr:`lfdkit.execute.arm.Arm.ur_type`).
    yaw : array_like, shape (n,), optional
        The brush's heading at each point of ``path`` (rad, unwrapped; e.g.
        :func:`lfdkit.execute.poses.yaw_from_quaternions` of a plan's
        orientations), carried to the poses by arc-length fraction; default
        along the path's tangent.

    Returns
    -------
    poses : ndarray, shape (m, 4, 4)
        Flange poses, one every 2 mm of path (so that a sharp but real turn of
        the brush stays below the IK's branch-flip threshold between poses).
    joints : ndarray, shape (m, arm.n_joints)
        Joint angles, rad, on one continuous IK branch.

    Raises
    ------
    lfdkit.execute.ur5.KinematicsError
        Unreachable poses, joint limits or a singularity, naming the pose.
    """
    path = check_path(path, "path", n_dims=2, min_points=2)
    n_poses = max(len(path), math.ceil(path_length(path) / 0.002) + 1)
    given = path
    if smoothing:
        path = smooth_path(path, check_positive(smoothing, "smoothing"), n_poses)
    else:
        path = resample(path, n_poses)
    headings = None
    if yaw is not None:
        headings = np.asarray(yaw, dtype=np.float64)
        if headings.shape != (len(given),) or not np.all(np.isfinite(headings)):
            raise ValueError(f"yaw: expected {len(given)} finite angles, one per path point")
        # Both paths run from the same start to the same end: match them by arc-length fraction.
        headings = np.interp(
            arc_length(path) / path_length(path), arc_length(given) / path_length(given), headings
        )
    frames = sweeping_poses(path, height=brush.sweep_height, yaw=headings)
    # The generic chain's IK: the branch nearest q_home, one continuous branch after it.
    return frames, joint_path(frames, arm, q_home)


def _cannot_follow(task: SweepingTask, exc: Exception) -> SweepResult:
    """The result of a path the arm cannot follow (unreachable, limits, a singularity)."""
    return SweepResult(
        success=False,
        cube_in_dustpan=False,
        touched=[],
        failures=[f"the robot cannot follow the path: {exc}"],
        obstacle_shift=np.zeros(len(task.scene)),
    )


def simulate_timed_path(
    times: Any,
    points: Any,
    task: SweepingTask,
    *,
    brush: Brush = BRUSH,
    smoothing: float = 0.01,
    q_home: Any = HOME,
    tolerance: float = TRACKING_TOLERANCE,
    render: bool = False,
    camera: str = "overview",
    sample_rate: float = 50.0,
    arm: Arm = UR5,
    progress: ProgressLike = None,
    yaw: Any = None,
) -> SweepResult:
    """Sweep along a table path *with its own timing* in MuJoCo: the brush at ``points[k]`` at
    ``times[k]``.

    What a closed loop executed (e.g. :class:`lfdkit.emulate.RecedingPlanner`
    among moving obstacles, whose moves were timed by the skill), replayed on
    the arm: the flange poses and inverse kinematics of :func:`sweep_motion`,
    the joints interpolated in time along the path's arc length (the brush
    runs the path as ``(times, points)`` say, not as a time-optimal law would),
    and moving obstacles of ``task.scene`` driven along their motion as mocap
    bodies (``t = 0`` when the sweep starts).

    Parameters
    ----------
    times : array_like, shape (n,)
        Seconds from the sweep's start, non-decreasing, starting at 0.
    points : array_like, shape (n, 2)
        The brush's path on the table, m.
    task, brush, smoothing, q_home, tolerance, render, camera, sample_rate, arm, progress
        As :func:`execute_sweep` and :func:`simulate_sweep`.
    yaw : array_like, shape (n,), optional
        The brush's heading at each point (rad, unwrapped), as :func:`sweep_motion`;
        default along the path's tangent.

    Returns
    -------
    SweepResult
        A path the robot cannot follow is reported as a failure.
    """
    path = check_path(points, "points", n_dims=2, min_points=2)
    t = np.asarray(times, dtype=np.float64).reshape(-1)
    if t.size != len(path) or not np.all(np.isfinite(t)) or np.any(np.diff(t) < 0.0):
        raise ValueError(f"times: expected {len(path)} finite, non-decreasing times")
    try:
        poses, joints = sweep_motion(
            path, brush=brush, smoothing=smoothing, q_home=q_home, arm=arm, yaw=yaw
        )
    except ur5.KinematicsError as exc:
        return _cannot_follow(task, exc)
    # Fraction of arc length reached at each time, then the poses' joints at that fraction.
    run = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(path, axis=0), axis=1))])
    flange = poses[:, :2, 3]
    along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(flange, axis=0), axis=1))])
    duration = float(t[-1] - t[0])
    n_steps = math.ceil((duration + 2 * SETTLE_TIME) / TIMESTEP)
    step_times = np.arange(1, n_steps + 1) * TIMESTEP
    fraction = np.interp(step_times - SETTLE_TIME + t[0], t, run) / max(run[-1], 1e-12)
    where = fraction * along[-1]
    q_ref = np.column_stack([np.interp(where, along, joints[:, j]) for j in range(joints.shape[1])])
    qd_ref = np.gradient(q_ref, TIMESTEP, axis=0)
    result = _simulate(
        q_ref,
        qd_ref,
        joints[0],
        step_times,
        duration,
        task,
        brush,
        check_positive(tolerance, "tolerance"),
        render,
        camera,
        sample_rate,
        check_arm(arm),
        progress,
    )
    result.joint_path = joints
    return result


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
    progress: ProgressLike = None,
) -> SweepResult:
    """Sweep along a planned table path in MuJoCo: poses, IK, timing, simulation.

    Parameters
    ----------
    path : array_like, shape (n, 2)
        The planned path of the brush on the table (e.g. :meth:`lfdkit.skill.Skill.plan`), m.
    task : SweepingTask
    brush : Brush
    smoothing : float
        Width (m) of the corner rounding (:func:`lfdkit.core.geometry.smooth_path`)
        applied before the poses are made: a plan's corners would otherwise
        turn the brush abruptly. 0 leaves the path as it is.
    speed_fraction : float
        Fraction of the arm's joint speed limits (thesis: playback at 0.2).
    q_home : array_like, shape (arm.n_joints,)
        Configuration that picks the IK branch.
    tolerance : float
        Largest accepted tracking error, m.
    render : bool
        Render the final scene (``SweepResult.image``).
    camera : {"overview", "top"}
    arm : Arm
        A UR-type arm (:attr:`lfdkit.execute.arm.Arm.ur_type`); its limits time the motion.
    progress : Progress, callable, bool or None
        As in :func:`simulate_sweep`.

    Returns
    -------
    SweepResult
        A path the robot cannot follow (unreachable, joint limits, a
        singularity) is reported as a failure, not raised.
    """
    try:
        _, joints = sweep_motion(path, brush=brush, smoothing=smoothing, q_home=q_home, arm=arm)
    except ur5.KinematicsError as exc:
        return _cannot_follow(task, exc)
    timing = time_parameterize(joints, arm=arm, speed_fraction=speed_fraction)
    return simulate_sweep(
        timing,
        task,
        brush=brush,
        tolerance=tolerance,
        render=render,
        camera=camera,
        arm=arm,
        progress=progress,
    )
