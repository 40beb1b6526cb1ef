"""NumPy forms of the planner's compiled kernels, for a process without numba.

Same names, arguments and effects as :mod:`._problem_kernels`'
:func:`planner_cost` and :func:`planner_newton` and :mod:`._planner_kernels`'
grid search; :mod:`lfdkit.core.kernels` chooses between the two (a one-shot
``lfdkit plan`` saves numba's ~1.1 s CPU start-up with these). Each point's
arithmetic is vectorised over points and grid states, in the compiled
kernels' order of operations: sums that the compiled loops accumulate one
term at a time are accumulated the same way (``np.add.accumulate``, never
NumPy's pairwise ``sum``), and terms a kernel skips are added as exact zeros.
The steps that depend on the previous one (the line search's clamp to the
predecessor's box, the dynamic programme's backward pass, the grid walk) stay
loops over points. On the receding horizon's short 2-D windows (8 points, one
obstacle or a declined gap's row of side blockers) NumPy's cost per call
outweighs its arithmetic, so the solver runs there on Python floats
(:func:`planner_newton_scalar`, the compiled loops line by line): the README's
example plans in 0.14–0.15 s of CPU instead of 0.33–0.34 s with the vectorised
forms (numba's: about 0.07 s, after its ~1.1 s start-up); a batch runs
numba's. Short windows run on floats whatever their obstacles
(:data:`SCALAR_POINTS`): a random sweeping scene whose declined gap adds a
row of side blockers (13-21 terms a point) plans in 0.2-0.5 s of CPU instead
of 0.7-1.5 s, what a batch worker's first tasks take before numba.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "SCALAR_POINTS",
    "SCALAR_TERMS",
    "block_tree_solve",
    "grid_backward",
    "grid_cost_to_go",
    "grid_hard_costs",
    "grid_node_costs",
    "grid_state_costs",
    "grid_walk",
    "lateral_dp",
    "planner_cost",
    "planner_derivatives",
    "planner_newton",
    "planner_newton_scalar",
    "return_clamped",
]

#: Most terms (points × (1 + obstacles + hard radii)) for which a 2-D solve runs on Python
#: floats (:func:`planner_newton_scalar`): on the receding horizon's windows (8 points, one
#: obstacle) NumPy's cost per call outweighs its vector arithmetic several times over.
SCALAR_TERMS = 96
#: Most points for which a 2-D solve runs on Python floats whatever its terms: the vectorised
#: form pays NumPy's per-call cost once per obstacle and hard radius, the scalar form a Python
#: step per point and term, so short windows stay scalar however many obstacles they see (a
#: declined gap's side blockers: 13-21 terms a point; 8-point windows 0.4-0.8 ms a solve
#: against 2.0-3.2 ms vectorised, 16 points 1.1-2.5 against 3.1-4.8 ms; about even at 32).
SCALAR_POINTS = 16


def _sequential_sum(terms: np.ndarray) -> float:
    """``terms`` (any shape, C order) summed one at a time from 0.0, as a compiled loop does."""
    if terms.size == 0:
        return 0.0
    return float(np.add.accumulate(terms.reshape(-1))[-1])


def _barrier(
    u: np.ndarray, inner2: np.ndarray, outer2: np.ndarray, mu: float, slopes: bool = True
) -> tuple:
    """The clearance barrier's value and first two derivatives in ``u`` (elementwise).

    As ``_problem_kernels.barrier``: 0 (and zero slopes) from ``outer2`` on,
    ``+inf`` (zero slopes) from ``inner2`` in. Computed where ``u`` lies
    between, the rest set afterwards (no division by zero to silence);
    without ``slopes`` the derivatives are None (the cost alone needs none).
    """
    closer = u < outer2
    between = closer & (u > inner2)
    if not between.any():  # the usual case: far from every hard radius, or inside one
        zeros = np.zeros(between.shape)
        return (np.where(closer, np.inf, 0.0) if closer.any() else zeros), zeros, zeros
    kappa = 1.0 / np.where(outer2 > inner2, outer2 - inner2, 1.0)
    t = np.where(between, (outer2 - u) * kappa, 0.5)
    one = 1.0 - t
    value = np.where(between, mu * t * t * t / one, np.where(closer, np.inf, 0.0))
    if not slopes:
        return value, None, None
    first = -mu * kappa * (3.0 * t * t - 2.0 * t * t * t) / (one * one)
    second = mu * kappa * kappa * (6.0 * t - 6.0 * t * t + 2.0 * t * t * t) / (one * one * one)
    return value, np.where(between, first, 0.0), np.where(between, second, 0.0)


def _bumps(c, b, a, d):
    """Exponents' terms ``exp(−s)`` (n, L) and ``N P u`` (n, L, m) at offsets ``d`` (n, m)."""
    m = d.shape[1]
    if m == 1:  # the same operations, fewer NumPy calls (most windows are 2-D)
        b0 = b[:, :, 0]
        value = b0 + a[:, :, 0, 0] * d
        return np.exp(-(c + (b0 + value) * d)), value[:, :, None]
    s = c.copy()
    npu = np.empty(b.shape)
    for i in range(m):
        value = b[:, :, i]
        for j in range(m):
            value = value + a[:, :, i, j] * d[:, None, j]
        npu[:, :, i] = value
        s = s + (b[:, :, i] + value) * d[:, None, i]
    return np.exp(-s), npu


