"""Compiled cost and projected Newton solver of the planning problem (numba).

The kernels of :class:`lfdkit.emulate.problem.Problem`, shared by the planner
(:mod:`lfdkit.emulate.planner`, whose global grid search has its own kernels
in :mod:`._planner_kernels`) and the inverse optimal control
(:mod:`._ioc_kernels`). The cost in the lateral offsets ``d`` (n, m) is

    Σ_k Q_k |d_k|² + Σ_{k,o} exp(−(c + 2bᵀd + dᵀAd)) + Σ_{k,h} B(u_kh),

with ``u = |x_k − O_h|² = rr + 2 nrᵀd + |d|²`` for the obstacles with a hard
radius, and ``B`` the clearance barrier: 0 beyond the outer radius ρ, rising
to ``+inf`` at the inner radius. Arrays with zero obstacles (shape (n, 0, …))
switch a term off; the ``offset_*`` functions are the thesis's model, without
hard radii. Argument names as the attributes of ``Problem``.

:meth:`Problem.derivatives <lfdkit.emulate.problem.Problem.derivatives>` is
the readable NumPy form of :func:`planner_derivatives` (without the barrier);
``tests/emulate/test_problem.py`` holds the two to the same numbers.

Where a point has many terms (a 3-D plan among boxes: 54 bumps and 390 hard
radii, the boxes' ball covers and side blockers), nearly all are exactly zero
there: ``exp(−s)`` underflows, ``u`` is beyond the outer radius. The Newton
solver lists each point's live terms (:func:`live_terms`: bounds over a ball
of :data:`LIVE_REACH` action bounds round the offsets, listed again when the
offsets leave it) and sums only those, to the bit the sums over all terms.
The seed-0 fold 6 of ``benchmarks/boxes_sides.py`` (3-D, three boxes) fits in
16.6 s instead of 19.3 s (CPU 27.6 against 32.9 s), with the same reward,
model choice and plan.

Imported lazily: compiling costs a few seconds once, after which the machine
code is cached on disk next to this file. Every entry point releases the GIL
(``nogil``): plans run side by side on threads (a Dask worker's, a skill's
model choice: issue 34).
"""

import numba
import numpy as np

#: ``exp(−s)`` is exactly 0.0 in double precision beyond s = 745.2: a bump whose exponent
#: certainly stays beyond this is left out of a solve's sums (:func:`live_terms`).
DEAD_EXPONENT = 750.0
#: A Newton solve lists each point's live terms (:func:`live_terms`) where a point has more
#: terms than this; below it the lists cost more than they save (the IOC's 15 terms a point:
#: 10 % slower with them).
LISTED_TERMS = 32
#: How far (in action bounds) the offsets may move from where the live terms were listed
#: before they are listed again: in a 3-D plan's goal join (99 points, 54 bumps and 390 hard
#: radii a point) 4 lists the terms again about once in three Newton steps, and the solves
#: take 0.18 of the time (2, 8 and 16 action bounds: 0.30, 0.19 and 0.26).
LIVE_REACH = 4.0
# The term lists that stand for every term (``every`` True: read by none), made once: a
# planner_cost call in the receding horizon's loops allocated two arrays each time.
_NO_IDS = np.empty((0, 0), dtype=np.int64)
_NO_COUNTS = np.empty(0, dtype=np.int64)


@numba.njit(cache=True, inline="always")
def barrier(u, inner2, outer2, mu):
    """Barrier value and its first two derivatives in ``u`` (a squared distance).

    ``B = μ t³ / (1 − t)`` with ``t = (ρ² − u) / (ρ² − r²)``: zero with zero
    first and second derivatives at ``u = ρ²`` (so Newton sees a C² cost), and
    ``+inf`` at ``u = r²``.
    """
    if u >= outer2:
        return 0.0, 0.0, 0.0
    if u <= inner2:
        return np.inf, 0.0, 0.0
    kappa = 1.0 / (outer2 - inner2)
    t = (outer2 - u) * kappa
    one = 1.0 - t
    value = mu * t * t * t / one
    first = -mu * kappa * (3.0 * t * t - 2.0 * t * t * t) / (one * one)
    second = mu * kappa * kappa * (6.0 * t - 6.0 * t * t + 2.0 * t * t * t) / (one * one * one)
    return value, first, second


