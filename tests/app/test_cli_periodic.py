"""``lfdkit learn --periodic``, and ``plan``/``plot``/``execute`` of a periodic skill."""

from __future__ import annotations

import contextlib
import io
from pathlib import Path

import numpy as np
import pytest

from lfdkit.app.cli import main
from lfdkit.datasets import export_dataset
from lfdkit.io import save_demos
from lfdkit.skill.periodic import PeriodicSkill
from tests.app.test_cli import error_line, run_cli

REACH = Path(__file__).parent / "data" / "reach3d.json"  # a skill from a start to a goal


@pytest.fixture(scope="module")
def wipe(tmp_path_factory) -> tuple[Path, Path, str]:
    """The wipe recording, and the periodic skill ``lfdkit learn --periodic`` made of it."""
    folder = tmp_path_factory.mktemp("periodic")
    demos = folder / "wipe.csv"
    export_dataset("wipe", demos)
    skill = folder / "wipe.json"
    said = io.StringIO()
    with contextlib.redirect_stderr(said):
        code = main(["learn", "--periodic", str(demos), "-o", str(skill)])
    assert code == 0, said.getvalue()
    return demos, skill, said.getvalue()


def test_learn_writes_the_skill_and_says_what_it_found(wipe) -> None:
    _, skill_file, err = wipe
    skill = PeriodicSkill.load(skill_file)
    assert skill.period_ == pytest.approx(1.6, rel=3e-3)
    assert skill.orientation_ is not None
    (line,) = err.splitlines()
    assert line.startswith("learned a periodic skill: period 1.6")
    assert "4.3 cycles" in line and "fit RMS" in line and f"wrote {skill_file}" in line


def test_plan_writes_the_run_asked_for(capsys, wipe, tmp_path) -> None:
    _, skill_file, _ = wipe
    out = tmp_path / "plan.csv"
    argv = ["--cycles", "2", "--amplitude", "1.5", "--frequency", "0.8", "--centre", "0.4,0,0.1"]
    code, _, err = run_cli(capsys, "plan", skill_file, *argv, "-o", out)
    assert code == 0, err
    assert "planned 2 cycles of 1.25 s at amplitude 1.5" in err
    header = out.read_text().splitlines()[0]
    assert header == "t,x,y,z,qx,qy,qz,qw"
    table = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(table[[0, -1], 1:4], [[0.4, 0.0, 0.1]] * 2, atol=1e-6)
    assert table[-1, 0] == pytest.approx(2 * 1.25 + 2.5 * 0.5 * 1.25, rel=1e-9)
    # The file's plan is the library's, to the bit (CSV floats are written exactly).
    skill = PeriodicSkill.load(skill_file)
    frequency = 0.8 * skill.period_
    plan = skill.plan(2, amplitude=1.5, frequency=frequency, centre=[0.4, 0.0, 0.1])
    assert np.array_equal(table[:, 1:4], plan.positions)
    np.testing.assert_allclose(table[:, 4:], plan.orientations, atol=1e-15)  # normalised
    # Refused over an existing file, one line, exit 1.
    code, _, err = run_cli(capsys, "plan", skill_file, "--cycles", "1", "-o", out)
    assert code == 1 and "exists; pass --force" in error_line(err, "plan")


def test_plan_to_standard_output_with_velocities_in_mm(capsys, wipe) -> None:
    _, skill_file, _ = wipe
    argv = ["--duration", "2", "--period", "2", "--velocities", "--units", "mm", "--ramp", "0"]
    code, out, err = run_cli(capsys, "plan", skill_file, *argv)
    assert code == 0, err
    lines = out.splitlines()
    assert lines[0] == "t,x,y,z,qx,qy,qz,qw,vx,vy,vz"
    table = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    assert table[-1, 0] == pytest.approx(2.0)
    assert np.ptp(table[:, 2]) == pytest.approx(120.0, rel=0.03)  # the 12 cm stroke, in mm
    assert np.abs(table[0, 8:]).max() > 10.0  # no ramp: on the cycle, moving


def test_plot_draws_the_cycles(capsys, wipe, tmp_path) -> None:
    demos, skill_file, _ = wipe
    out = tmp_path / "wipe.png"
    argv = ["--demos", demos, "--cycles", "1", "--dpi", "40"]
    code, _, err = run_cli(capsys, "plot", skill_file, *argv, "-o", out)
    assert code == 0, err
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_execute_runs_the_wipe_on_the_arm(capsys, wipe, tmp_path) -> None:
    _, skill_file, _ = wipe
    out = tmp_path / "run"
    argv = ["--cycles", "1", "--frequency", "0.8", "--speed-fraction", "1", "--no-sim"]
    code, _, err = run_cli(capsys, "execute", skill_file, *argv, "-o", out)
    assert code == 0, err
    plan = np.loadtxt(out / "plan.csv", delimiter=",", skiprows=1)
    assert plan.shape[1] == 8 and plan[-1, 0] == pytest.approx(1.25 * 2.25, rel=1e-9)
    assert (out / "program.script").exists()


