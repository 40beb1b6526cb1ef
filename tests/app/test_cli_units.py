"""``--units``: learn keeps it in the skill, plan and plot convert, compare reports in it."""

from __future__ import annotations

import itertools
import json

import numpy as np
import pytest

import lfdkit.app.evaluation
import lfdkit.app.plot
from lfdkit.io import save_demos
from lfdkit.skill import Skill
from lfdkit.tasks.sweeping import example_files
from tests.app.test_cli import run_cli, usage_exit
from tests.conftest import example_skill_file_copy

SMALL = [
    np.c_[np.linspace(0, 1, 20), 0.1 * np.sin(np.linspace(0, np.pi, 20)) + dy] for dy in (0, 0.01)
]


def rows_of(text: str) -> np.ndarray:
    return np.array([[float(v) for v in line.split(",")] for line in text.splitlines()[1:]])


@pytest.fixture(scope="module")
def skill_path(example_skill_file_once, tmp_path_factory):
    return example_skill_file_copy(example_skill_file_once, tmp_path_factory.mktemp("units"))


@pytest.mark.parametrize(("units", "factor"), [(None, 1.0), ("m", 1.0), ("cm", 100.0), ("mm", 1e3)])
def test_learn_keeps_the_units_of_the_demonstrations(capsys, tmp_path, units, factor) -> None:
    demos = tmp_path / "demos.csv"
    save_demos(demos, [factor * d for d in SMALL])
    out = tmp_path / "skill.json"
    option = [] if units is None else ["--units", units]
    code, _, err = run_cli(capsys, "learn", demos, *option, "-o", out)
    assert code == 0, err
    assert f"lengths in {units or 'm'}" in err
    doc = json.loads(out.read_text())
    assert doc["units"] == doc["params"]["units"] == (units or "m")
    skill = Skill.load(out)
    reference = Skill().fit(SMALL)
    np.testing.assert_allclose(skill.path_ / factor, reference.path_, rtol=0, atol=1e-12)


@pytest.mark.parametrize("command", ["learn", "plan", "plot", "compare"])
def test_an_unknown_unit_is_a_usage_error_listing_the_choices(capsys, command) -> None:
    argv = {
        "learn": ["learn", "d.csv", "-o", "s.json"],
        "plan": ["plan", "s.json"],
        "plot": ["plot", "s.json", "-o", "f.png"],
        "compare": ["compare"],
    }[command]
    code, out, err = usage_exit(capsys, *argv, "--units", "inch")
    assert code == 2 and out == ""
    assert "--units: invalid choice: 'inch' (choose from 'm', 'cm', 'mm')" in err


def test_plan_in_other_units_is_the_plan_in_the_skills_units_converted(capsys, skill_path):
    base = ["plan", skill_path, "--goal", "0.36,0.5", "--obstacle", "cup:-0.02,0.47,r=0.03"]
    code, in_m, err = run_cli(capsys, *base, "--clearance", "0.005", "-v")
    assert code == 0, err
    assert " m from the goal" in err and " m beyond radius + clearance" in err
    code, same, _ = run_cli(capsys, *base, "--clearance", "0.005", "--units", "m")
    assert same == in_m  # the skill's own units: the very same plan
    mm = ["plan", skill_path, "--goal", "360,500", "--obstacle", "cup:-20,470,r=30"]
    code, in_mm, err = run_cli(capsys, *mm, "--clearance", "5", "--units", "mm", "-v")
    assert code == 0, err
    assert " mm from the goal" in err and " mm beyond radius + clearance" in err
    plan_m, plan_mm = rows_of(in_m), rows_of(in_mm)
    assert plan_mm.shape == plan_m.shape == (100, 3)  # t, x, y
    np.testing.assert_allclose(plan_mm[:, 0], plan_m[:, 0], rtol=1e-9)  # seconds either way
    # 1e-6 of the 0.8 m sweep.
    np.testing.assert_allclose(plan_mm[:, 1:] / 1000.0, plan_m[:, 1:], rtol=0.0, atol=1e-6 * 0.8)


def test_plot_draws_in_the_units_asked_for(capsys, tmp_path, skill_path, monkeypatch) -> None:
    seen = []
    original = lfdkit.app.plot.emulation_figure

    def spy(reward, nominal, scene, **kw):
        seen.append((kw["units"], float(np.ptp(nominal[:, 0]))))
        return original(reward, nominal, scene, **kw)

    monkeypatch.setattr(lfdkit.app.plot, "emulation_figure", spy)
    for units, goal in ((None, "0.36,0.5"), ("mm", "360,500")):
        out = tmp_path / f"{units}.png"
        option = [] if units is None else ["--units", units]
        code, _, err = run_cli(capsys, "plot", skill_path, "--goal", goal, "-o", out, *option)
        assert code == 0, err
        assert out.read_bytes().startswith(b"\x89PNG")
    (units_m, width_m), (units_mm, width_mm) = seen
    assert (units_m, units_mm) == ("m", "mm")
    assert width_mm == pytest.approx(1000.0 * width_m, rel=1e-9)