@numba.njit(cache=True, inline="always")
def point_cost(c, b, a, weight, rr, nr, inner2, outer2, mu, k, g, bumps, hards):
    """Cost of offset ``g`` (m,) at point ``k`` alone.

    Over the obstacles ``bumps`` and the hard radii ``hards`` (indices; the
    others are left out: the grid search drops those negligible at a point).
    """
    m = g.shape[0]
    total = 0.0
    for i in range(m):
        total += weight[k] * g[i] * g[i]
    for o in bumps:
        s = c[k, o]
        for i in range(m):
            npu = b[k, o, i]
            for j in range(m):
                npu += a[k, o, i, j] * g[j]
            s += (b[k, o, i] + npu) * g[i]
        total += np.exp(-s)
    for h in hards:
        u = rr[k, h]
        for i in range(m):
            u += (2.0 * nr[k, h, i] + g[i]) * g[i]
        total += barrier(u, inner2[h], outer2[h], mu)[0]
    return total


@numba.njit(cache=True, nogil=True)
def planner_cost(c, b, a, weight, rr, nr, inner2, outer2, mu, d):
    """The planner cost of offsets ``d`` (n, m); ``+inf`` inside a hard radius.

    :func:`point_cost` of every obstacle and hard radius at each point, summed
    over the points, with the same operations in the same order (the same
    number to the bit), written out on ``d``'s rows: a row's view and the
    index ranges handed to :func:`point_cost` cost six times the arithmetic
    (9 against 1.5 µs for 99 points and one obstacle), and the projected
    Newton solver's line search is most of a fit's time.
    """
    return _listed_cost(
        c, b, a, weight, rr, nr, inner2, outer2, mu, d, True, _NO_IDS, _NO_COUNTS, _NO_IDS,
        _NO_COUNTS,
    )  # fmt: skip


@numba.njit(cache=True, nogil=True)
def planner_derivatives(c, b, a, weight, rr, nr, inner2, outer2, mu, d, gradient, hessian):
    """Cost; fills the gradient (n, m) and Hessian blocks (n, m, m) in the offsets."""
    return _listed_derivatives(
        c, b, a, weight, rr, nr, inner2, outer2, mu, d, gradient, hessian,
        True, _NO_IDS, _NO_COUNTS, _NO_IDS, _NO_COUNTS,
    )  # fmt: skip


@numba.njit(cache=True, inline="always")
def _listed_cost(
    c, b, a, weight, rr, nr, inner2, outer2, mu, d, every, bumps, n_bumps, hards, n_hards
):
    """:func:`planner_cost` over the terms listed at each point (``every``: all of them).

    ``bumps[k, :n_bumps[k]]`` and ``hards[k, :n_hards[k]]``: the obstacles and
    hard radii of point ``k``, in increasing order (:func:`live_terms`). A term
    left out must be exactly zero at ``d``: adding it would add 0.0, so the
    sum is the full one to the bit.
    """
    n, m = d.shape
    n_obs, n_hard = c.shape[1], rr.shape[1]
    total = 0.0
    for k in range(n):
        point = 0.0
        for i in range(m):
            point += weight[k] * d[k, i] * d[k, i]
        for q in range(n_obs if every else n_bumps[k]):
            o = q if every else bumps[k, q]
            s = c[k, o]
            for i in range(m):
                npu = b[k, o, i]
                for j in range(m):
                    npu += a[k, o, i, j] * d[k, j]
                s += (b[k, o, i] + npu) * d[k, i]
            point += np.exp(-s)
        for q in range(n_hard if every else n_hards[k]):
            h = q if every else hards[k, q]
            u = rr[k, h]
            for i in range(m):
                u += (2.0 * nr[k, h, i] + d[k, i]) * d[k, i]
            point += barrier(u, inner2[h], outer2[h], mu)[0]
        total += point
    return total


