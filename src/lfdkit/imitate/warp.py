"""The affine warp: a path carried to a new start and goal without a dynamical system.

Each point of the path moves by a blend of the start and goal offsets, weighted
by how far along the path it lies::

    p'(u) = p(u) + (1 − u) (start' − p(0)) + u (goal' − p(1)),

``u`` the normalised arc length (0 at the first point, 1 at the last). It is
the baseline a DMP's retargeting is measured against (benchmark
``imitate.py``, held-out section): the simplest map that hits the new start
and goal exactly, keeps a straight line straight, commutes with translations
and never moves a point by more than the larger of the two offsets. It is
defined for closed paths too (start = goal), where rotating and scaling with
the start→goal vector is not. :class:`lfdkit.imitate.DMP` with
``scaling="translate"`` carries its reproduction the same way (with the
minimum-jerk law of time in place of ``u``, equal to it under minimum-jerk
timing).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from lfdkit.core.geometry import arc_length
from lfdkit.core.validation import check_path, check_point

__all__ = ["warp_path"]


def warp_path(path: Any, start: Any = None, goal: Any = None) -> np.ndarray:
    """Move a path onto a new start and goal, blending the offsets along its length.

    Parameters
    ----------
    path : array_like, shape (n_points, q)
        The path, e.g. a generalized path; at least 2 points and a non-zero
        length. Repeated points are allowed.
    start, goal : array_like, shape (q,), optional
        New first and last point, in the path's units (default: the path's own).

    Returns
    -------
    ndarray, shape (n_points, q)
        ``path[i] + (1 − u_i) (start − path[0]) + u_i (goal − path[-1])`` with
        ``u_i`` the arc length up to point ``i`` over the path's length: the
        first point is ``start`` and the last ``goal`` exactly.

    Raises
    ------
    ValueError
        For NaN/inf, a ``start`` or ``goal`` of the wrong shape, or a path of
        zero length (all points coincide: no arc length to blend along).
    """
    points = check_path(path, "path", min_points=2, min_dims=1)
    q = points.shape[1]
    new_start = points[0].copy() if start is None else check_point(start, "start", q)
    new_goal = points[-1].copy() if goal is None else check_point(goal, "goal", q)
    along = arc_length(points)
    if along[-1] <= 0.0:
        raise ValueError("path: has zero length (all points coincide); nothing to warp along")
    u = (along / along[-1])[:, None]
    warped = points + (1.0 - u) * (new_start - points[0]) + u * (new_goal - points[-1])
    # Exact ends, not 1 − u rounded: the callers compare them with the wanted points.
    warped[0], warped[-1] = new_start, new_goal
    return warped
