"""Tests for lfdkit.tasks.sweeping.execution: a learned skill carried to the robot and simulated.

The example skill sweeps to the demo's moved dustpan around a cup and a
marker with a UR5 and a UR10: the plan keeps clear, the joint path is
continuous and within the limits, the URScript reads back sample for sample
(with the reader of ``tests/robot/test_urscript.py``), and MuJoCo sweeps the
cube into the dustpan. What the arm cannot do is refused before anything is
written, naming what and where.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from lfdkit.execute import ur5
from lfdkit.execute.arm import UR5, UR10
from lfdkit.model.scene import Obstacle, Scene
from lfdkit.skill import Skill
from lfdkit.tasks.sweeping.execution import (
    GOAL_APPROACH,
    SERVO_RATE,
    ExecutionError,
    execute_skill,
    execution_outputs,
    write_execution,
)
from lfdkit.tasks.sweeping.scenarios import BRUSH, NEW_GOAL, unseen_scenes
from tests.conftest import example_skill_copy
from tests.execute.test_urscript import read_program

#: A goal the UR10 reaches and the UR5 does not (about 0.95 m from the base).
FAR_GOAL = (0.9, 0.45)


@pytest.fixture(scope="module")
def skill(example_skill_once) -> Skill:
    return example_skill_copy(example_skill_once)


@pytest.fixture(scope="module")
def scene(skill) -> Scene:
    return unseen_scenes(skill.path_[0], NEW_GOAL)[0]


@pytest.fixture(scope="module")
def run(skill, scene):
    """The UR5 sweep of unseen scene 1, simulated, with the stages it reported."""
    heard: list[str] = []
    return execute_skill(skill, None, NEW_GOAL, scene, progress=heard.append), heard


def test_the_plan_keeps_clear_and_ends_at_the_goal(run):
    done, _ = run
    assert done.arm is UR5
    np.testing.assert_allclose(done.plan.points[-1], NEW_GOAL, atol=1e-3)
    assert done.plan.details.clearance.min() >= 0.0  # beyond radius plus the brush's half width
    np.testing.assert_allclose(done.dustpan.goal(), NEW_GOAL, atol=1e-12)


def test_the_joint_path_reaches_the_poses_on_one_branch(run):
    done, _ = run
    assert done.poses.shape == (len(done.joints), 4, 4)
    np.testing.assert_allclose(ur5.forward(done.joints), done.poses, atol=1e-9)
    assert np.abs(np.diff(done.joints, axis=0)).max() < 0.1
    lower, upper = UR5.joint_limits.T
    assert np.all((done.joints >= lower) & (done.joints <= upper))


def test_the_stream_is_timed_within_the_limits_and_the_program_reads_back(run):
    done, _ = run
    dt = 1.0 / SERVO_RATE
    np.testing.assert_allclose(np.diff(done.times), dt, rtol=1e-6)
    speeds = np.abs(np.diff(done.stream, axis=0)) / dt
    assert speeds.max() <= 0.2 * UR5.max_joint_speed.max() * 1.01
    program = read_program(done.program)
    assert len(program.servoj) == len(done.stream)
    streamed = np.array([q for q, *_ in program.servoj])
    np.testing.assert_allclose(streamed, done.stream, atol=5e-10)
    np.testing.assert_allclose(program.movej[0], done.stream[0], atol=5e-10)


def test_the_simulated_sweep_succeeds_and_the_summary_says_so(run):
    done, heard = run
    assert done.result is not None and done.result.success, done.result.summary()
    summary = done.summary()
    json.dumps(summary, allow_nan=False)
    assert summary["simulation"]["success"] is True
    assert summary["simulation"]["touched"] == []
    assert 0.0 <= summary["simulation"]["clearance_m"] < 0.2
    assert summary["simulation"]["tracking_error_m"] < 0.005
    assert summary["plan"]["goal_approach_m"] == GOAL_APPROACH
    assert summary["plan"]["tool_clearance_m"] == 0.5 * BRUSH.width
    assert summary["robot"]["joint_speed_of_limit"] <= 0.2 * 1.01
    assert set(summary["seconds"]) == {"plan", "poses", "timing", "program", "simulation"}
    # Each step was reported as it started.
    for label in (
        "plan the sweep around 2 obstacles",
        "robot: flange poses and inverse kinematics (UR5)",
        "robot: URScript servoj stream at 125 Hz",
        "simulate the sweep in MuJoCo (UR5)",
    ):
        assert label in heard


def test_the_pose_table_is_timed_and_its_rotations_unwrapped(run):
    done, _ = run
    table = done.pose_table()
    assert table.shape == (len(done.poses), 7)
    assert table[0, 0] == 0.0 and np.all(np.diff(table[:, 0]) >= 0.0)
    np.testing.assert_allclose(table[-1, 0], done.timing.duration)
    np.testing.assert_allclose(table[:, 1:4], done.poses[:, :3, 3])
    np.testing.assert_allclose(np.linalg.norm(table[:, 4:], axis=1), np.pi, atol=1e-9)
    assert np.abs(np.diff(table[:, 4:], axis=0)).max() < 0.5  # no sign flips


def test_files_are_written_once_and_read_back(run, tmp_path):
    done, _ = run
    written = write_execution(tmp_path, done, extra={"skill": "example"})
    assert sorted(p.name for p in written) == sorted(
        p.name for p in execution_outputs(tmp_path, simulate=True)
    )
    header, *rows = (tmp_path / "joints.csv").read_text().splitlines()
    assert header == "t,q1,q2,q3,q4,q5,q6"
    np.testing.assert_array_equal(
        np.array([[float(v) for v in row.split(",")] for row in rows])[:, 1:], done.stream
    )
    poses = np.loadtxt(tmp_path / "poses.csv", delimiter=",", skiprows=1)
    np.testing.assert_array_equal(poses, done.pose_table())
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["skill"] == "example"
    assert summary["files"] == [p.name for p in written]
    assert (tmp_path / "sweep.png").read_bytes().startswith(b"\x89PNG")
    # Nothing is replaced unless asked, and nothing at all is written then.
    (tmp_path / "summary.json").unlink()
    before = (tmp_path / "plan.csv").stat().st_mtime_ns
    with pytest.raises(FileExistsError, match=r"plan\.csv: exists"):
        write_execution(tmp_path, done)
    assert not (tmp_path / "summary.json").exists()
    assert (tmp_path / "plan.csv").stat().st_mtime_ns == before
    write_execution(tmp_path, done, overwrite=True)
    assert (tmp_path / "summary.json").is_file()


def test_a_ur10_sweeps_where_a_ur5_cannot_reach(skill):
    with pytest.raises(ExecutionError) as refused:
        execute_skill(skill, None, FAR_GOAL, simulate=False)
    message = str(refused.value)
    assert message.startswith("the UR5 cannot follow the plan: poses[")
    assert "unreachable (position (" in message and "too far" in message
    assert "m along the" in message
    done = execute_skill(skill, None, FAR_GOAL, arm=UR10)
    assert done.arm is UR10
    assert done.result is not None and done.result.success, done.result.summary()
    read_program(done.program)
    assert done.summary()["arm"] == "UR10"


def test_a_tool_too_fast_is_refused_naming_when_and_where(skill, monkeypatch):
    # The check is the generic chain's (lfdkit.execute.pipeline.check_tool_speed).
    monkeypatch.setattr("lfdkit.execute.pipeline.MAX_TOOL_SPEED", 0.05)
    too_fast = r"the tool would move at [0-9.]+ m/s at t = [0-9.]+ s, at \(.*\) m, above"
    with pytest.raises(ExecutionError, match=too_fast):
        execute_skill(skill, simulate=False)


def test_without_mujoco_the_simulation_is_skipped_with_the_reason(skill, monkeypatch):
    def missing():
        raise ImportError("lfdkit.execute needs MuJoCo: python -m pip install mujoco")

    monkeypatch.setattr("lfdkit.tasks.sweeping.sim.load_mujoco", missing)
    done = execute_skill(skill)
    assert done.result is None
    assert done.skipped.startswith("MuJoCo is not available (lfdkit.execute needs MuJoCo")
    assert done.summary()["simulation"] == {"skipped": done.skipped}
    assert done.program  # everything but the simulation is there
    assert execute_skill(skill, simulate=False).skipped == "not asked for"


def test_obstacles_without_a_radius_stand_with_their_class_radius(skill):
    bare = Scene((Obstacle("cup", [-0.05, 0.49]), Obstacle("marker", [0.15, 0.455], 0.02)))
    done = execute_skill(skill, None, NEW_GOAL, bare, simulate=False)
    assert [o.radius for o in done.scene] == [0.03, 0.02]


def test_an_obstacle_of_a_class_never_learned_is_swept_around_only_when_asked(skill):
    # A 4 cm "bottle" stands on the sweep; the skill learned cups and markers only.
    bottle = Scene((Obstacle("bottle", [0.0, 0.47], 0.04),))
    with pytest.raises(ValueError, match=r"'bottle' was never learned.*unknown_class"):
        execute_skill(skill, None, NEW_GOAL, bottle, simulate=False)
    with pytest.warns(UserWarning, match=r"'bottle' never learned.*margin 0\.01 m"):
        done = execute_skill(skill, None, NEW_GOAL, bottle, simulate=False, unknown_class=0.01)
    # Beyond radius + margin + the brush's half width (the sweep's own clearance).
    kept = bottle.distances(done.plan.points)[0]
    assert kept >= 0.01 + 0.5 * BRUSH.width - 1e-9


def test_bad_arguments_are_refused_naming_them(skill):
    u = np.linspace(0.0, 1.0, 20)
    flat3 = Skill().fit([np.c_[u, 0.1 * u, 0.0 * u], np.c_[u, 0.1 * u + 0.01, 0.0 * u]])
    with pytest.raises(ValueError, match=r"^skill: is 3-D; the robot sweeps a 2-D path"):
        execute_skill(flat3)
    in_mm = Skill(units="mm").use_path(1000 * skill.path_)
    with pytest.raises(ValueError, match=r"^skill: is in 'mm'; the robot needs a skill in metres"):
        execute_skill(in_mm)
    with pytest.raises(ValueError, match=r"^speed_fraction: must be in \(0, 1\], got 0"):
        execute_skill(skill, speed_fraction=0)
    with pytest.raises(TypeError, match=r"^skill: expected an lfdkit.skill.Skill"):
        execute_skill("skill.json")
    with pytest.raises(TypeError, match=r"^scene: expected a Scene"):
        execute_skill(skill, scene=[("cup", 0.0, 0.4)])


def test_a_moving_obstacle_is_refused_with_the_way_to_run_it(skill):
    from lfdkit.model.motion import ConstantVelocity

    cup = Obstacle("cup", [0.0, 0.3], 0.03, motion=ConstantVelocity([0.0, 0.05]))
    with pytest.raises(ValueError, match=r"moving obstacles.*run_moving"):
        execute_skill(skill, scene=Scene((cup,)), simulate=False)


def test_a_wall_holding_the_arms_base_is_refused_before_planning(skill):
    from lfdkit.model.half_space import HalfSpace

    # A half-plane below the sweep (free side +y): the base at the origin is inside it,
    # and MuJoCo's plane is infinite, so no run could start. (Its class's radius, 1 cm
    # for a marker, lifts its surface.)
    below = HalfSpace("marker", [0.0, 0.2], 0.0, [0.0, 1.0])
    with pytest.raises(ValueError) as caught:
        execute_skill(skill, scene=Scene((below,)), simulate=False)
    assert str(caught.value) == (
        "scene: obstacle 0 ('marker', half_space) reaches the arm's base at the origin (the "
        "base's centre 21.0 cm inside it): the robot stands there; give a wall the normal that "
        "points toward the arm (its free side holds the arm) or place the obstacle beyond the base"
    )
    # A round obstacle on the base is refused too; the base's reach is the arm's first link.
    near = Obstacle("cup", [0.0, 0.08], 0.03)
    reach = 100 * UR5.link_radii[0]
    with pytest.raises(
        ValueError, match=rf"\(5.0 cm from the base's centre, within its {reach:.1f}"
    ):
        execute_skill(skill, scene=Scene((near,)), simulate=False)
