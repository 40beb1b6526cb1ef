"""Tests for lfdkit.emulate._planner_numpy: the NumPy kernels give numba's plans.

Whole plans on random scenes (2-D and 3-D, with and without clearance, MPC
and full horizon) are planned once with each form (``LFDKIT_KERNELS``), and
the kernels are compared call by call on random problems. The forms do the
same operations in the same order, so plans agree bit for bit where NumPy's
``exp`` and LAPACK's Cholesky are the ones numba calls; the assertions allow
round-off (1e-9), and exact agreement is asserted separately where it holds by
construction (2-D, no Cholesky) and NumPy's ``exp`` is libm's. On AVX-512
processors NumPy's own SIMD ``exp`` differs from libm's in the last bit for some
arguments; there the 2-D forms agree to 1e-12 instead.
"""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from lfdkit.core import kernels
from lfdkit.core.memo import DigestMemo
from lfdkit.emulate import Corridor, Reward, plan_path
from lfdkit.emulate import _planner_kernels as compiled_grid
from lfdkit.emulate import _planner_numpy as numpy_form
from lfdkit.emulate import _problem_kernels as compiled
from lfdkit.emulate.problem import Problem
from lfdkit.imitate import _dmp_kernels
from lfdkit.imitate._dmp_numerics import evaluate_quintic_pieces
from lfdkit.model.scene import Obstacle, Scene

# Whether NumPy's exp is libm's (numba's) on this processor, bit for bit.
_ARGUMENTS = np.linspace(-50.0, 5.0, 20001)
EXP_IS_LIBM = np.exp(_ARGUMENTS).tolist() == [math.exp(v) for v in _ARGUMENTS.tolist()]


def assert_same_numbers(actual, desired) -> None:
    """Bit for bit where NumPy's exp is libm's, else to round-off (1e-12 of the largest)."""
    if EXP_IS_LIBM:
        np.testing.assert_array_equal(actual, desired)
    else:
        scale = float(np.max(np.abs(desired), initial=0.0))
        np.testing.assert_allclose(actual, desired, rtol=1e-12, atol=1e-12 * scale)


REWARD = Reward(10.0, {"a": [2500.0, 215.0], "b": [400.0, 900.0]})
REWARD_3D = Reward(10.0, {"a": [2500.0, 300.0, 215.0], "b": [400.0, 600.0, 900.0]})


def scene_along(nominal: np.ndarray, seed: int, count: int) -> Scene:
    """``count`` obstacles near random points of ``nominal`` (classes a and b)."""
    rng = np.random.default_rng(seed)
    obstacles = []
    for k in rng.integers(10, len(nominal) - 10, size=count):
        centre = nominal[k] + rng.uniform(-0.06, 0.06, nominal.shape[1])
        radius = float(rng.uniform(0.0, 0.03))
        obstacles.append(Obstacle(str(rng.choice(["a", "b"])), centre, radius=radius))
    return Scene(tuple(obstacles))


def nominal_path(q: int, bend: float) -> np.ndarray:
    t = np.linspace(0.0, 1.0, 150)
    columns = [0.8 * t, bend * np.sin(np.pi * t)] + ([0.2 * t * t] if q == 3 else [])
    return np.column_stack(columns)


def both(monkeypatch: pytest.MonkeyPatch, **plan_args):
    """The plan with numba's kernels and with the NumPy forms (or the error each raised)."""
    plans = []
    for form in ("numba", "numpy"):
        monkeypatch.setenv(kernels.KERNELS_VARIABLE, form)
        try:
            plans.append(plan_path(**plan_args))
        except ValueError as error:  # an unsafe scene: both must refuse it alike
            plans.append(str(error))
    return plans


