"""Manoeuvring obstacles in the sweeping task: the six kinds, and the closed loop among them."""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.tasks.sweeping.manoeuvres import KINDS, MAX_ACCELERATION, manoeuvre_scenarios
from lfdkit.tasks.sweeping.moving import MAX_PERIOD, run_moving, true_clearance

# fixtures `skill` and `setting`: conftest.py


def _kinematics(obstacle) -> tuple[np.ndarray, np.ndarray]:
    """Speeds (n,) and acceleration magnitudes (n,) of a track, from its samples."""
    track = obstacle.motion
    dt = np.diff(track.times)
    velocity = np.diff(track.positions, axis=0) / dt[:, None]
    acceleration = np.diff(velocity, axis=0) / dt[1:, None]
    return np.linalg.norm(velocity, axis=1), np.linalg.norm(acceleration, axis=1)


@pytest.mark.parametrize("kind", KINDS)
def test_every_kind_keeps_to_its_description(setting, kind):
    nominal, times = setting
    scenarios = manoeuvre_scenarios(kind, 6, 11, nominal, times)
    assert len(scenarios) == 6 and {s.kind for s in scenarios} == {kind}
    for s in scenarios:
        for obstacle in s.obstacles:
            speed, acceleration = _kinematics(obstacle)
            assert acceleration.max() <= MAX_ACCELERATION * 1.02  # the tracker's bound
            assert speed[0] == pytest.approx(0.0, abs=0.02) and speed[-1] < 0.02  # at rest
            assert speed.max() <= (0.31 if kind == "fast" else 0.26)
            # it comes within 2 cm of the path (on it when it crosses)
            track = obstacle.motion.positions
            assert np.linalg.norm(nominal[None] - track[:, None], axis=2).min() < 0.02
        speed, _ = _kinematics(s.obstacle)
        if kind == "fast":
            assert speed.max() >= 0.15
        if kind == "stop-and-go":  # it stands still between two motions
            moving = speed > 1e-9
            assert np.any(moving[:-1] & ~moving[1:]) and np.any(~moving[:-1] & moving[1:])
        if kind == "head-on":  # along the path, against the sweep's direction
            track = s.obstacle.motion.positions
            direction = track[-1] - track[0]
            sweep = nominal[-1] - nominal[0]
            assert direction @ sweep < -0.9 * np.linalg.norm(direction) * np.linalg.norm(sweep)
    assert (len(scenarios[0].obstacles) == 2) == (kind == "two crossing")
    if kind == "accelerating":  # both: some speed up through the crossing, some brake
        signs = set()
        for s in manoeuvre_scenarios(kind, 12, 2, nominal, times):
            speed, _ = _kinematics(s.obstacle)
            i = int(np.searchsorted(s.obstacle.motion.times, s.crossing_time))
            signs.add(np.sign(speed[min(i + 20, len(speed) - 1)] - speed[max(i - 20, 0)]))
        assert {-1.0, 1.0} <= signs


def test_manoeuvre_scenarios_refuse_an_unknown_kind(setting):
    with pytest.raises(ValueError, match="kind: expected one of"):
        manoeuvre_scenarios("teleport", 1, 0, *setting)


@pytest.mark.parametrize("kind", KINDS)
def test_the_predictive_loop_never_touches_a_manoeuvring_obstacle(skill, setting, kind):
    # Against the TRUE tracks, densely in time: no contact; a run that stops says why
    # before any contact. Observations every MAX_PERIOD s at most, the long first and
    # last steps included.
    nominal, times = setting
    (scenario,) = manoeuvre_scenarios(kind, 1, 5, nominal, times)
    run = run_moving(skill, scenario, "predictive MPC")
    gap, _ = true_clearance(scenario, run.times, run.points, rate=1000.0)
    assert gap >= 0.0
    assert run.reached_goal or run.failure
    seen = run.observations[:, 0]
    assert np.diff(seen[seen >= 0.0]).max() <= MAX_PERIOD + 1e-9
    # the allowance (2σ with the acceleration bound) holds the truth near the tool
    errors = run.prediction_errors
    near = errors[:, 0] < 0.15
    assert np.mean(errors[near, 1] <= errors[near, 2]) >= 0.97
