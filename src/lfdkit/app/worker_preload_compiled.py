"""The workers' fork server of a long batch: :mod:`lfdkit.app.worker_preload` with numba (issue 30).

A worker forked from :mod:`lfdkit.app.worker_preload` starts without numba
and pays numba's start-up itself after a second of CPU in the planner's
NumPy kernels (about 2× slower a plan): about 2 s more CPU per worker than
its share of a serial run (64 ``plan`` tasks on 2 workers, a loaded 2-core
machine: 4.4 s against 2.35 s a worker). Where a batch gives each worker
enough tasks to earn that back (:func:`lfdkit.app.batch.start_worker_server`
decides), the fork server imports numba first and warms the planner on
numba's cached kernels instead, once (about 1.2 s more CPU in the fork
server, which starts while the calling process still loads its own
modules), and every fork starts on the compiled kernels.

Importing this module does the warm-up; only the fork server and
:func:`lfdkit.app.batch.load_modules` import it. It never
raises (as :mod:`lfdkit.app.worker_preload`).
"""

from __future__ import annotations

import contextlib
import os
import sys

from lfdkit.app.batch import ONE_THREAD_ENV, load_compiled

if "numpy" not in sys.modules:  # a fork server: the forks inherit the thread pools
    os.environ.update(ONE_THREAD_ENV)  # (a serial batch's process keeps its own)
with contextlib.suppress(Exception):  # best effort: without numba the NumPy kernels serve
    load_compiled()  # numba loaded: the kernels' rule picks numba's from the first call

import lfdkit.app.worker_preload  # noqa: F401  (the warm-up, now on numba's kernels)
