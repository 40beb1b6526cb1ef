"""Tests for lfdkit.tasks.sweeping.demo: the planner experiment and ``lfdkit demo``'s run.

The experiment runs the default planners of the learned example skill on two
scenes in MuJoCo: the learned skill must sweep the cube into the dustpan
without touching anything, while the DMP alone, which ignores the obstacles,
must hit one. :func:`run_demo` writes into a hidden sibling folder and moves
the outputs into place at the end, so an interrupted run never looks
complete (its work is replaced by a stand-in here; the whole workflow runs
in ``tests/test_cli.py``).
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import pytest

from lfdkit.tasks.sweeping import demo as sweeping_demo
from lfdkit.tasks.sweeping.demo import (
    default_planners,
    demo_outputs,
    run_experiment,
    summarize,
)
from lfdkit.tasks.sweeping.scenarios import random_scenarios
from lfdkit.tasks.sweeping.sim import SweepResult
from tests.conftest import example_skill_copy

PLANNERS = ("learned skill", "learned, thesis end", "replay generalized path", "DMP alone")


@pytest.fixture(scope="module")
def skill(example_skill_once):
    return example_skill_copy(example_skill_once)


@pytest.fixture(scope="module")
def experiment(skill):
    """Rows and progress messages of the default planners on two scenes (seed 0)."""
    messages = []
    rows = run_experiment(
        random_scenarios(2, seed=0), default_planners(skill), progress=messages.append
    )
    return rows, messages


# ------------------------------------------------------------------ experiment
def test_default_planners_names(skill):
    assert tuple(default_planners(skill)) == PLANNERS


def test_run_experiment_has_a_row_per_scenario_and_planner(experiment):
    rows, messages = experiment
    assert [(r["scenario"], r["planner"]) for r in rows] == [
        (i, name) for i in range(2) for name in PLANNERS
    ]
    assert messages == ["scenario 1/2", "scenario 2/2"]
    for row in rows:
        result = row["result"]
        assert isinstance(result, SweepResult)
        assert row["success"] == result.success
        assert row["cube_in_dustpan"] == result.cube_in_dustpan
        assert row["touched"] == len(result.touched)
        assert row["failures"] == result.failures
        assert row["tracking_error"] == result.tracking_error
        assert row["plan_s"] >= 0


def test_summarize_is_consistent_with_the_rows(experiment):
    rows, _ = experiment
    summary = summarize(rows)
    assert tuple(summary) == PLANNERS
    for name, stats in summary.items():
        mine = [r for r in rows if r["planner"] == name]
        assert stats["runs"] == len(mine) == 2
        for key in ("success_rate", "cube_in_dustpan_rate", "no_touch_rate"):
            assert 0.0 <= stats[key] <= 1.0
        assert stats["success_rate"] == np.mean([r["success"] for r in mine])
        assert stats["cube_in_dustpan_rate"] == np.mean([r["cube_in_dustpan"] for r in mine])
        assert stats["no_touch_rate"] == np.mean([r["touched"] == 0 for r in mine])
        tracking = [r["tracking_error"] for r in mine]
        assert stats["tracking_max_m"] == max(tracking)
        assert stats["tracking_median_m"] == pytest.approx(np.median(tracking))
        assert stats["not_run"] == 0


def test_learned_skill_sweeps_both_scenarios(experiment):
    rows, _ = experiment
    learned = [r for r in rows if r["planner"] == "learned skill"]
    assert [r["success"] for r in learned] == [True, True], [r["failures"] for r in learned]
    assert all(r["touched"] == 0 and r["cube_in_dustpan"] for r in learned)
    assert all(r["tracking_error"] < 0.005 for r in learned)


def test_dmp_alone_touches_an_obstacle(experiment):
    rows, _ = experiment
    dmp = [r for r in rows if r["planner"] == "DMP alone"]
    assert sum(r["touched"] for r in dmp) >= 1
    assert not all(r["success"] for r in dmp)
    touched = [f for r in dmp for f in r["failures"] if f.startswith("touched obstacle")]
    assert touched


def test_failing_planner_is_reported_and_the_experiment_goes_on():
    def broken(start, goal, scene):
        raise ValueError("no path here")

    def straight(start, goal, scene):
        return np.linspace(start, goal, 30)

    scenarios = random_scenarios(1, seed=0)
    rows = run_experiment(scenarios, {"broken": broken, "straight": straight})
    assert [r["planner"] for r in rows] == ["broken", "straight"]
    failed = rows[0]
    assert failed["success"] is False
    assert failed["cube_in_dustpan"] is False
    assert failed["result"] is None
    assert failed["touched"] == 0
    assert len(failed["failures"]) == 1
    assert failed["failures"][0].startswith("planning failed")
    assert "no path here" in failed["failures"][0]
    assert math.isnan(failed["tracking_error"])
    assert isinstance(rows[1]["result"], SweepResult)
    summary = summarize(rows)
    assert summary["broken"]["runs"] == 1
    assert summary["broken"]["success_rate"] == 0.0
    assert summary["broken"]["not_run"] == 1
    assert math.isnan(summary["broken"]["tracking_max_m"])
    assert summary["straight"]["not_run"] == 0


# ------------------------------------------------------------------ run_demo
def _fake_run_into(fail_after: int | None = None):
    """Stands in for the demo's work: writes every output, or fails midway."""

    def run_into(out: Path, progress, started) -> dict:
        for i, path in enumerate(demo_outputs(out)):
            if fail_after is not None and i == fail_after:
                raise RuntimeError("simulated failure midway")
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(f"new {path.name}\n")
        return {"written": True}

    return run_into


