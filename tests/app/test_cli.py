"""Tests for the ``lfdkit`` command (lfdkit.app.cli): help, learn, plan, plot, bench and demo.

Most tests call :func:`lfdkit.app.cli.main` in-process and read stdout/stderr with
``capsys``; the demo test runs the installed console script in a subprocess, as
the README does. The example skill is learned once per module.
"""

from __future__ import annotations

import io
import json
import os
import re
import subprocess
import sys
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path
from types import SimpleNamespace

import matplotlib.image as mpimg
import numpy as np
import pytest

from lfdkit.app.cli import main
from lfdkit.core.geometry import path_length
from lfdkit.emulate.metrics import clearance as path_clearance
from lfdkit.imitate import SpeedProfile
from lfdkit.io import SKILL_VERSION, save_demos
from lfdkit.io.scenes import save_scenes
from lfdkit.model.scene import Obstacle, Scene
from lfdkit.skill import Skill
from lfdkit.tasks.sweeping import demo_outputs, example_files

SUBCOMMANDS = ("demo", "import", "learn", "plan", "plot", "compare", "datasets", "batch", "bench")
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
REPO = Path(__file__).resolve().parents[2]

# Two small clean demonstrations: a skill without obstacle reward, learned in a blink.
SMALL_DEMOS = "demo,x,y\n1,0,0\n1,0.5,0.1\n1,1,0\n2,0,0\n2,0.5,0.05\n2,1,0\n"

# Where the plan tests put their obstacles (the example sweeps run from x=-0.4 to 0.4 at y~0.45).
START, GOAL = (-0.4, 0.45), (0.36, 0.5)
CUP = ("cup", (-0.02, 0.47), 0.03)
MARKER = ("marker", (0.15, 0.47), 0.01)


# --------------------------------------------------------------------------- #
# Helpers and fixtures
# --------------------------------------------------------------------------- #


def run_cli(capsys: pytest.CaptureFixture[str], *argv: object) -> tuple[int, str, str]:
    """``main(argv)`` in-process: (exit code, stdout, stderr)."""
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def usage_exit(capsys: pytest.CaptureFixture[str], *argv: object) -> tuple[int, str, str]:
    """``main(argv)`` for arguments argparse handles itself: (SystemExit code, stdout, stderr)."""
    with pytest.raises(SystemExit) as exc:
        main([str(a) for a in argv])
    captured = capsys.readouterr()
    return exc.value.code, captured.out, captured.err


def error_line(err: str, command: str) -> str:
    """The one stderr line of a failed command, checked for the ``lfdkit CMD: error:`` form."""
    lines = err.splitlines()
    assert len(lines) == 1, f"expected one stderr line, got {len(lines)}: {err!r}"
    assert lines[0].startswith(f"lfdkit {command}: error: "), lines[0]
    return lines[0]


def obstacle_arg(obstacle: tuple[str, tuple[float, float], float]) -> str:
    label, (x, y), r = obstacle
    return f"{label}:{x!r},{y!r},r={r!r}"


def scene_of(*obstacles: tuple[str, tuple[float, float], float]) -> Scene:
    return Scene(tuple(Obstacle(label, np.array(pos), r) for label, pos, r in obstacles))


def read_plan_table(text: str) -> dict[str, np.ndarray]:
    """The columns of a plan CSV by name (``t``, ``x``, ``y``, ``vx``, ...), in file order."""
    lines = text.splitlines()
    rows = np.array([[float(v) for v in line.split(",")] for line in lines[1:]], dtype=np.float64)
    return dict(zip(lines[0].split(","), rows.T, strict=True))


def read_plan_csv(text: str) -> tuple[str, np.ndarray]:
    """(header line, positions: the x,y[,z] columns as rows) of a plan CSV."""
    table = read_plan_table(text)
    return text.splitlines()[0], np.column_stack([table[c] for c in "xyz" if c in table])


def comparable(skill_dict: dict) -> dict:
    """A skill dict as JSON reads it, without the creation time and the timings."""

    def strip(value):
        if isinstance(value, dict):
            return {k: strip(v) for k, v in value.items() if k != "seconds"}
        if isinstance(value, list):
            return [strip(v) for v in value]
        return value

    data = json.loads(json.dumps(skill_dict))
    data.pop("created", None)
    return strip(data)


@pytest.fixture(scope="module")
def examples() -> dict[str, Path]:
    return example_files()


@pytest.fixture(scope="module")
def learned(tmp_path_factory: pytest.TempPathFactory, examples: dict[str, Path]):
    """The example skill, learned once with ``lfdkit learn ... -q``, with what it printed."""
    path = tmp_path_factory.mktemp("skill") / "skill.json"
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        demos, scenes = str(examples["demos"]), str(examples["scenes"])
        code = main(["learn", demos, "--scenes", scenes, "-o", str(path), "-q"])
    return SimpleNamespace(path=path, code=code, stdout=out.getvalue(), stderr=err.getvalue())


@pytest.fixture(scope="module")
def skill_path(learned) -> Path:
    assert learned.code == 0, learned.stderr
    return learned.path


@pytest.fixture
def small_demos(tmp_path: Path) -> Path:
    path = tmp_path / "small.csv"
    path.write_text(SMALL_DEMOS)
    return path


# --------------------------------------------------------------------------- #
# 1. Help, version, usage
# --------------------------------------------------------------------------- #


@pytest.mark.parametrize("command", [None, *SUBCOMMANDS])
def test_help_exits_zero_and_prints_usage(capsys, command):
    argv = ["--help"] if command is None else [command, "--help"]
    code, out, err = usage_exit(capsys, *argv)
    assert code == 0
    prog = "lfdkit" if command is None else f"lfdkit {command}"
    assert out.startswith(f"usage: {prog} "), out[:200]
    assert err == ""
    if command is None:
        for name in SUBCOMMANDS:
            assert name in out


def test_learn_option_defaults_are_the_skills(capsys, monkeypatch, small_demos):
    """Every option of ``learn`` that sets a Skill parameter defaults to Skill()'s value."""
    passed = {}

    def fake_learn(demos_path, scenes_path=None, *, progress=None, **params):
        passed.update(params)
        raise ValueError("stop here")

    monkeypatch.setattr("lfdkit.skill.learn", fake_learn)
    code, _, err = run_cli(capsys, "learn", small_demos, "-o", "never.json")
    assert code == 1, err
    assert set(passed) == {
        "mimic",
        "n_points",
        "random_state",
        "planner",
        "horizon",
        "model",
        "duration",
    }  # no units without --units: the Skill's default, and implausible metres refused
    defaults = Skill().get_params()
    assert passed == {name: defaults[name] for name in passed}
    code, out, _ = usage_exit(capsys, "learn", "--help")
    assert code == 0
    text = " ".join(out.split())
    for name in ("mimic", "n_points", "planner", "horizon", "units"):
        assert f"(default {defaults[name]}" in text, name


def test_learn_help_lists_the_csv_columns_and_every_mimic_method(capsys):
    from lfdkit.mimic import MIMIC_METHODS

    code, out, _ = usage_exit(capsys, "learn", "--help")
    assert code == 0
    text = " ".join(out.split())
    for columns in ("x,y[,z]", "demo", "t or time", "qx,qy,qz,qw", "demo,class,x,y[,z][,radius]"):
        assert columns in text, columns
    assert "without it the file is one demonstration" in text
    assert "DEMOS [DEMOS ...]" in text
    assert ", ".join(MIMIC_METHODS) in text
    for option in ("--planner {mpc,full}", "--model {auto,thesis,path}", "--units {m,cm,mm}"):
        assert option in text


