"""``lfdkit execute`` of a 3-D skill on any arm (the generic chain, ``--task path``).

Six timed 3-D demonstrations of a reach over a box (6 s each, ±5 %) are
learned once per module; the skill then runs on the UR5 (URScript) and on a
Panda read from its URDF (``--arm FILE --tip-link``), with the learned
duration kept within the limits, and is refused in one line when out of reach.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from lfdkit.datasets import example_urdf, reach_demos
from lfdkit.skill import Skill
from tests.app.test_cli import run_cli

DATA = example_urdf("ur5").parent  # the example arms lfdkit ships
pytestmark = pytest.mark.slow  # learning the skill takes ~15 s on a busy 2-core machine


@pytest.fixture(scope="module")
def reach_skill(tmp_path_factory) -> Path:
    # Six reaches of 6 s over 0.6 m, 0.22 m up, each 1 cm higher or lower and off in x.
    demos, times = reach_demos(6, seed=3)
    path = tmp_path_factory.mktemp("reach") / "reach.json"
    Skill(random_state=0).fit(demos, times=times).save(path)
    return path


def test_a_3d_skill_runs_on_the_ur5_at_the_learned_timing(reach_skill, tmp_path, capsys):
    out = tmp_path / "ur5"
    code, _, err = run_cli(
        capsys, "execute", reach_skill, "--speed-fraction", "0.5", "--rate", "500", "-o", out
    )
    assert code == 0, err
    summary = json.loads((out / "summary.json").read_text())
    plan = np.loadtxt(out / "plan.csv", delimiter=",", skiprows=1)
    # The learned duration (about 6 s) is kept: within the limits at half speed.
    assert summary["robot"]["duration_ratio"] == pytest.approx(1.0)
    assert summary["robot"]["motion_s"] == pytest.approx(plan[-1, 0])
    assert 5.5 < plan[-1, 0] < 6.5
    rows = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    np.testing.assert_allclose(np.diff(rows[:, 0]), 0.002, atol=1e-12)
    assert "], a=0.7, v=0.525)" in (out / "program.script").read_text()


def test_a_3d_skill_runs_on_a_urdf_panda(reach_skill, tmp_path, capsys):
    out = tmp_path / "panda"
    code, _, err = run_cli(
        capsys,
        "execute",
        reach_skill,
        "--arm",
        DATA / "panda.urdf",
        "--tip-link",
        "panda_hand_tcp",
        "--speed-fraction",
        "0.5",
        "-o",
        out,
    )
    assert code == 0, err
    message = json.loads((out / "trajectory.json").read_text())
    assert message["joint_names"] == [f"panda_joint{k}" for k in range(1, 8)]
    assert not (out / "program.script").exists()  # URScript is for UR arms only
    summary = json.loads((out / "summary.json").read_text())
    assert summary["robot"]["duration_ratio"] == pytest.approx(1.0)
    # Simulated in MuJoCo from the URDF: tracked within 2 mm, nothing to touch.
    assert summary["simulation"]["tracking_error_m"] <= 0.002
    assert summary["simulation"]["touched"] == []


def test_out_of_reach_is_one_line(reach_skill, tmp_path, capsys):
    code, _, err = run_cli(
        capsys, "execute", reach_skill, "--offset", "1", "0", "0", "-o", tmp_path / "far"
    )
    assert code == 1
    (line,) = err.splitlines()
    assert "out of reach of the UR5 (distance" in line and "> reach 1.103 m" in line
    assert not (tmp_path / "far").exists()
    code, _, err = run_cli(capsys, "execute", reach_skill, "--arm", "ur7", "-o", tmp_path / "x")
    assert code == 1
    assert err.strip().endswith("--arm ur7: neither an arm name (ur5, ur10) nor a URDF file")


def test_an_obstacle_of_a_class_never_learned_needs_unknown_class(reach_skill, tmp_path, capsys):
    box = ("--obstacle", "box:0.45,0,0.37,r=0.03")  # on the reach's top
    code, _, err = run_cli(capsys, "execute", reach_skill, *box, "--no-sim", "-o", tmp_path / "a")
    assert code == 1
    (line,) = err.splitlines()
    assert "no obstacle reward" in line and "pass --unknown-class margin=M" in line
    out = tmp_path / "b"
    code, _, err = run_cli(
        capsys,
        "execute",
        reach_skill,
        *box,
        "--unknown-class",
        "margin=0.02",
        "--no-sim",
        "-o",
        out,
    )
    assert code == 0, err
    assert "'box' never learned: planned around it (1 obstacle)" in err
    assert "margin 0.02 m" in err
    table = np.loadtxt(out / "plan.csv", delimiter=",", skiprows=1)
    points = table[:, 1:4]
    nominal = Skill.load(reach_skill).nominal()
    centre = np.array([0.45, 0.0, 0.37])
    assert np.linalg.norm(nominal - centre, axis=1).min() < 0.05  # it had to swerve
    assert np.linalg.norm(points - centre, axis=1).min() >= 0.05 - 1e-9