@numba.njit(cache=True, inline="always")
def _listed_derivatives(
    c, b, a, weight, rr, nr, inner2, outer2, mu, d, gradient, hessian,
    every, bumps, n_bumps, hards, n_hards,
):  # fmt: skip
    """:func:`planner_derivatives` over the terms listed at each point (as :func:`_listed_cost`)."""
    n, n_obs = c.shape
    n_hard = rr.shape[1]
    m = d.shape[1]
    total = 0.0
    npu = np.empty(m)
    for k in range(n):
        for i in range(m):
            total += weight[k] * d[k, i] * d[k, i]
            gradient[k, i] = 2.0 * weight[k] * d[k, i]
            for j in range(m):
                hessian[k, i, j] = 2.0 * weight[k] if i == j else 0.0
        for q in range(n_obs if every else n_bumps[k]):
            o = q if every else bumps[k, q]
            s = c[k, o]
            for i in range(m):
                npu[i] = b[k, o, i]
                for j in range(m):
                    npu[i] += a[k, o, i, j] * d[k, j]
                s += (b[k, o, i] + npu[i]) * d[k, i]
            e = np.exp(-s)
            total += e
            for i in range(m):
                gradient[k, i] -= 2.0 * e * npu[i]
                for j in range(m):
                    hessian[k, i, j] += e * (4.0 * npu[i] * npu[j] - 2.0 * a[k, o, i, j])
        for q in range(n_hard if every else n_hards[k]):
            h = q if every else hards[k, q]
            u = rr[k, h]
            for i in range(m):
                u += (2.0 * nr[k, h, i] + d[k, i]) * d[k, i]
            value, first, second = barrier(u, inner2[h], outer2[h], mu)
            if value == 0.0:
                continue
            total += value
            for i in range(m):
                gradient[k, i] += 2.0 * first * (nr[k, h, i] + d[k, i])
                for j in range(m):
                    hessian[k, i, j] += (
                        4.0 * second * (nr[k, h, i] + d[k, i]) * (nr[k, h, j] + d[k, j])
                    )
                hessian[k, i, i] += 2.0 * first
    return total


@numba.njit(cache=True, nogil=True)
def live_terms(c, b, a, rr, nr, outer2, centre, radius, bumps, n_bumps, hards, n_hards):
    """The terms that may be nonzero at each point within ``radius`` of ``centre`` (n, m).

    Fills ``bumps`` (n, n_obstacles) and ``hards`` (n, n_hard) with each
    point's indices, in increasing order, and ``n_bumps``, ``n_hards`` (n,)
    with their counts. A bump ``exp(−s)`` is left out where ``s`` certainly
    exceeds :data:`DEAD_EXPONENT` for every offset within ``radius`` (its
    value at the centre, less the gradient's reach, less the reach of the
    curvature's most negative part, bounded by Gershgorin's discs); a hard
    radius where the squared distance ``u`` certainly stays beyond its outer
    radius (the barrier's exact zero). Both tests leave a relative slack of
    1e-9 of the numbers' sizes for rounding, so a term left out is exactly zero.
    """
    n, n_obs = c.shape
    m = centre.shape[1]
    n_hard = rr.shape[1]
    for k in range(n):
        count = 0
        for o in range(n_obs):
            s = c[k, o]
            size = abs(s)
            slope2 = 0.0
            lowest = np.inf  # Gershgorin: every eigenvalue of A's symmetric part is above it
            for i in range(m):
                npu = b[k, o, i]
                slope = 2.0 * b[k, o, i]
                disc = 0.0
                for j in range(m):
                    npu += a[k, o, i, j] * centre[k, j]
                    slope += (a[k, o, i, j] + a[k, o, j, i]) * centre[k, j]
                    if j != i:
                        disc += 0.5 * abs(a[k, o, i, j] + a[k, o, j, i])
                term = (b[k, o, i] + npu) * centre[k, i]
                s += term
                size += abs(term)
                slope2 += slope * slope
                lowest = min(lowest, a[k, o, i, i] - disc)
            bend = min(lowest, 0.0) * radius * radius
            least = s - np.sqrt(slope2) * radius + bend
            if not least > DEAD_EXPONENT + 1e-9 * (size + abs(bend) + 1.0):
                bumps[k, count] = o
                count += 1
        n_bumps[k] = count
        count = 0
        for h in range(n_hard):
            far2 = 0.0
            norm2 = 0.0
            for i in range(m):
                x = centre[k, i] + nr[k, h, i]
                far2 += x * x
                norm2 += nr[k, h, i] * nr[k, h, i]
            # u = |d + nr|² + (rr − |nr|²): the squared distance, at least this much
            beyond = np.sqrt(far2) - radius
            least = rr[k, h] - norm2 + (beyond * beyond if beyond > 0.0 else 0.0)
            slack = 1e-9 * (abs(rr[k, h]) + norm2 + far2 + radius * radius + outer2[h])
            if not least > outer2[h] + slack:
                hards[k, count] = h
                count += 1
        n_hards[k] = count


