"""Tests for lfdkit.core.threads: the one-thread limit reaches every BLAS loaded."""

from __future__ import annotations

import json
import os
import subprocess
import sys

from lfdkit.core.threads import available_cores, one_blas_thread

# In a fresh interpreter: the limit is first used with NumPy's OpenBLAS alone, then
# SciPy's (numba's np.linalg calls it) is loaded and set to 2 threads; inside the
# limit every BLAS must run on one.
_SCRIPT = """
import json
import numpy
from threadpoolctl import threadpool_info, threadpool_limits
from lfdkit.core.threads import one_blas_thread
with one_blas_thread():
    pass
before = len(threadpool_info())
import scipy.linalg
threadpool_limits(2)  # both libraries threaded, as on a user's machine
with one_blas_thread():
    inside = [(i["filepath"], i["num_threads"]) for i in threadpool_info()
              if i["user_api"] == "blas"]
print(json.dumps({"before": before, "inside": inside}))
"""


def test_a_blas_loaded_after_the_first_limit_is_limited_too() -> None:
    env = {k: v for k, v in os.environ.items() if not k.endswith("_NUM_THREADS")}
    env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if p)
    done = subprocess.run(
        [sys.executable, "-c", _SCRIPT], capture_output=True, text=True, env=env, timeout=60
    )
    assert done.returncode == 0, done.stderr
    found = json.loads(done.stdout.strip().splitlines()[-1])
    libraries = {path for path, _ in found["inside"]}
    assert len(libraries) > found["before"]  # SciPy brought its own BLAS after the first limit
    assert all(threads == 1 for _, threads in found["inside"]), found["inside"]


def test_the_limit_is_undone_on_leaving() -> None:
    from threadpoolctl import threadpool_info

    before = {i["filepath"]: i["num_threads"] for i in threadpool_info()}
    with one_blas_thread():
        assert all(i["num_threads"] == 1 for i in threadpool_info() if i["user_api"] == "blas")
    assert {i["filepath"]: i["num_threads"] for i in threadpool_info()} == before


def test_available_cores_is_at_least_one() -> None:
    assert 1 <= available_cores() <= (os.cpu_count() or 1)
