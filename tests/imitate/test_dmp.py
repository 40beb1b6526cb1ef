"""Tests for lfdkit.imitate.DMP against closed forms, an ODE solver and geometric identities."""

from __future__ import annotations

import itertools
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import linalg
from scipy.integrate import solve_ivp
from scipy.interpolate import interp1d
from sklearn.base import clone
from sklearn.exceptions import NotFittedError

from lfdkit.core.options import THESIS_DMP
from lfdkit.imitate import DMP, minimum_jerk_times
from lfdkit.imitate._dmp_numerics import transition as _transition
from lfdkit.model.timed_path import TimedPath

OMEGA = 12.5  # sqrt(156.25): the thesis's gains, critically damped


def s_curve(n: int = 120) -> np.ndarray:
    u = np.linspace(0.0, 1.0, n)
    return np.column_stack([4.0 * u, np.sin(2.0 * np.pi * u) + 0.5 * u])


def helix(n: int = 150) -> np.ndarray:
    u = np.linspace(0.0, 1.0, n)
    return np.column_stack([np.cos(3 * u), np.sin(3 * u), 2.0 * u])


def extent(path: np.ndarray) -> float:
    return float(np.max(np.ptp(path, axis=0)))


def reproduction_rms(dmp: DMP) -> float:
    """Time-aligned RMS between a dense rollout and the training samples, over the extent."""
    rollout = dmp.rollout(n_steps=5001)
    at_samples = interp1d(rollout.times, rollout.positions, axis=0, kind="cubic")(dmp.times_)
    error = np.linalg.norm(at_samples - dmp.path_, axis=1)
    return float(np.sqrt(np.mean(error**2)) / extent(dmp.path_))


def spring(y0: np.ndarray, goal: np.ndarray, s: np.ndarray) -> tuple[np.ndarray, ...]:
    """Critically damped response from rest in normalised time: position, velocity, acceleration."""
    decay = np.exp(-OMEGA * s)[:, None]
    e0 = y0 - goal
    pos = goal + e0 * (1.0 + OMEGA * s[:, None]) * decay
    vel = -e0 * OMEGA**2 * s[:, None] * decay
    acc = -e0 * OMEGA**2 * (1.0 - OMEGA * s[:, None]) * decay
    return pos, vel, acc


# ------------------------------------------------------------------- closed forms
def test_transition_matches_matrix_exponential_for_every_damping() -> None:
    t = np.array([0.0, 1e-6, 0.013, 0.3, 1.0, 2.5])
    for k, c in [(156.25, 25.0), (100.0, 5.0), (100.0, 40.0), (156.25, 25.0 + 1e-9)]:
        a = np.array([[0.0, 1.0], [-k, -c]])
        expected = np.stack([linalg.expm(a * ti) for ti in t])
        got = np.moveaxis(_transition(k, c, t), 2, 0)
        np.testing.assert_allclose(got, expected, rtol=1e-9, atol=1e-12)


def test_unforced_path_gives_the_critically_damped_spring_for_a_new_goal() -> None:
    s = np.linspace(0.0, 1.0, 400)
    y0, goal = np.array([0.0, 1.0]), np.array([2.0, -1.0])
    path = spring(y0, goal, s)[0]
    dmp = DMP(n_basis=20, scaling="per_dimension", end="free").fit(path, timing="uniform")
    # The path is the spring's own response: next to the spring force k |y0 - g| there is
    # nothing to learn (what is left comes from differentiating samples).
    spring_force = dmp.k * np.abs(y0 - goal).max()
    assert np.abs(dmp.forcing(dmp.forcing_times_)).max() < 5e-3 * spring_force
    new_start, new_goal = np.array([1.0, 1.0]), np.array([-3.0, 0.5])
    rollout = dmp.rollout(new_start, new_goal, n_steps=300)
    pos, vel, acc = spring(new_start, new_goal, np.linspace(0, 1, 300))
    scale = np.abs(new_goal - new_start).max()
    np.testing.assert_allclose(rollout.positions, pos, atol=1e-4 * scale)
    np.testing.assert_allclose(rollout.velocities, vel, atol=1e-3 * scale * OMEGA)
    np.testing.assert_allclose(rollout.accelerations, acc, atol=1e-2 * scale * OMEGA**2)