@numba.njit(cache=True, inline="always")
def _within(d, centre, radius):
    """Whether every row of ``d`` lies within ``radius`` of ``centre``'s."""
    n, m = d.shape
    for k in range(n):
        far2 = 0.0
        for i in range(m):
            x = d[k, i] - centre[k, i]
            far2 += x * x
        if not far2 <= radius * radius:
            return False
    return True


@numba.njit(cache=True, nogil=True)
def _without_radii(n, m):
    """The hard-radius arrays of a problem without any (the thesis's model)."""
    return np.zeros((n, 0)), np.zeros((n, 0, m)), np.zeros(0), np.zeros(0)


@numba.njit(cache=True, nogil=True)
def offset_derivatives(c, b, a, weight, d, gradient, hessian):
    """:func:`planner_derivatives` without hard radii (the thesis's model)."""
    rr, nr, inner2, outer2 = _without_radii(d.shape[0], d.shape[1])
    return planner_derivatives(c, b, a, weight, rr, nr, inner2, outer2, 0.0, d, gradient, hessian)


@numba.njit(cache=True, nogil=True)
def offset_groups(free, index):
    """Reduced-variable index per offset component (−1: anchored); returns their number."""
    n, m = free.shape
    count = 0
    for i in range(m):
        current = -1
        for k in range(n):
            if free[k, i]:
                current = count
                count += 1
            index[k, i] = current
    return count


@numba.njit(cache=True, nogil=True)
def _positive_block(h00, h01, h11, floor):
    """A symmetric 2×2 block with its eigenvalues replaced by ``max(|λ|, floor)``."""
    mean = 0.5 * (h00 + h11)
    radius = np.sqrt((0.5 * (h00 - h11)) ** 2 + h01 * h01)
    low, high = mean - radius, mean + radius
    fixed_low, fixed_high = max(abs(low), floor), max(abs(high), floor)
    if low == fixed_low and high == fixed_high:
        return h00, h01, h11
    if radius == 0.0:
        return fixed_high, 0.0, fixed_high
    # eigenvector of the high eigenvalue: (h01, high − h00) or (high − h11, h01)
    ux, uy = (h01, high - h00) if abs(high - h00) > abs(high - h11) else (high - h11, h01)
    norm = np.sqrt(ux * ux + uy * uy)
    ux, uy = ux / norm, uy / norm
    vx, vy = -uy, ux
    return (
        fixed_high * ux * ux + fixed_low * vx * vx,
        fixed_high * ux * uy + fixed_low * vx * vy,
        fixed_high * uy * uy + fixed_low * vy * vy,
    )


