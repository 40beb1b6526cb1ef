"""``lfdkit plan --via X,Y[,Z]@T``: plans through via-points; every mistake is one line."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from lfdkit.core.geometry import polyline_distances
from lfdkit.skill import Skill
from tests.app.test_cli import error_line, run_cli
from tests.test_skill_via import sweeps


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