def _hard_u(rr, nr, d):
    """Squared distances ``u`` (n, H) to the obstacles with a hard radius."""
    if d.shape[1] == 1:
        return rr + (2.0 * nr[:, :, 0] + d) * d
    u = rr.copy()
    for i in range(d.shape[1]):
        u = u + (2.0 * nr[:, :, i] + d[:, None, i]) * d[:, None, i]
    return u


def _cost_terms(c, b, a, weight, rr, nr, inner2, outer2, mu, d):
    """Per point, the cost's terms in the compiled kernels' order (n, m + L + H)."""
    e, _ = _bumps(c, b, a, d)
    barrier = _barrier(_hard_u(rr, nr, d), inner2[None], outer2[None], mu, slopes=False)[0]
    return np.concatenate([weight[:, None] * d * d, e, barrier], axis=1)


def planner_cost(c, b, a, weight, rr, nr, inner2, outer2, mu, d):
    """The planner cost of offsets ``d`` (n, m); ``+inf`` inside a hard radius."""
    terms = _cost_terms(c, b, a, weight, rr, nr, inner2, outer2, mu, d)
    if terms.size == 0:
        return 0.0
    # Each point's cost summed first, then the points' (as the compiled loop over points).
    return _sequential_sum(np.add.accumulate(terms, axis=1)[:, -1])


def planner_derivatives(c, b, a, weight, rr, nr, inner2, outer2, mu, d, gradient, hessian):
    """Cost; fills the gradient (n, m) and Hessian blocks (n, m, m) in the offsets."""
    m = d.shape[1]
    e, npu = _bumps(c, b, a, d)
    u = _hard_u(rr, nr, d)
    value, first, second = _barrier(u, inner2[None], outer2[None], mu)
    total = _sequential_sum(np.concatenate([weight[:, None] * d * d, e, value], axis=1))
    if m == 1:  # the same operations on (n, 1) columns, fewer NumPy calls
        grad, hess = 2.0 * weight[:, None] * d, (2.0 * weight)[:, None]
        for o in range(c.shape[1]):
            e_o, npu_o = e[:, o, None], npu[:, o]
            grad = grad - 2.0 * e_o * npu_o
            hess = hess + e_o * (4.0 * npu_o * npu_o - 2.0 * a[:, o, 0])
        for h in range(rr.shape[1]):
            active = value[:, h, None] != 0.0
            near = nr[:, h] + d
            grad = np.where(active, grad + 2.0 * first[:, h, None] * near, grad)
            added = hess + 4.0 * second[:, h, None] * near * near + 2.0 * first[:, h, None]
            hess = np.where(active, added, hess)
        gradient[:, :] = grad
        hessian[:, :, :] = hess[:, :, None]
        return total
    grad = 2.0 * weight[:, None] * d
    hess = np.zeros((d.shape[0], m, m))
    for i in range(m):
        hess[:, i, i] = 2.0 * weight
    for o in range(c.shape[1]):
        grad = grad - 2.0 * e[:, o, None] * npu[:, o]
        hess = hess + e[:, o, None, None] * (
            4.0 * npu[:, o, :, None] * npu[:, o, None, :] - 2.0 * a[:, o]
        )
    for h in range(rr.shape[1]):
        active = value[:, h] != 0.0  # the compiled loop skips the others
        near = nr[:, h] + d  # (n, m)
        grad = np.where(active[:, None], grad + 2.0 * first[:, h, None] * near, grad)
        added = hess + 4.0 * second[:, h, None, None] * near[:, :, None] * near[:, None, :]
        diagonal = np.arange(m)
        added[:, diagonal, diagonal] += 2.0 * first[:, h, None]
        hess = np.where(active[:, None, None], added, hess)
    gradient[:, :] = grad
    hessian[:, :, :] = hess
    return total


