"""``lfdkit learn``/``plan``/``execute`` with the tool's orientation (``qx, qy, qz, qw``).

A demonstrations file with quaternion columns gives a skill with orientation;
its plans carry the columns, unit and ending exactly at ``--goal-orientation``;
``execute`` turns the brush as demonstrated (not along the path's tangent)
unless ``--yaw tangent``; bad orientation options are one line naming them.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from lfdkit.core.rotations import angle_between
from lfdkit.execute.poses import path_yaw, yaw_from_quaternions
from lfdkit.io import save_demos
from lfdkit.io.training import read_training_data
from lfdkit.skill import Skill
from lfdkit.tasks.sweeping.examples import example_files
from lfdkit.tasks.sweeping.execution import execute_skill
from tests.app.test_cli import run_cli
from tests.skill.test_orientation import demonstrations

#: The demonstrated brush heading across the sweep: -0.3 rad at x = -0.4 m to +0.3 at 0.4 m.
YAW_LOW, YAW_HIGH = -0.3, 0.3


NUMBERS = "finite numbers qx,qy,qz,qw (a quaternion, scalar last)"


def demonstrated_yaw(x: np.ndarray) -> np.ndarray:
    return YAW_LOW + (YAW_HIGH - YAW_LOW) * np.clip((x + 0.4) / 0.8, 0.0, 1.0)


def yaw_quaternions(yaw: np.ndarray) -> np.ndarray:
    return np.stack([0 * yaw, 0 * yaw, np.sin(yaw / 2), np.cos(yaw / 2)], axis=-1)


@pytest.fixture(scope="module")
def files(tmp_path_factory) -> dict[str, Path]:
    """A 3-D demonstrations file in cm and a 2-D sweeping one in m, both with orientations."""
    folder = tmp_path_factory.mktemp("orientation")
    demos, quats = demonstrations(3, 100.0, seed=5)
    save_demos(folder / "cm.csv", demos, orientations=quats)
    sweeps = read_training_data(example_files()["demos"], example_files()["scenes"]).free_demos
    turned = [yaw_quaternions(demonstrated_yaw(d[:, 0])) for d in sweeps]
    save_demos(folder / "sweeps.csv", sweeps, orientations=turned)
    return {"folder": folder, "cm": folder / "cm.csv", "sweeps": folder / "sweeps.csv"}


@pytest.fixture(scope="module")
def skill_cm(files) -> Path:
    path = files["folder"] / "skill_cm.json"
    from lfdkit.app.cli import main

    assert main(["learn", str(files["cm"]), "--units", "cm", "-q", "-o", str(path)]) == 0
    return path


def read_csv(text: str) -> tuple[list[str], np.ndarray]:
    lines = text.splitlines()
    return lines[0].split(","), np.array([[float(v) for v in row.split(",")] for row in lines[1:]])


def test_learn_then_plan_writes_unit_quaternion_columns(skill_cm, capsys) -> None:
    assert "orientation" in json.loads(skill_cm.read_text())
    code, out, err = run_cli(capsys, "plan", skill_cm)
    assert code == 0, err
    header, table = read_csv(out)
    assert header == ["t", "x", "y", "z", "qx", "qy", "qz", "qw"]
    q = table[:, 4:]
    assert np.abs(np.linalg.norm(q, axis=1) - 1.0).max() < 1e-12
    learned = Skill.load(skill_cm).orientations_
    assert angle_between(q[0], learned[0]) < 1e-9 and angle_between(q[-1], learned[-1]) < 1e-9

    code, out, err = run_cli(
        capsys, "plan", skill_cm, "--goal-orientation", "0,0,2,2", "--velocities"
    )
    assert code == 0, err
    header, table = read_csv(out)
    assert header == ["t", "x", "y", "z", "qx", "qy", "qz", "qw", "vx", "vy", "vz"]
    goal_q = np.array([0.0, 0.0, 1.0, 1.0]) / np.sqrt(2.0)  # normalised
    assert angle_between(table[-1, 4:8], goal_q) < 1e-9


@pytest.mark.parametrize(
    ("option", "value", "fragment"),
    [
        ("--goal-orientation", "0,0,1", f"expected 4 {NUMBERS}, got '0,0,1'"),
        ("--start-orientation", "nan,0,0,1", f"expected 4 {NUMBERS}, got 'nan,0,0,1'"),
        ("--goal-orientation", "0,0,0,0", "a zero quaternion is no orientation, got '0,0,0,0'"),
        ("--start-orientation", "a,b,c,d", f"expected 4 {NUMBERS}, got 'a,b,c,d'"),
    ],
)
def test_a_bad_orientation_option_is_one_line(
    skill_cm, tmp_path, capsys, option, value, fragment
) -> None:
    never = tmp_path / "never"
    for command in ("plan", "execute"):
        code, _, err = run_cli(capsys, command, skill_cm, option, value, "-o", never)
        assert code == 2
        assert err.strip().splitlines() == [f"lfdkit {command}: error: {option}: {fragment}"], err
    assert not never.exists()


def test_an_orientation_for_a_skill_without_one_is_one_line(files, capsys) -> None:
    plain = files["folder"] / "plain.json"
    sweeps = read_training_data(example_files()["demos"], example_files()["scenes"]).free_demos
    Skill().fit(sweeps).save(plain)
    code, _, err = run_cli(capsys, "plan", plain, "--start-orientation", "0,0,0,1")
    assert code == 1
    assert err.strip().splitlines() == [
        "lfdkit plan: error: --start-orientation: this skill has no orientation; learn it "
        "from demonstrations with orientations (qx, qy, qz, qw)"
    ]
    code, _, err = run_cli(
        capsys,
        "execute",
        plain,
        "--no-sim",
        "--yaw",
        "demonstrated",
        "-o",
        files["folder"] / "never",
    )
    assert code == 1 and len(err.strip().splitlines()) == 1 and "--yaw: 'demonstrated'" in err
    assert not (files["folder"] / "never" / "plan.csv").exists()


def _tool_yaw(poses: np.ndarray) -> np.ndarray:
    """The heading of the tool x axis of each pose (rad)."""
    return np.arctan2(poses[:, 1, 0], poses[:, 0, 0])


def test_execute_turns_the_brush_as_demonstrated(files, capsys) -> None:
    path = files["folder"] / "sweeps.json"
    from lfdkit.skill import learn

    skill = learn(files["sweeps"])
    skill.save(path)
    run = execute_skill(skill, simulate=False)
    assert run.yaw == "demonstrated" and run.summary()["robot"]["yaw"] == "demonstrated"
    yaw = _tool_yaw(run.poses)
    x = run.poses[:, 0, 3]
    # The flange poses follow the demonstrated heading, within 2 degrees ...
    assert np.degrees(np.abs(yaw - demonstrated_yaw(x))).max() < 2.0
    assert np.degrees(np.abs(yaw_from_quaternions(run.plan.orientations) - yaw[[0]])).min() < 1.0
    # ... not the path's tangent, which points along +x.
    tangent = execute_skill(skill, simulate=False, yaw="tangent")
    assert tangent.yaw == "tangent"
    along = _tool_yaw(tangent.poses)
    assert np.degrees(np.abs(along - path_yaw(tangent.poses[:, :2, 3]))).max() < 2.0
    assert np.degrees(np.abs(yaw - along)).max() > 15.0

    out = files["folder"] / "run"
    code, _, err = run_cli(capsys, "execute", path, "--no-sim", "-q", "-o", out)
    assert code == 0, err
    assert json.loads((out / "summary.json").read_text())["robot"]["yaw"] == "demonstrated"
    assert (out / "plan.csv").read_text().startswith("t,x,y,qx,qy,qz,qw\n")  # with the timing
    code, _, err = run_cli(
        capsys, "execute", path, "--no-sim", "-q", "--yaw", "tangent", "-f", "-o", out
    )
    assert code == 0, err
    assert json.loads((out / "summary.json").read_text())["robot"]["yaw"] == "tangent"
