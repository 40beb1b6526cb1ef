"""Tests for lfdkit.examples.sweeping_sim: random sweeping scenes and the planner comparison.

The scenario generator is checked against its documented geometry (dustpan
moved within its bounds and facing the start, a cup and a marker near the
straight line at the stated fractions of the way). The experiment runs the
default planners of the learned example skill on two scenes in MuJoCo: the
learned skill must sweep the cube into the dustpan without touching anything,
while the DMP alone, which ignores the obstacles, must hit one.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from lfdkit.examples import example_files
from lfdkit.examples.sweeping_sim import (
    NOMINAL_DUSTPAN,
    SweepScenario,
    default_planners,
    random_scenarios,
    run_experiment,
    summarize,
)
from lfdkit.robot.sim import SweepResult
from lfdkit.skill import learn

PLANNERS = ("learned skill", "learned, thesis end", "replay generalized path", "DMP alone")


@pytest.fixture(scope="module")
def skill():
    files = example_files()
    return learn(files["demos"], files["scenes"])


@pytest.fixture(scope="module")
def experiment(skill):
    """Rows and progress messages of the default planners on two scenes (seed 0)."""
    messages = []
    rows = run_experiment(
        random_scenarios(2, seed=0), default_planners(skill), progress=messages.append
    )
    return rows, messages


def positions(scenarios: list[SweepScenario]) -> np.ndarray:
    return np.array(
        [np.concatenate([s.dustpan.position, s.scene.positions.ravel()]) for s in scenarios]
    )


# ------------------------------------------------------------------ scenarios
def test_random_scenarios_are_reproducible():
    first, again = random_scenarios(5, seed=3), random_scenarios(5, seed=3)
    np.testing.assert_array_equal(positions(first), positions(again))
    assert [o.label for s in first for o in s.scene] == [o.label for s in again for o in s.scene]
    other = random_scenarios(5, seed=4)
    assert not np.any(np.all(np.isclose(positions(first), positions(other)), axis=1))
    # A Generator seeded alike gives the same scenes.
    generated = random_scenarios(5, seed=np.random.default_rng(3))
    np.testing.assert_array_equal(positions(first), positions(generated))


def test_random_scenarios_put_a_cup_and_a_marker_near_the_line():
    lateral = 0.03
    scenarios = random_scenarios(5, seed=3, lateral=lateral)
    assert len(scenarios) == 5
    for s in scenarios:
        np.testing.assert_array_equal(s.start, [-0.4, 0.45])
        np.testing.assert_array_equal(s.goal, s.dustpan.goal())
        assert sorted(o.label for o in s.scene) == ["cup", "marker"]
        radius = {o.label: o.radius for o in s.scene}
        assert radius == {"cup": 0.03, "marker": 0.01}
        line = s.goal - s.start
        normal = np.array([-line[1], line[0]]) / np.linalg.norm(line)
        fractions = [(o.position - s.start) @ line / (line @ line) for o in s.scene]
        offsets = [abs((o.position - s.start) @ normal) for o in s.scene]
        assert 0.3 <= fractions[0] <= 0.45
        assert 0.55 <= fractions[1] <= 0.7
        assert max(offsets) <= lateral


def test_random_scenarios_dustpan_faces_the_start_within_its_shift():
    for s in random_scenarios(5, seed=3):
        shift = s.dustpan.position - NOMINAL_DUSTPAN
        assert -0.12 <= shift[0] <= 0.0
        assert abs(shift[1]) <= 0.08
        towards = s.dustpan.position - s.start
        assert s.dustpan.yaw == pytest.approx(math.atan2(towards[1], towards[0]), abs=1e-12)
        # The start lies straight in front of the opening, on the centre line.
        local = s.dustpan.local(s.start)
        assert local[0] < 0
        assert local[1] == pytest.approx(0.0, abs=1e-12)


def test_random_scenarios_rejects_bad_count():
    with pytest.raises(ValueError, match=r"^n: "):
        random_scenarios(0)


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
