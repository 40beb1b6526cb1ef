"""Compiled inner loops (numba). Imported lazily: compiling costs a few seconds once,
after which the machine code is cached on disk next to this file.
"""

import numba
import numpy as np


@numba.njit(cache=True, inline="always")
def _check_chunk(p, t, verts, v0, n_seg, c, b, same_direction, tol, best, out_pt_row):
    """Best crossing of chunk ``c``; returns (distance, segment) improving on ``best``."""
    q = p.shape[0]
    best_seg = -1
    first = c * b
    last = min(first + b, n_seg)  # exclusive segment bound
    side_a = 0.0
    for k in range(q):
        side_a += (verts[v0 + first, k] - p[k]) * t[k]
    if abs(side_a) <= tol:
        side_a = 0.0
    for s in range(first, last):
        side_b = 0.0
        for k in range(q):
            side_b += (verts[v0 + s + 1, k] - p[k]) * t[k]
        if abs(side_b) <= tol:
            side_b = 0.0
        if same_direction:
            crosses = side_a <= 0.0 and side_b >= 0.0 and side_b > side_a
        else:
            crosses = (side_a <= 0.0 and side_b >= 0.0) or (side_a >= 0.0 and side_b <= 0.0)
        if crosses:
            ds = side_b - side_a
            u = -side_a / ds if ds != 0.0 else 0.0
            d2 = 0.0
            for k in range(q):
                a = verts[v0 + s, k]
                x = a + u * (verts[v0 + s + 1, k] - a) - p[k]
                d2 += x * x
            d = np.sqrt(d2)
            if d < best:
                best = d
                best_seg = s
                for k in range(q):
                    a = verts[v0 + s, k]
                    out_pt_row[k] = a + u * (verts[v0 + s + 1, k] - a)
        side_a = side_b
    return best, best_seg


@numba.njit(cache=True, inline="always")
def _one_query(i, max_chunks, points, tangents, polylines, b, same_direction, tol, out):
    """All polylines for query ``i`` (see :func:`nearest_crossings`)."""
    verts, vert_offset, n_seg, centres, radii, chunk_offset, n_chunks = polylines
    out_pt, out_seg, out_dist = out
    q = points.shape[1]
    n = n_seg.shape[0]
    p = points[i]
    t = tangents[i]
    lower = np.empty(max_chunks)
    for j in range(n):
        c0 = chunk_offset[j]
        first_c = -1
        first_lb = np.inf
        for c in range(n_chunks[j]):
            along = 0.0
            d2 = 0.0
            for k in range(q):
                diff = centres[c0 + c, k] - p[k]
                along += diff * t[k]
                d2 += diff * diff
            # Widen each ball by the on-plane tolerance so that a vertex counted
            # as lying on the plane is never in a pruned chunk.
            r = radii[c0 + c] + tol
            lb = np.sqrt(d2) - r if abs(along) <= r else np.inf
            lower[c] = lb
            if lb < first_lb:
                first_lb = lb
                first_c = c
        if first_c < 0:
            continue
        best, seg = _check_chunk(
            p,
            t,
            verts,
            vert_offset[j],
            n_seg[j],
            first_c,
            b,
            same_direction,
            tol,
            np.inf,
            out_pt[i, j],
        )
        for c in range(n_chunks[j]):
            if c != first_c and lower[c] < best:
                d, s = _check_chunk(
                    p,
                    t,
                    verts,
                    vert_offset[j],
                    n_seg[j],
                    c,
                    b,
                    same_direction,
                    tol,
                    best,
                    out_pt[i, j],
                )
                if s >= 0:
                    best, seg = d, s
        if seg >= 0:
            out_seg[i, j] = seg
            out_dist[i, j] = best


@numba.njit(cache=True)
def _max_chunks(n_chunks):
    out = 0
    for j in range(n_chunks.shape[0]):
        out = max(out, n_chunks[j])
    return out


@numba.njit(cache=True)
def _serial(points, tangents, polylines, b, same_direction, tol, out):
    max_chunks = _max_chunks(polylines[6])
    for i in range(points.shape[0]):
        _one_query(i, max_chunks, points, tangents, polylines, b, same_direction, tol, out)


@numba.njit(parallel=True, cache=True)
def _parallel(points, tangents, polylines, b, same_direction, tol, out):
    max_chunks = _max_chunks(polylines[6])
    for i in numba.prange(points.shape[0]):
        _one_query(i, max_chunks, points, tangents, polylines, b, same_direction, tol, out)


