"""The MuJoCo check of any arm: run a timed joint trajectory, measure tracking and contacts.

:func:`urdf_mjcf` models a :class:`lfdkit.execute.urdf.UrdfArm` the way
:mod:`lfdkit.execute.mujoco` models a DH arm: nested bodies at the URDF's
joint origins, a hinge (or slide) about each joint's axis within its limits,
a capsule from each joint to the next (radius :data:`LINK_RADIUS`, mass
:data:`LINK_MASS`: the URDF's meshes and inertias are not read), gravity
compensated, one position servo per joint. :func:`simulate_execution` plays
an execution's fixed-rate samples on it (:func:`lfdkit.execute.mujoco.arm_mjcf`
for a DH arm), with the scene's obstacles as fixed spheres (3-D skills) or
upright cylinders (2-D skills) placed by the task's frame, and reports the
largest distance between the simulated and the commanded tool point
(tracking error, m) and the obstacles any link touched.

The servo gains (:data:`KP`, :data:`KV`) are this module's choice, stiff
enough that a 6 s reach tracks within 0.1 mm on the UR5e and the Panda
(``tests/execute/test_simulation.py``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from lfdkit.execute.kinematics import forward
from lfdkit.execute.mujoco import ROBOT_CONTACT, arm_mjcf, load_mujoco, mjcf_numbers
from lfdkit.execute.urdf import UrdfArm

__all__ = [
    "KP",
    "KV",
    "LINK_MASS",
    "LINK_RADIUS",
    "SimulationCheck",
    "simulate_execution",
    "urdf_mjcf",
]

LINK_RADIUS = 0.04  # m
LINK_MASS = 2.0  # kg
KP = 3000.0  # N·m/rad (N/m for a slide)
KV = 120.0  # N·m·s/rad
_TIMESTEP = 0.002  # s
_OBSTACLE_CONTACT = 'contype="2" conaffinity="2"'  # touched by the robot's geoms


def _quat(rotation: np.ndarray) -> np.ndarray:
    """MuJoCo's (w, x, y, z) quaternion of a rotation matrix."""
    from scipy.spatial.transform import Rotation

    x, y, z, w = Rotation.from_matrix(rotation).as_quat()
    return np.array([w, x, y, z])


def urdf_mjcf(arm: UrdfArm, obstacles: str = "") -> str:
    """The MJCF of a URDF arm on the origin, with ``obstacles`` (MJCF geoms) in the world."""
    origins, axes = arm.joint_origins, arm.joint_axes
    nxt = [origins[j + 1][:3, 3] for j in range(arm.n_joints - 1)] + [arm.tip_transform[:3, 3]]
    opening, closing = [], []
    for j in range(arm.n_joints):
        pad = "  " * (j + 2)
        kind = "slide" if arm.joint_types[j] == "prismatic" else "hinge"
        child = nxt[j]
        shape = (
            f'type="capsule" fromto="0 0 0 {mjcf_numbers(child)}"'
            if np.linalg.norm(child) > 1e-9
            else 'type="sphere"'
        )
        opening += [
            f'{pad}<body name="link{j + 1}" pos="{mjcf_numbers(origins[j][:3, 3])}" '
            f'quat="{mjcf_numbers(_quat(origins[j][:3, :3]))}" gravcomp="1">',
            f'{pad}  <joint name="joint{j + 1}" type="{kind}" axis="{mjcf_numbers(axes[j])}" '
            f'range="{mjcf_numbers(arm.joint_limits[j])}" armature="0.1" damping="0.5"/>',
            f'{pad}  <geom {shape} size="{LINK_RADIUS}" mass="{LINK_MASS}" {ROBOT_CONTACT}/>',
        ]
        closing.insert(0, f"{pad}</body>")
    tip = arm.tip_transform
    pad = "  " * (arm.n_joints + 2)
    body = [
        f'{pad}<body name="flange" pos="{mjcf_numbers(tip[:3, 3])}" '
        f'quat="{mjcf_numbers(_quat(tip[:3, :3]))}">',
        f'{pad}  <site name="flange" size="0.005"/>',
        f"{pad}</body>",
    ]
    servos = "\n".join(
        f'    <position joint="joint{j + 1}" kp="{KP}" kv="{KV}"/>' for j in range(arm.n_joints)
    )
    chain = "\n".join(opening + body + closing)
    return f"""<mujoco model="lfdkit {arm.name}">
  <compiler angle="radian" autolimits="true"/>
  <option integrator="implicitfast" timestep="{_TIMESTEP}"/>
  <worldbody>
{obstacles}
{chain}
  </worldbody>
  <actuator>
{servos}
  </actuator>
</mujoco>
"""


