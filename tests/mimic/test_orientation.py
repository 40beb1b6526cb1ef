"""Reversed and multi-motion demonstrations, handled alike by every mimicking method."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lfdkit.core.geometry import path_length
from lfdkit.mimic import (
    GMR,
    NLPCA,
    DemoOrientationWarning,
    MeanPath,
    SeveralMotionsError,
    check_one_motion,
    orient_demos,
    pointwise_average,
)


def arc_demos(n_demos=6, n=80, noise=0.01, scale=1.0, seed=0):
    """Noisy quarter circles from (scale, 0) to (0, scale), each with its own sampling."""
    rng = np.random.default_rng(seed)
    demos = []
    for _ in range(n_demos):
        th = np.sort(rng.uniform(0.0, np.pi / 2, n + int(rng.integers(0, 30))))
        th[0], th[-1] = 0.0, np.pi / 2
        demo = scale * (np.c_[np.cos(th), np.sin(th)] + rng.normal(0, noise, (len(th), 2)))
        demos.append(demo)
    return demos


def flip(demos, which):
    return [d[::-1].copy() if j in which else d for j, d in enumerate(demos)]


def fit_path(method, demos):
    """The generalized path of each method, ``(path, reversed mask or None)``."""
    if method == "mean_path":
        model = MeanPath(n_points=60).fit(demos)
        return model.path_, model.reversed_
    if method == "gmr":
        model = GMR(n_components=5, random_state=0).fit(demos)
        return model.path(60), model.reversed_
    if method == "nlpca":
        model = NLPCA(n_restarts=1, n_points=60, random_state=0).fit(demos)
        return model.path_, model.reversed_
    return pointwise_average(demos, 60), None


METHODS = ["mean_path", "gmr", "nlpca", "pointwise"]


# ------------------------------------------------------------- partly reversed
@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize(("scale", "reversed_ones"), [(1.0, (1, 4)), (250.0, (0, 2))])
def test_partly_reversed_demos_give_the_forward_path(method, scale, reversed_ones):
    demos = arc_demos(scale=scale, noise=0.02, seed=3)
    forward, _ = fit_path(method, demos)
    with pytest.warns(DemoOrientationWarning, match="reversed demonstration") as record:
        path, mask = fit_path(method, flip(demos, reversed_ones))
    assert ", ".join(map(str, reversed_ones)) in str(record[0].message)
    if mask is not None:
        np.testing.assert_array_equal(mask, np.isin(np.arange(len(demos)), reversed_ones))
    # Runs from (scale, 0) to (0, scale), like most demonstrations, and is the forward path.
    np.testing.assert_allclose(path[0], [scale, 0.0], atol=0.08 * scale)
    np.testing.assert_allclose(path[-1], [0.0, scale], atol=0.08 * scale)
    np.testing.assert_allclose(path, forward, atol=0.02 * scale)


def test_gmr_on_partly_reversed_demos_is_not_a_stub():
    # The case: GMR learned a path from (0.486, 0) to (0.483, 0).
    x = np.linspace(0.0, 0.97, 50)
    demos = [np.c_[x, 0.1 * np.sin(np.pi * x / 0.97) + 0.003 * k] for k in range(4)]
    model = GMR(n_components=4, random_state=0).fit(flip(demos, (1, 3)))
    path = model.path(50)
    assert path_length(path) == pytest.approx(path_length(demos[0]), rel=0.05)
    np.testing.assert_allclose(path[0], [0.0, 0.0045], atol=0.01)


def test_gmr_with_explicit_times_trusts_them():
    demos = arc_demos(n_demos=3)
    # The times run backwards along demonstration 1: it is the same motion as the others.
    times = [np.linspace(0, 1, len(d)) for d in demos]
    times[1] = times[1][::-1].copy()
    with warnings.catch_warnings():
        warnings.simplefilter("error", DemoOrientationWarning)
        model = GMR(n_components=4, random_state=0).fit(demos, times=times)
    assert not model.reversed_.any()


def test_orient_as_given_trusts_the_demonstrations():
    demos = flip(arc_demos(), (2,))
    with warnings.catch_warnings():
        warnings.simplefilter("error", DemoOrientationWarning)
        assert not GMR(n_components=4, random_state=0, orient="as_given").fit(demos).reversed_.any()
        assert not NLPCA(n_restarts=1, random_state=0, orient="as_given").fit(demos).reversed_.any()
        pointwise_average(demos, orient="as_given")


@pytest.mark.parametrize("n_demos", [4, 7, 15])
def test_tie_keeps_demonstration_zero_and_many_demos_use_the_spectral_split(n_demos):
    demos = arc_demos(n_demos=n_demos, seed=n_demos)
    half = tuple(range(n_demos // 2, n_demos)) if n_demos % 2 == 0 else (1, 2)
    with pytest.warns(DemoOrientationWarning):
        _, mask = orient_demos(flip(demos, half))
    np.testing.assert_array_equal(mask, np.isin(np.arange(n_demos), half))


# ------------------------------------------------------------- closed paths
def circle_demos(n_demos=5, noise=0.01, seed=0):
    """Handwritten "o"s: start and end (almost) at the same point, random start angle."""
    rng = np.random.default_rng(seed)
    demos = []
    for _ in range(n_demos):
        start = rng.uniform(-0.3, 0.3)
        th = start + np.linspace(0.0, 2 * np.pi * rng.uniform(0.95, 1.02), 120)
        demos.append(np.c_[np.cos(th), np.sin(th)] + rng.normal(0, noise, (120, 2)))
    return demos


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_closed_demonstrations_are_oriented_not_refused(seed):
    demos = circle_demos(seed=seed)
    with warnings.catch_warnings():
        warnings.simplefilter("error", DemoOrientationWarning)
        _, mask = orient_demos(demos)
    assert not mask.any()
    with pytest.warns(DemoOrientationWarning):
        oriented, mask = orient_demos(flip(demos, (3,)))
    np.testing.assert_array_equal(mask, [False, False, False, True, False])
    np.testing.assert_array_equal(oriented[3], demos[3])
    # The average of the oriented "o"s is an "o" again, not a stub.
    average = pointwise_average(flip(demos, (1,)), 100)
    assert path_length(average) > 0.9 * 2 * np.pi


# ------------------------------------------------------------- refusals
def test_there_and_back_demonstration_is_refused_by_name():
    demos = arc_demos(n_demos=3)
    there_and_back = np.vstack([demos[1], demos[1][::-1]])
    with pytest.raises(ValueError, match=r"demos\[1\]: its direction cannot be decided"):
        orient_demos([demos[0], there_and_back, demos[2]])


def two_motions(n_each=3, noise=0.01, seed=0):
    """Curves into the goal (0, 0) from the left and from the right, bulging upwards."""
    rng = np.random.default_rng(seed)
    u = np.linspace(0.0, 1.0, 90)
    demos = []
    for side in (-1.0, 1.0):
        for _ in range(n_each):
            curve = np.c_[side * (1.0 - u), 0.4 * np.sin(np.pi * u)]
            demos.append(curve + rng.normal(0, noise, curve.shape))
    return demos


def four_directions(noise=0.01, seed=0):
    """Like LASA's Multi_Models: straight into the origin from four sides, two demos each."""
    rng = np.random.default_rng(seed)
    u = np.linspace(0.0, 1.0, 70)[:, None]
    starts = [(-40.0, 0.0), (0.0, 40.0), (40.0, 0.0), (0.0, -40.0)]
    return [
        np.asarray(s) * (1.0 - u) + rng.normal(0, noise * 40, (70, 2))
        for s in starts
        for _ in (0, 1)
    ]


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("make", [two_motions, four_directions])
def test_several_motions_are_refused_by_every_method(method, make):
    with pytest.raises(SeveralMotionsError, match="several motions"):
        fit_path(method, make())


