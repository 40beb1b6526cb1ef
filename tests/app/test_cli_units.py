"""``--units``: learn keeps it in the skill, plan and plot convert, compare reports in it."""

from __future__ import annotations

import json

import numpy as np
import pytest

import lfdkit.app.evaluation
import lfdkit.app.plot
from lfdkit.io import save_demos
from lfdkit.skill import Skill, learn
from lfdkit.tasks.sweeping import example_files
from tests.app.test_cli import run_cli, usage_exit

SMALL = [
    np.c_[np.linspace(0, 1, 20), 0.1 * np.sin(np.linspace(0, np.pi, 20)) + dy] for dy in (0, 0.01)
]


def rows_of(text: str) -> np.ndarray:
    return np.array([[float(v) for v in line.split(",")] for line in text.splitlines()[1:]])


@pytest.fixture(scope="module")
def skill_path(tmp_path_factory):
    files = example_files()
    path = tmp_path_factory.mktemp("units") / "skill.json"
    learn(files["demos"], files["scenes"]).save(path)
    return path


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
