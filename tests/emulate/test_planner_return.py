"""A slow return: the receding horizon's step back toward the nominal bounded (issue 26).

A late, reactive person swerves steeply and comes back slowly; the thesis's
model has no action cost, so below the symmetric action bound that cannot be
expressed. ``plan_path(return_fraction=r)`` bounds each executed step toward
the nominal by ``r · max_step`` (steps away keep ``max_step``), in the
compiled 2-D loop and in its NumPy form alike; the fit measures ``r`` from the
demonstrations (:func:`lfdkit.emulate.ioc.demonstrated_return`).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from lfdkit.core import kernels
from lfdkit.emulate import Reward, UnsafePlanError, plan_path, planner
from lfdkit.emulate import _planner_kernels as compiled
from lfdkit.emulate import _planner_numpy as numpy_forms
from lfdkit.emulate.ioc import demonstrated_return, prepare_demos
from lfdkit.emulate.problem import Corridor
from lfdkit.model.scene import Obstacle, Scene

from .test_ioc_slope import straight, swerve

REWARD = Reward(10.0, {"cup": [2500.0, 215.0]})
N_POINTS = 60


def line() -> np.ndarray:
    x = np.linspace(0.0, 1.0, N_POINTS)
    return np.column_stack([x, np.zeros_like(x)])


def steps(plan) -> tuple[np.ndarray, np.ndarray]:
    """Each step's size toward the nominal and away from it, in action bounds (1 step = 1/59)."""
    d = plan.offsets[:, 0]
    step = np.diff(d) * (N_POINTS - 1)
    toward = np.sign(d[:-1]) * step < 0.0
    return np.where(toward, np.abs(step), 0.0), np.where(toward, 0.0, np.abs(step))


@pytest.mark.parametrize("fraction", [0.2, 0.5])
@pytest.mark.parametrize("lookahead", [False, True])
def test_steps_back_are_bounded_and_steps_out_keep_the_bound(fraction, lookahead) -> None:
    scene = Scene((Obstacle("cup", [0.4, 0.01], 0.02),))
    args = dict(horizon=8, lookahead=lookahead, n_points=N_POINTS, goal_approach=None)
    free = plan_path(REWARD, line(), scene, **args)
    slow = plan_path(REWARD, line(), scene, return_fraction=fraction, **args)
    back, out = steps(slow)
    assert back.max() <= fraction * (1.0 + 1e-9)
    assert out.max() == pytest.approx(1.0)  # the swerve still at the action bound
    assert steps(free)[0].max() == pytest.approx(1.0)  # without it, back as steeply
    # The same swerve out; it returns later and ends no farther from the nominal.
    top = int(np.argmax(np.abs(free.offsets[:, 0])))
    np.testing.assert_array_equal(slow.offsets[: top + 1], free.offsets[: top + 1])
    assert np.abs(slow.offsets[top + 1 :, 0]).sum() > np.abs(free.offsets[top + 1 :, 0]).sum()
    assert slow.clearance.min() >= 0.0


def test_a_fraction_of_one_is_the_symmetric_plan_bit_for_bit() -> None:
    scene = Scene((Obstacle("cup", [0.4, 0.01], 0.02), Obstacle("cup", [0.7, -0.02], 0.01)))
    args = dict(horizon=8, lookahead=False, n_points=N_POINTS, clearance=0.01)
    np.testing.assert_array_equal(
        plan_path(REWARD, line(), scene, return_fraction=1.0, **args).points,
        plan_path(REWARD, line(), scene, **args).points,
    )


def test_the_numpy_form_clamps_as_the_kernel() -> None:
    rng = np.random.default_rng(3)
    for _ in range(200):
        m = int(rng.integers(1, 3))
        anchor = rng.normal(0.0, 1.0, m) * (rng.random(m) > 0.2)  # some exactly 0
        new = anchor + rng.normal(0.0, 1.0, m)
        back = float(rng.uniform(0.05, 1.0))
        a, b = new.copy(), new.copy()
        compiled.return_clamped(anchor, a, back)
        numpy_forms.return_clamped(anchor, b, back)
        np.testing.assert_array_equal(a, b)
        toward = np.where(anchor > 0.0, anchor - a, np.where(anchor < 0.0, a - anchor, 0.0))
        assert np.all(toward <= back * (1.0 + 1e-12))