def test_short_path_error_names_both_lengths():
    demo = np.c_[np.linspace(0, 10, 11), np.zeros(11)]
    stub = np.c_[np.linspace(0, 2.9, 5), np.zeros(5)]
    with pytest.raises(SeveralMotionsError, match=r"2\.9 long, 0\.29 times .* length 10"):
        check_one_motion(stub, [demo, demo + 1], "test")
    check_one_motion(np.c_[np.linspace(0, 3.0, 5), np.zeros(5)], [demo, demo + 1])


def test_dense_noisy_demonstrations_are_not_taken_for_several_motions():
    # 2000 samples with 1 % noise: the raw polyline is ~20 times longer than the motion.
    demos = arc_demos(n_demos=4, n=2000, noise=0.01, seed=5)
    assert path_length(demos[0]) > 10 * np.pi / 2
    path = pointwise_average(demos, 100)
    assert path_length(path) < 5 * np.pi / 2
    gmr = GMR(n_components=6, random_state=0).fit(demos)
    assert not gmr.reversed_.any()


def test_stationary_demonstrations_have_no_direction():
    demos = [np.ones((10, 2)), np.ones((12, 2))]
    oriented, mask = orient_demos(demos)
    assert not mask.any()
    assert oriented[0] is demos[0]


# ------------------------------------------------------------- property
@settings(max_examples=25, deadline=None)
@given(
    seed=st.integers(0, 10_000),
    n_demos=st.integers(2, 9),
    noise=st.sampled_from([0.0, 0.005, 0.03]),
    scale=st.sampled_from([1e-3, 1.0, 1e3]),
    data=st.data(),
)
def test_orientation_recovers_the_minority(seed, n_demos, noise, scale, data):
    rng = np.random.default_rng(seed)
    # A random smooth open curve: a cubic Bezier with well separated ends.
    control = rng.uniform(-1, 1, (4, 2))
    control[3] = control[0] + rng.uniform(1.0, 2.0) * np.array([1.0, 0.0])
    u = np.linspace(0, 1, 60)[:, None]
    basis = np.hstack([(1 - u) ** 3, 3 * u * (1 - u) ** 2, 3 * u**2 * (1 - u), u**3])
    curve = basis @ control
    demos = [scale * (curve + rng.normal(0, noise, curve.shape)) for _ in range(n_demos)]
    flipped = data.draw(st.sets(st.integers(0, n_demos - 1)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DemoOrientationWarning)
        oriented, mask = orient_demos(flip(demos, flipped))
    expected = np.isin(np.arange(n_demos), sorted(flipped))
    if 2 * len(flipped) > n_demos or (2 * len(flipped) == n_demos and 0 in flipped):
        expected = ~expected
    np.testing.assert_array_equal(mask, expected)
    # All now run one way: the forward demos, or all reversed together.
    direction = oriented[0][-1] - oriented[0][0]
    assert all(np.dot(d[-1] - d[0], direction) > 0 for d in oriented)


def test_compiled_pair_distances_equal_numpys_bit_for_bit():
    # The compiled all-pairs loop reproduces _mean_distances (x² + y², NumPy's pairwise
    # sum of the distances: one block of eight accumulators up to 128 samples) to the bit.
    from lfdkit.mimic._mean_path_kernels import pair_distances
    from lfdkit.mimic.orientation import _mean_distances

    rng = np.random.default_rng(5)
    for s in (1, 5, 8, 9, 17, 64, 127, 128):
        m = int(rng.integers(2, 25))
        stack = rng.normal(size=(m, s, 2)) * 10.0 ** rng.integers(-3, 4)
        got_fwd, got_bwd = np.zeros((m, m)), np.zeros((m, m))
        pair_distances(stack, got_fwd, got_bwd)
        for a in range(m - 1):
            assert np.array_equal(got_fwd[a, a + 1 :], _mean_distances(stack[a], stack[a + 1 :]))
            want = _mean_distances(stack[a], stack[a + 1 :, ::-1])
            assert np.array_equal(got_bwd[a, a + 1 :], want), s