@pytest.mark.parametrize("scaling", ["per_dimension", "spatial"])
@pytest.mark.parametrize("timing", ["uniform", "minimum_jerk"])
def test_a_straight_line_stays_straight_for_any_goal(scaling: str, timing: str) -> None:
    path = np.linspace([0.0, 0.0, 0.0], [3.0, 1.0, -2.0], 50)
    dmp = DMP(n_basis=15, scaling=scaling).fit(path, timing=timing)
    goals = np.array([[3.0, 1.0, -2.0], [1.0, 4.0, 2.0], [-2.0, -1.0, 0.5]])
    start = np.array([0.5, 0.0, 0.0])
    rollouts = dmp.rollout(start=start, goal=goals)
    for goal, positions in zip(goals, rollouts.positions, strict=True):
        direction = (goal - start) / np.linalg.norm(goal - start)
        offsets = positions - start
        off_line = offsets - np.outer(offsets @ direction, direction)
        assert np.abs(off_line).max() < 1e-10


# ----------------------------------------------------------------- reproduction
# A full sine period in one movement is demanding for 10 weights (about 1.1 %).
@pytest.mark.parametrize("n_basis, bound", [(10, 1.2e-2), (20, 2e-3), (50, 5e-4)])
def test_reproduces_a_smooth_path_with_minimum_jerk_timing(n_basis: int, bound: float) -> None:
    dmp = DMP(n_basis=n_basis).fit(s_curve(), timing="minimum_jerk")
    assert reproduction_rms(dmp) < bound


def test_reproduces_a_3d_path_with_given_times() -> None:
    path = helix()
    times = minimum_jerk_times(path, duration=3.0)
    dmp = DMP(n_basis=30).fit(path, times)
    assert dmp.duration_ == pytest.approx(3.0)
    assert reproduction_rms(dmp) < 2e-3


def test_more_basis_functions_reproduce_better() -> None:
    errors = [
        reproduction_rms(DMP(n_basis=n).fit(s_curve(), timing="minimum_jerk"))
        for n in (5, 10, 20, 40)
    ]
    assert all(a > b for a, b in itertools.pairwise(errors))


def test_uniform_timing_starts_at_rest_and_so_lags_the_constant_speed_path() -> None:
    # The thesis's equal time steps give the path its speed at t = 0; the DMP starts at rest.
    path = s_curve()
    uniform = reproduction_rms(DMP(n_basis=20).fit(path, timing="uniform"))
    jerk = reproduction_rms(DMP(n_basis=20).fit(path, timing="minimum_jerk"))
    assert jerk < 0.5 * uniform
    # Given the path's initial velocity the DMP follows it from the start.
    dmp = DMP(n_basis=20, end="free").fit(path, timing="uniform")
    initial_velocity = (path[1] - path[0]) / (dmp.times_[1] - dmp.times_[0])
    moving = dmp.rollout(start_velocity=initial_velocity, n_steps=path.shape[0])
    at_rest = dmp.rollout(n_steps=path.shape[0])
    early = slice(0, 20)
    assert (
        np.abs(moving.positions[early] - path[early]).max()
        < 0.5 * np.abs(at_rest.positions[early] - path[early]).max()
    )


