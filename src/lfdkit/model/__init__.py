"""Floor two: the data records the layers pass to one another (no files, no algorithms).

:mod:`.demos` (a demonstration set: arrays, times, ids; the :class:`~.demos.Demo`
record; ``PathLike``),
:mod:`.scene` (:class:`~.scene.Scene`, the obstacle contract
:class:`~.scene.Obstacle` and its shapes), :mod:`.motion` (how an obstacle
moves: constant velocity, tracked, a trajectory) and :mod:`.timed_path` (the
one timed-path record, :class:`~.timed_path.TimedPath`: positions at times with
velocities, what a DMP rolls out and a robot runs; :class:`~.timed_path.TimedPlan`,
what a skill plans). Files of these records are
:mod:`lfdkit.io`.
"""
