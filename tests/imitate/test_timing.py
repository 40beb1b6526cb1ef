"""Tests for lfdkit.imitate.timing: speed laws, learning them from timed demonstrations,
timing a path, files, and the DMP trained with a learned speed profile."""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.core.geometry import arc_length, path_length, resample
from lfdkit.imitate import DMP, SpeedProfile, learn_timing, path_progress
from lfdkit.imitate.timing import MAX_COEFFICIENTS

# A known, lopsided speed profile: quick start, long slow finish (not minimum jerk).
TRUE_SPEED = np.array([0, 0, 2.0, 6.0, 8.0, 7.0, 5.0, 4.0, 3.0, 2.5, 2.0, 1.5, 1.0, 0.5, 0, 0])
PHASES = np.linspace(0.0, 1.0, 1001)


def wave(n: int = 2000) -> np.ndarray:
    """A smooth open path, 1 unit wide, in metres."""
    x = np.linspace(0.0, 1.0, n)
    return np.c_[x, 0.15 * np.sin(2.0 * np.pi * x)]


def along(path: np.ndarray, fraction: np.ndarray) -> np.ndarray:
    """Points at the given arc-length fractions of a dense path."""
    s = arc_length(path) / path_length(path)
    return np.column_stack([np.interp(fraction, s, path[:, k]) for k in range(path.shape[1])])


