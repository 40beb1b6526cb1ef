"""TimedPath, the one timed-path record: its checks, sampling and fixed-rate stream."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lfdkit.core.rotations import exp
from lfdkit.model.timed_path import TimedPath, TimedPlan, fixed_rate_times


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
    stream = TimedPlan(t, points, velocities).at_rate(rate)
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
    stream = TimedPlan(t, points, velocities).at_rate(1e5)
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
    stream = TimedPlan(t, points, velocities, orientations=turns).at_rate(4.0)  # 0, .25, .5, .75
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
    plan = TimedPlan(t, np.zeros((3, 2)), np.zeros((3, 2)))
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


def test_a_batch_is_sampled_as_each_of_its_rollouts():
    t = np.array([0.0, 0.4, 1.0, 1.5])
    rng = np.random.default_rng(7)
    positions, velocities = rng.normal(size=(2, 3, 4, 2))
    batch = TimedPath(t, positions, velocities).sample(np.linspace(-0.2, 1.7, 23))
    for k in range(3):
        one = TimedPath(t, positions[k], velocities[k]).sample(batch.times)
        np.testing.assert_array_equal(batch.positions[k], one.positions)
        np.testing.assert_array_equal(batch.velocities[k], one.velocities)
    # At its own times the curve is the samples; outside them it rests at the ends.
    own = TimedPath(t, positions[0], velocities[0]).sample(t)
    np.testing.assert_allclose(own.positions, positions[0], atol=1e-15)
    np.testing.assert_array_equal(batch.positions[:, 0], positions[:, 0])
    np.testing.assert_array_equal(batch.velocities[:, [0, -1]], 0.0)


def test_the_record_is_immutable_and_leaves_the_callers_arrays_alone():
    points = np.zeros((3, 2))
    path = TimedPath([0.0, 1.0, 2.0], points, np.zeros((3, 2)))
    with pytest.raises(ValueError, match="read-only"):
        path.positions[0, 0] = 1.0
    with pytest.raises(AttributeError):
        path.times = np.zeros(3)  # type: ignore[misc]
    points[0, 0] = 5.0  # the caller's array stays writable
    assert path.duration == 2.0 and path.accelerations is None


@pytest.mark.parametrize(
    ("fields", "message"),
    [
        ({"times": [[0.0, 1.0]]}, r"times: expected a 1-D array"),
        ({"times": [0.0, np.nan]}, "times: contains NaN"),
        ({"times": [1.0, 0.0]}, "times: must not decrease"),
        ({"positions": np.zeros((3, 2))}, r"positions: expected shape \(2, q\)"),
        ({"velocities": np.zeros((2, 3))}, r"velocities: expected the positions' shape \(2, 2\)"),
        ({"accelerations": np.zeros(2)}, "accelerations: expected the positions' shape"),
        ({"orientations": np.zeros((2, 3))}, r"orientations: expected shape \(2, 4\)"),
        ({"positions": "ab"}, "positions: expected an array of numbers"),
    ],
)
def test_a_malformed_path_is_one_line_naming_the_field(fields, message):
    given = {"times": [0.0, 1.0], "positions": np.zeros((2, 2)), "velocities": np.zeros((2, 2))}
    given.update(fields)
    with pytest.raises((ValueError, TypeError), match=message) as error:
        TimedPath(given.pop("times"), given.pop("positions"), given.pop("velocities"), **given)
    assert "\n" not in str(error.value)


def test_a_plan_is_one_path_whose_points_are_its_positions():
    plan = TimedPlan([0.0, 1.0], np.eye(2), np.zeros((2, 2)), details="planner")
    assert plan.points is plan.positions and plan.details == "planner"
    assert plan.at_rate(4.0).details == "planner"
    with pytest.raises(ValueError, match="a plan is one path"):
        TimedPlan([0.0, 1.0], np.zeros((3, 2, 2)), np.zeros((3, 2, 2)))


def test_without_velocities_the_path_is_linear_and_held_at_its_ends():
    # An obstacle's track (model.motion.Trajectory) is such a path: np.interp's numbers.
    t = np.array([1.0, 2.5, 4.0])
    points = np.array([[0.0, 0.3], [0.2, 0.5], [0.0, 0.6]])
    path = TimedPath(t, points)
    query = np.array([3.0, 0.0, 1.75, 9.0])  # any order
    expected = np.column_stack([np.interp(query, t, points[:, i]) for i in range(2)])
    np.testing.assert_array_equal(path.positions_at(query), expected)
    batch = TimedPath(t, np.stack([points, 2 * points]))
    np.testing.assert_array_equal(batch.positions_at(query)[1], 2 * expected)
    sampled = path.sample(np.sort(query))
    assert sampled.velocities is None
    with pytest.raises(ValueError, match="velocities: this path has none"):
        _ = path.speeds
