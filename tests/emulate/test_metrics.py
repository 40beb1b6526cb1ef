"""Tests for lfdkit.emulate.metrics: e1, e2, e3, penetration and the distance space."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lfdkit.core.geometry import point_tangents
from lfdkit.emulate.metrics import distance_space, e1, e2, e3, penetration


def hline(x0, x1, y, n):
    """Horizontal segment from (x0, y) to (x1, y) with n points."""
    return np.column_stack((np.linspace(x0, x1, n), np.full(n, float(y))))


def arc(radius, a0, a1, n, centre=(0.0, 0.0)):
    th = np.linspace(a0, a1, n)
    return np.asarray(centre) + radius * np.column_stack((np.cos(th), np.sin(th)))


# ----------------------------------------------------------------- e1
@settings(max_examples=20, deadline=None)
@given(
    offsets=st.lists(st.floats(-5, 5, allow_nan=False), min_size=1, max_size=5),
    m=st.integers(2, 60),
    n_demo=st.integers(2, 40),
)
def test_e1_parallel_lines(offsets, m, n_demo):
    path = hline(0.0, 10.0, 0.0, m)
    demos = [hline(-1.0, 11.0, d, n_demo) for d in offsets]
    value, misses = e1(path, demos, return_misses=True)
    assert misses == 0
    assert value == pytest.approx(m * np.sum(np.square(offsets)), rel=1e-9, abs=1e-9)
    assert e1(path, demos) == pytest.approx(value)


def test_e1_parallel_lines_3d():
    x = np.linspace(0.0, 4.0, 9)
    path = np.column_stack((x, np.zeros(9), np.zeros(9)))
    demos = [
        np.column_stack((np.linspace(-1, 5, 4), np.full(4, a), np.full(4, b)))
        for a, b in ((1.0, 0.0), (0.0, -2.0), (3.0, 4.0))
    ]
    assert e1(path, demos) == pytest.approx(9 * (1 + 4 + 25))


def test_e1_counts_misses_and_leaves_them_out():
    path = hline(0.0, 10.0, 0.0, 11)  # points at x = 0, 1, ..., 10
    short = hline(2.5, 7.5, 1.0, 6)  # met by the normals at x = 3..7 only
    value, misses = e1(path, [short], return_misses=True)
    assert (value, misses) == (pytest.approx(5.0), 6)
    # A demonstration travelled backwards is not associated (same_direction).
    back = hline(11.0, -1.0, 2.0, 13)
    value, misses = e1(path, [short, back], return_misses=True)
    assert (value, misses) == (pytest.approx(5.0), 6 + 11)
    value, misses = e1(path, [short, back], same_direction=False, return_misses=True)
    assert (value, misses) == (pytest.approx(5.0 + 11 * 4.0), 6)
    assert isinstance(e1(path, [short]), float)


def test_e1_takes_the_nearest_crossing():
    path = hline(0.0, 4.0, 0.0, 5)
    # Two forward legs: y = 3 and, after a detour, y = 1 (the nearest).
    demo = np.array([[-1.0, 3.0], [5.0, 3.0], [5.0, 2.0], [-1.0, 2.0], [-1.0, 1.0], [5.0, 1.0]])
    assert e1(path, [demo]) == pytest.approx(5 * 1.0)
    assert e1(path, [demo], same_direction=False) == pytest.approx(5 * 1.0)
    assert e1(path, [demo[:4]]) == pytest.approx(5 * 9.0)  # backward leg y = 2 ignored
    assert e1(path, [demo[:4]], same_direction=False) == pytest.approx(5 * 4.0)


# ----------------------------------------------------------------- distance space
def test_distance_space_shapes_and_signs():
    path = hline(0.0, 10.0, 0.0, 11)
    demos = [hline(-1, 11, 0.5, 7), hline(-1, 11, -2.0, 30), hline(4.5, 20, 1.0, 3)]
    z = distance_space(path, demos)
    assert z.shape == (3, 11, 2)
    np.testing.assert_allclose(z[0], np.tile([0.0, 0.5], (11, 1)), atol=1e-12)
    np.testing.assert_allclose(z[1], np.tile([0.0, -2.0], (11, 1)), atol=1e-12)
    assert np.isnan(z[2, :5]).all()
    np.testing.assert_allclose(z[2, 5:], np.tile([0.0, 1.0], (6, 1)), atol=1e-12)
    # On a curve the vectors are along the path's normals: orthogonal to its tangents.
    c = arc(2.0, 0.0, np.pi, 40)
    z = distance_space(c, [arc(2.5, -0.2, np.pi + 0.2, 300), arc(1.0, -0.2, np.pi + 0.2, 300)])
    assert z.shape == (2, 40, 2)
    np.testing.assert_allclose(np.einsum("nmq,mq->nm", z, point_tangents(c)), 0.0, atol=1e-12)
    # Signed radial lengths: +0.5 outwards, -1 inwards (polygon chord errors ~1e-4;
    # the end tangents are those of the end segments, half a step off).
    radial = np.einsum("nmq,mq->nm", z, c / 2.0)
    np.testing.assert_allclose(radial[0, 1:-1], 0.5, atol=1e-4)
    np.testing.assert_allclose(radial[1, 1:-1], -1.0, atol=1e-4)
    np.testing.assert_allclose(radial[:, [0, -1]], [[0.5, 0.5], [-1.0, -1.0]], atol=2e-3)


def test_distance_space_3d_and_backward_demos():
    path = np.column_stack((np.linspace(0, 3, 4), np.zeros(4), np.zeros(4)))
    demo = np.column_stack((np.linspace(-1, 4, 6), np.ones(6), np.full(6, -2.0)))
    z = distance_space(path, [demo, demo[::-1]])
    assert z.shape == (2, 4, 3)
    np.testing.assert_allclose(z[0], np.tile([0.0, 1.0, -2.0], (4, 1)), atol=1e-12)
    assert np.isnan(z[1]).all()
    z = distance_space(path, [demo[::-1]], same_direction=False)
    np.testing.assert_allclose(z[0], np.tile([0.0, 1.0, -2.0], (4, 1)), atol=1e-12)


# ----------------------------------------------------------------- e2
@pytest.mark.parametrize("d", [0.0, 0.25, -1.5])
def test_e2_offset_line(d):
    nominal = hline(0.0, 10.0, 0.0, 11)
    estimate = hline(-1.0, 11.0, d, 5)
    assert e2(estimate, nominal) == pytest.approx(11 * abs(d), abs=1e-12)
    # Resampling the nominal: the sum runs over n_points points.
    assert e2(estimate, nominal, n_points=100) == pytest.approx(100 * abs(d), abs=1e-12)
    # A backward estimate is not matched; the Euclidean fallback gives the same |d|.
    assert e2(estimate[::-1], nominal) == pytest.approx(11 * abs(d), abs=1e-12)


def test_e2_concentric_arc():
    nominal = arc(3.0, 0.0, np.pi, 5000)  # finely sampled ground truth
    estimate = arc(3.2, -0.3, np.pi + 0.3, 2000)
    assert e2(estimate, nominal, n_points=100) == pytest.approx(100 * 0.2, rel=1e-4)
    inner = arc(2.5, -0.3, np.pi + 0.3, 2000)
    assert e2(inner, nominal, n_points=40) == pytest.approx(40 * 0.5, rel=1e-4)


def test_e2_penalises_an_estimate_that_stops_short():
    nominal = hline(0.0, 10.0, 0.0, 11)
    d = 0.5
    estimate = hline(0.0, 5.0, d, 6)  # stops at x = 5
    # Normals at x = 0..5 meet it at distance d; beyond, the closest point is (5, d).
    expected = 6 * d + sum(np.hypot(k, d) for k in range(1, 6))
    assert e2(estimate, nominal) == pytest.approx(expected)
    full = hline(0.0, 10.0, d, 6)
    assert e2(estimate, nominal) > e2(full, nominal) + 10


def test_e2_errors():
    with pytest.raises(ValueError, match=r"nominal.*columns"):
        e2(hline(0, 1, 0, 3), np.zeros((3, 3)))
    with pytest.raises(ValueError, match=r"estimate.*NaN"):
        e2(np.array([[0.0, 0.0], [np.nan, 1.0]]), hline(0, 1, 0, 3))
    with pytest.raises(ValueError, match=r"n_points"):
        e2(hline(0, 1, 0, 3), hline(0, 1, 0, 3), n_points=1)


# ----------------------------------------------------------------- e3
def test_e3():
    assert e3(np.array([[3.0, 4.0], [0.0, 0.0], [1.0, 0.0]])) == pytest.approx(6.0)
    assert e3(np.array([[1.0, 2.0, 2.0]])) == pytest.approx(3.0)
    assert e3(np.zeros((5, 2))) == 0.0
    with pytest.raises(ValueError, match=r"innovation"):
        e3(np.array([1.0, 2.0]))
    with pytest.raises(ValueError, match=r"innovation.*NaN"):
        e3(np.array([[np.nan, 1.0]]))


# ----------------------------------------------------------------- penetration
def test_penetration_material_left_and_right():
    nominal = hline(0.0, 10.0, 0.0, 21)  # travelling +x: left is +y
    above = hline(1.0, 9.0, 0.3, 17)
    below = hline(1.0, 9.0, -0.5, 17)
    assert penetration(above, nominal, +1) == pytest.approx((0.3, 1.0))
    assert penetration(below, nominal, +1) == (0.0, 0.0)
    assert penetration(below, nominal, -1) == pytest.approx((0.5, 1.0))
    assert penetration(above, nominal, -1) == (0.0, 0.0)
    # Reversing the nominal swaps its left and right.
    assert penetration(below, nominal[::-1], +1) == pytest.approx((0.5, 1.0))
    # On the boundary is not inside.
    assert penetration(hline(1.0, 9.0, 0.0, 5), nominal, +1) == (0.0, 0.0)


def test_penetration_partly_inside():
    nominal = hline(0.0, 10.0, 0.0, 11)
    estimate = np.array([[1.0, -0.2], [2.0, 0.1], [3.0, 0.4], [4.0, -0.3]])
    assert penetration(estimate, nominal, +1) == pytest.approx((0.4, 0.5))
    assert penetration(estimate, nominal, -1) == pytest.approx((0.3, 0.5))


def test_penetration_chord_cuts_inside_an_arc():
    radius = 2.0
    nominal = arc(radius, 0.0, np.pi, 2001)  # counter-clockwise: left normal points inwards
    a, b = nominal[500], nominal[1500]  # at pi/4 and 3pi/4
    chord = a + np.linspace(0.0, 1.0, 51)[:, None] * (b - a)
    depth, fraction = penetration(chord, nominal, +1)  # material: the disc
    sagitta = radius * (1 - np.cos(np.pi / 4))
    assert depth == pytest.approx(sagitta, abs=1e-5)
    assert fraction == pytest.approx(49 / 51)  # the two end points lie on the boundary
    assert penetration(chord, nominal, -1) == (0.0, 0.0)  # material outside the disc
    outside = arc(radius + 0.1, 0.2, np.pi - 0.2, 100)
    assert penetration(outside, nominal, +1) == (0.0, 0.0)
    depth, fraction = penetration(outside, nominal, -1)
    assert depth == pytest.approx(0.1, abs=1e-5) and fraction == 1.0


def test_penetration_errors():
    nominal = hline(0.0, 10.0, 0.0, 11)
    with pytest.raises(ValueError, match=r"material_side"):
        penetration(nominal, nominal, 0)
    with pytest.raises(ValueError, match=r"material_side"):
        penetration(nominal, nominal, 2)
    three = np.column_stack((nominal, np.zeros(11)))
    with pytest.raises(ValueError, match=r"estimate.*2 columns"):
        penetration(three, nominal, 1)
    with pytest.raises(ValueError, match=r"nominal.*2 columns"):
        penetration(nominal, three, 1)


# ----------------------------------------------------------------- input errors
def test_e1_and_distance_space_errors():
    path = hline(0.0, 1.0, 0.0, 5)
    with pytest.raises(ValueError, match=r"demos\[1\].*columns"):
        e1(path, [path, np.zeros((3, 3))])
    with pytest.raises(ValueError, match=r"path.*infinite"):
        e1(np.array([[0.0, 0.0], [np.inf, 0.0]]), [path])
    with pytest.raises(ValueError, match=r"demos.*one 2-D array"):
        distance_space(path, path)
    with pytest.raises(ValueError, match=r"path.*at least 2 points"):
        distance_space(path[:1], [path])


# ------------------------------------------------------------ held-out distances
def _frechet_reference(a: np.ndarray, b: np.ndarray) -> float:
    """Eiter and Mannila's memoised recursion, written literally."""
    from functools import cache

    @cache
    def c(i: int, j: int) -> float:
        d = float(np.linalg.norm(a[i] - b[j]))
        if i == 0 and j == 0:
            return d
        if i == 0:
            return max(c(0, j - 1), d)
        if j == 0:
            return max(c(i - 1, 0), d)
        return max(min(c(i - 1, j), c(i - 1, j - 1), c(i, j - 1)), d)

    return c(len(a) - 1, len(b) - 1)