# ---------------------------------------------------------------- goal reaching
@pytest.mark.parametrize("scaling", ["per_dimension", "spatial", "translate"])
def test_every_new_goal_is_reached_at_rest_at_the_end(scaling: str) -> None:
    path = s_curve()
    dmp = DMP(n_basis=30, scaling=scaling).fit(path, timing="minimum_jerk")
    rng = np.random.default_rng(0)
    size = extent(path)
    goals = dmp.goal_ + rng.uniform(-0.5, 0.5, size=(100, 2)) * size
    rollouts = dmp.rollout(goal=goals)
    np.testing.assert_allclose(rollouts.positions[:, -1], goals, atol=1e-7 * size)
    assert np.abs(rollouts.velocities[:, -1]).max() < 1e-5 * size
    assert np.abs(rollouts.accelerations[:, -1]).max() < 1e-3 * size
    # The forcing is off after the movement, so the state stays at the goal.
    t, pos, vel = rollouts.times[-1], rollouts.positions[:, -1], rollouts.velocities[:, -1]
    for _ in range(50):
        pos, vel, _ = dmp.step(t, pos, vel, 0.02, goal=goals)
        t += 0.02
    np.testing.assert_allclose(pos, goals, atol=1e-7 * size)


def test_free_end_converges_to_the_goal_after_the_movement() -> None:
    dmp = DMP(n_basis=20, end="free").fit(s_curve())
    goal = dmp.goal_ + np.array([0.5, -0.7])
    rollout = dmp.rollout(goal=goal)
    assert np.linalg.norm(rollout.positions[-1] - goal) > 1e-6  # not there yet at t = T
    t, pos, vel = rollout.times[-1], rollout.positions[-1], rollout.velocities[-1]
    dt = 0.01
    for _ in range(300):
        pos, vel, _ = dmp.step(t, pos, vel, dt, goal=goal)
        t += dt
    assert np.linalg.norm(pos - goal) < 1e-6 * extent(dmp.path_)


def test_start_equal_to_goal_stays_put() -> None:
    for scaling in ("per_dimension", "spatial"):
        dmp = DMP(scaling=scaling).fit(s_curve())
        point = np.array([1.0, 2.0])
        rollout = dmp.rollout(start=point, goal=point)
        np.testing.assert_allclose(rollout.positions, np.broadcast_to(point, (120, 2)), atol=1e-12)
        np.testing.assert_allclose(rollout.velocities, 0.0, atol=1e-12)


@pytest.mark.parametrize("scaling", ["per_dimension", "spatial"])
def test_goal_on_the_other_side_of_the_start_mirrors_the_shape_through_the_start(
    scaling: str,
) -> None:
    dmp = DMP(n_basis=20, scaling=scaling).fit(s_curve(), timing="minimum_jerk")
    reproduction = dmp.rollout().positions
    y0 = dmp.start_
    mirrored = dmp.rollout(goal=2.0 * y0 - dmp.goal_).positions
    np.testing.assert_allclose(mirrored, 2.0 * y0 - reproduction, atol=1e-10)


def test_spatial_scaling_rotates_and_scales_the_shape_rigidly() -> None:
    path = helix()
    dmp = DMP(n_basis=20, scaling="spatial").fit(path, timing="minimum_jerk")
    reproduction = dmp.rollout().positions
    angle = 0.7
    axis = np.cross(dmp.goal_ - dmp.start_, [0.0, 0.0, 1.0])
    axis /= np.linalg.norm(axis)
    skew = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    rotation = linalg.expm(angle * skew)
    goal = dmp.start_ + 1.5 * rotation @ (dmp.goal_ - dmp.start_)
    rollout = dmp.rollout(goal=goal).positions
    expected = dmp.start_ + 1.5 * (reproduction - dmp.start_) @ rotation.T
    np.testing.assert_allclose(rollout, expected, atol=1e-10)


def test_per_dimension_scaling_is_the_thesis_factor_per_axis() -> None:
    dmp = DMP(n_basis=20, scaling="per_dimension").fit(s_curve(), timing="minimum_jerk")
    reproduction = dmp.rollout().positions
    start = np.array([1.0, -1.0])
    goal = start + np.array([2.0, 3.0]) * (dmp.goal_ - dmp.start_)
    rollout = dmp.rollout(start=start, goal=goal).positions
    expected = start + (reproduction - dmp.start_) * [2.0, 3.0]
    np.testing.assert_allclose(rollout, expected, atol=1e-10)


