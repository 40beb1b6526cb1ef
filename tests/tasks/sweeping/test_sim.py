"""Tests for lfdkit.tasks.sweeping.sim: the sweeping scene in MuJoCo and its verdicts.

The model holds the robot of the arm description and the scene of
:mod:`lfdkit.tasks.sweeping.scenarios`, every size, mass and colour read from
there. The sweeps are short straight pushes along the world ``x`` axis at
``y = 0.45`` m, in front of the robot, whose outcome is known in advance: the
cube ends in a dustpan that stands at the end of the line, a cup on the line is
hit, a cup 15 cm beside it is not, a dustpan 20 cm off the line is missed, and
a line 1.1 m from the base is out of reach. The UR10 and a planar three-joint
arm are built into the scene from their descriptions alone, and the UR10
sweeps as the UR5 does. No test renders (no OpenGL needed), except to check
that a requested image is either absent or of the documented size.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from lfdkit.execute.arm import UR5, UR10
from lfdkit.execute.timing import time_parameterize
from lfdkit.model.scene import Capsule, Obstacle, Scene
from lfdkit.tasks.sweeping import sim
from lfdkit.tasks.sweeping.scenarios import (
    BRUSH,
    CUBE,
    OBSTACLE_CLASSES,
    TABLE,
    Dustpan,
    SweepingTask,
)
from lfdkit.tasks.sweeping.sim import HOME, SweepResult
from tests.execute.arms import PLANAR

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
    return path, task, sim.execute_sweep(path, task)


# ------------------------------------------------------------------ model
def test_robot_in_the_scene_has_the_arms_joints_and_limits():
    model = sim.build_model()
    assert model.njnt == 6 and model.nu == 6
    np.testing.assert_array_equal(model.jnt_range[:6], UR5.joint_limits)
    assert np.all(model.jnt_limited[:6])
    np.testing.assert_allclose(model.geom("table").size[:2], [TABLE.half_size] * 2)
    np.testing.assert_allclose(model.geom("table").rgba, TABLE.rgba, atol=1e-7)
    head, handle = model.geom("brush"), model.geom("handle")
    np.testing.assert_allclose(
        head.size, [0.5 * BRUSH.thickness, 0.5 * BRUSH.width, 0.5 * BRUSH.height], atol=1e-15
    )
    # The brush is all the flange body holds.
    assert model.body(int(head.bodyid[0])).name == "flange"
    assert model.body("flange").mass[0] == pytest.approx(BRUSH.mass + BRUSH.handle_mass)
    np.testing.assert_allclose(handle.size[0], BRUSH.handle_radius, atol=1e-15)


def test_task_adds_free_cube_and_obstacles_as_their_classes_describe():
    scene = Scene(
        (
            Obstacle("cup", np.array([0.0, 0.5])),  # radius 0: the class default
            Obstacle("marker", np.array([0.1, 0.4])),
            Obstacle("bowl", np.array([-0.1, 0.6]), 0.05),  # unknown class: a cup's cylinder
        )
    )
    task = SweepingTask(np.array([-0.2, 0.45]), PAN, scene, cube_yaw=0.3)
    model = sim.build_model(task)
    assert model.njnt == 6 + 1 + len(scene)
    assert all(int(t) == mujoco.mjtJoint.mjJNT_FREE for t in model.jnt_type[6:])
    np.testing.assert_array_equal(model.jnt_range[:6], UR5.joint_limits)
    np.testing.assert_allclose(model.body("cube").pos[:2], task.cube, atol=1e-12)
    np.testing.assert_allclose(model.geom("cube").size, [CUBE.size / 2] * 3, atol=1e-12)
    assert model.body("cube").mass[0] == pytest.approx(CUBE.mass, abs=1e-15)
    # A cylinder's size is (radius, half height); 0 picks 3 cm for a cup, 1 cm for a marker.
    radii = [model.geom(f"obstacle{i}").size[0] for i in range(3)]
    np.testing.assert_allclose(radii, [0.03, 0.01, 0.05], atol=1e-12)
    cup_class, marker_class = OBSTACLE_CLASSES["cup"], OBSTACLE_CLASSES["marker"]
    for i, kind in enumerate((cup_class, marker_class, cup_class)):
        geom = model.geom(f"obstacle{i}")
        assert geom.size[1] == pytest.approx(0.5 * kind.height, abs=1e-15)
        assert model.body(f"obstacle{i}").mass[0] == pytest.approx(kind.mass, abs=1e-15)
        np.testing.assert_allclose(geom.rgba, kind.rgba, atol=1e-7)
    for i, obstacle in enumerate(scene):
        np.testing.assert_allclose(model.body(f"obstacle{i}").pos[:2], obstacle.position)
    np.testing.assert_allclose(model.body("dustpan").pos[:2], PAN.position, atol=1e-12)
    np.testing.assert_allclose(
        model.geom("dustpan_back").size[2], 0.5 * PAN.wall_height, atol=1e-15
    )
    xml = sim.sweeping_mjcf(task)
    assert xml.count("<freejoint") == 1 + len(scene)
    assert "<freejoint" not in sim.sweeping_mjcf()


def test_a_wall_is_a_static_plane_in_the_model():
    from lfdkit.model.half_space import HalfSpace

    # A wall beyond the sweep, facing the robot (MuJoCo refuses a plane in a free body).
    wall = HalfSpace("wall", [0.0, 0.6], 0.01, [0.0, -1.0])  # its surface at y = 0.59
    scene = Scene((wall, Obstacle("cup", np.array([0.0, 0.5]))))
    model = sim.build_model(SweepingTask(np.array([-0.2, 0.45]), PAN, scene))
    assert model.njnt == 6 + 1 + 1  # the arm, the cube and the cup: the wall has no joint
    assert model.geom("obstacle0").type == mujoco.mjtGeom.mjGEOM_PLANE
    assert model.body("obstacle0").jntnum[0] == 0
    np.testing.assert_allclose(model.body("obstacle0").pos[:2], [0.0, 0.59], atol=1e-12)
    # Its normal (the plane's z axis) points to the free side, towards the robot.
    frame = np.zeros(9)
    mujoco.mju_quat2Mat(frame, model.geom("obstacle0").quat)
    np.testing.assert_allclose(frame.reshape(3, 3)[:, 2], [0.0, -1.0, 0.0], atol=1e-12)


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
    result = sim.execute_sweep(path, task)
    assert not result.success
    assert 0 in result.touched
    assert result.obstacle_shift.shape == (1,)
    assert result.obstacle_shift[0] > 0.005
    assert any("touched obstacle 0 (cup)" in failure for failure in result.failures)


def test_cup_beside_the_line_is_not_touched():
    path = straight_path()
    task = SweepingTask.for_path(path, PAN, cup(0.0, 0.6))
    result = sim.execute_sweep(path, task)
    assert result.touched == []
    assert result.obstacle_shift[0] < 1e-3
    assert result.success, result.failures


def test_dustpan_off_the_path_is_missed():
    pan = Dustpan((0.3, 0.65), 0.0)
    path = straight_path(end=PAN.goal())  # still ends at (0.32, 0.45)
    result = sim.execute_sweep(path, SweepingTask.for_path(path, pan))
    assert not result.success
    assert not result.cube_in_dustpan
    assert not pan.contains(result.cube_final)
    assert any(failure.startswith("cube missed the dustpan") for failure in result.failures)


def test_unreachable_path_is_reported_not_raised():
    path = straight_path(start=(-0.2, 1.1), end=(0.2, 1.1), n=20)
    task = SweepingTask.for_path(path, PAN, cup(0.0, 0.6))
    result = sim.execute_sweep(path, task)
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
        sim.simulate_sweep(np.array([HOME, HOME + 0.05]), task)
    with pytest.raises(ValueError, match="timing"):
        five_joints = np.array([[0.0] * 5, [0.1] * 5])
        sim.simulate_sweep(time_parameterize(five_joints, max_velocity=1, max_acceleration=1), task)
    for tolerance in (0.0, -0.001):
        with pytest.raises(ValueError, match="tolerance"):
            sim.simulate_sweep(timing, task, tolerance=tolerance)


def test_tracking_beyond_tolerance_is_a_failure(straight_sweep):
    path, task, reference = straight_sweep
    result = sim.execute_sweep(path, task, tolerance=1e-6)
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
    result = sim.execute_sweep(path, SweepingTask.for_path(path, PAN), render=True, camera="top")
    assert result.image is None or result.image.shape == (720, 960, 3)


def test_the_overview_camera_sees_the_table_as_the_top_view_does():
    """Image right is world +x and image up is away from the arm (+y), as in sweep_figure."""
    import mujoco

    model = sim.build_model()
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    mujoco.mj_camlight(model, data)
    axes = data.cam_xmat[model.camera("overview").id].reshape(3, 3)  # columns: x, y, z
    assert axes[:, 0] @ [1.0, 0.0, 0.0] > 0.99  # not mirrored: the dustpan's side on the right
    assert axes[:, 1] @ [0.0, 1.0, 0.0] > 0.5  # the arm's base at the bottom
    assert axes[:, 2][2] > 0.9  # looking down onto the table


def test_a_missing_opengl_backend_leaves_physics_running(tmp_path):
    """Headless, with no usable off-screen OpenGL, MuJoCo still simulates; no image."""
    import os
    import subprocess
    import sys

    script = (
        "import numpy as np\n"
        "from lfdkit.execute import mujoco\n"
        "from lfdkit.tasks import sweeping as sim\n"
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
def test_the_scene_is_built_from_the_arm_description():
    model = sim.build_model(arm=UR10)
    assert model.njnt == 6 and model.nu == 6
    for i in range(6):
        assert model.body(f"link{i + 1}").mass[0] == pytest.approx(UR10.link_masses[i])
        assert model.actuator(f"joint{i + 1}").gainprm[0] == UR10.kp[i]
    np.testing.assert_array_equal(model.jnt_range[:6], UR10.joint_limits)
    assert 'model="lfdkit UR10 sweeping"' in sim.sweeping_mjcf(arm=UR10)
    # Any number of joints: a planar 3R arm among the task's free bodies.
    task = SweepingTask(np.array([-0.2, 0.45]), PAN, cup(0.0, 0.6))
    model = sim.build_model(task, arm=PLANAR)
    assert model.nu == 3
    assert model.njnt == 3 + 1 + 1
    for i in range(3):
        assert model.body(f"link{i + 1}").mass[0] == pytest.approx(PLANAR.link_masses[i])
    with pytest.raises(TypeError, match="arm: expected an Arm"):
        sim.build_model(arm="UR10")


def test_the_sweeping_simulation_builds_and_steps_with_a_ur10():
    """A 4 cm push with a UR10 among a cup, a marker and an unknown class: it runs and tracks."""
    path = straight_path(start=(0.0, 0.45), end=(0.04, 0.45), n=5)
    scene = Scene(
        (
            Obstacle("cup", np.array([0.0, 0.65])),
            Obstacle("marker", np.array([0.1, 0.25])),
            Obstacle("bowl", np.array([-0.15, 0.6]), 0.04),
        )
    )
    task = SweepingTask.for_path(path, PAN, scene)
    _, joints = sim.sweep_motion(path, arm=UR10)
    assert joints.shape[1] == UR10.n_joints
    timing = time_parameterize(joints, arm=UR10, speed_fraction=0.2)
    result = sim.simulate_sweep(timing, task, arm=UR10, sample_rate=100.0)
    assert result.timing is timing
    assert result.joint_path.shape[1] == 6
    assert np.all(np.isfinite(result.tool_trace)) and np.all(np.isfinite(result.cube_trace))
    assert len(result.times) == len(result.tool_trace) == len(result.cube_trace) > 10
    assert result.tracking_error < 0.005
    assert result.touched == []
    assert result.obstacle_shift.shape == (3,)
    np.testing.assert_allclose(result.tool_trace[:, 2], BRUSH.sweep_height, atol=0.005)


def test_a_ur10_sweeps_into_the_dustpan():
    path = straight_path()
    task = SweepingTask.for_path(path, PAN)
    result = sim.execute_sweep(path, task, arm=UR10)
    assert result.success, result.summary()
    np.testing.assert_allclose(result.timing.max_velocity, 0.2 * UR10.max_joint_speed)
    with pytest.raises(ValueError, match="timing: expected 6 joints for the UR10, got 5"):
        five = np.array([[0.0] * 5, [0.1] * 5])
        five_joints = time_parameterize(five, max_velocity=1, max_acceleration=1)
        sim.simulate_sweep(five_joints, task, arm=UR10)


def test_any_arm_runs_in_the_scene_with_its_own_joint_count():
    """A planar 3R arm (no sweep IK) follows a 3-joint trajectory in the scene."""
    timing = time_parameterize(
        np.array([[0.0, 0.5, 0.2], [0.1, 0.6, 0.25]]), arm=PLANAR, speed_fraction=0.2
    )
    task = SweepingTask(np.array([0.5, 0.45]), PAN)
    result = sim.simulate_sweep(timing, task, arm=PLANAR)
    assert result.joint_path.shape == (2, 3)
    assert result.tracking_error < 0.005
    assert not result.success  # nothing pushed the cube into the dustpan
    assert result.failures[0].startswith("cube missed the dustpan")


# ------------------------------------------------------------------ other shapes
def test_a_rod_lies_on_the_table_as_a_capsule_and_is_hit_across_the_sweep():
    # The obstacle contract's solid: a rod (Capsule) is a capsule geom along its axis.
    rod = Capsule("marker", np.array([0.0, 0.40]), 0.012, np.array([0.0, 0.52]))
    path = straight_path()
    task = SweepingTask.for_path(path, PAN, Scene((rod,)))
    model = sim.build_model(task)
    geom = model.geom("obstacle0")
    assert int(geom.type[0]) == mujoco.mjtGeom.mjGEOM_CAPSULE
    assert geom.size[0] == pytest.approx(0.012, abs=1e-15)
    assert geom.size[1] == pytest.approx(0.06, abs=1e-12)  # half the axis
    np.testing.assert_allclose(model.body("obstacle0").pos, [0.0, 0.46, 0.012 + 1e-4])
    result = sim.execute_sweep(path, task)
    assert 0 in result.touched
    assert not result.success
    # Beside the sweep (wholly above the brush's line), it is left alone.
    beside = Capsule("marker", np.array([-0.1, 0.62]), 0.012, np.array([0.1, 0.64]))
    task = SweepingTask.for_path(path, PAN, Scene((beside,)))
    result = sim.execute_sweep(path, task)
    assert result.touched == []
    assert result.success, result.failures