@pytest.mark.parametrize("seed", range(3))
def test_the_compiled_loop_bounds_as_the_python_loop(monkeypatch, seed: int) -> None:
    monkeypatch.setenv(kernels.KERNELS_VARIABLE, "numba")
    rng = np.random.default_rng(seed)
    path = line()
    scene = Scene(
        tuple(
            Obstacle("cup", path[k] + [0.0, rng.normal(0.0, 0.03)], float(rng.uniform(0, 0.02)))
            for k in rng.integers(10, N_POINTS - 10, size=3)
        )
    )
    plans = []
    for use in (False, True):
        monkeypatch.setattr(planner, "use_compiled", lambda use=use: use)
        try:
            plans.append(
                plan_path(
                    REWARD,
                    path,
                    scene,
                    horizon=8,
                    lookahead=False,
                    n_points=N_POINTS,
                    return_fraction=0.3,
                    clearance=0.005,
                ).points
            )
        except UnsafePlanError as error:
            plans.append(str(error))
    if isinstance(plans[0], str):
        assert plans[1] == plans[0]
    else:
        np.testing.assert_array_equal(plans[1], plans[0])


@pytest.mark.xfail(
    strict=True,
    raises=UserWarning,
    reason="a slow return cannot cross the nominal in time for an S-curve's next obstacle: "
    "the bounded plan is refused and the plan without the bound made (planner's design record)",
)
def test_an_s_curve_is_planned_with_the_slow_return() -> None:
    # Below the nominal round the first cup, above it round the second. Returning at 0.3
    # of the bound, the way across takes longer than the gap between the cups allows.
    scene = Scene((Obstacle("cup", [0.3, -0.02], 0.02), Obstacle("cup", [0.6, 0.02], 0.02)))
    args = dict(horizon=8, lookahead=False, n_points=N_POINTS, goal_approach=None)
    free = plan_path(REWARD, line(), scene, **args)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no fallback to the plan without the bound
        slow = plan_path(REWARD, line(), scene, return_fraction=0.3, **args)
    d = slow.offsets[:, 0]
    at = [round(u * (N_POINTS - 1)) for u in (0.3, 0.6)]
    assert d[at[0]] > 0.0 > d[at[1]]  # above the first cup, below the second
    assert free.offsets[at[0], 0] > 0.0 > free.offsets[at[1], 0]  # as without the bound
    # Every step back that does not go on across the nominal is slow.
    back, _ = steps(slow)
    across = [np.any(np.sign(d[k + 1 : k + 9]) * np.sign(d[k]) < 0.0) for k in range(len(d) - 1)]
    assert back[~np.array(across)].max() <= 0.3 * (1.0 + 1e-9)


def test_where_no_bounded_plan_passes_the_plan_without_it_is_warned() -> None:
    # Up round the first ball, then a wide ball just above the nominal: the slow return
    # cannot come back under it in time. The plan with the whole bound, said; the whole
    # path's plan returns no more slowly here, so the receding horizon's.
    path = line()
    scene = Scene((Obstacle("cup", [0.30, -0.005], 0.03), Obstacle("cup", [0.5, 0.14], 0.12)))
    args = dict(horizon=8, lookahead=False, n_points=N_POINTS, goal_approach=None)
    free = plan_path(REWARD, path, scene, **args)
    with pytest.warns(UserWarning, match="returns to the nominal at most 0.05"):
        plan = plan_path(REWARD, path, scene, return_fraction=0.05, **args)
    np.testing.assert_array_equal(plan.points, free.points)


def test_the_fast_return_of_offsets_is_summed_past_the_bound() -> None:
    # Out 0.1, back 0.05 (0.04 past 0.01), across the nominal from 0.05 to -0.02 (only
    # the 0.05 down to 0 is toward it: 0.04 past), out again, back 0.005 (within).
    d = np.array([[0.0], [0.1], [0.05], [-0.02], [-0.03], [-0.025]])
    assert planner.fast_return(d, 0.01) == pytest.approx(0.08)
    assert planner.fast_return(d, 0.1) == 0.0
    two = np.column_stack([d[:, 0], -d[:, 0]])  # per component: twice
    assert planner.fast_return(two, 0.01) == pytest.approx(0.16)