def test_per_dimension_scaling_refuses_a_dimension_with_no_training_displacement() -> None:
    u = np.linspace(0.0, 1.0, 80)
    bump = np.column_stack([u, np.sin(np.pi * u)])  # starts and ends at y = 0
    dmp = DMP(**THESIS_DMP).fit(bump)
    dmp.rollout(goal=[2.0, 0.0])  # the flat dimension stays flat: fine
    with pytest.raises(ValueError, match=r"dimension 1.*scaling='spatial'"):
        dmp.rollout(goal=[1.0, 0.5])
    spatial = DMP(scaling="spatial").fit(bump).rollout(goal=[1.0, 0.5])
    np.testing.assert_allclose(spatial.positions[-1], [1.0, 0.5], atol=1e-9)


@pytest.mark.parametrize("scaling", ["per_dimension", "spatial"])
def test_a_closed_movement_can_be_moved_but_not_stretched(scaling: str) -> None:
    u = np.linspace(0.0, 1.0, 100)
    loop = np.column_stack([np.cos(2 * np.pi * u), np.sin(2 * np.pi * u)])
    dmp = DMP(n_basis=20, scaling=scaling).fit(loop, timing="minimum_jerk")
    shifted = dmp.rollout(start=[3.0, 1.0], goal=[3.0, 1.0])
    moved = dmp.rollout().positions + np.array([2.0, 1.0])
    np.testing.assert_allclose(shifted.positions, moved, atol=1e-12)
    with pytest.raises(ValueError, match=r"goal: .*starts and ends at the same"):
        dmp.rollout(goal=[2.0, 0.0])


def test_per_dimension_scaling_warns_when_it_amplifies_a_tiny_displacement() -> None:
    u = np.linspace(0.0, 1.0, 80)
    nearly_flat = np.column_stack([u, np.sin(np.pi * u) + 0.01 * u])
    dmp = DMP(**THESIS_DMP).fit(nearly_flat)
    with pytest.warns(RuntimeWarning, match="multiplies the shape of dimension 1"):
        dmp.rollout(goal=[1.0, 0.5])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        dmp.rollout(goal=[1.5, 0.02])


# -------------------------------------------------------- exactness and agreement
def test_rollout_matches_a_high_accuracy_ode_solution() -> None:
    dmp = DMP(n_basis=25, scaling="per_dimension").fit(
        s_curve(), timing="minimum_jerk", duration=2.0
    )
    start, goal = np.array([0.3, -0.2]), np.array([5.0, 2.0])
    velocity0 = np.array([0.4, -1.0])
    matrix = dmp.scale_matrix(start, goal)

    def rhs(s: float, x: np.ndarray) -> np.ndarray:
        forcing = matrix @ dmp.forcing(np.array([s * dmp.duration_]))[0]
        return np.concatenate([x[2:], -dmp.k * x[:2] - dmp.c * x[2:] + forcing])

    x0 = np.concatenate([start - goal, velocity0 * dmp.duration_])
    solution = solve_ivp(
        rhs, (0.0, 1.0), x0, method="DOP853", rtol=1e-12, atol=1e-12, dense_output=True
    )
    rollout = dmp.rollout(start, goal, n_steps=700, start_velocity=velocity0)
    reference = solution.sol(np.linspace(0.0, 1.0, 700))
    np.testing.assert_allclose(rollout.positions, reference[:2].T + goal, atol=1e-9)
    np.testing.assert_allclose(rollout.velocities, reference[2:].T / dmp.duration_, atol=1e-8)


