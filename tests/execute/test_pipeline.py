"""Tests of :func:`lfdkit.execute.pipeline.execute_plan`: any timed plan on any arm.

A 3-D reach over a box (a timed plan, as :meth:`lfdkit.skill.Skill.plan` returns)
runs on the UR5 (analytic IK, URScript) and a Panda from its URDF (numerical
IK): the tool follows the plan, the plan's duration is kept when the limits
allow, slowed (and said) when not; files carry ``t``; the refusals are one line
naming the pose, the distance and the reach, or the likely unit mistake.
"""

from __future__ import annotations

import json
from types import SimpleNamespace

import numpy as np
import pytest

from lfdkit.datasets import example_urdf
from lfdkit.execute.arm import UR5
from lfdkit.execute.kinematics import forward
from lfdkit.execute.pipeline import (
    ExecutionError,
    TaskDescription,
    execute_plan,
    write_robot_execution,
)
from lfdkit.execute.urdf import UrdfArm

DATA = example_urdf("ur5").parent  # the example arms lfdkit ships


def reach_over_a_box(duration: float = 3.0, n: int = 80, scale: float = 1.0) -> SimpleNamespace:
    """A timed plan from (0.45, -0.25, 0.15) over a 0.2 m box to (0.45, 0.25, 0.15), metres."""
    t = np.linspace(0.0, duration, n)
    s = 0.5 - 0.5 * np.cos(np.pi * t / duration)
    p = np.column_stack([np.full(n, 0.45), -0.25 + 0.5 * s, 0.15 + 0.2 * np.sin(np.pi * s)])
    return SimpleNamespace(times=t, positions=scale * p)


@pytest.fixture(scope="module")
def panda() -> UrdfArm:
    return UrdfArm(DATA / "panda.urdf", tip_link="panda_hand_tcp")


def tool_positions(run) -> np.ndarray:
    return forward(run.arm, run.samples.positions, run.task.tool)[:, :3, 3]


@pytest.mark.parametrize("which", ["ur5", "panda"])
def test_the_plan_runs_as_timed_and_the_tool_follows_it(which, panda):
    arm = UR5 if which == "ur5" else panda
    plan = reach_over_a_box()
    tool = np.eye(4)
    tool[2, 3] = 0.05
    run = execute_plan(plan, arm, TaskDescription(tool=tool), speed_fraction=0.5, rate=125.0)
    assert run.trajectory.slowdowns == ()
    assert run.trajectory.duration == pytest.approx(3.0, abs=1e-12)
    t = run.samples.times
    np.testing.assert_allclose(np.diff(t), 0.008, atol=1e-12)
    # At the plan's times the tool is at the plan's points (cubic in time between them).
    at = np.interp(plan.times, t, np.arange(len(t))).round().astype(int)
    on_grid = np.isclose(t[at], plan.times, atol=1e-9)
    np.testing.assert_allclose(tool_positions(run)[at[on_grid]], plan.positions[on_grid], atol=1e-5)
    # Tool pointing down (the default orientation) all along.
    down = forward(arm, run.samples.positions, tool)[:, :3, 2]
    np.testing.assert_allclose(down, np.tile([0.0, 0.0, -1.0], (len(t), 1)), atol=1e-5)
    assert (run.program is not None) == (which == "ur5")


def test_a_slow_arm_stretches_the_plan_and_says_where(panda):
    run = execute_plan(reach_over_a_box(duration=1.0, n=40), panda, speed_fraction=0.1)
    assert run.trajectory.duration > 1.0
    assert run.timing_note.startswith("slowed for the arm's limits: 1.000 s planned")
    qd, qdd = run.samples.velocities, run.samples.accelerations
    assert (np.abs(qd) <= 0.1 * panda.max_joint_speed * (1 + 1e-6)).all()
    assert (np.abs(qdd) <= 0.01 * panda.max_joint_acceleration * (1 + 1e-6)).all()


def test_the_urscript_moves_within_the_speed_fraction(tmp_path):
    run = execute_plan(reach_over_a_box(), UR5, speed_fraction=0.2, rate=500.0)
    movej = next(line for line in run.program.splitlines() if line.strip().startswith("movej("))
    assert movej.endswith("a=0.28, v=0.21)")
    assert "t=0.002," in run.program
    # A folder that is not there yet is made (README: write_robot_execution("run_panda_py/", run)).
    assert write_robot_execution(tmp_path / "new" / "run", run)[0].is_file()
    files = write_robot_execution(tmp_path, run)
    assert [f.name for f in files] == [
        "plan.csv",
        "trajectory.csv",
        "trajectory.json",
        "program.script",
        "summary.json",
    ]
    plan_rows = (tmp_path / "plan.csv").read_text().splitlines()
    assert plan_rows[0] == "t,x,y,z" and len(plan_rows) == 81
    # The plan as carried is one TimedPath, written as it is held.
    written = np.loadtxt(tmp_path / "plan.csv", delimiter=",", skiprows=1)
    np.testing.assert_array_equal(written, np.column_stack([run.plan.times, run.plan.positions]))
    assert run.plan.orientations is None and run.plan.duration == 3.0
    header = (tmp_path / "trajectory.csv").read_text().splitlines()[0].split(",")
    assert header[:2] == ["t", "q1"] and header[-1] == "q6_acc" and len(header) == 19
    message = json.loads((tmp_path / "trajectory.json").read_text())
    assert len(message["points"]) == len(run.samples.times)
    summary = json.loads((tmp_path / "summary.json").read_text())
    # At 20 % of the UR5's limits the 3 s reach is slowed, and the summary says so.
    assert summary["robot"]["duration_ratio"] == pytest.approx(run.trajectory.duration / 3.0)
    assert summary["robot"]["duration_ratio"] > 1.0 and summary["robot"]["slowdowns"]
    with pytest.raises(FileExistsError, match=r"plan\.csv: exists"):
        write_robot_execution(tmp_path, run)


