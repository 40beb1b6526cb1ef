"""lfdkit: robot learning from a few noisy demonstrations.

Layers, each knowing only those below it:
``geometry`` → ``demos``, ``scene`` (the data models) → ``io`` (every file
read or written) → ``mimic`` → ``imitate`` → ``emulate`` → ``robot`` →
``skill``, with ``metrics``, ``datasets``, ``evaluation``, ``plot`` and
``report`` on the side; the tasks built on them (``tasks``: the sweeping
example) and ``cli`` on top. ``progress`` (what long work reports: bars,
timed log records, or nothing) imports no other module and serves them all.
Each mimicking method registers itself in
:data:`lfdkit.mimic.MIMIC_METHODS` (the contract is :mod:`lfdkit.mimic.base`);
each obstacle shape is one subclass of :class:`lfdkit.scene.Obstacle` (the
obstacle contract) in :data:`lfdkit.scene.OBSTACLE_SHAPES`; each robot arm is
one :class:`lfdkit.robot.arm.Arm` description.
"""

__version__ = "0.1.0"
