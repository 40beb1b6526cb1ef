"""Floor one: what every layer uses and that knows nothing of demonstrations or scenes.

:mod:`.geometry` (polylines: arc length, resampling, projections, distances;
its compiled loops in ``_geometry_kernels``), :mod:`.rotations` (unit
quaternions, x, y, z, w), :mod:`.units` (length units and their factors),
:mod:`.validation` (the checks of arguments, one-line errors),
:mod:`.estimator` (the scikit-learn-style base: ``get_params``, fitted
checks), :mod:`.options` (defaults and choices users set by name; imports
nothing), :mod:`.progress` (what long work reports), :mod:`.threads` (one
BLAS thread for hot loops; the process's worker threads and work side by side,
each task's warnings caught in its own thread) and :mod:`.memo` (values kept by a digest of the
arrays they were made from). Nothing here imports another floor of lfdkit.
"""
