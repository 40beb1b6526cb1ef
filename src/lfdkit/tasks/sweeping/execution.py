"""A learned skill on the robot: plan → tool poses → IK → timing → URScript → MuJoCo.

:func:`execute_skill` is the chain that ``lfdkit execute`` runs on a user's
skill and ``lfdkit demo`` on its unseen scene, for the sweeping task on a
table:

1. **plan**: :meth:`lfdkit.skill.Skill.plan_details` to the goal, with the
   goal approach :data:`GOAL_APPROACH` (the plan ends in the dustpan) and the
   brush's half width as the hard clearance around every obstacle;
2. **tool poses**: the brush's flange poses every 2 mm along the plan, corners
   rounded (:func:`lfdkit.tasks.sweeping.sim.sweep_motion`,
   :func:`lfdkit.tasks.sweeping.scenarios.sweeping_poses`);
3. **inverse kinematics**: one continuous branch within the joint limits
   (:func:`lfdkit.execute.ur5.inverse_path`) for any UR-type
   :class:`lfdkit.execute.arm.Arm`;
4. **timing**: time-optimal within the arm's joint speed and acceleration
   limits times a speed fraction (:func:`lfdkit.execute.timing.time_parameterize`);
5. **URScript**: a ``servoj`` stream at :data:`SERVO_RATE`
   (:func:`lfdkit.execute.urscript.urscript_program`, which checks every sample
   against the arm's limits);
6. **MuJoCo**: the same trajectory in the sweeping scene, the dustpan at the
   goal and the cube in front of the brush
   (:func:`lfdkit.tasks.sweeping.sim.simulate_sweep`): success, obstacles
   touched, tracking error, a picture when OpenGL works.

What the robot cannot do is refused with an :class:`ExecutionError` naming
what and where (an unreachable pose and its position, a joint limit, a tool
faster than :data:`lfdkit.execute.urscript.MAX_TOOL_SPEED`), before any file is
written; what happens in the simulated scene (the cube misses the dustpan, an
obstacle is touched) is an outcome, reported in the result. MuJoCo missing
skips the simulation with a reason.

:func:`write_execution` writes the files of :func:`execution_outputs`, each
atomically and none over an existing one unless asked.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from lfdkit import __version__
from lfdkit.core.geometry import path_length
from lfdkit.core.progress import ProgressLike, as_progress
from lfdkit.execute import ur5
from lfdkit.execute.arm import UR5, Arm, check_arm
from lfdkit.execute.pipeline import ExecutionError, check_tool_speed
from lfdkit.execute.poses import pose_vector, unwrap_rotvecs, yaw_from_quaternions
from lfdkit.execute.timing import Timing, time_parameterize
from lfdkit.execute.urscript import Workspace, urscript_program
from lfdkit.io import atomic_write, save_path, write_text
from lfdkit.model.scene import Scene
from lfdkit.model.timed_path import TimedPlan
from lfdkit.skill import Skill
from lfdkit.tasks.sweeping.scenarios import (
    BRUSH,
    GOAL_APPROACH,
    TABLE_Z,
    Dustpan,
    SweepingTask,
    obstacle_class,
)
from lfdkit.tasks.sweeping.sim import SweepResult, simulate_sweep, sweep_motion

__all__ = [
    "GOAL_APPROACH",
    "PLAN_SETTINGS",
    "SERVO_RATE",
    "ExecutionError",
    "SweepExecution",
    "execute_skill",
    "execution_outputs",
    "write_execution",
]

#: How every sweep is planned (:meth:`lfdkit.skill.Skill.plan` keywords): back on the
#: nominal over the goal approach, and the brush's half-width from every obstacle.
PLAN_SETTINGS = {"goal_approach": GOAL_APPROACH, "clearance": 0.5 * BRUSH.width}
#: Rate of the ``servoj`` stream (Hz): one tick of a CB-series controller, 8 ms.
SERVO_RATE = 125.0

# The files of write_execution, by what they hold.
_PLAN, _POSES, _JOINTS = "plan.csv", "poses.csv", "joints.csv"
_PROGRAM, _SUMMARY = "program.script", "summary.json"
_TOP_VIEW, _RENDER = "sweep.png", "render.png"


@dataclass
class SweepExecution:
    """A skill's plan carried to the robot, and what the simulated robot did with it.

    Attributes
    ----------
    plan : TimedPlan
        The plan as the skill gave it (:meth:`lfdkit.skill.Skill.plan`):
        ``times`` (n,) s, the person's timing, written in ``plan.csv`` (the
        robot runs the sweep time-optimally instead); ``positions`` (n, 2),
        the table path in m; ``orientations`` (n, 4) or None, the tool's
        (the skill's, when it has them); ``details``, the planner's result
        with its clearance and goal error.
    start, goal : ndarray, shape (2,)
        Where the sweep starts and where it should end (in the dustpan), m.
    scene : Scene
        The obstacles, each with the radius it stands with in the simulation
        (its class's where it gave none), as planned around.
    arm : Arm
    speed_fraction : float
        Fraction of the arm's joint limits the motion is timed at.
    dustpan : Dustpan
        At the goal, facing the start.
    poses : ndarray, shape (m, 4, 4)
        Flange poses along the plan, one every 2 mm, m.
    joints : ndarray, shape (m, arm.n_joints)
        Their joint angles on one continuous branch, rad.
    timing : Timing
        The timed joint trajectory.
    times : ndarray, shape (k,)
        Times of the ``servoj`` samples, s.
    stream : ndarray, shape (k, arm.n_joints)
        The joint angles the program streams, rad.
    program : str
        The URScript program.
    result : SweepResult or None
        The simulated sweep; None when it was not simulated.
    skipped : str
        Why it was not simulated ("" when it was).
    seconds : dict of str to float
        Wall time of each step: plan, poses, timing, program, simulation.
    yaw : {"tangent", "demonstrated"}
        Where the brush's heading came from: the path's tangent, or the
        orientation the skill learned from the demonstrations.
    """

    plan: TimedPlan
    start: np.ndarray
    goal: np.ndarray
    scene: Scene
    arm: Arm
    speed_fraction: float
    dustpan: Dustpan
    poses: np.ndarray = field(repr=False)
    joints: np.ndarray = field(repr=False)
    timing: Timing = field(repr=False)
    times: np.ndarray = field(repr=False)
    stream: np.ndarray = field(repr=False)
    program: str = field(repr=False)
    result: SweepResult | None = None
    skipped: str = ""
    seconds: dict[str, float] = field(default_factory=dict)
    yaw: str = "tangent"

    def pose_table(self) -> np.ndarray:
        """Rows ``t, x, y, z, rx, ry, rz``: when the flange passes each pose, and the pose.

        Positions in metres, orientation as a rotation vector (rad) kept
        continuous along the path (:func:`lfdkit.execute.poses.unwrap_rotvecs`),
        as ``movel`` takes it; ``t`` in seconds from the start of the motion.
        """
        vectors = pose_vector(self.poses)
        vectors[:, 3:] = unwrap_rotvecs(vectors[:, 3:])
        # A pose dropped by the timing as a repeat is passed when its twin is.
        kept = np.zeros(len(self.poses), dtype=np.intp)
        kept[self.timing.waypoint_index] = self.timing.waypoint_index
        at = np.maximum.accumulate(kept)
        time_of = np.zeros(len(self.poses))
        time_of[self.timing.waypoint_index] = self.timing.times
        return np.column_stack([time_of[at], vectors])

    def summary(self) -> dict[str, Any]:
        """What was planned, what the robot does and what the simulation found, JSON-ready."""
        dt = float(self.times[1] - self.times[0])
        speeds = np.abs(np.diff(self.stream, axis=0)) / dt
        flange = ur5.forward(self.stream, arm=self.arm)[:, :3, 3]
        tool_speed = np.linalg.norm(np.diff(flange, axis=0), axis=1) / dt
        out: dict[str, Any] = {
            "lfdkit": __version__,
            "arm": self.arm.name,
            "speed_fraction": self.speed_fraction,
            "start": self.start.tolist(),
            "goal": self.goal.tolist(),
            "scene": [
                {"class": o.label, "position": o.position.tolist(), "radius": float(o.radius)}
                for o in self.scene
            ],
            "dustpan": {"position": self.dustpan.position.tolist(), "yaw": self.dustpan.yaw},
            "plan": {
                "points": len(self.plan.positions),
                "length_m": path_length(self.plan.positions),
                "goal_error_m": float(self.plan.details.goal_error),
                # Beyond every obstacle's radius plus the brush's half width.
                "clearance_m": _smallest(self.plan.details.clearance),
                "goal_approach_m": GOAL_APPROACH,
                "tool_clearance_m": 0.5 * BRUSH.width,
            },
            "robot": {
                "poses": len(self.poses),
                "yaw": self.yaw,
                "motion_s": float(self.timing.duration),
                "servo_rate_hz": SERVO_RATE,
                "samples": len(self.stream),
                "joint_speed_of_limit": float((speeds / self.arm.max_joint_speed).max()),
                "tool_speed_max_m_s": float(tool_speed.max()),
            },
            "seconds": dict(self.seconds),
        }
        result = self.result
        if result is None:
            out["simulation"] = {"skipped": self.skipped}
            return out
        trace = result.tool_trace[:, :2]
        clearance = (
            _smallest(self.scene.distances(trace)) - 0.5 * BRUSH.width
            if len(self.scene) and len(trace)
            else None
        )
        out["simulation"] = {
            "success": result.success,
            "summary": result.summary(),
            "failures": list(result.failures),
            "cube_in_dustpan": result.cube_in_dustpan,
            "touched": [int(i) for i in result.touched],
            "tracking_error_m": _number(result.tracking_error),
            "path_error_m": _number(result.path_error),
            # The simulated flange's distance to the nearest surface, less the brush's half width.
            "clearance_m": clearance,
            "cube_in_dustpan_frame_m": self.dustpan.local(result.cube_final).tolist(),
            "rendered": result.image is not None,
        }
        return out

    def top_view(self, title: str = "") -> Any:
        """A matplotlib figure of the simulated sweep from above (:func:`sweep_figure`).

        Raises
        ------
        ValueError
            When the sweep was not simulated.
        """
        if self.result is None:
            raise ValueError(f"the sweep was not simulated ({self.skipped})")
        from lfdkit.tasks.sweeping.figures import sweep_figure

        return sweep_figure(self.dustpan, self.scene, {"learned skill": self.result}, title=title)

    def render_view(self, title: str = "") -> Any:
        """MuJoCo's picture of the simulated sweep with its key (:func:`render_figure`).

        Raises
        ------
        ValueError
            When nothing was rendered (``result.image`` is None).
        """
        if self.result is None or self.result.image is None:
            raise ValueError("render_view: no picture was rendered; execute with render=True")
        from lfdkit.tasks.sweeping.figures import render_figure

        return render_figure(self.result.image, self.scene, title=title)


def execute_skill(
    skill: Skill,
    start: Any = None,
    goal: Any = None,
    scene: Scene | None = None,
    *,
    arm: Arm = UR5,
    speed_fraction: float = 0.2,
    simulate: bool = True,
    render: bool = False,
    header: str | None = None,
    progress: ProgressLike = None,
    yaw: str | None = None,
    start_orientation: Any = None,
    goal_orientation: Any = None,
    unknown_class: float | None = None,
    unknown_response: str | None = None,
    via: Any = None,
) -> SweepExecution:
    """Plan a sweep with a skill and carry it to the robot, checked and simulated.

    Parameters
    ----------
    skill : Skill
        A fitted 2-D skill in metres (a path on the table).
    start, goal : array_like, shape (2,), optional
        Default: the skill's generalized path's own. The dustpan stands at
        ``goal``, facing ``start``.
    scene : Scene, optional
        Obstacles on the table, of classes the skill has learned. An obstacle
        with radius 0 gets its class's (:func:`obstacle_class`): that is how
        it stands in the simulation, so the plan keeps clear of it.
    arm : Arm
        A UR-type arm (default the UR5; :data:`lfdkit.execute.arm.UR10`).
    speed_fraction : float
        In ``(0, 1]``: the fraction of the arm's joint speed limits (and its
        square of the acceleration limits) the motion is timed at.
    simulate : bool
        Run the sweep in MuJoCo (skipped, with a reason, when MuJoCo is missing).
    render : bool
        Also render the end of the simulated sweep (when OpenGL works).
    header : str, optional
        A comment line for the URScript program.
    progress : Progress, callable, bool or None
        Reports each step (:func:`lfdkit.core.progress.as_progress`); default silent.
    yaw : {"demonstrated", "tangent"}, optional
        The brush's heading along the sweep: ``"demonstrated"`` follows the
        orientation the skill learned (the heading of the plan's
        orientations, :func:`lfdkit.execute.poses.yaw_from_quaternions`),
        ``"tangent"`` the path's tangent. Default: demonstrated for a skill
        with orientation (:attr:`lfdkit.skill.Skill.orientation_dmp_`),
        else tangent.
    start_orientation, goal_orientation : array_like, shape (4,), optional
        The tool's orientation at the start and goal, for a skill with
        orientation (:meth:`lfdkit.skill.Skill.plan`); default the learned ones.
    unknown_class : float, optional
        Margin (m) for obstacles of a class the skill never learned: a hard
        radius plus this, no learned response, with a warning
        (:meth:`lfdkit.skill.Skill.plan_details`); default None refuses them.
    unknown_response : str, optional
        The response such an obstacle gets besides: None (none), ``"nearest"``
        (the learned class nearest in size) or a learned class's name
        (:meth:`lfdkit.skill.Skill.plan_details`).
    via : sequence of (float, array_like (2,)[, array_like (4,)]), optional
        Via-points the sweep passes, ``(phase, point)`` with the phase a
        fraction of the plan's duration (:meth:`lfdkit.skill.Skill.plan`).

    Returns
    -------
    SweepExecution

    Raises
    ------
    ExecutionError
        When the robot cannot follow the plan: a pose out of reach, no
        solution within the joint limits, a singularity or branch flip, a
        sample over the arm's limits, the tool faster than
        :data:`~lfdkit.execute.urscript.MAX_TOOL_SPEED`; the message names the
        pose or sample and where it is.
    lfdkit.emulate.UnsafePlanError
        When no plan keeps out of the obstacles.
    ValueError
        For a skill that is not 2-D in metres, bad points, a scene with a
        class the skill has not learned (without ``unknown_class``) or with moving obstacles,
        ``speed_fraction`` outside ``(0, 1]``.
    """
    arm = check_arm(arm)
    if not arm.ur_type:
        raise TypeError(f"arm: the {arm.name} is not a UR-type arm (no analytic inverse)")
    if not isinstance(skill, Skill):
        raise TypeError(f"skill: expected an lfdkit.skill.Skill, got {type(skill).__name__}")
    if getattr(skill, "n_dims_", None) != 2:
        raise ValueError(
            f"skill: is {getattr(skill, 'n_dims_', '?')}-D; the robot sweeps a 2-D path "
            "on the table"
        )
    if skill.units != "m":
        raise ValueError(f"skill: is in {skill.units!r}; the robot needs a skill in metres ('m')")
    fraction = float(speed_fraction)
    if not 0.0 < fraction <= 1.0:
        raise ValueError(f"speed_fraction: must be in (0, 1], got {speed_fraction!r}")
    oriented = getattr(skill, "orientation_dmp_", None) is not None
    if yaw is None:
        yaw = "demonstrated" if oriented else "tangent"
    if yaw not in ("demonstrated", "tangent"):
        raise ValueError(f"yaw: expected 'demonstrated' or 'tangent', got {yaw!r}")
    if yaw == "demonstrated" and not oriented:
        raise ValueError(
            "yaw: 'demonstrated' needs a skill learned with orientations (qx, qy, qz, qw); "
            "this one has none"
        )
    start = skill.path_[0] if start is None else np.asarray(start, dtype=np.float64)
    goal = skill.path_[-1] if goal is None else np.asarray(goal, dtype=np.float64)
    scene = _standing(Scene() if scene is None else scene)
    if scene.moving:
        # The robot's time-optimal timing is not the plan's: a moving obstacle would be
        # avoided where it is at the wrong moment.
        raise ValueError(
            "scene: has moving obstacles; execute_skill times the sweep by the arm's limits, "
            "not by the plan the obstacles were predicted for. Run the closed loop of "
            "lfdkit.tasks.sweeping.moving (run_moving, simulate_run) instead"
        )
    _check_base_clear(scene, arm)
    progress = as_progress(progress)
    seconds: dict[str, float] = {}

    with progress.stage(f"plan the sweep around {len(scene)} obstacles") as stage:
        timed = skill.plan(
            start,
            goal,
            scene,
            start_orientation=start_orientation,
            goal_orientation=goal_orientation,
            **PLAN_SETTINGS,
            unknown_class=unknown_class,
            unknown_response=unknown_response,
            progress=progress,
            via=via,
        )
        plan = timed.details
    seconds["plan"] = stage.seconds
    headings = None
    if yaw == "demonstrated":
        try:
            headings = yaw_from_quaternions(timed.orientations)
        except ValueError as exc:
            raise ExecutionError(f"the demonstrated orientation: {exc}") from None
    with progress.stage(f"robot: flange poses and inverse kinematics ({arm.name})") as stage:
        try:
            poses, joints = sweep_motion(plan.points, arm=arm, yaw=headings)
        except ur5.KinematicsError as exc:
            raise ExecutionError(_where(exc, arm, plan.points)) from None
    seconds["poses"] = stage.seconds
    label = f"robot: timing at {fraction:.0%} of the {arm.name}'s joint limits"
    with progress.stage(label) as stage:
        timing = time_parameterize(joints, arm=arm, speed_fraction=fraction)
    seconds["timing"] = stage.seconds
    with progress.stage(f"robot: URScript servoj stream at {SERVO_RATE:g} Hz") as stage:
        samples = timing.resample(SERVO_RATE)
        times, stream = samples.times, samples.positions
        check_tool_speed(times, stream, arm)
        try:
            program = urscript_program(
                motion="servoj",
                times=times,
                joint_path=stream,
                header=header,
                workspace=_workspace(arm),
                arm=arm,
                speed_fraction=fraction,
            )
        except ValueError as exc:  # a sample over the arm's limits, named
            raise ExecutionError(f"the {arm.name} cannot run the motion: {exc}") from None
    seconds["program"] = stage.seconds

    dustpan = Dustpan.for_sweep(start, goal)
    execution = SweepExecution(
        plan=timed,
        start=start,
        goal=goal,
        scene=scene,
        arm=arm,
        speed_fraction=fraction,
        dustpan=dustpan,
        poses=poses,
        joints=joints,
        timing=timing,
        times=times,
        stream=stream,
        program=program,
        seconds=seconds,
        yaw=yaw,
    )
    if not simulate:
        execution.skipped = "not asked for"
        return execution
    task = SweepingTask.for_path(plan.points, dustpan, scene)
    with progress.stage(f"simulate the sweep in MuJoCo ({arm.name})") as stage:
        try:
            execution.result = simulate_sweep(
                timing, task, render=render, arm=arm, progress=progress
            )
        except ImportError as exc:  # MuJoCo is a dependency, but may be broken or missing
            execution.skipped = f"MuJoCo is not available ({exc})"
    seconds["simulation"] = stage.seconds
    return execution


def execution_outputs(
    folder: str | os.PathLike[str], *, simulate: bool = True, render: bool = False
) -> list[Path]:
    """The files :func:`write_execution` may write in ``folder`` (pictures when simulated)."""
    out = Path(folder)
    files = [out / name for name in (_PLAN, _POSES, _JOINTS, _PROGRAM, _SUMMARY)]
    if simulate:
        files.append(out / _TOP_VIEW)
        if render:
            files.append(out / _RENDER)
    return files


def write_execution(
    folder: str | os.PathLike[str],
    execution: SweepExecution,
    *,
    overwrite: bool = False,
    extra: dict[str, Any] | None = None,
) -> list[Path]:
    """Write an execution's files in ``folder`` (which must exist), each atomically.

    ``plan.csv`` (``t,x,y``, s and m, and ``qx,qy,qz,qw`` for a skill with
    orientation), ``poses.csv`` (:meth:`SweepExecution.pose_table`),
    ``joints.csv`` (``t, q1 … qn``: the streamed samples, s and rad),
    ``program.script`` (URScript), ``summary.json``
    (:meth:`SweepExecution.summary` with ``extra`` and the list of files) and,
    when simulated, ``sweep.png`` (top view) and ``render.png`` (MuJoCo's
    picture with its key, when one was rendered).

    Returns
    -------
    list of Path
        The files written.

    Raises
    ------
    FileExistsError
        If a file exists and ``overwrite`` is false, before anything is written.
    """
    out = Path(folder)
    planned = [out / _PLAN, out / _POSES, out / _JOINTS, out / _PROGRAM]
    figure = None
    if execution.result is not None:
        planned.append(out / _TOP_VIEW)
        if execution.result.image is not None:
            planned.append(out / _RENDER)
    planned.append(out / _SUMMARY)
    clash = [p for p in planned if p.exists()]
    if clash and not overwrite:
        raise FileExistsError(f"{clash[0]}: exists; pass overwrite=True to replace it")

    save_path(
        out / _PLAN,
        execution.plan.positions,
        times=execution.plan.times,
        orientations=execution.plan.orientations,
        overwrite=overwrite,
    )
    columns = ["t", "x", "y", "z", "rx", "ry", "rz"]
    write_text(out / _POSES, _table(columns, execution.pose_table()), overwrite=overwrite)
    joints = np.column_stack([execution.times, execution.stream])
    columns = ["t", *(f"q{j + 1}" for j in range(execution.arm.n_joints))]
    write_text(out / _JOINTS, _table(columns, joints), overwrite=overwrite)
    write_text(out / _PROGRAM, execution.program, overwrite=overwrite)
    if execution.result is not None:
        figure = execution.top_view(f"{execution.arm.name} sweep in MuJoCo (top view)")
        atomic_write(
            out / _TOP_VIEW,
            lambda f: figure.savefig(f, format="png", dpi=110),
            binary=True,
            overwrite=overwrite,
        )
        import matplotlib.pyplot as plt

        plt.close(figure)
        if execution.result.image is not None:
            picture = execution.render_view(f"{execution.arm.name} sweep in MuJoCo (render)")
            atomic_write(
                out / _RENDER,
                lambda f: picture.savefig(f, format="png", dpi=110),
                binary=True,
                overwrite=overwrite,
            )
    summary = {**execution.summary(), **(extra or {})}
    summary["files"] = [p.name for p in planned]
    text = json.dumps(summary, indent=1, allow_nan=False) + "\n"
    write_text(out / _SUMMARY, text, overwrite=overwrite)
    return planned


# ------------------------------------------------------------------ helpers
def _standing(scene: Scene) -> Scene:
    """The scene with each obstacle's radius as it stands: its own, or its class's."""
    if not isinstance(scene, Scene):
        raise TypeError(f"scene: expected a Scene, got {type(scene).__name__}")
    return Scene(
        tuple(replace(o, radius=obstacle_class(o.label).cylinder_radius(o)) for o in scene)
    )


def _check_base_clear(scene: Scene, arm: Arm) -> None:
    """Refuse an obstacle that reaches the arm's base (the table's origin): the robot stands there.

    A wall (a half-plane) below the sweep holds the base: MuJoCo's plane is
    infinite, so the simulated arm starts inside it, and so would the real one.
    """
    base_radius = float(arm.link_radii[0])
    for k, obstacle in enumerate(scene):
        reach = obstacle.distance(np.zeros((1, 2)))
        if reach < base_radius:
            where = (
                f"the base's centre {-100 * reach:.1f} cm inside it"
                if reach < 0.0
                else f"{100 * reach:.1f} cm from the base's centre, within its "
                f"{100 * base_radius:.1f} cm"
            )
            raise ValueError(
                f"scene: obstacle {k} ({obstacle.label!r}, {obstacle.shape}) reaches the arm's "
                f"base at the origin ({where}): the robot stands there; give a wall the normal "
                "that points toward the arm (its free side holds the arm) or place the "
                "obstacle beyond the base"
            )


def _workspace(arm: Arm) -> Workspace:
    """The default box (on or above the table) widened to the arm's reach."""
    reach = float(np.abs(arm.a).sum() + np.abs(arm.d).sum())
    half = max(Workspace().upper[0], round(reach + 0.05, 2))
    return Workspace((-half, -half, TABLE_Z), (half, half, half))


def _where(exc: ur5.KinematicsError, arm: Arm, path: np.ndarray) -> str:
    """A kinematics error as one line: what, the pose, and how far along the sweep."""
    text = str(exc)
    if exc.index is not None:
        # sweep_motion puts a pose every 2 mm of the (smoothed) path.
        along = min(0.002 * exc.index, path_length(path))
        text += f" ({along:.3f} m along the {path_length(path):.3f} m sweep)"
    return f"the {arm.name} cannot follow the plan: {text}"


def _table(columns: list[str], rows: np.ndarray) -> str:
    """CSV text: a header, then one row per line, floats written exactly (``repr``)."""
    lines = [",".join(columns)]
    lines += [",".join(repr(float(v)) for v in row) for row in rows]
    return "\n".join(lines) + "\n"


def _smallest(values: np.ndarray) -> float | None:
    """The smallest of some distances as a float, None when there are none."""
    return float(np.min(values)) if len(values) else None


def _number(value: float) -> float | None:
    """A float for JSON: None for NaN."""
    return float(value) if np.isfinite(value) else None
