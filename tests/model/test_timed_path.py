"""TimedPlan.at_rate: fixed-rate samples of a timed path (what a controller streams)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lfdkit.core.rotations import exp
from lfdkit.model.timed_path import TimedPlan, fixed_rate_times


def cubic(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A 2-D cubic in time and its exact velocity."""
    return np.c_[t**3 - 2 * t, 0.5 * t**2 + t], np.c_[3 * t**2 - 2, t + 1]


@settings(max_examples=30, deadline=None)
@given(
    n=st.integers(3, 40),
    warp=st.floats(0.5, 2.0),
    rate=st.floats(5.0, 2000.0),
)
def test_a_cubic_motion_is_streamed_exactly_at_any_rate(n, warp, rate):
    # Unevenly spaced times: the Hermite curve through exact points and velocities
    # of a cubic is that cubic, so every sample is the motion itself.
    t = 2.0 * np.linspace(0.0, 1.0, n) ** warp
    points, velocities = cubic(t)
    stream = TimedPlan(t, points, velocities, None).at_rate(rate)
    # The last sample is the first at or after the end (to round-off: 1e-9 s).
    assert stream.times[0] == 0.0 and stream.times[-1] >= 2.0 - 1e-9 > stream.times[-2]
    np.testing.assert_allclose(np.diff(stream.times), 1.0 / rate, rtol=1e-9)
    inside = stream.times <= 2.0
    exact_points, exact_velocities = cubic(stream.times[inside])
    np.testing.assert_allclose(stream.points[inside], exact_points, atol=1e-12)
    np.testing.assert_allclose(stream.velocities[inside], exact_velocities, atol=1e-11)


def test_velocities_are_the_derivative_of_the_streamed_positions():
    t = np.linspace(0.0, 1.0, 9) ** 1.5
    rng = np.random.default_rng(3)
    points = np.cumsum(rng.normal(size=(9, 3)), axis=0)
    velocities = rng.normal(size=(9, 3))
    velocities[[0, -1]] = 0.0
    stream = TimedPlan(t, points, velocities, None).at_rate(1e5)
    dt = stream.times[1] - stream.times[0]
    central = (stream.points[2:] - stream.points[:-2]) / (2 * dt)
    inner = stream.velocities[1:-1]
    # The curve is C1: its acceleration may jump at a planned point, so a central
    # difference straddling one is off by about dt times the jump; elsewhere it is exact
    # to dt squared.
    straddles = np.searchsorted(t, stream.times[:-2], "right") != np.searchsorted(
        t, stream.times[2:], "right"
    )
    scale = np.abs(inner).max()
    assert np.max(np.abs(central - inner)[~straddles]) < 1e-6 * scale
    assert np.max(np.abs(central - inner)) < 1e-3 * scale


def test_after_the_end_the_tool_rests_at_the_last_point_and_orientations_stay_unit():
    t = np.array([0.0, 0.3, 0.7])
    points = np.array([[0.0, 0.0], [0.1, 0.05], [0.2, 0.0]])
    velocities = np.array([[0.0, 0.0], [0.3, 0.0], [0.0, 0.0]])
    turns = exp(np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.4], [0.0, 0.0, 0.9]]))
    stream = TimedPlan(t, points, velocities, None, turns).at_rate(4.0)  # 0, .25, .5, .75
    np.testing.assert_array_equal(stream.times, [0.0, 0.25, 0.5, 0.75])
    np.testing.assert_array_equal(stream.points[-1], points[-1])
    np.testing.assert_array_equal(stream.velocities[-1], 0.0)
    np.testing.assert_allclose(np.linalg.norm(stream.orientations, axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(stream.orientations[0], turns[0], atol=1e-15)
    np.testing.assert_allclose(stream.orientations[-1], turns[-1], atol=1e-12)


@pytest.mark.parametrize(
    ("rate", "message"),
    [(0.0, "rate_hz"), (-1.0, "rate_hz"), (float("nan"), "rate_hz"), (1e9, "lower the rate")],
)
def test_a_bad_rate_is_one_line_naming_it(rate, message):
    t = np.array([0.0, 1.0, 2.0])
    plan = TimedPlan(t, np.zeros((3, 2)), np.zeros((3, 2)), None)
    with pytest.raises(ValueError, match=message) as error:
        plan.at_rate(rate)
    assert "\n" not in str(error.value)


@pytest.mark.parametrize(
    ("duration", "rate", "expected"),
    [
        (1.0, 4, [0.0, 0.25, 0.5, 0.75, 1.0]),  # the end is a sample
        (1.1, 4, [0.0, 0.25, 0.5, 0.75, 1.0, 1.25]),  # the first at or after the end
        (0.0, 125, [0.0]),
        (0.3, 10, [0.0, 0.1, 0.2, 0.3]),  # 0.3 * 10 is 3.0000000000000004: no extra sample
    ],
)
def test_the_fixed_rate_grid_ends_at_the_first_sample_at_or_after_the_end(duration, rate, expected):
    np.testing.assert_allclose(fixed_rate_times(duration, rate), expected, atol=1e-15)


def test_the_fixed_rate_grid_refuses_what_would_not_fit_before_making_it():
    with pytest.raises(ValueError, match=r"^rate_hz: 1e\+09 Hz over 2 s gives 2e\+09 samples;"):
        fixed_rate_times(2.0, 1e9)
    with pytest.raises(ValueError, match="rate_hz: must be > 0"):
        fixed_rate_times(2.0, 0)
