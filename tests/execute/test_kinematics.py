"""Tests of :mod:`lfdkit.execute.kinematics`: reach, and joint paths for any arm.

The numerical inverse kinematics is checked against the analytic UR solution
(the same UR5 as a URDF, the same branch) and by forward kinematics on a
7-DoF Panda; the reach refusal names the distance and the reach.
"""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.datasets import example_urdf
from lfdkit.execute import ur5
from lfdkit.execute.arm import UR5, UR10
from lfdkit.execute.kinematics import check_reach, forward, joint_path, reach, solve_pose
from lfdkit.execute.urdf import UrdfArm

DATA = example_urdf("ur5").parent  # the example arms lfdkit ships


def arc_poses(n: int = 120, radius: float = 0.15, centre=(0.45, 0.0, 0.3)) -> np.ndarray:
    """Tool-down poses on a horizontal half circle, the tool turning with the path."""
    a = np.linspace(0.0, np.pi, n)
    poses = np.tile(np.eye(4), (n, 1, 1))
    poses[:, 0, 3] = centre[0] + radius * np.sin(a)
    poses[:, 1, 3] = centre[1] + radius * np.cos(a)
    poses[:, 2, 3] = centre[2]
    c, s = np.cos(0.5 * a), np.sin(0.5 * a)
    # Rz(a/2) Rx(π): tool z down.
    poses[:, :3, 0] = np.column_stack([c, s, np.zeros(n)])
    poses[:, :3, 1] = np.column_stack([s, -c, np.zeros(n)])
    poses[:, :3, 2] = (0.0, 0.0, -1.0)
    return poses


def test_reach_of_the_ur_arms_is_their_link_lengths_from_the_shoulder():
    shoulder, length = reach(UR5)
    np.testing.assert_allclose(shoulder, (0, 0, UR5.d[0]))
    assert length == pytest.approx(0.425 + 0.39225 + 0.10915 + 0.09465 + 0.0823)
    # The URDF of the same arm has the same reach; a tool adds its offset.
    tool = np.eye(4)
    tool[:3, 3] = (0.0, 0.03, 0.04)
    assert reach(UrdfArm(DATA / "ur5.urdf"), tool)[1] == pytest.approx(length + 0.05)
    assert reach(UR10)[1] > length


def test_a_pose_beyond_reach_is_refused_with_distance_and_reach():
    poses = arc_poses(centre=(1.3, 0.0, 0.3))
    with pytest.raises(ur5.UnreachableError) as info:
        joint_path(poses, UR5, (0.0, -1.2, 1.6, -1.97, -1.5708, 0.0))
    text = str(info.value)
    assert text.startswith("poses[0] at (1.300, 0.150, 0.300) m: out of reach of the UR5")
    assert "(distance 1.326 m > reach 1.103 m from its shoulder)" in text
    panda = UrdfArm(DATA / "panda.urdf", tip_link="panda_hand_tcp")
    with pytest.raises(ur5.UnreachableError, match="out of reach of the panda"):
        check_reach(poses, panda)


def test_numerical_ik_finds_the_analytic_ur5_branch():
    poses = arc_poses()
    start = np.array([0.0, -1.2, 1.6, -1.97, -1.5708, 0.0])
    analytic = joint_path(poses, UR5, start)  # UR-type DH arm: closed form
    numeric = joint_path(poses, UrdfArm(DATA / "ur5.urdf"), analytic[0] + 0.05)
    np.testing.assert_allclose(numeric, analytic, atol=1e-5)


def test_panda_follows_a_path_continuously_within_its_limits():
    arm = UrdfArm(DATA / "panda.urdf", tip_link="panda_hand_tcp")
    poses = arc_poses(centre=(0.45, 0.0, 0.25))
    q = joint_path(poses, arm, arm.joint_limits.mean(axis=1))
    reached = forward(arm, q)
    np.testing.assert_allclose(reached[:, :3, 3], poses[:, :3, 3], atol=1e-6)
    np.testing.assert_allclose(reached[:, :3, :3], poses[:, :3, :3], atol=1e-5)
    assert np.abs(np.diff(q, axis=0)).max() < 0.1  # one branch, no jump
    assert (q >= arm.joint_limits[:, 0]).all() and (q <= arm.joint_limits[:, 1]).all()


def test_a_joint_limit_is_named():
    arm = UrdfArm(DATA / "panda.urdf", tip_link="panda_hand_tcp")
    # Within reach but behind the base, low: the Panda's joint 4 cannot fold that far.
    target = arc_poses(centre=(0.0, 0.0, 0.05), radius=0.05)[:1]
    target[0, :3, 3] = (-0.05, 0.0, 0.05)
    with pytest.raises(
        ur5.JointLimitError,
        match=r"poses\[0\] at \(-0.050, 0.000, 0.050\) m: .*panda_joint4.* at its limit",
    ):
        joint_path(target, arm, arm.joint_limits.mean(axis=1))


def test_solve_pose_converges_from_nearby():
    arm = UrdfArm(DATA / "panda.urdf", tip_link="panda_hand_tcp")
    q = np.array([0.2, -0.4, 0.1, -2.0, 0.1, 1.8, 0.5])
    q_found, position_error, angle_error = solve_pose(arm, arm.forward(q), q + 0.1)
    assert position_error < 1e-6 and angle_error < 1e-5
    np.testing.assert_allclose(arm.forward(q_found), arm.forward(q), atol=1e-6)
