"""Compiled EM for full-covariance Gaussian mixtures of a few dimensions (numba).

Used by :func:`lfdkit.mimic.select_n_components`, which fits many mixtures
from warm starts. The iteration, regularisation and stopping rule are those
of scikit-learn's ``GaussianMixture`` (see :func:`lfdkit.mimic.gmr._em`); the
loops over samples and components run as machine code. Imported lazily:
compiling costs a few seconds once, after which the machine code is cached on
disk next to this file.
"""

import numba
import numpy as np

_LOG_2PI = np.log(2.0 * np.pi)


@numba.njit(cache=True)
def _cholesky(a, out):
    """Lower Cholesky factor of the small SPD matrix ``a`` into ``out``; False if not SPD."""
    d = a.shape[0]
    for i in range(d):
        for j in range(i + 1):
            s = a[i, j]
            for m in range(j):
                s -= out[i, m] * out[j, m]
            if i == j:
                if s <= 0.0:
                    return False
                out[i, i] = np.sqrt(s)
            else:
                out[i, j] = s / out[j, j]
        for j in range(i + 1, d):
            out[i, j] = 0.0
    return True


@numba.njit(cache=True)
def _log_densities(data, weights, means, covariances, chol, log_p):
    """``log π_k + log N(x_n; μ_k, Σ_k)`` into ``log_p`` (K, n); False on a singular Σ."""
    n, d = data.shape
    k_count = weights.shape[0]
    y = np.empty(d)
    for k in range(k_count):
        if not _cholesky(covariances[k], chol[k]):
            return False
        log_det = 0.0
        for i in range(d):
            log_det += np.log(chol[k, i, i])
        base = (np.log(weights[k]) if weights[k] > 0.0 else -np.inf) - log_det - 0.5 * d * _LOG_2PI
        for s in range(n):
            maha = 0.0
            for i in range(d):  # forward substitution: L y = x - μ
                v = data[s, i] - means[k, i]
                for m in range(i):
                    v -= chol[k, i, m] * y[m]
                y[i] = v / chol[k, i, i]
                maha += y[i] * y[i]
            log_p[k, s] = base - 0.5 * maha
    return True


@numba.njit(cache=True)
def _normalise(log_p, resp):
    """Responsibilities into ``resp`` (K, n); returns the mean log-likelihood."""
    k_count, n = log_p.shape
    total = 0.0
    for s in range(n):
        top = -np.inf
        for k in range(k_count):
            top = max(top, log_p[k, s])
        acc = 0.0
        for k in range(k_count):
            e = np.exp(log_p[k, s] - top)
            resp[k, s] = e
            acc += e
        total += top + np.log(acc)
        for k in range(k_count):
            resp[k, s] /= acc
    return total / n


@numba.njit(cache=True)
def em(data, weights, means, covariances, reg, tol, max_iter):
    """EM from the given parameters (updated in place).

    Returns
    -------
    (mean log-likelihood of the final parameters, iterations, ok)
        ``ok`` is False when a covariance stopped being positive definite.
    """
    n, d = data.shape
    k_count = weights.shape[0]
    chol = np.zeros((k_count, d, d))
    log_p = np.empty((k_count, n))
    resp = np.empty((k_count, n))
    diff = np.empty(d)
    tiny = 10.0 * np.finfo(np.float64).eps
    previous = -np.inf
    n_iter = 0
    for _ in range(max_iter):
        if not _log_densities(data, weights, means, covariances, chol, log_p):
            return np.nan, n_iter, False
        current = _normalise(log_p, resp)
        n_iter += 1
        for k in range(k_count):
            r = resp[k]
            nk = tiny
            for i in range(d):
                means[k, i] = 0.0
            for s in range(n):
                nk += r[s]
                for i in range(d):
                    means[k, i] += r[s] * data[s, i]
            weights[k] = nk / n
            for i in range(d):
                means[k, i] /= nk
            cov = covariances[k]
            cov[:, :] = 0.0
            for s in range(n):
                for i in range(d):
                    diff[i] = data[s, i] - means[k, i]
                for i in range(d):
                    w = r[s] * diff[i]
                    for j in range(i + 1):
                        cov[i, j] += w * diff[j]
            for i in range(d):
                for j in range(i + 1):
                    cov[i, j] /= nk
                    cov[j, i] = cov[i, j]
                cov[i, i] += reg
        if abs(current - previous) < tol:
            break
        previous = current
    if not _log_densities(data, weights, means, covariances, chol, log_p):
        return np.nan, n_iter, False
    return _normalise(log_p, resp), n_iter, True