def _groups(free: np.ndarray) -> tuple[np.ndarray, int]:
    """The reduced variable per offset component and their number (``offset_groups``)."""
    if free.shape[1] == 1:
        running = np.cumsum(free[:, 0])
        return np.where(running > 0, running - 1, -1)[:, None], int(running[-1])
    index = np.empty(free.shape, dtype=np.int64)
    count = 0
    for i in range(free.shape[1]):
        running = np.cumsum(free[:, i])
        index[:, i] = np.where(running > 0, count + running - 1, -1)
        count += int(running[-1]) if running.size else 0
    return index, count


def _positive_blocks(h00, h01, h11, floor):
    """``_problem_kernels._positive_block`` on arrays of 2×2 blocks."""
    with np.errstate(divide="ignore", invalid="ignore"):
        mean = 0.5 * (h00 + h11)
        radius = np.sqrt((0.5 * (h00 - h11)) ** 2 + h01 * h01)
        low, high = mean - radius, mean + radius
        fixed_low, fixed_high = np.maximum(np.abs(low), floor), np.maximum(np.abs(high), floor)
        first = np.abs(high - h00) > np.abs(high - h11)
        ux = np.where(first, h01, high - h11)
        uy = np.where(first, high - h00, h01)
        norm = np.sqrt(ux * ux + uy * uy)
        ux, uy = ux / norm, uy / norm
        vx, vy = -uy, ux
        p00 = fixed_high * ux * ux + fixed_low * vx * vx
        p01 = fixed_high * ux * uy + fixed_low * vx * vy
        p11 = fixed_high * uy * uy + fixed_low * vy * vy
    kept = (low == fixed_low) & (high == fixed_high)
    round_ = ~kept & (radius == 0.0)
    p00 = np.where(kept, h00, np.where(round_, fixed_high, p00))
    p01 = np.where(kept, h01, np.where(round_, 0.0, p01))
    p11 = np.where(kept, h11, np.where(round_, fixed_high, p11))
    return p00, p01, p11


def block_tree_solve(h00, h01, h11, index, n_vars, rhs, least=0.0):
    """``_problem_kernels.block_tree_solve`` on Python floats (its loops line by line)."""
    h00, h01, h11 = h00.tolist(), h01.tolist(), h11.tolist()
    pairs = index.tolist()
    pivot = [0.0] * n_vars
    last = [0] * n_vars
    for k, (v0, v1) in enumerate(pairs):
        if v0 >= 0:
            pivot[v0] += h00[k]
            last[v0] = k
        if v1 >= 0:
            pivot[v1] += h11[k]
            last[v1] = k
    parent = [-1] * n_vars
    up = [0.0] * n_vars
    order = []
    for k, (v0, v1) in enumerate(pairs):
        if v0 >= 0 and v1 >= 0:
            if last[v0] <= last[v1]:
                parent[v0] = v1
                up[v0] += h01[k]
            else:
                parent[v1] = v0
                up[v1] += h01[k]
        for v in (v0, v1):
            if v >= 0 and last[v] == k:
                order.append(v)
    x = np.array(rhs, dtype=np.float64).reshape(n_vars, -1).tolist()
    factor = [0.0] * n_vars
    for v in order:
        if not pivot[v] > least:
            return np.array(x).reshape(n_vars, -1), False
        w = parent[v]
        if w >= 0:
            factor[v] = up[v] / pivot[v]
            pivot[w] -= factor[v] * up[v]
            x[w] = [a - factor[v] * b for a, b in zip(x[w], x[v], strict=True)]
    x = [[a / pivot[v] for a in row] for v, row in enumerate(x)]
    for v in reversed(order):
        w = parent[v]
        if w >= 0:
            x[v] = [a - factor[v] * b for a, b in zip(x[v], x[w], strict=True)]
    return np.array(x).reshape(n_vars, -1), True


def _from_start(start: np.ndarray, steps: np.ndarray) -> np.ndarray:
    """Offsets (n, m) from the start offset (m,) and actions (n, m), summed one at a time."""
    return np.add.accumulate(np.concatenate((start[None], steps)), axis=0)[1:]


