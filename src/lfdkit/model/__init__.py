"""Floor two: the data records the layers pass to one another (no files, no algorithms).

:mod:`.demos` (a demonstration set: arrays, times, ids; ``PathLike``),
:mod:`.scene` (:class:`~.scene.Scene`, the obstacle contract
:class:`~.scene.Obstacle` and its shapes) and :mod:`.motion` (how an obstacle
moves: constant velocity, tracked, a trajectory). Files of these records are
:mod:`lfdkit.io`.
"""