def test_batch_single_and_stepwise_rollouts_agree() -> None:
    dmp = DMP(n_basis=20, scaling="spatial").fit(helix(), timing="minimum_jerk")
    rng = np.random.default_rng(3)
    goals = dmp.goal_ + rng.normal(size=(5, 3))
    starts = dmp.start_ + 0.1 * rng.normal(size=(5, 3))
    batch = dmp.rollout(start=starts, goal=goals, n_steps=200, tau=1.5)
    assert isinstance(batch, TimedPath) and batch.positions.shape == (5, 200, 3)
    assert not batch.positions.flags.writeable  # a record: np.array(...) to change a copy
    for i in range(5):
        single = dmp.rollout(start=starts[i], goal=goals[i], n_steps=200, tau=1.5)
        np.testing.assert_allclose(batch.positions[i], single.positions, atol=1e-12)
        np.testing.assert_allclose(batch.accelerations[i], single.accelerations, atol=1e-9)
    # Stepping with the same step reproduces the batch, including the accelerations.
    dt = batch.times[1]
    pos, vel = starts.copy(), np.zeros((5, 3))
    for j in range(199):
        pos, vel, acc = dmp.step(batch.times[j], pos, vel, dt, start=starts, goal=goals, tau=1.5)
        np.testing.assert_allclose(pos, batch.positions[:, j + 1], atol=1e-10)
        np.testing.assert_allclose(vel, batch.velocities[:, j + 1], atol=1e-9)
    np.testing.assert_allclose(acc, batch.accelerations[:, -1], atol=1e-8)


def test_step_is_exact_for_any_step_size() -> None:
    dmp = DMP(n_basis=20).fit(s_curve(), timing="minimum_jerk")
    fine = dmp.rollout(n_steps=101)
    pos, vel = dmp.start_, np.zeros(2)
    for j in range(0, 100, 25):  # four big steps of a quarter of the movement
        pos, vel, _ = dmp.step(fine.times[j], pos, vel, fine.times[25], start=dmp.start_)
    np.testing.assert_allclose(pos, fine.positions[-1], atol=1e-9)


def test_a_pushed_state_is_pulled_back_to_the_path_and_the_goal() -> None:
    dmp = DMP(n_basis=20).fit(s_curve(), timing="minimum_jerk")
    nominal = dmp.rollout(n_steps=201)
    dt = nominal.times[1]
    push = np.array([0.0, 0.8])  # 20 % of the extent, at t = 0.3 T
    pos, vel = dmp.start_.copy(), np.zeros(2)
    for j in range(400):  # twice the movement's duration
        if j == 60:
            pos = pos + push
        pos, vel, _ = dmp.step(j * dt, pos, vel, dt)
        if 60 <= j < 200:
            # The system is linear: the push decays as the free critically damped spring.
            elapsed = (j + 1 - 60) * dt / dmp.duration_
            decay = (1.0 + OMEGA * elapsed) * np.exp(-OMEGA * elapsed)
            np.testing.assert_allclose(pos - nominal.positions[j + 1], decay * push, atol=1e-10)
    assert np.linalg.norm(pos - dmp.goal_) < 1e-6 * extent(dmp.path_)


def test_temporal_scaling_changes_time_not_the_path() -> None:
    dmp = DMP(n_basis=20).fit(s_curve(), duration=2.0)
    base, slow = dmp.rollout(), dmp.rollout(tau=2.0)
    np.testing.assert_allclose(slow.times, 2.0 * base.times)
    np.testing.assert_allclose(slow.positions, base.positions, atol=1e-12)
    np.testing.assert_allclose(slow.velocities, base.velocities / 2.0, atol=1e-12)
    np.testing.assert_allclose(slow.accelerations, base.accelerations / 4.0, atol=1e-10)
    assert base.times[-1] == pytest.approx(2.0)
    assert DMP(tau=3.0).fit(s_curve()).rollout().times[-1] == pytest.approx(3.0)


@settings(max_examples=30, deadline=None)
@given(
    st.lists(st.floats(-5.0, 5.0), min_size=2, max_size=2),
    st.lists(st.floats(-5.0, 5.0), min_size=2, max_size=2),
)
def test_rollout_from_rest_is_an_affine_copy_of_the_reproduction(start, goal) -> None:
    dmp = _fitted_spatial()
    start, goal = np.array(start), np.array(goal)
    matrix = dmp.scale_matrix(start, goal)
    reproduction = dmp.rollout(n_steps=50).positions
    rollout = dmp.rollout(start, goal, n_steps=50).positions
    np.testing.assert_allclose(rollout, goal + (reproduction - dmp.goal_) @ matrix.T, atol=1e-9)
    np.testing.assert_allclose(rollout[0], start, atol=1e-12)