def _newton_step(gradient, hessian, index, n_vars, floor, m):
    """The reduced Newton step per offset (n, m), zero where anchored."""
    valid = index >= 0
    g = np.bincount(index[valid], weights=gradient[valid], minlength=n_vars)
    if m == 1:
        h = np.bincount(index[valid], weights=hessian[:, 0, 0][valid[:, 0]], minlength=n_vars)
        move = -g / np.maximum(np.abs(h), floor)
    else:
        rows = valid[:, 0] | valid[:, 1]
        h00, h01, h11 = hessian[rows, 0, 0], hessian[rows, 0, 1], hessian[rows, 1, 1]
        solved, definite = block_tree_solve(h00, h01, h11, index[rows], n_vars, g, floor)
        if not definite:  # each point's block made positive first
            p00, p01, p11 = _positive_blocks(h00, h01, h11, floor)
            solved, _ = block_tree_solve(p00, p01, p11, index[rows], n_vars, g)
        move = -solved[:, 0]
    return np.where(valid, move[np.maximum(index, 0)] if n_vars else 0.0, 0.0)


def _clamped(d, step_d, t, start, max_step):
    """Offsets ``d + t·step`` each clamped to its predecessor's box (one point after another)."""
    target = (d + t * step_d).T.tolist()
    out = np.empty(d.shape)
    for i, column in enumerate(target):
        previous = float(start[i])
        values = []
        for value in column:
            value = min(max(value, previous - max_step), previous + max_step)
            values.append(value)
            previous = value
        out[:, i] = values
    return out


def planner_newton(c, b, a, weight, rr, nr, inner2, outer2, mu, max_step, d0, d, tol, max_iter):
    """Projected Newton on the actions ``a_k = d_k − d_{k−1}``, box ``|a| <= max_step``.

    ``d`` (n, m) holds the start on entry and the optimum on exit. Returns
    ``(cost, iterations, converged)``, as ``_problem_kernels.planner_newton``.
    Short 2-D windows (at most :data:`SCALAR_POINTS` points or
    :data:`SCALAR_TERMS` point terms) run
    :func:`planner_newton_scalar`.
    """
    n, m = d.shape
    if m == 1 and (n <= SCALAR_POINTS or n * (1 + c.shape[1] + rr.shape[1]) <= SCALAR_TERMS):
        args = (c, b, a, weight, rr, nr, inner2, outer2, mu, max_step, d0, d, tol, max_iter)
        return planner_newton_scalar(*args)
    args = (c, b, a, weight, rr, nr, inner2, outer2, mu)
    previous = np.concatenate((d0[None], d[:-1]))
    actions = np.minimum(np.maximum(d - previous, -max_step), max_step)
    d[:, :] = _from_start(d0, actions)
    gradient = np.empty((n, m))
    hessian = np.empty((n, m, m))
    base = weight.min()
    floor = 1e-8 * 2.0 * base
    scale = 1.0 + 2.0 * base * max_step
    cost = planner_derivatives(*args, d, gradient, hessian)
    if not np.isfinite(cost):
        return cost, 0, False
    upper_bound, lower_bound = max_step * (1.0 - 1e-12), -max_step * (1.0 - 1e-12)
    upper_push, lower_push = max_step * (1.0 - 1e-9), -max_step * (1.0 - 1e-9)
    for iteration in range(max_iter):
        action_gradient = np.add.accumulate(gradient[::-1], axis=0)[::-1]
        held = ((actions >= upper_bound) & (action_gradient < 0.0)) | (
            (actions <= lower_bound) & (action_gradient > 0.0)
        )
        free = ~held
        worst = float(np.abs(action_gradient[free]).max(initial=0.0))
        if worst <= tol * scale:
            return cost, iteration, True
        for _refine in range(8):
            index, n_vars = _groups(free)
            step_d = _newton_step(gradient, hessian, index, n_vars, floor, m)
            change = step_d - np.concatenate((np.zeros((1, m)), step_d[:-1]))
            pushed = free & (
                ((actions >= upper_push) & (change > 0.0))
                | ((actions <= lower_push) & (change < 0.0))
            )
            if not pushed.any():
                break
            free = free & ~pushed
        step_a = step_d - np.concatenate((np.zeros((1, m)), step_d[:-1]))
        accepted, best_cost, best = False, np.inf, None
        for retraction in range(2):
            t = 1.0
            for _ in range(60 if retraction else 30):
                if retraction == 0:
                    trial = _clamped(d, step_d, t, d0, max_step)
                    decrease = _sequential_sum((gradient * (trial - d)).T)
                else:
                    action = np.minimum(np.maximum(actions + t * step_a, -max_step), max_step)
                    decrease = _sequential_sum((action_gradient * (action - actions)).T)
                    trial = _from_start(d0, action)
                trial_cost = planner_cost(*args, trial)
                if trial_cost <= cost + 1e-4 * decrease and (retraction == 1 or decrease < 0.0):
                    if trial_cost < best_cost:
                        best_cost, best = trial_cost, trial
                    accepted = True
                    break
                t *= 0.5
            if accepted and t == 1.0:
                break  # a full Newton step: nothing better to look for
        if not accepted or best is None:
            return cost, iteration + 1, worst <= 1e-6 * scale
        moved = float(np.abs(best - d).max(initial=0.0))
        actions = best - np.concatenate((d0[None], best[:-1]))
        d[:, :] = best
        cost = planner_derivatives(*args, d, gradient, hessian)
        if moved <= 1e-13 * max_step:
            return cost, iteration + 1, worst <= 1e-6 * scale  # the steps stopped moving
    return cost, max_iter, False


