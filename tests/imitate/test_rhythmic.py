"""Rhythmic DMPs: closed-form periodic movements and rotations reproduced, period kept.

Known answers: a two-harmonic 2-D cycle and a periodic rotation ``exp(a sin Ωt
n₁ + b sin(2Ωt + 0.5) n₂) ⊗ g``, sampled unevenly over 4.4 cycles with noise
(and random quaternion signs); the learned rhythm must give them back, with
amplitude, frequency and centre acting as their closed forms say, unit
quaternions, continuity, and a smooth start and stop at rest.
"""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.core.rotations import angle_between, conjugate, exp, log, multiply
from lfdkit.imitate import QuaternionRhythmicDMP, RhythmicDMP, RhythmicPoseDMP, estimate_period

PERIOD = 1.7
OMEGA = 2.0 * np.pi / PERIOD
STEP = PERIOD / 100  # tests' integration step (the default is a 400th)


def cycle(t: np.ndarray, centre=(0.3, -0.1), scale: float = 1.0) -> np.ndarray:
    """Two dimensions, two harmonics, in metres."""
    u = OMEGA * np.asarray(t)
    wave = np.c_[0.2 * np.sin(u), 0.05 * np.cos(2 * u + 0.3) + 0.08 * np.sin(u)]
    return np.asarray(centre) + scale * wave


def rotation_vectors(t: np.ndarray) -> np.ndarray:
    """Half-angle vectors of the periodic rotation about its centre (two axes, two harmonics)."""
    u = OMEGA * np.asarray(t)
    return np.outer(0.3 * np.sin(u), [0.0, 0.0, 1.0]) + np.outer(
        0.12 * np.sin(2 * u + 0.5), [0.6, 0.8, 0.0]
    )


CENTRE_Q = exp(np.array([0.2, -0.1, 0.4]))


def uneven_times(seed: int, cycles: float = 4.4, n: int = 700) -> np.ndarray:
    rng = np.random.default_rng(seed)
    t = np.sort(rng.uniform(0.0, cycles * PERIOD, n))
    t[0] = 0.0
    return t


@pytest.fixture(scope="module")
def position_data():
    t = uneven_times(0)
    noise = np.random.default_rng(1).normal(0.0, 2e-3, (len(t), 2))
    return t, cycle(t) + noise


@pytest.fixture(scope="module")
def orientation_data():
    t = uneven_times(2)
    rng = np.random.default_rng(3)
    jitter = exp(rng.normal(0.0, 5e-4, (len(t), 3)))  # 1 mrad of sensor noise
    q = multiply(multiply(exp(rotation_vectors(t)), CENTRE_Q), jitter)
    q[rng.random(len(t)) < 0.3] *= -1.0  # q and −q: the same orientation
    return t, q


def test_the_period_is_learned_from_noisy_uneven_samples(position_data) -> None:
    t, y = position_data
    assert estimate_period(y, t) == pytest.approx(PERIOD, rel=1e-3)
    # A second harmonic stronger than the first must not halve the period.
    strong = np.c_[0.05 * np.sin(OMEGA * t), 0.3 * np.sin(2 * OMEGA * t)]
    assert estimate_period(strong, t) == pytest.approx(PERIOD, rel=1e-3)
    # Another period, in other units (mm), evenly sampled.
    s = np.linspace(0.0, 12.0, 1200)
    assert estimate_period(np.c_[250.0 * np.cos(2 * np.pi * s / 3.1)], s) == pytest.approx(
        3.1, rel=1e-3
    )


def test_the_rollout_reproduces_the_demonstrated_cycle(position_data) -> None:
    t, y = position_data
    dmp = RhythmicDMP(period=PERIOD).fit(y, t)
    assert dmp.residual_rms_ == pytest.approx(2e-3 * np.sqrt(2), rel=0.15)  # the noise
    np.testing.assert_allclose(dmp.centre_, [0.3, -0.1], atol=1e-3)
    run = dmp.rollout(3 * PERIOD, STEP)
    assert run.times[-1] == pytest.approx(3 * PERIOD)
    # Within the noise's share of the fit (1.5 mm) on the 0.2 m cycle; the period kept.
    np.testing.assert_allclose(run.positions, cycle(run.times), atol=1.5e-3)
    np.testing.assert_allclose(run.positions[100:], run.positions[:-100], atol=2e-5)
    # Velocities: the closed form's derivative.
    u = OMEGA * run.times
    speed = np.c_[0.2 * np.cos(u), -0.1 * np.sin(2 * u + 0.3) + 0.08 * np.cos(u)] * OMEGA
    np.testing.assert_allclose(run.velocities, speed, atol=0.03 * np.abs(speed).max())


