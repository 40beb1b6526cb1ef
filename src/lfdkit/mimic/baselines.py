"""Simple generalized paths to compare against.

The point-wise average after arc-length resampling is a strong naive baseline
that the thesis did not test: on slender demonstrations with the same extent it
is hard to beat; it suffers where demonstrations start or stop at different
places along the task (corresponding points drift apart) and, being a mean,
from local detours.
"""

from __future__ import annotations

import numpy as np

from lfdkit._validation import check_demos, check_positive
from lfdkit.geometry import resample

__all__ = ["pointwise_average"]


def pointwise_average(demos: list[np.ndarray], n_points: int = 100) -> np.ndarray:
    """Average of the demonstrations after resampling each evenly in arc length.

    Parameters
    ----------
    demos : list of array_like, each shape (n_j, q)
    n_points : int
        Points per resampled demonstration and in the result.

    Returns
    -------
    ndarray, shape (n_points, q)
    """
    demos = check_demos(demos, "demos")
    n_points = check_positive(n_points, "n_points", integer=True)
    return np.mean([resample(d, n_points) for d in demos], axis=0)