def nearest_crossings(points, tangents, polylines, b, same_direction, tol, out) -> None:
    """Nearest crossing of each query's normal hyperplane with each polyline.

    See :class:`lfdkit.geometry.PolylineSet` for the method. ``polylines`` is the
    tuple (verts, vert_offset, n_seg, centres, radii, chunk_offset, n_chunks);
    results are written in place into ``out`` = (points (m, n, q), segment
    (m, n), distance (m, n)). Small problems run serially: starting threads costs
    more than it saves there, and far more when the cores are busy.
    """
    kernel = _parallel if points.shape[0] * polylines[2].shape[0] >= 20_000 else _serial
    kernel(points, tangents, polylines, b, same_direction, tol, out)


@numba.njit(cache=True)
def evaluate_quintic_pieces(s, spacing, pieces, out):
    """Value, slope and curvature of a uniform piecewise quintic at ``s``.

    ``pieces`` (n_pieces, 6, q) holds the monomial coefficients of each piece in
    its local ``t = s / spacing − i``; ``out`` (q, 3, len(s)) receives the value
    and the first two derivatives in ``s``. See ``lfdkit.imitate.dmp``.
    """
    last = pieces.shape[0] - 1
    q = pieces.shape[2]
    inv, inv2 = 1.0 / spacing, 1.0 / (spacing * spacing)
    for j in range(s.shape[0]):
        i = min(int(s[j] * inv), last)
        t = s[j] * inv - i
        for d in range(q):
            c0, c1, c2 = pieces[i, 0, d], pieces[i, 1, d], pieces[i, 2, d]
            c3, c4, c5 = pieces[i, 3, d], pieces[i, 4, d], pieces[i, 5, d]
            out[d, 0, j] = ((((c5 * t + c4) * t + c3) * t + c2) * t + c1) * t + c0
            out[d, 1, j] = (
                (((5.0 * c5 * t + 4.0 * c4) * t + 3.0 * c3) * t + 2.0 * c2) * t + c1
            ) * inv
            out[d, 2, j] = (((20.0 * c5 * t + 12.0 * c4) * t + 6.0 * c3) * t + 2.0 * c2) * inv2


# ----------------------------------------------------------------- emulation
# The planner's cost in the lateral offsets d (see lfdkit.emulate.planner):
#   Σ_k Q_k |d_k|² + Σ_{k,o} exp(−(c + 2bᵀd + dᵀAd)) + Σ_{k,h} B(u_kh),
# with u = |x_k − O_h|² = rr + 2 nrᵀd + |d|² for the obstacles with a hard radius, and
# B the clearance barrier: 0 beyond the outer radius ρ, rising to +inf at the inner radius.
# Arrays with zero obstacles (shape (n, 0, …)) switch a term off.


@numba.njit(cache=True, inline="always")
def _barrier(u, inner2, outer2, mu):
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


@numba.njit(cache=True)
def _point_cost(c, b, a, weight, rr, nr, inner2, outer2, mu, k, g):
    """Cost of offset ``g`` (m,) at point ``k`` alone."""
    m = g.shape[0]
    total = 0.0
    for i in range(m):
        total += weight[k] * g[i] * g[i]
    for o in range(c.shape[1]):
        s = c[k, o]
        for i in range(m):
            npu = b[k, o, i]
            for j in range(m):
                npu += a[k, o, i, j] * g[j]
            s += (b[k, o, i] + npu) * g[i]
        total += np.exp(-s)
    for h in range(rr.shape[1]):
        u = rr[k, h]
        for i in range(m):
            u += (2.0 * nr[k, h, i] + g[i]) * g[i]
        total += _barrier(u, inner2[h], outer2[h], mu)[0]
    return total


@numba.njit(cache=True)
def planner_cost(c, b, a, weight, rr, nr, inner2, outer2, mu, d):
    """The planner cost of offsets ``d`` (n, m); ``+inf`` inside a hard radius."""
    total = 0.0
    for k in range(d.shape[0]):
        total += _point_cost(c, b, a, weight, rr, nr, inner2, outer2, mu, k, d[k])
    return total


