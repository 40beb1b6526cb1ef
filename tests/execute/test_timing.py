"""Tests for lfdkit.execute.timing: time parameterisation within joint limits.

Limits are checked at 1 kHz with no margin, both on the analytic derivatives
and on finite differences of the positions (a difference quotient is an
average of the derivative, so it must respect the same bound).
"""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.execute.arm import UR5, UR10
from lfdkit.execute.timing import (
    SAFETY_MARGIN,
    Timing,
    time_parameterize,
)

UR5_MAX_VELOCITY = float(UR5.max_joint_speed[0])  # the same on every joint
UR5_MAX_ACCELERATION = float(UR5.max_joint_acceleration[0])

RATE = 1000.0


def min_time(distance: float, v: float, a: float) -> float:
    """Closed-form shortest rest-to-rest time: trapezoid, or triangle for short moves."""
    if distance >= v * v / a:
        return distance / v + v / a
    return 2.0 * np.sqrt(distance / a)


def random_path(seed: int, n: int | None = None, scale: float = 0.4) -> np.ndarray:
    rng = np.random.default_rng(seed)
    n = int(rng.integers(3, 25)) if n is None else n
    return np.cumsum(rng.normal(scale=scale, size=(n, 6)), axis=0)


def assert_within_limits(timing: Timing) -> None:
    t = np.arange(0.0, timing.duration + 1.0 / RATE, 1.0 / RATE)
    samples = timing.sample(t)
    q, qd, qdd = samples.positions, samples.velocities, samples.accelerations
    vmax, amax = timing.max_velocity, timing.max_acceleration
    assert np.all(np.abs(qd) <= vmax)
    assert np.all(np.abs(qdd) <= amax)
    h = 1.0 / RATE
    fd_v = np.diff(q, axis=0) / h
    fd_a = (q[2:] - 2 * q[1:-1] + q[:-2]) / h**2
    assert np.all(np.abs(fd_v) <= vmax * (1 + 1e-9))
    assert np.all(np.abs(fd_a) <= amax * (1 + 1e-6))  # rounding of q / h² only
    # The analytic velocity is the derivative of the positions.
    np.testing.assert_allclose((q[2:] - q[:-2]) / (2 * h), qd[1:-1], atol=amax.max() * h)


# ------------------------------------------------------------------ single joint
@pytest.mark.parametrize("distance", [0.05, 0.3, 0.68, 1.0, 2.5, 6.0])
@pytest.mark.parametrize("joint", [0, 4])
def test_single_joint_matches_closed_form(distance, joint):
    q = np.zeros((2, 6))
    q[1, joint] = distance
    timing = time_parameterize(q)
    best = min_time(distance, UR5_MAX_VELOCITY, UR5_MAX_ACCELERATION)
    assert best <= timing.duration <= best * (1 + 1.5 * SAFETY_MARGIN)
    assert_within_limits(timing)
    # Other joints do not move.
    t = np.linspace(0, timing.duration, 200)
    samples = timing.sample(t)
    q_s, qd_s = samples.positions, samples.velocities
    others = np.delete(np.arange(6), joint)
    np.testing.assert_allclose(q_s[:, others], 0.0, atol=1e-12)
    np.testing.assert_allclose(qd_s[:, others], 0.0, atol=1e-12)


def test_collinear_waypoints_stay_on_the_line():
    # Unevenly spaced waypoints on one straight line: the spline is the line itself.
    q = np.zeros((5, 6))
    q[:, 1] = [0.0, 0.1, 0.15, 0.9, 2.0]
    q[:, 3] = -0.5 * q[:, 1]
    timing = time_parameterize(q, max_velocity=2.0, max_acceleration=8.0)
    qs = timing.sample(np.linspace(0, timing.duration, 500)).positions
    np.testing.assert_allclose(qs[:, 3], -0.5 * qs[:, 1], atol=1e-12)
    assert np.all(np.diff(qs[:, 1]) >= -1e-12)  # no overshoot, no going back
    # Limits bind on joint 1 (the faster one): same time as a single joint move of it.
    best = min_time(2.0, 2.0, 8.0)
    assert best <= timing.duration <= best * (1 + 1.5 * SAFETY_MARGIN)


# ------------------------------------------------------------------ multi joint
@pytest.mark.parametrize("seed", range(6))
def test_random_paths_respect_limits(seed):
    timing = time_parameterize(random_path(seed))
    assert_within_limits(timing)