def grid_node_costs(c, b, a, weight, rr, nr, inner2, outer2, mu, levels, out):
    """Cost of every grid state at every point: ``out`` (n, G^m), m from its width."""
    grid_state_costs(c, b, a, weight, levels, out)
    grid_hard_costs(rr, nr, inner2, outer2, mu, levels, out)


def _grid_states(levels: np.ndarray, width: int) -> list[np.ndarray]:
    """Each offset component of every grid state, (1, G^m) each."""
    g_count = levels.shape[0]
    if width == g_count:
        return [levels[None, :]]
    return [np.repeat(levels, g_count)[None, :], np.tile(levels, g_count)[None, :]]


def grid_state_costs(c, b, a, weight, levels, out):
    """:func:`grid_node_costs`' first terms (``_planner_kernels.grid_state_costs``)."""
    states = _grid_states(levels, out.shape[1])
    m = len(states)
    if m == 1:
        lowest = c - b[:, :, 0] ** 2 / np.maximum(a[:, :, 0, 0], 1e-300)
    else:
        det = a[:, :, 0, 0] * a[:, :, 1, 1] - a[:, :, 0, 1] * a[:, :, 1, 0]
        det = np.maximum(det, 1e-300)
        quad = (
            a[:, :, 1, 1] * b[:, :, 0] ** 2
            - 2.0 * a[:, :, 0, 1] * b[:, :, 0] * b[:, :, 1]
            + a[:, :, 0, 0] * b[:, :, 1] ** 2
        ) / det
        lowest = c - quad
    near = lowest < 40.0  # (n, L): obstacles whose term matters somewhere at the point
    total = weight[:, None] * states[0] * states[0]
    for i in range(1, m):
        total = total + weight[:, None] * states[i] * states[i]
    for o in range(c.shape[1]):
        s = c[:, o, None]
        for i in range(m):
            value = b[:, o, i, None]
            for j in range(m):
                value = value + a[:, o, i, j, None] * states[j]
            s = s + (b[:, o, i, None] + value) * states[i]
        total = total + np.where(near[:, o, None], np.exp(-s), 0.0)
    out[:, :] = total


def grid_hard_costs(rr, nr, inner2, outer2, mu, levels, out):
    """:func:`grid_node_costs`' last terms, added (``_planner_kernels.grid_hard_costs``)."""
    states = _grid_states(levels, out.shape[1])
    closest = rr.copy()
    for i in range(len(states)):
        closest = closest - nr[:, :, i] ** 2
    hit = closest < outer2[None]  # (n, H)
    total = out
    for h in range(rr.shape[1]):
        u = rr[:, h, None]
        for i in range(len(states)):
            u = u + (2.0 * nr[:, h, i, None] + states[i]) * states[i]
        value = _barrier(u, inner2[h], outer2[h], mu, slopes=False)[0]
        total = total + np.where(hit[:, h, None], value, 0.0)
    out[:, :] = total