def test_compare_reports_in_the_units_asked_for(capsys, tmp_path, monkeypatch) -> None:
    # One cheap method: the property is the reporting, not the methods.
    every = lfdkit.app.evaluation.lfdkit_methods()
    monkeypatch.setattr(
        lfdkit.app.evaluation,
        "lfdkit_methods",
        lambda: {"arc-length average": every["arc-length average"]},
    )
    # One figure a run, not four: drawing them was ~3/4 of the test's time, and their
    # other three (quasi_circular's, the mean-path ones) are drawn by test_cli_progress.
    figures = lfdkit.app.evaluation.comparison_figures
    monkeypatch.setattr(
        lfdkit.app.evaluation,
        "comparison_figures",
        lambda *args, **kwargs: itertools.islice(figures(*args, **kwargs), 1),
    )
    names = ["deburring_linear", "quasi_circular"]  # mm and m
    results = {}
    for units in (None, "m"):
        out = tmp_path / str(units)
        option = [] if units is None else ["--units", units]
        code, stdout, err = run_cli(capsys, "compare", "--datasets", *names, "-o", out, *option)
        assert code == 0, err
        assert "units" in stdout.splitlines()[0] and "e1 [units²]" in stdout
        results[units] = json.loads((out / "mimic.json").read_text())
        assert results[units]["units"] == units
        assert (out / "deburring_linear.png").is_file()
    own, metres = results[None]["summary"], results["m"]["summary"]
    assert [row["units"] for row in own] == ["mm", "m"]
    assert [row["units"] for row in metres] == ["m", "m"]
    assert metres[0]["e1_mean"] == pytest.approx(1e-6 * own[0]["e1_mean"], rel=1e-12)
    assert metres[0]["e2_mean"] == pytest.approx(1e-3 * own[0]["e2_mean"], rel=1e-12)
    for key in ("e1_mean", "e2_mean", "units"):
        assert metres[1][key] == own[1][key]
    table = (tmp_path / "m" / "mimic_table.txt").read_text().splitlines()
    assert table[2].split()[:2] == ["deburring_linear", "m"]


# ------------------------------------------------ units and time checked where data enter (31)
def _sweeps(factor: float) -> list[np.ndarray]:
    """Five shipped sweeps (metres, 0.80 m across) times ``factor``."""
    from lfdkit.io import load_demos

    return [factor * d for d in load_demos(example_files()["demos"])[:5]]


@pytest.mark.parametrize(("factor", "likely"), [(1e3, "mm"), (1e2, "cm")])
def test_learn_refuses_millimetres_or_centimetres_read_as_metres(
    capsys, tmp_path, factor, likely
) -> None:
    demos = tmp_path / "reach.csv"
    save_demos(demos, _sweeps(factor))
    out = tmp_path / "skill.json"
    code, _, err = run_cli(capsys, "learn", demos, "-o", out)
    assert code == 1 and not out.exists()
    (line,) = err.strip().splitlines()
    span = max(float(np.ptp(d, axis=0).max()) for d in _sweeps(factor))
    assert f"they span {span:.4g} m, more than a demonstration can (over 20 m)" in line
    assert f"in {likely} they would span {span / factor:.3g} m" in line
    assert f"pass --units {likely} if that is their unit" in line
    code, _, err = run_cli(capsys, "learn", demos, "--units", likely, "-o", out)
    assert code == 0, err
    assert Skill.load(out).units == likely
    # Said to be metres: learned as such, with a warning in the command's words.
    code, _, err = run_cli(capsys, "learn", demos, "--units", "m", "-o", tmp_path / "m.json")
    assert code == 0, err
    assert f"warning: {demos}: they span" in err and f"pass --units {likely}" in err


def test_learn_warns_metres_given_as_centimetres(capsys, tmp_path) -> None:
    # The shipped 0.8 m sweeps with --units cm: a 0.8 cm task, learned silently at 2f1f475.
    demos = tmp_path / "sweeps.csv"
    save_demos(demos, _sweeps(1.0))
    code, _, err = run_cli(capsys, "learn", demos, "--units", "cm", "-o", tmp_path / "s.json")
    assert code == 0, err
    said = [line for line in err.splitlines() if "--units" in line]
    span = max(float(np.ptp(d, axis=0).max()) for d in _sweeps(1.0))
    assert said == [
        f"lfdkit learn: warning: {demos}: they span {span:.4g} cm, less than a task recorded "
        f"in centimetres does (under 2 cm; one that small is recorded in mm); in m they would "
        f"span {span:.3g} m: if that is their unit, pass --units m"
    ]