@numba.njit(cache=True, nogil=True)
def block_tree_solve(h00, h01, h11, index, n_vars, rhs, least=0.0):
    """``x`` (n_vars, p) with ``H x = rhs`` for two components' grouped 2×2 blocks, in O(n).

    ``H = Σ_k E_kᵀ [[h00_k, h01_k], [h01_k, h11_k]] E_k``, ``E_k`` picking the
    reduced variables ``index[k]`` (n, 2) of point ``k`` (−1: anchored, left
    out). Each component's variables are intervals of points (an offset held
    to its predecessor joins its group), so two variables couple only where a
    group of one component overlaps a group of the other: a forest. Eliminated
    in the order of their last point (component 0 first on a tie), each has at
    most one neighbour left (the other component's group at its last point),
    so LDLᵀ makes no fill: O(n) where the dense Cholesky it replaces was
    O(n³) (issue 34: a 250-point 3-D plan's Newton step, 500 variables).
    Returns ``(x, ok)``; ``ok`` False (``x`` unusable) where a pivot is not
    above ``least`` (0: ``H`` is not positive definite).
    """
    n = index.shape[0]
    n_cols = rhs.shape[1]
    pivot = np.zeros(n_vars)
    last = np.empty(n_vars, dtype=np.int64)
    for k in range(n):
        v0, v1 = index[k, 0], index[k, 1]
        if v0 >= 0:
            pivot[v0] += h00[k]
            last[v0] = k
        if v1 >= 0:
            pivot[v1] += h11[k]
            last[v1] = k
    parent = np.full(n_vars, -1, dtype=np.int64)
    up = np.zeros(n_vars)  # the coupling of a variable to its parent
    order = np.empty(n_vars, dtype=np.int64)
    count = 0
    for k in range(n):
        v0, v1 = index[k, 0], index[k, 1]
        if v0 >= 0 and v1 >= 0:
            if last[v0] <= last[v1]:
                parent[v0] = v1
                up[v0] += h01[k]
            else:
                parent[v1] = v0
                up[v1] += h01[k]
        for i in range(2):
            v = index[k, i]
            if v >= 0 and last[v] == k:
                order[count] = v
                count += 1
    x = np.empty((n_vars, n_cols))
    for v in range(n_vars):
        for p in range(n_cols):
            x[v, p] = rhs[v, p]
    factor = np.zeros(n_vars)
    for t in range(n_vars):
        v = order[t]
        if not pivot[v] > least:  # NaN too
            return x, False
        w = parent[v]
        if w >= 0:
            factor[v] = up[v] / pivot[v]
            pivot[w] -= factor[v] * up[v]
            for p in range(n_cols):
                x[w, p] -= factor[v] * x[v, p]
    for v in range(n_vars):
        for p in range(n_cols):
            x[v, p] /= pivot[v]
    for t in range(n_vars - 1, -1, -1):
        v = order[t]
        w = parent[v]
        if w >= 0:
            for p in range(n_cols):
                x[v, p] -= factor[v] * x[w, p]
    return x, True


@numba.njit(cache=True, nogil=True)
def offsets_newton(c, b, a, weight, max_step, d0, d, tol, max_iter):
    """:func:`planner_newton` without hard radii (the thesis's model)."""
    rr, nr, inner2, outer2 = _without_radii(d.shape[0], d.shape[1])
    return planner_newton(
        c, b, a, weight, rr, nr, inner2, outer2, 0.0, max_step, d0, d, tol, max_iter
    )