def timed_demos(
    profile: SpeedProfile,
    durations: list[float],
    *,
    n_samples: int = 150,
    noise: float = 0.0,
    jitter: float = 0.0,
    seed: int = 0,
) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Demonstrations that run along :func:`wave` with ``profile``'s law, one per duration.

    ``noise``: Gaussian position noise (m); ``jitter``: Gaussian time-stamp noise
    (s), recorded as the stamps while the positions are where the law says at
    the true times (a clock that misreports).
    """
    rng = np.random.default_rng(seed)
    path = wave()
    demos, stamps = [], []
    for duration in durations:
        t = np.linspace(0.0, duration, n_samples)
        demos.append(along(path, profile.progress(t / duration)))
        demos[-1] = demos[-1] + rng.normal(0.0, noise, demos[-1].shape)
        recorded = t + rng.normal(0.0, jitter, t.shape) if jitter else t
        stamps.append(np.maximum.accumulate(recorded) + 1e-9 * np.arange(n_samples))
    return demos, stamps


# ------------------------------------------------------------------ laws
def test_minimum_jerk_and_uniform_laws_are_exact() -> None:
    u = PHASES
    jerk = SpeedProfile.minimum_jerk(2.5)
    np.testing.assert_allclose(jerk.progress(u), 10 * u**3 - 15 * u**4 + 6 * u**5, atol=1e-14)
    np.testing.assert_allclose(jerk.speed(u), 30 * u**2 * (1 - u) ** 2, atol=1e-13)
    _, _, bend = jerk.law(u)
    np.testing.assert_allclose(bend, 60 * u * (1 - u) * (1 - 2 * u), atol=1e-12)
    assert jerk.peak_speed == pytest.approx(1.875, abs=1e-12)
    assert jerk.duration == 2.5 and jerk.source == "minimum_jerk"
    flat = SpeedProfile.uniform(3.0)
    np.testing.assert_allclose(flat.progress(u), u, atol=1e-14)
    np.testing.assert_allclose(flat.speed(u), 1.0, atol=1e-14)
    # Outside the movement: clipped, at the ends.
    assert jerk.progress(-1.0) == 0.0 and jerk.progress(2.0) == 1.0


def test_phase_inverts_progress_and_the_scale_of_coefficients_does_not_matter() -> None:
    profile = SpeedProfile(1.0, TRUE_SPEED)
    scaled = SpeedProfile(1.0, 7.0 * TRUE_SPEED)
    np.testing.assert_allclose(profile.phase(profile.progress(PHASES)), PHASES, atol=1e-12)
    np.testing.assert_allclose(scaled.speed(PHASES), profile.speed(PHASES), rtol=1e-12)
    # ν averages 1: σ(1) = 1.
    assert profile.progress(1.0) == pytest.approx(1.0, abs=1e-14)
    assert np.trapezoid(profile.speed(PHASES), PHASES) == pytest.approx(1.0, abs=1e-6)


def test_time_path_runs_the_law_along_the_arc_length_in_seconds() -> None:
    path = resample(wave(), 200)
    length = path_length(path)
    profile = SpeedProfile(4.0, TRUE_SPEED)
    times, velocities = profile.time_path(path)
    assert times[0] == 0.0 and times[-1] == pytest.approx(4.0, abs=1e-12)
    assert np.all(np.diff(times) > 0)
    speeds = np.linalg.norm(velocities, axis=1)
    # Speed along the path L ν(t/T) / T, at rest at the ends.
    np.testing.assert_allclose(speeds, length * profile.speed(times / 4.0) / 4.0, rtol=1e-12)
    assert speeds[0] == 0.0 and speeds[-1] == 0.0
    # Distance covered = path length; finite differences agree with the velocities.
    assert np.trapezoid(speeds, times) == pytest.approx(length, rel=5e-3)
    steps = np.diff(path, axis=0) / np.diff(times)[:, None]
    middle = 0.5 * (velocities[1:] + velocities[:-1])
    # (but in the first and last step, where the speed rises from 0 as t²)
    assert np.max(np.abs(steps - middle)[1:-1]) < 0.01 * speeds.max()
    # Directions are the path's tangents.
    chords = np.gradient(path, axis=0)
    cosines = (
        np.einsum("ij,ij->i", chords, velocities)[1:-1]
        / (np.linalg.norm(chords, axis=1) * speeds)[1:-1]
    )
    assert np.min(cosines) > 0.999
    # Another duration scales times up and speeds down.
    slow_times, slow_velocities = profile.time_path(path, duration=8.0)
    np.testing.assert_allclose(slow_times, 2.0 * times, rtol=1e-12)
    np.testing.assert_allclose(slow_velocities, 0.5 * velocities, rtol=1e-12, atol=1e-15)


def test_to_dict_round_trips_exactly_and_bad_fields_are_named() -> None:
    profile = SpeedProfile(3.25, TRUE_SPEED / 7.0, "demonstrations", (3.0, 3.5))
    again = SpeedProfile.from_dict(profile.to_dict())
    assert again == profile
    assert again.coefficients.tobytes() == profile.coefficients.tobytes()
    bad = {
        "duration": (-1.0, "timing.duration: must be > 0"),
        "speed": ([0, 0, -1.0, 0, 0], "timing.speed: expected non-negative"),
        "source": ("magic", "timing.source: expected one of"),
    }
    for key, (value, message) in bad.items():
        doc = profile.to_dict() | {key: value}
        with pytest.raises(ValueError, match=message):
            SpeedProfile.from_dict(doc)
    with pytest.raises(ValueError, match=r"timing\.speed: expected a list of numbers"):
        SpeedProfile.from_dict(profile.to_dict() | {"speed": ["a"]})
    with pytest.raises(ValueError, match=r"timing\.duration: missing field"):
        SpeedProfile.from_dict({"source": "given", "speed": [1, 1, 1, 1, 1]})


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"duration": 0.0}, "duration: must be > 0"),
        ({"duration": float("nan")}, "duration: must be finite"),
        ({"duration": 1e12}, "duration: expected 1e-06 to 1e\\+09 s"),
        ({"coefficients": [1.0, 1.0]}, "coefficients: expected a 1-D array of 5 to"),
        ({"coefficients": np.ones(MAX_COEFFICIENTS + 1)}, "coefficients: expected a 1-D"),
        ({"coefficients": [0.0] * 5}, "not all zero"),
        ({"coefficients": [1.0, np.nan, 1.0, 1.0, 1.0]}, "coefficients: contains NaN"),
    ],
)
def test_bad_profiles_are_refused_naming_the_argument(kwargs, message) -> None:
    args = {"duration": 1.0, "coefficients": np.ones(5)} | kwargs
    with pytest.raises(ValueError, match=message):
        SpeedProfile(**args)


# ------------------------------------------------------------------ learning
def test_timing_of_clean_demonstrations_is_recovered() -> None:
    truth = SpeedProfile(1.0, TRUE_SPEED)
    demos, times = timed_demos(truth, [3.0, 3.4, 3.8, 4.2, 4.6])
    learned = learn_timing(demos, times, resample(wave(), 100))
    assert learned.source == "demonstrations"
    assert learned.duration == pytest.approx(3.8, abs=1e-6)  # the median
    assert learned.demo_durations == pytest.approx((3.0, 3.4, 3.8, 4.2, 4.6))
    error = np.max(np.abs(learned.speed(PHASES) - truth.speed(PHASES)))
    assert error < 0.02 * truth.peak_speed
    assert np.max(np.abs(learned.progress(PHASES) - truth.progress(PHASES))) < 2e-3
    # At rest at both ends, with zero acceleration along the path.
    _, slope, bend = learned.law(np.array([0.0, 1.0]))
    np.testing.assert_allclose(slope, 0.0, atol=1e-12)
    np.testing.assert_allclose(bend, 0.0, atol=1e-10)


def test_timing_is_robust_to_noisy_positions_time_stamps_and_an_outlier() -> None:
    truth = SpeedProfile(1.0, TRUE_SPEED)
    durations = [3.0, 3.4, 3.8, 4.2, 4.6, 5.0, 5.4]
    demos, times = timed_demos(truth, durations, noise=0.003, jitter=0.004, seed=1)
    # One demonstrator ran at constant speed: the median ignores it.
    outlier, outlier_times = timed_demos(SpeedProfile.uniform(), [20.0], noise=0.003, seed=2)
    learned = learn_timing(demos + outlier, times + outlier_times, resample(wave(), 100))
    assert learned.duration == pytest.approx(4.4, abs=0.02)
    error = np.max(np.abs(learned.speed(PHASES) - truth.speed(PHASES)))
    assert error < 0.06 * truth.peak_speed
    # The demonstrations' own (noisy) arc length would be far off: the path matters.
    own = [learn_timing([d], [t], d).speed(PHASES) for d, t in zip(demos, times, strict=True)]
    assert np.max(np.abs(np.median(own, axis=0) - truth.speed(PHASES))) > 2 * error


def test_minimum_jerk_demonstrations_give_the_minimum_jerk_law() -> None:
    jerk = SpeedProfile.minimum_jerk()
    demos, times = timed_demos(jerk, [2.0, 2.0, 2.0], n_samples=400)
    learned = learn_timing(demos, times, resample(wave(), 100))
    assert np.max(np.abs(learned.speed(PHASES) - jerk.speed(PHASES))) < 0.01
    assert learned.peak_speed == pytest.approx(1.875, rel=0.01)


def test_path_progress_follows_a_loop_in_order() -> None:
    # A circle travelled once (start = end): the nearest point is ambiguous at the
    # seam, the monotone matching is not.
    angle = np.linspace(0.0, 2.0 * np.pi, 400)
    circle = np.c_[np.cos(angle), np.sin(angle)]
    path = resample(circle, 60)
    rng = np.random.default_rng(0)
    demo = circle + rng.normal(0.0, 0.01, circle.shape)
    progress = path_progress(demo, path)
    assert np.all(np.diff(progress) >= 0)
    np.testing.assert_allclose(progress, angle / (2 * np.pi), atol=0.02)
    # Along itself, the progress is the arc-length fraction.
    np.testing.assert_allclose(
        path_progress(path, path), arc_length(path) / path_length(path), atol=1e-12
    )


def test_learning_refuses_bad_times_naming_them() -> None:
    demos, times = timed_demos(SpeedProfile.minimum_jerk(), [2.0, 2.5])
    path = resample(wave(), 100)
    nan = [times[0].copy(), times[1]]
    nan[0][5] = np.nan
    with pytest.raises(ValueError, match=r"times\[0\]: contains NaN"):
        learn_timing(demos, nan, path)
    backwards = [times[0], times[1][::-1]]
    with pytest.raises(ValueError, match=r"times\[1\]: must increase strictly"):
        learn_timing(demos, backwards, path)
    with pytest.raises(ValueError, match=r"times\[1\]: expected shape \(150,\)"):
        learn_timing(demos, [times[0], times[1][:-1]], path)
    with pytest.raises(ValueError, match="times: got 1 entries for 2 demonstrations"):
        learn_timing(demos, times[:1], path)
    with pytest.raises(ValueError, match=r"demos: demos\[0\] covers \d+% of the path"):
        learn_timing([demos[0][:40]], [times[0][:40]], path)
    # A partial demonstration among others is left out, with a warning.
    with pytest.warns(UserWarning, match=r"timing: left out demos\[1\] covers \d+%"):
        learned = learn_timing([demos[0], demos[1][:40]], [times[0], times[1][:40]], path)
    assert learned.demo_durations == pytest.approx((2.0,))
    with pytest.raises(ValueError, match="n_coefficients: expected 6 to 200"):
        learn_timing(demos, times, path, n_coefficients=5)


# ------------------------------------------------------------------ the DMP
def test_dmp_with_the_minimum_jerk_profile_equals_the_named_law() -> None:
    path = resample(wave(), 100)
    named = DMP(n_basis=20).fit(path, timing="minimum_jerk", duration=2.0)
    profiled = DMP(n_basis=20).fit(path, timing=SpeedProfile.minimum_jerk(2.0))
    np.testing.assert_allclose(profiled.weights_, named.weights_, rtol=0, atol=1e-9)
    np.testing.assert_allclose(profiled.times_, named.times_, atol=1e-12)
    assert named.timing_ == SpeedProfile.minimum_jerk(2.0)
    assert DMP(n_basis=20).fit(path, times=named.times_).timing_ is None


def test_dmp_rollouts_follow_a_learned_speed_profile_and_duration() -> None:
    truth = SpeedProfile(1.0, TRUE_SPEED)
    demos, times = timed_demos(truth, [4.0, 4.5, 5.0])
    path = resample(wave(), 100)
    learned = learn_timing(demos, times, path)
    # Within 0.05 % of the peak speed from the demonstrations, 0.24 % through 40 basis
    # functions (15, what n_basis="auto" takes for 1 % in position: 6 %).
    assert np.max(np.abs(learned.speed(PHASES) - truth.speed(PHASES))) < 1e-3 * 1.875
    dmp = DMP(n_basis=40, scaling="translate").fit(path, timing=learned)
    assert dmp.duration_ == pytest.approx(4.5)
    run = dmp.rollout(n_steps=1000)
    assert run.times[-1] == pytest.approx(4.5)
    speeds = np.linalg.norm(run.velocities, axis=1)
    expected = path_length(path) * truth.speed(run.times / 4.5) / 4.5
    assert np.max(np.abs(speeds - expected)) < 0.01 * expected.max()
    # Twice as slow with tau = 2: same profile over twice the time.
    slow = dmp.rollout(tau=2.0, n_steps=1000)
    np.testing.assert_allclose(slow.positions, run.positions, atol=1e-9)
    np.testing.assert_allclose(2.0 * slow.velocities, run.velocities, atol=1e-9)
    with pytest.raises(ValueError, match="timing: expected one of"):
        DMP().fit(path, timing="learned")


@pytest.mark.parametrize("n_coefficients", [5, 9, 40, 200])
def test_the_numpy_splines_agree_with_scipy(n_coefficients: int) -> None:
    """Issue 30: the speed law and the plan's tangents without scipy.interpolate, to rounding."""
    from scipy.interpolate import BSpline, make_interp_spline

    from lfdkit.imitate.timing import DEGREE, _interpolant_slopes, _knots

    rng = np.random.default_rng(n_coefficients)
    coefficients = rng.uniform(0.0, 3.0, n_coefficients)
    profile = SpeedProfile(2.0, coefficients)
    speed = BSpline(_knots(n_coefficients), coefficients, DEGREE)
    progress = speed.antiderivative()
    u = np.r_[0.0, np.sort(rng.uniform(0.0, 1.0, 500)), 1.0]
    total = progress(1.0)
    for ours, theirs in zip(
        profile.law(u),
        (progress(u) / total, speed(u) / total, speed.derivative()(u) / total),
        strict=True,
    ):
        np.testing.assert_allclose(ours, theirs, rtol=0, atol=1e-13 * np.abs(theirs).max())
    for n in (2, 3, 4, 7, 60):
        x = np.r_[0.0, np.sort(rng.uniform(0.05, 0.95, n - 2)), 1.0]
        y = rng.normal(size=(n, 3)).cumsum(axis=0)
        expected = make_interp_spline(x, y, k=min(3, n - 1), axis=0)(x, 1)
        np.testing.assert_allclose(
            _interpolant_slopes(x, y), expected, rtol=0, atol=1e-12 * np.abs(expected).max()
        )


