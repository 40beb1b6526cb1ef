"""Tests for ``lfdkit execute``: a learned skill on a UR arm, from the command line.

The shipped example skill (learned once per module) sweeps to a moved
dustpan around a cup and a marker: every output is written and reads back
(the URScript with the reader of ``tests/robot/test_urscript.py``), the UR10
is a parameter, what the arm cannot do ends in one line and exit status 1
with nothing written, and existing files are kept unless ``--force``.
"""

from __future__ import annotations

import json
from pathlib import Path

import matplotlib.image as mpimg
import numpy as np
import pytest

from lfdkit.app.cli import main
from tests.app.test_cli import run_cli
from tests.conftest import example_skill_file_copy
from tests.execute.test_urscript import read_program

GOAL = "0.36,0.5"
SCENE = ["--obstacle", "cup:-0.05,0.49", "--obstacle", "marker:0.15,0.455"]
#: Beyond the UR5's reach at the sweeping height, within the UR10's.
FAR_GOAL = "0.9,0.45"
FILES = ("plan.csv", "poses.csv", "joints.csv", "program.script", "summary.json")


def one_error_line(err: str) -> str:
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("lfdkit execute: error: "), lines[0]
    return lines[0]


@pytest.fixture(scope="module")
def skill_path(example_skill_file_once, tmp_path_factory) -> Path:
    return example_skill_file_copy(example_skill_file_once, tmp_path_factory.mktemp("skill"))


@pytest.fixture(scope="module")
def executed(skill_path, tmp_path_factory):
    """``lfdkit execute`` of the example skill with a UR5, simulated and rendered."""
    out = tmp_path_factory.mktemp("execute") / "ur5"
    code = main(["execute", str(skill_path), "--goal", GOAL, *SCENE, "--render", "-o", str(out)])
    return code, out


def test_execute_writes_every_output_and_they_read_back(executed):
    code, out = executed
    assert code == 0
    for name in (*FILES, "sweep.png"):
        assert (out / name).is_file(), name
    summary = json.loads((out / "summary.json").read_text())
    assert summary["arm"] == "UR5" and summary["speed_fraction"] == 0.2
    assert summary["simulation"]["success"] is True, summary["simulation"]
    assert summary["plan"]["clearance_m"] >= 0.0
    assert [o["radius"] for o in summary["scene"]] == [0.03, 0.01]  # the classes' radii
    program = read_program((out / "program.script").read_text())
    joints = np.loadtxt(out / "joints.csv", delimiter=",", skiprows=1)
    assert len(program.servoj) == len(joints) == summary["robot"]["samples"]
    np.testing.assert_allclose([q for q, *_ in program.servoj], joints[:, 1:], atol=5e-10)
    assert (out / "plan.csv").read_text().startswith("t,x,y\n")  # the learned timing too
    plan = np.loadtxt(out / "plan.csv", delimiter=",", skiprows=1)
    np.testing.assert_allclose(plan[-1, 1:], [0.36, 0.5], atol=1e-3)
    assert plan[0, 0] == 0.0 and (np.diff(plan[:, 0]) > 0).all()
    # The first movej within --speed-fraction 0.2, as the servoj stream: UR's 1.4 and 1.05 x 0.2.
    assert "], a=0.28, v=0.21)" in (out / "program.script").read_text()
    poses = np.loadtxt(out / "poses.csv", delimiter=",", skiprows=1)
    assert poses.shape == (summary["robot"]["poses"], 7)
    assert mpimg.imread(out / "sweep.png").ndim == 3
    # The picture: where OpenGL works, MuJoCo's; the summary says which.
    assert (out / "render.png").is_file() == summary["simulation"]["rendered"]
    listed = {*FILES, "sweep.png", *(["render.png"] if summary["simulation"]["rendered"] else [])}
    assert set(summary["files"]) == listed


def test_execute_says_what_it_did(skill_path, tmp_path, capsys):
    code, out, err = run_cli(
        capsys, "execute", skill_path, "--goal", GOAL, *SCENE, "--no-sim", "-o", tmp_path / "x"
    )
    assert code == 0, err
    assert out == ""
    lines = err.splitlines()
    assert lines[0].startswith("planned a 0.8")
    assert "UR5: " in lines[0] and "20% of its joint limits" in lines[0]
    assert lines[-1].startswith(f"wrote 5 files in {tmp_path / 'x'}/ in ")
    assert not (tmp_path / "x" / "sweep.png").exists()
    code, out, err = run_cli(
        capsys, "execute", skill_path, "--goal", GOAL, "--no-sim", "-o", tmp_path / "q", "-q"
    )
    assert (code, out, err) == (0, "", "")