def test_demo_failing_midway_leaves_no_output_folder(monkeypatch, tmp_path):
    monkeypatch.setattr(sweeping_demo, "_run_into", _fake_run_into(fail_after=5))
    out = tmp_path / "demo"
    with pytest.raises(RuntimeError, match="midway"):
        sweeping_demo.run_demo(out)
    assert not out.exists()
    assert list(tmp_path.iterdir()) == []  # no hidden .partial- folder left either


def test_demo_moves_its_outputs_into_place_at_the_end(monkeypatch, tmp_path):
    monkeypatch.setattr(sweeping_demo, "_run_into", _fake_run_into())
    out = tmp_path / "demo"
    assert sweeping_demo.run_demo(out) == {"written": True}
    for path in demo_outputs(out):
        assert path.read_text() == f"new {path.name}\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["demo"]


def test_demo_force_keeps_other_files_and_an_interrupted_move_is_marked(monkeypatch, tmp_path):
    monkeypatch.setattr(sweeping_demo, "_run_into", _fake_run_into())
    out = tmp_path / "demo"
    out.mkdir()
    (out / "mine.txt").write_text("the user's\n")
    for path in demo_outputs(out):
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text("old\n")
    with pytest.raises(FileExistsError):
        sweeping_demo.run_demo(out)
    assert (out / "report.html").read_text() == "old\n"

    # Interrupted while moving the new files in: marked, and no report to open.
    moves = []
    real_replace = os.replace

    def replace(src, dst):
        if len(moves) == 4:
            raise KeyboardInterrupt
        moves.append(dst)
        real_replace(src, dst)

    monkeypatch.setattr(sweeping_demo.os, "replace", replace)
    with pytest.raises(KeyboardInterrupt):
        sweeping_demo.run_demo(out, overwrite=True)
    assert (out / sweeping_demo.INCOMPLETE_MARKER).is_file()
    assert not (out / "report.html").exists()

    monkeypatch.setattr(sweeping_demo.os, "replace", real_replace)
    sweeping_demo.run_demo(out, overwrite=True)
    assert not (out / sweeping_demo.INCOMPLETE_MARKER).exists()
    assert (out / "report.html").read_text() == "new report.html\n"
    assert (out / "mine.txt").read_text() == "the user's\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["demo"]


def test_demo_output_folder_gets_the_usual_permissions(monkeypatch, tmp_path):
    monkeypatch.setattr(sweeping_demo, "_run_into", _fake_run_into())
    plain = tmp_path / "plain"
    plain.mkdir()
    sweeping_demo.run_demo(tmp_path / "demo")
    assert (tmp_path / "demo").stat().st_mode == plain.stat().st_mode
