"""Tests of :mod:`lfdkit.execute.simulation`: the MuJoCo check of any arm.

MuJoCo's model of a URDF arm has the URDF's kinematics (its flange where
:meth:`UrdfArm.forward` puts it, to round-off); a reach over a box tracks
within 2 mm and touches nothing on the UR5 (DH), a UR5e and a Panda (URDFs),
and touches the box when the box is moved into the tool's way.
"""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.datasets import example_urdf
from lfdkit.execute.arm import UR5
from lfdkit.execute.pipeline import UR_START, TaskDescription, execute_plan
from lfdkit.execute.urdf import UrdfArm
from lfdkit.model.scene import Obstacle, Scene
from tests.execute.test_pipeline import reach_over_a_box

mujoco = pytest.importorskip("mujoco")

from lfdkit.execute.simulation import simulate_execution, urdf_mjcf  # noqa: E402

DATA = example_urdf("ur5").parent  # the example arms lfdkit ships


def arms():
    return {
        "ur5": UR5,
        "ur5e": UrdfArm(DATA / "ur5e.urdf"),
        "panda": UrdfArm(DATA / "panda.urdf", tip_link="panda_hand_tcp"),
    }


def test_the_mujoco_model_has_the_urdf_kinematics():
    arm = arms()["panda"]
    model = mujoco.MjModel.from_xml_string(urdf_mjcf(arm))
    data = mujoco.MjData(model)
    site = model.site("flange").id
    rng = np.random.default_rng(2)
    for _ in range(10):
        q = rng.uniform(arm.joint_limits[:, 0], arm.joint_limits[:, 1])
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        np.testing.assert_allclose(data.site_xpos[site], arm.forward(q)[:3, 3], atol=1e-12)
        flange = data.site_xmat[site].reshape(3, 3)
        np.testing.assert_allclose(flange, arm.forward(q)[:3, :3], atol=1e-12)


@pytest.mark.parametrize("name", ["ur5", "ur5e", "panda"])
def test_a_reach_over_a_box_tracks_and_touches_nothing(name):
    arm = arms()[name]
    task = TaskDescription(q_start=UR_START if arm.n_joints == 6 else None)
    plan = reach_over_a_box(duration=2.0, n=60)
    run = execute_plan(plan, arm, task, speed_fraction=1.0, rate=500.0)
    assert run.trajectory.slowdowns == ()  # the learned 2 s kept
    box = Scene((Obstacle("box", (0.45, 0.0, 0.1), 0.1),))
    check = simulate_execution(run, box)
    assert check.tracking_error <= 0.002
    assert check.touched == ()
    in_the_way = Scene(
        (Obstacle("box", (0.45, 0.0, 0.1), 0.1), Obstacle("cup", (0.45, 0, 0.33), 0.05))
    )
    assert simulate_execution(run, in_the_way).touched == (1,)
