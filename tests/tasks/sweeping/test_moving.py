"""The sweeping task with a sliding obstacle: scenarios, closed loops, the MuJoCo replay."""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.tasks.sweeping import SETTLE_TIME
from lfdkit.tasks.sweeping.moving import (
    METHODS,
    SLIDE_SPEEDS,
    moving_scenarios,
    run_moving,
    simulate_run,
)

# fixtures `skill` and `setting`: conftest.py


def test_scenarios_cross_the_sweep_near_when_the_brush_is_there(setting):
    nominal, times = setting
    scenarios = moving_scenarios(20, 3, nominal, times)
    assert len(scenarios) == 20
    for s in scenarios:
        assert SLIDE_SPEEDS[0] <= s.speed <= SLIDE_SPEEDS[1]
        assert 0.0 <= s.start_time <= 0.5 * times[-1]
        track = s.truth(np.array([0.0, s.start_time, s.crossing_time]))
        # at rest until it starts; off the path then; on the path at the crossing
        np.testing.assert_allclose(track[0], track[1])
        gap = np.linalg.norm(nominal - track[0], axis=1).min()
        assert gap >= 0.08 + s.obstacle.radius - 0.01
        assert np.linalg.norm(nominal - track[2], axis=1).min() < 0.01
        # the brush passes within 0.75 s of the crossing
        k = np.argmin(np.linalg.norm(nominal - track[2], axis=1))
        assert abs(times[k] - s.crossing_time) <= 0.75 + 0.1
    # random start times, sides and labels
    assert len({s.obstacle.label for s in scenarios}) == 2
    assert np.ptp([s.start_time for s in scenarios]) > 1.0


def test_closed_loops_predictive_mpc_keeps_clear_where_the_blind_dmp_collides(skill, setting):
    # the "DMP + coupling" baseline is movement_primitives' own DMP
    pytest.importorskip("movement_primitives.dmp", reason="pip install movement_primitives")
    nominal, times = setting
    scenarios = moving_scenarios(3, 1, nominal, times)
    dmp_collisions = 0
    for s in scenarios:
        runs = {m: run_moving(skill, s, m) for m in METHODS}
        predictive = runs["predictive MPC"]
        assert not predictive.collided and predictive.reached_goal
        assert predictive.clearance > 0.005
        assert predictive.step_ms.size >= len(times) - 1
        # its windows are drawn from the predictions: means at the window's times
        _, window, means, sigma = predictive.windows[10]
        assert window.shape[0] == means.shape[0] + 1 and np.all(sigma > 0)
        dmp_collisions += runs["DMP"].collided
        assert runs["DMP"].reached_goal and runs["DMP + coupling"].reached_goal
    assert dmp_collisions >= 2  # the scenarios put the obstacle in the blind sweep's way


def test_run_moving_refuses_an_unknown_method(skill, setting):
    nominal, times = setting
    (scenario,) = moving_scenarios(1, 0, nominal, times)
    with pytest.raises(ValueError, match="method: expected one of"):
        run_moving(skill, scenario, "teleport")


def test_mujoco_replay_sweeps_the_cube_past_the_sliding_obstacle(skill, setting):
    pytest.importorskip("mujoco", reason="pip install mujoco")
    nominal, times = setting
    (scenario,) = moving_scenarios(1, 1, nominal, times)
    run = run_moving(skill, scenario, "predictive MPC")
    result = simulate_run(run, scenario)
    # Nothing touched, the arm on the plan. (The cube itself reaches the dustpan in 98-100 %
    # of the benchmark's scenarios, not in every one: this one is among the misses with the
    # example skill of five clean sweeps.)
    assert result.touched == [], result.failures
    assert result.tracking_error < 0.002
    # the mocap obstacle went along its true track (it stops 0.15 m past the path)
    end = result.times[-1] - SETTLE_TIME
    travelled = np.linalg.norm(scenario.truth([end])[0] - scenario.truth([0.0])[0])
    assert result.obstacle_shift[0] == pytest.approx(travelled, abs=0.01)
    blind = simulate_run(run_moving(skill, scenario, "DMP"), scenario)
    assert blind.touched == [0]


def test_scenario_tracks_keep_off_the_robots_base(setting):
    from lfdkit.tasks.sweeping.moving import BASE_CLEARANCE

    nominal, times = setting
    for s in moving_scenarios(40, 5, nominal, times):
        track = s.truth(np.linspace(0.0, 30.0, 301))
        assert np.linalg.norm(track, axis=1).min() >= BASE_CLEARANCE - 1e-9