@settings(
    max_examples=8, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    seed=st.integers(0, 10_000),
    count=st.integers(1, 3),
    bend=st.floats(-0.15, 0.15),
    horizon=st.sampled_from([None, 4, 8]),
    clearance=st.sampled_from([0.0, 0.01]),
)
def test_numpy_plans_are_numbas_in_2d(monkeypatch, seed, count, bend, horizon, clearance) -> None:
    nominal = nominal_path(2, bend)
    compiled_plan, numpy_plan = both(
        monkeypatch,
        reward=REWARD,
        nominal=nominal,
        scene=scene_along(nominal, seed, count),
        horizon=horizon,
        n_points=30,
        clearance=clearance,
    )
    if isinstance(compiled_plan, str):
        assert numpy_plan == compiled_plan
        return
    # Same operations in the same order, no LAPACK in 2-D: the same plan, bit for bit
    # (else last-bit differences in exp move Newton's iterates within its tolerance).
    if EXP_IS_LIBM:
        np.testing.assert_array_equal(numpy_plan.points, compiled_plan.points)
        assert (numpy_plan.cost, numpy_plan.n_iter) == (compiled_plan.cost, compiled_plan.n_iter)
    else:
        scale = np.abs(compiled_plan.points).max()
        np.testing.assert_allclose(numpy_plan.points, compiled_plan.points, atol=1e-9 * scale)
        assert numpy_plan.cost == pytest.approx(compiled_plan.cost, rel=1e-9)


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("horizon", [None, 6])
def test_numpy_plans_are_numbas_in_3d(monkeypatch, seed: int, horizon: int | None) -> None:
    # 3-D solves a 2×2-block system by Cholesky (NumPy's LAPACK against the one numba
    # calls): the plans agree to round-off.
    nominal = nominal_path(3, 0.1)
    compiled_plan, numpy_plan = both(
        monkeypatch,
        reward=REWARD_3D,
        nominal=nominal,
        scene=scene_along(nominal, seed, 2),
        horizon=horizon,
        n_points=30,
        clearance=0.01,
    )
    scale = np.abs(compiled_plan.points).max()
    np.testing.assert_allclose(numpy_plan.points, compiled_plan.points, rtol=0, atol=1e-9 * scale)
    assert numpy_plan.cost == pytest.approx(compiled_plan.cost, rel=1e-9)


def random_problem(seed: int, q: int, clearance: float) -> tuple[Problem, np.ndarray]:
    """A problem with obstacles (hard radii when ``clearance``) and random offsets near them."""
    nominal = nominal_path(q, 0.1)
    reward = REWARD if q == 2 else REWARD_3D
    corridor = Corridor.from_path(nominal, 50)
    problem = Problem.from_scene(
        reward, corridor, scene_along(nominal, seed, 3), 1.0, "auto", clearance=clearance
    )
    rng = np.random.default_rng(seed)
    return problem, rng.uniform(-0.03, 0.03, (problem.n, problem.m))


@pytest.mark.parametrize("q", [2, 3])
@pytest.mark.parametrize("seed", range(4))
def test_kernels_agree_call_by_call(q: int, seed: int) -> None:
    problem, d = random_problem(seed, q, 0.01)
    args = problem.kernel_arguments()
    assert_same_numbers(numpy_form.planner_cost(*args, d), compiled.planner_cost(*args, d))
    gradients = [np.empty_like(d) for _ in range(2)]
    hessians = [np.empty((problem.n, problem.m, problem.m)) for _ in range(2)]
    totals = [
        form.planner_derivatives(*args, d, g, h)
        for form, g, h in zip((compiled, numpy_form), gradients, hessians, strict=True)
    ]
    assert_same_numbers(totals[0], totals[1])
    assert_same_numbers(gradients[0], gradients[1])
    assert_same_numbers(hessians[0], hessians[1])
    # The solver from a start outside every hard radius (the nominal, if it is).
    start = np.zeros((problem.n, problem.m))
    results = []
    for form in (compiled, numpy_form):
        out = start.copy()
        cost, n_iter, ok = form.planner_newton(
            *args, problem.max_step, np.zeros(problem.m), out, 1e-10, 100
        )
        results.append((out, cost, n_iter, ok))
    (d_c, cost_c, iter_c, ok_c), (d_n, cost_n, iter_n, ok_n) = results
    assert ok_n == ok_c
    if np.isfinite(cost_c):
        np.testing.assert_allclose(d_n, d_c, rtol=0, atol=1e-9 * max(np.abs(d_c).max(), 1e-3))
        assert cost_n == pytest.approx(cost_c, rel=1e-9)
    if q == 2:  # no Cholesky: the same numbers
        assert_same_numbers(d_n, d_c)
        assert_same_numbers(cost_n, cost_c)
        if EXP_IS_LIBM:
            assert iter_n == iter_c