def test_learn_keeps_a_small_task_in_millimetres(capsys, tmp_path) -> None:
    # A 5 mm insertion recorded in mm (and 15 mm strokes): no word on units.
    for size in (5.0, 15.0):
        demos = [
            np.c_[np.linspace(0, size, 30), 0.1 * size * np.sin(np.linspace(0, 3, 30)) + dy]
            for dy in (0.0, 0.02 * size)
        ]
        path = tmp_path / f"small{size:g}.csv"
        save_demos(path, demos)
        out = tmp_path / f"s{size:g}.json"
        code, _, err = run_cli(capsys, "learn", path, "--units", "mm", "-o", out)
        assert code == 0, err
        assert "span" not in err and "--units" not in err


def test_learn_refuses_timed_centimetres_by_their_speed(capsys, tmp_path) -> None:
    # 15 cm strokes in cm over 0.5 s: span 15 (under the 20 m rule), 30 "m/s" on average.
    x = np.linspace(0.0, 15.0, 30)
    demos = [np.c_[x, np.sin(x / 5.0) + dy] for dy in (0.0, 0.2, 0.4)]
    times = [np.linspace(0.0, 0.5, 30)] * 3
    path = tmp_path / "strokes.csv"
    save_demos(path, demos, times=times)
    code, _, err = run_cli(capsys, "learn", path, "-o", tmp_path / "s.json")
    assert code == 1 and "faster than a hand (over 5 m/s)" in err
    assert "pass --units cm" in err


def test_learn_keeps_genuinely_large_metre_data(capsys, tmp_path) -> None:
    # A walking path of 7 m (a built-in set in metres) and 12 m paths: learned, no word on units.
    demos = [np.c_[np.linspace(0, 12.0, 40), np.sin(np.linspace(0, 3, 40)) + dy] for dy in (0, 0.3)]
    path = tmp_path / "walk.csv"
    save_demos(path, demos)
    code, _, err = run_cli(capsys, "learn", path, "-o", tmp_path / "s.json")
    assert code == 0, err
    assert "span" not in err and "--units" not in err


def test_learn_says_the_assumed_duration_and_plan_follows_it(capsys, tmp_path) -> None:
    demos = tmp_path / "sweeps.csv"
    save_demos(demos, _sweeps(1.0))
    out = tmp_path / "skill.json"
    code, _, err = run_cli(capsys, "learn", demos, "-o", out)
    assert code == 0, err
    skill = Skill.load(out)
    length = float(np.sum(np.linalg.norm(np.diff(skill.path_, axis=0), axis=1)))
    assert skill.timing_.duration == pytest.approx(length / 0.2)  # 0.2 m/s, a hand's pace
    assert 3.5 < skill.timing_.duration < 4.5  # an 80 cm sweep: about 4 s, not 1 s
    assert f"assumed {skill.timing_.duration:.3g} s for the {length:.3g} m path" in err
    assert "set it with --duration S" in err
    code, _, err = run_cli(capsys, "plan", out, "-o", tmp_path / "p.csv")
    assert code == 0, err
    assert f"lasts {skill.timing_.duration:.4g} s" in err and "duration is assumed" in err
    # the peak of a minimum-jerk profile is 1.875 times the mean: 0.375 m/s, a hand's
    peak = float(err.split("peak speed ")[1].split(" ")[0])
    assert peak == pytest.approx(1.875 * 0.2, rel=0.02)
    code, _, err = run_cli(capsys, "plan", out, "--duration", "8", "-o", tmp_path / "q.csv")
    assert code == 0 and "lasts 8 s" in err and "duration is assumed" not in err
    code, _, err = run_cli(capsys, "learn", demos, "--duration", "6", "-o", tmp_path / "d.json")
    assert code == 0 and Skill.load(tmp_path / "d.json").timing_.duration == 6.0
    assert "as --duration gave" in err
    code, _, err = usage_exit(capsys, "learn", demos, "--duration", "-1", "-o", tmp_path / "e.json")
    assert code == 2 and "expected seconds > 0 or 'auto', got '-1'" in err


def test_the_python_api_warns_of_implausible_units() -> None:
    from lfdkit.core.units import UnitsWarning

    with pytest.warns(UnitsWarning, match=r"in mm they would span 0.8 m.*units='mm'"):
        Skill().fit_path(_sweeps(1e3))
    skill = Skill(units="mm").fit_path(_sweeps(1e3))  # no warning with the right unit
    assert skill.timing_.duration == pytest.approx(Skill().fit_path(_sweeps(1.0)).timing_.duration)