_SPATIAL: list[DMP] = []


def _fitted_spatial() -> DMP:
    if not _SPATIAL:
        _SPATIAL.append(DMP(n_basis=15, scaling="spatial").fit(s_curve(), timing="minimum_jerk"))
    return _SPATIAL[0]


# --------------------------------------------------------------- regularisation
def test_very_many_basis_functions_stay_well_posed() -> None:
    path = s_curve(40)
    few = DMP(n_basis=30).fit(path, timing="minimum_jerk")
    many = DMP(n_basis=800).fit(path, timing="minimum_jerk")
    assert np.all(np.isfinite(many.weights_))
    assert reproduction_rms(many) < 2e-3
    assert abs(reproduction_rms(many) - reproduction_rms(few)) < 2e-3


def test_estimator_conventions() -> None:
    dmp = DMP(n_basis=12, scaling="spatial")
    assert clone(dmp).get_params()["n_basis"] == 12
    assert dmp.fit(s_curve()) is dmp
    assert dmp.weights_.shape == (12, 2)
    assert dmp.n_basis_ == 12
    assert dmp.centers_.shape == dmp.widths_.shape == (12,)
    assert np.all(np.diff(dmp.centers_) < 0)  # phase decays from 1
    with pytest.raises(NotFittedError):
        DMP().rollout()