@dataclass(frozen=True)
class SimulationCheck:
    """What MuJoCo did with an execution.

    Attributes
    ----------
    tracking_error : float
        Largest distance between the simulated and the commanded tool point (m).
    touched : tuple of int
        Indices of the obstacles a link touched.
    steps : int
        Simulation steps of :data:`_TIMESTEP` (2 ms).
    """

    tracking_error: float
    touched: tuple[int, ...]
    steps: int


def _obstacle_geoms(execution: Any, scene: Any) -> str:
    if scene is None or not len(scene):
        return ""
    frame = execution.task.frame
    lines = []
    for k, obstacle in enumerate(scene):
        centre = np.asarray(obstacle.position, dtype=np.float64)
        radius = float(obstacle.radius)
        if centre.shape == (2,):  # an upright cylinder standing on the skill's plane
            height = float(execution.task.height)
            base = frame @ np.r_[centre, 0.0, 1.0]
            shape = f'type="cylinder" size="{radius} {0.5 * height}"'
            pos = base[:3] + frame[:3, 2] * 0.5 * height
        else:
            shape = f'type="sphere" size="{radius}"'
            pos = (frame @ np.r_[centre, 1.0])[:3]
        lines.append(
            f'    <geom name="obstacle{k}" {shape} pos="{mjcf_numbers(pos)}" '
            f'rgba="0.8 0.3 0.3 0.6" {_OBSTACLE_CONTACT}/>'
        )
    return "\n".join(lines)


def simulate_execution(execution: Any, scene: Any = None) -> SimulationCheck:
    """Play an execution's fixed-rate samples in MuJoCo (:mod:`lfdkit.execute.pipeline`).

    Parameters
    ----------
    execution : RobotExecution
        Its ``arm`` (an :class:`Arm` or :class:`UrdfArm`), ``samples`` and ``task``.
    scene : Scene, optional
        Obstacles (skill frame) as fixed spheres (3-D) or upright cylinders (2-D),
        with their own ``radius``.

    Returns
    -------
    SimulationCheck
    """
    mujoco = load_mujoco()
    arm = execution.arm
    geoms = _obstacle_geoms(execution, scene)
    if isinstance(arm, UrdfArm):
        xml = urdf_mjcf(arm, geoms)
    else:
        xml = arm_mjcf(arm).replace("<worldbody>\n", f"<worldbody>\n{geoms}\n", 1)
        option = f'<option integrator="implicitfast" timestep="{_TIMESTEP}"/>'
        xml = xml.replace('<option integrator="implicitfast"/>', option)
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    samples = execution.samples
    times, q, qd = samples.times, samples.positions, samples.velocities
    n = arm.n_joints
    data.qpos[:n] = q[0]
    mujoco.mj_forward(model, data)
    steps = math.ceil(times[-1] / _TIMESTEP) + 1
    clock = np.arange(steps) * _TIMESTEP
    command = np.column_stack([np.interp(clock, times, q[:, j]) for j in range(n)])
    speed = np.column_stack([np.interp(clock, times, qd[:, j]) for j in range(n)])
    # A position servo pulls by kp (ctrl - q) - kv q̇: leading the command by kv/kp q̇_cmd
    # cancels the damping's lag (velocity feedforward, as robot controllers do).
    lead = -model.actuator_biasprm[:n, 2] / model.actuator_gainprm[:n, 0]
    obstacle_ids = {
        model.geom(f"obstacle{k}").id: k for k in range(len(scene) if scene is not None else 0)
    }
    touched: set[int] = set()
    reached = np.empty((steps, n))
    for k in range(steps):
        reached[k] = data.qpos[:n]  # the state at clock[k], before the step from it
        data.ctrl[:n] = command[k] + lead * speed[k]
        mujoco.mj_step(model, data)
        for c in data.contact[: data.ncon]:
            for geom in (c.geom1, c.geom2):
                if geom in obstacle_ids:
                    touched.add(obstacle_ids[geom])
    tool = execution.task.tool
    wanted = forward(arm, command, tool)[:, :3, 3]
    got = forward(arm, reached, tool)[:, :3, 3]
    error = float(np.linalg.norm(got - wanted, axis=1).max())
    return SimulationCheck(tracking_error=error, touched=tuple(sorted(touched)), steps=steps)