def test_a_refused_slow_return_keeps_the_side_the_whole_path_plan_keeps() -> None:
    # The fidelity benchmark's late person, seed 2, an S-curve new task (rounded): the
    # first box passed 5.7 cm below the nominal; the windows then cross over the second
    # box, which a return at 0.21 of the bound cannot, so the bounded plan is refused.
    # The person, still below, goes under the second box; so does the plan over the
    # whole path, which returns far less steeply, and is the plan made.
    u = np.linspace(0.0, 1.0, 400)
    nominal = np.column_stack([0.8 * u, 0.08 * np.sin(2.0 * np.pi * u)])
    reward = Reward(0.00175, {"box": [357.0, 3488.0], "cup": [436.0, 3978.0]})
    scene = Scene(
        (
            Obstacle("box", [0.1475, 0.0906], 0.05),
            Obstacle("box", [0.3624, 0.0048], 0.05),
            Obstacle("cup", [0.6952, -0.1428], 0.03),
        )
    )
    args = dict(
        n_points=100, max_slope=1.0, goal_approach="auto", clearance=[0.0094, 0.0094, 0.023]
    )
    windows = plan_path(reward, nominal, scene, horizon=8, lookahead=False, **args)
    with pytest.warns(UserWarning, match="returns to the nominal at most 0.21"):
        plan = plan_path(
            reward, nominal, scene, horizon=8, lookahead=False, return_fraction=0.21, **args
        )
    first, second = 18, 45  # the points nearest the two boxes
    assert windows.offsets[first, 0] < 0.0 < windows.offsets[second, 0]  # a weave
    assert plan.offsets[first, 0] < 0.0 and plan.offsets[second, 0] < 0.0  # under both
    back = 0.21 * 1.0 * Corridor.from_path(nominal, 100).step
    assert planner.fast_return(plan.offsets, back) < planner.fast_return(windows.offsets, back)
    assert plan.clearance.min() >= 0.0


@pytest.mark.parametrize(
    "bad, match",
    [
        (dict(return_fraction=0.0), "return_fraction"),
        (dict(return_fraction=1.5), "return_fraction: expected a fraction"),
        (dict(return_fraction=0.5, horizon=None), "receding horizon's return only"),
    ],
)
def test_bad_fractions_are_refused(bad, match) -> None:
    args = {"horizon": 8, "n_points": N_POINTS, **bad}
    with pytest.raises(ValueError, match=match):
        plan_path(REWARD, line(), Scene((Obstacle("cup", [0.4, 0.01]),)), **args)


@pytest.mark.parametrize("out, back", [(1.5, 0.2), (1.0, 0.4), (0.5, 0.5)])
def test_the_return_slope_of_synthetic_swerves_is_recovered(out: float, back: float) -> None:
    # Three swerves of different heights (the smallest still above half the largest),
    # each out at slope `out` and back at `back` after a held top.
    demos = [swerve(out, back, height) for height in (0.06, 0.08, 0.1)]
    data = prepare_demos(demos, [Scene()] * 3, straight(), 100)
    measured = demonstrated_return(data)
    assert measured["count"] == 3
    assert measured["back"] == pytest.approx(back, rel=0.05)
    assert measured["out"] == pytest.approx(out, rel=0.05)
    assert measured["ratio"] == pytest.approx(back / out, rel=0.08)


def test_small_swerves_and_flat_demonstrations_are_not_measured() -> None:
    demos = [swerve(1.5, 0.2, 0.1), swerve(0.5, 0.5, 0.02), straight()[::3]]
    data = prepare_demos(demos, [Scene()] * 3, straight(), 100)
    measured = demonstrated_return(data)
    assert measured["count"] == 1  # the swerve of 2 cm is below half the largest
    assert measured["back"] == pytest.approx(0.2, rel=0.05)
    flat = demonstrated_return(prepare_demos([straight()[::3]], [Scene()], straight(), 100))
    assert flat["count"] == 0 and np.isnan(flat["back"])