@numba.njit(cache=True, nogil=True)  # the IOC runs demonstrations on threads
def planner_newton(c, b, a, weight, rr, nr, inner2, outer2, mu, max_step, d0, d, tol, max_iter):
    """Projected Newton on the actions ``a_k = d_k − d_{k−1}``, box ``|a| <= max_step``.

    ``d`` (n, m) holds the start on entry and the optimum on exit. The start
    must have a finite cost (outside every hard radius): the line search never
    accepts a step into one. Returns ``(cost, iterations, converged)``. See
    ``lfdkit.emulate.planner``. With more than :data:`LISTED_TERMS` terms a
    point, each cost and derivative sums only the terms :func:`live_terms`
    finds may be nonzero near the offsets (a 3-D plan among boxes: 54 bumps
    and 390 hard radii a point, of which a handful are live), to the bit the
    sums over all of them.
    """
    n, m = d.shape
    actions = np.empty((n, m))
    for k in range(n):
        for i in range(m):
            previous = d0[i] if k == 0 else d[k - 1, i]
            actions[k, i] = min(max(d[k, i] - previous, -max_step), max_step)
    for i in range(m):
        running = d0[i]
        for k in range(n):
            running += actions[k, i]
            d[k, i] = running
    gradient = np.empty((n, m))
    hessian = np.empty((n, m, m))
    action_gradient = np.empty((n, m))
    free = np.empty((n, m), dtype=np.bool_)
    index = np.empty((n, m), dtype=np.int64)
    step_d = np.empty((n, m))
    step_a = np.empty((n, m))
    trial_a = np.empty((n, m))
    trial_d = np.empty((n, m))
    block00, block01, block11 = np.zeros(n), np.zeros(n), np.zeros(n)  # 3-D: positive blocks
    # The reduced system's gradient, move and 2-D curvature: at most n m variables, each
    # refinement's on the front of these (not three arrays a refinement).
    g_all, move_all, h_all = np.empty(n * m), np.empty(n * m), np.empty(n * m)
    # The base weight (the smallest) sets the scales, so a goal ramp does not loosen them.
    base = weight.min()
    floor = 1e-8 * 2.0 * base
    scale = 1.0 + 2.0 * base * max_step
    # Each point's live terms, listed again whenever the offsets move beyond LIVE_REACH
    # action bounds of where they were listed: the same sums, without the exact zeros.
    every = c.shape[1] + rr.shape[1] <= LISTED_TERMS or not np.isfinite(max_step)
    reach = LIVE_REACH * max_step
    centre = d.copy()
    bumps = np.empty((n, 0 if every else c.shape[1]), dtype=np.int64)
    hards = np.empty((n, 0 if every else rr.shape[1]), dtype=np.int64)
    n_bumps, n_hards = np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64)
    if not every:
        live_terms(c, b, a, rr, nr, outer2, centre, reach, bumps, n_bumps, hards, n_hards)
    cost = _listed_derivatives(
        c, b, a, weight, rr, nr, inner2, outer2, mu, d, gradient, hessian,
        every, bumps, n_bumps, hards, n_hards,
    )  # fmt: skip
    if not np.isfinite(cost):
        return cost, 0, False
    for iteration in range(max_iter):
        worst = 0.0
        for i in range(m):
            running = 0.0
            for k in range(n - 1, -1, -1):
                running += gradient[k, i]
                action_gradient[k, i] = running
                upper = actions[k, i] >= max_step * (1.0 - 1e-12)
                lower = actions[k, i] <= -max_step * (1.0 - 1e-12)
                held = (upper and running < 0.0) or (lower and running > 0.0)
                free[k, i] = not held
                if not held and abs(running) > worst:
                    worst = abs(running)
        if worst <= tol * scale:
            return cost, iteration, True
        # Refine the held set: an action at its bound that the Newton step would push
        # further out is held too (the gradient alone misses it), and the step redone.
        for _refine in range(8):
            n_vars = offset_groups(free, index)
            g = g_all[:n_vars]
            g[:] = 0.0
            for k in range(n):
                for i in range(m):
                    if index[k, i] >= 0:
                        g[index[k, i]] += gradient[k, i]
            move = move_all[:n_vars]
            if m == 1:
                h = h_all[:n_vars]
                h[:] = 0.0
                for k in range(n):
                    if index[k, 0] >= 0:
                        h[index[k, 0]] += hessian[k, 0, 0]
                for v in range(n_vars):
                    move[v] = -g[v] / max(abs(h[v]), floor)
            else:
                # The reduced system, a sum of the points' 2×2 blocks, couples its groups
                # as a forest: an O(n) elimination (block_tree_solve) replaces a dense
                # factorisation. The blocks as they are where that system is definite
                # (every pivot above the floor), else each made positive definite first
                # (eigenvalues by their magnitude, at least the floor), and the sum with
                # them. Making each positive always lengthened a group's curvature where
                # one of its points curved down, and the solve crept (3-D IOC plans of
                # boxes_sides, seed 0, fold 3: median 20 iterations, 99 of 1,064 at 200;
                # now 5, and 3).
                for k in range(n):
                    if index[k, 0] < 0 and index[k, 1] < 0:
                        continue
                    block00[k] = hessian[k, 0, 0]
                    block01[k] = hessian[k, 0, 1]
                    block11[k] = hessian[k, 1, 1]
                solved, definite = block_tree_solve(
                    block00, block01, block11, index, n_vars, g.reshape(n_vars, 1), floor
                )
                if not definite:
                    for k in range(n):
                        if index[k, 0] < 0 and index[k, 1] < 0:
                            continue
                        block00[k], block01[k], block11[k] = _positive_block(
                            hessian[k, 0, 0], hessian[k, 0, 1], hessian[k, 1, 1], floor
                        )
                    solved, _ = block_tree_solve(
                        block00, block01, block11, index, n_vars, g.reshape(n_vars, 1)
                    )
                for v in range(n_vars):
                    move[v] = -solved[v, 0]
            for k in range(n):
                for i in range(m):
                    step_d[k, i] = move[index[k, i]] if index[k, i] >= 0 else 0.0
            changed = False
            for i in range(m):
                for k in range(n):
                    if not free[k, i]:
                        continue
                    before = step_d[k - 1, i] if k > 0 else 0.0
                    change = step_d[k, i] - before
                    if (actions[k, i] >= max_step * (1.0 - 1e-9) and change > 0.0) or (
                        actions[k, i] <= -max_step * (1.0 - 1e-9) and change < 0.0
                    ):
                        free[k, i] = False
                        changed = True
            if not changed:
                break
        # Two ways back onto the bounds, and the better is taken: clamp each offset to
        # its predecessor's box (a clipped action moves only its own offset, not the
        # rest of the path, which a stiff goal weight at the end makes expensive), or
        # clip the actions (Bertsekas's projection arc).
        for i in range(m):
            for k in range(n):
                before = step_d[k - 1, i] if k > 0 else 0.0
                step_a[k, i] = step_d[k, i] - before
        accepted = False
        best_cost = np.inf
        for retraction in range(2):
            t = 1.0
            for _ in range(60 if retraction else 30):
                decrease = 0.0
                for i in range(m):
                    previous = d0[i]
                    for k in range(n):
                        if retraction == 0:
                            value = d[k, i] + t * step_d[k, i]
                            value = min(max(value, previous - max_step), previous + max_step)
                            decrease += gradient[k, i] * (value - d[k, i])
                        else:
                            action = actions[k, i] + t * step_a[k, i]
                            action = min(max(action, -max_step), max_step)
                            decrease += action_gradient[k, i] * (action - actions[k, i])
                            value = previous + action
                        trial_d[k, i] = value
                        previous = value
                if not (every or _within(trial_d, centre, reach)):
                    centre[:, :] = trial_d
                    live_terms(
                        c, b, a, rr, nr, outer2, centre, reach, bumps, n_bumps, hards, n_hards
                    )
                trial_cost = _listed_cost(
                    c, b, a, weight, rr, nr, inner2, outer2, mu, trial_d,
                    every, bumps, n_bumps, hards, n_hards,
                )  # fmt: skip
                if trial_cost <= cost + 1e-4 * decrease and (retraction == 1 or decrease < 0.0):
                    if trial_cost < best_cost:
                        best_cost = trial_cost
                        trial_a[:, :] = trial_d
                    accepted = True
                    break
                t *= 0.5
            if accepted and t == 1.0:
                break  # a full Newton step: nothing better to look for
        trial_d[:, :] = trial_a
        for i in range(m):
            previous = d0[i]
            for k in range(n):
                trial_a[k, i] = trial_d[k, i] - previous
                previous = trial_d[k, i]
        if not accepted:
            # No decrease left to find: stationary to round-off if the gradient is tiny.
            return cost, iteration + 1, worst <= 1e-6 * scale
        change = 0.0
        for k in range(n):
            for i in range(m):
                change = max(change, abs(trial_d[k, i] - d[k, i]))
        actions[:, :] = trial_a
        d[:, :] = trial_d
        if not (every or _within(d, centre, reach)):
            centre[:, :] = d
            live_terms(c, b, a, rr, nr, outer2, centre, reach, bumps, n_bumps, hards, n_hards)
        cost = _listed_derivatives(
            c, b, a, weight, rr, nr, inner2, outer2, mu, d, gradient, hessian,
            every, bumps, n_bumps, hards, n_hards,
        )  # fmt: skip
        if change <= 1e-13 * max_step:
            return cost, iteration + 1, worst <= 1e-6 * scale  # the steps stopped moving
    return cost, max_iter, False
