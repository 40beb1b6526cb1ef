"""Compiled inner loops of the inverse optimal control (numba).

The derivative of a plan with respect to θ (:mod:`lfdkit.emulate.ioc`), for
one full-horizon plan and for every window of a receding-horizon plan. The
problem's own compiled pieces (projected Newton, cost derivatives, action
groups) come from :mod:`._problem_kernels` through its public functions.
Imported lazily: compiling costs a few seconds once, after which the machine
code is cached on disk next to this file.

Notation as in :class:`lfdkit.emulate.problem.Problem`: ``c`` (n, L),
``b`` (n, L, m), ``a`` (n, L, m, m) are the obstacle terms of the offsets,
``weight`` (n,) the nominal weight per offset, ``base`` (n, q) and ``normals``
(n, m, q) the nominal points and their normals, ``obstacles`` (L, q) and
``precision`` (L, q) the obstacles' centres and diagonal precisions,
``class_of`` (L,) their class. θ = [log Q, log p_{c,i}], and with the swerve
model (issue 26) then ``[log w_before, log w_after]`` per class: ``shift``,
``shift_rate`` (n, L, q) and ``shift_side`` (n, L) of
:class:`lfdkit.emulate.problem.Problem` (arrays of size zero: no swerve, the
thesis's model, computed exactly as before they existed).
"""

import numba
import numpy as np

from lfdkit.emulate._problem_kernels import (
    block_tree_solve,
    offset_derivatives,
    offset_groups,
    offsets_newton,
)


@numba.njit(cache=True)
def _theta_derivative(
    weight,
    base,
    normals,
    obstacles,
    precision,
    class_of,
    n_classes,
    shift,
    shift_rate,
    shift_side,
    d,
    out,
):
    """``∂G/∂θ`` (n, m, n_theta): derivative of the offset gradient ``G`` w.r.t. θ.

    For obstacle ``o`` of class ``c`` with ``u = x − O`` and ``e = exp(−uᵀPu)``
    the gradient term is ``−2e N P u``, whose derivative in ``log p_j`` is
    ``2 e p_j u_j (u_j (N P u)_i − N_{ij})``. With a swerve ``u`` gains the
    shift ``s``, whose derivative in the log-stretch of the point's side is
    ``v`` (``shift_rate``): ``∂G_i = 2 e (2 (uᵀPv) (N P u)_i − (N P v)_i)``.
    """
    n, m = d.shape
    q = base.shape[1]
    n_obs = obstacles.shape[0]
    swerve = shift.shape[0] > 0
    first_swerve = 1 + n_classes * q
    out[:, :, :] = 0.0
    rel = np.empty(q)
    pu = np.empty(q)
    npu = np.empty(m)
    for k in range(n):
        for i in range(m):
            out[k, i, 0] = 2.0 * weight[k] * d[k, i]
        for o in range(n_obs):
            exponent = 0.0
            for j in range(q):
                x = base[k, j]
                for i in range(m):
                    x += d[k, i] * normals[k, i, j]
                rel[j] = x - obstacles[o, j]
                if swerve:
                    rel[j] += shift[k, o, j]
                pu[j] = precision[o, j] * rel[j]
                exponent += rel[j] * pu[j]
            e = np.exp(-exponent)
            if e == 0.0:
                continue
            for i in range(m):
                npu[i] = 0.0
                for j in range(q):
                    npu[i] += normals[k, i, j] * pu[j]
            column = 1 + class_of[o] * q
            for i in range(m):
                for j in range(q):
                    out[k, i, column + j] += 2.0 * e * pu[j] * (rel[j] * npu[i] - normals[k, i, j])
            if swerve:
                upv = 0.0
                for j in range(q):
                    upv += pu[j] * shift_rate[k, o, j]
                column = first_swerve + 2 * class_of[o] + shift_side[k, o]
                for i in range(m):
                    npv = 0.0
                    for j in range(q):
                        npv += normals[k, i, j] * precision[o, j] * shift_rate[k, o, j]
                    out[k, i, column] += 2.0 * e * (2.0 * upv * npu[i] - npv)


