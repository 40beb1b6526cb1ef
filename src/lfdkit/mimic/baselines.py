"""Simple generalized paths to compare against.

The point-wise average after arc-length resampling is a strong naive baseline
that the thesis did not test: on slender demonstrations with the same extent it
is hard to beat; it suffers where demonstrations start or stop at different
places along the task (corresponding points drift apart) and, being a mean,
from local detours.
"""

from __future__ import annotations

import numpy as np

from lfdkit._validation import check_count, check_demos
from lfdkit.geometry import resample
from lfdkit.mimic.orientation import check_one_motion, orient_demos

__all__ = ["pointwise_average"]


def pointwise_average(
    demos: list[np.ndarray], n_points: int = 100, *, orient: str = "auto"
) -> np.ndarray:
    """Average of the demonstrations after resampling each evenly in arc length.

    Parameters
    ----------
    demos : list of array_like, each shape (n_j, q)
    n_points : int
        Points per resampled demonstration and in the result, 2 to
        1,000,000 (:data:`lfdkit._validation.MAX_POINTS`).
    orient : {"auto", "as_given"}
        ``"auto"``: reverse demonstrations recorded against the majority's
        direction first (:func:`lfdkit.mimic.orient_demos`) and refuse an
        average shorter than 0.3 times the median demonstration
        (:func:`lfdkit.mimic.check_one_motion`); ``"as_given"``: the plain
        average of the demonstrations as recorded.

    Returns
    -------
    ndarray, shape (n_points, q)
    """
    demos = check_demos(demos, "demos")
    n_points = check_count(n_points, "n_points", minimum=2)  # at most MAX_POINTS
    if orient not in ("auto", "as_given"):
        raise ValueError(f"orient: expected 'auto' or 'as_given', got {orient!r}")
    if orient == "as_given":
        return np.mean([resample(d, n_points) for d in demos], axis=0)
    demos, _ = orient_demos(demos, method="pointwise_average")
    average = np.mean([resample(d, n_points) for d in demos], axis=0)
    check_one_motion(average, demos, "pointwise_average")
    return average
