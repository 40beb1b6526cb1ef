"""The compiled inverse of the speed law equals its NumPy form bit for bit, and inverts it."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lfdkit.core import kernels
from lfdkit.imitate import SpeedProfile
from lfdkit.imitate._timing_kernels import phase_bisection as compiled_bisection
from lfdkit.imitate.timing import BISECTION_STEPS, phase_bisection


def _both(profile: SpeedProfile, target: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    _, progress, _, total = profile._law_splines()
    a, b = np.empty_like(target), np.empty_like(target)
    args = (progress.t, progress.c, progress.k, total, BISECTION_STEPS)
    compiled_bisection(*args, target, a)
    phase_bisection(*args, target, b)
    return a, b


@settings(max_examples=12, deadline=None)
@given(
    coefficients=st.lists(st.floats(0.0, 10.0), min_size=5, max_size=40).filter(
        lambda c: max(c) > 0.0
    ),
    seed=st.integers(0, 2**32 - 1),
)
def test_compiled_phase_equals_numpy_bit_for_bit(coefficients, seed):
    # Random laws with pauses (zero coefficients) and targets at and beyond the ends.
    profile = SpeedProfile(2.0, np.array(coefficients))
    rng = np.random.default_rng(seed)
    target = np.clip(np.r_[rng.uniform(-0.1, 1.1, 100), 0.0, 1.0, 0.5], 0.0, 1.0)
    a, b = _both(profile, target)
    assert np.array_equal(a, b)


@pytest.mark.parametrize("form", ["numba", "numpy"])
def test_phase_inverts_the_minimum_jerk_progress(monkeypatch, form):
    # Closed form: σ(u) = 10u³ − 15u⁴ + 6u⁵; phase(σ(u)) must give u back.
    monkeypatch.setenv(kernels.KERNELS_VARIABLE, form)
    u = np.linspace(0.0, 1.0, 101)
    sigma = 10 * u**3 - 15 * u**4 + 6 * u**5
    phase = SpeedProfile.minimum_jerk().phase(sigma)
    assert phase.shape == u.shape
    np.testing.assert_allclose(phase, u, atol=1e-7)
    assert phase[0] == 0.0 and phase[-1] == 1.0
    # Any shape of fractions, clipped to [0, 1].
    grid = SpeedProfile.minimum_jerk().phase(np.array([[-1.0, 0.5], [2.0, 0.5]]))
    assert grid.shape == (2, 2) and grid[0, 0] == 0.0 and grid[1, 0] == 1.0
    assert grid[0, 1] == pytest.approx(0.5, abs=1e-12)
