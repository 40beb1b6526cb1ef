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
or below ``rcond`` times the largest are dropped. Where the innovation
covariance is certainly well conditioned (``tr(S) · tr(S⁻¹) <= 1e6``, a
bound on its condition number), nothing would be dropped and its inverse
Cholesky factor is the root instead: three points in 2-D, 6.9 → 3.1 µs
(Jacobi's 6 × 6 took 5 µs); results agree with the Jacobi route to 3e-13
of their scale on 420 conditionings of 42 models (1–3 dimensions, units
1e-3 to 1e3) at bounds up to 1e3, and with LAPACK's (the NumPy twin) as
closely as Jacobi's does up to 1e6. Its twin with the same arguments and effects is
:func:`lfdkit.imitate.promp.condition_weights` (``lfdkit.core.kernels``
picks one); they agree to rounding (the tests hold them to 1e-9 of the
units). :func:`condition_point` is the one-point call with fewer arguments,
:func:`condition_points` the one for several points with a variance;
:func:`conditioned_covariance` forms the new covariance when it is read
(:func:`conditioned_covariance_rows` where the weight covariance is exactly
symmetric).

Imported lazily: compiling costs a few seconds once, after which the
machine code is cached on disk next to this file.
"""

import numba
import numpy as np

#: Sweeps after which Jacobi stops (it converges quadratically: 1 for 2 rows, 5–8 for 30).
_MAX_SWEEPS = 60

#: Largest bound ``tr(S) · tr(S⁻¹)`` on the innovation covariance's condition number
#: for which its inverse Cholesky factor stands in for the pseudo-inverse's root: far
#: from the cut of 1e-10 (nothing would be dropped). Both routes round within about the
#: condition number times the machine epsilon: on the benchmark's three random phases
#: (walking, 1000 draws) the 555 with a bound in (1e3, 1e6] agreed with the NumPy twin
#: (LAPACK) to 2.6e-10 of the results' scale by Cholesky, 2.0e-10 by Jacobi; the worst
#: of all draws, Jacobi's beyond 1e6, 3e-7. 1e3 took the Cholesky route for 40 % of the
#: draws, 1e6 for 98 % (3 new phases: 11 → 8 µs a conditioning).
_CHOLESKY_BOUND = 1e6


@numba.njit(cache=True)
def _jacobi_eigh(matrix, vectors, values, m):
    """Eigenvalues of the symmetric ``m × m`` ``matrix`` (flat, row-major; destroyed) into
    ``values``; eigenvectors into ``vectors`` (flat, row-major, one per column)."""
    for i in range(m * m):
        vectors[i] = 0.0
    for i in range(m):
        vectors[i * m + i] = 1.0
    scale = 0.0
    for i in range(m * m):
        scale += matrix[i] * matrix[i]
    for _ in range(_MAX_SWEEPS):
        off = 0.0
        for p in range(m - 1):
            for q in range(p + 1, m):
                off += matrix[p * m + q] * matrix[p * m + q]
        if not off > 1e-32 * scale:  # off-diagonal below rounding of the whole (or NaN)
            break
        for p in range(m - 1):
            for q in range(p + 1, m):
                apq = matrix[p * m + q]
                if apq == 0.0:
                    continue
                theta = (matrix[q * m + q] - matrix[p * m + p]) / (2.0 * apq)
                if abs(theta) > 1e150:
                    t = 0.5 / theta
                else:
                    t = 1.0 / (abs(theta) + np.sqrt(theta * theta + 1.0))
                    if theta < 0.0:
                        t = -t
                c = 1.0 / np.sqrt(t * t + 1.0)
                s = t * c
                for k in range(m):
                    akp, akq = matrix[k * m + p], matrix[k * m + q]
                    matrix[k * m + p] = c * akp - s * akq
                    matrix[k * m + q] = s * akp + c * akq
                for k in range(m):
                    apk, aqk = matrix[p * m + k], matrix[q * m + k]
                    matrix[p * m + k] = c * apk - s * aqk
                    matrix[q * m + k] = s * apk + c * aqk
                for k in range(m):
                    vkp, vkq = vectors[k * m + p], vectors[k * m + q]
                    vectors[k * m + p] = c * vkp - s * vkq
                    vectors[k * m + q] = s * vkp + c * vkq
                # Zero by construction; rounding would leave ~1e-16 and slow convergence.
                matrix[p * m + q] = 0.0
                matrix[q * m + p] = 0.0
    for i in range(m):
        values[i] = matrix[i * m + i]


@numba.njit(cache=True)
def _inverse_cholesky(work, matrix, factor, inverse, m):
    """``C⁻¹`` into ``work`` at ``inverse`` with ``C Cᵀ`` the symmetric ``m × m`` matrix at
    ``matrix`` (``C`` lower triangular, into ``work`` at ``factor``; all flat, row-major;
    offsets into one buffer, not views: a view costs a reference count, an atomic
    operation, on making and on dropping).

    Returns ``tr(matrix) · tr(matrix⁻¹)``, a bound on its condition number
    (``tr(S⁻¹)`` is the squared Frobenius norm of ``C⁻¹``), or infinity where the
    factorisation fails (not positive definite).
    """
    for j in range(m):
        acc = work[matrix + j * m + j]
        for p in range(j):
            acc -= work[factor + j * m + p] * work[factor + j * m + p]
        if not acc > 0.0:  # NaN fails too
            return np.inf
        diagonal = np.sqrt(acc)
        work[factor + j * m + j] = diagonal
        for i in range(j + 1, m):
            acc = work[matrix + i * m + j]
            for p in range(j):
                acc -= work[factor + i * m + p] * work[factor + j * m + p]
            work[factor + i * m + j] = acc / diagonal
    trace, trace_inverse = 0.0, 0.0
    for i in range(m):
        trace += work[matrix + i * m + i]
        for j in range(m):
            work[inverse + i * m + j] = 0.0
    for j in range(m):  # column j of C⁻¹: C x = e_j by forward substitution
        for i in range(j, m):
            acc = 1.0 if i == j else 0.0
            for p in range(j, i):
                acc -= work[factor + i * m + p] * work[inverse + p * m + j]
            entry = acc / work[factor + i * m + i]
            work[inverse + i * m + j] = entry
            trace_inverse += entry * entry
    return trace * trace_inverse


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
    out : (2 (n_sets + k·d) n_weights + n_sets·k·d,)
        Written, one after the other: the new means (n_sets, n_weights);
        ``Z = Lᵀ H Σ`` (k·d, n_weights), ``L Lᵀ`` the innovation covariance's
        pseudo-inverse (a zero row per dropped direction), so that the new
        covariance is ``Σ − Zᵀ Z`` (formed by the caller when asked for, one
        product that BLAS makes exactly symmetric: here it cost 2 µs, a
        quarter of a one-point call, that a path's mean does not need); each
        set's offset in the dropped directions (n_sets, k·d; zero if none);
        the new means basis-major (n_sets, b, d: a path is one contiguous
        product with them, a transposed operand cost 40 % more); ``Z`` with
        its rows split by dimension and transposed (b, k·d·d: the same for a
        band). One buffer passed in, not arrays returned: boxing a returned
        array costs about a microsecond.

    Returns
    -------
    n_dropped : directions the pseudo-inverse dropped, or −1 for a point that
    is not finite or a phase outside [0, 1] (nothing written: the caller's full
    checks then say which).
    """
    n_sets, k, d = sets.shape
    work = np.empty(_work_size(k, d, scaled_centres.shape[0]))
    return _condition(
        mean, 0, np.ascontiguousarray(cov).reshape(-1), 0, mean.shape[0],
        scaled_centres, 0, phases, 0, k, width,
        np.ascontiguousarray(sets).reshape(-1), 0, n_sets, d,
        variance, np.ascontiguousarray(noise).reshape(-1), noise.shape[0], rcond, out, work,
    )  # fmt: skip


@numba.njit(cache=True)
def condition_point(prior, phase, point, variance, out):
    """:func:`condition_weights` for one point set of one via-point with a variance.

    ``prior`` is the model's ``[width, rcond, mean (n), cov (n × n, row-major)]``
    in one writeable array, ``phase`` a float, ``point`` (1, d), ``out`` the
    buffer of one set (its length gives ``n``): the common call, with five
    arguments to type and unbox (numba's dispatch was a third of a one-point
    call; a read-only array takes its slow typing path), no phase array to
    make in Python, and the basis centres over the width formed here (as
    ``np.linspace(0, 1, b) / width``, to the bit).
    """
    d = point.shape[1]
    n = (out.shape[0] - d) // (2 * (1 + d))
    b = n // d
    width, rcond = prior[0], prior[1]
    # One allocation for all scratch (each costs about a twentieth of the kernel): what
    # _condition needs, then the phase, the point and the centres, as offsets (no views).
    at = _work_size(1, d, b)
    work = np.empty(at + 1 + d + b)
    work[at] = phase
    for c in range(d):
        work[at + 1 + c] = point[0, c]
    at_centres = at + 1 + d
    step = 1.0 / (b - 1)
    for j in range(b - 1):
        work[at_centres + j] = j * step / width
    work[at_centres + b - 1] = 1.0 / width
    return _condition(
        prior, 2, prior, 2 + n, n, work, at_centres, work, at, 1, width, work, at + 1, 1, d,
        variance, work, 0, rcond, out, work,
    )  # fmt: skip


@numba.njit(cache=True)
def condition_points(prior, phases, points, variance, out):
    """:func:`condition_weights` for one point set of ``k`` via-points with a variance.

    ``prior`` as :func:`condition_point`'s, ``phases`` (k,), ``points`` (k, d),
    ``out`` the buffer of one set (its length and ``points``' shape give the
    weights): the call for several points, with five arguments and the model
    in one writeable array (the general kernel's ten, three of them read-only,
    cost a tenth of a three-point conditioning to type and unbox).
    """
    k, d = points.shape
    m = k * d
    n = (out.shape[0] - m) // (2 * (1 + m))
    b = n // d
    width, rcond = prior[0], prior[1]
    at = _work_size(k, d, b)
    work = np.empty(at + m + b)
    for i in range(k):
        for c in range(d):
            work[at + i * d + c] = points[i, c]
    at_centres = at + m
    step = 1.0 / (b - 1)
    for j in range(b - 1):
        work[at_centres + j] = j * step / width
    work[at_centres + b - 1] = 1.0 / width
    return _condition(
        prior, 2, prior, 2 + n, n, work, at_centres, phases, 0, k, width, work, at, 1, d,
        variance, work, 0, rcond, out, work,
    )  # fmt: skip


@numba.njit(cache=True)
def _work_size(k, d, b):
    """Scratch floats :func:`_condition` needs for ``k`` points in ``d`` dimensions."""
    m = k * d
    return m * d * b + k * b + 3 * m * m + 4 * m


@numba.njit(cache=True, inline="always")  # in its callers: 0.14 of a 1.1 µs one-point call
def _condition(
    mean, at_mean, cov, at_cov, n, centres, at_centres, phases, at_phases, k, width,
    sets, at_sets, n_sets, d, variance, noise, n_noise, rcond, out, work,
):  # fmt: skip
    """The work of :func:`condition_weights`, its arrays flat (C order), each with the
    offset where it starts: ``mean`` (n) and ``cov`` (n × n) the weights', ``centres``
    (b) the scaled centres, ``phases`` (k), ``sets`` (n_sets × k × d), ``noise``
    (n_noise × d × d; n_noise 0 or k); ``out`` as there and ``work`` scratch of
    :func:`_work_size` floats.

    Flat indices into buffers, not views: making a view costs a reference count,
    an atomic operation, on making and on dropping it; a dozen views were a fifth
    of a one-point call, and the last fifteen (of the model, the scratch and the
    innovation covariance's parts) a tenth of its time.
    ``Σ Hᵀ`` is formed from the rows of ``Σ`` (it is symmetric): a contiguous
    sweep per basis function, not a sum along each row (a third of the time).
    """
    b = n // d  # n weights, b per dimension
    m = k * d
    for i in range(k):
        if not 0.0 <= phases[at_phases + i] <= 1.0:  # NaN fails too
            return -1
        for s in range(n_sets):
            for c in range(d):
                if not np.isfinite(sets[at_sets + (s * k + i) * d + c]):
                    return -1
    # out: means (n_sets, n) | Z = Lᵀ H Σ (m, n) | lost (n_sets, m) | means basis-major
    # (n_sets, b, d) | Z by dimension, transposed (b, m·d).
    at_root = n_sets * n
    at_lost = at_root + m * n
    at_columns = at_lost + n_sets * m
    at_root_t = at_columns + n_sets * n
    # work: H Σ (m, n) | φ (k, b) | innovation (m, m) | its vectors (m, m) | Lᵀ (m, m) |
    # prior (m) | values (m) | offset (m) | along the root (m).
    at_features = m * n
    at_innovation = at_features + k * b
    at_vectors = at_innovation + m * m
    at_lower = at_vectors + m * m
    at_prior = at_lower + m * m
    at_values = at_prior + m
    at_offset = at_values + m
    at_along = at_offset + m
    for i in range(k):
        total = 0.0
        scaled_phase = phases[at_phases + i] / width
        for j in range(b):
            x = centres[at_centres + j] - scaled_phase
            bump = np.exp(-0.5 * x * x)
            work[at_features + i * b + j] = bump
            total += bump
        for j in range(b):
            work[at_features + i * b + j] /= total
    # H Σ: row (i, c) is Σ_j φ_j(s_i) Σ[c-block row j, :]; H is never built.
    for i in range(k):
        for c in range(d):
            row = (i * d + c) * n
            for r in range(n):
                work[row + r] = 0.0
            for j in range(b):
                f = work[at_features + i * b + j]
                for r in range(n):
                    work[row + r] += cov[at_cov + (c * b + j) * n + r] * f
    for i in range(k):
        for c in range(d):
            row = i * d + c
            acc = 0.0
            for j in range(b):
                acc += work[at_features + i * b + j] * mean[at_mean + c * b + j]
            work[at_prior + row] = acc
            for col in range(m):
                acc = 0.0
                for j in range(b):
                    acc += work[at_features + i * b + j] * work[col * n + c * b + j]
                work[at_innovation + row * m + col] = acc
    for row in range(m):
        work[at_innovation + row * m + row] += variance
    for i in range(n_noise):
        for a in range(d):
            for c in range(d):
                work[at_innovation + (i * d + a) * m + i * d + c] += noise[(i * d + a) * d + c]
    # Symmetric before the decomposition (the products above round differently).
    for a in range(m):
        for c in range(a + 1, m):
            half = 0.5 * (work[at_innovation + a * m + c] + work[at_innovation + c * m + a])
            work[at_innovation + a * m + c] = half
            work[at_innovation + c * m + a] = half
    # S⁺ = L Lᵀ; K H Σ = (Lᵀ H Σ)ᵀ (Lᵀ H Σ) and the mean's step K offset =
    # (Lᵀ H Σ)ᵀ (Lᵀ offset): no gain needed. Where S is certainly well conditioned,
    # Lᵀ = C⁻¹ with S = C Cᵀ (Cholesky; no direction is dropped): a tenth of the work
    # of the eigen-decomposition for three points in 2-D.
    n_dropped = 0
    cut = 0.0
    bound = _inverse_cholesky(work, at_innovation, at_vectors, at_lower, m)
    if not bound <= _CHOLESKY_BOUND:  # views only here, off the common path
        _jacobi_eigh(
            work[at_innovation:at_vectors], work[at_vectors:at_lower], work[at_values:at_offset], m
        )
        largest = 2.2250738585072014e-308  # the smallest positive float: an all-zero matrix
        for e in range(m):
            largest = max(largest, work[at_values + e])
        cut = rcond * largest
        # L: the kept eigenvectors over the square roots of their values (a dropped
        # direction: a zero column).
        for e in range(m):
            for a in range(m):
                work[at_lower + e * m + a] = 0.0
            if work[at_values + e] > cut:
                scale = 1.0 / np.sqrt(work[at_values + e])
                for a in range(m):
                    work[at_lower + e * m + a] = work[at_vectors + a * m + e] * scale
            else:
                n_dropped += 1
    for e in range(m):
        row = at_root + e * n
        for r in range(n):
            out[row + r] = 0.0
        for a in range(m):
            factor = work[at_lower + e * m + a]
            for r in range(n):
                out[row + r] += factor * work[a * n + r]
        for c in range(d):
            for j in range(b):
                out[at_root_t + j * m * d + e * d + c] = out[row + c * b + j]
    for s in range(n_sets):
        for i in range(k):
            for c in range(d):
                point = sets[at_sets + (s * k + i) * d + c]
                work[at_offset + i * d + c] = point - work[at_prior + i * d + c]
        for e in range(m):
            acc = 0.0
            for a in range(m):
                acc += work[at_lower + e * m + a] * work[at_offset + a]
            work[at_along + e] = acc
        row = s * n
        for r in range(n):
            out[row + r] = mean[at_mean + r]
        for e in range(m):
            step = work[at_along + e]
            for r in range(n):
                out[row + r] += out[at_root + e * n + r] * step
        for c in range(d):
            for j in range(b):
                out[at_columns + s * n + j * d + c] = out[row + c * b + j]
        for a in range(m):
            out[at_lost + s * m + a] = 0.0
        if n_dropped:
            for e in range(m):
                if not work[at_values + e] > cut:
                    along = 0.0
                    for a in range(m):
                        along += work[at_vectors + a * m + e] * work[at_offset + a]
                    for a in range(m):
                        out[at_lost + s * m + a] += along * work[at_vectors + a * m + e]
    return n_dropped


@numba.njit(cache=True)
def conditioned_covariance(prior, out, start, m, result):
    """The conditioned covariance ``Σ' = Σ − Zᵀ Z`` into ``result`` (n × n), exactly symmetric.

    ``prior`` is :func:`condition_point`'s model (``Σ`` row-major after the mean),
    ``out`` the buffer :func:`condition_weights` wrote, ``Z`` (m, n) at ``start``
    (after the means), ``m`` the observed coordinates. Each row's upper part
    sums ``Zᵀ Z`` a row of ``Z`` at a time (the order of NumPy's ``Σ − Zᵀ Z``), is
    taken from ``Σ`` and mirrored. Indices unsigned: a signed index is checked for
    a negative value on every access, which kept the inner loop scalar (a sum per
    entry over ``Z``'s column, or over a transposed copy, took 1.5–3× the time).
    """
    n = np.uint64(result.shape[0])
    rows = np.uint64(m)
    at = np.uint64(2) + n
    first = np.uint64(start)
    flat = result.reshape(-1)
    for i in range(n):
        for j in range(i, n):
            flat[i * n + j] = 0.0
        for e in range(rows):
            z = out[first + e * n + i]
            for j in range(i, n):
                flat[i * n + j] += z * out[first + e * n + j]
        for j in range(i, n):
            entry = prior[at + i * n + j] - flat[i * n + j]
            flat[i * n + j] = entry
            flat[j * n + i] = entry
    return 0


@numba.njit(cache=True)
def conditioned_covariance_rows(prior, out, start, m, result):
    """:func:`conditioned_covariance` for an exactly symmetric ``Σ`` (every fitted or
    conditioned model's), in whole rows: the same numbers to the bit.

    Each entry sums the same products in the same order (a row of ``Z`` at a time,
    from 0; a product is the same either way round) and ``Σ[j, i] = Σ[i, j]``, so
    ``Σ'`` comes out exactly symmetric without the mirrored copy down the columns,
    whose stores a column apart were a third of the upper triangle's time; the
    rows' sweeps are contiguous (one point in 2-D, 15 basis functions: 0.65 µs
    against 0.95 with the dispatch left out, on a loaded 2-core machine).
    """
    n = np.uint64(result.shape[0])
    size = n * n
    at_sigma = np.uint64(2) + n
    first = np.uint64(start)
    flat = result.reshape(-1)
    for q in range(size):
        flat[q] = 0.0
    for e in range(np.uint64(m)):  # a row of Z at a time over all of Σ'
        at_z = first + e * n
        for i in range(n):
            z_i = out[at_z + i]
            at_row = i * n
            for j in range(n):
                flat[at_row + j] += z_i * out[at_z + j]
    for q in range(size):
        flat[q] = prior[at_sigma + q] - flat[q]
    return 0