# ----------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "path, match",
    [
        (np.zeros((1, 2)), "at least 3 points"),
        (np.zeros((2, 2)), "at least 3 points"),
        (np.array([[0.0, 0.0], [np.nan, 1.0], [2.0, 2.0]]), "NaN at row 1"),
        (np.zeros(5), "2-D array"),
    ],
)
def test_bad_paths_are_refused_with_a_clear_message(path: np.ndarray, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        DMP().fit(path)


def test_bad_times_and_options_are_refused() -> None:
    path = s_curve(10)
    with pytest.raises(ValueError, match="times: must increase strictly"):
        DMP().fit(path, np.r_[0.0, 0.0, np.arange(2, 10)])
    with pytest.raises(ValueError, match=r"times: expected shape \(10,\)"):
        DMP().fit(path, np.arange(9))
    with pytest.raises(ValueError, match="either times or a duration"):
        DMP().fit(path, np.arange(10.0), duration=2.0)
    with pytest.raises(ValueError, match="either duration or dt"):
        DMP().fit(path, duration=2.0, dt=0.1)
    assert DMP().fit(path, dt=0.5).duration_ == pytest.approx(4.5)
    with pytest.raises(ValueError, match="timing"):
        DMP().fit(path, timing="fast")
    with pytest.raises(ValueError, match="scaling"):
        DMP(scaling="rigid").fit(path)
    with pytest.raises(ValueError, match="end"):
        DMP(end="stop").fit(path)
    with pytest.raises(TypeError, match="n_basis"):
        DMP(n_basis=2.5).fit(path)
    with pytest.raises(ValueError, match="n_basis: end='rest' puts 3 constraints"):
        DMP(n_basis=3).fit(path)
    assert np.all(np.isfinite(DMP(n_basis=1, end="free").fit(path).weights_))
    with pytest.raises(ValueError, match="coincide"):
        DMP().fit(np.array([[0.0, 0.0], [1.0, 1.0], [1.0, 1.0], [2.0, 0.0]]), timing="minimum_jerk")


def test_bad_rollout_and_step_arguments_are_refused() -> None:
    dmp = DMP().fit(s_curve(10))
    with pytest.raises(ValueError, match=r"goal: expected shape \(2,\)"):
        dmp.rollout(goal=[1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="goal: contains NaN"):
        dmp.rollout(goal=[1.0, np.nan])
    with pytest.raises(ValueError, match="n_steps"):
        dmp.rollout(n_steps=1)
    with pytest.raises(ValueError, match="start, goal: 3 starts and 2 goals"):
        dmp.rollout(start=np.zeros((3, 2)), goal=np.ones((2, 2)))
    with pytest.raises(ValueError, match="tau"):
        dmp.rollout(tau=0.0)
    with pytest.raises(ValueError, match="dt"):
        dmp.step(0.0, [0.0, 0.0], [0.0, 0.0], -0.1)
    with pytest.raises(ValueError, match="velocity: contains NaN"):
        dmp.step(0.0, [0.0, 0.0], [np.nan, 0.0], 0.1)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda d: d.rollout(goal=[1e300, 1e300]), r"goal: 1e\+300 is beyond 1e\+06 times"),
        (lambda d: d.rollout(start=[0.0, -5e6]), r"start: 5e\+06 is beyond"),
        (lambda d: d.rollout(goal=np.full((3, 2), np.inf)), "goal: contains NaN or infinite"),
        (lambda d: d.rollout(start_velocity=[1e7, 0.0]), "start_velocity: 1e\\+07 units/s"),
        (lambda d: d.rollout(n_steps=10**9), "n_steps: expected 2 to 1,000,000"),
        (lambda d: d.rollout(goal=np.ones((100, 2)), n_steps=200_000), "exceed 10,000,000"),
        (lambda d: d.rollout(tau=1e300), "tau: expected 1e-06 to 1e\\+06"),
        (lambda d: d.rollout(tau=1e-300), "tau: expected"),
        (lambda d: d.rollout(goal=["a", "b"]), "goal: expected 2 numbers"),
        (lambda d: d.step(0.0, [1e200, 0.0], [0.0, 0.0], 0.01), "position: 1e\\+200"),
        (lambda d: d.step(0.0, [0.0, 0.0], [1e12, 0.0], 0.01), "velocity: 1e\\+12"),
        (lambda d: d.step(0.0, [0.0, 0.0], [0.0, 0.0], 1e10), "dt: 1e\\+10 s is more than"),
        (lambda d: d.step(0.0, [0.0, 0.0], [0.0, 0.0], 0.1, goal=[0, 1e300]), "goal: 1e\\+300"),
    ],
)
def test_absurd_arguments_are_errors_not_inf(call, match) -> None:
    dmp = DMP().fit(s_curve(10))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow warning on the way to the error
        with pytest.raises((ValueError, TypeError), match=match):
            call(dmp)


def test_the_magnitude_bound_is_relative_to_the_training_scale() -> None:
    # The same shape in micrometres and in kilometres: the bound scales with it.
    for scale in (1e-6, 1e3):
        dmp = DMP().fit(scale * s_curve(10))
        far = dmp.rollout(goal=scale * np.array([1e5, 1e5]), n_steps=5)
        assert np.all(np.isfinite(far.positions))
        np.testing.assert_allclose(far.positions[-1], scale * np.array([1e5, 1e5]), rtol=1e-9)
        with pytest.raises(ValueError, match="goal"):
            dmp.rollout(goal=scale * np.array([1e7, 0.0]))


def test_size_caps_are_errors_not_memory_errors() -> None:
    with pytest.raises(ValueError, match="n_basis: expected 1 to 1,000, got 1,000,000"):
        DMP(n_basis=10**6).fit(s_curve(10))
    DMP(n_basis=1000, end="free").fit(s_curve(10))  # the cap itself is allowed
    for duration, match in [(1e-9, "duration: the path must last"), (1e12, "duration")]:
        with pytest.raises(ValueError, match=match):
            DMP().fit(s_curve(10), duration=duration)