def test_per_joint_limits_respected():
    q = random_path(11, n=8)
    vmax = [1.0, 2.0, 3.2, 0.5, 3.0, 1.5]
    amax = [4.0, 15.0, 10.0, 2.0, 6.0, 9.0]
    timing = time_parameterize(q, max_velocity=vmax, max_acceleration=amax)
    np.testing.assert_array_equal(timing.max_velocity, vmax)
    np.testing.assert_array_equal(timing.max_acceleration, amax)
    assert_within_limits(timing)


def test_limits_are_nearly_reached():
    # Time-optimal in spirit: some joint runs close to one of its limits.
    timing = time_parameterize(random_path(3))
    samples = timing.sample(np.arange(0, timing.duration, 1e-3))
    qd, qdd = samples.velocities, samples.accelerations
    ratio = max(
        (np.abs(qd) / timing.max_velocity).max(), (np.abs(qdd) / timing.max_acceleration).max()
    )
    assert ratio > 1 - 2 * SAFETY_MARGIN


def test_starts_and_ends_at_rest():
    q = random_path(4)
    timing = time_parameterize(q)
    ends = timing.sample([0.0, timing.duration])
    np.testing.assert_allclose(ends.positions, q[[0, -1]], atol=1e-12)
    np.testing.assert_allclose(ends.velocities[0], 0.0, atol=1e-12)
    np.testing.assert_allclose(ends.velocities[1], 0.0, atol=1e-9)
    # Outside [0, duration] the robot holds still.
    for t, end in ((-1.0, q[0]), (timing.duration + 1.0, q[-1])):
        samples = timing.sample(t)
        qq, qd, qdd = samples.positions[0], samples.velocities, samples.accelerations
        np.testing.assert_allclose(qq, end, atol=1e-12)
        np.testing.assert_array_equal(qd, 0.0)
        np.testing.assert_array_equal(qdd, 0.0)


def test_passes_through_every_waypoint():
    # The spline interpolates: each waypoint is hit exactly at its time (to rounding).
    q = random_path(5, n=20)
    timing = time_parameterize(q)
    assert timing.times.shape == (20,)
    assert timing.times[0] == 0.0
    assert np.all(np.diff(timing.times) > 0)
    assert timing.times[-1] == pytest.approx(timing.duration)
    np.testing.assert_allclose(timing.sample(timing.times).positions, q, atol=1e-9)
    np.testing.assert_array_equal(timing.waypoint_index, np.arange(20))


def test_path_reversal():
    q = np.zeros((3, 6))
    q[1, :2] = [1.0, 0.5]
    timing = time_parameterize(q)
    assert_within_limits(timing)
    np.testing.assert_allclose(timing.sample(timing.times).positions, q, atol=1e-12)


def test_dense_waypoints():
    s = np.linspace(0, 2 * np.pi, 600)
    q = np.column_stack((np.sin(s), np.cos(2 * s), s / 4, 0 * s, 0.2 * np.sin(s), 0.1 * s))
    timing = time_parameterize(q)
    assert_within_limits(timing)
    np.testing.assert_allclose(timing.sample(timing.times).positions, q, atol=1e-9)


def test_repeated_waypoints_are_dropped():
    q = np.zeros((5, 6))
    q[1:3, 0] = 1.0  # rows 1 and 2 coincide
    q[3:, 0] = 2.0  # rows 3 and 4 coincide
    q[4, 0] += 1e-12  # within DUPLICATE_TOL
    timing = time_parameterize(q)
    np.testing.assert_array_equal(timing.waypoint_index, [0, 1, 3])
    np.testing.assert_array_equal(timing.waypoints, q[[0, 1, 3]])
    assert np.all(np.diff(timing.times) > 0)