def test_a_2d_plan_runs_on_its_plane():
    plan = reach_over_a_box()
    flat = SimpleNamespace(times=plan.times, positions=plan.positions[:, :2])
    run = execute_plan(flat, UR5, TaskDescription(height=0.25))
    np.testing.assert_allclose(tool_positions(run)[:, 2], 0.25, atol=1e-6)


def test_out_of_reach_is_named_with_distance_and_reach():
    frame = np.eye(4)
    frame[0, 3] = 0.9  # the plan 0.9 m further out
    with pytest.raises(ExecutionError) as info:
        execute_plan(reach_over_a_box(), UR5, TaskDescription(frame=frame))
    text = str(info.value)
    assert "\n" not in text
    assert "poses[0] at (1.350, -0.250, 0.150) m: out of reach of the UR5" in text
    assert "(distance 1.374 m > reach 1.103 m from its shoulder)" in text


def test_millimetres_read_as_metres_are_refused():
    with pytest.raises(ValueError, match=r"absurd for the UR5 .* millimetres or centimetres"):
        execute_plan(reach_over_a_box(scale=1000.0), UR5)


def test_bad_arguments_are_named():
    with pytest.raises(ValueError, match="speed_fraction: must be in"):
        execute_plan(reach_over_a_box(), UR5, speed_fraction=0.0)
    with pytest.raises(ValueError, match="rate: must be in"):
        execute_plan(reach_over_a_box(), UR5, rate=5000.0)
    with pytest.raises(TypeError, match="plan: expected a timed plan"):
        execute_plan(np.zeros((5, 3)), UR5)
    with pytest.raises(ValueError, match="tool: is not a rigid transform"):
        TaskDescription(tool=2 * np.eye(4))


def test_a_task_description_round_trips_through_json_and_refuses_bad_keys():
    frame = np.eye(4)
    frame[:3, :3] = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
    frame[:3, 3] = [0.1, -0.2, 0.3]
    task = TaskDescription(frame=frame, height=0.05, q_start=(0.0, -1.0, 1.0, 0.0, 1.5, 0.0))
    again = TaskDescription.from_dict(json.loads(json.dumps(task.to_dict())))
    assert again.to_dict() == task.to_dict()
    np.testing.assert_array_equal(
        again.poses(np.zeros((1, 2)), None), task.poses(np.zeros((1, 2)), None)
    )
    short = TaskDescription.from_dict({"offset": [0.1, -0.2, 0.3], "tool_length": 0.12})
    np.testing.assert_array_equal(short.frame[:3, 3], [0.1, -0.2, 0.3])
    assert short.tool[2, 3] == 0.12 and short.height == 0.0
    for bad, message in [
        ({"offest": [0, 0, 0]}, "task.json: unknown key 'offest'; expected some of"),
        ({"offset": [1, 2]}, r"task.json: offset: expected \[x, y, z\] in metres"),
        ({"offset": [0, 0, 0], "frame": np.eye(4).tolist()}, "give 'offset' or 'frame'"),
        ({"height": "high"}, "task.json: height: must be a finite number of metres"),
        ({"tool": [[1, 0], [0, 1]]}, "task.json: tool: expected a finite 4x4 transform"),
        ([0, 0, 0], "task.json: expected a JSON object, got list"),
    ]:
        with pytest.raises(ValueError, match=message) as error:
            TaskDescription.from_dict(bad, "task.json")
        assert "\n" not in str(error.value)


def test_approach_and_retreat_move_straight_along_the_tool_axis():
    plan = reach_over_a_box()
    task = TaskDescription(approach=0.1, retreat=0.05)
    run = execute_plan(plan, UR5, task, speed_fraction=0.5, rate=125.0)
    # 0.1 m at 0.1 m/s: 1 s in; 0.05 m: 1 s out (the shortest); the plan's 3 s kept between.
    assert run.trajectory.slowdowns == ()
    assert run.trajectory.duration == pytest.approx(1.0 + 3.0 + 1.0, abs=1e-9)
    t, tool = run.samples.times, tool_positions(run)
    start, end = plan.positions[0], plan.positions[-1]
    # The tool points down: it comes down onto the start from 10 cm above, and rises 5 cm.
    up = np.array([0.0, 0.0, 1.0])
    np.testing.assert_allclose(tool[0], start + 0.1 * up, atol=1e-5)
    np.testing.assert_allclose(tool[t.searchsorted(1.0)], start, atol=1e-5)
    np.testing.assert_allclose(tool[t.searchsorted(4.0)], end, atol=1e-5)
    np.testing.assert_allclose(tool[-1], end + 0.05 * up, atol=1e-5)
    into, out = tool[t < 1.0], tool[t > 4.0]
    np.testing.assert_allclose(into[:, :2], np.tile(start[:2], (len(into), 1)), atol=1e-5)
    np.testing.assert_allclose(out[:, :2], np.tile(end[:2], (len(out), 1)), atol=1e-5)
    assert (np.diff(into[:, 2]) <= 1e-9).all() and (np.diff(out[:, 2]) >= -1e-9).all()
    assert run.summary()["plan"]["duration_s"] == pytest.approx(3.0)
    with pytest.raises(ValueError, match=r"approach: expected a distance from 0 to 1 m, got -0\.1"):
        TaskDescription(approach=-0.1)