def test_an_unreachable_goal_is_one_line_exit_1_and_nothing_written(skill_path, tmp_path, capsys):
    out = tmp_path / "far"
    code, _, err = run_cli(capsys, "execute", skill_path, "--goal", FAR_GOAL, "-o", out)
    assert code == 1
    line = one_error_line(err)
    assert "the UR5 cannot follow the plan: poses[" in line
    assert "unreachable (position (" in line and "m along the" in line
    assert line.endswith("; wrote nothing")
    assert not out.exists() or list(out.iterdir()) == []


def test_the_ur10_reaches_that_goal(skill_path, tmp_path, capsys):
    out = tmp_path / "ur10"
    code, _, err = run_cli(
        capsys, "execute", skill_path, "--goal", FAR_GOAL, "--arm", "ur10", "-o", out
    )
    assert code == 0, err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["arm"] == "UR10"
    assert summary["simulation"]["success"] is True, summary["simulation"]
    read_program((out / "program.script").read_text())


def test_existing_outputs_are_refused_before_the_work_then_forced(
    skill_path, tmp_path, capsys, monkeypatch
):
    out = tmp_path / "again"
    out.mkdir()
    (out / "program.script").write_text("mine\n")

    def no_work(*args, **kwargs):
        raise AssertionError("the work started")

    with monkeypatch.context() as patch:
        patch.setattr("lfdkit.tasks.sweeping.execution.execute_skill", no_work)
        code, _, err = run_cli(capsys, "execute", skill_path, "--no-sim", "-o", out)
    assert code == 1
    assert one_error_line(err).endswith("program.script exists; pass --force to overwrite it")
    assert (out / "program.script").read_text() == "mine\n"
    code, _, err = run_cli(capsys, "execute", skill_path, "--no-sim", "-o", out, "--force", "-q")
    assert (code, err) == (0, "")
    assert read_program((out / "program.script").read_text()).servoj


def test_without_mujoco_the_simulation_is_skipped_with_a_warning(
    skill_path, tmp_path, capsys, monkeypatch
):
    def missing():
        raise ImportError("lfdkit.execute needs MuJoCo: python -m pip install mujoco")

    monkeypatch.setattr("lfdkit.tasks.sweeping.sim.load_mujoco", missing)
    out = tmp_path / "nosim"
    code, _, err = run_cli(capsys, "execute", skill_path, "-o", out)
    assert code == 0, err
    assert "lfdkit execute: warning: skipped the simulation: MuJoCo is not available" in err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["simulation"]["skipped"].startswith("MuJoCo is not available")
    assert not (out / "sweep.png").exists()


def test_an_unknown_arm_is_one_line(skill_path, tmp_path, capsys):
    code, _, err = run_cli(capsys, "execute", skill_path, "--arm", "ur3", "-o", tmp_path / "x")
    assert code == 1
    assert one_error_line(err).endswith(
        "--arm ur3: neither an arm name (ur5, ur10) nor a URDF file"
    )


@pytest.mark.parametrize(
    ("argv", "fragment"),
    [
        (["--speed-fraction", "0"], "expected a number in (0, 1], got '0'"),
        (["--speed-fraction", "1.5"], "expected a number in (0, 1], got '1.5'"),
        (["--speed-fraction", "fast"], "expected a number in (0, 1], got 'fast'"),
    ],
)
def test_bad_options_are_usage_errors(skill_path, tmp_path, capsys, argv, fragment):
    with pytest.raises(SystemExit) as exc:
        main(["execute", str(skill_path), "-o", str(tmp_path / "x"), *argv])
    assert exc.value.code == 2
    assert fragment in capsys.readouterr().err


def test_a_3d_skill_or_a_radius_given_as_a_coordinate_is_one_line(skill_path, tmp_path, capsys):
    demos = tmp_path / "d3.csv"
    demos.write_text("demo,x,y,z\n1,0,0,0\n1,0.5,0.1,0\n1,1,0,0\n2,0,0,0\n2,0.5,0.05,0\n2,1,0,0\n")
    skill3 = tmp_path / "s3.json"
    assert main(["learn", str(demos), "-o", str(skill3), "-q"]) == 0
    # A 3-D skill runs through the generic chain: this one starts inside the UR5's base.
    code, _, err = run_cli(capsys, "execute", skill3, "-o", tmp_path / "x")
    assert code == 1
    line = one_error_line(err)
    assert "the UR5 cannot follow the plan: poses[0] at (0.000, 0.000, 0.000) m" in line
    assert line.endswith("; wrote nothing") and not (tmp_path / "x").exists()
    code, _, err = run_cli(
        capsys, "execute", skill_path, "--obstacle", "cup:0.1,0.4,0.03", "-o", tmp_path / "y"
    )
    assert code == 1
    assert one_error_line(err).endswith(
        "--obstacle cup: 3 coordinates for a 2-D skill (a radius is given as r=R)"
    )