def test_amplitude_frequency_and_centre_act_as_their_closed_forms(position_data) -> None:
    t, y = position_data
    dmp = RhythmicDMP(period=PERIOD).fit(y, t)
    run = dmp.rollout(2 * PERIOD, STEP / 2, amplitude=1.5, frequency=2.0, centre=[-1.0, 2.0])
    # Twice as fast (four cycles), 1.5 times as wide, about the new centre.
    expected = cycle(2.0 * run.times, centre=(-1.0, 2.0), scale=1.5)
    np.testing.assert_allclose(run.positions, expected, atol=3e-3)


def test_a_smooth_start_and_stop_at_the_centre_at_rest(position_data) -> None:
    t, y = position_data
    dmp = RhythmicDMP(period=PERIOD).fit(y, t)
    run = dmp.rollout(5 * PERIOD, STEP, ramp=PERIOD)
    np.testing.assert_array_equal(run.positions[0], dmp.centre_)
    np.testing.assert_array_equal(run.velocities[0], [0.0, 0.0])
    np.testing.assert_allclose(run.positions[-1], dmp.centre_, atol=1e-9)
    np.testing.assert_allclose(run.velocities[-1], [0.0, 0.0], atol=1e-8)
    # No jerk at the start: the acceleration grows from 0 (velocity steps stay small).
    accelerations = np.diff(run.velocities, axis=0) / STEP
    steady = np.abs(accelerations[200:300]).max()
    assert np.abs(accelerations[:3]).max() < 0.01 * steady
    # Between the ramps it is the full cycle (phase kept from the start).
    middle = (run.times > 2.0 * PERIOD) & (run.times < 3.4 * PERIOD)
    np.testing.assert_allclose(run.positions[middle], cycle(run.times[middle]), atol=2e-3)


def test_a_frequency_changed_while_running_keeps_the_movement_continuous(position_data) -> None:
    t, y = position_data
    dmp = RhythmicDMP(period=PERIOD).fit(y, t)
    run = dmp.rollout(4 * PERIOD, STEP, frequency=lambda s: 1.0 if s < 2 * PERIOD else 1.25)
    steps = np.linalg.norm(np.diff(run.positions, axis=0), axis=1)
    jumps = np.linalg.norm(np.diff(run.velocities, axis=0), axis=1)
    fast = steps[-100:].max()
    assert steps.max() <= 1.05 * fast  # no jump: the largest step is a fast cycle's
    assert jumps.max() < 0.2 * np.abs(run.velocities).max()
    # After settling it runs the cycle at 1.25× the speed (a period is 80 steps).
    lag = round(PERIOD / 1.25 / STEP)
    np.testing.assert_allclose(run.positions[-50:], run.positions[-50 - lag : -lag], atol=4e-3)


def test_a_periodic_rotation_is_reproduced_unit_and_continuous(orientation_data) -> None:
    t, q = orientation_data
    dmp = QuaternionRhythmicDMP().fit(q, t)
    assert dmp.period_ == pytest.approx(PERIOD, rel=1e-3)
    assert dmp.residual_rms_ < 2e-3  # the sensor noise (1 mrad per axis)
    run = dmp.rollout(3 * PERIOD, STEP)
    truth = multiply(exp(rotation_vectors(run.times)), CENTRE_Q)
    # Within 2 mrad over 3 cycles (0.5 measured: 1 mrad noise; period found to 1e-5).
    assert angle_between(run.orientations, truth).max() < 2e-3
    np.testing.assert_allclose(np.linalg.norm(run.orientations, axis=1), 1.0, atol=1e-12)
    dots = np.sum(run.orientations[1:] * run.orientations[:-1], axis=1)
    assert dots.min() > 0.99  # continuous in sign and small steps
    # Period kept: the same orientation one learned period later.
    lag = round(dmp.period_ / STEP)
    assert angle_between(run.orientations[lag:], run.orientations[:-lag]).max() < 5e-3
    # positions: the rotation vector from the centre (angle·axis, rad).
    turned = 2.0 * log(multiply(run.orientations, conjugate(dmp.centre_)))
    np.testing.assert_allclose(run.positions, turned, atol=1e-9)


