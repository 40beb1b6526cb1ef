"""Compiled ProMP conditioning (numba), for :mod:`lfdkit.imitate.promp`.

One call does what conditioning on via-points needs after the arguments are
checked: the basis at each phase, ``H Σ``, the innovation covariance, its
pseudo-inverse as ``L Lᵀ``, ``Z = Lᵀ H Σ``, the new means and the part of
each offset the model cannot reach (the new covariance ``Σ − Zᵀ Z`` is
formed by the caller when it is asked for).
Why compiled: at a new phase the NumPy form is about 20 small NumPy calls
(each ~1 µs of overhead for a few hundred flops), so it could not be 10×
faster than movement_primitives' ~15 calls; this is one.

The pseudo-inverse comes from a cyclic Jacobi eigen-decomposition (the
innovation covariance is at most a few tens of rows; no LAPACK call, whose
set-up costs more than the work), with the NumPy form's cut: eigenvalues at
or below ``rcond`` times the largest are dropped. Its twin with the same
arguments and effects is :func:`lfdkit.imitate.promp.condition_weights`
(``lfdkit.core.kernels`` picks one); they agree to rounding (the tests hold
them to 1e-12 relative).

Imported lazily: compiling costs a few seconds once, after which the
machine code is cached on disk next to this file.
"""

import numba
import numpy as np

#: Sweeps after which Jacobi stops (it converges quadratically: 1 for 2 rows, 5–8 for 30).
_MAX_SWEEPS = 60


@numba.njit(cache=True)
def _jacobi_eigh(matrix, vectors):
    """Eigenvalues of the symmetric ``matrix`` (destroyed); eigenvectors into ``vectors``."""
    m = matrix.shape[0]
    for i in range(m):
        for j in range(m):
            vectors[i, j] = 0.0
        vectors[i, i] = 1.0
    scale = 0.0
    for i in range(m):
        for j in range(m):
            scale += matrix[i, j] * matrix[i, j]
    for _ in range(_MAX_SWEEPS):
        off = 0.0
        for p in range(m - 1):
            for q in range(p + 1, m):
                off += matrix[p, q] * matrix[p, q]
        if not off > 1e-32 * scale:  # off-diagonal below rounding of the whole (or NaN)
            break
        for p in range(m - 1):
            for q in range(p + 1, m):
                apq = matrix[p, q]
                if apq == 0.0:
                    continue
                theta = (matrix[q, q] - matrix[p, p]) / (2.0 * apq)
                if abs(theta) > 1e150:
                    t = 0.5 / theta
                else:
                    t = 1.0 / (abs(theta) + np.sqrt(theta * theta + 1.0))
                    if theta < 0.0:
                        t = -t
                c = 1.0 / np.sqrt(t * t + 1.0)
                s = t * c
                for k in range(m):
                    akp, akq = matrix[k, p], matrix[k, q]
                    matrix[k, p] = c * akp - s * akq
                    matrix[k, q] = s * akp + c * akq
                for k in range(m):
                    apk, aqk = matrix[p, k], matrix[q, k]
                    matrix[p, k] = c * apk - s * aqk
                    matrix[q, k] = s * apk + c * aqk
                for k in range(m):
                    vkp, vkq = vectors[k, p], vectors[k, q]
                    vectors[k, p] = c * vkp - s * vkq
                    vectors[k, q] = s * vkp + c * vkq
                # Zero by construction; rounding would leave ~1e-16 and slow convergence.
                matrix[p, q] = 0.0
                matrix[q, p] = 0.0
    values = np.empty(m)
    for i in range(m):
        values[i] = matrix[i, i]
    return values


