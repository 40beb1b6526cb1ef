"""What a batch worker that carries plans onto a robot loads once more, before its first task.

Where a batch's tasks run the execution pipeline (``lfdkit batch evaluate
--check robot`` or ``mujoco``), the workers' fork server imports this module
after :mod:`lfdkit.app.worker_preload` (or its compiled form): SciPy's
splines and rotations and the pipeline's modules, about 0.2 s of CPU that
each worker's first such task paid, and with the rest of its first-call
loading about 0.3 s a worker (a loaded 2-core machine: a robot task's
worker start-up 0.41-0.43 → 0.08-0.12 s of CPU). MuJoCo is not imported
here (0.1 s): its import may load an OpenGL library the fork server would
then fork.

Importing this module does the loading; only the fork server and
:func:`lfdkit.app.batch.load_modules` import it. It never raises: what fails to load,
a task loads itself (and reports).
"""

from __future__ import annotations

import contextlib

with contextlib.suppress(Exception):
    import lfdkit.execute.pipeline
    import lfdkit.execute.simulation
    import lfdkit.execute.ur5  # noqa: F401  (what the robot and mujoco checks run)
