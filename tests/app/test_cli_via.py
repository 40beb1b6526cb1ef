"""``lfdkit plan --via X,Y[,Z]@T``: plans through via-points; every mistake is one line."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from lfdkit.core.geometry import polyline_distances
from lfdkit.skill import Skill
from tests.app.test_cli import error_line, run_cli
from tests.skill.test_via import sweeps


@pytest.fixture(scope="module")
def skill_file(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("via")
    return Skill(mimic="average").fit_path(sweeps()).save(folder / "skill.json")


def positions(out: Path) -> np.ndarray:
    """The x, y columns of a plan CSV (``t,x,y``)."""
    return np.loadtxt(out, delimiter=",", skiprows=1)[:, 1:3]


def test_plan_passes_the_via_points_given(capsys, skill_file, tmp_path) -> None:
    out = tmp_path / "plan.csv"
    duration = Skill.load(skill_file).timing_.duration
    code, _, err = run_cli(
        capsys,
        "plan",
        skill_file,
        "--via=-0.1,0.6@0.3",
        "--via",
        f"0.2,0.6@{0.7 * duration!r}s",
        "-o",
        out,
    )
    assert code == 0, err
    points = positions(out)
    miss = polyline_distances(np.array([[-0.1, 0.6], [0.2, 0.6]]), points)
    assert miss.max() < 1e-3
    assert "passes 2 via-points within" in err


def test_plan_in_millimetres_takes_via_points_in_millimetres(capsys, skill_file, tmp_path) -> None:
    out = tmp_path / "plan_mm.csv"
    code, _, err = run_cli(
        capsys, "plan", skill_file, "--units", "mm", "--via", "0,620@50%", "-o", out
    )
    assert code == 0, err
    points = positions(out)
    assert polyline_distances(np.array([[0.0, 620.0]]), points)[0] < 1.0  # mm


@pytest.mark.parametrize(
    ("via", "message"),
    [
        ("0.1,0.6", r"--via '0.1,0.6': no '@T'; expected X,Y\[,Z\]@T"),
        ("0.1,0.6@1.2", r"phase 1.2 is outside \(0, 1\)"),
        ("0.1,0.6@0", r"phase 0 is outside \(0, 1\)"),
        ("0.1,0.6@120%", r"phase 1.2 is outside \(0, 1\)"),
        ("0.1,0.6,0.2@0.5", r"3 coordinates for a 2-D skill; give 2"),
        ("0.1,x@0.5", r"the point '0.1,x' is not finite numbers"),
        ("0.1m,0.6m@0.5", r"coordinates take no unit; give plain numbers"),
        ("0.1,0.6@1e3s", r"1000 s is not within the plan, which lasts"),
        ("0.1,0.6@2min", r"unknown unit of time 'min'"),
        ("0.1,0.6@soon", r"when 'soon' is not a number"),
        ("0.1,0.6@nan", r"when 'nan' is not a number"),
        ("0.1,0.6@0.5:0,0,1", r"the orientation has 3 values; give a unit quaternion"),
        ("0.1,0.6@0.5:0,0,2,0", r"the orientation has norm 2; a unit quaternion's norm is 1"),
        ("0.1,0.6@0.5:a,b,c,d", r"the orientation 'a,b,c,d' is not numbers"),
    ],
)
def test_bad_via_points_are_one_line(capsys, skill_file, via, message) -> None:
    code, out, err = run_cli(capsys, "plan", skill_file, "--via", via)
    assert code == 2
    assert out == ""
    assert re.search(message, error_line(err, "plan"))


def test_plot_draws_the_via_points_and_the_band(capsys, skill_file, tmp_path) -> None:
    out = tmp_path / "via.png"
    code, _, err = run_cli(capsys, "plot", skill_file, "--via", "0,0.6@0.5", "-o", out)
    assert code == 0, err
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    code, _, err = run_cli(capsys, "plot", skill_file, "--via", "0,0.6,1@0.5", "-o", out, "-f")
    assert code == 2 and "3 coordinates for a 2-D skill" in error_line(err, "plot")


REACH = Path(__file__).parent / "data" / "reach3d.json"  # a stored 3-D reach in metres


def test_execute_plans_through_the_via_points_to_the_robot(capsys, tmp_path) -> None:
    # The reach's arch tops out at (0.45, 0, 0.35) m half-way; pass 5 cm beside it instead.
    out = tmp_path / "run"
    argv = ["execute", REACH, "--task", "path", "--no-sim", "--via", "0.5,0,0.3@2s", "-o", out]
    code, _, err = run_cli(capsys, *argv)
    assert code == 0, err
    plan = np.loadtxt(out / "plan.csv", delimiter=",", skiprows=1)
    via = np.array([[0.5, 0.0, 0.3]])
    assert polyline_distances(via, plan[:, 1:4])[0] < 1e-3
    # Without it the plan stays at least 4 cm away: the via-point moved it.
    assert polyline_distances(via, Skill.load(REACH).plan().points)[0] > 0.04


def test_execute_sweeps_through_the_via_points(capsys, skill_file, tmp_path) -> None:
    # A 2-D skill on the UR5: the sweeping task (brush, dustpan), planned through the point.
    out = tmp_path / "sweep"
    code, _, err = run_cli(
        capsys, "execute", skill_file, "--no-sim", "--via", "0,0.62@0.5", "-o", out
    )
    assert code == 0, err
    plan = np.loadtxt(out / "plan.csv", delimiter=",", skiprows=1)
    assert polyline_distances(np.array([[0.0, 0.62]]), plan[:, -2:])[0] < 1e-3


def test_batch_evaluate_plans_every_task_through_the_via_points(capsys, tmp_path) -> None:
    import json

    from lfdkit.app.batch import read_results
    from lfdkit.app.execute_batch import random_goal

    results = tmp_path / "r.jsonl"
    argv = ["batch", "evaluate", REACH, "--task", "path", "--random", 2, "--seed", 3]
    code, _, err = run_cli(
        capsys, *argv, "--check", "plan", "--via", "0.5,0,0.3@50%", "-o", results
    )
    assert code == 0, err
    assert json.loads(results.read_text().splitlines()[0])["spec"]["via"] == [[0.5, [0.5, 0, 0.3]]]
    skill = Skill.load(REACH)
    for row in read_results(results):
        goal = random_goal(skill.path_[-1], 0.05, 3, row["scenario"]["index"])
        plan = skill.plan(goal=goal, via=[(0.5, (0.5, 0.0, 0.3))])
        length = np.linalg.norm(np.diff(plan.points, axis=0), axis=1).sum()
        assert row["plan"]["length_m"] == pytest.approx(length, rel=1e-12)
        assert polyline_distances(np.array([[0.5, 0.0, 0.3]]), plan.points)[0] < 1e-3


def test_plan_turns_to_the_via_orientation(capsys, tmp_path) -> None:
    from lfdkit.core.rotations import angle_between
    from tests.skill.test_orientation import demonstrations

    demos, quats = demonstrations(3, 100.0, seed=4)
    skill = Skill(units="cm", mimic="average", n_points=60).fit_path(demos, orientations=quats)
    path = skill.save(tmp_path / "oriented.json")
    turn = [0.0, 0.38268343236508984, 0.0, 0.9238795325112867]  # 45 degrees about y
    out = tmp_path / "plan.csv"
    code, _, err = run_cli(
        capsys, "plan", path, "--via", f"50,20,15@0.5:{','.join(map(repr, turn))}", "-o", out
    )
    assert code == 0, err
    rows = np.loadtxt(out, delimiter=",", skiprows=1)
    via = [(0.5, (50.0, 20.0, 15.0), turn)]
    expected = Skill.load(path).plan(via=via)
    np.testing.assert_allclose(rows[:, 4:8], expected.orientations, atol=1e-12)
    assert angle_between(Skill.load(path).orientations_at([0.5], via=via)[0], turn) <= 1e-6


def test_an_orientation_for_a_skill_without_one_is_one_line(capsys, skill_file) -> None:
    code, out, err = run_cli(capsys, "plan", skill_file, "--via", "0,0.6@0.5:0,0,0,1")
    assert code != 0 and out == ""
    line = error_line(err, "plan")
    assert "--via (value 1): orientation: this skill has no orientation" in line
