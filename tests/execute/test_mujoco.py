"""Tests for lfdkit.execute.mujoco: an arm's MuJoCo model from its description alone.

The model's kinematics is checked against :func:`lfdkit.execute.ur5.forward` (the
same DH table, built independently as nested MuJoCo bodies) for the UR5, the
UR10 and a planar three-joint arm; its joints, limits, masses and servo gains
against the description. No test renders (no OpenGL needed), except to check
that an image is either absent or of the asked size.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from lfdkit.execute import ur5
from lfdkit.execute.arm import UR5, UR10
from lfdkit.execute.mujoco import arm_mjcf, flange_poses, render_camera
from tests.execute.arms import PLANAR

#: Link masses (kg), Universal Robots' published dynamics parameters.
UR5_MASSES = (3.7, 8.393, 2.275, 1.219, 1.219, 0.1879)
UR10_MASSES = (7.1, 12.7, 4.27, 2.0, 2.0, 0.365)


def test_mujoco_flange_pose_equals_ur5_forward():
    q = np.random.default_rng(0).uniform(-2 * np.pi, 2 * np.pi, size=(200, 6))
    poses = flange_poses(q)
    assert poses.shape == (200, 4, 4)
    np.testing.assert_allclose(poses, ur5.forward(q), rtol=0, atol=1e-12)
    # One configuration in, one pose out.
    np.testing.assert_allclose(flange_poses(q[7]), ur5.forward(q[7]), rtol=0, atol=1e-12)


def test_mujoco_flange_poses_rejects_bad_configurations():
    with pytest.raises(ValueError, match="q"):
        flange_poses(np.zeros(5))
    with pytest.raises(ValueError, match="q"):
        flange_poses(np.zeros((3, 7)))
    with pytest.raises(ValueError, match="q"):
        flange_poses([0.0, 0.0, np.nan, 0.0, 0.0, 0.0])


@pytest.mark.parametrize(("arm", "masses"), [(UR5, UR5_MASSES), (UR10, UR10_MASSES)])
def test_the_model_has_the_arms_joints_limits_masses_and_gains(arm, masses):
    model = mujoco.MjModel.from_xml_string(arm_mjcf(arm))
    assert model.njnt == 6 and model.nu == 6
    for i in range(6):
        joint = model.joint(f"joint{i + 1}")
        assert int(joint.type[0]) == mujoco.mjtJoint.mjJNT_HINGE
        np.testing.assert_array_equal(joint.axis, [0.0, 0.0, 1.0])
        assert model.body(int(joint.bodyid[0])).name == f"link{i + 1}"
        assert model.body(f"link{i + 1}").mass[0] == pytest.approx(masses[i], abs=1e-12)
        assert model.actuator(f"joint{i + 1}").gainprm[0] == arm.kp[i]
    np.testing.assert_array_equal(model.jnt_range, arm.joint_limits)
    assert np.all(model.jnt_limited)
    assert f'model="lfdkit {arm.name}"' in arm_mjcf(arm)


def test_any_arm_is_built_from_its_description():
    q = np.random.default_rng(4).uniform(-np.pi, np.pi, size=(50, 6))
    np.testing.assert_allclose(
        flange_poses(q, arm=UR10), ur5.forward(q, arm=UR10), rtol=0, atol=1e-12
    )
    # Any number of joints: a planar 3R arm.
    model = mujoco.MjModel.from_xml_string(arm_mjcf(PLANAR))
    assert model.njnt == 3 and model.nu == 3
    q = np.random.default_rng(5).uniform(-3.0, 3.0, size=(20, 3))
    np.testing.assert_allclose(
        flange_poses(q, arm=PLANAR), ur5.forward(q, arm=PLANAR), rtol=0, atol=1e-12
    )
    with pytest.raises(ValueError, match=r"q: .*\(3,\) or \(m, 3\) for the planar 3R"):
        flange_poses(np.zeros(6), arm=PLANAR)
    with pytest.raises(TypeError, match="arm: expected an Arm"):
        arm_mjcf("UR10")


@pytest.mark.filterwarnings("ignore::UserWarning")  # GLFW's complaints without a display
def test_render_camera_gives_an_image_or_none():
    xml = arm_mjcf().replace(
        "<worldbody>",
        '<visual><global offwidth="64" offheight="48"/></visual>\n  <worldbody>\n'
        '    <camera name="look" pos="0 -2 1" xyaxes="1 0 0 0 0.5 1"/>',
    )
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    dots = (np.array([[0.0, 0.0, 0.5], [0.1, 0.0, 0.5]]), (1.0, 0.0, 0.0, 1.0))
    image = render_camera(model, data, "look", [dots], size=(48, 64))
    assert image is None or image.shape == (48, 64, 3)