def test_learn_from_several_files_one_demonstration_each(capsys, tmp_path):
    """A recorder's takes: one CSV per demonstration, no demo column; the same skill."""
    rng = np.random.default_rng(11)
    s = np.linspace(0.0, 1.0, 40)
    takes = []
    for _ in range(4):
        take = np.column_stack([0.8 * s - 0.4, 0.45 + 0.1 * np.sin(np.pi * s)])
        takes.append(take + 0.003 * rng.standard_normal(take.shape))
    files = []
    for k, take in enumerate(takes):
        files.append(tmp_path / f"take_{k:02d}.csv")
        files[-1].write_text("x,y\n" + "".join(f"{x!r},{y!r}\n" for x, y in take.tolist()))
    code, _, err = run_cli(capsys, "learn", *files, "-o", tmp_path / "takes.json")
    assert code == 0, err
    assert "learned from 4 clean demonstrations" in err
    # The same demonstrations in one file with a demo column give the same skill.
    save_demos(tmp_path / "all.csv", takes)
    code, _, err = run_cli(capsys, "learn", tmp_path / "all.csv", "-o", tmp_path / "all.json")
    assert code == 0, err
    np.testing.assert_array_equal(
        Skill.load(tmp_path / "takes.json").path_, Skill.load(tmp_path / "all.json").path_
    )
    # A scene file names a take by its file's stem.
    scenes = tmp_path / "scenes.csv"
    scenes.write_text("demo,class,x,y,radius\ntake_09,cup,0,0.5,0.02\n")
    code, _, err = run_cli(capsys, "learn", *files, "--scenes", scenes, "-o", tmp_path / "x.json")
    assert code == 1
    assert "demo 'take_09' is not in" in error_line(err, "learn")
    # Files that disagree: one line naming both.
    flat = tmp_path / "flat3d.csv"
    flat.write_text("x,y,z\n0,0,0\n0.5,0,0\n1,0,0\n")
    code, _, err = run_cli(capsys, "learn", files[0], flat, "-o", tmp_path / "y.json")
    assert code == 1
    line = error_line(err, "learn")
    assert f"{flat}: has 3-D demonstrations, but {files[0]} has 2-D demonstrations" in line
    assert not (tmp_path / "y.json").exists()


def test_version(capsys):
    code, out, err = usage_exit(capsys, "--version")
    assert code == 0
    assert out.strip() == "lfdkit 0.1.0"
    assert err == ""


@pytest.mark.parametrize(
    "argv",
    [[], ["--bogus"], ["nosuch"], ["learn", "x.csv", "-o", "s.json", "--bogus"], ["plan"]],
    ids=["no-command", "unknown-top-option", "unknown-command", "unknown-option", "missing-arg"],
)
def test_usage_errors_exit_2(capsys, argv):
    code, out, err = usage_exit(capsys, *argv)
    assert code == 2
    assert out == ""
    assert "usage: lfdkit" in err
    assert "error:" in err


# --------------------------------------------------------------------------- #
# 2. learn
# --------------------------------------------------------------------------- #


def test_learn_quiet_prints_nothing(learned):
    assert learned.code == 0, learned.stderr
    assert learned.stdout == ""
    assert learned.stderr == ""
    assert learned.path.is_file()


def test_learn_cli_matches_python_api(skill_path, example_skill_once):
    from_cli = json.loads(skill_path.read_text())
    # The session's learn(example demos, example scenes), default parameters.
    from_api = example_skill_once.to_dict()
    assert from_cli["version"] == SKILL_VERSION
    cli, api = comparable(from_cli), comparable(from_api)
    for field in ("path", "reward", "params"):
        assert cli[field] == api[field], field
    assert cli == api
    assert np.array(cli["path"]).shape == (100, 2)
    assert set(cli["reward"]["precisions"]) == {"cup", "marker"}


def test_learn_refuses_to_overwrite_then_force(capsys, tmp_path, small_demos):
    out = tmp_path / "skill.json"
    out.write_text("precious\n")
    code, stdout, err = run_cli(capsys, "learn", small_demos, "-o", out)
    assert code == 1
    line = error_line(err, "learn")
    assert "--force" in line
    assert str(out) in line
    assert stdout == ""
    assert out.read_text() == "precious\n"

    code, stdout, err = run_cli(capsys, "learn", small_demos, "-o", out, "--force", "-q")
    assert code == 0, err
    assert (stdout, err) == ("", "")
    skill = Skill.load(out)
    assert skill.n_dims_ == 2
    assert skill.reward_ is None


def test_learn_output_is_a_directory(capsys, tmp_path, small_demos):
    folder = tmp_path / "somewhere"
    folder.mkdir()
    code, stdout, err = run_cli(capsys, "learn", small_demos, "-o", folder)
    assert code == 1
    assert str(folder) in error_line(err, "learn")
    assert "directory" in err
    assert stdout == ""
    assert list(folder.iterdir()) == []


# --------------------------------------------------------------------------- #
# 3. plan
# --------------------------------------------------------------------------- #


def test_plan_csv_equals_the_python_plan(capsys, tmp_path, skill_path):
    out = tmp_path / "plan.csv"
    code, stdout, err = run_cli(
        capsys,
        "plan",
        skill_path,
        f"--start={START[0]},{START[1]}",
        "--goal",
        f"{GOAL[0]},{GOAL[1]}",
        "--obstacle",
        obstacle_arg(CUP),
        "-o",
        out,
    )
    assert code == 0, err
    assert stdout == ""
    header, rows = read_plan_csv(out.read_text())
    assert header == "t,x,y"
    assert rows.shape == (100, 2)
    skill = Skill.load(skill_path)
    assert np.array_equal(rows, skill.plan(START, GOAL, scene_of(CUP)))
    assert not np.allclose(rows, skill.plan(START, GOAL), atol=1e-3)  # the cup is avoided
    assert np.array_equal(rows[0], START)


def test_plan_ends_at_the_goal_by_default(capsys, skill_path):
    goal = np.array([0.36, 0.5])
    cup = "cup:0.0,0.47,r=0.03"
    args = ("plan", skill_path, "--goal", "0.36,0.5", "--obstacle", cup)
    code, stdout, err = run_cli(capsys, *args, "--goal-approach", "none")
    assert code == 0, err
    thesis_end = read_plan_csv(stdout)[1][-1]
    assert np.linalg.norm(thesis_end - goal) > 0.02  # the swerve leaves it beside the goal
    skill = Skill.load(skill_path)
    scene = Scene((Obstacle("cup", [0.0, 0.47], 0.03),))
    for extra, approach in (((), "auto"), (("--goal-approach", "0.1"), 0.1)):
        code, stdout, err = run_cli(capsys, *args, *extra)
        assert code == 0, err
        rows = read_plan_csv(stdout)[1]
        np.testing.assert_allclose(rows[-1], goal, atol=1e-3)
        assert np.array_equal(rows, skill.plan(None, goal, scene, goal_approach=approach))
    for bad in ("0", "-1", "soon", "nan"):
        code, _, err = usage_exit(capsys, *args, "--goal-approach", bad)
        assert code == 2
        assert "--goal-approach" in err


