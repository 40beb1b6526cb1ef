"""Tests for the ruckig backend: jerk-limited trajectories through timed states.

Known answers: a rest-to-rest move limited by its jerk only lasts
``4 (D / 2j)^(1/3)`` (four jerk phases of equal length); scaling every limit
by the speed fraction (v·f, a·f², j·f³) stretches the whole trajectory by
exactly ``1/f``. Every state it keeps is passed exactly, the limits hold at
2 kHz (the jerk by finite differences), a reference that the jerk limit
allows keeps its times, and the bang-bang time-optimal one is slowed
uniformly, cutting corners only where it skips a waypoint.
"""

from __future__ import annotations

import sys

import numpy as np
import pytest

pytest.importorskip("ruckig")

from lfdkit.execute.arm import UR5
from lfdkit.execute.jerk_limited import (
    JERK_PER_ACCELERATION,
    through_states,
    time_parameterize_ruckig,
)
from lfdkit.execute.timing import time_parameterize


def random_path(seed: int, n: int = 60) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.cumsum(rng.normal(0.0, 0.05, (n, 6)), axis=0)


def within_limits(traj, rate: float = 2000.0) -> tuple[float, float, float]:
    """Largest velocity, acceleration and finite-difference jerk over their limits."""
    samples = traj.resample(rate)
    qd, qdd = samples.velocities, samples.accelerations
    jerk = np.diff(qdd, axis=0) * rate
    return (
        float((np.abs(qd) / traj.max_velocity).max()),
        float((np.abs(qdd) / traj.max_acceleration).max()),
        float((np.abs(jerk) / traj.max_jerk).max()),
    )


@pytest.mark.parametrize(("distance", "jerk"), [(2e-3, 1.0), (0.5, 40.0)])
def test_a_move_limited_by_its_jerk_lasts_the_closed_form_time(distance, jerk):
    rest = np.zeros((2, 1))
    q = np.array([[0.0], [distance]])
    traj = through_states(
        [0.0, 1e-3],
        q,
        rest,
        rest,
        max_velocity=10.0,
        max_acceleration=10.0,
        max_jerk=jerk,
        keep_times=False,
    )
    assert traj.duration == pytest.approx(4.0 * (distance / (2.0 * jerk)) ** (1 / 3), rel=1e-9)
    v, a, j = within_limits(traj)
    assert v < 1 and a < 1 and j <= 1 + 1e-6


@pytest.mark.parametrize("seed", [0, 1])
def test_the_limits_hold_and_the_chosen_waypoints_are_passed(seed):
    q = random_path(seed, 30)
    traj = time_parameterize_ruckig(q, speed_fraction=0.5)
    states = traj.sample(traj.times)
    at, qd = states.positions, states.velocities
    np.testing.assert_allclose(at, traj.waypoints, atol=1e-9)
    np.testing.assert_array_equal(traj.waypoints, q[traj.waypoint_index])
    assert traj.waypoint_index[0] == 0 and traj.waypoint_index[-1] == len(q) - 1
    assert len(traj.waypoint_index) > 0.8 * len(q)  # most: only those at a switch are skipped
    assert np.abs(qd[[0, -1]]).max() < 1e-9  # rest to rest
    v, a, j = within_limits(traj)
    assert v <= 1 + 1e-9 and a <= 1 + 1e-9 and j <= 1 + 1e-6
    reference = time_parameterize(q, speed_fraction=0.5)
    # The bang-bang reference breaks the jerk limit; the jerk-limited one takes longer.
    ref_acc = reference.resample(2000.0).accelerations
    assert (np.abs(np.diff(ref_acc, axis=0)) * 2000.0 / traj.max_jerk).max() > 2.0
    assert reference.duration <= traj.duration < 1.5 * reference.duration
    # Uniformly slowed: the kept states at the reference's times times the slowdown.
    kept = np.searchsorted(reference.waypoint_index, traj.waypoint_index)
    np.testing.assert_allclose(traj.times, reference.times[kept] * traj.slowdown, rtol=1e-6)
    # A skipped waypoint is a corner cut: on this walk's sharp 0.1 rad corners, by < 0.08 rad.
    assert path_distance(traj, reference) < 0.08


