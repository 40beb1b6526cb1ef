"""Mimicking: one clean generalized path from several noisy demonstrations."""

from lfdkit.mimic.baselines import pointwise_average
from lfdkit.mimic.gmr import GMR, select_n_components
from lfdkit.mimic.mean_path import MeanPath
from lfdkit.mimic.nlpca import NLPCA
from lfdkit.mimic.orientation import (
    DemoOrientationWarning,
    PathLengthWarning,
    SeveralMotionsError,
    check_one_motion,
    orient_demos,
)

__all__ = [
    "GMR",
    "NLPCA",
    "DemoOrientationWarning",
    "MeanPath",
    "PathLengthWarning",
    "SeveralMotionsError",
    "check_one_motion",
    "orient_demos",
    "pointwise_average",
    "select_n_components",
]