@pytest.mark.parametrize("clearance", [0.0, 0.01])
@pytest.mark.parametrize("seed", range(3))
def test_scalar_newton_is_numbas_on_short_windows(seed: int, clearance: float) -> None:
    # The receding horizon's 2-D windows run on Python floats: every window of a problem
    # (some against a bound, some near a hard radius), from random starts, bit for bit.
    problem, _ = random_problem(seed, 2, clearance)
    rng = np.random.default_rng(seed)
    compared = 0
    for start in range(0, problem.n - 8, 3):
        window = problem.window(start, start + 8)
        args = window.kernel_arguments()
        assert 8 * (1 + args[0].shape[1] + args[4].shape[1]) <= numpy_form.SCALAR_TERMS
        d0 = rng.uniform(-0.02, 0.02, 1)
        init = rng.uniform(-0.04, 0.04, (8, 1))
        results = []
        for solve in (compiled.planner_newton, numpy_form.planner_newton_scalar):
            out = init.copy()
            results.append((solve(*args, window.max_step, d0, out, 1e-10, 100), out))
        (found_c, d_c), (found_s, d_s) = results
        np.testing.assert_array_equal(d_s, d_c)
        assert tuple(found_s) == tuple(found_c)
        compared += np.isfinite(found_c[0])
    assert compared >= 5  # most starts lie outside the hard radii


@pytest.mark.parametrize("points", [8, 16])
@pytest.mark.parametrize("seed", range(2))
def test_short_windows_among_many_obstacles_run_on_floats(monkeypatch, seed, points) -> None:
    # A declined gap's row of side blockers gives the receding horizon's windows 13-21
    # obstacles and as many hard radii: far more terms than SCALAR_TERMS, but a short
    # window still solves on Python floats (the vectorised form paid NumPy's cost per
    # call once per term: a random sweeping scene planned 3x slower), numba's bit for bit.
    nominal = nominal_path(2, 0.1)
    rng = np.random.default_rng(seed)
    # Two obstacles and a row of 14 small ones beside the path, 4-6 cm off it.
    row = nominal[rng.choice(np.arange(20, 130), 16, replace=False)]
    row[:, 1] += rng.uniform(0.04, 0.06, 16)
    radii = [0.02, 0.02] + [0.009] * 14
    labels = rng.choice(["a", "b"], 16).tolist()
    scene = Scene(
        tuple(Obstacle(k, c, radius=r) for k, c, r in zip(labels, row, radii, strict=True))
    )
    problem = Problem.from_scene(
        REWARD, Corridor.from_path(nominal, 50), scene, 1.0, "auto", clearance=0.01
    )
    scalar = numpy_form.planner_newton_scalar
    calls = []
    monkeypatch.setattr(
        numpy_form, "planner_newton_scalar", lambda *args: calls.append(1) or scalar(*args)
    )
    compared = 0
    for start in range(0, problem.n - points, 5):
        window = problem.window(start, start + points)
        args = window.kernel_arguments()
        assert points * (1 + args[0].shape[1] + args[4].shape[1]) > numpy_form.SCALAR_TERMS
        d0 = rng.uniform(-0.02, 0.02, 1)
        init = rng.uniform(-0.02, 0.02, (points, 1))
        results = []
        for solve in (compiled.planner_newton, numpy_form.planner_newton):
            out = init.copy()
            results.append((solve(*args, window.max_step, d0, out, 1e-10, 100), out))
        (found_c, d_c), (found_n, d_n) = results
        np.testing.assert_array_equal(d_n, d_c)
        assert tuple(found_n) == tuple(found_c)
        compared += np.isfinite(found_c[0])
    assert len(calls) == len(range(0, problem.n - points, 5))
    assert compared >= 3


