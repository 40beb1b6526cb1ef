"""Tests of :func:`lfdkit.execute.trajectory.keep_timing`: the person's timing, kept or stretched.

Known answers: within the limits the waypoint times are the plan's exactly;
over them, the result is within the limits everywhere (dense check), only the
stretch that needs it is slowed (the rest keeps its planned durations), and a
uniformly too-fast plan is stretched by about the ratio a closed form gives.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from lfdkit.execute.trajectory import keep_timing


def bump(duration: float = 6.0, n: int = 601, amplitude: float = 1.0):
    """A rest-to-rest move of one joint and a slower one of another: (t, q)."""
    t = np.linspace(0.0, duration, n)
    s = 0.5 - 0.5 * np.cos(np.pi * t / duration)
    return t, np.column_stack([amplitude * s, 0.3 * amplitude * np.sin(np.pi * s)])


def dense_state(traj):
    tt = np.linspace(0.0, traj.duration, 20001)
    return traj.sample(tt)


def test_within_the_limits_the_plan_times_are_kept_exactly():
    t, q = bump()
    traj = keep_timing(t, q, [10.0, 10.0], [10.0, 10.0])
    np.testing.assert_array_equal(traj.times, t)
    assert traj.slowdowns == ()
    assert traj.duration == traj.planned_duration == 6.0
    assert "kept" in traj.describe_slowdowns()
    # Passes every waypoint at its time, at rest at both ends.
    samples = traj.sample(t)
    q_at, qd_at = samples.positions, samples.velocities
    np.testing.assert_allclose(q_at, q, atol=1e-12)
    np.testing.assert_allclose(qd_at[[0, -1]], 0.0, atol=1e-12)


@pytest.mark.parametrize("fraction", [0.5, 0.2, 0.05])
def test_over_the_limits_it_is_within_them_everywhere(fraction):
    t, q = bump()
    samples = keep_timing(t, q, [10.0, 10.0], [10.0, 10.0]).sample(t)
    qd, qdd = samples.velocities, samples.accelerations
    vmax = fraction * np.abs(qd).max(axis=0)
    amax = fraction**2 * np.abs(qdd).max(axis=0)
    traj = keep_timing(t, q, vmax, amax)
    samples = dense_state(traj)
    v, a = samples.velocities, samples.accelerations
    assert (np.abs(v) <= vmax * (1 + 1e-9)).all()
    assert (np.abs(a) <= amax * (1 + 1e-9)).all()
    # A uniform stretch by 1/fraction would do; a local one does no worse, and not much better.
    ratio = traj.duration / traj.planned_duration
    assert 0.5 / fraction <= ratio <= 1.0 / fraction * 1.05
    assert traj.slowdowns and "slowed for the arm's limits" in traj.describe_slowdowns()


def test_only_the_fast_stretch_is_slowed():
    # 4 s of slow motion, then a fast 1 s move of joint 1.
    t = np.linspace(0.0, 5.0, 501)
    slow = np.clip(t / 4.0, 0, 1)
    fast = np.clip(t - 4.0, 0, 1)
    q = np.column_stack(
        [0.1 * (0.5 - 0.5 * np.cos(np.pi * slow)), 0.5 - 0.5 * np.cos(np.pi * fast)]
    )
    vmax, amax = np.array([1.0, 0.8]), np.array([5.0, 5.0])  # the fast move peaks at 1.57 rad/s
    traj = keep_timing(t, q, vmax, amax)
    early = t < 3.5  # before the stretch ramps up (0.25 s ramp)
    np.testing.assert_allclose(traj.times[early], t[early], atol=1e-12)
    assert traj.duration > 5.5
    (slowdown,) = traj.slowdowns
    assert slowdown.joint == 1 and slowdown.limit == "velocity"
    assert 3.5 <= slowdown.start < 4.0 and slowdown.end == 5.0


def test_fixed_rate_samples_and_the_ros_message():
    t, q = bump(duration=2.0, n=201)
    traj = keep_timing(t, q, [10.0, 10.0], [50.0, 50.0], joint_names=("a", "b"))
    samples = traj.resample(500.0)
    times, pos, vel, acc = (
        samples.times,
        samples.positions,
        samples.velocities,
        samples.accelerations,
    )
    np.testing.assert_allclose(np.diff(times), 0.002, atol=1e-12)
    assert times[-1] >= traj.duration and len(times) == 1001
    # The velocities are the positions' derivative (central differences, tiny step).
    h = 1e-6
    inner = times[1:-1]
    numeric = (traj.sample(inner + h).positions - traj.sample(inner - h).positions) / (2 * h)
    np.testing.assert_allclose(numeric, vel[1:-1], rtol=1e-6, atol=1e-6)
    numeric = (traj.sample(inner + h).velocities - traj.sample(inner - h).velocities) / (2 * h)
    np.testing.assert_allclose(numeric, acc[1:-1], rtol=1e-5, atol=1e-5)
    np.testing.assert_allclose(pos[[0, -1]], q[[0, -1]], atol=1e-12)  # rest to rest
    message = traj.ros_message(500.0)
    assert message["joint_names"] == ["a", "b"]
    last = message["points"][-1]
    assert last["time_from_start"] == {"sec": 2, "nanosec": 0}
    np.testing.assert_allclose(last["positions"], q[-1], atol=1e-12)
    json.dumps(message, allow_nan=False)


def test_bad_times_are_refused():
    t, q = bump(n=11)
    with pytest.raises(ValueError, match="times: must be strictly increasing"):
        keep_timing(t[::-1], q, 1.0, 1.0)
    with pytest.raises(ValueError, match="times: expected one per waypoint"):
        keep_timing(t[:5], q, 1.0, 1.0)
