"""lfdkit.imitate.warp_path against its closed form."""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.imitate import warp_path


def s_curve(n: int = 120) -> np.ndarray:
    u = np.linspace(0.0, 1.0, n)
    return np.column_stack([4.0 * u, np.sin(2.0 * np.pi * u) + 0.5 * u])


def test_the_new_start_and_goal_are_hit_exactly() -> None:
    path = s_curve()
    start, goal = np.array([0.1, -0.3]), np.array([5.0, 2.0])
    warped = warp_path(path, start, goal)
    assert warped.shape == path.shape
    np.testing.assert_array_equal(warped[0], start)
    np.testing.assert_array_equal(warped[-1], goal)
    np.testing.assert_array_equal(warp_path(path), path)  # default: the path's own ends


def test_each_point_moves_by_the_arc_length_blend_of_the_offsets() -> None:
    # Uneven spacing: the blend follows the arc length, not the sample index.
    path = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 3.0], [1.0, 4.0]])
    start, goal = np.array([0.0, 1.0]), np.array([3.0, 4.0])
    u = np.array([0.0, 1.0, 4.0, 5.0]) / 5.0  # segments of length 1, 3 and 1
    expected = path + (1 - u)[:, None] * (start - path[0]) + u[:, None] * (goal - path[-1])
    np.testing.assert_allclose(warp_path(path, start, goal), expected, atol=1e-15)


@pytest.mark.parametrize("q", [1, 2, 3])
def test_a_straight_line_stays_straight(q: int) -> None:
    rng = np.random.default_rng(q)
    a, b = rng.normal(size=q), rng.normal(size=q)
    # Unevenly sampled, still straight.
    path = a + np.sort(rng.uniform(0.0, 1.0, 40))[:, None] * (b - a)
    path = np.vstack([a, path, b])
    start, goal = rng.normal(size=q), rng.normal(size=q)
    warped = warp_path(path, start, goal)
    direction = (goal - start) / np.linalg.norm(goal - start)
    offsets = warped - start
    off_line = offsets - np.outer(offsets @ direction, direction)
    assert np.abs(off_line).max() < 1e-12
    # And evenly along it, as the original was.
    fraction = (offsets @ direction) / np.linalg.norm(goal - start)
    original = ((path - a) @ (b - a)) / np.dot(b - a, b - a)
    np.testing.assert_allclose(fraction, original, atol=1e-12)


def test_warping_commutes_with_translations() -> None:
    path = s_curve()
    start, goal = np.array([0.3, 0.2]), np.array([4.5, 1.0])
    shift = np.array([-7.0, 2.5])
    np.testing.assert_allclose(
        warp_path(path + shift, start + shift, goal + shift),
        warp_path(path, start, goal) + shift,
        atol=1e-12,
    )
    # Moving start and goal by the same vector moves the whole path by it.
    np.testing.assert_allclose(
        warp_path(path, path[0] + shift, path[-1] + shift), path + shift, atol=1e-12
    )


def test_a_closed_path_is_warped_with_bounded_distortion() -> None:
    angle = np.linspace(0.0, 2.0 * np.pi, 100)
    loop = np.column_stack([np.cos(angle), np.sin(angle)])
    start, goal = loop[0] + [0.2, 0.0], loop[-1] + [0.0, -0.3]
    warped = warp_path(loop, start, goal)
    np.testing.assert_array_equal(warped[[0, -1]], [start, goal])
    assert np.linalg.norm(warped - loop, axis=1).max() <= 0.3 + 1e-12


@pytest.mark.parametrize(
    ("args", "error", "match"),
    [
        ((np.zeros((5, 2)), [1.0, 1.0], None), ValueError, "path: has zero length"),
        ((np.zeros((1, 2)),), ValueError, "path: needs at least 2 points"),
        ((np.zeros(5),), ValueError, "path: expected a 2-D array"),
        ((np.array([[0.0, 0.0], [np.nan, 1.0]]),), ValueError, "path: contains NaN at row 1"),
        ((s_curve(), [0.0, 0.0, 0.0]), ValueError, r"start: expected shape \(2,\)"),
        ((s_curve(), None, [np.inf, 0.0]), ValueError, "goal: contains NaN or infinite"),
        ((s_curve(), ["a", "b"]), TypeError, "start: expected 2 numbers"),
    ],
)
def test_bad_input_is_refused_naming_the_argument(args, error, match) -> None:
    with pytest.raises(error, match=match):
        warp_path(*args)
