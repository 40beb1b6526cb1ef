"""Tests for lfdkit.robot.sim: the MuJoCo sweeping scene, its kinematics and its verdicts.

The model's kinematics is checked against :func:`lfdkit.robot.ur5.forward` (the
same DH table, built independently as nested MuJoCo bodies). The sweeps are
short straight pushes along the world ``x`` axis at ``y = 0.45`` m, in front of
the robot, whose outcome is known in advance: the cube ends in a dustpan that
stands at the end of the line, a cup on the line is hit, a cup 15 cm beside it
is not, a dustpan 20 cm off the line is missed, and a line 1.1 m from the base
is out of reach. The UR10 and a planar three-joint arm are built from their
descriptions alone, and the UR10 sweeps as the UR5 does. No test renders (no
OpenGL needed), except to check that a requested image is either absent or of
the documented size.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from lfdkit.robot import ur5
from lfdkit.robot.arm import UR5, UR10
from lfdkit.robot.mujoco import flange_poses as mujoco_flange_poses
from lfdkit.robot.sim import (
    BRUSH,
    CUBE_SIZE,
    HOME,
    Dustpan,
    SweepingTask,
    SweepResult,
    build_model,
    execute_sweep,
    simulate_sweep,
    sweeping_mjcf,
)
from lfdkit.robot.timing import time_parameterize
from lfdkit.scene import Obstacle, Scene
from tests.robot.arms import PLANAR

#: UR5 link masses (kg), Universal Robots' published dynamics parameters.
UR5_MASSES = (3.7, 8.393, 2.275, 1.219, 1.219, 0.1879)

START = np.array([-0.3, 0.45])
PAN = Dustpan((0.3, 0.45), 0.0)


def straight_path(start=START, end=None, n: int = 50) -> np.ndarray:
    """A straight table path from ``start`` to ``end`` (default: the dustpan's goal)."""
    end = PAN.goal() if end is None else np.asarray(end, dtype=np.float64)
    return np.linspace(start, end, n)


def cup(x: float, y: float) -> Scene:
    return Scene((Obstacle("cup", np.array([x, y]), 0.03),))


@pytest.fixture(scope="module")
def straight_sweep() -> tuple[np.ndarray, SweepingTask, SweepResult]:
    """The free straight sweep into the dustpan, simulated once for the module."""
    path = straight_path()
    task = SweepingTask.for_path(path, PAN)
    return path, task, execute_sweep(path, task)


# ------------------------------------------------------------------ model
def test_mujoco_flange_pose_equals_ur5_forward():
    q = np.random.default_rng(0).uniform(-2 * np.pi, 2 * np.pi, size=(200, 6))
    poses = mujoco_flange_poses(q)
    assert poses.shape == (200, 4, 4)
    np.testing.assert_allclose(poses, ur5.forward(q), rtol=0, atol=1e-12)
    # One configuration in, one pose out.
    np.testing.assert_allclose(mujoco_flange_poses(q[7]), ur5.forward(q[7]), rtol=0, atol=1e-12)


def test_mujoco_flange_poses_rejects_bad_configurations():
    with pytest.raises(ValueError, match="q"):
        mujoco_flange_poses(np.zeros(5))
    with pytest.raises(ValueError, match="q"):
        mujoco_flange_poses(np.zeros((3, 7)))
    with pytest.raises(ValueError, match="q"):
        mujoco_flange_poses([0.0, 0.0, np.nan, 0.0, 0.0, 0.0])


def test_robot_model_has_ur5_joints_limits_and_masses():
    model = build_model()
    assert model.njnt == 6
    for i in range(6):
        joint = model.joint(f"joint{i + 1}")
        assert int(joint.type[0]) == mujoco.mjtJoint.mjJNT_HINGE
        np.testing.assert_array_equal(joint.axis, [0.0, 0.0, 1.0])
        assert model.body(int(joint.bodyid[0])).name == f"link{i + 1}"
        assert model.body(f"link{i + 1}").mass[0] == pytest.approx(UR5_MASSES[i], abs=1e-12)
    np.testing.assert_array_equal(model.jnt_range[:6], UR5.joint_limits)
    assert np.all(model.jnt_limited[:6])
    assert model.nu == 6


def test_task_adds_free_cube_and_obstacles():
    scene = Scene(
        (
            Obstacle("cup", np.array([0.0, 0.5])),  # radius 0: the class default
            Obstacle("marker", np.array([0.1, 0.4])),
            Obstacle("bowl", np.array([-0.1, 0.6]), 0.05),
        )
    )
    task = SweepingTask(np.array([-0.2, 0.45]), PAN, scene, cube_yaw=0.3)
    model = build_model(task)
    assert model.njnt == 6 + 1 + len(scene)
    assert all(int(t) == mujoco.mjtJoint.mjJNT_FREE for t in model.jnt_type[6:])
    np.testing.assert_array_equal(model.jnt_range[:6], UR5.joint_limits)
    np.testing.assert_allclose(model.body("cube").pos[:2], task.cube, atol=1e-12)
    np.testing.assert_allclose(model.geom("cube").size, [CUBE_SIZE / 2] * 3, atol=1e-12)
    # A cylinder's size is (radius, half height); 0 picks 3 cm for a cup, 1 cm for a marker.
    radii = [model.geom(f"obstacle{i}").size[0] for i in range(3)]
    np.testing.assert_allclose(radii, [0.03, 0.01, 0.05], atol=1e-12)
    for i, obstacle in enumerate(scene):
        np.testing.assert_allclose(model.body(f"obstacle{i}").pos[:2], obstacle.position)
    np.testing.assert_allclose(model.body("dustpan").pos[:2], PAN.position, atol=1e-12)
    xml = sweeping_mjcf(task)
    assert xml.count("<freejoint") == 1 + len(scene)
    assert "<freejoint" not in sweeping_mjcf()


# ------------------------------------------------------------------ dustpan
def test_dustpan_frame_with_yaw_zero():
    pan = Dustpan((0.3, 0.45), 0.0)
    inside = np.array([0.35, 0.45])
    np.testing.assert_allclose(pan.local(inside), [0.05, 0.0], atol=1e-15)
    assert pan.contains(inside)
    assert pan.contains([0.3 + pan.depth - 1e-9, 0.45 + 0.5 * pan.width - 1e-9])  # a corner
    assert not pan.contains([0.3 + pan.depth + 0.01, 0.45])  # beyond the back wall
    assert not pan.contains([0.35, 0.45 + 0.5 * pan.width + 0.01])  # beside the side wall
    assert not pan.contains([0.29, 0.45])  # in front of the opening
    np.testing.assert_allclose(pan.goal(), [0.32, 0.45], atol=1e-15)
    np.testing.assert_allclose(pan.goal(0.05), [0.35, 0.45], atol=1e-15)
    # Batches of points keep their leading shape.
    local = pan.local(np.array([[0.3, 0.45], [0.3, 0.5], [0.2, 0.45]]))
    np.testing.assert_allclose(local, [[0.0, 0.0], [0.0, 0.05], [-0.1, 0.0]], atol=1e-15)


def test_dustpan_frame_with_yaw_quarter_turn():
    pan = Dustpan((0.1, 0.5), math.pi / 2)  # opening faces -y, the cube arrives along +y
    np.testing.assert_allclose(pan.axes, [[0.0, 1.0], [-1.0, 0.0]], atol=1e-15)
    inside = np.array([0.1, 0.55])
    np.testing.assert_allclose(pan.local(inside), [0.05, 0.0], atol=1e-15)
    assert pan.contains(inside)
    assert not pan.contains([0.1, 0.5 + pan.depth + 0.01])  # beyond the back wall
    beside = np.array([0.1 + 0.5 * pan.width + 0.01, 0.55])
    np.testing.assert_allclose(pan.local(beside), [0.05, -0.09], atol=1e-15)
    assert not pan.contains(beside)
    assert not pan.contains([0.1, 0.49])  # in front of the opening
    np.testing.assert_allclose(pan.goal(), [0.1, 0.52], atol=1e-15)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"position": (np.nan, 0.45), "yaw": 0.0}, "position"),
        ({"position": (0.3, 0.45, 0.0), "yaw": 0.0}, "position"),
        ({"position": (0.3, 0.45), "yaw": np.inf}, "yaw"),
        ({"position": (0.3, 0.45), "yaw": 0.0, "depth": 0.0}, "depth"),
        ({"position": (0.3, 0.45), "yaw": 0.0, "depth": -0.1}, "depth"),
        ({"position": (0.3, 0.45), "yaw": 0.0, "width": 0.0}, "width"),
    ],
)
def test_dustpan_rejects_bad_input(kwargs, name):
    with pytest.raises(ValueError, match=name):
        Dustpan(**kwargs)