@numba.njit(cache=True)
def condition_weights(
    mean, cov, scaled_centres, phases, width, sets, variance, noise, rcond, out
):  # fmt: skip
    """Condition ``N(mean, cov)`` on ``k`` via-points for each of ``n_sets`` point sets.

    Parameters
    ----------
    mean : (n_weights,) and cov : (n_weights, n_weights), dimension-major blocks of ``b``.
    scaled_centres : (b,) basis centres over the width; phases : (k,); width : basis width.
    sets : (n_sets, k, d) the points; variance : added to every observed coordinate;
    noise : (k, d, d) per-point covariances added too, or (0, d, d) for none.
    rcond : relative cut of the pseudo-inverse.
    out : (n_sets·n_weights + k·d·n_weights + n_sets·k·d,)
        Written, one after the other: the new means (n_sets, n_weights);
        ``Z = Lᵀ H Σ`` (k·d, n_weights), ``L Lᵀ`` the innovation covariance's
        pseudo-inverse (a zero row per dropped direction), so that the new
        covariance is ``Σ − Zᵀ Z`` (formed by the caller when asked for, one
        product that BLAS makes exactly symmetric: here it cost 2 µs, a
        quarter of a one-point call, that a path's mean does not need); each
        set's offset in the dropped directions (n_sets, k·d; zero if none).
        One buffer passed in, not arrays returned: boxing a returned array
        costs about a microsecond.

    Returns
    -------
    n_dropped : directions the pseudo-inverse dropped, or −1 for a point that
    is not finite or a phase outside [0, 1] (nothing written: the caller's full
    checks then say which).
    """
    n_sets, k, d = sets.shape
    b = scaled_centres.shape[0]
    n_weights = mean.shape[0]
    m = k * d
    for i in range(k):
        if not 0.0 <= phases[i] <= 1.0:  # NaN fails too
            return -1
        for n in range(n_sets):
            for c in range(d):
                if not np.isfinite(sets[n, i, c]):
                    return -1
    means = out[: n_sets * n_weights].reshape((n_sets, n_weights))
    start = n_sets * n_weights
    root_h = out[start : start + m * n_weights].reshape((m, n_weights))  # Lᵀ H Σ
    lost = out[start + m * n_weights :].reshape((n_sets, m))
    observed = np.empty((m, n_weights))  # H Σ = (Σ Hᵀ)ᵀ
    features = np.empty((k, b))
    for i in range(k):
        total = 0.0
        scaled_phase = phases[i] / width
        for j in range(b):
            x = scaled_centres[j] - scaled_phase
            bump = np.exp(-0.5 * x * x)
            features[i, j] = bump
            total += bump
        for j in range(b):
            features[i, j] /= total
    # Σ Hᵀ: column (i, c) is Σ[:, c-block] φ(s_i); H is never built.
    for r in range(n_weights):
        for i in range(k):
            for c in range(d):
                acc = 0.0
                for j in range(b):
                    acc += cov[r, c * b + j] * features[i, j]
                observed[i * d + c, r] = acc
    innovation_cov = np.empty((m, m))
    prior = np.empty(m)
    for i in range(k):
        for c in range(d):
            row = i * d + c
            acc = 0.0
            for j in range(b):
                acc += features[i, j] * mean[c * b + j]
            prior[row] = acc
            for col in range(m):
                acc = 0.0
                for j in range(b):
                    acc += features[i, j] * observed[col, c * b + j]
                innovation_cov[row, col] = acc
    for row in range(m):
        innovation_cov[row, row] += variance
    for i in range(noise.shape[0]):
        for a in range(d):
            for c in range(d):
                innovation_cov[i * d + a, i * d + c] += noise[i, a, c]
    # Symmetric before the decomposition (the products above round differently).
    for a in range(m):
        for c in range(a + 1, m):
            half = 0.5 * (innovation_cov[a, c] + innovation_cov[c, a])
            innovation_cov[a, c] = half
            innovation_cov[c, a] = half
    vectors = np.empty((m, m))
    values = _jacobi_eigh(innovation_cov, vectors)
    largest = 2.2250738585072014e-308  # the smallest positive float: an all-zero matrix
    for e in range(m):
        largest = max(largest, values[e])
    cut = rcond * largest
    # S⁺ = L Lᵀ, L = the kept eigenvectors over the square roots of their values
    # (a dropped direction: a zero column). K H Σ = (Lᵀ H Σ)ᵀ (Lᵀ H Σ) and the
    # mean's step K offset = (Lᵀ H Σ)ᵀ (Lᵀ offset): no gain needed.
    root_t = np.zeros((m, m))  # Lᵀ
    n_dropped = 0
    for e in range(m):
        if values[e] > cut:
            scale = 1.0 / np.sqrt(values[e])
            for a in range(m):
                root_t[e, a] = vectors[a, e] * scale
        else:
            n_dropped += 1
    for e in range(m):
        for r in range(n_weights):
            root_h[e, r] = 0.0
        for a in range(m):
            factor = root_t[e, a]
            for r in range(n_weights):
                root_h[e, r] += factor * observed[a, r]
    offset = np.empty(m)
    along_root = np.empty(m)
    for n in range(n_sets):
        for i in range(k):
            for c in range(d):
                offset[i * d + c] = sets[n, i, c] - prior[i * d + c]
        for e in range(m):
            acc = 0.0
            for a in range(m):
                acc += root_t[e, a] * offset[a]
            along_root[e] = acc
        for r in range(n_weights):
            means[n, r] = mean[r]
        for e in range(m):
            step = along_root[e]
            for r in range(n_weights):
                means[n, r] += root_h[e, r] * step
        for a in range(m):
            lost[n, a] = 0.0
        if n_dropped:
            for e in range(m):
                if not values[e] > cut:
                    along = 0.0
                    for a in range(m):
                        along += vectors[a, e] * offset[a]
                    for a in range(m):
                        lost[n, a] += along * vectors[a, e]
    return n_dropped