@numba.njit(cache=True)
def planner_derivatives(c, b, a, weight, rr, nr, inner2, outer2, mu, d, gradient, hessian):
    """Cost; fills the gradient (n, m) and Hessian blocks (n, m, m) in the offsets."""
    n, n_obs = c.shape
    m = d.shape[1]
    total = 0.0
    npu = np.empty(m)
    for k in range(n):
        for i in range(m):
            total += weight[k] * d[k, i] * d[k, i]
            gradient[k, i] = 2.0 * weight[k] * d[k, i]
            for j in range(m):
                hessian[k, i, j] = 2.0 * weight[k] if i == j else 0.0
        for o in range(n_obs):
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
        for h in range(rr.shape[1]):
            u = rr[k, h]
            for i in range(m):
                u += (2.0 * nr[k, h, i] + d[k, i]) * d[k, i]
            value, first, second = _barrier(u, inner2[h], outer2[h], mu)
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


@numba.njit(cache=True)
def _without_radii(n, m):
    """The hard-radius arrays of a problem without any (the thesis's model)."""
    return np.zeros((n, 0)), np.zeros((n, 0, m)), np.zeros(0), np.zeros(0)


@numba.njit(cache=True)
def offset_cost(c, b, a, weight, d):
    """Planner cost without hard radii (the thesis's model)."""
    rr, nr, inner2, outer2 = _without_radii(d.shape[0], d.shape[1])
    return planner_cost(c, b, a, weight, rr, nr, inner2, outer2, 0.0, d)


@numba.njit(cache=True)
def offset_derivatives(c, b, a, weight, d, gradient, hessian):
    """:func:`planner_derivatives` without hard radii (the thesis's model)."""
    rr, nr, inner2, outer2 = _without_radii(d.shape[0], d.shape[1])
    return planner_derivatives(c, b, a, weight, rr, nr, inner2, outer2, 0.0, d, gradient, hessian)


@numba.njit(cache=True)
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


@numba.njit(cache=True)
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


@numba.njit(cache=True)
def _cholesky_solve(lower, rhs):
    """``x`` with ``L Lᵀ x = rhs`` for a lower-triangular ``L``."""
    n = rhs.shape[0]
    y = np.empty(n)
    for i in range(n):
        total = rhs[i]
        for j in range(i):
            total -= lower[i, j] * y[j]
        y[i] = total / lower[i, i]
    x = np.empty(n)
    for i in range(n - 1, -1, -1):
        total = y[i]
        for j in range(i + 1, n):
            total -= lower[j, i] * x[j]
        x[i] = total / lower[i, i]
    return x


@numba.njit(cache=True)
def offsets_newton(c, b, a, weight, max_step, d0, d, tol, max_iter):
    """:func:`planner_newton` without hard radii (the thesis's model)."""
    rr, nr, inner2, outer2 = _without_radii(d.shape[0], d.shape[1])
    return planner_newton(
        c, b, a, weight, rr, nr, inner2, outer2, 0.0, max_step, d0, d, tol, max_iter
    )


