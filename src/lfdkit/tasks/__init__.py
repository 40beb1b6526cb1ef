"""Tasks built on the layers: each one a package that holds everything particular to it.

A task describes its scene once, runs it (in simulation), draws it and ships
its example files; it may use every layer below (``skill``, ``execute``,
``emulate``, ``datasets``, ``app.plot`` ...), and no layer below imports a task.

* :mod:`lfdkit.tasks.sweeping`: sweeping a cube into a dustpan past cups and
  markers with a UR arm (thesis §6.4), the example of ``lfdkit demo``.
"""
