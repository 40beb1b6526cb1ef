"""``lfdkit learn --task-frames`` and ``plan --frame``: a task-frame skill on the command line."""

from __future__ import annotations

import io
import json

import numpy as np
import pytest

from lfdkit.imitate import TaskFrame
from lfdkit.io import save_demos
from lfdkit.model.demos import Demo
from lfdkit.skill import TaskFrameSkill
from tests.app.test_cli import error_line, run_cli

REACH = "tests/app/data/reach3d.json"  # a skill from a start to a goal


@pytest.fixture(scope="module")
def sweeps(tmp_path_factory):
    """Sweeps into a pan moved and turned at random, with frame_start_* and frame_pan_* columns."""
    folder = tmp_path_factory.mktemp("task_frames")
    rng = np.random.default_rng(4)
    t = np.linspace(0.0, 1.0, 80)
    hook = np.c_[-0.3 * (1 - t) ** 2, 0.06 * np.sin(np.pi * t) * (1 - t)]
    demos = []
    for _ in range(6):
        pan = np.r_[rng.uniform(0.4, 0.7, 2), rng.uniform(-1.0, 1.0)]
        start = np.r_[rng.uniform(-0.05, 0.05, 2), 0.0]
        path = TaskFrame.from_vector(pan).to_world(hook) + 5e-4 * rng.normal(size=hook.shape)
        demos.append(Demo(path, 1.6 * t, frames={"start": start, "pan": pan}))
    return save_demos(folder / "sweeps.csv", demos), folder


def test_learn_then_plan_the_new_poses(capsys, sweeps, tmp_path) -> None:
    demos, _ = sweeps
    skill_file = tmp_path / "frames.json"
    code, _, err = run_cli(
        capsys, "learn", demos, "--task-frames", "--components", 8, "-o", skill_file
    )
    assert code == 0, err
    assert err.startswith("learned a task-frame skill: 2-D movement in the task frames start, pan")
    out = tmp_path / "plan.csv"
    poses = ["--frame", "start=0.01,-0.02,0", "--frame", "pan=0.55,0.35,1.7"]
    code, _, err = run_cli(capsys, "plan", skill_file, *poses, "-o", out, "--velocities")
    assert code == 0, err
    assert "planned 100 points in the task frames start, pan; lasts 1.6 s" in err
    assert out.read_text().splitlines()[0] == "t,x,y,vx,vy"
    table = np.loadtxt(out, delimiter=",", skiprows=1)
    # The file's plan is the library's, to the bit (CSV floats are written exactly).
    plan = TaskFrameSkill.load(skill_file).plan(
        {"start": [0.01, -0.02, 0.0], "pan": [0.55, 0.35, 1.7]}
    )
    np.testing.assert_array_equal(table[:, 1:3], plan.positions)
    np.testing.assert_array_equal(table[:, 3:], plan.velocities)
    assert np.linalg.norm(table[-1, 1:3] - [0.55, 0.35]) < 0.01  # into the pan
    mm = ["--frame", "start=10,-20,0", "--frame", "pan=550,350,1.7", "--units", "mm"]
    code, written, err = run_cli(capsys, "plan", skill_file, *mm)
    assert code == 0, err
    in_mm = np.loadtxt(io.StringIO(written), delimiter=",", skiprows=1)
    np.testing.assert_allclose(in_mm[:, 1:3], 1e3 * plan.positions, rtol=0, atol=1e-6)
    code, written, err = run_cli(capsys, "plan", skill_file, *poses, "--speed", 2, "--points", 11)
    assert code == 0, err
    faster = np.loadtxt(io.StringIO(written), delimiter=",", skiprows=1)  # to standard output
    assert faster.shape == (11, 3) and faster[-1, 0] == 0.8


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        (["--frame", "pan=0.5,0.3,1"], "--frame: missing start; this skill was learned in"),
        (
            ["--frame", "start=0,0,0", "--frame", "pan=0.5,0.3"],
            "--frame pan: pose: expected [x, y, angle] (2-D)",
        ),
        ([], "--frame: give each frame's new pose: start, pan"),
        (
            ["--frame", "start=0,0,0", "--frame", "pan=0.5,0.3,1", "--goal", "1,1"],
            "--goal: ",
        ),
        (
            ["--frame", "start=0,0,0", "--frame", "start=0,0,1", "--frame", "pan=0.5,0.3,1"],
            "--frame: a frame given twice",
        ),
    ],
)
def test_plan_errors_are_one_line(capsys, sweeps, tmp_path, argv, expected) -> None:
    demos, folder = sweeps
    skill_file = folder / "learned.json"
    if not skill_file.exists():
        assert run_cli(capsys, "learn", demos, "--task-frames", "-o", skill_file)[0] == 0
    code, _, err = run_cli(capsys, "plan", skill_file, *argv)
    assert code in (1, 2)
    assert expected in error_line(err, "plan")


