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
@numba.njit(cache=True)
def offset_cost(c, b, a, weight, d):
    """Planner cost ``Σ Q_k|d_k|² + Σ exp(−(c + 2bᵀd + dᵀAd))``; see ``lfdkit.emulate.planner``."""
    n, n_obs = c.shape
    m = d.shape[1]
    total = 0.0
    for k in range(n):
        for i in range(m):
            total += weight[k] * d[k, i] * d[k, i]
        for o in range(n_obs):
            s = c[k, o]
            for i in range(m):
                npu = b[k, o, i]
                for j in range(m):
                    npu += a[k, o, i, j] * d[k, j]
                s += (b[k, o, i] + npu) * d[k, i]
            total += np.exp(-s)
    return total


@numba.njit(cache=True)
def offset_derivatives(c, b, a, weight, d, gradient, hessian):
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
    return total


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
def offsets_newton(c, b, a, weight, max_step, d0, d, tol, max_iter):
    """Projected Newton on the actions ``a_k = d_k − d_{k−1}``, box ``|a| <= max_step``.

    ``d`` (n, m) holds the start on entry and the optimum on exit. Returns
    ``(cost, iterations, converged)``. See ``lfdkit.emulate.planner``.
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
    cost = offset_derivatives(c, b, a, weight, d, gradient, hessian)
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
            h2 = np.zeros((n_vars, n_vars))
            for k in range(n):
                for i in range(m):
                    if index[k, i] < 0:
                        continue
                    for j in range(m):
                        if index[k, j] >= 0:
                            h2[index[k, i], index[k, j]] += hessian[k, i, j]
            values, vectors = np.linalg.eigh(h2)
            projected = vectors.T @ g
            for v in range(n_vars):
                projected[v] /= max(abs(values[v]), floor)
            move = -(vectors @ projected)
        for k in range(n):
            for i in range(m):
                step_d[k, i] = move[index[k, i]] if index[k, i] >= 0 else 0.0
                before = step_d[k - 1, i] if k > 0 else 0.0
                step_a[k, i] = step_d[k, i] - before
        t = 1.0
        accepted = False
        for _ in range(40):
            decrease = 0.0
            for i in range(m):
                running = d0[i]
                for k in range(n):
                    value = min(max(actions[k, i] + t * step_a[k, i], -max_step), max_step)
                    trial_a[k, i] = value
                    decrease += action_gradient[k, i] * (value - actions[k, i])
                    running += value
                    trial_d[k, i] = running
            trial_cost = offset_cost(c, b, a, weight, trial_d)
            if trial_cost <= cost + 1e-4 * decrease:
                accepted = True
                break
            t *= 0.5
        if not accepted:
            # No decrease left to find: stationary to round-off if the gradient is tiny.
            return cost, iteration + 1, worst <= 1e-6 * scale
        change = 0.0
        for k in range(n):
            for i in range(m):
                change = max(change, abs(trial_d[k, i] - d[k, i]))
        actions[:, :] = trial_a
        d[:, :] = trial_d
        cost = offset_derivatives(c, b, a, weight, d, gradient, hessian)
        if change <= 1e-13 * max_step:
            return cost, iteration + 1, worst <= 1e-6 * scale  # the steps stopped moving
    return cost, max_iter, False