# ------------------------------------------------------------------ task
def test_for_path_places_cube_ahead_of_the_brush():
    ahead = 0.5 * BRUSH.thickness + 0.5 * CUBE_SIZE + 0.004
    direction = np.array([3.0, 4.0]) / 5.0
    path = np.array([0.0, 0.4]) + np.linspace(0.0, 0.3, 20)[:, None] * direction
    task = SweepingTask.for_path(path, PAN)
    np.testing.assert_allclose(task.cube, path[0] + ahead * direction, atol=1e-12)
    assert task.cube_yaw == pytest.approx(math.atan2(4.0, 3.0), abs=1e-12)
    assert len(task.scene) == 0
    assert task.dustpan is PAN


def test_for_path_going_in_minus_x_puts_cube_at_smaller_x():
    ahead = 0.5 * BRUSH.thickness + 0.5 * CUBE_SIZE + 0.004
    path = straight_path(start=(0.2, 0.45), end=(-0.2, 0.45))
    task = SweepingTask.for_path(path, PAN, cup(0.0, 0.6))
    assert task.cube[0] < path[0, 0]
    np.testing.assert_allclose(task.cube, [0.2 - ahead, 0.45], atol=1e-12)
    assert abs(task.cube_yaw) == pytest.approx(math.pi, abs=1e-12)
    assert len(task.scene) == 1