def _window_min(values: np.ndarray, window: int) -> np.ndarray:
    """Sliding minimum over ``|t − s| ≤ window`` along the first axis (the edges clipped)."""
    best = values.copy()
    for shift in range(1, min(window, values.shape[0] - 1) + 1):
        np.minimum(best[shift:], values[:-shift], out=best[shift:])
        np.minimum(best[:-shift], values[shift:], out=best[:-shift])
    return best


def grid_backward(node, g_count, window, end_zero, extra, out):
    """The backward dynamic programme from states' costs ``node`` (n, G^m), into ``out``."""
    n, n_states = out.shape
    m = 2 if n_states != g_count else 1
    out[:, :] = node + (extra if extra.shape[0] else 0.0)
    if end_zero:
        zero = (g_count - 1) // 2
        keep = zero * g_count + zero if m == 2 else zero
        last = out[n - 1, keep]
        out[n - 1] = np.inf
        out[n - 1, keep] = last
    for k in range(n - 2, -1, -1):
        if m == 1:
            best = _window_min(out[k + 1], window)
        else:  # along j (the state i·G + j), then along i
            square = out[k + 1].reshape(g_count, g_count)
            best = _window_min(_window_min(square.T, window).T, window).reshape(-1)
        out[k] += best


def grid_cost_to_go(
    c, b, a, weight, rr, nr, inner2, outer2, mu, levels, window, end_zero, extra, out
):
    """Backward dynamic programme on the lateral grid (``_planner_kernels.grid_cost_to_go``)."""
    grid_node_costs(c, b, a, weight, rr, nr, inner2, outer2, mu, levels, out)
    grid_backward(out.copy(), levels.shape[0], window, end_zero, extra, out)


def lateral_dp(
    c, b, a, weight, rr, nr, inner2, outer2, mu, max_step, d0, levels, window, end_zero, extra, out
):
    """Globally best offsets on a lateral grid (``_planner_kernels.lateral_dp``)."""
    n, m = out.shape
    value = np.empty((n, levels.shape[0] ** m))
    grid_cost_to_go(
        c, b, a, weight, rr, nr, inner2, outer2, mu, levels, window, end_zero, extra, value
    )
    return grid_walk(value, levels, window, max_step, d0, out)


def _first_least(values: np.ndarray) -> tuple[int, float]:
    """Index and value of the first least entry; (−1, inf) when none is below ``+inf``."""
    if values.size == 0:
        return -1, np.inf
    where = int(np.argmin(values))
    best = float(values.reshape(-1)[where])
    return (where, best) if best < np.inf else (-1, np.inf)


def return_clamped(anchor, new, back):
    """Bound the step from ``anchor`` to ``new`` toward the nominal by ``back``, in place.

    ``_planner_kernels.return_clamped``: per component, ``new ≥ anchor − back``
    from ``anchor > 0`` and ``new ≤ anchor + back`` from ``anchor < 0``.
    """
    new[...] = np.where(
        anchor > 0.0,
        np.maximum(new, anchor - back),
        np.where(anchor < 0.0, np.minimum(new, anchor + back), new),
    )