# ------------------------------------------------------------------ speed fraction
def test_speed_fraction_stretches_time():
    q = random_path(6)
    fast = time_parameterize(q)
    slow = time_parameterize(q, speed_fraction=0.2)
    # Velocity limits × 0.2, acceleration limits × 0.2²: the same motion 5 times slower.
    np.testing.assert_allclose(slow.max_velocity, 0.2 * UR5_MAX_VELOCITY)
    np.testing.assert_allclose(slow.max_acceleration, 0.04 * UR5_MAX_ACCELERATION)
    assert slow.duration == pytest.approx(fast.duration / 0.2, rel=1e-9)
    np.testing.assert_allclose(slow.times, fast.times / 0.2, rtol=1e-9, atol=1e-12)
    t = np.linspace(0, 0.999 * fast.duration, 50)  # inside: the end is at rest, qdd = 0 after
    samples = fast.sample(t)
    qf, qdf, qddf = samples.positions, samples.velocities, samples.accelerations
    samples = slow.sample(t / 0.2)
    qs, qds, qdds = samples.positions, samples.velocities, samples.accelerations
    np.testing.assert_allclose(qs, qf, atol=1e-9)
    np.testing.assert_allclose(qds, 0.2 * qdf, atol=1e-9)
    np.testing.assert_allclose(qdds, 0.04 * qddf, atol=1e-8)
    assert_within_limits(slow)


# ------------------------------------------------------------------ resampling
def test_resample_uniform_125_hz():
    q = random_path(7)
    timing = time_parameterize(q)
    samples = timing.resample(125)
    times, qq, qd, qdd = samples.times, samples.positions, samples.velocities, samples.accelerations
    m = len(times)
    assert qq.shape == qd.shape == qdd.shape == (m, 6)
    np.testing.assert_allclose(np.diff(times), 1 / 125, rtol=1e-12)
    assert times[0] == 0.0
    assert times[-1] >= timing.duration > times[-2]
    np.testing.assert_allclose(qq[0], q[0], atol=1e-12)
    np.testing.assert_allclose(qq[-1], q[-1], atol=1e-12)
    np.testing.assert_allclose(qd[[0, -1]], 0.0, atol=1e-9)
    q2 = timing.sample(times).positions
    np.testing.assert_array_equal(qq, q2)


def test_sample_shapes():
    timing = time_parameterize(random_path(8, n=4))
    samples = timing.sample(0.1)  # a number is one time
    q, qd, qdd = samples.positions, samples.velocities, samples.accelerations
    assert q.shape == qd.shape == qdd.shape == (1, 6) and samples.times.shape == (1,)
    samples = timing.sample([0.1, 0.2, 0.3])
    q, qd, qdd = samples.positions, samples.velocities, samples.accelerations
    assert q.shape == (3, 6)
    assert timing.n_joints == 6


def test_other_joint_counts():
    q = np.array([[0.0], [1.0]])
    timing = time_parameterize(q, max_velocity=1.0, max_acceleration=2.0)
    assert timing.duration == pytest.approx(min_time(1.0, 1.0, 2.0), rel=2 * SAFETY_MARGIN)


# ------------------------------------------------------------------ errors
@pytest.mark.parametrize(
    ("q", "kwargs", "error", "message"),
    [
        (np.zeros((1, 6)), {}, ValueError, "q: needs at least 2 points"),
        (np.zeros(6), {}, ValueError, "q: expected a 2-D array"),
        ([[0.0] * 6, [np.nan] * 6], {}, ValueError, "q: contains NaN"),
        (np.zeros((3, 6)), {}, ValueError, "q: all 3 waypoints coincide"),
        (np.eye(6)[:2], {"max_velocity": 0.0}, ValueError, "max_velocity: must be finite and > 0"),
        (np.eye(6)[:2], {"max_velocity": [1.0, 2.0]}, ValueError, r"max_velocity: expected .*6"),
        (np.eye(6)[:2], {"max_acceleration": -1}, ValueError, "max_acceleration: must be"),
        (np.eye(6)[:2], {"max_acceleration": np.inf}, ValueError, "max_acceleration: must be"),
        (np.eye(6)[:2], {"max_velocity": "fast"}, TypeError, "max_velocity: expected numbers"),
        (
            np.eye(6)[:2],
            {"speed_fraction": 0.0},
            ValueError,
            r"speed_fraction: must be in \[0.001, 1\]",
        ),
        (np.eye(6)[:2], {"speed_fraction": 1.5}, ValueError, "speed_fraction: must be in"),
        (np.eye(6)[:2], {"speed_fraction": np.nan}, ValueError, "speed_fraction: must be in"),
    ],
)
def test_errors(q, kwargs, error, message):
    with pytest.raises(error, match=message):
        time_parameterize(q, **kwargs)


def test_sample_and_resample_errors():
    timing = time_parameterize(np.eye(6)[:2])
    with pytest.raises(ValueError, match="t: contains NaN"):
        timing.sample(np.nan)
    with pytest.raises(ValueError, match="t: expected a number or a 1-D array"):
        timing.sample(np.zeros((2, 2)))
    with pytest.raises(ValueError, match="rate_hz: must be > 0"):
        timing.resample(0)


