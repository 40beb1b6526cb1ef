"""The fixed-rate trajectory's velocities are finite differences of its positions (issue 29).

At the rate a controller streams (500 Hz, ``h = 2 ms``) the joint trajectory
of :func:`lfdkit.execute.pipeline.execute_plan` is a cubic in time between
two waypoints (10 ms apart). Away from a waypoint (all stencil samples in one
interval):

* the 5-point difference ``(-q(t+2h) + 8 q(t+h) - 8 q(t-h) + q(t-2h)) / 12h``
  is exact for a cubic, so it equals the velocities to rounding (relative
  1e-9, the issue asks 1e-6);
* the plain central difference ``(q(t+h) - q(t-h)) / 2h`` is off by exactly
  ``h² q'''/6`` (its truncation error, ``q'''`` constant on the interval):
  within 1e-6 of the largest velocity on the UR5 (analytic IK), 2-3e-6 on
  the UR5e and Panda (numerical IK), whose joint paths bend faster;
* the accelerations are central differences of the velocities to rounding
  (``q''`` is linear there).

Across a waypoint the spline is C²: the differences agree to 1e-3 of the
largest value. The 6 s reach is the benchmark's (``benchmarks/robot.py``). The plan's own
stream (:meth:`lfdkit.model.timed_path.TimedPlan.at_rate`, ``lfdkit plan --rate``) is a cubic
Hermite curve between planned points: the same 5-point check holds.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from lfdkit.datasets import example_urdf
from lfdkit.execute.arm import UR5
from lfdkit.execute.pipeline import execute_plan
from lfdkit.execute.urdf import UrdfArm

DATA = example_urdf("ur5").parent  # the example arms lfdkit ships
RATE = 500.0


def reach_plan():
    t = np.linspace(0.0, 6.0, 120)
    s = 0.5 - 0.5 * np.cos(np.pi * t / 6.0)
    p = np.column_stack([np.full_like(t, 0.45), -0.3 + 0.6 * s, 0.15 + 0.22 * np.sin(np.pi * s)])
    return SimpleNamespace(times=t, positions=p)


def within_one_interval(knots: np.ndarray, times: np.ndarray, reach: int) -> np.ndarray:
    """For samples ``reach … m-reach-1``: whether the stencil ``±reach`` lies in one interval."""
    first = np.searchsorted(knots, times[: -2 * reach], "right")
    last = np.searchsorted(knots, times[2 * reach :], "right")
    return first == last


@pytest.mark.parametrize(
    ("arm", "central_bound"),
    [(UR5, 1e-6), (UrdfArm(DATA / "panda.urdf", tip_link="panda_hand_tcp"), 5e-6)],
    ids=["ur5", "panda"],
)
def test_velocities_are_finite_differences_of_the_positions(arm, central_bound):
    run = execute_plan(reach_plan(), arm, speed_fraction=0.5, rate=RATE)
    samples = run.samples
    t, q, qd, qdd = (
        samples.times,
        samples.positions,
        samples.velocities,
        samples.accelerations,
    )
    h = 1.0 / RATE
    np.testing.assert_allclose(np.diff(t), h, rtol=1e-12)
    knots = run.trajectory.times
    v_scale, a_scale = np.abs(qd).max(), np.abs(qdd).max()

    away = within_one_interval(knots, t, 2)
    assert away.sum() > 250  # one sample in each 10 ms interval
    five = (-q[4:] + 8 * q[3:-1] - 8 * q[1:-3] + q[:-4]) / (12 * h)
    assert np.abs(five - qd[2:-2])[away].max() < 1e-9 * v_scale

    away = within_one_interval(knots, t, 1)
    central = (q[2:] - q[:-2]) / (2 * h)
    error = np.abs(central - qd[1:-1])
    # The central difference's truncation error is h^2 q'''/6; q''' is the slope of qdd there.
    jerk = np.abs(qdd[2:] - qdd[:-2]) / (2 * h)
    np.testing.assert_allclose(error[away], (h * h / 6 * jerk)[away], atol=1e-9 * v_scale)
    assert error[away].max() < central_bound * v_scale
    assert error.max() < 1e-3 * v_scale  # across a waypoint too

    central = (qd[2:] - qd[:-2]) / (2 * h)
    assert np.abs(central - qdd[1:-1])[away].max() < 1e-9 * a_scale
    assert np.abs(central - qdd[1:-1]).max() < 1e-2 * a_scale


def test_the_plans_stream_too_lfdkit_plan_rate():
    # TimedPlan.at_rate (lfdkit plan --rate): a cubic Hermite curve between planned points.
    from lfdkit.model.timed_path import TimedPlan

    rng = np.random.default_rng(5)
    times = np.r_[0.0, np.cumsum(rng.uniform(0.03, 0.08, 60))]
    points = np.cumsum(rng.normal(0.0, 0.01, (61, 3)), axis=0)
    velocities = rng.normal(0.0, 0.2, (61, 3))
    velocities[[0, -1]] = 0.0
    stream = TimedPlan(times, points, velocities, None).at_rate(RATE)
    t, q, qd = stream.times, stream.points, stream.velocities
    inside = t <= times[-1]
    t, q, qd = t[inside], q[inside], qd[inside]
    h = 1.0 / RATE
    away = within_one_interval(times, t, 2)
    assert away.sum() > 0.5 * len(t)
    five = (-q[4:] + 8 * q[3:-1] - 8 * q[1:-3] + q[:-4]) / (12 * h)
    assert np.abs(five - qd[2:-2])[away].max() < 1e-9 * np.abs(qd).max()
