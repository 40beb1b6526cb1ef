"""Kinematics of any arm: forward, Jacobian, reach, and a joint path for a pose path.

One entry for the two kinds of arm lfdkit knows: a DH :class:`lfdkit.execute.arm.Arm`
(:mod:`.ur5`'s forward kinematics and Jacobian, any DH table) and a
:class:`lfdkit.execute.urdf.UrdfArm` (its own). :func:`joint_path` follows a
pose path on one continuous configuration branch:

* UR-type DH arms use the closed-form solution (:func:`lfdkit.execute.ur5.inverse_path`),
  the reference;
* every other arm uses damped least squares (Levenberg–Marquardt on the 6-D
  pose error, λ = 1e-3, steps capped at 0.3 rad), started from the previous
  pose's solution, so that the path stays on one branch and a redundant arm
  (a 7-DoF Panda) takes the smallest joint move; joints are clipped to their
  limits each step. A pose converges to 1e-7 m and 1e-6 rad in 3–6 steps
  when the previous one is 10 ms away. The first pose starts from ``q_start``
  and, if that fails, from 16 seeded random configurations (the nearest to
  ``q_start`` that converges wins).

Before any solving, :func:`check_reach` refuses poses farther from the arm's
shoulder than its reach (the sum of its link lengths beyond the shoulder plus
the tool's offset, an upper bound), with a one-line error "out of reach
(distance d m > reach r m)" naming the pose, not a failed solve or a
branch jump.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from lfdkit.execute import ur5
from lfdkit.execute.arm import Arm
from lfdkit.execute.poses import rotvec_from_matrix
from lfdkit.execute.urdf import UrdfArm

__all__ = [
    "AnyArm",
    "check_any_arm",
    "check_reach",
    "forward",
    "jacobian",
    "joint_path",
    "reach",
    "solve_pose",
]

AnyArm = Arm | UrdfArm

_POSITION_TOL = 1e-7  # m
_ANGLE_TOL = 1e-6  # rad
_DAMPING = 1e-3
_MAX_STEP = 0.3  # rad per iteration
_ITERATIONS = 100
_RESTARTS = 16


def check_any_arm(arm: Any) -> AnyArm:
    """``arm`` if it is an :class:`Arm` or a :class:`UrdfArm`, else a ``TypeError`` naming it."""
    if not isinstance(arm, (Arm, UrdfArm)):
        raise TypeError(f"arm: expected an Arm (lfdkit.execute.arm.UR5) or a UrdfArm, got {arm!r}")
    return arm


def forward(arm: AnyArm, q: Any, tool: Any = None) -> np.ndarray:
    """Flange (tip) or tool pose(s) of ``q`` (n,) or (m, n): (4, 4) or (m, 4, 4), metres."""
    if isinstance(arm, UrdfArm):
        return arm.forward(q, tool=tool)
    return ur5.forward(q, tool=tool, arm=arm)


def jacobian(arm: AnyArm, q: Any, tool: Any = None) -> np.ndarray:
    """Geometric Jacobian (6, n) (rows v, ω in the base frame) at the flange or tool point."""
    if isinstance(arm, UrdfArm):
        return arm.jacobian(q, tool=tool)
    return ur5.jacobian(q, tool=tool, arm=arm)


def _joint_points(arm: AnyArm) -> np.ndarray:
    """Joint origins and the flange at zero joint positions, (n + 1, 3), m; joint 1 first."""
    if isinstance(arm, UrdfArm):
        return arm.link_origins()
    return ur5.link_frames(np.zeros(arm.n_joints), arm=arm)[:, :3, 3]


def reach(arm: AnyArm, tool: Any = None) -> tuple[np.ndarray, float]:
    """The arm's shoulder point and an upper bound on its reach from it (m).

    The shoulder is joint 2's origin when it lies on joint 1's axis (it then
    never moves), else joint 1's origin; the reach is the sum of the distances
    between consecutive joint origins beyond it, to the flange, plus the tool's
    offset. No pose farther than that can be reached.
    """
    points = _joint_points(arm)
    if isinstance(arm, UrdfArm):
        axis = arm.jacobian(np.zeros(arm.n_joints))[3:, 0]
    else:
        axis = np.array([0.0, 0.0, 1.0])
    lever = points[1] - points[0]
    on_axis = np.linalg.norm(lever - axis * (lever @ axis)) < 1e-9
    first = 1 if on_axis else 0
    length = float(np.linalg.norm(np.diff(points[first:], axis=0), axis=1).sum())
    if tool is not None:
        length += float(np.linalg.norm(np.asarray(tool, dtype=np.float64)[:3, 3]))
    return points[first], length


def check_reach(poses: np.ndarray, arm: AnyArm, tool: Any = None) -> None:
    """Raise :class:`lfdkit.execute.ur5.UnreachableError` for the first pose beyond reach.

    The message: ``poses[i] at (x, y, z) m: out of reach of the UR5 (distance d m > reach r m
    from its shoulder)``.
    """
    shoulder, length = reach(arm, tool)
    distance = np.linalg.norm(poses[:, :3, 3] - shoulder, axis=1)
    far = distance > length
    if far.any():
        i = int(np.argmax(far))
        where = ", ".join(f"{v:.3f}" for v in poses[i, :3, 3])
        raise ur5.UnreachableError(
            f"poses[{i}] at ({where}) m: out of reach of the {arm.name} (distance "
            f"{distance[i]:.3f} m > reach {length:.3f} m from its shoulder)",
            i,
        )


def _pose_error(target: np.ndarray, current: np.ndarray) -> np.ndarray:
    """(position error, rotation vector of target · current⁻¹) in the base frame, (6,)."""
    r = target[:3, :3] @ current[:3, :3].T
    axis = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
    sin2 = float(np.linalg.norm(axis))  # 2 sin θ
    cos = 0.5 * (r[0, 0] + r[1, 1] + r[2, 2] - 1.0)
    if sin2 < 1e-6 and cos < 0:  # θ near π: the skew part vanishes; take the general formula
        rotvec = rotvec_from_matrix(r)
    else:
        angle = math.atan2(0.5 * sin2, cos)
        rotvec = axis * (0.5 if sin2 < 1e-12 else angle / sin2)
    return np.concatenate((target[:3, 3] - current[:3, 3], rotvec))


def _pose_and_jacobian(arm: AnyArm, q: np.ndarray, tool: Any) -> tuple[np.ndarray, np.ndarray]:
    if isinstance(arm, UrdfArm):
        return arm.pose_and_jacobian(q, tool)
    return ur5.forward(q, tool=tool, arm=arm), ur5.jacobian(q, tool=tool, arm=arm)


def solve_pose(
    arm: AnyArm, target: np.ndarray, q0: np.ndarray, tool: Any = None
) -> tuple[np.ndarray, float, float]:
    """Damped least squares from ``q0`` to the pose ``target`` (4, 4), within the joint limits.

    Returns the configuration and its remaining position (m) and angle (rad) errors.
    """
    lo, hi = arm.joint_limits[:, 0], arm.joint_limits[:, 1]
    q = np.clip(np.asarray(q0, dtype=np.float64), lo, hi)
    tool = None if tool is None else np.asarray(tool, dtype=np.float64)
    pose, jac = _pose_and_jacobian(arm, q, tool)
    err = _pose_error(target, pose)
    for _ in range(_ITERATIONS):
        if np.linalg.norm(err[:3]) < _POSITION_TOL and np.linalg.norm(err[3:]) < _ANGLE_TOL:
            break
        step = jac.T @ np.linalg.solve(jac @ jac.T + _DAMPING**2 * np.eye(6), err)
        biggest = np.abs(step).max()
        if biggest > _MAX_STEP:
            step *= _MAX_STEP / biggest
        q = np.clip(q + step, lo, hi)
        pose, jac = _pose_and_jacobian(arm, q, tool)
        err = _pose_error(target, pose)
    return q, float(np.linalg.norm(err[:3])), float(np.linalg.norm(err[3:]))


def _converged(position_error: float, angle_error: float) -> bool:
    return position_error < 10 * _POSITION_TOL and angle_error < 10 * _ANGLE_TOL


def _first(arm: AnyArm, target: np.ndarray, q_start: np.ndarray, tool: Any, seed: int) -> Any:
    q, pe, ae = solve_pose(arm, target, q_start, tool)
    if _converged(pe, ae):
        return q, pe, ae
    rng = np.random.default_rng(seed)
    lo, hi = arm.joint_limits[:, 0], arm.joint_limits[:, 1]
    found = []
    for _ in range(_RESTARTS):
        q, pe, ae = solve_pose(arm, target, rng.uniform(lo, hi), tool)
        if _converged(pe, ae):
            found.append(q)
    if not found:
        return q, pe, ae
    best = min(found, key=lambda c: float(np.abs(c - q_start).max()))
    return best, 0.0, 0.0


def _numeric_path(
    poses: np.ndarray, arm: AnyArm, q_start: np.ndarray, tool: Any, max_step: float, seed: int
) -> np.ndarray:
    out = np.empty((len(poses), arm.n_joints))
    q, pe, ae = _first(arm, poses[0], q_start, tool, seed)
    for i in range(len(poses)):
        if i:
            q, pe, ae = solve_pose(arm, poses[i], out[i - 1], tool)
        if not _converged(pe, ae):
            at = np.isclose(q, arm.joint_limits[:, 0]) | np.isclose(q, arm.joint_limits[:, 1])
            named = ", ".join(arm_joint_name(arm, j) for j in np.flatnonzero(at))
            cause = (
                f"joint {named} at its limit"
                if named
                else "no configuration found (out of the arm's workspace or beyond a singularity)"
            )
            where = ", ".join(f"{v:.3f}" for v in poses[i, :3, 3])
            error = ur5.JointLimitError if named else ur5.UnreachableError
            raise error(
                f"poses[{i}] at ({where}) m: the {arm.name} cannot reach it: {cause} "
                f"(left {pe * 1e3:.3g} mm, {np.degrees(ae):.3g} deg off)",
                i,
            )
        if i and np.abs(q - out[i - 1]).max() > max_step:
            j = int(np.argmax(np.abs(q - out[i - 1])))
            raise ur5.SingularityError(
                f"poses[{i}]: joint {arm_joint_name(arm, j)} jumps by "
                f"{abs(q[j] - out[i - 1, j]):.3g} rad (a singularity or a joint limit on the way)",
                i,
            )
        out[i] = q
    return out


def arm_joint_name(arm: AnyArm, j: int) -> str:
    """How messages name joint ``j`` (0-based): its URDF name, or its number from 1."""
    return arm.joint_names[j] if isinstance(arm, UrdfArm) else str(j + 1)


def joint_path(
    poses: np.ndarray,
    arm: AnyArm,
    q_start: Any,
    *,
    tool: Any = None,
    max_step: float = 0.5,
    seed: int = 0,
) -> np.ndarray:
    """Joint configurations following tool poses on one continuous branch.

    Parameters
    ----------
    poses : ndarray, shape (m, 4, 4)
        Tool poses in the base frame, metres, close to each other (a branch
        jump of more than ``max_step`` rad between neighbours is refused).
    arm : Arm or UrdfArm
    q_start : array_like, shape (arm.n_joints,)
        Picks the branch: the first pose's solution nearest to it.
    tool : array_like, shape (4, 4), optional
        Flange→tool transform.
    max_step : float
        Largest joint move between neighbouring poses (rad).
    seed : int
        Seeds the random restarts of the numerical solver at the first pose.

    Returns
    -------
    ndarray, shape (m, arm.n_joints)

    Raises
    ------
    lfdkit.execute.ur5.KinematicsError
        ``UnreachableError`` (out of reach, named with distance and reach),
        ``JointLimitError`` (naming the joint) or ``SingularityError``, each
        naming the pose's index.
    """
    arm = check_any_arm(arm)
    check_reach(poses, arm, tool)
    q_start = np.asarray(q_start, dtype=np.float64)
    if q_start.shape != (arm.n_joints,):
        raise ValueError(f"q_start: expected shape ({arm.n_joints},), got {q_start.shape}")
    if isinstance(arm, Arm) and arm.ur_type:
        try:
            first = ur5.nearest_solution(poses[0], q_start, tool=tool, arm=arm)
        except ur5.KinematicsError as exc:  # named as the path's first pose, with its position
            where = ", ".join(f"{v:.3f}" for v in poses[0, :3, 3])
            text = str(exc).removeprefix("pose: ")
            raise type(exc)(f"poses[0] at ({where}) m: {text}", 0) from None
        return ur5.inverse_path(poses, first, tool=tool, arm=arm, max_step=max_step)
    return _numeric_path(poses, arm, q_start, tool, max_step, seed)