def test_plan_keeps_out_of_the_radius_plus_clearance(capsys, skill_path):
    # The example: a 10 cm cup the learned response alone passes 3.9 cm inside.
    args = ("plan", skill_path, "--goal", "0.36,0.5", "--obstacle", "cup:0.0,0.46,r=0.1")
    scene = Scene((Obstacle("cup", [0.0, 0.46], 0.1),))
    for clearance in ("0", "0.025"):
        code, stdout, err = run_cli(capsys, *args, "--clearance", clearance, "-v")
        assert code == 0, err
        rows = read_plan_csv(stdout)[1]
        assert path_clearance(rows, scene, float(clearance))[0] >= 0.0
        assert "from the goal" in err and "beyond radius + clearance" in err
    # No way round within the action bound: refused on one line, exit 1.
    nominal = Skill.load(skill_path).nominal(None, [0.36, 0.5])
    middle = nominal[len(nominal) // 2]
    across = np.array([-1.0, 1.0]) * (nominal[-1] - nominal[0])[::-1]
    across /= np.linalg.norm(across)
    wall = [middle + t * across for t in np.arange(-0.6, 0.61, 0.08)]
    obstacles = [arg for x, y in wall for arg in ("--obstacle", f"cup:{x:.4f},{y:.4f},r=0.05")]
    code, stdout, err = run_cli(capsys, "plan", skill_path, "--goal", "0.36,0.5", *obstacles)
    assert code == 1
    assert stdout == ""
    assert "no collision-free plan" in err and len(err.strip().splitlines()) == 1


def test_plan_with_a_moving_obstacle(capsys, skill_path):
    # vx, vy: the plan keeps clear of where the cup is when the brush passes.
    from lfdkit.model.motion import ConstantVelocity

    cup = "cup:0.0,0.30,r=0.03,vx=0,vy=0.3"
    args = ("plan", skill_path, "--obstacle", cup, "--clearance", "0.02", "--duration", "1")
    code, stdout, err = run_cli(capsys, *args, "-v")
    assert code == 0, err
    rows = read_plan_csv(stdout)[1]
    skill = Skill.load(skill_path)
    moving = Obstacle("cup", [0.0, 0.30], 0.03, motion=ConstantVelocity([0.0, 0.3]))
    plan = skill.plan(scene=Scene((moving,)), clearance=0.02, duration=1.0)
    assert np.array_equal(rows, plan.points)
    assert not np.array_equal(rows, skill.plan(scene=Scene((moving.at(0.0),)), clearance=0.02))
    code, _, err = usage_exit(capsys, "plan", skill_path, "--obstacle", "cup:0,0.3,vx=0.1")
    assert code == 2 and "vy=" in err


def test_plan_with_a_fast_marker_is_clear_at_the_plans_own_times(capsys, skill_path):
    # Issue 27: a standing cup forces a detour, a marker crosses at 4 m/s; the plan's CSV
    # times are the ones it is clear at (the planner's were the nominal's).
    from lfdkit.emulate.planner import moving_clearance
    from lfdkit.model.motion import ConstantVelocity

    args = (
        "plan",
        skill_path,
        "--goal",
        "0.36,0.5",
        "--obstacle",
        "cup:0.0,0.46,r=0.1",
        "--obstacle",
        "marker:-0.327,-0.893,r=0.01,vx=0.283,vy=3.99",
        "--duration",
        "1",
    )
    code, stdout, err = run_cli(capsys, *args)
    assert code == 0, err
    table = read_plan_table(stdout)
    times, points = table["t"], np.column_stack([table["x"], table["y"]])
    marker = Obstacle("marker", [-0.327, -0.893], 0.01, motion=ConstantVelocity([0.283, 3.99]))
    scene = Scene((Obstacle("cup", [0.0, 0.46], 0.1), marker))
    assert np.all(moving_clearance(points, times, scene, 0.0, 2.0) >= -1e-6)


def test_plan_without_output_writes_csv_to_stdout(capsys, skill_path):
    code, stdout, err = run_cli(capsys, "plan", skill_path, "--obstacle", obstacle_arg(MARKER))
    assert code == 0, err
    assert err == ""
    header, rows = read_plan_csv(stdout)
    assert header == "t,x,y"
    assert rows.shape == (100, 2)
    skill = Skill.load(skill_path)
    assert np.array_equal(rows, skill.plan(None, None, scene_of(MARKER)))
    assert not np.allclose(rows, skill.plan(), atol=1e-3)  # the marker is avoided


def test_plan_scene_file_equals_obstacle_args(capsys, tmp_path, skill_path):
    scene_file = tmp_path / "scene.csv"
    save_scenes(scene_file, {0: scene_of(CUP, MARKER)})
    goal = ["--goal", f"{GOAL[0]},{GOAL[1]}"]
    code, from_file, err = run_cli(capsys, "plan", skill_path, *goal, "--scene", scene_file)
    assert code == 0, err
    code, from_args, err = run_cli(
        capsys,
        "plan",
        skill_path,
        *goal,
        "--obstacle",
        obstacle_arg(CUP),
        "--obstacle",
        obstacle_arg(MARKER),
    )
    assert code == 0, err
    assert from_file == from_args
    code, free, err = run_cli(capsys, "plan", skill_path, *goal)
    assert code == 0, err
    assert not np.array_equal(read_plan_csv(from_file)[1], read_plan_csv(free)[1])


@pytest.mark.parametrize(
    ("args", "fragments"),
    [
        (["--obstacle", "bottle:0,0.45"], ["'bottle'", "cup", "marker"]),
        (["--goal", "1,2,3"], ["--goal", "3 coordinates", "2-D"]),
        (["--obstacle", "cup:0,0.45,0.1"], ["--obstacle cup", "3 coordinates", "2-D"]),
        (["--horizon", "20"], ["horizon", "20"]),
    ],
    ids=["unknown-class", "3-D-goal", "3-D-obstacle", "horizon"],
)
def test_plan_bad_arguments_exit_1(capsys, tmp_path, skill_path, args, fragments):
    out = tmp_path / "plan.csv"
    code, stdout, err = run_cli(capsys, "plan", skill_path, *args, "-o", out)
    assert code == 1
    line = error_line(err, "plan")
    for fragment in fragments:
        assert fragment in line
    assert stdout == ""
    assert not out.exists()


def test_plan_around_an_unlearned_class_with_unknown_class(capsys, skill_path):
    bottle = ("bottle", (-0.05, 0.47), 0.03)
    args = ("plan", skill_path, "--goal", "0.36,0.5", "--obstacle", obstacle_arg(bottle))
    # Refused without the option, the one error line naming it in the command's words.
    code, stdout, err = run_cli(capsys, *args)
    assert code == 1 and stdout == ""
    line = error_line(err, "plan")
    assert "'bottle' was never learned" in line
    assert "pass --unknown-class margin=M" in line and "unknown_class=" not in line
    # With it: radius + margin + clearance kept, and the warning says how it was planned.
    code, stdout, err = run_cli(
        capsys, *args, "--unknown-class", "margin=0.02", "--clearance", "0.005", "-v"
    )
    assert code == 0, err
    assert "'bottle' never learned: planned around it (1 obstacle) as a hard radius plus " in err
    assert "margin 0.02 m (plus the clearance) with no learned response" in err
    assert "around 1 obstacle in" in err  # not "1 obstacles"
    rows = read_plan_csv(stdout)[1]
    assert path_clearance(rows, scene_of(bottle), 0.025)[0] >= -1e-12
    nominal = Skill.load(skill_path).nominal(None, [0.36, 0.5])
    assert path_clearance(nominal, scene_of(bottle), 0.025)[0] < 0.0  # it had to swerve


def test_plan_an_unlearned_class_with_the_nearest_learned_response(capsys, skill_path):
    pen = ("pen", (-0.05, 0.47), 0.008)
    args = ("plan", skill_path, "--goal", "0.36,0.5", "--obstacle", obstacle_arg(pen))
    option = ("--unknown-class", "margin=0.01,response=nearest", "-v")
    code, stdout, err = run_cli(capsys, *args, *option)
    assert code == 0, err
    assert "'pen' takes the learned response of 'marker' (radius 0.008 m against 0.01 m)" in err
    nearest = read_plan_csv(stdout)[1]
    code, stdout, _ = run_cli(capsys, *args, "--unknown-class", "margin=0.01,response=marker")
    assert code == 0
    np.testing.assert_array_equal(read_plan_csv(stdout)[1], nearest)
    code, stdout, err = run_cli(capsys, *args, "--unknown-class", "margin=0.01,response=bowl")
    assert code == 1 and stdout == ""
    line = error_line(err, "plan")
    assert "error: --unknown-class response: 'bowl' is not a learned class" in line


@pytest.mark.parametrize(
    "value",
    [
        "0.02",
        "margin=",
        "margin=-1",
        "radius=0.1",
        "margin=nan",
        "margin=0.02,response=",
        "margin=0.02,colour=red",
        "margin=1,margin=2",
        "response=cup",
    ],
)
def test_plan_bad_unknown_class_is_a_usage_error(capsys, skill_path, value):
    code, out, err = usage_exit(capsys, "plan", skill_path, "--unknown-class", value)
    assert code == 2 and out == ""
    assert "--unknown-class: expected" in err and repr(value) in err


def test_plan_non_numeric_goal_is_a_usage_error(capsys, skill_path):
    code, out, err = usage_exit(capsys, "plan", skill_path, "--goal", "a,b")
    assert code == 2
    assert out == ""
    assert "--goal" in err
    assert "'a,b'" in err


def test_plan_missing_skill_file(capsys, tmp_path):
    missing = tmp_path / "no_such_skill.json"
    code, out, err = run_cli(capsys, "plan", missing)
    assert code == 1
    assert str(missing) in error_line(err, "plan")
    assert out == ""


def test_plan_accepts_a_negative_start_as_a_separate_argument(capsys, skill_path):
    try:
        code = main(["plan", str(skill_path), "--start", "-0.4,0.45", "--goal", "0.36,0.5"])
    except SystemExit as exc:
        code = exc.code
    captured = capsys.readouterr()
    assert code == 0, captured.err
    _, rows = read_plan_csv(captured.out)
    assert np.array_equal(rows[0], START)


def test_plan_writes_times_in_seconds_and_with_velocities_the_velocities(capsys, skill_path):
    # The example has no times: the skill's law, minimum jerk over its duration, the
    # path's length at a hand's pace (0.2 m/s on average: the 0.8 m sweep, about 4 s).
    skill = Skill.load(skill_path)
    expected = skill.plan(None, GOAL, scene_of(CUP))
    args = ("plan", skill_path, "--goal", f"{GOAL[0]},{GOAL[1]}", "--obstacle", obstacle_arg(CUP))
    code, stdout, err = run_cli(capsys, *args, "--velocities")
    assert code == 0, err
    assert stdout.splitlines()[0] == "t,x,y,vx,vy"
    table = read_plan_table(stdout)
    assert table["t"][0] == 0.0 and table["t"][-1] == skill.timing_.duration
    assert skill.timing_.duration == path_length(skill.path_) / 0.2
    assert np.all(np.diff(table["t"]) > 0)
    np.testing.assert_array_equal(table["t"], expected.times)
    np.testing.assert_array_equal(np.c_[table["x"], table["y"]], expected.points)
    np.testing.assert_array_equal(np.c_[table["vx"], table["vy"]], expected.velocities)
    assert table["vx"][0] == table["vy"][0] == table["vx"][-1] == table["vy"][-1] == 0.0
    # --duration and --speed rescale the times (and the velocities), not the path.
    half = skill.timing_.duration / 2
    for option, value, total in (("--duration", "3", 3.0), ("--speed", "2", half)):
        code, stdout, err = run_cli(capsys, *args, "--velocities", option, value)
        assert code == 0, err
        scaled = read_plan_table(stdout)
        assert scaled["t"][-1] == total
        ratio = total / table["t"][-1]
        np.testing.assert_allclose(scaled["t"], ratio * table["t"], rtol=1e-12)
        np.testing.assert_allclose(scaled["vx"], table["vx"] / ratio, rtol=1e-12, atol=1e-15)
        np.testing.assert_array_equal(scaled["x"], table["x"])
    code, _, err = run_cli(capsys, *args, "-v")
    assert code == 0, err
    assert f"lasts {skill.timing_.duration:.4g} s, peak speed" in err and "m/s" in err
    assert "duration is assumed" in err


def test_plan_at_a_fixed_rate_streams_the_same_motion(capsys, skill_path):
    skill = Skill.load(skill_path)
    expected = skill.plan(None, GOAL, scene_of(CUP))
    args = ("plan", skill_path, "--goal", f"{GOAL[0]},{GOAL[1]}", "--obstacle", obstacle_arg(CUP))
    code, stdout, err = run_cli(capsys, *args, "--velocities", "--rate", "125", "-v")
    assert code == 0, err
    assert "written at 125 Hz" in err
    table = read_plan_table(stdout)
    np.testing.assert_allclose(np.diff(table["t"]), 1 / 125, rtol=0, atol=1e-12)
    assert table["t"][-1] >= expected.duration > table["t"][-2]
    # The stream passes through the planned points: at the plan's own times it is the
    # plan (between them, a cubic through points and velocities: within 0.1 mm here).
    stream = expected.at_rate(125)
    np.testing.assert_array_equal(np.c_[table["x"], table["y"]], stream.points)
    np.testing.assert_array_equal(np.c_[table["vx"], table["vy"]], stream.velocities)
    for axis, column in enumerate("xy"):
        between = np.interp(expected.times, table["t"], table[column])
        assert np.max(np.abs(between - expected.points[:, axis])) < 1e-4
    np.testing.assert_array_equal(stream.points[-1], expected.points[-1])
    for bad in ("0", "-5", "fast"):
        code, stdout, err = run_cli(capsys, *args, "--rate", bad)
        assert code == 2 and stdout == "", err
        assert "--rate: expected a positive rate in Hz" in error_line(err, "plan")
    code, stdout, err = run_cli(capsys, *args, "--rate", "1e9")
    assert code == 1 and stdout == ""
    assert "--rate: 1e+09 Hz over" in error_line(err, "plan") and "lower the rate" in err


def test_plan_follows_the_timing_learned_from_a_timed_demonstrations_file(capsys, tmp_path):
    # Three sweeps recorded over 2, 3 and 4 s, at minimum jerk along the path.
    x = np.linspace(0.0, 1.0, 2000)
    path = np.c_[x, 0.1 * np.sin(np.pi * x)]
    along = np.r_[0.0, np.cumsum(np.hypot(*np.diff(path, axis=0).T))]
    law = SpeedProfile.minimum_jerk()
    demos, times = [], []
    for duration in (2.0, 3.0, 4.0):
        t = np.linspace(0.0, duration, 120)
        s = law.progress(t / duration) * along[-1]
        demos.append(np.c_[np.interp(s, along, path[:, 0]), np.interp(s, along, path[:, 1])])
        times.append(t)
    demos_file = save_demos(tmp_path / "timed.csv", demos, times=times)
    skill_file = tmp_path / "timed.json"
    code, _, err = run_cli(capsys, "learn", demos_file, "-o", skill_file, "-q")
    assert code == 0, err
    code, stdout, err = run_cli(capsys, "plan", skill_file, "--velocities")
    assert code == 0, err
    table = read_plan_table(stdout)
    assert table["t"][-1] == pytest.approx(3.0)  # the median duration, in seconds
    speed = np.hypot(table["vx"], table["vy"])
    peak = 1.875 * np.sum(np.hypot(np.diff(table["x"]), np.diff(table["y"]))) / 3.0
    assert speed.max() == pytest.approx(peak, rel=0.01)


@pytest.mark.parametrize(
    ("bad", "message"),
    [
        (("--duration", "-1"), "--duration: expected a positive number of seconds, got '-1'"),
        (("--duration", "-1e3"), "--duration: expected a positive number of seconds"),
        (("--duration", "0"), "--duration: expected a positive number of seconds, got '0'"),
        (("--duration", "nan"), "--duration: expected a positive number of seconds"),
        (("--duration", "soon"), "--duration: expected a positive number of seconds"),
        (("--speed", "0"), "--speed: expected a positive speed factor, got '0'"),
        (("--speed", "-2"), "--speed: expected a positive speed factor, got '-2'"),
        (("--speed", "inf"), "--speed: expected a positive speed factor, got 'inf'"),
        (("--duration", "2", "--speed", "2"), "--speed: give --duration or --speed, not both"),
    ],
)
def test_plan_refuses_a_bad_duration_or_speed_naming_the_option(
    capsys, tmp_path, skill_path, bad, message
):
    out = tmp_path / "plan.csv"
    code, stdout, err = run_cli(capsys, "plan", skill_path, *bad, "-o", out)
    assert code == 2
    assert stdout == "" and not out.exists()
    assert error_line(err, "plan").startswith(f"lfdkit plan: error: {message}")


def test_plan_refuses_a_duration_out_of_range_on_one_line(capsys, skill_path):
    for option, value in (("--speed", "1e-12"), ("--duration", "1e12")):
        code, stdout, err = run_cli(capsys, "plan", skill_path, option, value)
        assert code == 1 and stdout == ""
        assert f"{option}: the plan would last" in error_line(err, "plan") or (
            f"{option}: expected" in error_line(err, "plan")
        )


def test_learn_refuses_nan_times_naming_the_file(capsys, tmp_path):
    demos = tmp_path / "nan.csv"
    demos.write_text("demo,t,x,y\n1,0,0,0\n1,nan,0.5,0.1\n1,2,1,0\n2,0,0,0\n2,1,0.5,0\n2,2,1,0\n")
    code, stdout, err = run_cli(capsys, "learn", demos, "-o", tmp_path / "s.json")
    assert code == 1 and stdout == ""
    line = error_line(err, "learn")
    assert "nan.csv" in line and "nan" in line.split("nan.csv", 1)[1]
    assert not (tmp_path / "s.json").exists()


# --------------------------------------------------------------------------- #
# 4. plot
# --------------------------------------------------------------------------- #


def check_png(path: Path) -> np.ndarray:
    assert path.read_bytes()[:8] == PNG_SIGNATURE
    image = mpimg.imread(path)
    assert image.ndim == 3
    assert image.shape[0] > 100
    assert image.shape[1] > 100
    return image


@pytest.mark.parametrize("with_obstacles", [False, True], ids=["no-obstacles", "obstacles"])
def test_plot_writes_a_png(capsys, tmp_path, skill_path, examples, with_obstacles):
    out = tmp_path / "skill.png"
    args = ["plot", skill_path, "-o", out, "-q"]
    if with_obstacles:
        args += ["--obstacle", obstacle_arg(CUP), "--obstacle", obstacle_arg(MARKER)]
        args += ["--demos", examples["demos"], "--goal", f"{GOAL[0]},{GOAL[1]}"]
    code, stdout, err = run_cli(capsys, *args)
    assert code == 0, err
    assert (stdout, err) == ("", "")
    check_png(out)


def test_plot_of_a_skill_without_reward(capsys, tmp_path, small_demos):
    skill = tmp_path / "small.json"
    code, _, err = run_cli(capsys, "learn", small_demos, "-o", skill, "-q")
    assert code == 0, err
    out = tmp_path / "small.png"
    code, _, err = run_cli(capsys, "plot", skill, "-o", out, "--demos", small_demos)
    assert code == 0, err
    assert str(out) in err
    check_png(out)


# --------------------------------------------------------------------------- #
# 5. Bad input files
# --------------------------------------------------------------------------- #

GOOD_SCENES = "demo,class,x,y,radius\n"
BAD_LEARN_INPUTS = {
    # id: (demos file, its content, scenes content or None, fragments besides the file name)
    "missing-column": ("demos.csv", "demo,y\n1,0.1\n1,0.2\n1,0.3\n", None, ["'x'"]),
    "non-numeric": (
        "demos.csv",
        "demo,x,y\n1,0,0\n1,0.5,abc\n1,1,0\n2,0,0\n2,0.5,0.1\n2,1,0\n",
        None,
        ["line 3", "'y'", "'abc'"],
    ),
    "single-row": ("demos.csv", SMALL_DEMOS + "3,0,0\n", None, ["demo '3'", "1 row"]),
    "mixed-dims": (
        "demos.json",
        json.dumps(
            {
                "format": "lfdkit-demos",
                "version": 1,
                "n_dims": 2,
                "demos": [
                    {"id": "flat", "points": [[0, 0], [0.5, 0.1], [1, 0]]},
                    {"id": "tall", "points": [[0, 0, 0], [0.5, 0.1, 0], [1, 0, 0]]},
                ],
            }
        ),
        None,
        ["demos[1]", "'tall'", "3 dimensions"],
    ),
    "scene-unknown-demo": (
        "demos.csv",
        SMALL_DEMOS,
        GOOD_SCENES + "ghost,cup,0.5,0.2,0.03\n",
        ["'ghost'"],
    ),
    "scene-non-numeric": (
        "demos.csv",
        SMALL_DEMOS,
        GOOD_SCENES + "1,cup,0.5,zz,0.03\n",
        ["line 2", "'y'", "'zz'"],
    ),
}


@pytest.mark.parametrize(
    ("demos_name", "demos_text", "scenes_text", "fragments"),
    list(BAD_LEARN_INPUTS.values()),
    ids=list(BAD_LEARN_INPUTS),
)
def test_learn_bad_input_files(capsys, tmp_path, demos_name, demos_text, scenes_text, fragments):
    demos = tmp_path / demos_name
    demos.write_text(demos_text)
    args = ["learn", demos]
    culprit = demos
    if scenes_text is not None:
        culprit = tmp_path / "scenes.csv"
        culprit.write_text(scenes_text)
        args += ["--scenes", culprit]
    out = tmp_path / "skill.json"
    code, stdout, err = run_cli(capsys, *args, "-o", out, "-q")
    assert code == 1
    line = error_line(err, "learn")
    assert str(culprit) in line
    for fragment in fragments:
        assert fragment in line
    assert stdout == ""
    assert not out.exists()


def test_learn_two_row_demo_names_the_file_and_demo(capsys, tmp_path):
    demos = tmp_path / "demos.csv"
    demos.write_text("demo,x,y\nfirst,0,0\nfirst,0.5,0.1\nfirst,1,0\nshort,0,0\nshort,1,0\n")
    code, _, err = run_cli(capsys, "learn", demos, "-o", tmp_path / "skill.json", "-q")
    assert code == 1
    line = error_line(err, "learn")
    assert str(demos) in line
    assert "short" in line


def test_learn_failure_without_quiet_is_one_clean_line(capsys, tmp_path):
    demos = tmp_path / "demos.csv"
    demos.write_text("demo,y\n1,0.1\n1,0.2\n1,0.3\n")
    code, _, err = run_cli(capsys, "learn", demos, "-o", tmp_path / "skill.json")
    assert code == 1
    assert "\r" not in err, repr(err)
    assert str(demos) in error_line(err, "learn")


def _future(data: dict, text: str) -> str:
    data["version"] = 99
    return json.dumps(data, indent=1)


def _truncated(data: dict, text: str) -> str:
    return text[: len(text) // 2]


def _no_path(data: dict, text: str) -> str:
    del data["path"]
    return json.dumps(data, indent=1)


@pytest.mark.parametrize(
    ("breaker", "fragments"),
    [(_future, ["version 99", "newer"]), (_truncated, ["not valid JSON"]), (_no_path, ["path"])],
    ids=["future-version", "truncated", "missing-path"],
)
def test_plan_refuses_a_broken_skill_file(capsys, tmp_path, skill_path, breaker, fragments):
    text = skill_path.read_text()
    broken = tmp_path / "broken.json"
    broken.write_text(breaker(json.loads(text), text))
    code, out, err = run_cli(capsys, "plan", broken)
    assert code == 1
    line = error_line(err, "plan")
    assert str(broken) in line
    for fragment in fragments:
        assert fragment in line
    if breaker is _truncated:
        with pytest.raises(json.JSONDecodeError) as exc:
            json.loads(broken.read_text())
        assert f"line {exc.value.lineno}:" in line
    if breaker is _no_path:
        assert re.search(r": path: missing field$", line), line
    assert out == ""


def test_plan_refuses_a_skill_file_with_absurd_n_points(capsys, tmp_path, skill_path):
    data = json.loads(skill_path.read_text())
    data["params"]["n_points"] = 10**15
    broken = tmp_path / "huge.json"
    broken.write_text(json.dumps(data))
    code, _, err = run_cli(capsys, "plan", broken)
    assert code == 1
    assert "n_points" in error_line(err, "plan")


# --------------------------------------------------------------------------- #
# 6. The installed command, end to end
# --------------------------------------------------------------------------- #


def test_demo_command_end_to_end(demo_runs):
    """Two whole demos, run at once (the session's ``demo_runs``): one with ``-v`` (its
    output, every stage line, one clock for terminal and report; then a rerun without
    ``--force`` is refused), one ``--quiet --force`` over a stale output folder (silent,
    and the stale results are overwritten)."""
    out, first = demo_runs.out, demo_runs.verbose
    assert first.returncode == 0, first.stderr[-2000:]
    assert "held-out sweeps" in first.stdout
    for path in demo_outputs(out):
        assert path.is_file(), path

    html = (out / "report.html").read_text(encoding="utf-8")
    assert html.count("data:image/png;base64,") >= 4
    assert 'src="http' not in html
    results_text = (out / "results.json").read_text()
    results = json.loads(results_text)
    assert results["emulate"]["test"]["improvement"] > 90
    assert results["lfdkit"] == "0.1.0"
    Skill.load(out / "skill.json")
    # The terminal's whole-run time is the report's: one clock, one span.
    said = re.search(r"^done in (\d+\.\d) s; open ", first.stderr, re.M)
    assert said, first.stderr
    assert said.group(1) == f"{results['seconds']['total']:.1f}"
    reported = re.search(r"whole run</dt><dd[^>]*>([0-9.]+) s<", html)
    assert reported and reported.group(1) == said.group(1)
    # -v: every step of the demo, and the stages inside them, with their wall times.
    for stage in (
        "learn the skill from data/demos.csv and data/scenes.csv",
        "IOC MPC H=8: refining",
        "score the held-out sweeps",
        "plan in 3 unseen scenes with a new goal",
        "simulate the sweep in MuJoCo (UR5)",
        "draw the figures",
        "write the skill, the plans, the figures, the results and the report",
    ):
        line = rf"\] +{re.escape(stage)}: done in [0-9.]+ s$"
        assert re.search(line, first.stderr, re.M), stage

    command = ["lfdkit", "demo", "--output", str(out)]
    again = subprocess.run(
        command, capture_output=True, text=True, timeout=300, cwd=demo_runs.folder
    )
    assert again.returncode == 1
    errors = [line for line in again.stderr.splitlines() if "error:" in line]
    assert len(errors) == 1, again.stderr
    assert errors[0].startswith("lfdkit demo: error: ")
    assert "--force" in errors[0]
    assert (out / "results.json").read_text() == results_text

    quiet = demo_runs.quiet_run
    assert quiet.returncode == 0, quiet.stderr[-2000:]
    assert quiet.stdout == ""
    # -q silences progress and summaries, never a warning that a result may be poor:
    # the thesis's scenes hold one gap no training demonstration showed (issue 26).
    said = quiet.stderr.splitlines()
    assert all(line.startswith("lfdkit demo: warning: plan: obstacles") for line in said), said
    assert all("whether the person would pass between them is not known" in s for s in said)
    for path in demo_outputs(demo_runs.quiet):
        assert path.is_file(), path
    # --force: the stale results were overwritten.
    assert json.loads((demo_runs.quiet / "results.json").read_text())["lfdkit"] == "0.1.0"


# --------------------------------------------------------------------------- #
# 7. bench
# --------------------------------------------------------------------------- #


def test_bench_unknown_name_lists_the_available_ones(capsys):
    folder = REPO / "benchmarks"
    names = [p.stem for p in folder.glob("*.py")] + [
        p.parent.name for p in folder.glob("*/__main__.py")
    ]
    available = sorted(name for name in names if not name.startswith("_"))
    assert "emulate" in available, "no benchmarks/emulate/ package in the checkout"
    code, out, err = run_cli(capsys, "bench", "no_such_benchmark")
    assert code == 1
    line = error_line(err, "bench")
    assert "'no_such_benchmark'" in line
    assert line.endswith("choose from " + ", ".join(available))
    assert out == ""


BENCHMARK = """import pathlib, sys
here = pathlib.Path(__file__).resolve().parent
(here / "ran.txt").write_text(f"{pathlib.Path.cwd()} {' '.join(sys.argv[1:])}")
"""


def test_bench_runs_the_benchmarks_of_the_folder_given(capsys, tmp_path):
    folder = tmp_path / "mine"
    folder.mkdir()
    (folder / "hello.py").write_text(BENCHMARK)
    code, out, err = run_cli(capsys, "bench", "--benchmarks", folder, "hello", "--quick", "-q")
    assert (code, out) == (0, ""), err
    assert (folder / "ran.txt").read_text() == f"{tmp_path} --quick"


def test_bench_finds_benchmarks_in_the_current_folder(capsys, monkeypatch, tmp_path):
    (tmp_path / "benchmarks").mkdir()
    (tmp_path / "benchmarks" / "hello.py").write_text(BENCHMARK)
    monkeypatch.chdir(tmp_path)
    code, out, err = run_cli(capsys, "bench", "-q")
    assert (code, out) == (0, ""), err
    assert (tmp_path / "benchmarks" / "ran.txt").read_text() == f"{tmp_path} "


def test_bench_without_benchmarks_is_a_usage_error_naming_where_it_looked(
    capsys, monkeypatch, tmp_path
):
    import lfdkit.app.cli.bench

    # An installed package: no source checkout around the module.
    monkeypatch.setattr(
        lfdkit.app.cli.bench,
        "__file__",
        str(tmp_path / "site" / "lfdkit" / "app" / "cli" / "bench.py"),
    )
    monkeypatch.chdir(tmp_path)
    code, out, err = run_cli(capsys, "bench")
    assert code == 2
    line = err.strip()
    assert line.startswith("lfdkit bench: error: no benchmarks folder: looked for ")
    assert str(tmp_path / "benchmarks") in line
    assert "--benchmarks DIR" in line
    assert out == ""
    code, out, err = run_cli(capsys, "bench", "--benchmarks", tmp_path / "nowhere")
    assert code == 2
    assert err == f"lfdkit bench: error: --benchmarks {tmp_path / 'nowhere'}: no such folder\n"


# --------------------------------------------------------------------------- #
# 8. Never a traceback; outputs checked before the work
# --------------------------------------------------------------------------- #


def _raiser(exc: BaseException):
    def handler(args) -> None:
        raise exc

    return handler


def test_unexpected_exception_is_one_line_without_traceback(capsys, monkeypatch, small_demos):
    monkeypatch.setattr(
        "lfdkit.app.cli.learn.run_command", _raiser(RuntimeError("boom\nsecond line"))
    )
    code, out, err = run_cli(capsys, "learn", small_demos, "-o", "never.json")
    assert code == 1
    line = error_line(err, "learn")
    assert line == "lfdkit learn: error: unexpected RuntimeError: boom (run with -v for details)"
    assert "Traceback" not in err
    assert out == ""


def test_unexpected_exception_with_verbose_shows_the_traceback(capsys, monkeypatch, small_demos):
    monkeypatch.setattr("lfdkit.app.cli.learn.run_command", _raiser(KeyError("deep")))
    code, _, err = run_cli(capsys, "learn", small_demos, "-o", "never.json", "-v")
    assert code == 1
    assert err.startswith("Traceback (most recent call last):")
    assert "KeyError: 'deep'" in err
    assert err.splitlines()[-1].startswith("lfdkit learn: error: unexpected KeyError: 'deep'")


def test_interrupt_exits_130_with_one_line(capsys, monkeypatch, small_demos):
    monkeypatch.setattr("lfdkit.app.cli.learn.run_command", _raiser(KeyboardInterrupt()))
    code, out, err = run_cli(capsys, "learn", small_demos, "-o", "never.json")
    assert code == 130
    assert err == "lfdkit learn: interrupted\n"
    assert out == ""


def test_memory_error_names_the_inputs_to_check(capsys, monkeypatch, small_demos):
    monkeypatch.setattr("lfdkit.app.cli.learn.run_command", _raiser(MemoryError()))
    code, _, err = run_cli(capsys, "learn", small_demos, "-o", "never.json", "--n-points", "77")
    assert code == 1
    line = error_line(err, "learn")
    assert "out of memory" in line
    assert "--n-points 77" in line
    assert str(small_demos) in line


def test_file_exists_error_from_the_library_says_force(capsys, monkeypatch, tmp_path, small_demos):
    # The library's own wording (for Python callers) must not reach the command line.
    def save(self, path, *, overwrite=False):
        raise FileExistsError(f"{path}: file already exists; pass overwrite=True to replace it")

    monkeypatch.setattr("lfdkit.skill.Skill.save", save)
    out = tmp_path / "skill.json"
    code, _, err = run_cli(capsys, "learn", small_demos, "-o", out)
    assert code == 1
    line = error_line(err, "learn")
    assert line == f"lfdkit learn: error: {out}: exists; pass --force to overwrite it"


def _no_learning(*args, **kwargs):
    raise AssertionError("learned although the output cannot be written")


@pytest.mark.parametrize("command", ["learn", "plan", "plot"])
def test_unwritable_output_folder_fails_before_the_work(capsys, monkeypatch, tmp_path, command):
    monkeypatch.setattr("lfdkit.skill.learn", _no_learning)
    monkeypatch.setattr("lfdkit.app.cli.common._load_skill", _no_learning)
    blocker = tmp_path / "a_file"
    blocker.write_text("not a folder\n")
    out = blocker / "out.json"
    first = tmp_path / "demos.csv" if command == "learn" else tmp_path / "skill.json"
    code, stdout, err = run_cli(capsys, command, first, "-o", out)
    assert code == 1
    line = error_line(err, command)
    assert f"--output {out}: cannot write in folder {blocker}" in line
    assert stdout == ""


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() == 0, reason="root writes anyway")
def test_read_only_output_folder_fails_before_learning(capsys, monkeypatch, tmp_path, small_demos):
    monkeypatch.setattr("lfdkit.skill.learn", _no_learning)
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o555)
    try:
        code, _, err = run_cli(capsys, "learn", small_demos, "-o", folder / "skill.json")
    finally:
        folder.chmod(0o755)
    assert code == 1
    assert "cannot write in folder" in error_line(err, "learn")