def _thomas_on_rows(below, diagonal, above, rhs):
    """The tridiagonal elimination on NumPy rows (the solver's earlier form)."""
    n = diagonal.size
    pivot, y = np.empty(n), np.empty(rhs.shape)
    pivot[0], y[0] = diagonal[0], rhs[0]
    for i in range(1, n):
        factor = below[i - 1] / pivot[i - 1]
        pivot[i] = diagonal[i] - factor * above[i - 1]
        y[i] = rhs[i] - factor * y[i - 1]
    x = np.empty(rhs.shape)
    x[-1] = y[-1] / pivot[-1]
    for i in range(n - 2, -1, -1):
        x[i] = (y[i] - above[i] * x[i + 1]) / pivot[i]
    return x


@pytest.mark.parametrize("n", [2, 5, 100, 250])
def test_the_tridiagonal_solve_on_floats_is_the_row_elimination_bit_for_bit(n: int) -> None:
    """The plan's tangents' solver on Python floats: the same numbers as on NumPy rows."""
    from scipy.linalg import solve_banded

    from lfdkit.imitate.timing import _solve_tridiagonal

    rng = np.random.default_rng(n)
    diagonal = rng.uniform(2.0, 4.0, n)
    below, above = rng.uniform(-1.0, 1.0, n - 1), rng.uniform(-1.0, 1.0, n - 1)
    for q in (1, 2, 3):
        rhs = rng.normal(size=(n, q))
        x = _solve_tridiagonal(below, diagonal, above, rhs)
        assert x.shape == (n, q) and x.flags.c_contiguous
        np.testing.assert_array_equal(x, _thomas_on_rows(below, diagonal, above, rhs))
        bands = np.zeros((3, n))
        bands[0, 1:], bands[1], bands[2, :-1] = above, diagonal, below
        np.testing.assert_allclose(x, solve_banded((1, 1), bands, rhs), rtol=0, atol=1e-12)