def test_for_path_uses_the_first_two_centimetres_not_the_first_segment():
    # A rollout that creeps 0.1 mm sideways before heading along +x.
    path = np.array([[0.0, 0.45], [0.0, 0.4501], [0.1, 0.4501], [0.3, 0.4501]])
    task = SweepingTask.for_path(path, PAN)
    assert abs(task.cube_yaw) < 0.01  # the first segment alone would give π/2
    assert task.cube[0] > 0.02


def test_sweeping_task_rejects_bad_input():
    scene_3d = Scene((Obstacle("cup", np.array([0.0, 0.5, 0.0])),))
    with pytest.raises(ValueError, match="scene"):
        SweepingTask.for_path(straight_path(), PAN, scene_3d)
    with pytest.raises(ValueError, match="cube"):
        SweepingTask(np.array([np.nan, 0.45]), PAN)
    with pytest.raises(ValueError, match="cube"):
        SweepingTask(np.array([0.0, 0.45, 0.0]), PAN)
    with pytest.raises(TypeError, match="dustpan"):
        SweepingTask(np.array([0.0, 0.45]), (0.3, 0.45))
    with pytest.raises(ValueError, match="path"):
        SweepingTask.for_path([[0.0, 0.45], [np.nan, 0.45]], PAN)


# ------------------------------------------------------------------ sweeps
def test_straight_sweep_pushes_cube_into_dustpan(straight_sweep):
    path, task, result = straight_sweep
    assert result.success, result.failures
    assert result.failures == []
    assert result.cube_in_dustpan
    assert PAN.contains(result.cube_final)
    assert result.touched == []
    assert result.tracking_error < 0.005
    assert result.path_error < 0.005
    # The cube starts where the task put it and is pushed ahead of the brush.
    np.testing.assert_allclose(result.cube_trace[0], task.cube, atol=1e-3)
    assert result.cube_final[0] > path[-1, 0]
    np.testing.assert_array_equal(result.cube_final, result.cube_trace[-1])
    # The flange stays at the sweeping height and ends above the path's end.
    np.testing.assert_allclose(result.tool_trace[:, 2], BRUSH.sweep_height, atol=0.005)
    np.testing.assert_allclose(result.tool_trace[-1, :2], path[-1], atol=0.005)
    assert result.duration > 0
    assert np.all(np.diff(result.times) > 0)
    assert len(result.times) == len(result.tool_trace) == len(result.cube_trace)
    assert result.joint_path.shape[1] == 6
    assert result.image is None
    assert result.summary().startswith("success")