# ------------------------------------------------------------------ the arm's limits
def test_limits_come_from_the_arm():
    """A UR10 base move keeps to its 120°/s; the same move on the UR5 may take 3.2 rad/s."""
    base = np.radians(120.0)
    q = np.zeros((2, 6))
    q[1, 0] = 3.0
    ur10 = time_parameterize(q, arm=UR10)
    np.testing.assert_allclose(ur10.max_velocity, UR10.max_joint_speed)
    np.testing.assert_allclose(ur10.max_acceleration, UR10.max_joint_acceleration)
    assert_within_limits(ur10)
    qd = ur10.sample(np.linspace(0.0, ur10.duration, 2000)).velocities
    assert np.abs(qd[:, 0]).max() <= base
    assert np.abs(qd[:, 0]).max() > 0.98 * base  # and uses it
    best = min_time(3.0, base, 15.0)
    assert best <= ur10.duration <= best * (1 + 1.5 * SAFETY_MARGIN)
    ur5 = time_parameterize(q)
    assert ur5.duration < ur10.duration
    # Wrist joints of the UR10 are allowed 180°/s.
    q[1] = [0, 0, 0, 3.0, 0, 0]
    wrist = time_parameterize(q, arm=UR10)
    best = min_time(3.0, np.pi, 15.0)
    assert best <= wrist.duration <= best * (1 + 1.5 * SAFETY_MARGIN)
    # Explicit limits win over the arm's; speed_fraction scales the arm's.
    np.testing.assert_allclose(time_parameterize(q, arm=UR10, max_velocity=1.0).max_velocity, 1.0)
    slow = time_parameterize(q, arm=UR10, speed_fraction=0.5)
    np.testing.assert_allclose(slow.max_velocity, 0.5 * UR10.max_joint_speed)
    np.testing.assert_allclose(slow.max_acceleration, 0.25 * UR10.max_joint_acceleration)


def test_joint_count_must_match_the_arm_whose_limits_are_used():
    q = np.array([[0.0] * 5, [0.1] * 5])
    with pytest.raises(ValueError, match="q: has 5 joints, the UR5 6"):
        time_parameterize(q)
    with pytest.raises(ValueError, match="q: has 5 joints, the UR10 6"):
        time_parameterize(q, arm=UR10, max_velocity=1.0)  # the acceleration is the arm's
    assert time_parameterize(q, max_velocity=1.0, max_acceleration=2.0).n_joints == 5
    with pytest.raises(TypeError, match="arm: expected an Arm"):
        time_parameterize(np.eye(6)[:2], arm="UR10")


def test_absurd_sizes_and_speeds_are_one_line_refusals_not_memory_errors():
    q = np.zeros((2, 6))
    q[1, 0] = 1e6  # a million radians: the timing exists, 125 Hz samples of it would not fit
    timing = time_parameterize(q)
    with pytest.raises(ValueError, match=r"rate_hz: 125 Hz over .* s gives .* at most 1,000,000"):
        timing.resample(125)
    short = time_parameterize(np.eye(6)[:2])
    with pytest.raises(ValueError, match=r"rate_hz: 1e\+09 Hz over .*split the motion"):
        short.resample(1e9)
    assert len(short.resample(125).times) == int(np.ceil(short.duration * 125 - 1e-9)) + 1
    with pytest.raises(ValueError, match=r"speed_fraction: must be in \[0.001, 1\], got 1e-300; a"):
        time_parameterize(np.eye(6)[:2], speed_fraction=1e-300)


def test_the_toppra_backend_gives_the_same_timing():
    """toppra (the field's TOPP-RA) on the same spline and grid: the same duration to 1e-6."""
    pytest.importorskip("toppra")
    rng = np.random.default_rng(5)
    q = np.cumsum(rng.normal(0.0, 0.1, (12, 6)), axis=0)
    mine = time_parameterize(q, speed_fraction=0.5)
    theirs = time_parameterize(q, speed_fraction=0.5, backend="toppra")
    assert theirs.duration == pytest.approx(mine.duration, rel=1e-6)
    np.testing.assert_allclose(theirs.times, mine.times, rtol=1e-6)
    with pytest.raises(ValueError, match="backend: expected 'lfdkit', 'toppra' or 'ruckig', got"):
        time_parameterize(q, backend="reflexxes")