def test_existing_output_is_refused_before_learning(capsys, monkeypatch, tmp_path, small_demos):
    monkeypatch.setattr("lfdkit.skill.learn", _no_learning)
    out = tmp_path / "skill.json"
    out.write_text("{}")
    code, _, err = run_cli(capsys, "learn", small_demos, "-o", out)
    assert code == 1
    assert error_line(err, "learn").endswith(f"{out}: exists; pass --force to overwrite it")


@pytest.mark.parametrize("command", ["learn", "plan", "plot"])
def test_a_link_as_output_is_refused_before_the_work_even_with_force(
    capsys, monkeypatch, tmp_path, command
):
    # --force replaces a regular file only; a link (or a device) is said before any work.
    monkeypatch.setattr("lfdkit.skill.learn", _no_learning)
    monkeypatch.setattr("lfdkit.app.cli.common._load_skill", _no_learning)
    target = tmp_path / "kept.csv"
    target.write_text("kept\n")
    out = tmp_path / "out.json"
    out.symlink_to(target)
    first = tmp_path / "demos.csv" if command == "learn" else tmp_path / "skill.json"
    code, stdout, err = run_cli(capsys, command, first, "-o", out, "--force")
    assert code == 1
    line = error_line(err, command)
    assert f"--output {out}: is a symbolic link" in line
    assert target.read_text() == "kept\n" and stdout == ""


