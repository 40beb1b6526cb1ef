"""Tests for lfdkit.core.kernels' loading: numba's start without the whole of ``scipy.linalg``.

(The choice between numba's kernels and their NumPy forms is tested with the
forms, in ``tests/emulate/test_planner_numpy.py``.)
"""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

from lfdkit.core import kernels

# A 3-D plan: its compiled kernels factor 2×2 blocks by Cholesky, through the
# LAPACK numba finds in scipy.linalg.cython_lapack.
PLAN_3D = """
import numpy as np
from lfdkit.emulate import Reward, plan_path
from lfdkit.model.scene import Obstacle, Scene
t = np.linspace(0.0, 1.0, 150)
nominal = np.column_stack([0.8 * t, 0.1 * np.sin(np.pi * t), 0.2 * t * t])
reward = Reward(10.0, {"a": [2500.0, 300.0, 215.0]})
scene = Scene((Obstacle("a", nominal[60] + [0.0, 0.02, 0.0], radius=0.02),))
points = plan_path(reward, nominal, scene, horizon=6, n_points=30, clearance=0.01).points
"""


@pytest.mark.slow  # a fresh interpreter on numba: ~2 s of CPU
def test_numba_starts_without_scipy_linalg_and_plans_the_same(monkeypatch) -> None:
    """Issue 30: a fresh process on numba's kernels loads SciPy's BLAS and LAPACK modules
    alone (not the package scipy.linalg, 0.3-0.45 s of CPU); its 3-D plan equals this
    process's to the bit, and scipy.linalg still imports and works afterwards."""
    code = PLAN_3D + (
        "import sys\n"
        "before = 'scipy.linalg' in sys.modules, 'scipy.linalg.cython_lapack' in sys.modules\n"
        "import scipy.linalg\n"
        "factor = scipy.linalg.cholesky([[4.0, 1.0], [1.0, 3.0]])\n"
        "ok = np.allclose(factor, [[2.0, 0.5], [0.0, 2.75**0.5]])\n"
        "print(repr((before, ok, points.tolist())))\n"
    )
    env = {**os.environ, kernels.KERNELS_VARIABLE: "numba"}
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120
    )
    assert done.returncode == 0, done.stderr[-500:]
    before, ok, fresh = eval(done.stdout.strip().splitlines()[-1])
    assert before == (False, True)  # numba found LAPACK without the package
    assert ok
    monkeypatch.setenv(kernels.KERNELS_VARIABLE, "numba")
    here: dict = {}
    exec(PLAN_3D, here)
    np.testing.assert_array_equal(np.array(fresh), here["points"])