@numba.njit(cache=True)
def planner_newton(c, b, a, weight, rr, nr, inner2, outer2, mu, max_step, d0, d, tol, max_iter):
    """Projected Newton on the actions ``a_k = d_k − d_{k−1}``, box ``|a| <= max_step``.

    ``d`` (n, m) holds the start on entry and the optimum on exit. The start
    must have a finite cost (outside every hard radius): the line search never
    accepts a step into one. Returns ``(cost, iterations, converged)``. See
    ``lfdkit.emulate.planner``.
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
    # The base weight (the smallest) sets the scales, so a goal ramp does not loosen them.
    base = weight.min()
    floor = 1e-8 * 2.0 * base
    scale = 1.0 + 2.0 * base * max_step
    cost = planner_derivatives(c, b, a, weight, rr, nr, inner2, outer2, mu, d, gradient, hessian)
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
            g = np.zeros(n_vars)
            for k in range(n):
                for i in range(m):
                    if index[k, i] >= 0:
                        g[index[k, i]] += gradient[k, i]
            move = np.empty(n_vars)
            if m == 1:
                h = np.zeros(n_vars)
                for k in range(n):
                    if index[k, 0] >= 0:
                        h[index[k, 0]] += hessian[k, 0, 0]
                for v in range(n_vars):
                    move[v] = -g[v] / max(abs(h[v]), floor)
            else:
                # Each point's 2×2 block made positive definite (eigenvalues by their
                # magnitude, at least the floor): the reduced system, a sum of them, is
                # then positive definite and a Cholesky solve replaces a dense
                # eigen-decomposition (many times cheaper for long 3-D paths).
                h2 = np.zeros((n_vars, n_vars))
                for k in range(n):
                    if index[k, 0] < 0 and index[k, 1] < 0:
                        continue
                    p00, p01, p11 = _positive_block(
                        hessian[k, 0, 0], hessian[k, 0, 1], hessian[k, 1, 1], floor
                    )
                    i0, i1 = index[k, 0], index[k, 1]
                    if i0 >= 0:
                        h2[i0, i0] += p00
                    if i1 >= 0:
                        h2[i1, i1] += p11
                    if i0 >= 0 and i1 >= 0:
                        h2[i0, i1] += p01
                        h2[i1, i0] += p01
                lower = np.linalg.cholesky(h2)
                move = -_cholesky_solve(lower, g)
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
                trial_cost = planner_cost(c, b, a, weight, rr, nr, inner2, outer2, mu, trial_d)
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
        cost = planner_derivatives(
            c, b, a, weight, rr, nr, inner2, outer2, mu, d, gradient, hessian
        )
        if change <= 1e-13 * max_step:
            return cost, iteration + 1, worst <= 1e-6 * scale  # the steps stopped moving
    return cost, max_iter, False


@numba.njit(cache=True)
def grid_node_costs(c, b, a, weight, rr, nr, inner2, outer2, mu, levels, out):
    """Cost of every grid state at every point: ``out`` (n, G^m), m from its width.

    At each point, obstacles whose term is negligible at every offset (the
    exponent's minimum over all offsets above 40, or the squared distance's
    minimum beyond the barrier) are left out of that point's states.
    """
    g_count = levels.shape[0]
    n = out.shape[0]
    m = 2 if out.shape[1] != g_count else 1
    n_obs, n_hard = c.shape[1], rr.shape[1]
    point = np.empty(m)
    bumps = np.empty(n_obs, dtype=np.int64)
    hards = np.empty(n_hard, dtype=np.int64)
    for k in range(n):
        n_bumps = 0
        for o in range(n_obs):
            # min over d of c + 2bᵀd + dᵀAd is c − bᵀA⁻¹b (A positive definite)
            if m == 1:
                lowest = c[k, o] - b[k, o, 0] ** 2 / max(a[k, o, 0, 0], 1e-300)
            else:
                det = a[k, o, 0, 0] * a[k, o, 1, 1] - a[k, o, 0, 1] * a[k, o, 1, 0]
                det = max(det, 1e-300)
                quad = (
                    a[k, o, 1, 1] * b[k, o, 0] ** 2
                    - 2.0 * a[k, o, 0, 1] * b[k, o, 0] * b[k, o, 1]
                    + a[k, o, 0, 0] * b[k, o, 1] ** 2
                ) / det
                lowest = c[k, o] - quad
            if lowest < 40.0:
                bumps[n_bumps] = o
                n_bumps += 1
        n_hards = 0
        for h in range(n_hard):
            closest = rr[k, h]
            for i in range(m):
                closest -= nr[k, h, i] ** 2
            if closest < outer2[h]:
                hards[n_hards] = h
                n_hards += 1
        for s in range(out.shape[1]):
            point[0] = levels[s // g_count if m == 2 else s]
            if m == 2:
                point[1] = levels[s % g_count]
            total = 0.0
            for i in range(m):
                total += weight[k] * point[i] * point[i]
            for j in range(n_bumps):
                o = bumps[j]
                e = c[k, o]
                for i in range(m):
                    npu = b[k, o, i]
                    for jj in range(m):
                        npu += a[k, o, i, jj] * point[jj]
                    e += (b[k, o, i] + npu) * point[i]
                total += np.exp(-e)
            for j in range(n_hards):
                h = hards[j]
                u = rr[k, h]
                for i in range(m):
                    u += (2.0 * nr[k, h, i] + point[i]) * point[i]
                total += _barrier(u, inner2[h], outer2[h], mu)[0]
            out[k, s] = total


@numba.njit(cache=True)
def _box_min(values, g_count, m, window, inner, out):
    """``out[s]`` = the smallest of ``values`` over the states within ``window`` cells of ``s``."""
    if m == 1:
        for s in range(g_count):
            best = np.inf
            for t in range(max(0, s - window), min(g_count, s + window + 1)):
                if values[t] < best:
                    best = values[t]
            out[s] = best
        return
    for i in range(g_count):
        for j in range(g_count):
            best = np.inf
            for t in range(max(0, j - window), min(g_count, j + window + 1)):
                v = values[i * g_count + t]
                if v < best:
                    best = v
            inner[i * g_count + j] = best
    for i in range(g_count):
        for j in range(g_count):
            best = np.inf
            for t in range(max(0, i - window), min(g_count, i + window + 1)):
                v = inner[t * g_count + j]
                if v < best:
                    best = v
            out[i * g_count + j] = best


@numba.njit(cache=True)
def grid_cost_to_go(
    c, b, a, weight, rr, nr, inner2, outer2, mu, levels, window, end_zero, extra, out
):
    """Backward dynamic programme on the lateral grid (see :func:`lateral_dp`).

    Fills ``out`` (n, G^m) with the least cost of points ``k … n − 1`` over grid
    paths that start in each state at point ``k`` (with ``end_zero``, that end
    on 0); ``+inf`` where none avoids the hard radii. ``extra`` (n, G^m) is
    added to the states' costs (``+inf`` forbids a state; empty: nothing).
    """
    grid_node_costs(c, b, a, weight, rr, nr, inner2, outer2, mu, levels, out)
    grid_backward(out.copy(), levels.shape[0], window, end_zero, extra, out)


@numba.njit(cache=True)
def grid_backward(node, g_count, window, end_zero, extra, out):
    """:func:`grid_cost_to_go` from states' costs ``node`` (n, G^m) computed before."""
    n, n_states = out.shape
    m = 2 if n_states != g_count else 1
    for k in range(n):
        for s in range(n_states):
            out[k, s] = node[k, s] + (extra[k, s] if extra.shape[0] else 0.0)
    if end_zero:
        zero = (g_count - 1) // 2
        keep = zero * g_count + zero if m == 2 else zero
        for s in range(n_states):
            if s != keep:
                out[n - 1, s] = np.inf
    best = np.empty(n_states)
    inner = np.empty(n_states)
    for k in range(n - 2, -1, -1):
        _box_min(out[k + 1], g_count, m, window, inner, best)
        for s in range(n_states):
            out[k, s] += best[s]


