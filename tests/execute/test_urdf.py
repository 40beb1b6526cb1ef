"""Tests of :class:`lfdkit.execute.urdf.UrdfArm` against independent references.

* The UR5 URDF in ``data/`` was written from the thesis's DH table: its forward
  kinematics and Jacobian agree with the DH arm (:mod:`lfdkit.execute.ur5`) to
  1e-9 at random joint vectors (hypothesis).
* The Panda URDF (Franka's published parameters) and the UR5e one agree with
  pinocchio, the field's reference, when it is installed (``pip install pin``).
* The Jacobian agrees with finite differences of the forward kinematics, for
  revolute and prismatic joints.
* Bad files fail in one line naming the joint.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lfdkit.datasets import example_urdf
from lfdkit.execute import ur5
from lfdkit.execute.arm import UR5
from lfdkit.execute.urdf import ACCELERATION_PER_SPEED, UrdfArm

DATA = example_urdf("ur5").parent  # the example arms lfdkit ships
UR5_URDF = DATA / "ur5.urdf"
PANDA_URDF = DATA / "panda.urdf"
UR5E_URDF = DATA / "ur5e.urdf"

angles = st.lists(
    st.floats(-2 * np.pi, 2 * np.pi, allow_nan=False, allow_infinity=False), min_size=6, max_size=6
)


def panda() -> UrdfArm:
    return UrdfArm(PANDA_URDF, tip_link="panda_hand_tcp")


@settings(max_examples=60, deadline=None)
@given(q=angles)
def test_ur5_urdf_matches_the_dh_arm(q):
    arm = UrdfArm(UR5_URDF)
    np.testing.assert_allclose(arm.forward(q), ur5.forward(q, arm=UR5), atol=1e-9)
    np.testing.assert_allclose(arm.jacobian(q), ur5.jacobian(q, arm=UR5), atol=1e-9)
    pose, jac = arm.pose_and_jacobian(np.array(q))
    np.testing.assert_allclose(pose, arm.forward(q), atol=1e-12)
    np.testing.assert_allclose(jac, arm.jacobian(q), atol=1e-12)


def test_ur5_urdf_reads_limits_and_names():
    arm = UrdfArm(UR5_URDF)
    assert arm.n_joints == 6 and arm.name == "UR5"
    assert arm.joint_names == tuple(f"joint{k}" for k in range(1, 7))
    np.testing.assert_allclose(arm.joint_limits, UR5.joint_limits)
    np.testing.assert_allclose(arm.max_joint_speed, 3.2)
    assert arm.guessed_acceleration
    np.testing.assert_allclose(arm.max_joint_acceleration, ACCELERATION_PER_SPEED * 3.2)
    given_acc = UrdfArm(UR5_URDF, max_joint_acceleration=15.0)
    assert not given_acc.guessed_acceleration
    np.testing.assert_allclose(given_acc.max_joint_acceleration, 15.0)
    with pytest.raises(ValueError, match=r"max_joint_acceleration: must be .* for joint 3$"):
        UrdfArm(UR5_URDF, max_joint_acceleration=[15, 15, -1, 15, 15, 15])
    with pytest.raises(ValueError, match=r"expected a number or one per joint \(6 joints\)"):
        UrdfArm(UR5_URDF, max_joint_acceleration=[15, 15])  # one line, not NumPy's broadcast error


def test_batch_and_single_agree_and_tool_is_appended():
    arm = panda()
    rng = np.random.default_rng(4)
    q = rng.uniform(arm.joint_limits[:, 0], arm.joint_limits[:, 1], size=(5, arm.n_joints))
    tool = np.eye(4)
    tool[:3, 3] = (0.01, -0.02, 0.15)
    batch = arm.forward(q, tool=tool)
    for k in range(5):
        np.testing.assert_allclose(batch[k], arm.forward(q[k]) @ tool, atol=1e-12)


def _numeric_jacobian(arm: UrdfArm, q: np.ndarray, h: float = 1e-6) -> np.ndarray:
    jac = np.empty((6, arm.n_joints))
    base = arm.forward(q)
    for j in range(arm.n_joints):
        dq = np.zeros(arm.n_joints)
        dq[j] = h
        plus, minus = arm.forward(q + dq), arm.forward(q - dq)
        jac[:3, j] = (plus[:3, 3] - minus[:3, 3]) / (2 * h)
        dr = (plus[:3, :3] - minus[:3, :3]) / (2 * h) @ base[:3, :3].T  # skew(ω)
        jac[3:, j] = (dr[2, 1], dr[0, 2], dr[1, 0])
    return jac


def test_jacobian_matches_finite_differences_with_a_prismatic_joint():
    # The Panda's finger is a prismatic joint: the chain to it has 8 joints.
    finger = UrdfArm(PANDA_URDF, tip_link="panda_leftfinger")
    assert finger.joint_types[-1] == "prismatic" and finger.n_joints == 8
    q = np.r_[0.1, -0.3, 0.2, -1.8, 0.1, 1.5, 0.4, 0.02]
    np.testing.assert_allclose(finger.jacobian(q), _numeric_jacobian(finger, q), atol=1e-7)
    arm = panda()
    q7 = q[:7]
    np.testing.assert_allclose(arm.jacobian(q7), _numeric_jacobian(arm, q7), atol=1e-7)


def test_panda_zero_pose_is_franka_published_one():
    # Franka's flange at q = 0: (0.088, 0, 0.333 + 0.316 + 0.384 - 0.107), pointing down.
    flange = UrdfArm(PANDA_URDF, tip_link="panda_link8").forward(np.zeros(7))
    np.testing.assert_allclose(flange[:3, 3], (0.088, 0.0, 0.926), atol=1e-12)
    np.testing.assert_allclose(flange[:3, 2], (0.0, 0.0, -1.0), atol=1e-12)


@pytest.mark.parametrize(
    ("path", "tip", "extra"), [(PANDA_URDF, "panda_hand_tcp", 2), (UR5E_URDF, None, 0)]
)
def test_forward_kinematics_agree_with_pinocchio(path, tip, extra):
    pin = pytest.importorskip("pinocchio")
    model = pin.buildModelFromUrdf(str(path))
    data = model.createData()
    arm = UrdfArm(path, tip_link=tip)
    frame = model.getFrameId(tip or "flange")
    rng = np.random.default_rng(7)
    for _ in range(20):
        q = rng.uniform(arm.joint_limits[:, 0], arm.joint_limits[:, 1])
        pin.framesForwardKinematics(model, data, np.r_[q, np.zeros(extra)])
        np.testing.assert_allclose(data.oMf[frame].homogeneous, arm.forward(q), atol=1e-12)


def test_the_tip_must_be_named_when_leaves_tie():
    with pytest.raises(ValueError, match="tie as the tip; name tip_link"):
        UrdfArm(PANDA_URDF)
    with pytest.raises(ValueError, match="tip_link: no link 'gripper'"):
        UrdfArm(PANDA_URDF, tip_link="gripper")


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (('type="revolute"', 'type="floating"', 1), "joint 'panda_joint1': type 'floating'"),
        (('velocity="2.1750"', 'velocity="0"', 1), "joint 'panda_joint1': needs <limit velocity>"),
        (('lower="-2.8973"', 'lower="3"', 1), "joint 'panda_joint1': limit lower 3.0"),
        (
            ('xyz="0 0 0.333"', 'xyz="0 0"', 1),
            "joint 'panda_joint1' origin xyz: expected 3 finite numbers, got '0 0'",
        ),
        (("</robot>", "", 1), "not valid XML"),
    ],
)
def test_bad_files_fail_in_one_line_naming_the_joint(change, message):
    text = PANDA_URDF.read_text().replace(*change)
    with pytest.raises(ValueError, match=message) as info:
        UrdfArm(text, tip_link="panda_hand_tcp")
    assert "\n" not in str(info.value)


def test_a_missing_file_is_named(tmp_path):
    with pytest.raises(ValueError, match="is not a file"):
        UrdfArm(tmp_path / "arm.urdf")