def test_flipped_demonstration_is_reported_only_with_verbose(capsys, tmp_path):
    # Demonstration 2 of three is recorded backwards: learned forwards, said at -v.
    rows = ["demo,x,y"]
    for j, dy in enumerate((0.0, 0.02, -0.02)):
        points = [(float(x), float(0.1 * np.sin(np.pi * x) + dy)) for x in np.linspace(0, 1, 12)]
        rows += [f"{j},{x!r},{y!r}" for x, y in (points[::-1] if j == 2 else points)]
    demos = tmp_path / "demos.csv"
    demos.write_text("\n".join(rows) + "\n")
    code, _, err = run_cli(capsys, "learn", demos, "-o", tmp_path / "a.json")
    assert code == 0, err
    assert "warning" not in err
    code, _, err = run_cli(capsys, "learn", demos, "-o", tmp_path / "b.json", "-v")
    assert code == 0, err
    warned = [line for line in err.splitlines() if "warning" in line]
    assert warned == [
        "lfdkit learn: warning: MeanPath: reversed demonstration(s) 2 of 3 to run in the "
        "others' direction"
    ]
    skill = Skill.load(tmp_path / "b.json")
    assert skill.mimic_info_["reversed"] == [2]
    path = skill.path_
    np.testing.assert_allclose(path[0], [0.0, 0.0], atol=0.02)
    np.testing.assert_allclose(path[-1], [1.0, 0.0], atol=0.02)


