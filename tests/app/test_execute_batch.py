"""Any skill on any arm in batch: ``evaluate_task``, ``lfdkit batch evaluate --task path``.

The skill is ``data/reach3d.json``: a 3-D reach over a box (0.4 m along y,
0.2 m up), learned from three timed 4 s demonstrations (:data:`REACH`;
``test_the_stored_skill_is_what_its_demonstrations_learn`` checks it is still
what they learn). A stored skill loads in ~20 ms, where learning it takes
~10 s on a busy machine.

The work unit is checked against the chain it wraps (``Skill.plan`` then
``execute_plan`` give the same row), random goal ``i`` depends on the seed
and ``i`` only and fills its ball uniformly, a goal out of reach is an
outcome naming the reach, and the command takes a URDF arm and a task file,
prints the outcome table and refuses bad combinations in one line.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from lfdkit.app.batch import read_results
from lfdkit.app.execute_batch import (
    TASK_CHECKS,
    arm_spec,
    evaluate_task,
    evaluate_task_batch,
    outcome_table,
    random_goal,
)
from lfdkit.datasets import example_urdf
from lfdkit.execute.pipeline import TaskDescription, execute_plan
from lfdkit.skill import Skill
from tests.app.conftest import reach_demos
from tests.app.test_cli import run_cli

SKILL = Path(__file__).parent / "data" / "reach3d.json"
URDFS = example_urdf("ur5").parent  # the example arms lfdkit ships


#: The demonstrations ``data/reach3d.json`` was learned from (``Skill(mimic="average")``).
REACH = {"n_demos": 3, "duration": 4.0, "n_samples": 40, "y_span": 0.4, "height": 0.2}


@pytest.fixture(scope="module")
def text() -> str:
    return SKILL.read_text()


@pytest.mark.slow  # learning takes ~10 s on a busy 2-core machine
def test_the_stored_skill_is_what_its_demonstrations_learn():
    demos, times = reach_demos(**REACH)
    learned = Skill(mimic="average", random_state=0).fit(demos, times=times)
    stored = Skill.load(SKILL)
    np.testing.assert_allclose(learned.path_, stored.path_, atol=1e-9)
    np.testing.assert_allclose(learned.plan().times, stored.plan().times, atol=1e-9)


def test_random_goal_i_depends_on_the_seed_and_i_only_and_fills_the_ball():
    goal = np.array([0.45, 0.2, 0.15])
    first = random_goal(goal, 0.05, 5, 3)
    assert np.array_equal(first, random_goal(goal, 0.05, 5, 3))
    assert not np.array_equal(first, random_goal(goal, 0.05, 5, 4))
    assert not np.array_equal(first, random_goal(goal, 0.05, 6, 3))
    drawn = np.array([random_goal(goal, 0.05, 0, i) for i in range(4000)])
    distance = np.linalg.norm(drawn - goal, axis=1)
    assert distance.max() <= 0.05
    # Uniform in the volume: a share (1/2)^3 = 1/8 within half the radius (4000 draws: sd 0.005).
    assert np.mean(distance < 0.025) == pytest.approx(0.125, abs=0.02)
    np.testing.assert_allclose(drawn.mean(axis=0), goal, atol=0.002)
    assert np.array_equal(random_goal(goal, 0.0, 1, 2), goal)


def test_the_row_is_what_the_chain_it_wraps_gives(text):
    arm = arm_spec(URDFS / "ur5e.urdf")
    task = TaskDescription(frame=np.diag([1.0, 1.0, 1.0, 1.0]), name="reach")
    where = {"seed": 2, "index": 1, "spread": 0.05, "start": None, "goal": None}
    rows = {
        check: evaluate_task(text, where, arm, task.to_dict(), check) for check in TASK_CHECKS[:2]
    }
    assert rows["plan"]["plan"] == rows["robot"]["plan"]
    assert "robot" not in rows["plan"] and all(r["ok"] for r in rows.values())
    assert json.loads(json.dumps(rows["robot"])) == rows["robot"]  # JSON-ready
    skill = Skill.load(SKILL)
    goal = random_goal(skill.path_[-1], 0.05, 2, 1)
    assert rows["robot"]["goal"] == goal.tolist()
    from lfdkit.execute.urdf import UrdfArm

    run = execute_plan(skill.plan(skill.path_[0], goal), UrdfArm(URDFS / "ur5e.urdf"), task)
    robot = run.summary()["robot"]
    got = rows["robot"]["robot"]
    assert got["motion_s"] == robot["motion_s"] and got["timing"] == run.timing_note
    assert got["duration_ratio"] == robot["duration_ratio"]
    assert got["slowed"] == bool(run.trajectory.slowdowns)
    assert rows["plan"]["plan"]["duration_s"] == pytest.approx(run.trajectory.planned_duration)


def test_a_goal_out_of_reach_is_an_outcome_naming_the_reach(text):
    where = {"scene": "far", "obstacles": None, "start": None, "goal": [1.6, 0.2, 0.15]}
    row = evaluate_task(text, where, {"arm": "ur5"}, TaskDescription().to_dict(), "robot")
    assert not row["ok"] and "plan" in row and "robot" not in row
    assert row["failure"].startswith("ExecutionError: the UR5 cannot follow the plan: ")
    assert "out of reach of the UR5" in row["failure"]
    with pytest.raises(ValueError, match="check: expected one of plan, robot, mujoco"):
        evaluate_task(text, where, {"arm": "ur5"}, {}, "kinematics")


def test_arm_spec_reads_a_urdf_once_and_refuses_a_bad_one(tmp_path):
    assert arm_spec("ur5") == {"arm": "ur5"}
    spec = arm_spec(URDFS / "panda.urdf", "panda_hand_tcp")
    assert spec["urdf"].lstrip().startswith("<") and spec["tip_link"] == "panda_hand_tcp"
    with pytest.raises(ValueError, match="tip_link: is for a URDF arm"):
        arm_spec("ur5", "tool0")
    with pytest.raises(ValueError, match="arm: kuka is neither an arm name"):
        arm_spec("kuka")
    bad = tmp_path / "bad.urdf"
    bad.write_text("<robot name='x'><link name='a'/>")
    with pytest.raises(ValueError, match=f"{bad}: "):
        arm_spec(bad)


def test_the_scenes_of_a_file_with_an_unlearned_class(text, tmp_path):
    scenes = tmp_path / "scenes.csv"
    # A bottle beside the reach (a class the skill never learned: --unknown-class margin).
    scenes.write_text(
        "demo,class,x,y,z,radius\na,bottle,0.45,0.0,0.6,0.03\nb,bottle,0.6,0,0.1,0.02\n"
    )
    results = tmp_path / "r.jsonl"
    summary = evaluate_task_batch(
        SKILL, results, scenes=scenes, check="robot", unknown_class=0.01, speed_fraction=0.5
    )
    assert summary.done == 2 and summary.failed == 0
    rows = {r["task"]: r for r in read_results(results)}
    assert rows["a"]["obstacles"] == 1 and rows["a"]["ok"]
    assert rows["a"]["plan"]["clearance_m"] > 0.01
    table, shown = outcome_table(results)
    assert table["tasks"] == 2 and table["ok"] + table["not_ok"] == 2
    assert "robot / plan duration" in shown
    # Without the margin the unlearned class is an error of each task, recorded, not the end.
    again = evaluate_task_batch(SKILL, tmp_path / "r2.jsonl", scenes=scenes, check="plan")
    assert again.failed == 2 and "unknown_class=MARGIN" in again.errors[0]


def test_the_command_passes_the_unknown_class_margin_and_response(tmp_path, capsys):
    # --unknown-class margin=M,response=R reaches every task's plan (it once reached the
    # tasks as the option's record and every task failed with a TypeError).
    scenes = tmp_path / "scenes.csv"
    scenes.write_text("demo,class,x,y,z,radius\na,bottle,0.45,0.0,0.6,0.03\n")
    argv = ["batch", "evaluate", SKILL, "--scenes", scenes, "--check", "plan"]
    answers = {}
    for option in ("margin=0.01", "margin=0.01,response=none"):
        results = tmp_path / f"{len(answers)}.jsonl"
        code, _, err = run_cli(capsys, *argv, "--unknown-class", option, "-o", results)
        assert code == 0, err
        (row,) = read_results(results)
        assert row["ok"] and row["plan"]["clearance_m"] > 0.01
        answers[option] = row["plan"]
    assert answers["margin=0.01"] == answers["margin=0.01,response=none"]
    code, _, err = run_cli(
        capsys, *argv, "--unknown-class", "margin=0.01,response=teapot", "-o", tmp_path / "t.jsonl"
    )
    assert code == 1 and "teapot" in err


def test_batch_inputs_are_refused_in_one_line(tmp_path):
    out = tmp_path / "r.jsonl"
    with pytest.raises(ValueError, match="random, scenes: give one of them"):
        evaluate_task_batch(SKILL, out)
    with pytest.raises(ValueError, match=r"goal: expected 3 finite coordinates"):
        evaluate_task_batch(SKILL, out, random=2, goal=[0.1, 0.2])
    with pytest.raises(ValueError, match=r"speed_fraction: must be in \(0, 1\]"):
        evaluate_task_batch(SKILL, out, random=2, speed_fraction=0)
    flat = tmp_path / "flat.csv"
    flat.write_text("demo,class,x,y,radius\na,cup,0.1,0.2,0.03\n")
    with pytest.raises(ValueError, match="scene 'a' is 2-D; the skill is 3-D"):
        evaluate_task_batch(SKILL, out, scenes=flat)
    assert not out.exists()


@pytest.mark.slow  # Skill.to_units refits (~5 s)
def test_a_skill_in_millimetres_is_refused(tmp_path):
    mm = tmp_path / "mm.json"
    Skill.load(SKILL).to_units("mm").save(mm)
    with pytest.raises(ValueError, match="a skill in 'mm'; the robot works in metres"):
        evaluate_task_batch(mm, tmp_path / "r.jsonl", random=2)
    assert not (tmp_path / "r.jsonl").exists()


def test_the_command_on_a_urdf_arm_with_a_task_file(tmp_path, capsys):
    task = tmp_path / "task.json"
    task.write_text(json.dumps({"name": "reach", "offset": [0.05, 0, 0], "tool_length": 0.1}))
    results, summary = tmp_path / "r.jsonl", tmp_path / "summary.json"
    argv = ["batch", "evaluate", SKILL, "--arm", URDFS / "ur5e.urdf"]
    argv += ["--task-file", task, "--random", 1, "--seed", 7, "--check", "robot"]
    code, out, err = run_cli(capsys, *argv, "-o", results, "--summary", summary)
    assert code == 0, err
    assert "ran 1 of 1 tasks" in err
    assert out.startswith("1 tasks: 1 ok, 0 not ok, 0 errors\n")
    assert "robot / plan duration" in out
    written = json.loads(summary.read_text())
    assert written["tasks"] == 1 and written["results"] == str(results)
    header = json.loads(results.read_text().splitlines()[0])["spec"]
    assert header["task"] == "path" and header["description"]["name"] == "reach"
    assert header["description"]["tool"][2][3] == 0.1
    (row,) = read_results(results)
    assert row["scenario"] == {"seed": 7, "index": 0}
    assert row["goal"] == random_goal(Skill.load(SKILL).path_[-1], 0.05, 7, 0).tolist()
    # Run again: resumed, nothing to do; the table is of the whole file.
    code, out, err = run_cli(capsys, *argv, "-o", results, "--summary", summary, "--force")
    assert code == 0, err


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--task-file", "t.json", "--offset", "0", "0", "0"], "--offset: the task file describes"),
        (["--check", "kinematics"], "--check kinematics: is the sweeping task's"),
        (["--task", "sweep", "--arm", "ur10"], "--arm: is for --task path"),
        (["--task", "sweep", "--approach", "0.1"], "--approach: is for --task path"),
        (["--task", "sweep", "--unknown-class", "margin=0"], "--unknown-class: is for --task"),
        (["--arm", "kuka"], "--arm: kuka is neither an arm name"),
        (["--spread", "-1"], "--spread: expected a radius in metres (e.g. 0.05), got '-1'"),
        (["--task-file", "missing.json"], "--task-file missing.json: no such file"),
        (["--goal", "0.1,0.2"], "--goal: 2 coordinates for a 3-D skill"),
        (["--scenes", "s.csv", "--spread", "0.1"], "--spread is for --random"),
        (["--rate", "5000"], "--rate: must be in [1, 1000] Hz, got 5000.0"),
    ],
)
def test_the_command_refuses_bad_combinations_in_one_line(extra, message, tmp_path, capsys):
    (tmp_path / "s.csv").write_text("demo,class,x,y,z,radius\na,box,0.4,0,0.3,0.02\n")
    which = [] if "--scenes" in extra else ["--random", 1]
    argv = ["batch", "evaluate", SKILL, *which, *extra, "-o", tmp_path / "r.jsonl"]
    with pytest.MonkeyPatch.context() as patch:
        patch.chdir(tmp_path)
        code, _, err = run_cli(capsys, *argv)
    assert code in (1, 2), err
    assert message in err and err.count("\n") == 1, err
    assert not (tmp_path / "r.jsonl").exists()


def test_a_bad_task_file_is_one_line_naming_it(tmp_path, capsys):
    task = tmp_path / "task.json"
    task.write_text(json.dumps({"offest": [0, 0, 0]}))
    argv = ["batch", "evaluate", SKILL, "--task", "path", "--random", 1, "--task-file", task]
    code, _, err = run_cli(capsys, *argv, "-o", tmp_path / "r.jsonl")
    assert code == 1 and err.count("\n") == 1
    assert f"--task-file {task}: unknown key 'offest'" in err


@pytest.mark.slow  # one MuJoCo run of a 4 s motion (~3 s)
def test_the_mujoco_check_on_the_panda_tracks_within_2_mm(text):
    arm = arm_spec(URDFS / "panda.urdf", "panda_hand_tcp")
    where = {"seed": 0, "index": 0, "spread": 0.02, "start": None, "goal": None}
    row = evaluate_task(text, where, arm, TaskDescription().to_dict(), "mujoco", 0.5)
    assert row["ok"] and row["failure"] is None
    assert row["simulation"]["tracking_error_m"] < 0.002
    assert row["simulation"]["touched"] == []
    assert row["robot"]["duration_ratio"] == pytest.approx(1.0)  # half speed: timing kept