def test_the_other_commands_and_kinds_refuse_on_one_line(capsys, sweeps, tmp_path) -> None:
    demos, folder = sweeps
    skill_file = folder / "learned.json"
    if not skill_file.exists():
        assert run_cli(capsys, "learn", demos, "--task-frames", "-o", skill_file)[0] == 0
    code, _, err = run_cli(capsys, "plan", REACH, "--frame", "pan=0,0,0")
    assert code == 2
    assert "--frame: only for a task-frame skill" in error_line(err, "plan")
    code, _, err = run_cli(capsys, "learn", demos, "--components", 4, "-o", tmp_path / "s.json")
    assert code == 2 and "--components: only with --task-frames" in error_line(err, "learn")
    plain = save_demos(tmp_path / "plain.csv", [np.c_[np.linspace(0, 1, 9), np.zeros(9)]] * 2)
    code, _, err = run_cli(capsys, "learn", plain, "--task-frames", "-o", tmp_path / "t.json")
    assert code == 1 and "carry no task frames" in error_line(err, "learn")
    assert not (tmp_path / "t.json").exists()


def test_plot_and_execute_take_a_task_frame_skill(capsys, sweeps, tmp_path) -> None:
    demos, folder = sweeps
    skill_file = folder / "learned.json"
    if not skill_file.exists():
        assert run_cli(capsys, "learn", demos, "--task-frames", "-o", skill_file)[0] == 0
    poses = ["--frame", "start=0.6,0.05,0", "--frame", "pan=0.5,0.3,1.5"]
    png = tmp_path / "frames.png"
    code, _, err = run_cli(capsys, "plot", skill_file, *poses, "--demos", demos, "-o", png)
    assert code == 0, err
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    code, _, err = run_cli(capsys, "plot", skill_file, "-o", tmp_path / "none.png")
    assert code == 2 and "--frame: give each frame's new pose" in error_line(err, "plot")
    out = tmp_path / "run"
    code, _, err = run_cli(capsys, "execute", skill_file, *poses, "--no-sim", "-o", out)
    assert code == 0, err
    summary = json.loads((out / "summary.json").read_text())
    planned = np.loadtxt(out / "plan.csv", delimiter=",", skiprows=1)
    plan = TaskFrameSkill.load(skill_file).plan({"start": [0.6, 0.05, 0.0], "pan": [0.5, 0.3, 1.5]})
    assert len(planned) == len(plan.times) and summary["robot"]["poses"] >= len(plan.times)
    code, _, err = run_cli(capsys, "execute", REACH, "--frame", "pan=0,0,0", "-o", tmp_path / "r")
    assert code == 2 and "--frame: only for a task-frame skill" in error_line(err, "execute")


def test_millimetres_without_units_are_refused_then_learned_with_them(capsys, sweeps, tmp_path):
    demos, _ = sweeps
    from lfdkit.io import load_demos

    records = load_demos(demos, as_records=True)
    in_mm = [
        Demo(
            r.points * 1e3,
            r.times,
            frames={k: np.r_[v[:2] * 1e3, v[2:]] for k, v in r.frames.items()},
        )
        for r in records
    ]
    path = save_demos(tmp_path / "sweeps_mm.csv", in_mm)
    code, _, err = run_cli(capsys, "learn", path, "--task-frames", "-o", tmp_path / "a.json")
    assert code == 1 and "pass --units mm if that is their unit" in error_line(err, "learn")
    code, _, err = run_cli(
        capsys, "learn", path, "--task-frames", "--units", "mm", "-o", tmp_path / "b.json"
    )
    assert code == 0, err
    assert TaskFrameSkill.load(tmp_path / "b.json").units == "mm"


def test_a_skill_with_the_tools_orientation_plans_it(capsys, tmp_path) -> None:
    from tests.skill.test_task_frames import _turned_demos

    demos = save_demos(tmp_path / "turned.csv", _turned_demos(6, seed=12))
    skill_file = tmp_path / "turned.json"
    code, _, err = run_cli(
        capsys, "learn", demos, "--task-frames", "--components", 6, "-o", skill_file
    )
    assert code == 0, err
    assert "2-D movement with the tool's orientation in the task frames start, pan" in err
    out = tmp_path / "plan.csv"
    poses = ["--frame", "start=0.2,-0.25,0", "--frame", "pan=0.6,-0.1,0.5"]
    assert run_cli(capsys, "plan", skill_file, *poses, "-o", out)[0] == 0
    assert out.read_text().splitlines()[0] == "t,x,y,qx,qy,qz,qw"
    table = np.loadtxt(out, delimiter=",", skiprows=1)
    plan = TaskFrameSkill.load(skill_file).plan({"start": [0.2, -0.25, 0], "pan": [0.6, -0.1, 0.5]})
    # the written quaternions normalised once more (as every orientation file's): to an ulp
    np.testing.assert_allclose(table[:, 3:], plan.orientations, rtol=0, atol=1e-15)
    png = tmp_path / "turned.png"  # the tool's axis drawn along the plan
    assert run_cli(capsys, "plot", skill_file, *poses, "--demos", demos, "-o", png)[0] == 0
    assert png.read_bytes()[:4] == b"\x89PNG"
