"""DMP(n_basis="auto") and scaling="translate": closed and nearly closed paths."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from sklearn.base import clone

from lfdkit.emulate.metrics import held_out_distances
from lfdkit.imitate import BASIS_LADDER, DMP, warp_path
from lfdkit.imitate._dmp_numerics import minimum_jerk_law as _minimum_jerk_law


def extent(path: np.ndarray) -> float:
    return float(np.max(np.ptp(path, axis=0)))


def wiggle(cycles: int, n: int = 1000) -> tuple[np.ndarray, np.ndarray]:
    """A rest-to-rest stroke with ``cycles`` sine periods across it, and its sample times.

    ``x`` follows the minimum-jerk law, ``y = 0.1 sin(2π m s) sin²(π s)``, a sum
    of sines of ``m − 1``, ``m`` and ``m + 1`` cycles per movement, at rest at
    both ends (so a DMP starting at rest can follow it exactly).
    """
    s = np.linspace(0.0, 1.0, n)
    x = _minimum_jerk_law(s)[0]
    y = 0.1 * np.sin(2.0 * np.pi * cycles * s) * np.sin(np.pi * s) ** 2
    return np.column_stack([x, y]), s


def circle(n: int = 200, turns: float = 1.0, radius: float = 1.0) -> np.ndarray:
    angle = 2.0 * np.pi * turns * np.linspace(0.0, 1.0, n)
    return radius * np.column_stack([np.cos(angle), np.sin(angle)])


def blend(s: np.ndarray) -> np.ndarray:
    return _minimum_jerk_law(s)[0][:, None]


# ------------------------------------------------------------------- auto basis
def test_auto_basis_picks_few_functions_for_a_smooth_stroke_and_many_for_a_wiggly_one() -> None:
    smooth = DMP(n_basis="auto").fit(*wiggle(1))
    cycles = 12
    wiggly = DMP(n_basis="auto").fit(*wiggle(cycles))
    assert smooth.n_basis_ <= 20
    # The basis centres are evenly spaced in time: fewer than two per period of the
    # fastest sine (m + 1 cycles) cannot represent it (Nyquist), whatever the fit.
    assert wiggly.n_basis_ >= 2 * (cycles + 1) + 1
    assert wiggly.n_basis_ > smooth.n_basis_
    for dmp in (smooth, wiggly):
        assert dmp.n_basis_ in BASIS_LADDER
        assert dmp.reproduction_error_ <= dmp.basis_tol
        # The smallest count that passes: the one before it on the ladder misses.
        rung = BASIS_LADDER.index(dmp.n_basis_)
        if rung:
            path, times = dmp.path_, dmp.times_
            fewer = DMP(n_basis=BASIS_LADDER[rung - 1]).fit(path, times)
            assert fewer.reproduction_error_ > dmp.basis_tol


def test_auto_basis_follows_the_tolerance() -> None:
    path, times = wiggle(6)
    loose = DMP(n_basis="auto", basis_tol=0.05).fit(path, times)
    tight = DMP(n_basis="auto", basis_tol=0.001).fit(path, times)
    assert loose.n_basis_ < tight.n_basis_
    assert loose.reproduction_error_ <= 0.05 and tight.reproduction_error_ <= 0.001
    # The ladder starts at its first rung: a straight stroke within 5 % needs no more.
    line = np.linspace([0.0, 0.0], [1.0, 2.0], 50)
    first = DMP(n_basis="auto", basis_tol=0.05).fit(line, timing="minimum_jerk")
    assert first.n_basis_ == BASIS_LADDER[0]


def test_reproduction_error_is_the_rollout_error_at_the_training_times() -> None:
    path, times = wiggle(4)
    for n_basis in (10, 20, "auto"):
        dmp = DMP(n_basis=n_basis).fit(path, times)
        rollout = dmp.rollout(n_steps=len(times))  # the training times exactly
        error = np.max(np.linalg.norm(rollout.positions - path, axis=1)) / extent(path)
        # Computed without a rollout (module notes): equal to within 2 %.
        assert dmp.reproduction_error_ == pytest.approx(error, rel=0.02)


def test_auto_basis_fits_exactly_as_the_chosen_integer_count() -> None:
    path, times = wiggle(8)
    auto = DMP(n_basis="auto", scaling="spatial").fit(path, times)
    fixed = DMP(n_basis=auto.n_basis_, scaling="spatial").fit(path, times)
    np.testing.assert_array_equal(auto.weights_, fixed.weights_)
    assert auto.reproduction_error_ == fixed.reproduction_error_
    assert auto.weights_.shape == (auto.n_basis_, 2)
    assert auto.centers_.shape == auto.widths_.shape == (auto.n_basis_,)
    goal = auto.goal_ + np.array([0.3, -0.2])
    np.testing.assert_array_equal(
        auto.rollout(goal=goal).positions, fixed.rollout(goal=goal).positions
    )
    # Stepping uses the fitted count's quadrature too: it agrees with the rollout.
    rollout = auto.rollout(goal=goal, n_steps=201)
    pos, vel = auto.start_.copy(), np.zeros(2)
    for j in range(200):
        pos, vel, _ = auto.step(rollout.times[j], pos, vel, rollout.times[1], goal=goal)
    np.testing.assert_allclose(pos, rollout.positions[-1], atol=1e-10)


def test_an_integer_count_is_kept_and_reports_its_error() -> None:
    path, times = wiggle(3)
    dmp = DMP(n_basis=12).fit(path, times)
    assert dmp.n_basis_ == 12 and dmp.weights_.shape == (12, 2)
    assert 0.0 < dmp.reproduction_error_ < 1.0
    assert clone(DMP(n_basis="auto", basis_tol=0.02)).get_params()["n_basis"] == "auto"


def test_auto_basis_warns_and_keeps_the_closest_when_nothing_passes() -> None:
    path, times = wiggle(3)
    with pytest.warns(RuntimeWarning, match=r"n_basis='auto'.*basis_tol=1e-09.*Raise basis_tol"):
        dmp = DMP(n_basis="auto", basis_tol=1e-9).fit(path, times)
    errors = {n: DMP(n_basis=n).fit(path, times).reproduction_error_ for n in BASIS_LADDER}
    assert dmp.n_basis_ == min(errors, key=errors.get)
    assert dmp.weights_.shape == (dmp.n_basis_, 2)


def test_uniform_timing_cannot_be_reproduced_from_rest_and_auto_says_so() -> None:
    # Equal time steps give the path its full speed at t = 0; the DMP starts at rest.
    angle = np.linspace(0.0, np.pi, 100)
    arc = np.column_stack([np.cos(angle), np.sin(angle)])
    with pytest.warns(RuntimeWarning, match="timing='minimum_jerk'"):
        DMP(n_basis="auto").fit(arc, timing="uniform")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        DMP(n_basis="auto").fit(arc, timing="minimum_jerk")


@pytest.mark.parametrize(
    ("params", "error", "match"),
    [
        ({"basis_tol": 0.0}, ValueError, "basis_tol: must be > 0"),
        ({"basis_tol": -0.01}, ValueError, "basis_tol: must be > 0"),
        ({"basis_tol": float("nan")}, ValueError, "basis_tol: must be finite"),
        ({"basis_tol": float("inf")}, ValueError, "basis_tol: must be finite"),
        ({"basis_tol": 2.0}, ValueError, "basis_tol: expected a fraction"),
        ({"basis_tol": "1%"}, TypeError, "basis_tol: expected a number"),
        ({"n_basis": "many"}, ValueError, "n_basis: expected an integer or 'auto'"),
        ({"n_basis": 2.5}, TypeError, "n_basis: expected an integer"),
        ({"scaling": "rigid"}, ValueError, "scaling: expected one of"),
    ],
)
def test_bad_basis_options_are_refused_naming_the_argument(params, error, match) -> None:
    path, times = wiggle(1, n=50)
    with pytest.raises(error, match=match):
        DMP(**params).fit(path, times)


# -------------------------------------------------------------- translate mode
def test_translate_carries_the_reproduction_by_the_blended_offsets() -> None:
    path, times = wiggle(2)
    dmp = DMP(n_basis=20, scaling="translate").fit(path, times)
    reproduction = dmp.rollout(n_steps=300).positions
    s = np.linspace(0.0, 1.0, 300)
    rng = np.random.default_rng(1)
    starts = dmp.start_ + rng.normal(scale=0.3, size=(6, 2))
    goals = dmp.goal_ + rng.normal(scale=0.3, size=(6, 2))
    batch = dmp.rollout(start=starts, goal=goals, n_steps=300)
    for start, goal, positions in zip(starts, goals, batch.positions, strict=True):
        expected = (
            reproduction + (1.0 - blend(s)) * (start - dmp.start_) + blend(s) * (goal - dmp.goal_)
        )
        np.testing.assert_allclose(positions, expected, atol=1e-12)
    np.testing.assert_array_equal(dmp.scale_matrix(starts[0], goals[0]), np.eye(2))
    # Every rollout ends at its goal at rest, and stepping agrees with the batch.
    np.testing.assert_allclose(batch.positions[:, -1], goals, atol=1e-9)
    assert np.abs(batch.velocities[:, -1]).max() < 1e-8
    pos, vel = starts.copy(), np.zeros((6, 2))
    for j in range(299):
        pos, vel, acc = dmp.step(batch.times[j], pos, vel, batch.times[1], start=starts, goal=goals)
    np.testing.assert_allclose(pos, batch.positions[:, -1], atol=1e-10)
    np.testing.assert_allclose(acc, batch.accelerations[:, -1], atol=1e-7)


def test_translate_rollout_matches_a_high_accuracy_ode_solution() -> None:
    dmp = DMP(n_basis=25, scaling="translate").fit(circle(), timing="minimum_jerk", duration=2.0)
    start, goal = np.array([0.3, -0.2]), np.array([2.0, 1.0])
    velocity0 = np.array([0.4, -1.0])
    change = (goal - start) - (dmp.goal_ - dmp.start_)

    def rhs(s: float, x: np.ndarray) -> np.ndarray:
        w, slope, bend = _minimum_jerk_law(np.array([s]))
        # The fixed forcing b = w'' + c w' + k (w − 1) per unit change (module notes).
        extra = (bend + dmp.c * slope + dmp.k * (w - 1.0)) * change
        forcing = dmp.forcing(np.array([s * dmp.duration_]))[0] + extra
        return np.concatenate([x[2:], -dmp.k * x[:2] - dmp.c * x[2:] + forcing])

    x0 = np.concatenate([start - goal, velocity0 * dmp.duration_])
    solution = solve_ivp(
        rhs, (0.0, 1.0), x0, method="DOP853", rtol=1e-12, atol=1e-12, dense_output=True
    )
    rollout = dmp.rollout(start, goal, n_steps=500, start_velocity=velocity0)
    reference = solution.sol(np.linspace(0.0, 1.0, 500))
    np.testing.assert_allclose(rollout.positions, reference[:2].T + goal, atol=1e-9)
    np.testing.assert_allclose(rollout.velocities, reference[2:].T / dmp.duration_, atol=1e-8)


def test_a_closed_circle_is_reproduced_and_moved_with_its_shape_intact() -> None:
    loop = circle()
    dmp = DMP(n_basis="auto", scaling="translate").fit(loop, timing="minimum_jerk")
    size = extent(loop)
    assert dmp.reproduction_error_ <= 0.01
    reproduction = dmp.rollout(n_steps=400).positions
    assert held_out_distances(reproduction, loop)["max"] < 0.01 * size
    shift = np.array([3.0, -1.5])
    moved = dmp.rollout(start=loop[0] + shift, goal=loop[-1] + shift, n_steps=400).positions
    # A translated start and goal translate the whole circle: no distortion at all.
    np.testing.assert_allclose(moved, reproduction + shift, atol=1e-12)
    assert held_out_distances(moved, loop + shift)["max"] < 0.01 * size


def test_a_closed_circle_goes_to_a_new_start_and_a_different_goal() -> None:
    loop = circle()
    size = extent(loop)
    translate = DMP(n_basis="auto", scaling="translate").fit(loop, timing="minimum_jerk")
    start, goal = loop[0] + [0.2, 0.1], loop[-1] + [-0.1, 0.3]
    rollout = translate.rollout(start=start, goal=goal, n_steps=400).positions
    np.testing.assert_allclose(rollout[[0, -1]], [start, goal], atol=1e-9)
    # Each point moves by at most the larger offset: the circle is not blown up.
    largest = max(np.linalg.norm(start - loop[0]), np.linalg.norm(goal - loop[-1]))
    reproduction = translate.rollout(n_steps=400).positions
    assert np.linalg.norm(rollout - reproduction, axis=1).max() <= largest + 1e-12
    # It is the warp of the reproduction, and close to the warp of the circle.
    assert held_out_distances(rollout, warp_path(loop, start, goal))["max"] < 0.01 * size
    # The rigid scalings have no direction to turn a closed path by: refused.
    spatial = DMP(n_basis=20, scaling="spatial").fit(loop, timing="minimum_jerk")
    with pytest.raises(ValueError, match="scaling='translate'"):
        spatial.rollout(start=start, goal=goal)


@pytest.mark.parametrize("units", [1.0, 1e-3, 1e3])
def test_a_nearly_closed_loop_carried_to_a_displaced_goal_is_not_blown_up(units: float) -> None:
    # 350° of a circle: the training start→goal vector is 9 % of the extent.
    loop = units * circle(turns=350.0 / 360.0)
    size = extent(loop)
    goal = loop[-1] + units * np.array([0.25, 0.1])
    translate = DMP(n_basis="auto", scaling="translate").fit(loop, timing="minimum_jerk")
    rollout = translate.rollout(goal=goal, n_steps=400).positions
    reproduction = translate.rollout(n_steps=400).positions
    displacement = np.linalg.norm(goal - loop[-1])
    assert np.linalg.norm(rollout - reproduction, axis=1).max() <= displacement * (1 + 1e-9)
    assert extent(rollout) < size + 2.0 * displacement
    np.testing.assert_allclose(rollout[-1], goal, atol=1e-9 * size)
    # The rigid scaling magnifies the loop by the ratio of the two short vectors, and says so.
    spatial = DMP(n_basis="auto", scaling="spatial").fit(loop, timing="minimum_jerk")
    with pytest.warns(RuntimeWarning, match="scaling='translate' keeps the shape"):
        blown = spatial.rollout(goal=loop[-1] + units * np.array([2.5, 0.0]), n_steps=400)
    assert extent(blown.positions) > 5.0 * size


def test_translate_keeps_a_straight_line_straight_up_to_the_reproduction_error() -> None:
    path = np.linspace([0.0, 0.0, 0.0], [3.0, 1.0, -2.0], 50)
    dmp = DMP(n_basis=15, scaling="translate").fit(path, timing="minimum_jerk")
    start = np.array([0.5, 0.0, 0.0])
    goals = np.array([[3.0, 1.0, -2.0], [1.0, 4.0, 2.0], [-2.0, -1.0, 0.5]])
    rollouts = dmp.rollout(start=start, goal=goals)
    for goal, positions in zip(goals, rollouts.positions, strict=True):
        direction = (goal - start) / np.linalg.norm(goal - start)
        offsets = positions - start
        off_line = offsets - np.outer(offsets @ direction, direction)
        # Off the line by no more than the reproduction lags the line's own timing.
        assert np.linalg.norm(off_line, axis=1).max() <= 1.05 * dmp.reproduction_error_ * 3.0