def test_cup_on_the_line_is_touched():
    path = straight_path()
    task = SweepingTask.for_path(path, PAN, cup(0.0, 0.45))
    result = execute_sweep(path, task)
    assert not result.success
    assert 0 in result.touched
    assert result.obstacle_shift.shape == (1,)
    assert result.obstacle_shift[0] > 0.005
    assert any("touched obstacle 0 (cup)" in failure for failure in result.failures)


def test_cup_beside_the_line_is_not_touched():
    path = straight_path()
    task = SweepingTask.for_path(path, PAN, cup(0.0, 0.6))
    result = execute_sweep(path, task)
    assert result.touched == []
    assert result.obstacle_shift[0] < 1e-3
    assert result.success, result.failures


def test_dustpan_off_the_path_is_missed():
    pan = Dustpan((0.3, 0.65), 0.0)
    path = straight_path(end=PAN.goal())  # still ends at (0.32, 0.45)
    result = execute_sweep(path, SweepingTask.for_path(path, pan))
    assert not result.success
    assert not result.cube_in_dustpan
    assert not pan.contains(result.cube_final)
    assert any(failure.startswith("cube missed the dustpan") for failure in result.failures)


def test_unreachable_path_is_reported_not_raised():
    path = straight_path(start=(-0.2, 1.1), end=(0.2, 1.1), n=20)
    task = SweepingTask.for_path(path, PAN, cup(0.0, 0.6))
    result = execute_sweep(path, task)
    assert not result.success
    assert not result.cube_in_dustpan
    assert len(result.failures) == 1
    assert result.failures[0].startswith("the robot cannot follow the path")
    assert math.isnan(result.tracking_error)
    assert result.tool_trace.shape == (0, 3)
    assert result.obstacle_shift.shape == (1,)


def test_simulate_sweep_rejects_bad_arguments(straight_sweep):
    _, task, _ = straight_sweep
    timing = time_parameterize(np.array([HOME, HOME + 0.05]))
    with pytest.raises(TypeError, match="timing"):
        simulate_sweep(np.array([HOME, HOME + 0.05]), task)
    with pytest.raises(ValueError, match="timing"):
        five_joints = np.array([[0.0] * 5, [0.1] * 5])
        simulate_sweep(time_parameterize(five_joints, max_velocity=1, max_acceleration=1), task)
    for tolerance in (0.0, -0.001):
        with pytest.raises(ValueError, match="tolerance"):
            simulate_sweep(timing, task, tolerance=tolerance)


def test_tracking_beyond_tolerance_is_a_failure(straight_sweep):
    path, task, reference = straight_sweep
    result = execute_sweep(path, task, tolerance=1e-6)
    assert not result.success
    assert result.cube_in_dustpan
    assert result.touched == []
    assert len(result.failures) == 1
    assert result.failures[0].startswith("tracking error")
    assert "exceeds" in result.failures[0]
    # The physics is deterministic: the same sweep tracks exactly as well.
    assert result.tracking_error == pytest.approx(reference.tracking_error, rel=1e-9)