def _timed(path: Path, points: np.ndarray, times=None) -> Path:
    save_demos(path, [points], times=None if times is None else [times])
    return path


@pytest.mark.parametrize(
    ("case", "code", "message"),
    [
        ("missing", 1, "no such file"),
        ("line", 1, "no repeating cycle found"),
        ("untimed", 1, "no t column; a periodic skill needs the samples' times"),
        ("two", 1, "2 demonstrations"),
        ("scenes", 2, "--scenes: a periodic skill has no obstacles"),
        ("harmonics", 1, "--harmonics: 40 needs at least 120 samples per cycle"),
        ("millimetres", 1, "no --units was given, so they were read as m: pass --units mm"),
    ],
)
def test_learn_mistakes_are_one_line(capsys, tmp_path, case, code, message) -> None:
    t = np.linspace(0.0, 6.0, 200)
    u = 2 * np.pi * t / 1.5
    circle = 0.2 * np.c_[np.cos(u), np.sin(u)]  # metres
    if case == "missing":
        demos = tmp_path / "nothing.csv"
    elif case == "line":
        demos = _timed(tmp_path / "line.csv", np.c_[0.1 * t, 0.2 * t], t)
    elif case == "untimed":
        demos = _timed(tmp_path / "untimed.csv", circle)
    elif case == "millimetres":
        demos = _timed(tmp_path / "mm.csv", 1000.0 * circle, t)
    else:
        demos = _timed(tmp_path / "circle.csv", circle, t)
    extra = {"scenes": ["--scenes", demos], "harmonics": ["--harmonics", "40"]}.get(case, [])
    if case == "two":
        save_demos(demos, [circle, circle], times=[t, t], overwrite=True)
    argv = ["learn", "--periodic", demos, *extra, "-o", tmp_path / "s.json"]
    got, _, err = run_cli(capsys, *argv)
    assert got == code and message in error_line(err, "learn")
    assert not (tmp_path / "s.json").exists()


def test_an_untimed_recording_learns_with_its_period_or_pace(capsys, tmp_path) -> None:
    u = np.linspace(0.0, 4.5 * 2 * np.pi, 300)
    demos = _timed(tmp_path / "untimed.csv", 0.2 * np.c_[np.cos(u), np.sin(u)])
    code, _, err = run_cli(
        capsys, "learn", "--periodic", demos, "--period", "2", "-o", tmp_path / "a.json"
    )
    assert code == 0, err
    assert PeriodicSkill.load(tmp_path / "a.json").period_ == 2.0
    argv = ["learn", "--periodic", demos, "--pace", "0.1", "-o", tmp_path / "b.json"]
    code, _, err = run_cli(capsys, *argv)
    assert code == 0, err
    # A circle of radius 0.2 m at 0.1 m/s: 0.4π / 0.1 = 12.6 s a cycle.
    assert PeriodicSkill.load(tmp_path / "b.json").period_ == pytest.approx(4 * np.pi, rel=1e-2)


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--cycles", "0"], "--cycles: expected a positive number of cycles, got '0'"),
        (["--cycles", "many"], "--cycles: expected a positive number of cycles, got 'many'"),
        (["--cycles", "2", "--duration", "3"], "--cycles: give --cycles or --duration"),
        (["--frequency", "1", "--period", "2"], "--period: give one of --frequency"),
        (["--amplitude", "-1"], "--amplitude: expected a positive size factor"),
        (["--ramp", "x"], "--ramp: expected seconds >= 0"),
        (["--start", "0,0,0"], "--start: "),
        (["--obstacle", "cup:0,0,0"], "--obstacle: "),
    ],
)
def test_plan_mistakes_are_usage_errors(capsys, wipe, argv, message) -> None:
    _, skill_file, _ = wipe
    code, _, err = run_cli(capsys, "plan", skill_file, *argv)
    assert code == 2 and message in error_line(err, "plan")


def test_periodic_options_are_refused_for_a_skill_to_a_goal(capsys) -> None:
    code, _, err = run_cli(capsys, "plan", REACH, "--cycles", "2")
    assert code == 2 and "--cycles: only for a periodic skill" in error_line(err, "plan")
    code, _, err = run_cli(capsys, "learn", REACH, "--period", "2", "-o", "x.json")
    assert code == 2 and "--period: only with --periodic" in error_line(err, "learn")