def test_several_motions_are_one_clean_error(capsys, tmp_path):
    rows = ["demo,x,y"]
    for j, side in enumerate((-1, -1, 1, 1)):
        for a in np.linspace(0, 1, 15):
            x, y = float(side * (1 - a)), float(0.4 * np.sin(np.pi * a) + 0.01 * j)
            rows.append(f"{j},{x!r},{y!r}")
    demos = tmp_path / "demos.csv"
    demos.write_text("\n".join(rows) + "\n")
    code, _, err = run_cli(capsys, "learn", demos, "-o", tmp_path / "s.json", "--mimic", "gmr")
    assert code == 1
    assert "several motions" in error_line(err, "learn")
    assert not (tmp_path / "s.json").exists()


# --------------------------------------------------------------------------- #
# 9. lfdkit demo: an interrupted run never looks complete (run_demo itself:
#    tests/tasks/sweeping/test_demo.py)
# --------------------------------------------------------------------------- #


def test_demo_cli_refuses_existing_outputs_before_the_work(capsys, monkeypatch, tmp_path):
    monkeypatch.setattr("lfdkit.tasks.sweeping.demo._run_into", _no_learning)
    out = tmp_path / "demo"
    (out / "figures").mkdir(parents=True)
    (out / "figures" / "mimic.png").write_text("old\n")
    code, _, err = run_cli(capsys, "demo", "-o", out)
    assert code == 1
    line = error_line(err, "demo")
    assert line.endswith("mimic.png exists; pass --force to overwrite it")


