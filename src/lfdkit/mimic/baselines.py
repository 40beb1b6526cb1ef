"""Simple generalized paths to compare against.

The point-wise average after arc-length resampling is a strong naive baseline
that the thesis did not test: on slender demonstrations with the same extent it
is hard to beat; it suffers where demonstrations start or stop at different
places along the task (corresponding points drift apart) and, being a mean,
from local detours.
"""

from __future__ import annotations

import numpy as np

from lfdkit.core.estimator import Estimator
from lfdkit.core.geometry import resample
from lfdkit.core.validation import check_count, check_demos
from lfdkit.mimic.base import MimicMethod, register
from lfdkit.mimic.orientation import check_one_motion, orient_demos

__all__ = ["ArcLengthAverage", "pointwise_average"]


class ArcLengthAverage(Estimator):
    """Average of the demonstrations after resampling each evenly in arc length.

    Parameters
    ----------
    n_points : int
        Points per resampled demonstration and in the result, 2 to
        1,000,000 (:data:`lfdkit.core.validation.MAX_POINTS`).
    orient : {"auto", "as_given"}
        ``"auto"``: reverse demonstrations recorded against the majority's
        direction first (:func:`lfdkit.mimic.orient_demos`) and refuse an
        average shorter than 0.3 times the median demonstration
        (:func:`lfdkit.mimic.check_one_motion`); ``"as_given"``: the plain
        average of the demonstrations as recorded.

    Attributes
    ----------
    path_ : ndarray, shape (n_points, q)
    reversed_ : ndarray of bool, shape (n_demos,)
    length_ratio_ : float
        NaN with ``orient="as_given"`` (not checked).
    converged_ : bool
        Always True (nothing iterates).
    """

    def __init__(self, n_points: int = 100, *, orient: str = "auto") -> None:
        self.n_points = n_points
        self.orient = orient

    def fit(
        self, demos: list[np.ndarray], y: None = None, *, check_input: bool = True
    ) -> ArcLengthAverage:
        """Average the demonstrations; returns ``self``.

        ``check_input=False``: ``demos`` are already validated (finite float64
        arrays of one dimension), and are not checked again.
        """
        demos = check_demos(demos, "demos") if check_input else list(demos)
        n_points = check_count(self.n_points, "n_points", minimum=2)  # at most MAX_POINTS
        if self.orient not in ("auto", "as_given"):
            raise ValueError(f"orient: expected 'auto' or 'as_given', got {self.orient!r}")
        self.reversed_ = np.zeros(len(demos), dtype=bool)
        self.length_ratio_ = float("nan")
        if self.orient == "auto":
            demos, self.reversed_ = orient_demos(demos, method="pointwise_average")
        self.path_ = np.mean([resample(d, n_points) for d in demos], axis=0)
        if self.orient == "auto":
            self.length_ratio_ = check_one_motion(self.path_, demos, "pointwise_average")
        self.converged_ = True
        return self


def pointwise_average(
    demos: list[np.ndarray],
    n_points: int = 100,
    *,
    orient: str = "auto",
    check_input: bool = True,
) -> np.ndarray:
    """:class:`ArcLengthAverage`'s path, in one call.

    Parameters
    ----------
    demos : list of array_like, each shape (n_j, q)
    n_points : int
    orient : {"auto", "as_given"}
    check_input : bool
        As :meth:`ArcLengthAverage.fit`.

    Returns
    -------
    ndarray, shape (n_points, q)
    """
    return ArcLengthAverage(n_points, orient=orient).fit(demos, check_input=check_input).path_


register(
    MimicMethod(
        key="average",
        label="arc-length average",
        color="#9467bd",
        build=lambda settings: ArcLengthAverage(n_points=settings.n_points),
        check_input=True,
    )
)