@pytest.mark.parametrize("seed", range(3))
def test_2d_grid_node_costs_are_each_states_point_cost(seed: int) -> None:
    # The compiled 2-D states' costs go term by term over the levels: each state's sum
    # is still point_cost's (the weight, the obstacles not negligible at the point, the
    # hard radii, in that order), to the bit; here on Python floats with libm's exp
    # (numba's). The levels reach into the hard radii (+inf) and far aside.
    problem, _ = random_problem(seed, 2, 0.02)
    c, b, a, weight, rr, nr, inner2, outer2, mu = problem.kernel_arguments()
    levels = np.linspace(-0.15, 0.15, 61)
    out = np.empty((problem.n, levels.size))
    compiled_grid.grid_node_costs(c, b, a, weight, rr, nr, inner2, outer2, mu, levels, out)
    barrier = compiled.barrier.py_func
    expected = np.empty_like(out)
    left_out = 0
    for k in range(problem.n):
        near = [o for o in range(c.shape[1]) if c[k, o] - b[k, o, 0] ** 2 / a[k, o, 0, 0] < 40.0]
        left_out += c.shape[1] - len(near)
        hit = [h for h in range(rr.shape[1]) if rr[k, h] - nr[k, h, 0] ** 2 < outer2[h]]
        for s, g in enumerate(levels.tolist()):
            total = 0.0 + float(weight[k]) * g * g
            for o in near:
                ck, bk, ak = float(c[k, o]), float(b[k, o, 0]), float(a[k, o, 0, 0])
                total += math.exp(-(ck + (bk + (bk + ak * g)) * g))
            for h in hit:
                u = float(rr[k, h]) + (2.0 * float(nr[k, h, 0]) + g) * g
                total += barrier(u, float(inner2[h]), float(outer2[h]), mu)[0]
            expected[k, s] = total
    assert np.isinf(out).any() and np.isfinite(out).mean() > 0.5 and left_out > 0
    np.testing.assert_array_equal(out, expected)