def test_broken_pipe_is_one_line(capsys, monkeypatch, small_demos):
    monkeypatch.setattr(
        "lfdkit.app.cli.learn.run_command", _raiser(BrokenPipeError(32, "Broken pipe"))
    )
    code, _, err = run_cli(capsys, "learn", small_demos, "-o", "never.json")
    assert code == 1
    assert error_line(err, "learn").endswith("standard output closed early (broken pipe)")


_SLOW_DEMO = """
import sys, time
from lfdkit.tasks.sweeping import demo as sweeping_demo
from lfdkit.app.cli import main

def slow(out, progress, started):
    (out / "figures").mkdir()
    (out / "figures" / "mimic.png").write_text("half\\n")
    print("started", flush=True)
    time.sleep(60)

sweeping_demo._run_into = slow
sys.argv = ["lfdkit", "demo", "-o", sys.argv[1]]
raise SystemExit(main())
"""


def test_a_killed_demo_leaves_nothing_behind(tmp_path):
    import signal

    out = tmp_path / "demo"
    env = {**os.environ, "PYTHONPATH": str(REPO / "src")}
    process = subprocess.Popen(
        [sys.executable, "-c", _SLOW_DEMO, str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
    )
    try:
        assert process.stdout.readline() == "started\n"
        assert [p.name.startswith(".demo.partial-") for p in tmp_path.iterdir()] == [True]
        process.send_signal(signal.SIGTERM)
        _, err = process.communicate(timeout=30)
    finally:
        if process.poll() is None:
            process.kill()
            process.communicate()
    assert process.returncode == 130
    assert err.splitlines()[-1] == "lfdkit demo: interrupted"
    assert list(tmp_path.iterdir()) == []


def test_learn_exits_1_and_writes_nothing_when_the_reward_fit_fails(
    capsys, tmp_path, examples, monkeypatch
):
    import lfdkit.emulate.ioc

    class TwoIterations(lfdkit.emulate.ioc.IOC):
        def __init__(self, *args, **kwargs):
            super().__init__(*args, **{**kwargs, "max_iter": 2})

    # The reward fit and the behaviour-model refits import the IOC where they fit.
    monkeypatch.setattr(lfdkit.emulate.ioc, "IOC", TwoIterations)
    out = tmp_path / "skill.json"
    code, stdout, err = run_cli(
        capsys, "learn", examples["demos"], "--scenes", examples["scenes"], "-o", out, "-q"
    )
    assert code == 1
    line = error_line(err, "learn")
    assert "did not converge" in line
    assert "ITERATIONS" in line
    assert "wrote nothing" in line
    assert stdout == ""
    assert not out.exists()


def test_learn_says_under_q_that_far_obstacles_cannot_be_learned(capsys, tmp_path, examples):
    """Issue 27: obstacles 10 m from every demonstration exited 0 under -q with nothing said."""
    from lfdkit.io.scenes import load_scenes

    far = {
        k: Scene(tuple(o.translated([10.0, 10.0]) for o in s))
        for k, s in load_scenes(examples["scenes"]).items()
    }
    save_scenes(tmp_path / "far.csv", far)
    out = tmp_path / "skill.json"
    code, _, err = run_cli(
        capsys, "learn", examples["demos"], "--scenes", tmp_path / "far.csv", "-o", out, "-q"
    )
    assert code == 0, err
    lines = err.splitlines()
    for label in ("cup", "marker"):
        said = [
            line
            for line in lines
            if line.startswith(
                f"lfdkit learn: warning: obstacle {label!r} is never near any demonstration"
            )
        ]
        assert len(said) == 1, lines
        assert said[0].endswith(
            f"its class cannot be learned from these demonstrations: show one passing within "
            f"{0.25 * 0.8:.3g} of a {label!r}; planning a scene with it is refused unless a "
            "reward for it is adopted (e.g. Skill.adopt)"
        )
    assert out.is_file()


def test_learn_shows_the_reward_fit_warnings_as_lines(capsys, tmp_path, examples, monkeypatch):
    import warnings

    import lfdkit.emulate.ioc

    class Warns(lfdkit.emulate.ioc.IOC):
        def fit(self, *args, **kwargs):
            warnings.warn("obstacle class 'vase' was not learned: ...", UserWarning, stacklevel=2)
            return super().fit(*args, **kwargs)

    # The reward fit and the behaviour-model refits import the IOC where they fit.
    monkeypatch.setattr(lfdkit.emulate.ioc, "IOC", Warns)
    out = tmp_path / "skill.json"
    code, _, err = run_cli(
        capsys, "learn", examples["demos"], "--scenes", examples["scenes"], "-o", out
    )
    assert code == 0, err
    assert "lfdkit learn: warning: obstacle class 'vase' was not learned: ..." in err.splitlines()
    assert out.is_file()
    code, _, err = run_cli(
        capsys,
        "learn",
        examples["demos"],
        "--scenes",
        examples["scenes"],
        "-o",
        out,
        "-q",
        "--force",
    )
    assert code == 0
    # -q silences progress and the summary, not a warning about the result (issue 27).
    assert err.splitlines() == ["lfdkit learn: warning: obstacle class 'vase' was not learned: ..."]
