"""Compiled global search of the planner on a lateral grid (numba).

Dynamic programmes over a grid of lateral offsets for
:mod:`lfdkit.emulate.planner`: the states' costs (:func:`grid_node_costs`; in two parts,
:func:`grid_state_costs` and :func:`grid_hard_costs`),
the backward cost-to-go (:func:`grid_backward`, :func:`grid_cost_to_go`),
following it from a start (:func:`grid_walk`), the whole search
(:func:`lateral_dp`), the 2-D receding-horizon loop
(:func:`receding_horizon_2d`) and its executed step's bound on a return to
the nominal (:func:`return_clamped`). Argument names as the attributes of
:class:`lfdkit.emulate.problem.Problem`; the cost is the one of
:mod:`._problem_kernels`, whose cost of one point it shares.

Imported lazily: compiling costs a few seconds once, after which the machine
code is cached on disk next to this file. Every entry point releases the GIL
(``nogil``): plans run side by side on threads (a Dask worker's, a skill's
model choice: issue 34).
"""

import numba
import numpy as np

from lfdkit.emulate._problem_kernels import barrier, planner_cost, planner_newton, point_cost


@numba.njit(cache=True, nogil=True)
def grid_node_costs(c, b, a, weight, rr, nr, inner2, outer2, mu, levels, out):
    """Cost of every grid state at every point: ``out`` (n, G^m), m from its width.

    At each point, obstacles whose term is negligible at every offset (the
    exponent's minimum over all offsets above 40, or the squared distance's
    minimum beyond the barrier) are left out of that point's states.
    """
    g_count = levels.shape[0]
    n = out.shape[0]
    m = 2 if out.shape[1] != g_count else 1
    if m == 1:
        _node_costs_1d(c, b, a, weight, rr, nr, inner2, outer2, mu, levels, out)
        return
    if _ascending(levels):
        _node_costs_2d(c, b, a, weight, rr, nr, inner2, outer2, mu, levels, out)
        return
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
                lowest = _lowest_2d(c, b, a, k, o)
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
        near, hit = bumps[:n_bumps], hards[:n_hards]
        for s in range(out.shape[1]):
            point[0] = levels[s // g_count if m == 2 else s]
            if m == 2:
                point[1] = levels[s % g_count]
            out[k, s] = point_cost(c, b, a, weight, rr, nr, inner2, outer2, mu, k, point, near, hit)


@numba.njit(cache=True, nogil=True)
def grid_state_costs(c, b, a, weight, levels, out):
    """:func:`grid_node_costs`' first terms into ``out`` (n, G^m): the weight's, the obstacles'.

    With :func:`grid_hard_costs` after it, :func:`grid_node_costs` bit for
    bit. They depend on the reward and the levels alone, not on the hard
    radii a plan keeps, so plans of one scene with other floors or blockers
    share them (``planner._node_costs``). ``levels`` must rise.
    """
    if out.shape[1] == levels.shape[0]:
        _state_costs_1d(c, b, a, weight, levels, out)
    else:
        _state_costs_2d(c, b, a, weight, levels, out)


@numba.njit(cache=True, nogil=True)
def grid_hard_costs(rr, nr, inner2, outer2, mu, levels, out):
    """:func:`grid_node_costs`' last terms added to ``out`` (n, G^m): the hard radii's barriers.

    ``levels`` must rise.
    """
    if out.shape[1] == levels.shape[0]:
        _hard_costs_1d(rr, nr, inner2, outer2, mu, levels, out)
    else:
        _hard_costs_2d(rr, nr, inner2, outer2, mu, levels, out)


@numba.njit(cache=True, nogil=True)
def _node_costs_1d(c, b, a, weight, rr, nr, inner2, outer2, mu, levels, out):
    """:func:`grid_node_costs` in 2-D (one offset component), term by term over the levels.

    Each state's sum takes the same terms in the same order as
    :func:`~._problem_kernels.point_cost` (the nominal weight, the kept
    obstacles, the hard radii), so the same numbers bit for bit; a whole row
    per term, not a call per state, is six times faster (issue 26).
    """
    _state_costs_1d(c, b, a, weight, levels, out)
    _hard_costs_1d(rr, nr, inner2, outer2, mu, levels, out)


@numba.njit(cache=True, nogil=True)
def _state_costs_1d(c, b, a, weight, levels, out):
    """:func:`_node_costs_1d`'s first terms: the nominal weight's and the kept obstacles'."""
    n, g_count = out.shape
    for k in range(n):
        row = out[k]
        w = weight[k]
        for s in range(g_count):
            g = levels[s]
            row[s] = 0.0 + w * g * g
        for o in range(c.shape[1]):
            ck, bk, ak = c[k, o], b[k, o, 0], a[k, o, 0, 0]
            if not ck - bk**2 / max(ak, 1e-300) < 40.0:  # negligible at every offset
                continue
            for s in range(g_count):
                g = levels[s]
                row[s] += np.exp(-(ck + (bk + (bk + ak * g)) * g))


@numba.njit(cache=True, nogil=True)
def _hard_costs_1d(rr, nr, inner2, outer2, mu, levels, out):
    """:func:`_node_costs_1d`'s last terms, added to ``out``: the hard radii's barriers."""
    n, g_count = out.shape
    for k in range(n):
        row = out[k]
        for h in range(rr.shape[1]):
            rk, nk = rr[k, h], nr[k, h, 0]
            if not rk - nk**2 < outer2[h]:  # beyond the barrier at every offset
                continue
            for s in range(g_count):
                g = levels[s]
                row[s] += barrier(rk + (2.0 * nk + g) * g, inner2[h], outer2[h], mu)[0]


@numba.njit(cache=True, inline="always")
def _lowest_2d(c, b, a, k, o):
    """Obstacle term ``o``'s least exponent at point ``k`` over every 2-D offset.

    The least of ``c + 2bᵀd + dᵀAd`` over ``d`` is ``c − bᵀA⁻¹b`` (A positive
    definite); terms whose least is above 40 are negligible at every offset.
    """
    det = a[k, o, 0, 0] * a[k, o, 1, 1] - a[k, o, 0, 1] * a[k, o, 1, 0]
    det = max(det, 1e-300)
    quad = (
        a[k, o, 1, 1] * b[k, o, 0] ** 2
        - 2.0 * a[k, o, 0, 1] * b[k, o, 0] * b[k, o, 1]
        + a[k, o, 0, 0] * b[k, o, 1] ** 2
    ) / det
    return c[k, o] - quad


@numba.njit(cache=True, nogil=True)
def _ascending(levels):
    """Whether ``levels`` rise strictly (the lateral grid's do), all finite."""
    for s in range(levels.shape[0]):
        if not np.isfinite(levels[s]) or (s > 0 and not levels[s] > levels[s - 1]):
            return False
    return True


@numba.njit(cache=True, nogil=True)
def _node_costs_2d(c, b, a, weight, rr, nr, inner2, outer2, mu, levels, out):
    """:func:`grid_node_costs` in 3-D (two offset components), term by term over the states.

    Each state's sum takes the same terms in the same order as
    :func:`~._problem_kernels.point_cost` (the nominal weight, the kept
    obstacles, the hard radii), so the same numbers bit for bit. A hard
    radius adds ``0.0`` (nothing) wherever its squared distance is beyond the
    barrier, which outside a disc of the grid it is at every state: each row
    of states (``levels[i]`` first) goes only over the columns within that
    disc, widened by ``1e-9`` of the terms' size (far more than their
    rounding) and a cell. With 3-D side blockers (a hundred hard radii at a
    point) the states' costs took most of a fit's replanning (issue 34).
    ``levels`` must rise (:func:`_ascending`).
    """
    _state_costs_2d(c, b, a, weight, levels, out)
    _hard_costs_2d(rr, nr, inner2, outer2, mu, levels, out)


@numba.njit(cache=True, nogil=True)
def _state_costs_2d(c, b, a, weight, levels, out):
    """:func:`_node_costs_2d`'s first terms: the nominal weight's and the kept obstacles'."""
    n = out.shape[0]
    g_count = levels.shape[0]
    bumps = np.empty(c.shape[1], dtype=np.int64)
    for k in range(n):
        row = out[k]
        w = weight[k]
        for i in range(g_count):
            g0 = levels[i]
            for j in range(g_count):
                g1 = levels[j]
                row[i * g_count + j] = (0.0 + w * g0 * g0) + w * g1 * g1
        n_bumps = 0
        for o in range(c.shape[1]):
            if _lowest_2d(c, b, a, k, o) < 40.0:
                bumps[n_bumps] = o
                n_bumps += 1
        for t in range(n_bumps):
            o = bumps[t]
            ck, b0, b1 = c[k, o], b[k, o, 0], b[k, o, 1]
            a00, a01, a10, a11 = a[k, o, 0, 0], a[k, o, 0, 1], a[k, o, 1, 0], a[k, o, 1, 1]
            for i in range(g_count):
                g0 = levels[i]
                p0 = b0 + a00 * g0
                p1 = b1 + a10 * g0
                for j in range(g_count):
                    g1 = levels[j]
                    s = (ck + (b0 + (p0 + a01 * g1)) * g0) + (b1 + (p1 + a11 * g1)) * g1
                    row[i * g_count + j] += np.exp(-s)


@numba.njit(cache=True, nogil=True)
def _hard_costs_2d(rr, nr, inner2, outer2, mu, levels, out):
    """:func:`_node_costs_2d`'s last terms, added to ``out``: each hard radius over its disc."""
    n = out.shape[0]
    g_count = levels.shape[0]
    widest = 0.0
    for s in range(g_count):
        widest = max(widest, abs(levels[s]))
    for k in range(n):
        row = out[k]
        for h in range(rr.shape[1]):
            r0, n0, n1 = rr[k, h], nr[k, h, 0], nr[k, h, 1]
            if not (r0 - n0**2) - n1**2 < outer2[h]:  # beyond the barrier at every offset
                continue
            # (2n + g)g = (g + n)² − n²: within the barrier only where (g1 + n1)² < reach
            tol = 1e-9 * (abs(r0) + n0**2 + n1**2 + abs(outer2[h]) + 2.0 * widest**2)
            for i in range(g_count):
                g0 = levels[i]
                part = r0 + (2.0 * n0 + g0) * g0
                reach = outer2[h] - part + n1**2 + tol
                if reach < 0.0:
                    continue
                if np.isfinite(reach):
                    half = np.sqrt(reach)
                    first = max(np.searchsorted(levels, -n1 - half) - 1, 0)
                    last = min(np.searchsorted(levels, -n1 + half, "right") + 1, g_count)
                else:
                    first, last = 0, g_count
                for j in range(first, last):
                    g1 = levels[j]
                    u = part + (2.0 * n1 + g1) * g1
                    row[i * g_count + j] += barrier(u, inner2[h], outer2[h], mu)[0]


@numba.njit(cache=True, inline="always")
def _window_min(values, start, stride, g_count, window, out, out_start):
    """Sliding minimum along one grid axis.

    ``out[out_start + s·stride]`` = the smallest of ``values[start + t·stride]``
    over ``|t − s| ≤ window``, ``0 ≤ s, t < g_count``.
    """
    for s in range(g_count):
        best = np.inf
        for t in range(max(0, s - window), min(g_count, s + window + 1)):
            v = values[start + t * stride]
            if v < best:
                best = v
        out[out_start + s * stride] = best


@numba.njit(cache=True, nogil=True)
def _box_min(values, g_count, m, window, inner, out):
    """``out[s]`` = the smallest of ``values`` over the states within ``window`` cells of ``s``.

    In 3-D (``m`` 2, state ``i·G + j``) the box is separable: a sliding
    minimum along ``j`` into ``inner``, then along ``i``.
    """
    if m == 1:
        _window_min(values, 0, 1, g_count, window, out, 0)
        return
    for i in range(g_count):
        _window_min(values, i * g_count, 1, g_count, window, inner, i * g_count)
    for j in range(g_count):
        _window_min(inner, j, g_count, g_count, window, out, j)


@numba.njit(cache=True, nogil=True)
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


@numba.njit(cache=True, nogil=True)
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


@numba.njit(cache=True, nogil=True)
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


@numba.njit(cache=True, nogil=True)
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


@numba.njit(cache=True, nogil=True)
def return_clamped(anchor, new, back):
    """Bound the step from ``anchor`` to ``new`` toward the nominal by ``back``, in place.

    Per component: from ``anchor > 0`` the offset falls by at most ``back``
    (``new ≥ anchor − back``), from ``anchor < 0`` it rises by at most
    ``back``; from 0, and away from the nominal, the step is left as it is.
    The receding horizon's executed step of a person who swerves at the
    action bound and returns more slowly (``back`` = ``r · max_step``).
    """
    for i in range(new.shape[0]):
        if anchor[i] > 0.0 and new[i] < anchor[i] - back:
            new[i] = anchor[i] - back
        elif anchor[i] < 0.0 and new[i] > anchor[i] + back:
            new[i] = anchor[i] + back


@numba.njit(cache=True, nogil=True)  # plans on threads (a Dask worker's) run side by side
def receding_horizon_2d(
    c,
    b,
    a,
    weight,
    rr,
    nr,
    inner2,
    outer2,
    mu,
    max_step,
    d0,
    horizon,
    ahead,
    reach_goal,
    lookahead,
    table,
    node,
    levels,
    cells,
    b_norm,
    radius,
    outer,
    distance2,
    reach,
    norms,
    largest,
    tol,
    max_iter,
    offsets,
    back,
):
    """The MPC loop of ``lfdkit.emulate.planner._receding_horizon`` for a 2-D scene with obstacles.

    Every step, operation for operation, as the planner's Python loop does it
    with these kernels (issue 26: that loop's glue around small kernel calls
    was four fifths of an MPC plan): the obstacle test of the look-ahead's
    ``ahead`` points (at least the window's; ``b_norm`` (n, L) the norms of
    ``b``, ``radius`` (n, H) and ``outer`` (H,) the hard balls' distance and
    outer radius), the warm start alone away
    from obstacles, else the warm start and the grid path (the global route
    from ``table``, the cost-to-go over ``levels`` with ``cells`` per step,
    ``node`` its states' costs; without ``lookahead`` the window's own best
    grid path, its grid from the per-point reaches ``distance2``, ``reach``,
    ``norms``, ``largest`` (all (L + H, n))) polished and ranked. A window's
    own grid on ``levels``' spacing takes its states' costs from ``node`` (a
    state's cost depends on its point and level alone: the same numbers, and
    no ``exp`` per window and state). ``back``: the largest executed step
    toward the nominal (units; :func:`return_clamped`, none at ``max_step``
    or more). Fills ``offsets`` (n + 1, 1), row 0 ``d0``; returns
    ``(iterations, converged, failed)``: ``failed`` the step whose every
    candidate entered a hard radius (−1: none).
    """
    n, m = c.shape[0], d0.shape[0]
    n_obs, n_hard, n_rows = c.shape[1], radius.shape[1], distance2.shape[0]
    root_m = np.sqrt(m)
    reach_grid = max_step * (1.0 + 1e-12)
    no_extra = np.zeros((0, 0))
    offsets[0] = d0
    guess = np.zeros((min(horizon, n), m))
    total_iter, all_ok = 0, True
    for k in range(n):
        stop = min(k + horizon, n)
        h = stop - k
        if guess.shape[0] > h:
            guess = guess[:h]
        elif guess.shape[0] < h:
            longer = np.empty((h, m))
            longer[: guess.shape[0]] = guess
            for i in range(guess.shape[0], h):
                longer[i] = guess[guess.shape[0] - 1]
            guess = longer
        anchor = offsets[k].copy()
        cw, bw, aw, ww = c[k:stop], b[k:stop], a[k:stop], weight[k:stop]
        rrw, nrw = rr[k:stop], nr[k:stop]
        # _ObstacleNear over the look-ahead: the same operations in the same order
        seen = min(k + ahead, n)
        anchor_norm = np.sqrt(np.sum(anchor * anchor))
        within = anchor_norm + (seen - k) * max_step * root_m
        near = False
        for i in range(k, seen):
            for o in range(n_obs):
                if c[i, o] - 2.0 * b_norm[i, o] * within < 28.0:
                    near = True
        if not near:
            for i in range(k, seen):
                for o in range(n_hard):
                    if radius[i, o] - within < outer[o]:
                        near = True
        if not near:  # best_window(sides=False): the warm start alone
            d = guess.copy()
            cost, n_iter, ok = planner_newton(
                cw, bw, aw, ww, rrw, nrw, inner2, outer2, mu, max_step, anchor, d, tol, max_iter
            )
            total_iter += n_iter
        else:
            grid = np.zeros((h, m))
            route = grid_walk(table[k:stop], levels, cells, max_step, anchor, grid)
            blocked = not np.isfinite(route)
            if not lookahead and not blocked:  # the window's own best grid path
                farthest = np.abs(anchor).max()
                span = max(farthest, 2.0 * max_step)
                found, widest = False, 0.0
                for row in range(n_rows):  # _WindowReaches.widest
                    nearest = k
                    for i in range(k + 1, stop):
                        if distance2[row, i] < distance2[row, nearest]:
                            nearest = i
                    if norms[row, nearest] < reach[row, nearest]:
                        value = largest[row, nearest] + reach[row, nearest]
                        if not found or value > widest:
                            found, widest = True, value
                if found:
                    span = max(span, widest)
                span = min(span, farthest + h * max_step)
                own_cells = max(1, min(4, int(400 * max_step / span)))
                spacing = max_step / own_cells
                count = min(int(np.ceil(span / spacing)), 400)
                own_levels = spacing * np.arange(-count, count + 1)
                end_on = reach_goal and stop == n
                offset = 0  # own_levels[i] is level i + offset - count
                if not end_on:  # _reachable
                    first, last = -1, -1
                    for i in range(own_levels.shape[0]):
                        if abs(own_levels[i] - anchor[0]) <= reach_grid:
                            if first < 0:
                                first = i
                            last = i
                    if first >= 0:
                        spread = own_cells * (h - 1)
                        offset = max(0, first - spread)
                        own_levels = own_levels[offset : last + spread + 1]
                own = np.zeros((h, m))
                # lateral_dp. On the whole path's spacing, its states' costs are node's: a
                # state's cost depends on the point and the level alone (the same numbers).
                g_own = own_levels.shape[0]
                shift = (levels.shape[0] - 1) // 2 - count + offset  # node's index of level 0
                if own_cells == cells and shift >= 0 and shift + g_own <= node.shape[1]:
                    costs = np.ascontiguousarray(node[k:stop, shift : shift + g_own])
                    to_go = np.empty((h, g_own))
                    grid_backward(costs, g_own, own_cells, end_on, no_extra, to_go)
                    total = grid_walk(to_go, own_levels, own_cells, max_step, anchor, own)
                else:
                    total = lateral_dp(
                        cw, bw, aw, ww, rrw, nrw, inner2, outer2, mu, max_step, anchor,
                        own_levels, own_cells, end_on, no_extra, own,
                    )  # fmt: skip
                if np.isfinite(total):
                    grid = own
            # the candidates: the warm start, the grid path polished, (lookahead) the grid path
            n_cand = 1 if blocked else (3 if lookahead else 2)
            found, best_score = False, np.inf
            d, cost, ok = guess, np.inf, False
            first_d, first_ok = guess, False
            for j in range(n_cand):
                if j < 2:
                    candidate = (guess if j == 0 else grid).copy()
                    _, n_iter, converged = planner_newton(
                        cw, bw, aw, ww, rrw, nrw, inner2, outer2, mu, max_step, anchor,
                        candidate, tol, max_iter,
                    )  # fmt: skip
                    total_iter += n_iter
                    if j == 0:
                        first_d, first_ok = candidate, converged
                else:
                    candidate, converged = grid, True
                value = planner_cost(cw, bw, aw, ww, rrw, nrw, inner2, outer2, mu, candidate)
                follow = 0.0  # _cost_to_go
                if stop < n:
                    end = min(max(candidate[h - 1, 0], levels[0]), levels[levels.shape[0] - 1])
                    follow = np.inf
                    for i in range(levels.shape[0]):
                        if abs(levels[i] - end) <= reach_grid and table[stop, i] < follow:
                            follow = table[stop, i]
                if not np.isfinite(follow):
                    continue
                score = value + follow if lookahead else value
                if not found or score < best_score:
                    found, best_score = True, score
                    d, cost, ok = candidate, value, converged
            if not found:  # blocked everywhere
                d, cost, ok = first_d, np.inf, first_ok
        if not np.isfinite(cost):
            return total_iter, all_ok, k
        all_ok &= ok
        offsets[k + 1] = d[0]
        if back < max_step:
            return_clamped(anchor, offsets[k + 1], back)
        if h > 1:
            shifted = np.empty((h, m))
            shifted[: h - 1] = d[1:]
            shifted[h - 1] = d[h - 1]
            guess = shifted
        else:
            guess = d
    return total_iter, all_ok, -1