@numba.njit(cache=True)
def _pseudo_solve(h, rhs):
    """``−h⁺ rhs`` for a symmetric ``h``, ignoring its (near-)null directions."""
    values, vectors = np.linalg.eigh(h)
    largest = np.max(np.abs(values))
    projected = vectors.T @ rhs
    for v in range(values.shape[0]):
        scale = 1.0 / values[v] if abs(values[v]) > 1e-14 * largest else 0.0
        for p in range(rhs.shape[1]):
            projected[v, p] *= -scale
    return vectors @ projected


@numba.njit(cache=True, nogil=True)  # the IOC runs demonstrations on threads
def plan_sensitivity(
    c,
    b,
    a,
    weight,
    max_step,
    base,
    normals,
    obstacles,
    precision,
    class_of,
    n_classes,
    shift,
    shift_rate,
    shift_side,
    anchor,
    anchor_sens,
    d,
    out,
):
    """Derivative ``dd/dθ`` (n, m, n_theta) of the optimum ``d`` (n, m), written into ``out``.

    At the optimum the free action groups satisfy ``G(d, d_0, θ) = 0``; held
    actions (at their bound, pushed outwards) lock offsets to their
    predecessor, so a group moves as one. The plan moves with θ directly and
    through its anchor ``d_0``, whose own derivative is ``anchor_sens`` (m,
    n_theta): ``dδ = −H⁻¹ (∂G/∂θ + ∂G/∂d_0 · anchor_sens)``; offsets anchored
    to ``d_0`` (no free action before them) move with it.
    """
    n, m = d.shape
    n_theta = out.shape[2]
    gradient = np.empty((n, m))
    hessian = np.empty((n, m, m))
    offset_derivatives(c, b, a, weight, d, gradient, hessian)
    # Held actions: at a bound with the action gradient pushing further out.
    free = np.empty((n, m), dtype=np.bool_)
    bound = max_step * (1.0 - 1e-9)
    for i in range(m):
        running = 0.0
        for k in range(n - 1, -1, -1):
            running += gradient[k, i]
            action = d[k, i] - (anchor[i] if k == 0 else d[k - 1, i])
            held = (action >= bound and running < 0.0) or (action <= -bound and running > 0.0)
            free[k, i] = not held
    index = np.empty((n, m), dtype=np.int64)
    n_vars = offset_groups(free, index)
    if n_vars == 0:
        for k in range(n):
            for i in range(m):
                for p in range(n_theta):
                    out[k, i, p] = anchor_sens[i, p]
        return
    d_theta = np.empty((n, m, n_theta))
    _theta_derivative(
        weight,
        base,
        normals,
        obstacles,
        precision,
        class_of,
        n_classes,
        shift,
        shift_rate,
        shift_side,
        d,
        d_theta,
    )
    rhs = np.zeros((n_vars, n_theta))
    for k in range(n):
        for i in range(m):
            v = index[k, i]
            if v < 0:
                continue
            for p in range(n_theta):
                rhs[v, p] += d_theta[k, i, p]
            for j in range(m):
                if index[k, j] < 0:  # component j is anchored: it moves with d_0
                    for p in range(n_theta):
                        rhs[v, p] += hessian[k, i, j] * anchor_sens[j, p]
    moves = np.empty((n_vars, n_theta))
    definite = False
    if m == 2:
        # The groups couple as a forest: an O(n) elimination where H is positive
        # definite (at a minimum; issue 34), the dense solve below otherwise.
        solved, definite = block_tree_solve(
            np.ascontiguousarray(hessian[:, 0, 0]),
            np.ascontiguousarray(hessian[:, 0, 1]),
            np.ascontiguousarray(hessian[:, 1, 1]),
            index,
            n_vars,
            rhs,
        )
        if definite:
            for v in range(n_vars):
                for p in range(n_theta):
                    moves[v, p] = -solved[v, p]
    if not definite:
        h = np.zeros((n_vars, n_vars))
        for k in range(n):
            for i in range(m):
                v = index[k, i]
                if v < 0:
                    continue
                for j in range(m):
                    w = index[k, j]
                    if w >= 0:
                        h[v, w] += hessian[k, i, j]
    if m == 1:  # one component: the groups do not couple, H is diagonal
        for v in range(n_vars):
            inverse = 1.0 / h[v, v] if h[v, v] != 0.0 else 0.0
            for p in range(n_theta):
                moves[v, p] = -rhs[v, p] * inverse
    elif not definite:
        singular = False
        try:
            moves = -np.linalg.solve(h, rhs)
        except Exception:  # numba raises a bare Exception for a singular matrix
            singular = True
        if singular:  # symmetric: a pseudo-inverse
            moves = _pseudo_solve(h, rhs)
    for k in range(n):
        for i in range(m):
            v = index[k, i]
            for p in range(n_theta):
                out[k, i, p] = moves[v, p] if v >= 0 else anchor_sens[i, p]


