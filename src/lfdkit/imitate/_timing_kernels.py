"""Compiled inverse of the speed law's progress (numba), for :mod:`lfdkit.imitate.timing`.

:meth:`SpeedProfile.phase <lfdkit.imitate.SpeedProfile.phase>` bisects the
progress B-spline 55 times for every point of a plan. In NumPy each step is
a de Boor evaluation of about 150 small array operations: 11 ms of CPU for
a skill's 100-point 2-D plan (of 123 ms; 24-48 ms at load 16-20), against
1.6 ms for the whole timing with this kernel (``benchmarks/skill_speed.py``). This
kernel does the same floating-point operations in the same order, one point at
a time, so its phases equal the NumPy form's bit for bit
(``tests/imitate/test_timing_kernels.py``).

Imported lazily: compiling costs a few seconds once, after which the machine
code is cached on disk next to this file.
"""

import numba
import numpy as np


# error_model: a zero-width knot span gives inf/nan as in NumPy, never ZeroDivisionError.
@numba.njit(cache=True, error_model="numpy")
def phase_bisection(knots, coefficients, degree, total, steps, target, out):
    """``out[i]`` = the phase at which ``progress / total`` reaches ``target[i]`` (bisection).

    ``knots``, ``coefficients``, ``degree``: the progress B-spline (de Boor's
    algorithm as ``timing._Spline``); ``total`` its value at 1; ``steps``
    bisection steps; ``target`` already clipped to [0, 1].
    """
    n_knots = knots.shape[0]
    work = np.empty(degree + 1)
    for i in range(target.shape[0]):
        goal = target[i]
        low, high = 0.0, 1.0
        for _ in range(steps):
            mid = 0.5 * (low + high)
            x = min(max(mid, 0.0), 1.0)
            # searchsorted(knots, x, side="right") - 1, clipped to the spline's pieces
            lo, hi = 0, n_knots
            while lo < hi:
                half = (lo + hi) // 2
                if knots[half] <= x:
                    lo = half + 1
                else:
                    hi = half
            span = min(max(lo - 1, degree), n_knots - degree - 2)
            for j in range(degree + 1):
                work[j] = coefficients[span - degree + j]
            for r in range(1, degree + 1):
                for j in range(degree, r - 1, -1):
                    left, right = knots[span - degree + j], knots[span + 1 + j - r]
                    alpha = (x - left) / (right - left)
                    work[j] = (1.0 - alpha) * work[j - 1] + alpha * work[j]
            if work[degree] / total < goal:
                low = mid
            else:
                high = mid
        value = 0.5 * (low + high)
        if goal <= 0.0:
            value = 0.0
        if goal >= 1.0:
            value = 1.0
        out[i] = value