@settings(max_examples=40, deadline=None)
@given(
    st.integers(1, 9),
    st.integers(1, 9),
    st.integers(0, 2**31 - 1),
)
def test_discrete_frechet_matches_the_recursive_definition(n, m, seed):
    from lfdkit.emulate.metrics import discrete_frechet

    rng = np.random.default_rng(seed)
    a, b = rng.normal(size=(n, 2)), rng.normal(size=(m, 2))
    assert discrete_frechet(a, b) == pytest.approx(_frechet_reference(a, b), abs=1e-12)
    assert discrete_frechet(b, a) == pytest.approx(discrete_frechet(a, b), abs=1e-12)


def test_discrete_frechet_sees_order_where_closest_points_do_not():
    from lfdkit.emulate.metrics import discrete_frechet

    there_and_back = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 0.0], [1.0, 0.0]])
    straight = np.array([[0.0, 0.0], [1.0, 0.0]])
    assert discrete_frechet(there_and_back, straight) == pytest.approx(1.0)
    shifted = straight + np.array([0.0, 0.25])
    assert discrete_frechet(straight, shifted) == pytest.approx(0.25)


def test_held_out_distances_of_a_parallel_line_and_a_truncated_one():
    from lfdkit.emulate.metrics import held_out_distances

    x = np.linspace(0.0, 2.0, 50)
    demo = np.column_stack((x, np.zeros_like(x)))
    parallel = held_out_distances(demo + np.array([0.0, 0.1]), demo)
    assert parallel["mean"] == pytest.approx(0.1)
    assert parallel["max"] == pytest.approx(0.1)
    assert parallel["frechet"] == pytest.approx(0.1)
    # Cut at half length: the demonstration's second half is up to 1 away.
    half = held_out_distances(demo[:25], demo)
    assert half["max"] == pytest.approx(2.0 - x[24], rel=1e-9)
    # Half of the mean over x in [0, 2] of max(x - 0.98, 0), the reverse direction 0.
    assert half["mean"] == pytest.approx(0.5 * (2.0 - x[24]) ** 2 / 4.0, rel=0.02)
    assert half["frechet"] >= half["max"] - 1e-12