@numba.njit(cache=True, nogil=True)  # the IOC runs demonstrations on threads
def mpc_sensitivity(
    c,
    b,
    a,
    weight,
    max_step,
    base,
    normals,
    obstacles,
    precision,
    class_of,
    n_classes,
    shift,
    shift_rate,
    shift_side,
    start,
    guide,
    matched,
    horizon,
    offsets,
    sensitivity,
):
    """Receding-horizon plan (n, m) and its derivative w.r.t. θ (n, m, n_theta), in place.

    Window ``k`` covers offsets ``k … k + H − 1`` anchored to the executed
    offset before it. It is solved from the previous window shifted (as at
    run time) and from the demonstration's own offsets ``guide`` (n, m) over
    the window; of the two optima, the one whose first offset is nearest the
    demonstration's (where ``matched``) is kept, then the lower cost. The
    demonstrator's choice of side is data; within one choice the plan is
    smooth in θ. Sensitivities are carried forward through the anchors.
    """
    n, m = offsets.shape
    n_theta = sensitivity.shape[2]
    anchor = start.copy()
    anchor_sens = np.zeros((m, n_theta))
    guess = np.empty((horizon, m))
    for k in range(min(horizon, n)):
        guess[k] = guide[k]
    trial = np.empty((horizon, m))
    best = np.empty((horizon, m))
    window_sens = np.empty((horizon, m, n_theta))
    swerve = shift.shape[0] > 0
    for k in range(n):
        stop = min(k + horizon, n)
        size = stop - k
        best_key0, best_key1 = np.inf, np.inf
        for candidate in range(2):
            for r in range(size):
                for i in range(m):
                    trial[r, i] = guess[r, i] if candidate == 0 else guide[k + r, i]
            d = trial[:size]
            cost, _, _ = offsets_newton(
                c[k:stop],
                b[k:stop],
                a[k:stop],
                weight[k:stop],
                max_step,
                anchor,
                d,
                1e-11,
                np.int64(200),  # int64, not the literal 200: the planner's own compiled version
            )
            key0 = 0.0
            if matched[k]:
                for i in range(m):
                    key0 += (d[0, i] - guide[k, i]) ** 2
            if key0 < best_key0 or (key0 == best_key0 and cost < best_key1):
                best_key0, best_key1 = key0, cost
                best[:size] = d
        w = best[:size]
        # the swerve's arrays over the window (size zero: none)
        stop_s = stop if swerve else 0
        k_s = k if swerve else 0
        plan_sensitivity(
            c[k:stop],
            b[k:stop],
            a[k:stop],
            weight[k:stop],
            max_step,
            base[k:stop],
            normals[k:stop],
            obstacles,
            precision,
            class_of,
            n_classes,
            shift[k_s:stop_s],
            shift_rate[k_s:stop_s],
            shift_side[k_s:stop_s],
            anchor,
            anchor_sens,
            w,
            window_sens[:size],
        )
        for i in range(m):
            offsets[k, i] = w[0, i]
            anchor[i] = w[0, i]
            for p in range(n_theta):
                sensitivity[k, i, p] = window_sens[0, i, p]
                anchor_sens[i, p] = window_sens[0, i, p]
        # The next window starts from this one shifted by a step.
        for r in range(size - 1):
            guess[r] = w[r + 1]
        guess[size - 1] = w[size - 1]