def test_a_long_step_past_the_end_settles_at_the_goal() -> None:
    dmp = DMP().fit(s_curve(30))
    # 500 movement durations in one step: no quadrature over it, no NaN, at the goal at rest.
    pos, vel, _ = dmp.step(0.5, dmp.goal_ + 0.3, [1.0, -2.0], 500.0 * dmp.duration_)
    np.testing.assert_allclose(pos, dmp.goal_, atol=1e-12)
    np.testing.assert_allclose(vel, 0.0, atol=1e-12)
    # And a step that starts after the end agrees with two shorter ones.
    one = dmp.step(1.5, dmp.goal_ + 0.1, [0.2, 0.0], 0.2)
    half = dmp.step(1.5, dmp.goal_ + 0.1, [0.2, 0.0], 0.1)
    two = dmp.step(1.6, half[0], half[1], 0.1)
    np.testing.assert_allclose(one[0], two[0], atol=1e-12)
    np.testing.assert_allclose(one[1], two[1], atol=1e-12)


def test_minimum_jerk_times_follow_the_quintic_law() -> None:
    line = np.linspace([0.0, 0.0], [1.0, 0.0], 101)
    times = minimum_jerk_times(line, duration=2.0)
    u = times / 2.0
    np.testing.assert_allclose(10 * u**3 - 15 * u**4 + 6 * u**5, line[:, 0], atol=1e-12)
    assert times[0] == 0.0 and times[-1] == 2.0
    assert np.all(np.diff(times) > 0)


@pytest.mark.parametrize("q", [1, 2, 3, 5])
def test_rotations_between_are_proper_and_map_u_onto_v(q: int) -> None:
    from lfdkit.imitate._dmp_numerics import rotations_between as _rotations_between

    rng = np.random.default_rng(q)
    u = rng.normal(size=q)
    u /= np.linalg.norm(u)
    v = rng.normal(size=(20, q))
    v[0], v[1] = u, -u  # identical and opposite directions
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    rotations = _rotations_between(u, v)
    np.testing.assert_allclose(rotations @ u, v, atol=1e-12)
    if q > 1:
        identity = np.broadcast_to(np.eye(q), rotations.shape)
        np.testing.assert_allclose(rotations @ rotations.transpose(0, 2, 1), identity, atol=1e-12)
        np.testing.assert_allclose(np.linalg.det(rotations), 1.0, atol=1e-12)
        # Vectors orthogonal to both u and v stay where they are.
        if q > 2:
            w = rng.normal(size=q)
            basis = np.linalg.qr(np.column_stack([u, v[5], w]))[0]
            np.testing.assert_allclose(rotations[5] @ basis[:, 2], basis[:, 2], atol=1e-12)


def test_piecewise_quintic_is_exact_for_quintic_polynomials() -> None:
    from lfdkit.imitate._dmp_numerics import evaluate_pieces as _evaluate_pieces
    from lfdkit.imitate._dmp_numerics import quintic_pieces as _quintic_pieces

    rng = np.random.default_rng(7)
    polys = [np.polynomial.Polynomial(rng.normal(size=6)) for _ in range(2)]
    knots = np.linspace(0.0, 1.0, 9)
    data = [np.column_stack([p.deriv(m)(knots) for p in polys]) for m in range(3)]
    pieces = _quintic_pieces(*data, knots[1])
    s = np.linspace(0.0, 1.0, 257)
    out = _evaluate_pieces(s, knots[1], pieces)  # (q, 3, n)
    for d, poly in enumerate(polys):
        for m in range(3):
            np.testing.assert_allclose(out[d, m], poly.deriv(m)(s), atol=1e-10)


def test_a_dmp_on_its_own_has_the_skills_defaults_and_the_thesis_is_one_option_away() -> None:
    from lfdkit.skill import Skill

    ours, skill = DMP().get_params(), Skill().get_params()
    assert (ours["n_basis"], ours["scaling"]) == (skill["n_basis"], skill["scaling"])
    assert (ours["n_basis"], ours["scaling"]) == ("auto", "translate")
    thesis = DMP(**THESIS_DMP).fit(s_curve())
    assert (thesis.n_basis_, thesis.scaling) == (10, "per_dimension")
    # The default chooses its basis count: the S curve is reproduced within 1 % of its extent.
    assert DMP().fit(s_curve()).reproduction_error_ <= 0.01
