"""Any learned plan on any arm: plan → tool poses → IK → the person's timing → samples → program.

:func:`execute_plan` carries a timed plan (what :meth:`lfdkit.skill.Skill.plan`
returns: ``times``, ``positions`` and, for a skill with orientation,
``orientations``) to an arm, for any task described by a small
:class:`TaskDescription` (where the skill's frame sits in the robot's base
frame, the tool on the flange, the plane height of a 2-D skill, the tool
orientation when the skill learned none):

1. **check**: the plan in metres and sensible for an arm (a 500 m path or a
   tool at 400 m/s is refused as "millimetres read as metres?");
2. **tool poses**: the plan resampled at :data:`WAYPOINT_RATE` (100 Hz,
   cubic in time, orientations by slerp), placed by the description;
3. **inverse kinematics**: one continuous branch
   (:func:`lfdkit.execute.kinematics.joint_path`: analytic for UR-type arms,
   numerical for others, e.g. a :class:`lfdkit.execute.urdf.UrdfArm`); a pose
   beyond reach is refused as "out of reach (distance d m > reach r m)";
4. **timing**: the plan's own times, stretched only where the arm's limits
   times the speed fraction require (:func:`lfdkit.execute.trajectory.keep_timing`;
   :attr:`RobotExecution.timing_note` says by how much and where);
5. **samples** at a fixed rate (``rate``, 125 Hz by default; 500 Hz for an
   e-Series), positions, velocities and accelerations;
6. **program**: a URScript ``servoj`` stream for a UR-type arm (its first
   ``movej`` within the speed fraction), and for every arm a
   ``trajectory_msgs/JointTrajectory``-shaped file.

Task-specific extras (the sweeping task's brush, dustpan and simulation) stay
in their task, :mod:`lfdkit.tasks.sweeping`, which uses steps 3 and 6.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.spatial.transform import Rotation, Slerp

from lfdkit import __version__
from lfdkit.core.geometry import path_length
from lfdkit.execute import ur5
from lfdkit.execute.arm import Arm
from lfdkit.execute.kinematics import AnyArm, check_any_arm, forward, joint_path, reach
from lfdkit.execute.trajectory import JointTrajectory, keep_timing
from lfdkit.execute.urdf import UrdfArm
from lfdkit.execute.urscript import MAX_TOOL_SPEED, Workspace, urscript_program
from lfdkit.imitate.timing import minimum_jerk_law
from lfdkit.io import write_text
from lfdkit.model.timed_path import TimedPath

__all__ = [
    "DEFAULT_RATE",
    "UR_START",
    "WAYPOINT_RATE",
    "ExecutionError",
    "RobotExecution",
    "TaskDescription",
    "check_tool_speed",
    "execute_plan",
    "robot_outputs",
    "write_robot_execution",
]

#: Rate at which the plan is resampled into tool poses for the inverse kinematics (Hz).
WAYPOINT_RATE = 100.0
#: Mean tool speed of a task's approach and retreat moves (m/s): a careful hand's.
APPROACH_SPEED = 0.1
#: Rate of the fixed-rate samples and the ``servoj`` stream (Hz): a CB-series controller's tick.
DEFAULT_RATE = 125.0
#: The configuration that picks a UR arm's branch: elbow up, tool down (the sweeping task's home).
UR_START = (0.0, -1.2, 1.6, -1.97, -1.5708, 0.0)
#: Beyond these a plan is taken for a unit mistake (m, m/s): no arm sweeps 20 m or moves at 5 m/s.
_ABSURD_LENGTH, _ABSURD_SPEED = 20.0, 5.0

_PLAN, _TRAJ_CSV, _TRAJ_JSON = "plan.csv", "trajectory.csv", "trajectory.json"
_PROGRAM, _SUMMARY = "program.script", "summary.json"


class ExecutionError(ValueError):
    """What the robot cannot do with a plan: the message names what and where."""


def _transform(value: Any, name: str) -> np.ndarray:
    arr = np.array(value, dtype=np.float64)
    if arr.shape != (4, 4) or not np.isfinite(arr).all():
        raise ValueError(f"{name}: expected a finite 4x4 transform, got shape {arr.shape}")
    rot = arr[:3, :3]
    if np.abs(rot @ rot.T - np.eye(3)).max() > 1e-6 or np.abs(arr[3] - [0, 0, 0, 1]).max() > 0:
        raise ValueError(f"{name}: is not a rigid transform (orthonormal rotation, row 0 0 0 1)")
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class TaskDescription:
    """Where and with what tool a skill's plan runs on an arm.

    Parameters
    ----------
    frame : array_like, shape (4, 4)
        The skill's frame in the robot's base frame (metres): a plan point
        ``p`` goes to ``frame @ p``. Default: the base frame.
    tool : array_like, shape (4, 4)
        Flange→tool transform (the tool centre point the plan moves), metres.
    height : float
        For a 2-D skill: the height (m) of its plane in the skill's frame.
    orientation : array_like, shape (4,)
        The tool's orientation (quaternion ``x, y, z, w``, in the skill's
        frame) when the skill learned none; default tool ``z`` pointing down.
    q_start : array_like, shape (n_joints,), optional
        Picks the arm's branch: the first pose's solution nearest to it.
        Default: :data:`UR_START` for a UR-type arm, the middle of the joint
        limits otherwise.
    name : str
        Shown in messages and the summary.
    approach, retreat : float
        Straight moves (m) along the tool's ``z`` axis: into the plan's first
        pose from ``approach`` metres back, and out of its last pose
        ``retreat`` metres back (default 0: none), each at rest at both ends,
        minimum jerk, at :data:`APPROACH_SPEED` on average (at least 1 s).
    """

    frame: Any = field(default_factory=lambda: np.eye(4))
    tool: Any = field(default_factory=lambda: np.eye(4))
    height: float = 0.0
    orientation: Any = (1.0, 0.0, 0.0, 0.0)
    q_start: Any = None
    name: str = "task"
    approach: float = 0.0
    retreat: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "frame", _transform(self.frame, "frame"))
        object.__setattr__(self, "tool", _transform(self.tool, "tool"))
        quat = np.array(self.orientation, dtype=np.float64)
        if quat.shape != (4,) or not np.isfinite(quat).all() or np.linalg.norm(quat) < 1e-9:
            raise ValueError(f"orientation: expected a quaternion (x, y, z, w), got {quat!r}")
        object.__setattr__(self, "orientation", quat / np.linalg.norm(quat))
        try:
            height = float(self.height)
        except (TypeError, ValueError):
            height = float("nan")
        if not np.isfinite(height):
            raise ValueError(f"height: must be a finite number of metres, got {self.height!r}")
        object.__setattr__(self, "height", height)
        for name in ("approach", "retreat"):
            try:
                value = float(getattr(self, name))
            except (TypeError, ValueError):
                value = float("nan")
            if not 0.0 <= value <= 1.0:
                raise ValueError(
                    f"{name}: expected a distance from 0 to 1 m, got {getattr(self, name)!r}"
                )
            object.__setattr__(self, name, value)

    def to_dict(self) -> dict[str, Any]:
        """The description, JSON-ready (:meth:`from_dict` reads it back exactly)."""
        return {
            "name": self.name,
            "frame": self.frame.tolist(),
            "tool": self.tool.tolist(),
            "height": float(self.height),
            "orientation": self.orientation.tolist(),
            "q_start": None if self.q_start is None else np.asarray(self.q_start, float).tolist(),
            "approach": float(self.approach),
            "retreat": float(self.retreat),
        }

    @classmethod
    def from_dict(cls, data: Any, source: str = "task") -> TaskDescription:
        """A description from a mapping (a task file's JSON), one-line errors naming ``source``.

        Keys: those of :meth:`to_dict`; ``offset`` ``[x, y, z]`` (m) may stand
        for a ``frame`` that only translates, ``tool_length`` (m, along the
        flange's ``z``) for a ``tool`` that only offsets. All are optional.
        """
        if not isinstance(data, dict):
            raise ValueError(f"{source}: expected a JSON object, got {type(data).__name__}")
        known = {"name", "frame", "tool", "height", "orientation", "q_start", "approach", "retreat"}
        unknown = sorted(set(data) - known - {"offset", "tool_length"})
        if unknown:
            raise ValueError(
                f"{source}: unknown key {unknown[0]!r}; expected some of "
                f"{', '.join(sorted(known | {'offset', 'tool_length'}))}"
            )
        fields = {k: v for k, v in data.items() if k in known}
        for short, full in (("offset", "frame"), ("tool_length", "tool")):
            if short in data and full in data:
                raise ValueError(f"{source}: give {short!r} or {full!r}, not both")
        try:
            if "offset" in data:
                offset = np.asarray(data["offset"], dtype=np.float64)
                if offset.shape != (3,):
                    raise ValueError(
                        f"offset: expected [x, y, z] in metres, got {data['offset']!r}"
                    )
                fields["frame"] = np.eye(4)
                fields["frame"][:3, 3] = offset
            if "tool_length" in data:
                fields["tool"] = np.eye(4)
                fields["tool"][2, 3] = float(data["tool_length"])
            if fields.get("q_start") is not None:
                fields["q_start"] = tuple(float(v) for v in fields["q_start"])
            return cls(**fields)
        except (TypeError, ValueError) as exc:
            raise ValueError(f"{source}: {str(exc).splitlines()[0]}") from None

    def start_configuration(self, arm: AnyArm) -> np.ndarray:
        """``q_start``, or the default for ``arm``."""
        if self.q_start is not None:
            q = np.asarray(self.q_start, dtype=np.float64)
            if q.shape != (arm.n_joints,):
                raise ValueError(
                    f"q_start: expected {arm.n_joints} values for the {arm.name}, got {q.shape}"
                )
            return q
        if isinstance(arm, Arm) and arm.ur_type:
            return np.array(UR_START)
        return arm.joint_limits.mean(axis=1)

    def poses(self, positions: np.ndarray, orientations: np.ndarray | None) -> np.ndarray:
        """Tool poses in the base frame, (m, 4, 4), of plan points (m, 2 or 3) and quaternions."""
        m = len(positions)
        points = positions
        if positions.shape[1] == 2:
            points = np.column_stack((positions, np.full(m, float(self.height))))
        quats = np.broadcast_to(self.orientation, (m, 4)) if orientations is None else orientations
        local = np.tile(np.eye(4), (m, 1, 1))
        local[:, :3, :3] = Rotation.from_quat(quats).as_matrix()
        local[:, :3, 3] = points
        return self.frame @ local


@dataclass
class RobotExecution:
    """A plan carried to an arm: poses, joints, the timed trajectory, samples and program.

    Attributes
    ----------
    arm : Arm or UrdfArm
    task : TaskDescription
    plan : TimedPath
        The plan as carried: ``times`` (n,) in s from 0 (repeated times
        dropped), ``positions`` (n, 2 or 3) in m in the skill frame,
        ``orientations`` (n, 4) or None; no velocities.
    poses : ndarray, shape (m, 4, 4)
        Tool poses at :data:`WAYPOINT_RATE`, base frame.
    trajectory : JointTrajectory
        The joint waypoints with the kept (or stretched) timing.
    rate : float
        Rate of the samples (Hz).
    samples : TimedPath
        ``times`` (k,) at ``rate``; joint ``positions``, ``velocities`` and
        ``accelerations`` (k, n_joints).
    program : str or None
        The URScript program (UR-type arms), None otherwise.
    speed_fraction : float
    """

    arm: AnyArm
    task: TaskDescription
    plan: TimedPath = field(repr=False)
    poses: np.ndarray = field(repr=False)
    trajectory: JointTrajectory = field(repr=False)
    rate: float
    samples: TimedPath = field(repr=False)
    program: str | None = field(repr=False)
    speed_fraction: float

    @property
    def timing_note(self) -> str:
        """One line: the plan's timing kept, or slowed by how much and where."""
        return self.trajectory.describe_slowdowns()

    def summary(self) -> dict[str, Any]:
        """What was planned and what the robot does, JSON-ready."""
        samples = self.samples
        t, q, qd, qdd = samples.times, samples.positions, samples.velocities, samples.accelerations
        tool = forward(self.arm, q, self.task.tool)[:, :3, 3]
        tool_speed = np.linalg.norm(np.diff(tool, axis=0), axis=1) * self.rate
        traj = self.trajectory
        return {
            "lfdkit": __version__,
            "arm": self.arm.name,
            "joints": list(traj.joint_names),
            "task": self.task.name,
            "speed_fraction": self.speed_fraction,
            "plan": {
                "points": len(self.plan.times),
                "dims": int(self.plan.positions.shape[1]),
                "length_m": path_length(self.plan.positions),
                "duration_s": self.plan.duration,
            },
            "robot": {
                "poses": len(self.poses),
                "motion_s": traj.duration,
                "duration_ratio": traj.duration / traj.planned_duration,
                "timing": self.timing_note,
                "slowdowns": [vars(s) for s in traj.slowdowns],
                "rate_hz": self.rate,
                "samples": len(t),
                "joint_speed_of_limit": float((np.abs(qd) / self.arm.max_joint_speed).max()),
                "joint_acceleration_of_limit": float(
                    (np.abs(qdd) / self.arm.max_joint_acceleration).max()
                ),
                "tool_speed_max_m_s": float(tool_speed.max()) if len(tool_speed) else 0.0,
                "program": "urscript servoj" if self.program is not None else None,
            },
        }


def _check_plan(plan: Any, arm: AnyArm) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    try:
        times = np.asarray(plan.times, dtype=np.float64)
        positions = np.asarray(plan.positions, dtype=np.float64)
    except AttributeError:
        raise TypeError(
            f"plan: expected a timed plan (times, positions), e.g. Skill.plan's; got "
            f"{type(plan).__name__}"
        ) from None
    orientations = getattr(plan, "orientations", None)
    if positions.ndim != 2 or positions.shape[1] not in (2, 3) or len(positions) != len(times):
        raise ValueError(
            f"plan: expected (n, 2) or (n, 3) positions with one time each, got {positions.shape} "
            f"and {times.shape}"
        )
    if len(times) < 2 or not np.isfinite(positions).all() or not np.isfinite(times).all():
        raise ValueError("plan: needs at least 2 finite points and times")
    keep = np.concatenate(([True], np.diff(times) > 1e-12))  # a repeated time adds nothing
    if (np.diff(times) < -1e-12).any():
        raise ValueError("plan: its times decrease; expected them from 0, increasing")
    times, positions = times[keep], positions[keep]
    if orientations is not None:
        orientations = np.asarray(orientations, dtype=np.float64)[keep]
    length = path_length(positions)
    speed = float((np.linalg.norm(np.diff(positions, axis=0), axis=1) / np.diff(times)).max())
    _, arm_reach = reach(arm)
    if length > _ABSURD_LENGTH or speed > _ABSURD_SPEED:
        raise ValueError(
            f"plan: a {length:.4g} m path at up to {speed:.4g} m/s is absurd for the {arm.name} "
            f"(reach {arm_reach:.2f} m); is the skill in millimetres or centimetres read as "
            "metres? Convert it with Skill.to_units('m')"
        )
    return times, positions, orientations


def _waypoints(
    times: np.ndarray, positions: np.ndarray, orientations: np.ndarray | None
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """The plan at :data:`WAYPOINT_RATE` (and its last instant): cubic in time, slerped."""
    duration = times[-1] - times[0]
    count = max(2, int(np.ceil(duration * WAYPOINT_RATE)) + 1)
    at = np.linspace(times[0], times[-1], count)
    points = CubicSpline(times, positions, bc_type="clamped", axis=0)(at)
    quats = None
    if orientations is not None:
        quats = Slerp(times, Rotation.from_quat(orientations))(at).as_quat()
    return at - times[0], points, quats


def _straight(pose: np.ndarray, distance: float, into: bool) -> tuple[np.ndarray, np.ndarray]:
    """A minimum-jerk move along ``pose``'s z axis: into it from ``distance`` back, or out.

    Returns the times (s, from 0) and poses (m, 4, 4) after the first (into: before ``pose``,
    which is left out; out: after it).
    """
    duration = max(1.0, distance / APPROACH_SPEED)
    count = max(2, int(np.ceil(duration * WAYPOINT_RATE)) + 1)
    u = np.linspace(0.0, 1.0, count)
    s = minimum_jerk_law(u)[0]  # at rest at both ends
    back = (1.0 - s[:-1]) if into else s[1:]
    moved = np.repeat(pose[None], len(back), axis=0)
    moved[:, :3, 3] -= back[:, None] * distance * pose[:3, 2]
    return u[:-1] * duration if into else u[1:] * duration, moved


def _with_approach(
    at: np.ndarray, poses: np.ndarray, task: TaskDescription
) -> tuple[np.ndarray, np.ndarray]:
    """The task's approach before and retreat after the plan's poses, with their times."""
    if task.approach > 0.0:
        t, moves = _straight(poses[0], task.approach, into=True)
        step = t[1] - t[0]  # the plan's first pose comes one step after the last of the move
        at, poses = np.concatenate((t, at + t[-1] + step)), np.concatenate((moves, poses))
    if task.retreat > 0.0:
        t, moves = _straight(poses[-1], task.retreat, into=False)
        at, poses = np.concatenate((at, at[-1] + t)), np.concatenate((poses, moves))
    return at, poses


def check_tool_speed(times: np.ndarray, stream: np.ndarray, arm: AnyArm, tool: Any = None) -> None:
    """Refuse a stream that moves the tool faster than ``MAX_TOOL_SPEED``, naming when and where."""
    point = forward(arm, stream, tool)[:, :3, 3]
    dt = float(times[1] - times[0])
    speed = np.linalg.norm(np.diff(point, axis=0), axis=1) / dt
    k = int(np.argmax(speed))
    if speed[k] > MAX_TOOL_SPEED:
        x, y, _ = point[k + 1]
        raise ExecutionError(
            f"the {arm.name} cannot run the motion: the tool would move at {speed[k]:.3g} m/s "
            f"at t = {times[k + 1]:.2f} s, at ({x:.3f}, {y:.3f}) m, above the "
            f"{MAX_TOOL_SPEED:g} m/s limit; lower the speed fraction"
        )


def execute_plan(
    plan: Any,
    arm: AnyArm,
    task: TaskDescription | None = None,
    *,
    speed_fraction: float = 0.2,
    rate: float = DEFAULT_RATE,
    header: str | None = None,
) -> RobotExecution:
    """Carry a timed plan to an arm, keeping its timing where the arm's limits allow.

    Parameters
    ----------
    plan : TimedPlan
        ``times`` (n,) s, ``positions`` (n, 2 or 3) m, and optionally
        ``orientations`` (n, 4) quaternions ``x, y, z, w``
        (:meth:`lfdkit.skill.Skill.plan`).
    arm : Arm or UrdfArm
    task : TaskDescription, optional
        Frame, tool, plane height, default orientation, start configuration.
    speed_fraction : float
        In ``(0, 1]``: the fraction of the joint speed limits (its square of
        the acceleration limits) the motion may use; the plan's timing is
        kept where it stays within them.
    rate : float
        Rate of the fixed-rate samples and the ``servoj`` stream (Hz), 1–1000.
    header : str, optional
        A comment line for the URScript program.

    Returns
    -------
    RobotExecution

    Raises
    ------
    ExecutionError
        A pose out of reach ("out of reach (distance d m > reach r m)"), a
        joint limit (naming the joint), a branch jump, a tool faster than
        :data:`~lfdkit.execute.urscript.MAX_TOOL_SPEED`; each names the pose.
    ValueError
        A plan that is not in metres or absurd for the arm, bad arguments.
    """
    arm = check_any_arm(arm)
    task = TaskDescription() if task is None else task
    if not isinstance(task, TaskDescription):
        raise TypeError(f"task: expected a TaskDescription, got {type(task).__name__}")
    fraction = float(speed_fraction)
    if not 0.0 < fraction <= 1.0:
        raise ValueError(f"speed_fraction: must be in (0, 1], got {speed_fraction!r}")
    rate = float(rate)
    if not 1.0 <= rate <= 1000.0:
        raise ValueError(f"rate: must be in [1, 1000] Hz, got {rate!r}")
    times, positions, orientations = _check_plan(plan, arm)
    at, points, quats = _waypoints(times, positions, orientations)
    at, poses = _with_approach(at, task.poses(points, quats), task)
    try:
        joints = joint_path(poses, arm, task.start_configuration(arm), tool=task.tool)
    except ur5.KinematicsError as exc:
        text = str(exc)
        if exc.index is not None:
            text += f" (t = {at[exc.index]:.2f} s of the {at[-1]:.2f} s plan)"
        raise ExecutionError(f"the {arm.name} cannot follow the plan: {text}") from None
    names = arm.joint_names if isinstance(arm, UrdfArm) else ()
    trajectory = keep_timing(
        at,
        joints,
        arm.max_joint_speed * fraction,
        arm.max_joint_acceleration * fraction**2,
        joint_names=names,
    )
    samples = trajectory.resample(rate)
    program = None
    if isinstance(arm, Arm) and arm.ur_type:
        check_tool_speed(samples.times, samples.positions, arm, task.tool)
        try:
            program = urscript_program(
                motion="servoj",
                name="lfdkit_skill",
                times=samples.times,
                joint_path=samples.positions,
                header=header,
                workspace=Workspace.unbounded(),
                arm=arm,
                speed_fraction=fraction,
            )
        except ValueError as exc:
            raise ExecutionError(f"the {arm.name} cannot run the motion: {exc}") from None
    return RobotExecution(
        arm=arm,
        task=task,
        plan=TimedPath(times - times[0], positions, orientations=orientations),
        poses=poses,
        trajectory=trajectory,
        rate=rate,
        samples=samples,
        program=program,
        speed_fraction=fraction,
    )


def robot_outputs(folder: str | os.PathLike[str], *, program: bool = True) -> list[Path]:
    """The files :func:`write_robot_execution` writes in ``folder``."""
    names = [_PLAN, _TRAJ_CSV, _TRAJ_JSON] + ([_PROGRAM] if program else []) + [_SUMMARY]
    return [Path(folder) / name for name in names]


def _csv_text(columns: list[str], rows: np.ndarray) -> str:
    lines = [",".join(columns)] + [",".join(repr(float(v)) for v in row) for row in rows]
    return "\n".join(lines) + "\n"


def write_robot_execution(
    folder: str | os.PathLike[str],
    execution: RobotExecution,
    *,
    overwrite: bool = False,
    extra: dict[str, Any] | None = None,
) -> list[Path]:
    """Write ``plan.csv`` (``t``, positions, quaternions), ``trajectory.csv`` (``t``,
    positions, velocities, accelerations per joint), ``trajectory.json`` (ROS
    ``JointTrajectory`` shape), ``program.script`` (UR arms) and ``summary.json``,
    each atomically; an existing file raises unless ``overwrite``, before anything is written.
    The folder is made if it is missing (as ``lfdkit execute -o FOLDER`` does).
    """
    planned = robot_outputs(folder, program=execution.program is not None)
    clash = [p for p in planned if p.exists()]
    if clash and not overwrite:
        raise FileExistsError(f"{clash[0]}: exists; pass overwrite=True to replace it")
    Path(folder).mkdir(parents=True, exist_ok=True)
    plan = execution.plan
    dims = plan.positions.shape[1]
    columns = ["t", *"xyz"[:dims]]
    rows = [plan.times[:, None], plan.positions]
    if plan.orientations is not None:
        columns += ["qx", "qy", "qz", "qw"]
        rows.append(plan.orientations)
    by_path = {p.name: p for p in planned}
    write_text(by_path[_PLAN], _csv_text(columns, np.hstack(rows)), overwrite=overwrite)
    samples = execution.samples
    t, q, qd, qdd = samples.times, samples.positions, samples.velocities, samples.accelerations
    names = execution.trajectory.joint_names
    columns = ["t", *names, *(f"{n}_vel" for n in names), *(f"{n}_acc" for n in names)]
    table = _csv_text(columns, np.hstack([t[:, None], q, qd, qdd]))
    write_text(by_path[_TRAJ_CSV], table, overwrite=overwrite)
    message = execution.trajectory.ros_message(execution.rate)
    write_text(by_path[_TRAJ_JSON], json.dumps(message) + "\n", overwrite=overwrite)
    if execution.program is not None:
        write_text(by_path[_PROGRAM], execution.program, overwrite=overwrite)
    summary = {**execution.summary(), **(extra or {}), "files": [p.name for p in planned]}
    text = json.dumps(summary, indent=1, allow_nan=False) + "\n"
    write_text(by_path[_SUMMARY], text, overwrite=overwrite)
    return planned