def test_a_rotation_at_another_amplitude_speed_and_centre(orientation_data) -> None:
    t, q = orientation_data
    dmp = QuaternionRhythmicDMP(period=PERIOD).fit(q, t)
    centre = exp(np.array([-0.5, 0.3, 0.1]))
    run = dmp.rollout(PERIOD, STEP / 2, amplitude=0.5, frequency=2.0, centre=centre)
    v = rotation_vectors(2.0 * run.times)
    # The learned centre is the cycle's own mean (within 0.2 mrad of CENTRE_Q): the swing
    # about it is exp(v) ⊗ CENTRE_Q ⊗ c̄, halved, and turned onto the new centre.
    about = log(multiply(multiply(exp(v), CENTRE_Q), conjugate(dmp.centre_)))
    expected = multiply(exp(0.5 * about), centre)
    assert angle_between(run.orientations, expected).max() < 4e-3
    # A smooth start from rest at a given orientation, ending at the centre.
    start = exp(np.array([0.1, 0.0, 0.0]))
    calm = dmp.rollout(4 * PERIOD, STEP, start=start, ramp=PERIOD)
    assert angle_between(calm.orientations[0], start) < 1e-12
    assert angle_between(calm.orientations[-1], dmp.centre_) < 1e-8
    np.testing.assert_allclose(calm.velocities[[0, -1]], 0.0, atol=1e-8)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda t, y: RhythmicDMP(period=3.0).fit(y, t), r"^demo: covers 1\.2 cycles"),
        (lambda t, y: RhythmicDMP(n_harmonics=50).fit(y, t), r"^n_harmonics: 50 needs"),
        (lambda t, y: RhythmicDMP(period=-1.0).fit(y, t), r"^period:"),
        (lambda t, y: estimate_period(np.ones((50, 2)), t[:50]), r"^demo: does not move"),
        (
            lambda t, y: RhythmicDMP(period=PERIOD).fit(y, t).rollout(1.0, frequency=0.0),
            r"^frequency:",
        ),
        (
            lambda t, y: (
                RhythmicDMP(period=PERIOD)
                .fit(y, t)
                .rollout(1.0, frequency=lambda s: 1.0 if s < 0.5 else -1.0)
            ),
            r"^frequency\(0\.5\d* s\): must be > 0, got -1",
        ),
        (
            lambda t, y: (
                RhythmicDMP(period=PERIOD)
                .fit(y, t)
                .rollout(1.0, centre=lambda s: [0.0, 0.0] if s < 0.5 else [0.0, np.nan])
            ),
            r"^centre\(0\.5\d* s\): ",
        ),
        (
            lambda t, y: RhythmicDMP(period=PERIOD).fit(y, t).rollout(1.0, ramp=0.6),
            r"^ramp: 0\.6 s, more than half",
        ),
        (
            lambda t, y: RhythmicDMP(period=PERIOD).fit(y, t).rollout(1.0, centre=[1.0]),
            r"^centre: expected a 2-D point, got shape \(1,\)",
        ),
    ],
)
def test_bad_input_is_one_line(call, message) -> None:
    t = np.linspace(0.0, 3.6, 181)
    y = cycle(t)
    with pytest.raises(ValueError, match=message) as info:
        call(t, y)
    assert "\n" not in str(info.value)


def test_an_orientation_turning_too_far_is_refused() -> None:
    t = np.linspace(0.0, 4 * PERIOD, 400)
    q = exp(np.outer(1.5 * np.sin(OMEGA * t), [0.0, 0.0, 1.0]))  # ±172°
    with pytest.raises(ValueError, match=r"^orientations: turn up to 1[78]\d° from their mean"):
        QuaternionRhythmicDMP(period=PERIOD).fit(q, t)


def test_a_pose_rhythm_keeps_position_and_orientation_in_step(position_data) -> None:
    t, y = position_data
    q = multiply(exp(rotation_vectors(t)), CENTRE_Q)
    pose = RhythmicPoseDMP().fit(y, q, t)
    assert pose.orientation_.period_ == pose.period_ == pose.position_.period_
    speed = lambda s: 1.0 if s < PERIOD else 1.25  # noqa: E731 - a schedule
    run = pose.rollout(2.5 * PERIOD, STEP, frequency=speed)
    alone = pose.orientation_.rollout(2.5 * PERIOD, STEP, frequency=speed)
    np.testing.assert_array_equal(run.orientations, alone.orientations)
    # In step: at the end (frequency changed on the way), the phase at which the learned
    # position cycle passes the position is the one at which the orientation cycle is.
    grid = np.linspace(0.0, 2 * np.pi, 20001)
    phase = grid[np.argmin(np.linalg.norm(pose.position_.cycle(grid) - run.positions[-1], axis=1))]
    assert angle_between(run.orientations[-1], pose.orientation_.cycle([phase])[0]) < 2e-3
    assert angle_between(run.orientations[-1], pose.orientation_.cycle([phase + 0.3])[0]) > 0.05
    with pytest.raises(ValueError, match=r"^orientations: "):
        RhythmicPoseDMP().fit(y, q[:-1], t)