@pytest.mark.parametrize("seed", range(3))
def test_3d_grid_node_costs_are_each_states_point_cost(seed: int) -> None:
    # The compiled 3-D states' costs go term by term over the states, and each hard
    # radius only over the states of its disc: each state's sum is still point_cost's
    # (the weight, the obstacles not negligible at the point, the hard radii, in that
    # order), to the bit. The levels reach into the hard radii (+inf) and far aside;
    # falling levels take the state-by-state path, the same numbers.
    problem, _ = random_problem(seed, 3, 0.02)
    args = problem.kernel_arguments()
    c, b, a, _, rr, nr, inner2, outer2, _ = args
    levels = np.linspace(-0.12, 0.12, 25)
    g_count = levels.size
    out = np.empty((problem.n, g_count**2))
    compiled_grid.grid_node_costs(*args, levels, out)
    expected = np.empty_like(out)
    in_barrier = 0
    for k in range(problem.n):
        (a00, a01), (a10, a11) = a[k, :, 0].T, a[k, :, 1].T
        b0, b1 = b[k].T
        det = np.maximum(a00 * a11 - a01 * a10, 1e-300)
        lowest = c[k] - (a11 * b0**2 - 2.0 * a01 * b0 * b1 + a00 * b1**2) / det
        near = np.flatnonzero(lowest < 40.0)
        hit = np.flatnonzero(rr[k] - nr[k, :, 0] ** 2 - nr[k, :, 1] ** 2 < outer2)
        for s in range(g_count**2):
            g = np.array([levels[s // g_count], levels[s % g_count]])
            expected[k, s] = compiled.point_cost(*args, k, g, near, hit)
            u = rr[k, hit] + ((2.0 * nr[k, hit] + g) * g).sum(axis=1)
            in_barrier += int(np.any((u < outer2[hit]) & (u > inner2[hit])))
    assert np.isinf(out).any() and np.isfinite(out).mean() > 0.5 and in_barrier > 0
    np.testing.assert_array_equal(out, expected)
    falling = np.empty_like(out)
    compiled_grid.grid_node_costs(*args, levels[::-1].copy(), falling)
    np.testing.assert_array_equal(falling[:, ::-1], out)


@pytest.mark.parametrize("seed", range(2))
def test_3d_windows_share_their_points_states_costs(monkeypatch, seed: int) -> None:
    # The 3-D receding horizon's windows on the same levels take each point's states'
    # costs from the last window (planner._WindowNodes, issue 34): the same plan, to the
    # bit, as each window computing its own.
    from lfdkit.emulate import planner

    nominal = nominal_path(3, 0.1)
    scene = scene_along(nominal, seed, 3)
    args = {"horizon": 8, "lookahead": False, "goal_approach": None, "clearance": 0.01}
    asked, computed = [], []
    original = planner._WindowNodes

    class Counted(original):
        def costs(self, start, stop, levels):
            before = (self.levels, self.first, self.stop)
            out = super().costs(start, stop, levels)
            again = before[0] != self.levels or not before[1] <= start <= before[2]
            asked.append(stop - start)
            computed.append(stop - start if again else max(stop - before[2], 0))
            return out

    monkeypatch.setattr(planner, "_WindowNodes", Counted)
    shared = plan_path(REWARD_3D, nominal, scene, **args).points

    class Fresh(original):
        def costs(self, start, stop, levels):
            return original(self.problem).costs(start, stop, levels)

    monkeypatch.setattr(planner, "_WindowNodes", Fresh)
    own = plan_path(REWARD_3D, nominal, scene, **args).points
    assert asked and sum(computed) < sum(asked)
    np.testing.assert_array_equal(shared, own)


@pytest.mark.parametrize("q", [2, 3])
@pytest.mark.parametrize("seed", range(2))
def test_states_costs_shared_across_hard_radii_are_the_same_numbers(
    monkeypatch, q: int, seed: int
) -> None:
    # planner._node_costs takes the obstacles' terms from a memo keyed by the reward's
    # arrays and the levels, and adds each problem's own hard radii (issue 34): on a
    # second problem of the same scene with other radii (a hit), and in either kernel
    # form, the numbers are grid_node_costs' to the bit; other levels are not a hit.
    from lfdkit.emulate import planner

    nominal = nominal_path(q, 0.1)
    reward = REWARD if q == 2 else REWARD_3D
    corridor = Corridor.from_path(nominal, 50)
    scene = scene_along(nominal, seed, 3)
    levels = np.linspace(-0.12, 0.12, 41 if q == 2 else 21)
    width = levels.size ** (q - 1)
    memo = DigestMemo(max_bytes=64 << 20)
    monkeypatch.setattr(planner, "_STATE_COSTS", memo)
    for name, form in (("numba", compiled_grid), ("numpy", numpy_form)):
        monkeypatch.setenv(kernels.KERNELS_VARIABLE, name)
        for clearance in (0.0, 0.01, 0.02):
            problem = Problem.from_scene(reward, corridor, scene, 1.0, "auto", clearance=clearance)
            args = problem.kernel_arguments()
            whole = np.empty((problem.n, width))
            form.grid_node_costs(*args, levels, whole)
            parts = np.empty_like(whole)
            form.grid_state_costs(*args[:4], levels, parts)
            form.grid_hard_costs(*args[4:], levels, parts)
            np.testing.assert_array_equal(parts, whole)
            np.testing.assert_array_equal(planner._node_costs(problem, levels), whole)
    # One entry per reward, levels and kernel form, whatever the hard radii.
    assert len(memo) == 2
    # A copy handed out each time: the caller's changes do not reach the kept one.
    problem = Problem.from_scene(reward, corridor, scene, 1.0, "auto", clearance=0.01)
    first = planner._node_costs(problem, levels)
    expected = first.copy()
    first[:] = -1.0
    np.testing.assert_array_equal(planner._node_costs(problem, levels), expected)
    assert len(memo) == 2
    planner._node_costs(problem, levels * 0.5)
    assert len(memo) == 3


@pytest.mark.parametrize("q", [2, 3])
@pytest.mark.parametrize("end_zero", [False, True])
def test_grid_search_agrees(q: int, end_zero: bool) -> None:
    problem, _ = random_problem(7, q, 0.01)
    args = problem.kernel_arguments()
    levels = np.linspace(-0.1, 0.1, 21 if q == 2 else 11)
    rng = np.random.default_rng(q)
    extra = np.where(rng.random((problem.n, levels.size**problem.m)) < 0.05, np.inf, 0.0)
    outs = []
    for form in (compiled_grid, numpy_form):
        out = np.zeros((problem.n, problem.m))
        total = form.lateral_dp(
            *args, problem.max_step, np.zeros(problem.m), levels, 2, end_zero, extra, out
        )
        outs.append((total, out))
    assert outs[1][0] == outs[0][0]
    np.testing.assert_array_equal(outs[1][1], outs[0][1])


def test_quintic_pieces_agree() -> None:
    rng = np.random.default_rng(0)
    pieces = rng.normal(size=(17, 6, 3))
    s = np.concatenate([rng.uniform(0.0, 1.0, 200), [0.0, 1.0]])
    outs = [np.empty((3, 3, s.size)) for _ in range(2)]
    _dmp_kernels.evaluate_quintic_pieces(s, 1.0 / 17, pieces, outs[0])
    evaluate_quintic_pieces(s, 1.0 / 17, pieces, outs[1])
    np.testing.assert_array_equal(outs[1], outs[0])


def test_the_choice_follows_the_variable(monkeypatch) -> None:
    monkeypatch.setenv(kernels.KERNELS_VARIABLE, "numpy")
    assert kernels.kernel("planner_cost", compiled.__name__, numpy_form.__name__) is (
        numpy_form.planner_cost
    )
    monkeypatch.setenv(kernels.KERNELS_VARIABLE, "numba")
    assert kernels.kernel("planner_cost", compiled.__name__, numpy_form.__name__) is (
        compiled.planner_cost
    )
    monkeypatch.setenv(kernels.KERNELS_VARIABLE, "fast")
    with pytest.raises(ValueError, match=r"LFDKIT_KERNELS='fast'.*auto, numba, numpy"):
        kernels.use_compiled()


def test_auto_turns_to_numba_after_the_switch_seconds(monkeypatch) -> None:
    # numba is loaded in this test process, so auto is numba's; without it, the
    # NumPy forms serve until the process has spent SWITCH_SECONDS of CPU since.
    monkeypatch.setenv(kernels.KERNELS_VARIABLE, "auto")
    assert kernels.use_compiled()
    monkeypatch.delitem(sys.modules, "numba")
    clock = {"cpu_start": None, "next_look": 0.0, "switched": False}
    monkeypatch.setattr(kernels, "_clock", clock)
    names = ("planner_cost", compiled.__name__, numpy_form.__name__)
    assert kernels.kernel(*names) is numpy_form.planner_cost
    assert clock["cpu_start"] is not None  # the first NumPy form starts the clock
    assert kernels.kernel(*names) is numpy_form.planner_cost
    clock["cpu_start"] -= kernels.SWITCH_SECONDS  # as if a second of CPU had passed
    assert kernels.kernel(*names) is numpy_form.planner_cost  # not looked at yet (wall clock)
    clock["next_look"] = 0.0
    assert kernels.kernel(*names) is compiled.planner_cost
    assert clock["switched"]