@pytest.mark.parametrize(
    ("path", "demo", "message"),
    [
        (np.zeros((5, 2)), np.eye(2), "path: has zero length"),
        (np.eye(2), np.ones((4, 3)), "demo"),
        (np.array([[0.0, np.nan], [1.0, 1.0]]), np.eye(2), "path"),
    ],
)
def test_held_out_distances_refuses_bad_input(path, demo, message):
    from lfdkit.emulate.metrics import held_out_distances

    with pytest.raises(ValueError, match=message):
        held_out_distances(path, demo)


def test_the_spread_of_demonstrations_is_their_sample_variance_about_the_path() -> None:
    from lfdkit.emulate.metrics import demonstration_spread

    # Two straight demonstrations 3 mm either side of the path: each 9e-6 m² from it,
    # and the path is their mean, so the sample variance is twice that (n / (n - 1) = 2).
    x = np.linspace(0.0, 1.0, 50)
    path = np.column_stack([x, np.zeros(50)])
    demos = [np.column_stack([x, np.full(50, s * 0.003)]) for s in (-1.0, 1.0)]
    assert demonstration_spread(path, demos, 100) == pytest.approx(2.0 * 0.003**2, rel=1e-12)
    # Three: offsets -3, 0, +3 mm, mean square 6e-6, times 3/2.
    demos.append(path.copy())
    assert demonstration_spread(path, demos, 100) == pytest.approx(9e-6, rel=1e-12)
    with pytest.raises(ValueError, match="demos"):
        demonstration_spread(path, demos[:1])