def reference_rk4(dmp: RhythmicDMP, seconds: float, step: float, amp, freq, centre, start, ramp):
    """The rollout as first written (issue 33): RK4 in Python, one schedule call per stage."""
    k = np.arange(1, dmp.n_harmonics + 1)
    cos_part, sin_part = dmp._forcing_coefficients()
    alpha, omega0, lag = dmp.alpha, 2 * np.pi / dmp.period_, 4.0 / dmp.period_

    def envelope(t):
        if ramp <= 0:
            return 1.0

        def smooth(x):
            x = np.clip(x, 0.0, 1.0)
            return x**3 * (10 - 15 * x + 6 * x * x)

        return smooth(t / ramp) * smooth((seconds - 0.5 * ramp - t) / ramp)

    def derivative(t, y, z, phi, speed):
        forcing = cos_part.T @ np.cos(k * phi) + sin_part.T @ np.sin(k * phi)
        drive = alpha * alpha / 4 * (np.asarray(centre(t)) - y) - alpha * z
        w = omega0 * speed
        return w * z, w * (drive + amp(t) * envelope(t) * forcing), w, (freq(t) - speed) * lag

    n = int(np.ceil(seconds / step - 1e-9))
    times = np.minimum(np.arange(n + 1) * step, seconds)
    y, z = np.asarray(start, dtype=float), np.zeros(dmp.n_dims_)
    state, out = (y, z, 0.0, freq(0.0)), []
    for i in range(n + 1):
        out.append(state[0])
        if i == n:
            break
        t, h = times[i], times[i + 1] - times[i]
        k1 = derivative(t, *state)
        k2 = derivative(t + h / 2, *(x + h / 2 * dx for x, dx in zip(state, k1, strict=True)))
        k3 = derivative(t + h / 2, *(x + h / 2 * dx for x, dx in zip(state, k2, strict=True)))
        k4 = derivative(t + h, *(x + h * dx for x, dx in zip(state, k3, strict=True)))
        state = tuple(
            x + h / 6 * (a + 2 * b + 2 * c + e)
            for x, a, b, c, e in zip(state, k1, k2, k3, k4, strict=True)
        )
    return times, np.array(out)


def test_the_compiled_rollout_is_the_python_rk4_to_rounding(position_data) -> None:
    t, y = position_data
    dmp = RhythmicDMP(period=PERIOD).fit(y, t)
    amp = lambda s: 1.0 + 0.4 * np.sin(3.0 * s)  # noqa: E731 - schedules
    freq = lambda s: 1.0 if s < 0.5 * PERIOD else 1.6  # noqa: E731
    centre = lambda s: [0.3 + 0.1 * s, -0.1]  # noqa: E731
    start = [0.25, -0.05]
    seconds = 1.3 * PERIOD  # the last step is a short one
    run = dmp.rollout(
        seconds, STEP, amplitude=amp, frequency=freq, centre=centre, start=start, ramp=0.3
    )
    times, expected = reference_rk4(dmp, seconds, STEP, amp, freq, centre, start, 0.3)
    np.testing.assert_array_equal(run.times, times)
    # Rounding only (the harmonics' recurrence and the summation order): 1e-12 of 0.2 m.
    np.testing.assert_allclose(run.positions, expected, rtol=0, atol=2e-13)


def test_held_schedules_give_the_exact_solution(position_data) -> None:
    t, y = position_data
    dmp = RhythmicDMP(period=PERIOD).fit(y, t)
    held = dmp.rollout(2 * PERIOD, amplitude=1.5, frequency=2.0, centre=[-1.0, 2.0])
    # Closed form: c + r (y(φ) − a₀) at φ = Ω F t, and its derivative in time.
    phi = 2 * np.pi / PERIOD * 2.0 * held.times
    expected = np.array([-1.0, 2.0]) + 1.5 * (dmp.cycle(phi) - dmp.centre_)
    np.testing.assert_allclose(held.positions, expected, rtol=0, atol=1e-15)
    h = 1e-6
    rate = 1.5 * (dmp.cycle(phi + h) - dmp.cycle(phi - h)) / (2 * h) * (2 * np.pi / PERIOD * 2.0)
    np.testing.assert_allclose(held.velocities, rate, rtol=0, atol=1e-7)
    # Schedules given as functions of time take the RK4 path: within its error at the
    # default 400 steps a cycle: 5e-8 m measured, 2e-7 of the cycle's 0.3 m stroke.
    exact = dmp.rollout(2 * PERIOD, amplitude=1.5, centre=[-1.0, 2.0])
    integrated = dmp.rollout(2 * PERIOD, amplitude=lambda s: 1.5, centre=lambda s: [-1, 2])
    error = np.abs(integrated.positions - exact.positions).max()
    assert 1e-10 < error < 1e-7  # not zero: the two paths are different computations
    np.testing.assert_allclose(integrated.velocities, exact.velocities, rtol=0, atol=1e-5)