def path_distance(traj, reference) -> float:
    """Largest distance (rad, Euclidean) from the trajectory to the reference's path."""
    from scipy.spatial import cKDTree

    dense = reference.sample(np.linspace(0.0, reference.duration, 40_001)).positions
    return float(cKDTree(dense).query(traj.resample(500.0).positions)[0].max())


def test_on_a_smooth_path_it_keeps_within_a_few_milliradians_of_it():
    s = np.linspace(0.0, 1.0, 150)[:, None]
    q = np.hstack([0.8 * np.sin(np.pi * s * (j + 1) / 3) for j in range(6)])
    traj = time_parameterize_ruckig(q)
    reference = time_parameterize(q)
    assert path_distance(traj, reference) < 5e-3
    assert traj.duration < 1.5 * reference.duration


def test_a_speed_fraction_stretches_time_by_exactly_its_inverse():
    q = random_path(2, 40)
    full = time_parameterize(q, backend="ruckig")
    slow = time_parameterize(q, backend="ruckig", speed_fraction=0.25)
    assert slow.duration == pytest.approx(full.duration / 0.25, rel=1e-6)
    np.testing.assert_allclose(slow.max_jerk, full.max_jerk * 0.25**3, rtol=1e-12)
    np.testing.assert_allclose(
        full.max_jerk, JERK_PER_ACCELERATION * UR5.max_joint_acceleration, rtol=1e-12
    )
    np.testing.assert_allclose(
        slow.sample(slow.times).positions, full.sample(full.times).positions, atol=1e-9
    )


def test_a_reference_within_the_jerk_limit_keeps_its_times():
    # A slow sine: jerk (2 pi / 4)^3 * 0.3 = 1.16 rad/s^3, far below 50 * 5 rad/s^3.
    t = np.linspace(0.0, 4.0, 401)
    w = 2 * np.pi / 4.0
    q = 0.3 * (1 - np.cos(w * t))[:, None] * np.ones(3)
    qd = 0.3 * w * np.sin(w * t)[:, None] * np.ones(3)
    qdd = 0.3 * w * w * np.cos(w * t)[:, None] * np.ones(3)
    traj = through_states(t, q, qd, qdd, max_velocity=2.0, max_acceleration=5.0)
    np.testing.assert_allclose(traj.times, t, atol=1e-9)
    dense = np.linspace(0.0, 4.0, 4001)
    got = traj.sample(dense).positions
    # Between 10 ms waypoints ruckig's own jerk profile: within 2 micro-radians of the sine.
    np.testing.assert_allclose(got[:, 0], 0.3 * (1 - np.cos(w * dense)), atol=2e-6)


def test_bad_inputs_are_one_line_errors(monkeypatch):
    rest = np.zeros((2, 2))
    q = np.array([[0.0, 0.0], [1.0, 1.0]])
    limits = {"max_velocity": 1.0, "max_acceleration": 1.0}
    with pytest.raises(ValueError, match=r"state 1 \(t = 1.000 s\) is at 3 x joint 2's limits"):
        through_states([0, 1], q, np.array([[0, 0], [0.5, 3.0]]), rest, **limits)
    with pytest.raises(ValueError, match="times: expected at least 2, strictly increasing"):
        through_states([1, 1], q, rest, rest, **limits)
    with pytest.raises(ValueError, match=r"expected shapes \(2,\) and \(2, 2\)"):
        through_states([0, 1, 2], q, rest, rest, **limits)
    with pytest.raises(ValueError, match=r"max_jerk: must be finite and > 0, got 0\.0 for joint 1"):
        through_states([0, 1], q, rest, rest, max_jerk=0.0, **limits)
    # One line naming the argument, not NumPy's broadcasting error (the arm's own check).
    with pytest.raises(ValueError, match=r"max_jerk: expected a number or one per joint \(2 j"):
        through_states([0, 1], q, rest, rest, max_jerk=[1.0, 2.0, 3.0], **limits)
    with pytest.raises(ValueError, match="backend: expected 'lfdkit', 'toppra' or 'ruckig'"):
        time_parameterize(q, max_velocity=1, max_acceleration=1, backend="reflexxes")
    monkeypatch.setitem(sys.modules, "ruckig", None)
    with pytest.raises(ImportError, match="backend: 'ruckig' needs ruckig: python -m pip"):
        time_parameterize(random_path(0), backend="ruckig")
