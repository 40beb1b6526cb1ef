"""Compiled RK4 rollout of the rhythmic DMP (numba), for :mod:`lfdkit.imitate.rhythmic`.

Imported lazily: compiling costs a few seconds once, after which the machine
code is cached on disk next to this file. The schedules (amplitude times the
ramp's envelope, frequency, centre) come sampled at every step's start, middle
and end, so no Python runs inside the loop; the harmonics ``cos kφ, sin kφ``
come from ``cos φ, sin φ`` by the angle-addition recurrence (two
trigonometric calls per stage instead of ``2K``; rounding grows about ``K``
ulps, below 1e-14 for ``K ≤ 50``).
"""

import numba
import numpy as np


@numba.njit(cache=True)
def _derivative(y, z, phi, speed, drive_amp, freq, centre, cos_part, sin_part, coefs, out):
    """Right-hand side at one stage; ``out`` rows: dy, dz (first ``d`` entries); returns dφ, ds."""
    k_max, d = cos_part.shape
    alpha, stiffness, base_omega, lag_rate = coefs[0], coefs[1], coefs[2], coefs[3]
    omega = base_omega * speed
    c1, s1 = np.cos(phi), np.sin(phi)
    for j in range(d):
        out[0, j] = omega * z[j]
        out[1, j] = stiffness * (centre[j] - y[j]) - alpha * z[j]
    ck, sk = c1, s1
    for k in range(k_max):
        for j in range(d):
            out[1, j] += drive_amp * (cos_part[k, j] * ck + sin_part[k, j] * sk)
        ck, sk = ck * c1 - sk * s1, sk * c1 + ck * s1
    for j in range(d):
        out[1, j] *= omega
    return omega, (freq - speed) * lag_rate


@numba.njit(cache=True)
def rk4_rhythm(times, drive_amp, freq, centre, cos_part, sin_part, coefs, y0, z0, speed0):
    """Classical RK4 of ``ẏ = Ω z, ż = Ω(α(β(c − y) − z) + r f(φ)), φ̇ = Ω, ṡ = (F − s)·lag``.

    Parameters
    ----------
    times : (n,) seconds of the samples.
    drive_amp, freq : (2n − 1,) the amplitude (times the ramp's envelope) and the asked
        frequency factor at ``times[0], mid, times[1], mid, …``.
    centre : (2n − 1, d) the centre at the same instants.
    cos_part, sin_part : (K, d) the forcing term's Fourier coefficients.
    coefs : (4,) ``α, αβ, 2π / period, lag rate (1/s)``.
    y0, z0 : (d,) initial state; speed0 : initial frequency factor.

    Returns
    -------
    positions, velocities : (n, d)
    """
    n = times.shape[0]
    d = y0.shape[0]
    base_omega = coefs[2]
    positions = np.empty((n, d))
    velocities = np.empty((n, d))
    y, z = y0.copy(), z0.copy()
    phi, speed = 0.0, speed0
    k1 = np.empty((2, d))
    k2 = np.empty((2, d))
    k3 = np.empty((2, d))
    k4 = np.empty((2, d))
    ys, zs = np.empty(d), np.empty(d)
    for i in range(n):
        for j in range(d):
            positions[i, j] = y[j]
            velocities[i, j] = base_omega * speed * z[j]
        if i == n - 1:
            break
        h = times[i + 1] - times[i]
        a, m, b = 2 * i, 2 * i + 1, 2 * i + 2
        p1, s1 = _derivative(
            y, z, phi, speed, drive_amp[a], freq[a], centre[a], cos_part, sin_part, coefs, k1
        )
        for j in range(d):
            ys[j] = y[j] + h / 2 * k1[0, j]
            zs[j] = z[j] + h / 2 * k1[1, j]
        p2, s2 = _derivative(
            ys, zs, phi + h / 2 * p1, speed + h / 2 * s1, drive_amp[m], freq[m], centre[m],
            cos_part, sin_part, coefs, k2,
        )  # fmt: skip
        for j in range(d):
            ys[j] = y[j] + h / 2 * k2[0, j]
            zs[j] = z[j] + h / 2 * k2[1, j]
        p3, s3 = _derivative(
            ys, zs, phi + h / 2 * p2, speed + h / 2 * s2, drive_amp[m], freq[m], centre[m],
            cos_part, sin_part, coefs, k3,
        )  # fmt: skip
        for j in range(d):
            ys[j] = y[j] + h * k3[0, j]
            zs[j] = z[j] + h * k3[1, j]
        p4, s4 = _derivative(
            ys, zs, phi + h * p3, speed + h * s3, drive_amp[b], freq[b], centre[b],
            cos_part, sin_part, coefs, k4,
        )  # fmt: skip
        for j in range(d):
            y[j] += h / 6 * (k1[0, j] + 2 * k2[0, j] + 2 * k3[0, j] + k4[0, j])
            z[j] += h / 6 * (k1[1, j] + 2 * k2[1, j] + 2 * k3[1, j] + k4[1, j])
        phi += h / 6 * (p1 + 2 * p2 + 2 * p3 + p4)
        speed += h / 6 * (s1 + 2 * s2 + 2 * s3 + s4)
    return positions, velocities