@numba.njit(cache=True)
def lateral_dp(
    c, b, a, weight, rr, nr, inner2, outer2, mu, max_step, d0, levels, window, end_zero, extra, out
):
    """Globally best offsets on a lateral grid, by dynamic programming.

    Every offset component takes a value of ``levels`` (G,), an odd-length
    grid symmetric about 0 with spacing ``max_step / window`` at most, so a
    move of up to ``window`` cells per point respects the action bound. The
    first point is reached from ``d0`` (off the grid) within the bound; with
    ``end_zero`` the last offset is 0 (the plan ends on the nominal). States
    are G (m = 1) or G² (m = 2); each transition is a box, so the minimum
    over predecessors is a separable sliding minimum. Fills ``out`` (n, m)
    and returns its cost (``+inf`` when no grid path avoids the hard radii).
    """
    n, m = out.shape
    g_count = levels.shape[0]
    n_states = g_count**m
    value = np.empty((n, n_states))
    grid_cost_to_go(
        c, b, a, weight, rr, nr, inner2, outer2, mu, levels, window, end_zero, extra, value
    )
    return grid_walk(value, levels, window, max_step, d0, out)


@numba.njit(cache=True)
def grid_walk(value, levels, window, max_step, d0, out):
    """Follow a cost-to-go table (:func:`grid_cost_to_go`) from ``d0`` for ``out``'s rows.

    The first state is the best within the action bound of ``d0`` (off the
    grid), each next one the best within ``window`` cells. Fills ``out``
    (h, m), h ≤ n, and returns the table's value of the first state (the
    least cost of the whole remaining path; ``+inf`` if blocked).
    """
    h, m = out.shape
    g_count = levels.shape[0]
    reach = max_step * (1.0 + 1e-12)
    state, total = -1, np.inf
    for s in range(value.shape[1]):
        i0 = s // g_count if m == 2 else s
        if abs(levels[i0] - d0[0]) > reach:
            continue
        if m == 2 and abs(levels[s % g_count] - d0[1]) > reach:
            continue
        if value[0, s] < total:
            state, total = s, value[0, s]
    if not np.isfinite(total):
        return total
    for k in range(h):
        i0 = state // g_count if m == 2 else state
        j0 = state % g_count
        out[k, 0] = levels[i0]
        if m == 2:
            out[k, 1] = levels[j0]
        if k == h - 1:
            break
        best_state, best = -1, np.inf
        for t in range(max(0, i0 - window), min(g_count, i0 + window + 1)):
            if m == 1:
                if value[k + 1, t] < best:
                    best_state, best = t, value[k + 1, t]
            else:
                for u in range(max(0, j0 - window), min(g_count, j0 + window + 1)):
                    v = value[k + 1, t * g_count + u]
                    if v < best:
                        best_state, best = t * g_count + u, v
        state = best_state
    return total