@pytest.mark.filterwarnings("ignore::UserWarning")  # GLFW's complaints without a display
def test_render_gives_an_image_or_none():
    path = straight_path(start=(0.0, 0.45), end=(0.05, 0.45), n=5)
    result = execute_sweep(path, SweepingTask.for_path(path, PAN), render=True, camera="top")
    assert result.image is None or result.image.shape == (720, 960, 3)


def test_a_missing_opengl_backend_leaves_physics_running(tmp_path):
    """Headless, with no usable off-screen OpenGL, MuJoCo still simulates; no image."""
    import os
    import subprocess
    import sys

    script = (
        "import numpy as np\n"
        "from lfdkit.robot import mujoco, sim\n"
        "mujoco.HEADLESS_GL = 'no-such-backend'  # MuJoCo refuses it on import, as without EGL\n"
        "p = np.column_stack([np.linspace(-0.3, 0.32, 50), np.full(50, 0.45)])\n"
        "task = sim.SweepingTask.for_path(p, sim.Dustpan([0.3, 0.45], 0.0))\n"
        "r = sim.execute_sweep(p, task, render=True)\n"
        "print(r.success, r.image is None)\n"
    )
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "MUJOCO_GL")}
    run = subprocess.run(
        [sys.executable, "-c", script], env=env, capture_output=True, text=True, timeout=120
    )
    assert run.returncode == 0, run.stderr[-2000:]
    assert run.stdout.split() == ["True", "True"]


# ------------------------------------------------------------------ other arms
#: UR10 link masses (kg), Universal Robots' published dynamics parameters.
UR10_MASSES = (7.1, 12.7, 4.27, 2.0, 2.0, 0.365)


def test_the_model_is_built_from_the_arm_description():
    model = build_model(arm=UR10)
    assert model.njnt == 6 and model.nu == 6
    for i in range(6):
        assert model.body(f"link{i + 1}").mass[0] == pytest.approx(UR10_MASSES[i], abs=1e-12)
        assert model.actuator(f"joint{i + 1}").gainprm[0] == UR10.kp[i]
    np.testing.assert_array_equal(model.jnt_range[:6], UR10.joint_limits)
    assert 'model="lfdkit UR10 sweeping"' in sweeping_mjcf(arm=UR10)
    q = np.random.default_rng(4).uniform(-np.pi, np.pi, size=(50, 6))
    np.testing.assert_allclose(
        mujoco_flange_poses(q, arm=UR10), ur5.forward(q, arm=UR10), rtol=0, atol=1e-12
    )
    # Any number of joints: a planar 3R arm.
    model = build_model(arm=PLANAR)
    assert model.njnt == 3 and model.nu == 3
    q = np.random.default_rng(5).uniform(-3.0, 3.0, size=(20, 3))
    np.testing.assert_allclose(
        mujoco_flange_poses(q, arm=PLANAR), ur5.forward(q, arm=PLANAR), rtol=0, atol=1e-12
    )
    with pytest.raises(ValueError, match=r"q: .*\(3,\) or \(m, 3\) for the planar 3R"):
        mujoco_flange_poses(np.zeros(6), arm=PLANAR)
    with pytest.raises(TypeError, match="arm: expected an Arm"):
        build_model(arm="UR10")


def test_a_ur10_sweeps_into_the_dustpan():
    path = straight_path()
    task = SweepingTask.for_path(path, PAN)
    result = execute_sweep(path, task, arm=UR10)
    assert result.success, result.summary()
    np.testing.assert_allclose(result.timing.max_velocity, 0.2 * UR10.max_joint_speed)
    with pytest.raises(ValueError, match="timing: expected 6 joints for the UR10, got 5"):
        five = np.array([[0.0] * 5, [0.1] * 5])
        simulate_sweep(time_parameterize(five, max_velocity=1, max_acceleration=1), task, arm=UR10)