def grid_walk(value, levels, window, max_step, d0, out):
    """Follow a cost-to-go table from ``d0`` for ``out``'s rows (``_planner_kernels.grid_walk``)."""
    h, m = out.shape
    g_count = levels.shape[0]
    reach = max_step * (1.0 + 1e-12)
    states = np.arange(value.shape[1])
    first = states // g_count if m == 2 else states
    allowed = np.abs(levels[first] - d0[0]) <= reach
    if m == 2:
        allowed &= np.abs(levels[states % g_count] - d0[1]) <= reach
    state, total = _first_least(np.where(allowed, value[0], np.inf))
    if not np.isfinite(total):
        return total
    if m == 1:  # the compiled loop on Python floats: a few cells a point, no NumPy calls
        rows = value[1:h].tolist()
        for k in range(h):
            out[k, 0] = levels[state]
            if k == h - 1:
                break
            row, best_state, best = rows[k], -1, np.inf
            for t in range(max(0, state - window), min(g_count, state + window + 1)):
                if row[t] < best:
                    best_state, best = t, row[t]
            state = best_state
        return total
    for k in range(h):
        i0 = state // g_count if m == 2 else state
        j0 = state % g_count
        out[k, 0] = levels[i0]
        if m == 2:
            out[k, 1] = levels[j0]
        if k == h - 1:
            break
        lo, hi = max(0, i0 - window), min(g_count, i0 + window + 1)
        if m == 1:
            found, _ = _first_least(value[k + 1, lo:hi])
            state = lo + found if found >= 0 else -1
        else:
            jlo, jhi = max(0, j0 - window), min(g_count, j0 + window + 1)
            block = value[k + 1].reshape(g_count, g_count)[lo:hi, jlo:jhi]
            found, _ = _first_least(block)
            width = jhi - jlo
            state = (lo + found // width) * g_count + jlo + found % width if found >= 0 else -1
    return total


def _barrier_value(u, inner2, outer2, mu):
    """``_problem_kernels.barrier``'s value alone, on floats."""
    if u >= outer2:
        return 0.0
    if u <= inner2:
        return math.inf
    t = (outer2 - u) * (1.0 / (outer2 - inner2))
    return mu * t * t * t / (1.0 - t)


def _barrier_all(u, inner2, outer2, mu):
    """``_problem_kernels.barrier`` on floats: value and first two derivatives in ``u``."""
    if u >= outer2:
        return 0.0, 0.0, 0.0
    if u <= inner2:
        return math.inf, 0.0, 0.0
    kappa = 1.0 / (outer2 - inner2)
    t = (outer2 - u) * kappa
    one = 1.0 - t
    value = mu * t * t * t / one
    first = -mu * kappa * (3.0 * t * t - 2.0 * t * t * t) / (one * one)
    second = mu * kappa * kappa * (6.0 * t - 6.0 * t * t + 2.0 * t * t * t) / (one * one * one)
    return value, first, second


def planner_newton_scalar(
    c, b, a, weight, rr, nr, inner2, outer2, mu, max_step, d0, d, tol, max_iter
):
    """:func:`planner_newton` in 2-D (``m`` 1) on Python floats: the compiled loops line by line.

    The arrays are turned into lists once; every cost and derivative of the
    line search is then a loop over points, as in ``_problem_kernels``, with
    the same operations in the same order (``math.exp`` is the C library's
    ``exp`` numba calls), so the results are numba's bit for bit. ``d``
    (n, 1) holds the start on entry and the optimum on exit.
    """
    n = d.shape[0]
    mu, max_step, tol, start = float(mu), float(max_step), float(tol), float(d0[0])
    bounds = list(zip(inner2.tolist(), outer2.tolist(), strict=True))
    # Per point: its weight, its obstacles' (c, b, a) and its hard radii's (rr, nr, r², ρ²).
    points = [
        (
            w,
            list(zip(ck, bk, ak, strict=True)),
            [(ro, no, lo, hi) for ro, no, (lo, hi) in zip(rk, nk, bounds, strict=True)],
        )
        for w, ck, bk, ak, rk, nk in zip(
            weight.tolist(),
            c.tolist(),
            b[:, :, 0].tolist(),
            a[:, :, 0, 0].tolist(),
            rr.tolist(),
            nr[:, :, 0].tolist(),
            strict=True,
        )
    ]
    exp = math.exp

    def cost_of(offsets):
        total = 0.0
        for g, (w, bumps, hards) in zip(offsets, points, strict=True):
            point = w * g * g  # 0.0 + x, the compiled point cost's first term, is x
            for co, bo, ao in bumps:
                point += exp(-(co + (bo + (bo + ao * g)) * g))
            for ro, no, lo, hi in hards:
                u = ro + (2.0 * no + g) * g
                if u < hi:  # else the barrier adds 0.0, which changes no sum
                    point += _barrier_value(u, lo, hi, mu)
            total += point
        return total

    def derivatives(offsets, gradient, hessian):
        total = 0.0
        for k, (g, (w, bumps, hards)) in enumerate(zip(offsets, points, strict=True)):
            total += w * g * g
            grad, hess = 2.0 * w * g, 2.0 * w
            for co, bo, ao in bumps:
                npu = bo + ao * g
                e = exp(-(co + (bo + npu) * g))
                total += e
                grad -= 2.0 * e * npu
                hess += e * (4.0 * npu * npu - 2.0 * ao)
            for ro, no, lo, hi in hards:
                value, first, second = _barrier_all(ro + (2.0 * no + g) * g, lo, hi, mu)
                if value == 0.0:
                    continue
                total += value
                grad += 2.0 * first * (no + g)
                hess += 4.0 * second * (no + g) * (no + g)
                hess += 2.0 * first
            gradient[k], hessian[k] = grad, hess
        return total

    previous, actions, offsets, running = start, [], [], start
    for value in d[:, 0].tolist():
        action = min(max(value - previous, -max_step), max_step)
        previous = value
        running += action
        actions.append(action)
        offsets.append(running)
    gradient, hessian = [0.0] * n, [0.0] * n

    def done(cost, iterations, converged):
        d[:, 0] = offsets
        return cost, iterations, converged

    base = float(weight.min())
    floor = 1e-8 * 2.0 * base
    scale = 1.0 + 2.0 * base * max_step
    cost = derivatives(offsets, gradient, hessian)
    if not math.isfinite(cost):
        return done(cost, 0, False)
    upper_bound, lower_bound = max_step * (1.0 - 1e-12), -max_step * (1.0 - 1e-12)
    upper_push, lower_push = max_step * (1.0 - 1e-9), -max_step * (1.0 - 1e-9)
    action_gradient, free = [0.0] * n, [True] * n
    low_step = -max_step
    for iteration in range(max_iter):
        worst, running = 0.0, 0.0
        for k in range(n - 1, -1, -1):
            running += gradient[k]
            action_gradient[k] = running
            held = (actions[k] >= upper_bound and running < 0.0) or (
                actions[k] <= lower_bound and running > 0.0
            )
            free[k] = not held
            if not held and abs(running) > worst:
                worst = abs(running)
        if worst <= tol * scale:
            return done(cost, iteration, True)
        for _refine in range(8):
            # A free point opens a group of the reduced variables; held ones join the last.
            step_d, total_g, total_h, opened = [], 0.0, 0.0, False
            groups = []
            for k in range(n):
                if free[k]:
                    if opened:
                        groups.append((total_g, total_h))
                    total_g, total_h, opened = 0.0, 0.0, True
                if opened:
                    total_g += gradient[k]
                    total_h += hessian[k]
                    step_d.append(len(groups))
                else:
                    step_d.append(-1)
            if opened:
                groups.append((total_g, total_h))
            moves = [-g / max(abs(h), floor) for g, h in groups]
            step_d = [moves[v] if v >= 0 else 0.0 for v in step_d]
            changed, before = False, 0.0
            for k in range(n):
                change = step_d[k] - before
                before = step_d[k]
                if free[k] and (
                    (actions[k] >= upper_push and change > 0.0)
                    or (actions[k] <= lower_push and change < 0.0)
                ):
                    free[k] = False
                    changed = True
            if not changed:
                break
        step_a = [step - before for step, before in zip(step_d, [0.0, *step_d[:-1]], strict=True)]
        accepted, best_cost, best = False, math.inf, offsets
        for retraction in range(2):
            t = 1.0
            for _ in range(60 if retraction else 30):
                decrease, previous, trial = 0.0, start, []
                if retraction == 0:
                    for dk, sk, gk in zip(offsets, step_d, gradient, strict=True):
                        value = dk + t * sk
                        # min(max(value, low), high) as the compiled builtins pick, without calls
                        low, high = previous - max_step, previous + max_step
                        value = low if low > value else value
                        value = high if high < value else value
                        decrease += gk * (value - dk)
                        trial.append(value)
                        previous = value
                else:
                    for ak, sk, gk in zip(actions, step_a, action_gradient, strict=True):
                        action = ak + t * sk
                        action = low_step if low_step > action else action
                        action = max_step if max_step < action else action
                        decrease += gk * (action - ak)
                        previous = previous + action
                        trial.append(previous)
                trial_cost = cost_of(trial)
                if trial_cost <= cost + 1e-4 * decrease and (retraction == 1 or decrease < 0.0):
                    if trial_cost < best_cost:
                        best_cost, best = trial_cost, trial
                    accepted = True
                    break
                t *= 0.5
            if accepted and t == 1.0:
                break  # a full Newton step: nothing better to look for
        if not accepted:
            return done(cost, iteration + 1, worst <= 1e-6 * scale)
        change = max(abs(new - old) for new, old in zip(best, offsets, strict=True))
        actions = [new - old for new, old in zip(best, [start, *best[:-1]], strict=True)]
        offsets = best
        cost = derivatives(offsets, gradient, hessian)
        if change <= 1e-13 * max_step:
            return done(cost, iteration + 1, worst <= 1e-6 * scale)  # the steps stopped moving
    return done(cost, max_iter, False)
